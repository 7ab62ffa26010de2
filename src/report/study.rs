//! The Markdown of a records study: settings, run times and counts, the
//! capacity fractiles against the paper's Eq. 10, lognormality, the fitted
//! against the published coefficients and the capacity-convergence finding,
//! with the bands' sections from [`super::bands`] and the figures.

use std::fmt::Write as _;

use super::bands::{bands, fit_bands};
use super::shared::{figures_section, heading, list};
use crate::figures::{convergence_levels, Figure};
use crate::fragility;
use crate::ida::CertificationKind;
use crate::study::StudyData;

/// The whole report. `figures` are listed with their captions, as files
/// under `figures/`.
pub fn render(d: &StudyData, figures: &[Figure]) -> String {
    let mut md = String::new();
    let plan = &d.plan;
    heading(&mut md, "Study", plan, &d.pipeline, &d.version, "");
    text_records(&mut md, d);
    settings(&mut md, d);
    runtime(&mut md, d);
    capacity_fractiles(&mut md, d);
    super::floor::scene_section(&mut md, d);
    super::orientation::orientation_section(&mut md, d);
    bands(&mut md, d);
    lognormality(&mut md, d);
    regression(&mut md, d);
    fit_bands(&mut md, d);
    convergence(&mut md, d);
    super::ims::ims_section(&mut md, d);
    super::damage::damage_section(&mut md, d);
    super::tree::tree_section(&mut md, d);
    figures_section(&mut md, figures);
    md
}

/// What the IMs of text records are: the motion's own, the floor's.
fn text_records(w: &mut String, d: &StudyData) {
    let rs = d.records_plan();
    if !d.stood_on && rs.records.text().is_some() && rs.floor.is_some() {
        let _ = writeln!(
            w,
            "**The records are text columns run through the building** (`[floor]`): they are \
             taken as its ground motions, their PGA the ground's. If they are a structural \
             model's floor motions already, drop `[floor]`: each capacity here is of a floor's \
             floor.\n"
        );
    }
    if !d.stood_on {
        return;
    }
    let _ = writeln!(
        w,
        "**The records are text columns** (a structural model's floor motions as given, each \
         scaled itself, with no `[floor]` to run them through). η is of each record's own \
         peak, the floor's PFA, and this report and its tables (`record_ims`, `im_efficiency`, \
         `damage_states`) state the capacities in the floor's demands of that motion, PFA, PFV \
         and FSA(T), not in the ground's measures. `rocking fragility`, `risk` and `export \
         --from` this pipeline refuse a ground IM of them; `--direct --im pfa|pfv|fsa(T)` states \
         the fragility in the floor's demands (docs/MODEL.md §16).\n"
    );
}

fn settings(w: &mut String, d: &StudyData) {
    let plan = &d.plan;
    let rs = d.records_plan();
    let (ps, es) = d.ps_and_eps();
    let _ = writeln!(w, "## Settings\n");
    let _ = writeln!(w, "| setting | value |\n|---|---|");
    let sets = if rs.sets.is_empty() {
        String::new()
    } else {
        format!(" ({})", rs.sets.join(", "))
    };
    let _ = writeln!(w, "| records | {}{sets} |", d.n_records());
    let _ = writeln!(
        w,
        "| model | {}, overturning {} |",
        model_text(plan.model),
        plan.overturn
    );
    let _ = writeln!(
        w,
        "| blocks | {}: p = {} 1/s; ε = {} |",
        plan.blocks().len(),
        list(&ps),
        list(&es)
    );
    let _ = writeln!(
        w,
        "| IM grid | {} {} levels of η from {} down to {}, capacity refined to Δη = {} |",
        rs.grid.count,
        match rs.grid.spacing {
            crate::ida::Spacing::Log => "log-spaced",
            crate::ida::Spacing::Linear => "evenly spaced",
        },
        rs.grid.eta_max,
        rs.grid.eta_min,
        rs.tol
    );
    let _ = writeln!(
        w,
        "| fractiles | {} |\n",
        crate::stats::FractileDef::describe(rs.fractile)
    );
}

