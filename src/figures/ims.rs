//! The IM figures: how the dispersion β of the capacity in each IM varies
//! with p, and which SA period predicts overturning best.

use super::figure::Figure;
use super::shared::ramp;
use crate::im::Im;
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::study::StudyData;
use crate::tables::ims::EfficiencyRow;

/// The SA periods (s) drawn against p; every other capacity measure is
/// drawn.
pub const SHOWN_PERIODS_S: [f64; 3] = [0.3, 1.0, 3.0];

/// The IMs drawn against p, in legend order: every capacity measure of
/// the study (the floor's where the blocks stand on the records), SA or
/// FSA at [`SHOWN_PERIODS_S`] only.
pub fn shown(d: &StudyData) -> Vec<Im> {
    d.capacity_measures()
        .into_iter()
        .filter(|im| match im {
            Im::Sa(t) | Im::Fsa(t) => SHOWN_PERIODS_S.contains(t),
            _ => true,
        })
        .collect()
}

/// An IM's name as a reader writes it ([`Im::short`]: PGA, SA(1.0),
/// AvgSA, Arias, CAV), or the efficiency table's vector row in capitals.
pub fn display_name(im: &str) -> String {
    im.parse::<Im>()
        .map_or_else(|_| im.to_uppercase(), |im| im.short())
}

/// The ε the β-against-p figure is drawn at: the grid's nearest to 0.75
/// (the paper's middle value) among those whose blocks overturn (a block
/// that slides first, say, has no capacity to disperse).
pub fn shown_eps(d: &StudyData) -> Option<f64> {
    let (_, es) = d.ps_and_eps();
    es.iter()
        .copied()
        .filter(|&e| d.efficiency.iter().any(|r| r.eps == e))
        .min_by(|a, b| (a - 0.75).abs().total_cmp(&(b - 0.75).abs()))
}

/// The blocks the β-against-p figure and the report's IM table show.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shown {
    /// A grid's blocks at one ε ([`shown_eps`]).
    Eps(f64),
    /// Every block, each at its own ε: a study of named blocks, whose ε
    /// differ (at one ε, each would be a line of one point).
    Every,
}

impl Shown {
    /// What a study's IM figures show; `None` without efficiency rows.
    pub fn of(d: &StudyData) -> Option<Shown> {
        if d.is_grid() {
            shown_eps(d).map(Shown::Eps)
        } else {
            (!d.efficiency.is_empty()).then_some(Shown::Every)
        }
    }

    pub fn holds(self, r: &EfficiencyRow) -> bool {
        match self {
            Shown::Eps(e) => r.eps == e,
            Shown::Every => true,
        }
    }

    /// "ε = 0.75", or "each block at its own ε".
    pub fn text(self) -> String {
        match self {
            Shown::Eps(e) => format!("ε = {e}"),
            Shown::Every => "each block at its own ε".into(),
        }
    }
}

/// (p, β) of one IM over the blocks `shown`, in increasing p.
fn series(rows: &[EfficiencyRow], im: &str, shown: Shown) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.im == im && shown.holds(r))
        .map(|r| (r.p, r.beta))
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v
}

/// The SA period (of the measure `named` calls SA: FSA where the blocks
/// stand on the records) of smallest β for each block `shown`: (its index,
/// p, the period, β), in increasing p. A floor study's FSA rows, its
/// floor's demands, are not the SA of its ground records.
pub fn best_periods(
    rows: &[EfficiencyRow],
    shown: Shown,
    named: impl Fn(Im) -> Im,
) -> Vec<(i64, f64, f64, f64)> {
    let mut best: Vec<(i64, f64, f64, f64)> = Vec::new();
    for r in rows.iter().filter(|r| shown.holds(r)) {
        let Ok(im) = r.im.parse::<Im>() else {
            continue;
        };
        let t = match im {
            Im::Sa(t) | Im::Fsa(t) if im == named(Im::Sa(t)) => t,
            _ => continue,
        };
        match best.iter_mut().find(|b| b.0 == r.block_index) {
            Some(b) if r.beta < b.3 => *b = (r.block_index, r.p, t, r.beta),
            Some(_) => {}
            None => best.push((r.block_index, r.p, t, r.beta)),
        }
    }
    best.sort_by(|a, b| a.1.total_cmp(&b.1));
    best
}

