//! The capacity-fractile figures: horizontal against vertical fractiles
//! (paper Fig. 7) and the median capacity against p (paper Fig. 8).

use super::figure::Figure;
use super::shared::{capacity_points, eta_axis, middle, ramp, Q_NAMES, Q_VALUES};
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::study::StudyData;

/// Fig. 7: horizontal against vertical capacity fractiles.
pub(super) fn horizontal_vs_vertical(d: &StudyData) -> Vec<Figure> {
    if !d.is_grid() {
        return Vec::new();
    }
    let (_, _, e_mid) = middle(d);
    let cf = &d.capacity_fractiles;
    let mut lines = Vec::new();
    for (qi, &q) in Q_VALUES.iter().enumerate() {
        lines.push(Line {
            name: Some(format!("{} vertical", Q_NAMES[qi])),
            points: capacity_points(cf, e_mid, q, |r| Some(r.eta_c)),
            style: Style::Line,
            hue: Hue::Fractile(qi),
        });
        lines.push(Line {
            name: Some(format!("{} horizontal", Q_NAMES[qi])),
            points: capacity_points(cf, e_mid, q, |r| r.eta_c_horizontal),
            style: Style::Points,
            hue: Hue::Fractile(qi),
        });
    }
    vec![Figure {
        file: "fig07_horizontal_vs_vertical.svg".into(),
        chart: Chart {
            title: format!("Capacity fractiles, horizontal against vertical, ε = {e_mid:.2}"),
            x_desc: "p (1/s)".into(),
            y_desc: eta_axis(d, "η_c"),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            x_range: None,
            y_range: None,
            x_ticks: None,
            lines,
        },
        caption: horizontal_caption(d, e_mid),
    }]
}

/// Fig. 7's caption: what the two statistics are, why they differ and by
/// how much in the figure.
fn horizontal_caption(d: &StudyData, e: f64) -> String {
    let def = d.records_plan().fractile;
    let n = d
        .capacity_fractiles
        .iter()
        .find(|r| r.eps == e)
        .map_or(0, |r| r.n_records as usize);
    let ks: Vec<String> = Q_VALUES
        .iter()
        .map(|&q| format!("{:.0}", crate::stats::position(n.max(1), q, def).ceil()))
        .collect();
    // The largest gap of each fractile in the figure, and where.
    let gaps: Vec<String> = Q_VALUES
        .iter()
        .enumerate()
        .filter_map(|(qi, &q)| {
            let v = capacity_points(&d.capacity_fractiles, e, q, |r| Some(r.eta_c));
            let h = capacity_points(&d.capacity_fractiles, e, q, |r| r.eta_c_horizontal);
            v.iter()
                .zip(&h)
                .map(|(a, b)| (a.0, b.1 / a.1 - 1.0))
                .filter(|g| g.1.is_finite())
                .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
                .map(|(p, g)| format!("{} {:+.0} % (p = {p:.2} 1/s)", Q_NAMES[qi], 100.0 * g))
        })
        .collect();
    format!(
        "Capacity fractiles from the records' η_c (vertical statistics, lines) and the \
         lowest intensity at which the same fractile of θmax/α given η reaches overturning \
         (horizontal statistics under the resurrection rule, points) (paper Fig. 7). They \
         are not the same statistic. With {n} records and {} fractiles, the horizontal \
         q-fractile is +∞ as soon as the k-th least fragile record (the k-th smallest η_c) has \
         overturned (k = {} for 16, 50, 84 %), since an interpolation with +∞ is +∞ whatever its weight; so each \
         point is that record's first overturning level, at grid resolution. The vertical \
         fractile interpolates between two records' capacities. They differ where those two \
         records lie far apart; the largest differences here: {}.",
        def.describe(),
        ks.join(", "),
        if gaps.is_empty() {
            "none".to_string()
        } else {
            gaps.join("; ")
        }
    )
}

