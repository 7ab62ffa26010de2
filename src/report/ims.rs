//! The report's IM section: which intensity measure predicts a block's
//! overturning best, over the grid and at one ε.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use crate::figures::ims::{best_periods, display_name, Shown};
use crate::im::efficiency::VECTOR;
use crate::study::StudyData;
use crate::tables::ims::EfficiencyRow;

/// `## Which IM predicts overturning`, when the ims stage has run.
pub(super) fn ims_section(w: &mut String, d: &StudyData) {
    let rows = &d.efficiency;
    let Some(shown) = Shown::of(d) else { return };
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(w, "## Which IM predicts overturning\n");
    let _ = writeln!(
        w,
        "Each record's capacity is converted into each intensity measure (the IM of the record \
         scaled to overturn the block), and β is the standard deviation of its logarithm over the \
         records that overturn the block: the smaller β, the tighter the fragility in that IM. In \
         risk, a lognormal fragility multiplies the rate by exp(k²β²/2) (Cornell), so with a \
         hazard slope k = 3 a β of 0.3 instead of 0.6 divides the rate by {:.1}. Definitions: \
         docs/MODEL.md §14; every value in `im_efficiency.parquet`.\n",
        (9.0f64 * (0.36 - 0.09) / 2.0).exp()
    );
    let mut best: BTreeMap<&str, usize> = BTreeMap::new();
    let mut blocks = 0;
    for r in rows.iter().filter(|r| r.rank == Some(1)) {
        *best.entry(r.im.as_str()).or_default() += 1;
        blocks += 1;
    }
    let mut counts: Vec<(&str, usize)> = best.into_iter().collect();
    counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    let text: Vec<String> = counts
        .iter()
        .map(|(im, n)| format!("{} in {n}", display_name(im)))
        .collect();
    let _ = writeln!(
        w,
        "The IM of smallest β, over the {blocks} blocks: {}.\n",
        text.join(", ")
    );
    let beta = |block: i64, im: &str| -> Option<&EfficiencyRow> {
        rows.iter().find(|r| r.block_index == block && r.im == im)
    };
    let periods = best_periods(rows, shown, |im| d.named(im));
    let (head, first) = match shown {
        Shown::Eps(_) => (format!("At {}:", shown.text()), "p (1/s)"),
        Shown::Every => ("Each block at its own ε:".to_string(), "block, ε, p (1/s)"),
    };
    let (named, sa, vector) = columns(d);
    let _ = writeln!(w, "{head}\n");
    let mut header = format!("| {first} | best IM (β) |");
    for (name, _) in named {
        let _ = write!(header, " β of {name} |");
    }
    let _ = write!(header, " best {sa}(T): T (s), β |");
    if vector {
        header.push_str(" β of PGA given PGV/PGA |");
    }
    let _ = writeln!(w, "{header}");
    let columns = named.len() + 3 + usize::from(vector);
    let _ = writeln!(w, "|{}", "---|".repeat(columns));
    let f = |r: Option<&EfficiencyRow>| r.map_or("—".to_string(), |r| format!("{:.3}", r.beta));
    for &(block, p, t, b) in &periods {
        let top = rows
            .iter()
            .find(|r| r.block_index == block && r.rank == Some(1))
            .map_or("—".to_string(), |r| {
                format!("{} ({:.3})", display_name(&r.im), r.beta)
            });
        let name = match (shown, rows.iter().find(|r| r.block_index == block)) {
            (Shown::Every, Some(r)) => format!("{}, {}, ", r.block, crate::im::level_text(r.eps)),
            _ => String::new(),
        };
        let mut line = format!("| {name}{p:.3} | {top} |");
        for (_, im) in named {
            let _ = write!(line, " {} |", f(beta(block, im)));
        }
        let _ = write!(line, " {}, {b:.3} |", crate::im::period_text(t));
        if vector {
            let _ = write!(line, " {} |", f(beta(block, VECTOR)));
        }
        let _ = writeln!(w, "{line}");
    }
    let periods: Vec<(f64, f64, f64)> = periods.iter().map(|b| (b.1, b.2, b.3)).collect();
    // Blocks of their own ε differ in more than size: no rule along p.
    let line = match shown {
        Shown::Eps(_) => best_period_line(&periods, sa),
        Shown::Every => None,
    };
    if let Some(line) = line {
        let _ = writeln!(w, "\n{line}");
    }
    if vector {
        vector_line(w, rows);
    } else {
        // The next section's heading a paragraph of its own.
        let _ = writeln!(w);
    }
}

/// The IM table's columns: the ground's PGA, PGV and AvgSA, SA and the
/// vector, or of text records the floor's PFA and PFV and FSA (the tables
/// hold only those).
type Columns = (&'static [(&'static str, &'static str)], &'static str, bool);

