//! The Markdown of a pulse map (`[pulses]` pipelines): settings, run times,
//! the walls against the paper's closed forms, the modes met, the figures.

use std::fmt::Write as _;

use super::shared::{figures_section, heading, list};
use crate::figures::Figure;
use crate::pipeline::{Plan, PulsePlan};
use crate::study::PulseData;

/// The report of a pulse map (`[pulses]` pipelines): settings, the walls
/// against the paper's closed forms, the modes met, and the figures.
pub fn render_pulses(d: &PulseData, figures: &[Figure]) -> String {
    let mut md = String::new();
    let plan = &d.plan;
    heading(
        &mut md,
        "Pulse map",
        plan,
        &d.pipeline,
        &d.version,
        " (`pulse_walls.parquet`, `pulse_map.parquet`)",
    );
    if let Some(pp) = plan.pulse_map() {
        settings(&mut md, plan, pp);
    }
    runtime(&mut md, d);
    walls(&mut md, d);
    modes(&mut md, d);
    figures_section(&mut md, figures);
    md
}

/// The map's settings: the pulse shapes and cycle, the model, ε, f and η.
fn settings(md: &mut String, plan: &Plan, pp: &PulsePlan) {
    let shapes: Vec<String> = pp
        .shapes
        .iter()
        .map(|s| match s.beta() {
            Some(b) => format!("exp β = {b}"),
            None => "rect".into(),
        })
        .collect();
    let _ = writeln!(md, "## Settings\n");
    let _ = writeln!(md, "| setting | value |\n|---|---|");
    let _ = writeln!(
        md,
        "| pulse | {}; {} cycle, lobes of t_d = 1 s (so p = f) |",
        shapes.join("; "),
        pp.cycle.name()
    );
    let _ = writeln!(
        md,
        "| model | {}, overturning {} |",
        super::study::model_text(plan.model),
        plan.overturn
    );
    let _ = writeln!(md, "| ε | {} |", list(&pp.eps));
    let span = |v: &[f64], what: &str| {
        let end = |x: Option<&f64>| x.copied().unwrap_or(f64::NAN);
        format!(
            "{} {what} from {} to {}",
            v.len(),
            end(v.first()),
            end(v.last())
        )
    };
    let _ = writeln!(md, "| f | {} |", span(&pp.f, "values"));
    let _ = writeln!(md, "| map | {} |", span(&pp.eta, "η levels"));
    let _ = writeln!(md, "| walls | a 500-level log grid of η from 1 to 1e-5, the first overturning bisected to 1e-10 |\n");
}

/// The time each stage took when it last ran.
fn runtime(md: &mut String, d: &PulseData) {
    let _ = writeln!(md, "## Runtime\n");
    let _ = writeln!(md, "| stage | time (s) |\n|---|---:|");
    for (s, t) in &d.stage_seconds {
        if let Some(t) = t {
            let _ = writeln!(md, "| {s} | {t:.2} |");
        }
    }
    let _ = writeln!(md);
}

/// Each family's walls against the paper's closed form, where one applies.
fn walls(md: &mut String, d: &PulseData) {
    let _ = writeln!(md, "## Walls against the paper's closed forms\n");
    let _ = writeln!(md, "| family | equation | wall | walls compared | largest relative difference |\n|---|---|---|---:|---:|");
    let mut any = false;
    for (beta, eps, label) in d.families() {
        let diffs: Vec<f64> = d
            .walls_of(beta, eps)
            .filter_map(|w| w.closed_form_gap())
            .collect();
        let first = d.walls_of(beta, eps).find(|w| w.closed_form.is_some());
        if let (Some(w), false) = (first, diffs.is_empty()) {
            any = true;
            let _ = writeln!(
                md,
                "| {label} | {} | {} | {} | {} |",
                w.closed_form_equation.as_deref().unwrap_or(""),
                match w.closed_form_kind() {
                    Some(crate::pulse::WallKind::Any) => "η_w",
                    _ => "η_w,0 (Mode 0)",
                },
                diffs.len(),
                largest_gap(&diffs)
            );
        }
    }
    if !any {
        let _ = writeln!(
            md,
            "| (none: no closed form applies to this pulse, model and criterion) | | | | |"
        );
    }
    let _ = writeln!(md);
}

/// The largest relative difference, or how many walls have none: a NaN
/// (a closed form or wall that could not be evaluated) is never folded away.
fn largest_gap(diffs: &[f64]) -> String {
    let undefined = diffs.iter().filter(|d| d.is_nan()).count();
    if undefined > 0 {
        return format!("**undefined (NaN) for {undefined} of {}**", diffs.len());
    }
    format!("{:.1e}", diffs.iter().cloned().fold(0.0, f64::max))
}

/// How many of each family's map points are safe or overturn in each mode.
fn modes(md: &mut String, d: &PulseData) {
    let _ = writeln!(md, "## Modes of overturning met on the map\n");
    let _ = writeln!(
        md,
        "| family | points | safe | Mode 0 | Mode 1 | Mode 2+ |\n|---|---:|---:|---:|---:|---:|"
    );
    for (beta, eps, label) in d.families() {
        let cells: Vec<_> = d.cells_of(beta, eps).collect();
        let n = |keep: &dyn Fn(bool, i64) -> bool| {
            cells
                .iter()
                .filter(|c| keep(c.overturned, c.impacts))
                .count()
        };
        let _ = writeln!(
            md,
            "| {label} | {} | {} | {} | {} | {} |",
            cells.len(),
            n(&|o, _| !o),
            n(&|o, i| o && i == 0),
            n(&|o, i| o && i == 1),
            n(&|o, i| o && i >= 2)
        );
    }
    let _ = writeln!(md);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{pulse_study, wall};

    /// A wall whose closed form is NaN is reported as such, not folded
    /// into the largest difference by `f64::max` (which drops NaN).
    #[test]
    fn a_nan_closed_form_is_reported_not_hidden() {
        let mut d = pulse_study("shape = \"exp\"\nbeta = [-5.0]\ncycle = \"half\"\neps = [0.9]");
        d.walls = vec![
            wall(
                Some(-5.0),
                0.9,
                2.0,
                Some(0.5),
                Some((0.5, "Eq. 5", "eta_w")),
            ),
            wall(
                Some(-5.0),
                0.9,
                10.0,
                Some(0.9),
                Some((f64::NAN, "Eq. 5", "eta_w")),
            ),
        ];
        let mut md = String::new();
        walls(&mut md, &d);
        assert!(md.contains("undefined (NaN) for 1 of 2"), "{md}");
        d.walls.pop();
        let mut md = String::new();
        walls(&mut md, &d);
        assert!(md.contains("| 1 | 0.0e0 |"), "{md}");
        // The model by its name in the paper, not the Rust variant.
        let mut md = String::new();
        settings(&mut md, &d.plan, d.plan.pulse_map().unwrap());
        assert!(md.contains("linearised equation (paper Eq. 8)"), "{md}");
        assert!(!md.contains("Linearized"), "{md}");
    }
}
