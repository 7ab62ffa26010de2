//! A study over orientations (`[records] orientation = "random"`): each
//! block's capacity under the three orientation rules, and each pair's
//! capacity against the angle (docs/MODEL.md §18).
//!
//! The study's records are `<a>@<θ>`, every pair at every angle. The
//! capacity is the rotated component's own PGA at overturning, α/η_c (g;
//! on a floor the ground's), or 1/η_c (in αg) for a block without α. As
//! recorded are the angles 0° and 90° (the components themselves), random
//! every angle, worst each pair's smallest.

use super::figure::Figure;
use super::shared::Q_VALUES;
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::stats;
use crate::study::StudyData;

/// One block's capacity fractiles (16, 50, 84 %) by each rule, +∞ where
/// the fractile survives.
#[derive(Debug, Clone, PartialEq)]
pub struct OrientationFractiles {
    pub block: String,
    pub p: f64,
    pub eps: f64,
    /// In g (`true`) or in αg.
    pub in_g: bool,
    /// The components as recorded (0° and 90°); `None` when the step
    /// does not land on 90°.
    pub as_recorded: Option<[f64; 3]>,
    pub random: [f64; 3],
    pub worst: [f64; 3],
    /// The components as recorded in their own PGA, as the ims stage
    /// states an IM: exp(mean ln PGA_c) and the standard deviation of
    /// ln PGA_c (n − 1) over those that overturn the block.
    pub as_recorded_lognormal: Option<(f64, f64)>,
    pub pairs: usize,
    pub angles: usize,
}

/// Each block's capacities by pair (its first component's id) and angle,
/// pairs in the study's order: `(pair, [(θ, capacity)])`.
fn by_pair(d: &StudyData, bi: usize) -> Vec<(String, Vec<(f64, f64)>)> {
    let plan = d.records_plan();
    let n_blocks = plan.blocks.len().max(1);
    let alpha = plan.blocks[bi].alpha_rad;
    let mut out: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for c in d.caps.iter().skip(bi).step_by(n_blocks) {
        let Some((pair, theta)) = crate::pair::split_angled_id(&c.record_id) else {
            continue;
        };
        let ground = c.pfa_over_pga.unwrap_or(1.0);
        let cap = c
            .eta_c
            .map_or(f64::INFINITY, |e| alpha.unwrap_or(1.0) / (e * ground));
        match out.iter_mut().find(|(p, _)| p == pair) {
            Some((_, v)) => v.push((theta, cap)),
            None => out.push((pair.to_string(), vec![(theta, cap)])),
        }
    }
    out
}

/// The fractiles of `values` by the plan's definition.
fn fractiles(d: &StudyData, mut values: Vec<f64>) -> [f64; 3] {
    values.sort_by(f64::total_cmp);
    let def = d.records_plan().fractile;
    Q_VALUES.map(|q| stats::fractile(&values, q, def).unwrap_or(f64::NAN))
}

/// Every block's fractiles by each rule; empty unless the study turns its pairs.
pub fn orientation_fractiles(d: &StudyData) -> Vec<OrientationFractiles> {
    let plan = d.records_plan();
    if plan.random_orientation.is_none() {
        return Vec::new();
    }
    plan.blocks
        .iter()
        .enumerate()
        .filter_map(|(bi, b)| {
            let pairs = by_pair(d, bi);
            let angles = pairs.first()?.1.len();
            let all: Vec<f64> = pairs
                .iter()
                .flat_map(|(_, v)| v.iter().map(|x| x.1))
                .collect();
            let axes: Vec<f64> = pairs
                .iter()
                .flat_map(|(_, v)| v.iter().filter(|x| x.0 == 0.0 || x.0 == 90.0).map(|x| x.1))
                .collect();
            let worst: Vec<f64> = pairs
                .iter()
                .map(|(_, v)| v.iter().map(|x| x.1).fold(f64::INFINITY, f64::min))
                .collect();
            let logs: Vec<f64> = axes
                .iter()
                .filter(|v| v.is_finite())
                .map(|v| v.ln())
                .collect();
            let as_recorded_lognormal = (logs.len() >= 3 && axes.len() == 2 * pairs.len())
                .then(|| stats::mean_sd(&logs))
                .map(|(m, s)| (m.exp(), s));
            Some(OrientationFractiles {
                as_recorded_lognormal,
                block: b.name.clone(),
                p: b.p,
                eps: b.eps,
                in_g: b.alpha_rad.is_some(),
                as_recorded: (axes.len() == 2 * pairs.len()).then(|| fractiles(d, axes)),
                random: fractiles(d, all),
                worst: fractiles(d, worst),
                pairs: pairs.len(),
                angles,
            })
        })
        .collect()
}

