//! The pulse map's figures: the pulse waveforms (paper Fig. 2), the safety
//! walls against f (paper Fig. 3) and the overturning modes on the map
//! (paper Fig. 4).

use super::figure::Figure;
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::study::PulseData;

/// Fig. 2: ψ̈ against t/t_d for each of the map's pulse shapes.
pub(super) fn pulse_waveforms(d: &PulseData) -> Vec<Figure> {
    let Some(pp) = d.plan.pulse_map() else {
        return Vec::new();
    };
    let lobes = pp.cycle.lobes();
    let lines = pp
        .shapes
        .iter()
        .enumerate()
        .map(|(k, shape)| {
            let mut pts = vec![(0.0, 0.0)];
            for (l, sign) in [1.0, -1.0].into_iter().take(lobes).enumerate() {
                for i in 0..=400 {
                    let u = i as f64 / 400.0;
                    pts.push((l as f64 + u, sign * shape.lobe(u)));
                }
            }
            pts.push((lobes as f64, 0.0));
            Line {
                name: Some(match shape.beta() {
                    Some(b) => format!("β = {b}"),
                    None => "rectangle".into(),
                }),
                points: pts,
                style: Style::Line,
                hue: Hue::Series(k),
            }
        })
        .collect();
    vec![Figure {
        file: "fig02_pulse_waveforms.svg".into(),
        chart: Chart {
            title: format!("Pulse waveforms ({} cycle)", pp.cycle.name()),
            x_desc: "t / t_d".into(),
            y_desc: "ψ̈ = ü_g / A_p".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.0, lobes as f64)),
            y_range: Some(if lobes == 1 { (0.0, 1.1) } else { (-1.1, 1.1) }),
            x_ticks: None,
            lines,
        },
        caption: format!(
            "The pulse shapes of this map: the paper's exponential pulse (Eq. 4) for each β \
             (β → −∞ the rectangle, β = 0 the triangle, β → +∞ a spike), {} (paper Fig. 2).",
            match lobes {
                1 => "one lobe of duration t_d (a half cycle)",
                _ => "a lobe of duration t_d followed by its negative (a full cycle)",
            }
        ),
    }]
}

/// The walls of one family along f: (f, η_w) and (f, closed form).
fn family_walls(
    d: &PulseData,
    beta: Option<f64>,
    eps: f64,
    pick: impl Fn(&crate::tables::pulse::PulseWallRow) -> Option<f64>,
) -> Vec<(f64, f64)> {
    d.walls_of(beta, eps)
        .filter_map(|w| pick(w).map(|e| (w.f, e)))
        .collect()
}

/// Fig. 3: each family's wall η_w against f, with the paper's closed form.
pub(super) fn pulse_walls(d: &PulseData) -> Vec<Figure> {
    let mut lines = Vec::new();
    for (k, (beta, eps, label)) in d.families().into_iter().enumerate() {
        lines.push(Line {
            name: Some(format!("{label}: η_w by simulation")),
            points: family_walls(d, beta, eps, |w| w.eta_w),
            style: Style::Line,
            hue: Hue::Series(k),
        });
        let closed = family_walls(d, beta, eps, |w| {
            w.closed_form
                .filter(|_| w.closed_form_kind() == Some(crate::pulse::WallKind::Any))
        });
        if !closed.is_empty() {
            let eq = d
                .walls
                .iter()
                .find_map(|w| w.closed_form_equation.clone())
                .unwrap_or_default();
            lines.push(Line {
                name: Some(format!("{label}: {eq}")),
                points: closed,
                style: Style::Dashed,
                hue: Hue::Series(k),
            });
        }
    }
    if lines.iter().all(|l| l.points.is_empty()) {
        return Vec::new();
    }
    let criterion = d
        .walls
        .first()
        .map_or(String::new(), |w| w.overturn.clone());
    vec![Figure {
        file: "fig03_pulse_walls.svg".into(),
        chart: Chart {
            title: format!("Safety walls (criterion {criterion})"),
            x_desc: "f = p t_d".into(),
            y_desc: "η = α g / A_p".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, 1.0)),
            x_ticks: None,
            lines,
        },
        caption: "The largest η at which the block overturns (its safety wall η_w) against f, one \
                  curve per family: the block is safe above its curve and overturns just below it; \
                  the paper's closed form dashed where one applies (Eq. 3 the rectangle, Eq. 5 the \
                  exponential half cycle; paper Fig. 3)."
            .into(),
    }]
}