/// The model as a reader names it (not the Rust variant).
pub(super) fn model_text(m: crate::physics::ModelChoice) -> &'static str {
    use crate::physics::ModelChoice::*;
    match m {
        Linearized => crate::physics::EquationKind::Linearized.describe(),
        Nonlinear => crate::physics::EquationKind::Nonlinear.describe(),
        Auto => {
            "linearised equation where its error 0.45·α² is within `auto_tol`, else nonlinear; \
             with sliding for every block with μ"
        }
        SlideRock => crate::physics::EquationKind::SlideRock.describe(),
    }
}

fn runtime(w: &mut String, d: &StudyData) {
    let _ = writeln!(w, "## Runtime and counts\n");
    let _ = writeln!(w, "| stage | time (s) |\n|---|---:|");
    for (s, t) in &d.stage_seconds {
        if let Some(t) = t {
            let _ = writeln!(w, "| {s} | {t:.2} |");
        }
    }
    let overturned = d.ida.iter().filter(|r| r.overturned).count();
    let _ = writeln!(
        w,
        "\n{} capacities from {} simulations ({} of them overturned); {} of the record × block cases never overturned down to η = {}.\n",
        d.caps.len(),
        d.ida.len(),
        overturned,
        d.caps.iter().filter(|c| c.eta_c.is_none()).count(),
        d.records_plan().grid.eta_min
    );
    let count = |k: CertificationKind| d.caps.iter().filter(|c| c.certification == k).count();
    let certified = d.caps.iter().filter(|c| c.certified).count();
    let (exact, tolerance) = (
        count(CertificationKind::Exact),
        count(CertificationKind::Tolerance),
    );
    let _ = write!(
        w,
        "Certification: {certified} of {} capacities certified ({exact} by the exact stepper, {tolerance} at an integrator's tolerance with their decisive verdicts standing at a 100× tighter one; in both, no decisive verdict changes when η moves by 1e-9)",
        d.caps.len()
    );
    let (chaotic, flips) = (
        count(CertificationKind::Chaotic),
        count(CertificationKind::Flips),
    );
    if chaotic + flips > 0 {
        let _ = write!(
            w,
            "; not certified: {chaotic} chaotic (a decisive verdict changes when η moves by 1e-9: η_c is one edge of a chaotic band) and {flips} whose verdict still flips at the tightest tolerance (η_c is not converged); column `certification` of capacities.parquet"
        );
    }
    let _ = writeln!(
        w,
        ". See docs/BENCHMARKS.md for how the tolerance was chosen.\n"
    );
}

/// The capacity fractile of block (p, ε) at quantile q, if tabulated.
fn fractile_at(d: &StudyData, p: f64, e: f64, q: f64) -> Option<f64> {
    d.capacity_fractiles
        .iter()
        .find(|r| r.p == p && r.eps == e && r.quantile == q)
        .map(|r| r.eta_c)
}

fn capacity_fractiles(w: &mut String, d: &StudyData) {
    let _ = writeln!(w, "## Capacity fractiles\n");
    if !d.is_grid() {
        let _ = writeln!(
            w,
            "| block | p | ε | η_c,16 | η_c,50 | η_c,84 |\n|---|---:|---:|---:|---:|---:|"
        );
        for b in &d.records_plan().blocks {
            let at = |q: f64| {
                d.capacity_fractiles
                    .iter()
                    .find(|r| r.block == b.name && r.quantile == q)
                    .map_or(f64::NAN, |r| r.eta_c)
            };
            let _ = writeln!(
                w,
                "| {} | {:.3} | {:.3} | {} | {} | {} |",
                b.name,
                b.p,
                b.eps,
                eta_cell(at(0.16)),
                eta_cell(at(0.5)),
                eta_cell(at(0.84))
            );
        }
        let _ = writeln!(w);
        survives_note(w, d);
        return;
    }
    let (ps, es) = d.ps_and_eps();
    for (q, label) in [(0.5, "median η_c,50"), (0.16, "η_c,16"), (0.84, "η_c,84")] {
        let _ = writeln!(w, "{label}, rows p (1/s), columns ε:\n");
        let header: Vec<String> = es.iter().map(|e| format!("{e:.2}")).collect();
        let _ = writeln!(w, "| p \\ ε | {} |", header.join(" | "));
        let _ = writeln!(w, "|---:|{}", "---:|".repeat(es.len()));
        for &p in &ps {
            let cells: Vec<String> = es
                .iter()
                .map(|&e| fractile_at(d, p, e, q).map_or(String::new(), eta_cell))
                .collect();
            let _ = writeln!(w, "| {p:.3} | {} |", cells.join(" | "));
        }
        let _ = writeln!(w);
    }
    survives_note(w, d);
    if let Some(line) = against_eq10(d) {
        let _ = writeln!(w, "{line}\n");
    }
}

