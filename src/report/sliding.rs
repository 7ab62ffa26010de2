//! The report's section on blocks that slide: those the slide-rock model
//! ran (their overturning beside the intensity at which their base has
//! slid 5 and 30 cm), and those a rocking model ran although they slide
//! first.

use std::fmt::Write as _;

use crate::damage::{self, DamageStates, StateCapacity, StateRun};
use crate::pipeline::BlockSpec;
use crate::study::StudyData;

/// The slides the section states, as damage states on the slide (each
/// reached by the slide or by overturning).
const SLIDES: &str = "slide_5cm=0.05m,slide_30cm=0.3m,overturned=overturned";

/// One block run sliding, over the records.
struct Row {
    name: String,
    mu: f64,
    b_over_h: f64,
    records: usize,
    overturned: usize,
    /// Runs in which the base slid at all, and all runs.
    slid: usize,
    runs: usize,
    /// Median of the records' capacities (peak of the motion the block
    /// feels, g) for 5 cm, 30 cm and overturning; `None` where more than
    /// half never reach it.
    medians: [Option<f64>; 3],
}

pub(super) fn sliding_section(w: &mut String, d: &StudyData) {
    let (sliding, rocking): (Vec<&BlockSpec>, Vec<&BlockSpec>) = d
        .plan
        .blocks()
        .iter()
        .filter(|b| b.mu.is_some())
        .partition(|b| b.run.model.equation.friction().is_some());
    let rows: Vec<Row> = sliding.iter().filter_map(|b| row(d, b)).collect();
    if !rows.is_empty() {
        let _ = writeln!(w, "## Blocks that slide\n");
        let _ = writeln!(
            w,
            "These blocks ran on their base's friction (the slide-rock model, docs/MODEL.md §21): \
             a block with μ up to b/h slides before it rocks and, under horizontal shaking, never \
             overturns; one above it rocks first and slips where its friction demand reaches μN. \
             Each record's capacity for a slide of 5 or 30 cm (or overturning, whichever comes \
             first) is where its IDA's slide first reaches it, interpolated in 1/η as the damage \
             states are; the medians are over the records, in the peak of the motion the block \
             feels (PGA, or PFA on a floor), \"—\" where more than half never reach it. Every \
             run's slide is `slide_max_m` in `ida_points.parquet`.\n"
        );
        let _ = writeln!(
            w,
            "| block | μ | b/h | records overturned | runs that slid | median at 5 cm (g) | \
             median at 30 cm (g) | median overturning (g) |\n|---|---:|---:|---:|---:|---:|---:|---:|"
        );
        let g = |m: Option<f64>| m.map_or("—".to_string(), |v| format!("{v:.3}"));
        for r in &rows {
            let _ = writeln!(
                w,
                "| {} | {} | {:.3} | {} of {} | {} of {} | {} | {} | {} |",
                r.name,
                r.mu,
                r.b_over_h,
                r.overturned,
                r.records,
                r.slid,
                r.runs,
                g(r.medians[0]),
                g(r.medians[1]),
                g(r.medians[2])
            );
        }
        let _ = writeln!(w);
    }
    let first: Vec<String> = rocking
        .iter()
        .filter(|b| b.slides_first())
        .map(|b| {
            format!(
                "`{}` (μ = {}, b/h = {:.3})",
                b.name,
                b.mu.unwrap_or(f64::NAN),
                b.alpha_rad.unwrap_or(f64::NAN).tan()
            )
        })
        .collect();
    if !first.is_empty() {
        let _ = writeln!(w, "## Blocks that slide first, run rocking\n");
        let _ = writeln!(
            w,
            "{}: the base's friction coefficient μ does not exceed b/h, so the base slips before the \
             shaking can lift a corner (Ishiyama 1982; Shenton 1996; docs/MODEL.md §17), but \
             the study's model rocks them. Their capacities hold only for a block restrained \
             against sliding; `[model] kind = \"auto\"` or `\"slide-rock\"` runs them sliding. \
             `slides_first` marks the rows in `capacities.parquet`.\n",
            first.join(", ")
        );
    }
}

/// The block's row: its records' capacities for each slide and for
/// overturning, from its IDA runs.
fn row(d: &StudyData, b: &BlockSpec) -> Option<Row> {
    let alpha = b.alpha_rad?;
    let states = DamageStates::parse(SLIDES).expect("valid states");
    let caps: Vec<_> = d.caps.iter().filter(|c| c.block == b.name).collect();
    let mut per_state: [Vec<f64>; 3] = Default::default();
    let (mut slid, mut runs) = (0, 0);
    for c in &caps {
        let points = d
            .ida
            .iter()
            .filter(|r| r.block == b.name && r.record_id == c.record_id);
        let points: Vec<StateRun> = points
            .map(|r| {
                runs += 1;
                slid += usize::from(r.slide_max_m.is_some_and(|s| s > 0.0));
                StateRun {
                    eta: r.eta,
                    edp: r.edp,
                    slide_m: r.slide_max_m.unwrap_or(0.0),
                    overturned: r.overturned,
                }
            })
            .collect();
        let found = damage::capacities(&states, points, c.eta_c);
        for (all, cap) in per_state.iter_mut().zip(found) {
            all.push(match cap {
                StateCapacity::Reached(eta) => alpha / eta,
                StateCapacity::NotReached(_) => f64::INFINITY,
            });
        }
    }
    let def = d.plan.records_study().ok()?.fractile;
    let medians = per_state.map(|mut v| {
        v.sort_by(f64::total_cmp);
        crate::stats::fractile(&v, 0.5, def).filter(|m| m.is_finite())
    });
    Some(Row {
        name: b.name.clone(),
        mu: b.mu?,
        b_over_h: alpha.tan(),
        records: caps.len(),
        overturned: caps.iter().filter(|c| c.eta_c.is_some()).count(),
        slid,
        runs,
        medians,
    })
}
