//! The capacity-convergence study in figures: its table summed over blocks
//! per grid resolution, the share of capacities that move against the
//! finest grid, and their mean change.

use super::figure::Figure;
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::stats;
use crate::study::StudyData;
use crate::tables::convergence::ConvergenceRow;

/// The capacity-convergence table summed over blocks, one entry per grid resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvergenceLevel {
    pub levels: f64,
    /// (record, block) capacities that differ from the finest grid's, and of how many.
    pub changed: f64,
    pub total: f64,
    /// Mean over blocks of the mean |Δη_c|; largest |Δη_c| anywhere.
    pub mean_abs_change: f64,
    pub max_abs_change: f64,
    /// Mean over blocks of η_c,50.
    pub mean_q50: f64,
}

/// Summarises `capacity_convergence` rows per resolution, coarsest first.
pub fn convergence_levels(conv: &[ConvergenceRow]) -> Vec<ConvergenceLevel> {
    stats::distinct(conv.iter().map(|r| r.levels as f64).collect())
        .into_iter()
        .map(|l| {
            let rows: Vec<&ConvergenceRow> = conv.iter().filter(|r| r.levels as f64 == l).collect();
            let n = rows.len().max(1) as f64;
            let sum = |f: fn(&ConvergenceRow) -> f64| rows.iter().map(|r| f(r)).sum::<f64>();
            ConvergenceLevel {
                levels: l,
                changed: sum(|r| r.n_changed as f64),
                total: sum(|r| r.n_records as f64),
                mean_abs_change: sum(|r| r.mean_abs_change) / n,
                max_abs_change: rows.iter().map(|r| r.max_abs_change).fold(0.0, f64::max),
                mean_q50: sum(|r| r.eta_c_q50) / n,
            }
        })
        .collect()
}

/// Share of capacities that move against the finest grid, per resolution.
pub(super) fn convergence_share(d: &StudyData) -> Vec<Figure> {
    let Some(conv) = &d.convergence else {
        return Vec::new();
    };
    let levels = convergence_levels(conv);
    let share: Vec<(f64, f64)> = levels
        .iter()
        .map(|c| (c.levels, c.changed / c.total.max(1.0)))
        .collect();
    let top = share.iter().map(|s| s.1).fold(0.05, f64::max) * 1.2;
    vec![Figure {
        file: "capacity_convergence.svg".into(),
        chart: Chart {
            title: "Capacity against IM-grid resolution".into(),
            x_desc: "levels in the IM grid".into(),
            y_desc: "share of (record, block) capacities that differ from the finest grid's".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, top)),
            x_ticks: Some(levels.iter().map(|c| c.levels).collect()),
            lines: vec![Line {
                name: Some("share changed".into()),
                points: share,
                style: Style::LinePoints,
                hue: Hue::Series(0),
            }],
        },
        caption: "How many records' capacities move (by more than twice the refinement \
                  tolerance) against the finest grid, as the grid is refined; every grid \
                  studied is a labelled tick, the finest (the reference, 0 by definition) last."
            .into(),
    }]
}

/// Mean |Δη_c| against the finest grid, per resolution.
pub(super) fn convergence_mean(d: &StudyData) -> Vec<Figure> {
    let Some(conv) = &d.convergence else {
        return Vec::new();
    };
    let levels = convergence_levels(conv);
    let mean: Vec<(f64, f64)> = levels
        .iter()
        .map(|c| (c.levels, c.mean_abs_change))
        .collect();
    vec![Figure {
        file: "capacity_convergence_mean.svg".into(),
        chart: Chart {
            title: "Mean |Δη_c| against the finest grid".into(),
            x_desc: "levels in the IM grid".into(),
            y_desc: "mean |η_c − η_c(finest)| (dimensionless)".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: None,
            x_ticks: Some(levels.iter().map(|c| c.levels).collect()),
            lines: vec![Line {
                name: Some("mean over records and blocks".into()),
                points: mean,
                style: Style::LinePoints,
                hue: Hue::Series(0),
            }],
        },
        caption: "Mean absolute change of η_c against the finest grid (the last tick, the \
                  reference: 0 by definition)."
            .into(),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{grid_study, level};

    /// Two blocks at 100 and 50 levels (rows out of order).
    fn rows() -> Vec<ConvergenceRow> {
        vec![
            level(100, 0, 10, 0.0, 0.5),
            level(50, 2, 10, 0.125, 0.25),
            level(100, 0, 10, 0.0, 0.5),
            level(50, 4, 10, 0.375, 0.75),
        ]
    }

    #[test]
    fn levels_are_summed_over_blocks_coarsest_first() {
        let got = convergence_levels(&rows());
        assert_eq!(
            got,
            [
                ConvergenceLevel {
                    levels: 50.0,
                    changed: 6.0,
                    total: 20.0,
                    mean_abs_change: 0.25,
                    max_abs_change: 0.375,
                    mean_q50: 0.5,
                },
                ConvergenceLevel {
                    levels: 100.0,
                    changed: 0.0,
                    total: 20.0,
                    mean_abs_change: 0.0,
                    max_abs_change: 0.0,
                    mean_q50: 0.5,
                },
            ]
        );
    }

    #[test]
    fn the_share_and_the_mean_change_per_resolution() {
        let mut d = grid_study(&[1.0, 2.0], &[0.5]);
        d.convergence = Some(rows());
        let share = convergence_share(&d);
        assert_eq!(share.len(), 1);
        let c = &share[0].chart;
        assert_eq!(
            (share[0].file.as_str(), c.x_scale),
            ("capacity_convergence.svg", Scale::Log)
        );
        // 6 of 20 at 50 levels, none at 100; the axis 20 % above the largest share.
        assert_eq!(c.lines[0].points, [(50.0, 0.3), (100.0, 0.0)]);
        assert_eq!(c.y_range, Some((0.0, 0.3 * 1.2)));
        let mean = convergence_mean(&d);
        assert_eq!(mean[0].file, "capacity_convergence_mean.svg");
        assert_eq!(mean[0].chart.lines[0].points, [(50.0, 0.25), (100.0, 0.0)]);
    }

    #[test]
    fn nothing_without_the_study() {
        let d = grid_study(&[1.0], &[0.5]);
        assert!(convergence_share(&d).is_empty() && convergence_mean(&d).is_empty());
    }
}