/// The grid's medians against the paper's Eq. 10, over the blocks with
/// p ≥ 0.5 1/s: the mean of |η_c,50 / Eq. 10 − 1|. A median that never
/// overturns (η_c,50 = 0: the grid stopped first) has no deviation to
/// count; it was counted as 100 %, and is now left out and said.
fn against_eq10(d: &StudyData) -> Option<String> {
    let law = &fragility::paper()[1];
    let medians = || {
        d.capacity_fractiles
            .iter()
            .filter(|r| r.quantile == 0.5 && r.p >= 0.5)
    };
    let ratios: Vec<f64> = medians()
        .filter(|r| r.eta_c > 0.0)
        .map(|r| (r.eta_c / law.eta_c(r.p, r.eps) - 1.0).abs())
        .collect();
    if ratios.is_empty() {
        return None;
    }
    let survive = medians().count() - ratios.len();
    Some(format!(
        "Against the paper's Eq. 10: mean |η_c,50 / Eq. 10 − 1| = {:.1} % over the {} block{} \
         with p ≥ 0.5 1/s{}.",
        100.0 * ratios.iter().sum::<f64>() / ratios.len() as f64,
        ratios.len(),
        if ratios.len() == 1 { "" } else { "s" },
        match survive {
            0 => String::new(),
            n => format!(
                " ({n} more whose median never overturns down to the grid's last level left out)"
            ),
        }
    ))
}

/// A capacity fractile as the tables show it: η_c, or "survives" where
/// the fractile falls among the records that never overturned the block
/// (η_c = 0 in `capacity_fractiles.parquet`).
fn eta_cell(v: f64) -> String {
    if v == 0.0 {
        "survives".into()
    } else {
        format!("{v:.4}")
    }
}

/// What "survives" means, under a table that shows it.
fn survives_note(w: &mut String, d: &StudyData) {
    if d.capacity_fractiles.iter().any(|r| r.eta_c == 0.0) {
        let _ = writeln!(
            w,
            "\"survives\": the fractile falls among the records that never overturned the block \
             down to the grid's last level, η = {} (η_c = 0 in `capacity_fractiles.parquet`).\n",
            d.records_plan().grid.eta_min
        );
    }
}

fn lognormality(w: &mut String, d: &StudyData) {
    let tested: Vec<_> = d
        .lognormal
        .iter()
        .filter(|r| r.p_value.is_some_and(f64::is_finite))
        .collect();
    let kept = tested.iter().filter(|r| !r.rejected_5pct).count();
    let _ = writeln!(w, "## Lognormality of η_c\n");
    let _ = writeln!(
        w,
        "The Lilliefors test does not reject lognormality at 5 % in **{kept} of {}** blocks ({:.0} %; the paper found about 80 %). p-values: Dallal–Wilkinson (1986), Stephens (1974) above 0.1, as R's `nortest`.\n",
        tested.len(),
        100.0 * kept as f64 / tested.len().max(1) as f64
    );
}

