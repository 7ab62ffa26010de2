//! The report's scene section: the building whose floor the blocks stand
//! on (each block's capacity on the floor and in the ground's PGA), and
//! the blocks that slide (`sliding`).

use std::fmt::Write as _;

use crate::figures::floor::floor_fractiles;
use crate::study::StudyData;
use crate::tables::ims::EfficiencyRow;

/// The demands the floor table states each block's fragility in: the
/// floor's (FEMA P-58's) and the ground's (the hazard's).
const DEMANDS: [(&str, &str); 4] = [
    ("pfa", "PFA (g)"),
    ("pfv", "PFV (cm/s)"),
    ("pga", "ground PGA (g)"),
    ("pgv", "ground PGV (cm/s)"),
];

/// Each block's lognormal fragility in the floor's demands beside the
/// ground's IMs (text records, stood on, have no ground: the floor's
/// alone), from the ims stage's `im_efficiency`.
fn demands_table(w: &mut String, d: &StudyData) {
    let demands = if d.stood_on {
        &DEMANDS[..2]
    } else {
        &DEMANDS[..]
    };
    let blocks: Vec<(i64, &str, f64)> = {
        let mut seen: Vec<(i64, &str, f64)> = Vec::new();
        for r in &d.efficiency {
            if !seen.iter().any(|s| s.0 == r.block_index) {
                seen.push((r.block_index, &r.block, r.p));
            }
        }
        seen
    };
    let find = |bi: i64, im: &str| -> Option<&EfficiencyRow> {
        d.efficiency
            .iter()
            .find(|r| r.block_index == bi && r.im == im)
    };
    if !blocks.iter().any(|b| find(b.0, "pfv").is_some()) {
        return;
    }
    let _ = writeln!(
        w,
        "Each block's fragility in the floor's demands (FEMA P-58's, of the motion it stands \
         on){}: the median exp(mean ln IM_c) and the \
         dispersion β over the records that overturn it (`im_efficiency.parquet`, which holds \
         FSA(T) too). These are moment fits: `rocking fragility --im pfa|pfv|fsa(T) --direct` \
         runs the same records but fits them by the paper's fractiles (or draws their own \
         curve where the lognormal check fails), so its medians differ from these by the fit, \
         by up to some 15 % where the capacities are skewed.\n",
        if d.stood_on {
            ""
        } else {
            " and in the ground's IMs (the hazard's)"
        }
    );
    let head: Vec<String> = demands
        .iter()
        .map(|(_, name)| format!("{name}: median, β"))
        .collect();
    let _ = writeln!(
        w,
        "| block | p (1/s) | {} |\n|---|---|{}",
        head.join(" | "),
        "---|".repeat(demands.len())
    );
    for &(bi, name, p) in &blocks {
        let cells: Vec<String> = demands
            .iter()
            .map(|(im, _)| {
                find(bi, im).map_or("—".into(), |r| match r.median {
                    Some(m) if r.unit == "cm/s" => format!("{m:.1}, {:.2}", r.beta),
                    Some(m) => format!("{m:.3}, {:.2}", r.beta),
                    None => format!("—, {:.2}", r.beta),
                })
            })
            .collect();
        let _ = writeln!(w, "| {name} | {p:.3} | {} |", cells.join(" | "));
    }
    let _ = writeln!(w);
}

/// `## On a building's floor` for a `[floor]` study, and `## Blocks that
/// slide first` when a block's μ is below its b/h.
pub(super) fn scene_section(w: &mut String, d: &StudyData) {
    let plan = d.records_plan();
    if let Some(building) = &plan.floor {
        let _ = writeln!(w, "## On a building's floor\n");
        let _ = writeln!(
            w,
            "Every record is run through a linear building with modes T, ζ, Γφ = {building} \
             (docs/MODEL.md §16), and the blocks feel its floor's absolute acceleration. η is the \
             floor motion's throughout the tables (α g over its peak, the PFA); \
             `capacities.parquet` holds each record's PFA/PGA, and the ground's η is η·PFA/PGA. \
             The IM tables are in the ground's IMs (the hazard's), followed by the floor's \
             demands PFA, PFV and FSA(T) (FEMA P-58's).\n"
        );
        let ratios: Vec<f64> = d
            .caps
            .iter()
            .step_by(plan.blocks.len().max(1))
            .filter_map(|c| c.pfa_over_pga)
            .collect();
        if let (Some(lo), Some(hi)) = (
            ratios.iter().copied().reduce(f64::min),
            ratios.iter().copied().reduce(f64::max),
        ) {
            let below = ratios.iter().filter(|&&r| r < 1.0).count();
            let _ = writeln!(
                w,
                "The building scales the records' peaks by PFA/PGA = {lo:.2} to {hi:.2}{}.\n",
                match below {
                    0 => ": it amplifies every one".to_string(),
                    n => format!(
                        " (it reduces the peak of {n} of the {} records)",
                        ratios.len()
                    ),
                }
            );
        }
        let _ = writeln!(
            w,
            "| block | p (1/s) | median PFA_c (g) | median ground PGA_c (g) | ratio |\n|---|---|---|---|---|"
        );
        for r in floor_fractiles(d) {
            let g = |v: f64| {
                if v.is_finite() {
                    format!("{v:.3}")
                } else {
                    "survives".into()
                }
            };
            let _ = writeln!(
                w,
                "| {} | {:.3} | {} | {} | {} |",
                r.block,
                r.p,
                g(r.pfa_g[1]),
                g(r.ground_pga_g[1]),
                g(r.pfa_g[1] / r.ground_pga_g[1])
            );
        }
        let _ = writeln!(w);
        demands_table(w, d);
    } else if d.stood_on {
        let _ = writeln!(w, "## In the floor's demands\n");
        demands_table(w, d);
    }
    super::sliding::sliding_section(w, d);
}
