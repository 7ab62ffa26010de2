//! A floor study's figure (`[floor]`): each block's capacity as the floor's
//! peak acceleration (PFA) and as the ground's PGA, side by side, and their
//! ratio.

use super::figure::Figure;
use super::shared::{Q_NAMES, Q_VALUES};
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::stats;
use crate::study::StudyData;

/// One block's capacity fractiles (16, 50, 84 %): as PFA and as the
/// ground's PGA (g), +∞ where the fractile survives every level.
#[derive(Debug, Clone, PartialEq)]
pub struct FloorFractiles {
    pub block: String,
    pub p: f64,
    pub pfa_g: [f64; 3],
    pub ground_pga_g: [f64; 3],
}

/// Each block's fractiles of PFA_c = α/η_c and of PGA_c = PFA_c/(PFA/PGA),
/// over the records (the plan's fractile definition; a record under which
/// the block survives every level counts as +∞, the resurrection rule's
/// capacity). Blocks without α have no acceleration and are left out.
pub fn floor_fractiles(d: &StudyData) -> Vec<FloorFractiles> {
    let plan = d.records_plan();
    if plan.floor.is_none() {
        return Vec::new();
    }
    let n_blocks = plan.blocks.len();
    plan.blocks
        .iter()
        .enumerate()
        .filter_map(|(bi, b)| {
            let alpha = b.alpha_rad?;
            let caps = d.caps.iter().skip(bi).step_by(n_blocks);
            let (mut pfa, mut pga): (Vec<f64>, Vec<f64>) = caps
                .map(|c| {
                    let on_floor = c.eta_c.map_or(f64::INFINITY, |e| alpha / e);
                    (on_floor, on_floor / c.pfa_over_pga.unwrap_or(1.0))
                })
                .unzip();
            pfa.sort_by(f64::total_cmp);
            pga.sort_by(f64::total_cmp);
            let q = |v: &[f64], i: usize| {
                stats::fractile(v, Q_VALUES[i], plan.fractile).unwrap_or(f64::NAN)
            };
            Some(FloorFractiles {
                block: b.name.clone(),
                p: b.p,
                pfa_g: [0, 1, 2].map(|i| q(&pfa, i)),
                ground_pga_g: [0, 1, 2].map(|i| q(&pga, i)),
            })
        })
        .collect()
}

/// The capacity fractiles against p, on the floor (solid) and in the
/// ground's PGA (dashed); and the ratio of each pair.
pub(super) fn floor_capacities(d: &StudyData) -> Vec<Figure> {
    let mut rows = floor_fractiles(d);
    let Some(building) = &d.records_plan().floor else {
        return Vec::new();
    };
    if rows.is_empty() {
        return Vec::new();
    }
    rows.sort_by(|a, b| a.p.total_cmp(&b.p));
    let finite = |v: f64| v.is_finite().then_some(v);
    let series = |get: &dyn Fn(&FloorFractiles) -> f64| -> Vec<(f64, f64)> {
        rows.iter()
            .filter_map(|r| finite(get(r)).map(|v| (r.p, v)))
            .collect()
    };
    let mut lines = Vec::new();
    for (i, name) in Q_NAMES.iter().enumerate() {
        lines.push(Line {
            name: Some(format!("{name}, PFA on the floor")),
            points: series(&|r| r.pfa_g[i]),
            style: Style::LinePoints,
            hue: Hue::Fractile(i),
        });
        lines.push(Line {
            name: Some(format!("{name}, the ground's PGA")),
            points: series(&|r| r.ground_pga_g[i]),
            style: Style::Dashed,
            hue: Hue::Fractile(i),
        });
    }
    let ratio_lines = Q_NAMES
        .iter()
        .enumerate()
        .map(|(i, name)| Line {
            name: Some(name.to_string()),
            points: series(&|r| r.pfa_g[i] / r.ground_pga_g[i]),
            style: Style::LinePoints,
            hue: Hue::Fractile(i),
        })
        .collect();
    let names: Vec<String> = rows
        .iter()
        .map(|r| format!("{} (p = {:.2} 1/s)", r.block, r.p))
        .collect();
    vec![
        Figure {
            file: "floor_capacity.svg".into(),
            chart: Chart {
                title: "Overturning capacity on the floor and in the ground's PGA".into(),
                x_desc: "p (1/s)".into(),
                y_desc: "acceleration at overturning (g)".into(),
                x_scale: Scale::Log,
                y_scale: Scale::Log,
                x_range: None,
                y_range: None,
                x_ticks: None,
                lines,
            },
            caption: format!(
                "Each block's 16/50/84 % capacity fractiles over the records: solid, the floor's \
                 peak acceleration at overturning (PFA_c = α g/η_c); dashed, the ground's PGA \
                 that gives it (PFA_c over the building's PFA/PGA for that record). The building's \
                 modes T, ζ, Γφ: {building}. Blocks: {}.",
                names.join(", ")
            ),
        },
        Figure {
            file: "floor_ratio.svg".into(),
            chart: Chart {
                title: "Capacity on the floor over the ground's PGA at overturning".into(),
                x_desc: "p (1/s)".into(),
                y_desc: "PFA_c / PGA_c of the same fractile (dimensionless)".into(),
                x_scale: Scale::Log,
                y_scale: Scale::Linear,
                x_range: None,
                y_range: None,
                x_ticks: None,
                lines: ratio_lines,
            },
            caption: "How much the building amplifies the shaking at the capacity: each \
                      fractile of PFA_c over the same fractile of the ground's PGA_c. Above 1, \
                      the ground shaking that overturns the block on the floor is weaker than \
                      the floor's peak at overturning, by this factor."
                .into(),
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{block_study, cap, floor_study};
    use crate::tables::sweep::CapacityRow;

    /// Five records by hand: η_c (the floor's) and PFA/PGA; one survives.
    /// PFA_c = α/η_c, the ground's PGA_c = PFA_c/(PFA/PGA); type-7 medians
    /// are the third of five sorted values (+∞ last).
    #[test]
    fn fractiles_on_the_floor_and_the_ground_by_hand() {
        let mut d = floor_study();
        let alpha = (0.2f64).atan();
        let cases = [
            (Some(0.5), 2.0),
            (Some(0.25), 4.0),
            (None, 1.5),
            (Some(1.0), 1.0),
            (Some(0.4), 2.5),
        ];
        d.caps = cases
            .iter()
            .enumerate()
            .map(|(i, &(eta, ratio))| CapacityRow {
                pfa_over_pga: Some(ratio),
                ..cap(i as i64, eta)
            })
            .collect();
        let rows = floor_fractiles(&d);
        assert_eq!(rows.len(), 1);
        // PFA_c: α/1, α/0.5, α/0.4, α/0.25, ∞ → median α/0.4 = 2.5 α.
        assert!((rows[0].pfa_g[1] - alpha / 0.4).abs() < 1e-15);
        // Ground: α/0.5/2 = α, α/0.25/4 = α, α/1/1 = α, α/0.4/2.5 = α, ∞ → α.
        assert!((rows[0].ground_pga_g[1] - alpha).abs() < 1e-15);
        assert!(rows[0].pfa_g[2].is_infinite());
        assert_eq!(floor_capacities(&d).len(), 2);
        assert!(d.records_plan().blocks[0].slides_first());
        // On the ground: no floor figures.
        assert!(floor_capacities(&block_study()).is_empty());
    }
}