/// Fig. 8: capacity curves.
pub(super) fn capacity_curves(d: &StudyData) -> Vec<Figure> {
    if !d.is_grid() {
        return Vec::new();
    }
    let (ps, es) = d.ps_and_eps();
    let mut lines: Vec<Line> = es
        .iter()
        .map(|&e| Line {
            name: Some(format!("ε = {e:.2}")),
            points: capacity_points(&d.capacity_fractiles, e, 0.5, |r| Some(r.eta_c)),
            style: Style::LinePoints,
            hue: ramp(&es, e),
        })
        .collect();
    // The paper draws the full-cycle rectangle's Mode 0 wall beside the
    // median (t_d = 1 s, so f = p): the shape its regression is built on.
    if !ps.is_empty() {
        lines.push(Line {
            name: Some("paper Eq. 6: (1 − exp(−p·1 s))²".into()),
            points: crate::fit::p_curve(&ps)
                .into_iter()
                .map(|p| (p, crate::pulse::full_cycle_eq6(p)))
                .collect(),
            style: Style::Dashed,
            hue: Hue::Ink,
        });
    }
    vec![Figure {
        file: "fig08_capacity_curves.svg".into(),
        chart: Chart {
            title: "Median capacity η_c,50 against p".into(),
            x_desc: "p (1/s)".into(),
            y_desc: eta_axis(d, "η_c,50"),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            x_range: None,
            y_range: None,
            x_ticks: None,
            lines,
        },
        caption: "The median capacity against the block's frequency parameter, one curve per ε \
                  (coloured by ε, as in every figure), with the full-cycle rectangular pulse's \
                  Mode 0 wall (Eq. 6, t_d = 1 s), the paper's reference, dashed in black as the \
                  paper draws it (paper Fig. 8). Both axes are logarithmic, so the small η_c \
                  of large blocks (p < 1 1/s, which need strong shaking) is not squashed."
            .into(),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{block_study, fractile, grid_study};
    use crate::tables::reduce::CapacityFractileRow;

    /// p = 1, 2 × ε = 0.5, 0.9; the median and the 16 % fractile tabulated.
    fn study() -> StudyData {
        let mut d = grid_study(&[1.0, 2.0], &[0.5, 0.9]);
        let with_horizontal = |p, e, q, v, h| CapacityFractileRow {
            eta_c_horizontal: h,
            ..fractile(p, e, q, v)
        };
        d.capacity_fractiles = vec![
            with_horizontal(1.0, 0.5, 0.5, 0.25, Some(0.3)),
            with_horizontal(1.0, 0.9, 0.5, 0.5, Some(0.5)),
            with_horizontal(1.0, 0.9, 0.16, 0.125, None),
            with_horizontal(2.0, 0.5, 0.5, 0.375, Some(0.4)),
            with_horizontal(2.0, 0.9, 0.5, 0.75, Some(0.8)),
            with_horizontal(2.0, 0.9, 0.16, 0.25, Some(0.25)),
        ];
        d
    }

    #[test]
    fn fig7_pairs_vertical_and_horizontal_fractiles_at_the_middle_eps() {
        let figs = horizontal_vs_vertical(&study());
        assert_eq!(figs.len(), 1);
        let c = &figs[0].chart;
        assert_eq!(
            c.title,
            "Capacity fractiles, horizontal against vertical, ε = 0.90"
        );
        assert_eq!((c.x_scale, c.y_scale), (Scale::Log, Scale::Log));
        let names: Vec<_> = c.lines.iter().map(|l| l.name.clone().unwrap()).collect();
        assert_eq!(
            names,
            [
                "16 % vertical",
                "16 % horizontal",
                "50 % vertical",
                "50 % horizontal",
                "84 % vertical",
                "84 % horizontal"
            ]
        );
        assert_eq!(c.lines[2].points, [(1.0, 0.5), (2.0, 0.75)]);
        assert_eq!(c.lines[2].style, Style::Line);
        assert_eq!(c.lines[3].points, [(1.0, 0.5), (2.0, 0.8)]);
        assert_eq!(c.lines[3].style, Style::Points);
        // A horizontal fractile that never reached overturning is not a number.
        assert_eq!(c.lines[0].points, [(1.0, 0.125), (2.0, 0.25)]);
        assert!(c.lines[1].points[0].1.is_nan() && c.lines[1].points[1] == (2.0, 0.25));
        assert!(c.lines[4].points.is_empty() && c.lines[5].points.is_empty());
    }

    #[test]
    fn fig8_draws_the_median_per_eps_and_the_full_cycle_mode0_wall() {
        let figs = capacity_curves(&study());
        assert_eq!(figs.len(), 1);
        let c = &figs[0].chart;
        assert_eq!(figs[0].file, "fig08_capacity_curves.svg");
        // Both axes logarithmic: small capacities at small p are not squashed.
        assert_eq!(
            (c.x_scale, c.y_scale, c.y_range),
            (Scale::Log, Scale::Log, None)
        );
        // One colour per ε on the ramp; the paper's wall in black, so it
        // cannot be read as one more ε.
        assert_eq!(c.lines[0].hue, crate::plot::Hue::Ramp(0.0));
        assert_eq!(c.lines[1].hue, crate::plot::Hue::Ramp(1.0));
        assert_eq!(c.lines[2].hue, crate::plot::Hue::Ink);
        assert_eq!(c.lines.len(), 3);
        assert_eq!(c.lines[0].name.as_deref(), Some("ε = 0.50"));
        assert_eq!(c.lines[0].points, [(1.0, 0.25), (2.0, 0.375)]);
        assert_eq!(c.lines[1].points, [(1.0, 0.5), (2.0, 0.75)]);
        // Eq. 6 with t_d = 1 s: (1 − e^{−p})² from the smallest p to the largest.
        let eq6 = &c.lines[2];
        assert_eq!(eq6.style, Style::Dashed);
        let (first, last) = (eq6.points[0], eq6.points[eq6.points.len() - 1]);
        let by_hand = |p: f64| (1.0 - (-p).exp()).powi(2);
        assert_eq!((first.0, last.0), (1.0, 2.0));
        assert!((first.1 - by_hand(1.0)).abs() < 1e-12);
        assert!((last.1 - by_hand(2.0)).abs() < 1e-12);
    }

    #[test]
    fn capacity_figures_need_the_grid() {
        assert!(horizontal_vs_vertical(&block_study()).is_empty());
        assert!(capacity_curves(&block_study()).is_empty());
    }
}
