//! The report's section of a study over orientations: each block's
//! capacity as recorded, facing a random direction and at its worst angle
//! (docs/MODEL.md §18).

use std::fmt::Write as _;

use crate::figures::orientation::orientation_fractiles;
use crate::study::StudyData;

/// `## Facing any direction`, for a study with `orientation = "random"`.
pub(super) fn orientation_section(w: &mut String, d: &StudyData) {
    let rows = orientation_fractiles(d);
    let Some(first) = rows.first() else { return };
    let step = d.records_plan().random_orientation.unwrap_or(f64::NAN);
    let unit = if first.in_g { "g" } else { "αg" };
    let _ = writeln!(w, "## Facing any direction\n");
    let _ = writeln!(
        w,
        "Every one of the {} record pairs is run with the block's rocking plane at every angle \
         {step}° apart over [0°, 180°) ({} angles; `<record>@<θ>` in `capacities.parquet`). \
         The capacity is the rotated component's own PGA at overturning ({unit}); its 16/50/84 % \
         fractiles as recorded (the angles 0° and 90°, the components themselves: the paper's \
         sample), facing a random direction (every angle, equally weighted: what the tables \
         and fits of this study are) and at each pair's worst angle. In the hazard's RotD50 \
         rather than the rotated component's PGA: `rocking fragility --direct --orientation \
         random --im rotd50_pga` over the same records (docs/MODEL.md §18).\n",
        first.pairs, first.angles
    );
    let _ = writeln!(
        w,
        "| block | p (1/s) | ε | as recorded 16/50/84 % ({unit}) | random 16/50/84 % ({unit}) | worst 16/50/84 % ({unit}) | random/recorded median | worst/recorded median |\n|---|---|---|---|---|---|---|---|"
    );
    let f = |v: f64| {
        if v.is_finite() {
            format!("{v:.3}")
        } else {
            "∞".into()
        }
    };
    let three = |q: &[f64; 3]| format!("{}, {}, {}", f(q[0]), f(q[1]), f(q[2]));
    for r in &rows {
        let rec = r.as_recorded.map_or("—".into(), |q| three(&q));
        let ratio = |q: &[f64; 3]| {
            r.as_recorded
                .map_or("—".into(), |a| format!("{:.3}", q[1] / a[1]))
        };
        let _ = writeln!(
            w,
            "| {} | {:.3} | {:.3} | {rec} | {} | {} | {} | {} |",
            if r.block.is_empty() { "—" } else { &r.block },
            r.p,
            r.eps,
            three(&r.random),
            three(&r.worst),
            ratio(&r.random),
            ratio(&r.worst)
        );
    }
    let _ = writeln!(w);
    rotd_table(w, d, &rows);
    pulse_table(w, d);
}

/// Along each pair's strongest velocity against across it.
fn pulse_table(w: &mut String, d: &StudyData) {
    let rows = crate::figures::orientation::pulse_directions(d);
    if rows.is_empty() {
        return;
    }
    // In g for blocks of α; in αg for the p × ε grid.
    let with_alpha = d.records_plan().blocks.first().and_then(|b| b.alpha_rad);
    let unit = if with_alpha.is_some() { "g" } else { "αg" };
    let _ = writeln!(
        w,
        "Along the strongest velocity and across it: for each pair, the angle of the study's \
         whose rotated component has the largest PGV (in a pulse-like record the pulse's \
         direction, which lies near the fault normal; Shahi & Baker 2011) and the angle 90° \
         from it. The capacity is the pair's RotD50 PGA at overturning (the pair scaled until \
         the block falls; median over the pairs): below 1, the block rocking along the \
         strongest velocity falls to weaker shaking.\n"
    );
    let _ = writeln!(
        w,
        "| block | p (1/s) | ε | pairs | along: median RotD50 PGA_c ({unit}) | across ({unit}) | along/across |\n|---|---|---|---|---|---|---|"
    );
    for r in &rows {
        let _ = writeln!(
            w,
            "| {} | {:.3} | {:.3} | {} | {:.3} | {:.3} | {:.3} |",
            if r.block.is_empty() { "—" } else { &r.block },
            r.p,
            r.eps,
            r.pairs,
            r.along,
            r.across,
            r.along / r.across
        );
    }
    let _ = writeln!(w);
}

/// The paper's per-component fragility (as recorded, each component's own
/// PGA) against the random orientation's in the hazard's RotD50 PGA, from
/// the ims stage's `im_efficiency`.
fn rotd_table(
    w: &mut String,
    d: &StudyData,
    rows: &[crate::figures::orientation::OrientationFractiles],
) {
    let rotd = |r: &crate::figures::orientation::OrientationFractiles| {
        d.efficiency
            .iter()
            .find(|e| e.p == r.p && e.eps == r.eps && e.block == r.block && e.im == "rotd50_pga")
            // In g for a block of α; in αg (RotD50 PGA/(αg)) for the grid.
            .and_then(|e| Some((e.median.or(e.median_dimensionless)?, e.beta)))
    };
    if !rows
        .iter()
        .any(|r| rotd(r).is_some() && r.as_recorded_lognormal.is_some())
    {
        return;
    }
    let _ = writeln!(
        w,
        "Against the hazard: the paper's per-component fragility (as recorded, in each \
         component's own PGA) and the random orientation's in its pair's RotD50 PGA, the \
         component of the ground-motion models behind a hazard curve (the median exp(mean ln) \
         and β over the motions that overturn the block, in {}; `im_efficiency.parquet`). \
         These are moment fits, as the IM comparison's: `rocking fragility --direct \
         --orientation random --im rotd50_pga` fits the same capacities by the paper's \
         fractiles (or draws the records' own curve where the lognormal check fails), so its \
         median differs from this table's by the fit, a few per cent.\n",
        if rows[0].in_g { "g" } else { "αg: PGA/(αg)" }
    );
    let unit = if rows[0].in_g { "g" } else { "αg" };
    let _ = writeln!(
        w,
        "| block | p (1/s) | ε | as recorded, PGA: median ({unit}), β | random, RotD50 PGA: median ({unit}), β | median ratio | β change |\n|---|---|---|---|---|---|---|"
    );
    for r in rows {
        let (Some((m0, b0)), Some((m1, b1))) = (r.as_recorded_lognormal, rotd(r)) else {
            continue;
        };
        let _ = writeln!(
            w,
            "| {} | {:.3} | {:.3} | {m0:.3}, {b0:.3} | {m1:.3}, {b1:.3} | {:.3} | {:+.3} |",
            if r.block.is_empty() { "—" } else { &r.block },
            r.p,
            r.eps,
            m1 / m0,
            b1 - b0
        );
    }
    let _ = writeln!(w);
}