fn columns(d: &StudyData) -> Columns {
    if d.stood_on {
        (&[("PFA", "pfa"), ("PFV", "pfv")], "FSA", false)
    } else {
        (
            &[("PGA", "pga"), ("PGV", "pgv"), ("AvgSA", "avgsa")],
            "SA",
            true,
        )
    }
}

/// How often PGA given PGV/PGA beats the best single IM.
fn vector_line(w: &mut String, rows: &[EfficiencyRow]) {
    let lower = rows
        .iter()
        .filter(|r| r.im == VECTOR)
        .filter(|v| {
            rows.iter()
                .find(|r| r.block_index == v.block_index && r.rank == Some(1))
                .is_some_and(|b| v.beta < b.beta)
        })
        .count();
    let total = rows.iter().filter(|r| r.im == VECTOR).count();
    let _ = writeln!(
        w,
        "\nPGA given PGV/PGA (PGV/PGA does not change when a record is scaled, so the capacity \
         in PGA can be conditioned on it: ln PGA_c regressed on ln(PGV/PGA)) has a smaller \
         dispersion than the best single IM in {lower} of {total} blocks.\n"
    );
}

/// How the best `sa` (SA or FSA) period changes with p (`best`: p, the period, β, by p),
/// where the study has two p or more: it moves, or stays.
fn best_period_line(best: &[(f64, f64, f64)], sa: &str) -> Option<String> {
    let (first, last) = (best.first()?, best.last()?);
    if first.0 == last.0 {
        return None;
    }
    let (t0, t1) = (
        crate::im::period_text(first.1),
        crate::im::period_text(last.1),
    );
    let (low, high) = best
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), b| {
            (lo.min(b.1), hi.max(b.1))
        });
    if low < high && first.1 == last.1 {
        return Some(format!(
            "The best {sa} period varies with p between {} and {} s ({t0} s at p = {:.2} and \
             {:.2} 1/s).",
            crate::im::period_text(low),
            crate::im::period_text(high),
            first.0,
            last.0
        ));
    }
    Some(match first.1.total_cmp(&last.1) {
        std::cmp::Ordering::Equal => format!(
            "The best {sa} period is {t0} s from p = {:.2} to {:.2} 1/s.",
            first.0, last.0
        ),
        std::cmp::Ordering::Greater => format!(
            "The best {sa} period moves from {t0} s at p = {:.2} 1/s to {t1} s at p = {:.2} 1/s: \
             a larger block (smaller p) is overturned by the record's longer periods.",
            first.0, last.0
        ),
        std::cmp::Ordering::Less => format!(
            "The best {sa} period moves from {t0} s at p = {:.2} 1/s to {t1} s at p = {:.2} 1/s.",
            first.0, last.0
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::best_period_line;

    /// One block says nothing (it said the period "moves from 1.0 s at
    /// p = 2.82 1/s to 1.0 s at p = 2.82 1/s"); a period that stays is said
    /// to stay; the larger block's longer period is explained, a shorter
    /// one is not.
    #[test]
    fn the_best_period_line_says_what_the_periods_do() {
        assert_eq!(best_period_line(&[(2.82, 1.0, 0.3)], "SA"), None);
        assert_eq!(best_period_line(&[], "SA"), None);
        assert_eq!(
            best_period_line(&[(1.0, 1.0, 0.3), (4.0, 1.0, 0.2)], "SA").unwrap(),
            "The best SA period is 1.0 s from p = 1.00 to 4.00 1/s."
        );
        let longer = best_period_line(&[(1.0, 2.0, 0.3), (4.0, 0.5, 0.2)], "SA").unwrap();
        assert!(
            longer.ends_with("overturned by the record's longer periods."),
            "{longer}"
        );
        assert_eq!(
            best_period_line(&[(1.0, 1.0, 0.3), (2.0, 2.0, 0.3), (4.0, 1.0, 0.2)], "SA").unwrap(),
            "The best SA period varies with p between 1.0 and 2.0 s (1.0 s at p = 1.00 and \
             4.00 1/s)."
        );
        let shorter = best_period_line(&[(1.0, 0.5, 0.3), (4.0, 2.0, 0.2)], "SA").unwrap();
        assert_eq!(
            shorter,
            "The best SA period moves from 0.5 s at p = 1.00 1/s to 2.0 s at p = 4.00 1/s."
        );
        // Text records' spectral measure is the floor's.
        assert_eq!(
            best_period_line(&[(1.0, 1.0, 0.3), (4.0, 1.0, 0.2)], "FSA").unwrap(),
            "The best FSA period is 1.0 s from p = 1.00 to 4.00 1/s."
        );
    }
}