/// One block's capacity with its rocking plane along each pair's
/// strongest velocity and across it, as the pair's RotD50 PGA at
/// overturning (g, or αg without α): the pair scaled until the block falls.
#[derive(Debug, Clone, PartialEq)]
pub struct PulseDirection {
    pub block: String,
    pub p: f64,
    pub eps: f64,
    /// Median over the pairs, along the direction of the largest PGV.
    pub along: f64,
    /// Median over the pairs, 90° from it.
    pub across: f64,
    pub pairs: usize,
}

/// A motion's value of `im` in `record_ims`.
fn measure(d: &StudyData, id: &str, im: &str) -> Option<f64> {
    d.record_ims
        .iter()
        .find(|r| r.record_id == id && r.im == im)
        .map(|r| r.value)
}

/// Each block's capacity along and across its pairs' strongest velocity
/// (the angle of the study's whose rotated component has the largest PGV:
/// the pulse's direction in a pulse-like record, near the fault normal),
/// where the angles hold θ + 90° and the ims stage wrote each motion's
/// PGA, PGV and its pair's RotD50 PGA.
pub fn pulse_directions(d: &StudyData) -> Vec<PulseDirection> {
    let plan = d.records_plan();
    if plan.random_orientation.is_none() || d.record_ims.is_empty() {
        return Vec::new();
    }
    plan.blocks
        .iter()
        .enumerate()
        .filter_map(|(bi, b)| {
            let mut along = Vec::new();
            let mut across = Vec::new();
            for (pair, v) in by_pair(d, bi) {
                let id = |t: f64| crate::pair::angled_id(&pair, t);
                let pgv = |t: f64| measure(d, &id(t), "pgv").unwrap_or(f64::NAN);
                let strongest = v
                    .iter()
                    .map(|x| x.0)
                    .max_by(|a, b| pgv(*a).total_cmp(&pgv(*b)))?;
                let other = (strongest + 90.0) % 180.0;
                // The pair's RotD50 PGA at overturning: its scale factor
                // PGA_c/PGA_θ times its RotD50 PGA.
                let in_rotd = |t: f64| -> Option<f64> {
                    let cap = v.iter().find(|x| x.0 == t)?.1;
                    Some(cap / measure(d, &id(t), "pga")? * measure(d, &id(t), "rotd50_pga")?)
                };
                along.push(in_rotd(strongest)?);
                across.push(in_rotd(other)?);
            }
            let n = along.len();
            Some(PulseDirection {
                block: b.name.clone(),
                p: b.p,
                eps: b.eps,
                along: fractiles(d, along)[1],
                across: fractiles(d, across)[1],
                pairs: n,
            })
        })
        .collect()
}