/// Fig. 4: per family, the map's points by outcome (safe, Mode 0, Mode 1,
/// Mode 2 or more), with the Mode 0 wall and Eq. 6 where it applies.
pub(super) fn pulse_modes(d: &PulseData) -> Vec<Figure> {
    let mut figs = Vec::new();
    for (beta, eps, label) in d.families() {
        let cells: Vec<_> = d.cells_of(beta, eps).collect();
        if cells.is_empty() {
            continue;
        }
        let class = |name: &str, hue: Hue, keep: &dyn Fn(bool, i64) -> bool| Line {
            name: Some(name.into()),
            points: cells
                .iter()
                .filter(|c| keep(c.overturned, c.impacts))
                .map(|c| (c.f, c.eta))
                .collect(),
            style: Style::Points,
            hue,
        };
        let mut lines = vec![
            class("Mode 0 (no impact)", Hue::Series(1), &|o, i| o && i == 0),
            class("Mode 1 (one impact)", Hue::Series(2), &|o, i| o && i == 1),
            class("Mode 2 or more", Hue::Series(4), &|o, i| o && i >= 2),
        ];
        lines.retain(|l| !l.points.is_empty());
        lines.push(Line {
            name: Some("η_w,0 by simulation".into()),
            points: family_walls(d, beta, eps, |w| w.eta_w_mode0),
            style: Style::Line,
            hue: Hue::Series(0),
        });
        let eq6 = family_walls(d, beta, eps, |w| {
            w.closed_form
                .filter(|_| w.closed_form_of.as_deref() == Some("eta_w_mode0"))
        });
        if !eq6.is_empty() {
            lines.push(Line {
                name: Some("Eq. 6: (1 − exp(−f))²".into()),
                points: eq6,
                style: Style::Dashed,
                hue: Hue::Series(0),
            });
        }
        let slug = match beta {
            Some(b) if d.families().len() > d.plan.pulse_map().map_or(1, |p| p.shapes.len()) => {
                format!("beta{b}_eps{eps:.2}")
            }
            Some(b) => format!("beta{b}"),
            None => format!("eps{eps:.2}"),
        };
        let eta_min = cells.iter().map(|c| c.eta).fold(f64::INFINITY, f64::min);
        let caption = modes_caption(&label, &lines);
        figs.push(Figure {
            file: format!("fig04_modes_{slug}.svg"),
            chart: Chart {
                title: format!("Overturning modes, {label}"),
                x_desc: "f = p t_d".into(),
                y_desc: "η = α g / A_p".into(),
                x_scale: Scale::Log,
                y_scale: Scale::Log,
                x_range: None,
                y_range: Some((eta_min * 0.9, 1.0)),
                x_ticks: None,
                lines,
            },
            caption,
        });
    }
    figs
}