/// β against p for each IM, at one ε of a grid or for every named block;
/// and the best SA period against p, one line per ε of a grid (one line
/// of every named block).
pub(super) fn im_efficiency(d: &StudyData) -> Vec<Figure> {
    let (ps, es) = d.ps_and_eps();
    let Some(which) = Shown::of(d) else {
        return Vec::new();
    };
    let at = which.text();
    if d.efficiency.is_empty() || ps.len() < 2 {
        return Vec::new();
    }
    let mut lines: Vec<Line> = shown(d)
        .into_iter()
        .enumerate()
        .map(|(i, im)| Line {
            name: Some(im.short()),
            points: series(&d.efficiency, &im.name(), which),
            // Blocks of their own ε are points: a line would read as a
            // trend along p at one ε.
            style: match which {
                Shown::Eps(_) => Style::Line,
                Shown::Every => Style::Points,
            },
            hue: Hue::Series(i),
        })
        .filter(|l| !l.points.is_empty())
        .collect();
    // The vector of the ground's PGA and PGV/PGA (none of text records).
    let vector = series(&d.efficiency, crate::im::efficiency::VECTOR, which);
    let has_vector = !vector.is_empty();
    if has_vector {
        lines.push(Line {
            name: Some("PGA | PGV/PGA".into()),
            points: vector,
            style: match which {
                Shown::Eps(_) => Style::Dashed,
                Shown::Every => Style::Points,
            },
            hue: Hue::Ink,
        });
    }
    let sa = d.named(Im::Sa(1.0)).short();
    let sa = sa.split('(').next().unwrap_or("SA");
    // Up to 1.2, or to the largest β (Arias's exceeds it at small p: its
    // line once ran clipped along the top of the frame).
    let top = lines
        .iter()
        .flat_map(|l| l.points.iter().map(|p| p.1))
        .fold(1.2f64, f64::max);
    let top = (top * 1.05 / 0.2).ceil() * 0.2;
    let beta = Figure {
        file: "im_efficiency.svg".into(),
        chart: Chart {
            title: format!("Dispersion of the overturning capacity in each IM, {at}"),
            x_desc: "p (1/s)".into(),
            y_desc: "β, standard deviation of ln IM at overturning (dimensionless)".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, top)),
            x_ticks: None,
            lines,
        },
        caption: format!(
            "The smaller β, the better the IM predicts overturning: each record's capacity \
             converted into the IM (the record scaled to overturn the block), and β the standard \
             deviation of its logarithm over the records. {at}; {sa} at 5 % damping{vector}.",
            vector = match (has_vector, which) {
                (false, _) => "",
                (true, Shown::Eps(_)) => {
                    "; the dashed black line is PGA given the record's PGV/PGA (a two-parameter \
                     fragility)"
                }
                (true, Shown::Every) => {
                    "; the black points are PGA given the record's PGV/PGA (a two-parameter \
                     fragility)"
                }
            }
        ),
    };
    let periods = Figure {
        file: "im_best_sa_period.svg".into(),
        chart: Chart {
            title: format!("The {sa} period that predicts overturning best"),
            x_desc: "p (1/s)".into(),
            y_desc: format!("period T of the smallest β of {sa}(T) (s)"),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            x_range: None,
            y_range: Some((0.04, 5.0)),
            x_ticks: None,
            lines: period_lines(d, which, &es),
        },
        caption: format!(
            "For each block, the period among 0.05–4 s whose {sa} has the smallest dispersion of \
             the capacity (the report's IM section says how it moves with p)."
        ),
    };
    vec![beta, periods]
}