/// The first block's capacity against the angle, one line per pair.
pub(super) fn orientation_capacity(d: &StudyData) -> Vec<Figure> {
    let plan = d.records_plan();
    if plan.random_orientation.is_none() || plan.blocks.is_empty() {
        return Vec::new();
    }
    let pairs = by_pair(d, 0);
    if pairs.is_empty() {
        return Vec::new();
    }
    let b = &plan.blocks[0];
    let unit = if b.alpha_rad.is_some() { "g" } else { "αg" };
    let lines = pairs
        .iter()
        .enumerate()
        .map(|(i, (_, v))| Line {
            name: None,
            // 180° is 0° mirrored: the line closes on its first point.
            points: v
                .iter()
                .copied()
                .chain(v.iter().find(|x| x.0 == 0.0).map(|x| (180.0, x.1)))
                .filter(|x| x.1.is_finite())
                .collect(),
            style: Style::LinePoints,
            hue: Hue::Series(i),
        })
        .collect();
    let name = if b.name.is_empty() {
        format!("p = {:.2} 1/s, ε = {}", b.p, b.eps)
    } else {
        format!("{} (p = {:.2} 1/s)", b.name, b.p)
    };
    vec![Figure {
        file: "orientation_capacity.svg".into(),
        chart: Chart {
            title: "Capacity against the block's orientation".into(),
            x_desc: "θ, the rocking plane from the pair's first component (°)".into(),
            y_desc: format!("the rotated component's PGA at overturning ({unit})"),
            x_scale: Scale::Linear,
            y_scale: Scale::Log,
            x_range: Some((0.0, 180.0)),
            y_range: None,
            x_ticks: None,
            lines,
        },
        caption: format!(
            "{name}: each of the {} record pairs run with its rocking plane at θ from its first \
             component towards its second (θ = 0° and 90° are the components as recorded; θ + \
             180° is θ's mirror image, so 180° repeats 0°). A pair's spread over θ is what the paper's \
             per-component capacities leave out.",
            pairs.len()
        ),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::cap;
    use crate::pipeline::load_str;
    use crate::tables::sweep::CapacityRow;

    /// Two pairs at 0, 45, 90, 135°, one block of α: capacities α/η_c by
    /// hand. Type-7 medians: as recorded of 4 values, random of 8, worst
    /// of 2 (the mean of the two).
    #[test]
    fn the_rules_by_hand() {
        let mut d = crate::figures::fixture::block_study();
        d.plan = load_str(
            "[records]\nat2 = [\"r\"]\norientation = \"random\"\nangle_step = 45\n\
             [[block]]\nname = \"vase\"\nb = 0.1\nh = 0.4\neps = 0.8\n",
            std::path::Path::new("t.toml"),
        )
        .unwrap();
        let alpha = (0.25f64).atan();
        let etas = [
            ("A@0", 0.5),
            ("A@45", 0.25),
            ("A@90", 0.4),
            ("A@135", 0.2),
            ("B@0", 1.0),
            ("B@45", 0.8),
            ("B@90", 0.5),
            ("B@135", 0.625),
        ];
        d.caps = etas
            .iter()
            .enumerate()
            .map(|(i, &(id, e))| CapacityRow {
                record_id: id.into(),
                alpha_rad: Some(alpha),
                ..cap(i as i64, Some(e))
            })
            .collect();
        let rows = orientation_fractiles(&d);
        assert_eq!(rows.len(), 1);
        let r = &rows[0];
        assert_eq!((r.pairs, r.angles), (2, 4));
        // As recorded: α × {2, 2.5, 1, 2}: sorted 1, 2, 2, 2.5 → median 2α.
        assert!((r.as_recorded.unwrap()[1] - 2.0 * alpha).abs() < 1e-15);
        // Worst: A's smallest α/0.5 = 2α, B's α/1 = α: median 1.5α.
        assert!((r.worst[1] - 1.5 * alpha).abs() < 1e-15);
        // Random: 1, 1.25, 1.6, 2, 2, 2.5, 4, 5 (×α): median (2 + 2)/2 = 2α.
        assert!((r.random[1] - 2.0 * alpha).abs() < 1e-15);
        assert_eq!(orientation_capacity(&d).len(), 1);
        // A study as recorded has none.
        assert!(orientation_fractiles(&crate::figures::fixture::block_study()).is_empty());
        // Along the strongest velocity: A's at 45°, B's at 135° (PGV by
        // hand), across at 135° and 45°; PGA 0.5 g at every angle and
        // RotD50 PGA 0.6 g, so the RotD50 capacity is 1.2 × the rotated PGA's.
        let pgv = [10.0, 30.0, 20.0, 5.0, 10.0, 5.0, 20.0, 40.0];
        for (k, &(id, _)) in etas.iter().enumerate() {
            for (im, v) in [("pga", 0.5), ("pgv", pgv[k]), ("rotd50_pga", 0.6)] {
                d.record_ims.push(crate::tables::ims::RecordImRow {
                    record_id: id.into(),
                    im: im.into(),
                    unit: String::new(),
                    period_s: None,
                    value: v,
                });
            }
        }
        let pulse = pulse_directions(&d);
        // Along: A@45 α/0.25 = 4α, B@135 α/0.625 = 1.6α → median 2.8α (× 1.2).
        // Across: A@135 α/0.2 = 5α, B@45 α/0.8 = 1.25α → median 3.125α (× 1.2).
        assert_eq!(pulse[0].pairs, 2);
        assert!(
            (pulse[0].along - 1.2 * 2.8 * alpha).abs() < 1e-14,
            "{pulse:?}"
        );
        assert!(
            (pulse[0].across - 1.2 * 3.125 * alpha).abs() < 1e-14,
            "{pulse:?}"
        );
    }
}