/// Fig. 4's caption: what each mode drawn means (only those on the map),
/// and Eq. 6 where it is drawn.
fn modes_caption(label: &str, lines: &[Line]) -> String {
    let drawn = |prefix: &str| {
        lines
            .iter()
            .any(|l| l.name.as_deref().is_some_and(|n| n.starts_with(prefix)))
    };
    let mut modes = Vec::new();
    if drawn("Mode 0") {
        modes.push("Mode 0: forward, no impact");
    }
    if drawn("Mode 1") {
        modes.push("Mode 1: after one impact and reversal");
    }
    if drawn("Mode 2") {
        modes.push("Mode 2 or more: after two impacts or more");
    }
    let eq6 = match drawn("Eq. 6") {
        true => ", Eq. 6 dashed",
        false => "",
    };
    format!(
        "Each point of the map where the block overturns, by the impacts before it does ({}), \
         for {label}; unmarked points are safe. The line is the Mode 0 wall found by \
         simulation{eq6} (paper Fig. 4).",
        modes.join("; ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{cell, grid_study, pulse_study, wall};

    #[test]
    fn waveforms_one_lobe_per_half_cycle_peaking_at_one() {
        let half = pulse_study("shape = \"exp\"\nbeta = [1.0, 5.0]\ncycle = \"half\"\neps = [0.7]");
        let figs = pulse_waveforms(&half);
        assert_eq!(figs.len(), 1);
        let c = &figs[0].chart;
        assert_eq!(c.title, "Pulse waveforms (half cycle)");
        let names: Vec<_> = c.lines.iter().map(|l| l.name.clone().unwrap()).collect();
        assert_eq!(names, ["β = 1", "β = 5"]);
        // From rest, 401 samples of the lobe, back to rest.
        let pts = &c.lines[0].points;
        assert_eq!(pts.len(), 403);
        assert_eq!((pts[0], pts[402]), ((0.0, 0.0), (1.0, 0.0)));
        assert_eq!(pts[201], (0.5, 1.0));
        assert_eq!((c.x_range, c.y_range), (Some((0.0, 1.0)), Some((0.0, 1.1))));

        let full = pulse_study("shape = \"rect\"\ncycle = \"full\"\neps = [0.7]");
        let c = &pulse_waveforms(&full)[0].chart;
        assert_eq!(c.lines[0].name.as_deref(), Some("rectangle"));
        let pts = &c.lines[0].points;
        assert_eq!(pts.len(), 1 + 2 * 401 + 1);
        // The second lobe is the first's negative.
        assert_eq!(
            (pts[1], pts[401], pts[402]),
            ((0.0, 1.0), (1.0, 1.0), (1.0, -1.0))
        );
        assert_eq!(pts[803], (2.0, 0.0));
        assert_eq!(
            (c.x_range, c.y_range),
            (Some((0.0, 2.0)), Some((-1.1, 1.1)))
        );
    }

    #[test]
    fn no_waveforms_without_pulses() {
        let mut d = pulse_study("shape = \"rect\"\neps = [0.7]");
        d.plan = grid_study(&[1.0], &[0.5]).plan;
        assert!(pulse_waveforms(&d).is_empty());
    }

    #[test]
    fn walls_with_the_closed_form_of_the_wall_itself() {
        let mut d = pulse_study("shape = \"exp\"\nbeta = [1.0, 5.0]\neps = [0.7]");
        assert!(pulse_walls(&d).is_empty(), "no walls, no figure");
        d.walls = vec![
            wall(
                Some(1.0),
                0.7,
                0.5,
                Some(0.3),
                Some((0.31, "Eq. 5", "eta_w")),
            ),
            wall(
                Some(1.0),
                0.7,
                1.0,
                Some(0.4),
                Some((0.41, "Eq. 5", "eta_w")),
            ),
            // A closed form of the Mode 0 wall is not drawn here.
            wall(
                Some(5.0),
                0.7,
                0.5,
                Some(0.2),
                Some((0.21, "Eq. 6", "eta_w_mode0")),
            ),
        ];
        let figs = pulse_walls(&d);
        assert_eq!(figs.len(), 1);
        let c = &figs[0].chart;
        assert_eq!(c.title, "Safety walls (criterion escape)");
        assert_eq!((c.x_scale, c.y_range), (Scale::Log, Some((0.0, 1.0))));
        let names: Vec<_> = c.lines.iter().map(|l| l.name.clone().unwrap()).collect();
        assert_eq!(
            names,
            [
                "β = 1: η_w by simulation",
                "β = 1: Eq. 5",
                "β = 5: η_w by simulation"
            ]
        );
        assert_eq!(c.lines[0].points, [(0.5, 0.3), (1.0, 0.4)]);
        assert_eq!(c.lines[1].points, [(0.5, 0.31), (1.0, 0.41)]);
        assert_eq!(c.lines[1].style, Style::Dashed);
        assert_eq!(c.lines[2].points, [(0.5, 0.2)]);
    }

    #[test]
    fn modes_sort_the_overturning_points_by_their_impacts() {
        let mut d = pulse_study("shape = \"exp\"\nbeta = [1.0]\neps = [0.7]");
        let b = Some(1.0);
        d.walls = vec![wall(
            b,
            0.7,
            0.5,
            Some(0.6),
            Some((0.5, "Eq. 6", "eta_w_mode0")),
        )];
        d.cells = vec![
            cell(b, 0.7, 0.5, 0.5, true, 0),
            cell(b, 0.7, 1.0, 0.5, true, 1),
            cell(b, 0.7, 2.0, 0.1, true, 3),
            cell(b, 0.7, 2.0, 1.0, false, 0),
        ];
        let figs = pulse_modes(&d);
        assert_eq!(figs.len(), 1);
        assert_eq!(figs[0].file, "fig04_modes_beta1.svg");
        let c = &figs[0].chart;
        assert_eq!(c.title, "Overturning modes, β = 1");
        let names: Vec<_> = c.lines.iter().map(|l| l.name.clone().unwrap()).collect();
        assert_eq!(
            names,
            [
                "Mode 0 (no impact)",
                "Mode 1 (one impact)",
                "Mode 2 or more",
                "η_w,0 by simulation",
                "Eq. 6: (1 − exp(−f))²"
            ]
        );
        // The safe point is in no class.
        assert_eq!(c.lines[0].points, [(0.5, 0.5)]);
        assert_eq!(c.lines[1].points, [(1.0, 0.5)]);
        assert_eq!(c.lines[2].points, [(2.0, 0.1)]);
        assert_eq!(c.lines[3].points, [(0.5, 0.6)]);
        assert_eq!(c.lines[4].points, [(0.5, 0.5)]);
        // The η axis from 10 % below the lowest point of the map to 1.
        assert_eq!((c.x_scale, c.y_scale), (Scale::Log, Scale::Log));
        assert_eq!(c.y_range, Some((0.1 * 0.9, 1.0)));
        assert!(
            figs[0].caption.contains("Mode 1: after one impact")
                && figs[0].caption.contains("Eq. 6 dashed")
        );
        // A map of Mode 0 alone, no Eq. 6 (an exponential half cycle): the
        // caption speaks of what is drawn, not of Mode 1 and Eq. 6.
        d.walls = vec![wall(b, 0.7, 0.5, Some(0.6), None)];
        d.cells = vec![cell(b, 0.7, 0.5, 0.5, true, 0)];
        let caption = &pulse_modes(&d)[0].caption;
        assert!(
            caption.contains("(Mode 0: forward, no impact)"),
            "{caption}"
        );
        assert!(
            !caption.contains("Mode 1") && !caption.contains("Eq. 6"),
            "{caption}"
        );
        // The waveforms of a half cycle say so.
        let w = &pulse_waveforms(&d)[0].caption;
        assert!(w.contains("one lobe of duration t_d (a half cycle)"), "{w}");
    }

    #[test]
    fn a_family_without_points_has_no_modes_figure() {
        let mut d = pulse_study("shape = \"exp\"\nbeta = [1.0]\neps = [0.7]");
        d.walls = vec![wall(Some(1.0), 0.7, 0.5, Some(0.6), None)];
        assert!(pulse_modes(&d).is_empty());
    }
}
