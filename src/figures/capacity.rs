//! The capacity-fractile figures: horizontal against vertical fractiles
//! (paper Fig. 7) and the median capacity against p (paper Fig. 8).

use super::figure::Figure;
use super::shared::{capacity_points, middle, Q_NAMES, Q_VALUES};
use crate::plot::{Chart, Line, Scale, Style};
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
            color: qi,
        });
        lines.push(Line {
            name: Some(format!("{} horizontal", Q_NAMES[qi])),
            points: capacity_points(cf, e_mid, q, |r| r.eta_c_horizontal),
            style: Style::Points,
            color: qi,
        });
    }
    vec![Figure {
        file: "fig07_horizontal_vs_vertical.svg".into(),
        chart: Chart {
            title: format!("Capacity fractiles, horizontal against vertical, ε = {e_mid:.2}"),
            x_desc: "p (1/s)".into(),
            y_desc: "η_c".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            x_range: None,
            y_range: None,
            lines,
        },
        caption: "Capacity fractiles from the records' η_c (vertical statistics, lines) and from \
                  the horizontal EDP fractiles reaching overturning (points, at grid resolution) \
                  (paper Fig. 7): they coincide up to the grid step."
            .into(),
    }]
}

/// Fig. 8: capacity curves.
pub(super) fn capacity_curves(d: &StudyData) -> Vec<Figure> {
    if !d.is_grid() {
        return Vec::new();
    }
    let (ps, es) = d.ps_and_eps();
    let mut lines: Vec<Line> = es
        .iter()
        .enumerate()
        .map(|(k, &e)| Line {
            name: Some(format!("ε = {e:.2}")),
            points: capacity_points(&d.capacity_fractiles, e, 0.5, |r| Some(r.eta_c)),
            style: Style::LinePoints,
            color: k,
        })
        .collect();
    // The paper draws the full-cycle rectangle's Mode 0 wall beside the
    // median (t_d = 1 s, so f = p): the shape its regression is built on.
    if !ps.is_empty() {
        lines.push(Line {
            name: Some("Eq. 6: (1 − exp(−p·1 s))²".into()),
            points: crate::fit::p_curve(&ps)
                .into_iter()
                .map(|p| (p, crate::pulse::full_cycle_eq6(p)))
                .collect(),
            style: Style::Dashed,
            color: 9,
        });
    }
    vec![Figure {
        file: "fig08_capacity_curves.svg".into(),
        chart: Chart {
            title: "Median capacity η_c,50 against p".into(),
            x_desc: "p (1/s)".into(),
            y_desc: "η_c,50".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, 1.0)),
            lines,
        },
        caption: "The median capacity against the block's frequency parameter, one curve per ε, \
                  with the full-cycle rectangular pulse's Mode 0 wall (Eq. 6, t_d = 1 s) dashed \
                  as the paper draws it (paper Fig. 8)."
            .into(),
    }]
}