/// The best SA period against p: one line per ε of a grid, or one of
/// every named block.
fn period_lines(d: &StudyData, shown: Shown, es: &[f64]) -> Vec<Line> {
    let line = |name: String, shown: Shown, style: Style, hue: Hue| Line {
        name: Some(name),
        points: best_periods(&d.efficiency, shown, |im| d.named(im))
            .into_iter()
            .map(|(_, p, t, _)| (p, t))
            .collect(),
        style,
        hue,
    };
    match shown {
        Shown::Eps(_) => es
            .iter()
            .map(|&e| line(format!("ε = {e}"), Shown::Eps(e), Style::Line, ramp(es, e)))
            .collect(),
        Shown::Every => vec![line(
            "every block".into(),
            Shown::Every,
            Style::Points,
            Hue::Ink,
        )],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One block per (p, ε) in these tests.
    fn index(p: f64, eps: f64) -> i64 {
        (p * 1000.0).round() as i64 * 1000 + (eps * 1000.0).round() as i64
    }

    fn row(p: f64, eps: f64, im: &str, beta: f64) -> EfficiencyRow {
        EfficiencyRow {
            block_index: index(p, eps),
            block: String::new(),
            p,
            eps,
            im: im.into(),
            unit: "g".into(),
            n: 44,
            median: None,
            median_dimensionless: None,
            dimensionless: None,
            beta,
            lilliefors_p: None,
            rank: None,
            slope: None,
        }
    }

    /// Every β drawn lies inside the frame: Arias's β of 1.6–1.7 at small
    /// p once ran clipped along the top of a frame fixed at 1.2.
    #[test]
    fn no_dispersion_is_clipped() {
        let mut d = super::super::fixture::grid_study(&[1.0, 2.0], &[0.75]);
        for (p, beta) in [(1.0, 1.67), (2.0, 0.9)] {
            d.efficiency.push(row(p, 0.75, "arias", beta));
            d.efficiency.push(row(p, 0.75, "pga", 0.4));
        }
        let figs = im_efficiency(&d);
        let chart = &figs[0].chart;
        let (lo, hi) = chart.y_range.unwrap();
        let ys = chart
            .lines
            .iter()
            .flat_map(|l| l.points.iter().map(|p| p.1));
        assert!(ys.clone().any(|y| y == 1.67));
        assert!(ys.into_iter().all(|y| (lo..=hi).contains(&y)), "{hi}");
        assert_eq!(hi, 1.8);
    }

    /// Named blocks each at their own ε are drawn together: at one ε each
    /// line was one point, and drew nothing (the floor study's figures).
    #[test]
    fn named_blocks_of_their_own_eps_are_drawn_together() {
        let mut d = super::super::fixture::two_blocks_study();
        let blocks = d.records_plan().blocks.clone();
        assert_eq!(blocks.len(), 2);
        for (i, b) in blocks.iter().enumerate() {
            for (im, beta) in [("pga", 0.5 + 0.1 * i as f64), ("sa(1.0)", 0.4)] {
                d.efficiency.push(EfficiencyRow {
                    block_index: i as i64,
                    block: b.name.clone(),
                    ..row(b.p, b.eps, im, beta)
                });
            }
        }
        let figs = im_efficiency(&d);
        assert_eq!(figs.len(), 2);
        let pga = figs[0]
            .chart
            .lines
            .iter()
            .find(|l| l.name.as_deref() == Some("PGA"));
        let mut want: Vec<(f64, f64)> = blocks
            .iter()
            .zip([0.5, 0.6])
            .map(|(b, v)| (b.p, v))
            .collect();
        want.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert_eq!(pga.expect("a PGA line").points, want);
        assert!(figs[0].chart.title.ends_with("each block at its own ε"));
        let periods = &figs[1].chart.lines;
        assert_eq!(periods.len(), 1);
        assert_eq!(periods[0].points.len(), 2);
        assert!(periods[0].points.iter().all(|&(_, t)| t == 1.0));
    }

    #[test]
    fn the_best_period_is_the_smallest_beta() {
        let rows = vec![
            row(1.0, 0.7, "sa(0.3)", 0.5),
            row(1.0, 0.7, "sa(2.0)", 0.3),
            row(4.0, 0.7, "sa(0.3)", 0.2),
            row(4.0, 0.7, "sa(2.0)", 0.4),
            row(4.0, 0.9, "sa(0.3)", 0.9),
            row(4.0, 0.7, "pgv", 0.1),
        ];
        assert_eq!(
            best_periods(&rows, Shown::Eps(0.7), |im| im),
            vec![
                (index(1.0, 0.7), 1.0, 2.0, 0.3),
                (index(4.0, 0.7), 4.0, 0.3, 0.2)
            ]
        );
        // Every block, each its own: the one at ε = 0.9 too, at the same p.
        assert_eq!(
            best_periods(&rows, Shown::Every, |im| im),
            vec![
                (index(1.0, 0.7), 1.0, 2.0, 0.3),
                (index(4.0, 0.7), 4.0, 0.3, 0.2),
                (index(4.0, 0.9), 4.0, 0.3, 0.9)
            ]
        );
        // A floor study's FSA rows (its floor's demands) are not its
        // ground's SA; text records' (stood on) are the only spectral ones.
        let mut floor = rows.clone();
        floor.push(row(1.0, 0.7, "fsa(0.5)", 0.01));
        floor.push(row(4.0, 0.7, "fsa(3.0)", 0.3));
        assert_eq!(
            best_periods(&floor, Shown::Eps(0.7), |im| im),
            best_periods(&rows, Shown::Eps(0.7), |im| im)
        );
        assert_eq!(
            best_periods(&floor, Shown::Eps(0.7), |im: Im| im.felt().unwrap_or(im)),
            vec![
                (index(1.0, 0.7), 1.0, 0.5, 0.01),
                (index(4.0, 0.7), 4.0, 3.0, 0.3)
            ]
        );
    }
}