fn regression(w: &mut String, d: &StudyData) {
    if d.laws.is_empty() {
        return;
    }
    let conv = d.fit_step1.iter().filter(|r| r.converged).count();
    let _ = writeln!(w, "## Regression η_c = a(1 − e^(−bp))^c\n");
    let _ = writeln!(
        w,
        "Step 1 converged in {conv} of {} (ε, fractile) fits. Step 2, against the paper:\n",
        d.fit_step1.len()
    );
    let _ = writeln!(w, "| fractile | | a = c0 + c1 ε | b = c0 + c1 ε + c2 ε² | c = c0 + c1 ε + c2 ε² |\n|---|---|---|---|---|");
    // An empty polynomial: too few converged step-1 fits to fit it.
    let fmt = |c: &[f64]| {
        if c.is_empty() {
            return "—".to_string();
        }
        c.iter()
            .map(|v| format!("{v:+.3}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut incomplete = false;
    for paper in fragility::paper().iter() {
        if let Some(law) = d.laws.iter().find(|l| l.quantile == paper.quantile) {
            incomplete |= law.a.is_empty() || law.b.is_empty() || law.c.is_empty();
            let _ = writeln!(
                w,
                "| {:.0} % | fitted | {} | {} | {} |",
                100.0 * law.quantile,
                fmt(&law.a),
                fmt(&law.b),
                fmt(&law.c)
            );
        }
        let _ = writeln!(
            w,
            "| | paper | {} | {} | {} |",
            fmt(&paper.a),
            fmt(&paper.b),
            fmt(&paper.c)
        );
    }
    if incomplete {
        let _ = writeln!(
            w,
            "\n— : too few converged step-1 fits of that fractile to fit the polynomial (a line needs 2, a quadratic 3)."
        );
    }
    let _ = writeln!(w);
}

fn convergence(w: &mut String, d: &StudyData) {
    let Some(conv) = &d.convergence else { return };
    let _ = writeln!(w, "## Capacity against IM-grid resolution\n");
    let summary = convergence_levels(conv);
    let levels: Vec<f64> = summary.iter().map(|c| c.levels).collect();
    let finest = levels.last().copied().unwrap_or(0.0);
    let _ = writeln!(
        w,
        "The capacity search repeated with {} levels; each record's η_c compared with the {finest}-level grid's.\n",
        levels.iter().map(|l| format!("{l}")).collect::<Vec<_>>().join(", ")
    );
    let _ = writeln!(w, "| levels | capacities that differ | mean abs. change | largest change | mean η_c,50 |\n|---:|---:|---:|---:|---:|");
    for c in &summary {
        let _ = writeln!(
            w,
            "| {} | {} of {} ({:.1} %) | {:.2e} | {:.3} | {:.4} |",
            c.levels,
            c.changed,
            c.total,
            100.0 * c.changed / c.total.max(1.0),
            c.mean_abs_change,
            c.max_abs_change,
            c.mean_q50
        );
    }
    let mean_q50 = |l: f64| {
        summary
            .iter()
            .find(|c| c.levels == l)
            .map_or(f64::NAN, |c| c.mean_q50)
    };
    let coarsest = levels.first().copied().unwrap_or(finest);
    let study = levels
        .iter()
        .copied()
        .find(|&l| l == d.records_plan().grid.count as f64)
        .unwrap_or(coarsest);
    let _ = writeln!(
        w,
        "\nA coarser grid can step over a thin island of overturning below the first one a finer grid finds, \
         so individual capacities move by much more than the refinement tolerance. The mean η_c,50 moves by \
         {:+.1} % from {study} levels (this study's grid) to {finest}, and by {:+.1} % from {coarsest} to {finest}: \
         capacities from a coarse grid are biased low.\n",
        100.0 * (mean_q50(finest) / mean_q50(study) - 1.0),
        100.0 * (mean_q50(finest) / mean_q50(coarsest) - 1.0),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{fractile, grid_study};

    /// Text records through a `[floor]` are its ground motions: the report
    /// says so first (it said nothing, and a structural model's floor
    /// motions passed through the building twice); over AT2 records, not.
    #[test]
    fn text_records_through_a_floor_are_said_to_be_its_ground() {
        let said = |d: &StudyData| {
            let mut w = String::new();
            text_records(&mut w, d);
            w
        };
        let through = said(&crate::figures::fixture::text_floor_study());
        assert!(through.contains("taken as its ground motions"), "{through}");
        assert!(said(&crate::figures::fixture::floor_study()).is_empty());
    }

    /// Two blocks at p = 1: one median 10 % above Eq. 10, one that never
    /// overturns (0): the mean is 10 % over one block, the other said
    /// (it counted as 100 %, which made the mean 55 %).
    #[test]
    fn a_median_that_never_overturns_is_not_a_deviation_from_eq_10() {
        let mut d = grid_study(&[1.0], &[0.5, 0.9]);
        let eq10 = fragility::paper()[1].eta_c(1.0, 0.5);
        d.capacity_fractiles = vec![
            fractile(1.0, 0.5, 0.5, 1.1 * eq10),
            fractile(1.0, 0.9, 0.5, 0.0),
        ];
        let line = against_eq10(&d).unwrap();
        assert!(line.contains("= 10.0 % over the 1 block with"), "{line}");
        assert!(
            line.contains("(1 more whose median never overturns"),
            "{line}"
        );
        d.capacity_fractiles.pop();
        assert!(!against_eq10(&d).unwrap().contains("never overturns"));
    }
}
