//! Where a chart's legend goes: the corner of the plot that covers the
//! fewest data points, or a panel beside the plot when every corner holds
//! some; and the drawing of that panel.

use plotters::prelude::*;

use super::axes::{axis_range, Scale, PALETTE};
use super::chart::{Chart, Line, Runs, Style};

/// Width (px) of the panel beside the plot that holds a legend no corner
/// of the plot can take without covering data.
pub(super) const LEGEND_PANEL: u32 = 300;

/// The corner of the plot where the legend covers the fewest data points
/// (upper right, upper left, lower right, lower left on ties), judged in
/// axis fractions: the legend spans about 40 % of the width and 5 % of the
/// height per entry; and how many points it covers there.
pub(super) fn legend_placement(chart: &Chart, lines: &Runs) -> (SeriesLabelPosition, usize) {
    let pts: Vec<(f64, f64)> = lines
        .iter()
        .flat_map(|(_, r)| r.iter().flatten())
        .copied()
        .collect();
    let fold = |f: fn(&(f64, f64)) -> f64| {
        pts.iter()
            .map(f)
            .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)))
    };
    let ((x0, x1), (y0, y1)) = (fold(|p| p.0), fold(|p| p.1));
    let (xa, xb) = axis_range(chart.x_scale, chart.x_range, x0, x1);
    let (ya, yb) = axis_range(chart.y_scale, chart.y_range, y0, y1);
    let frac = |scale: Scale, v: f64, a: f64, b: f64| match scale {
        Scale::Linear => (v - a) / (b - a),
        Scale::Log => (v / a).ln() / (b / a).ln(),
    };
    let entries = lines.iter().filter(|(l, _)| l.name.is_some()).count() as f64;
    let (w, h) = (0.4, (0.05 * entries + 0.04).min(0.9));
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let covered = |right: bool, upper: bool| {
        pts.iter()
            .filter(|&&(x, y)| {
                let (fx, fy) = (
                    frac(chart.x_scale, x, xa, xb),
                    frac(chart.y_scale, y, ya, yb),
                );
                (if right { fx > 1.0 - w } else { fx < w })
                    && (if upper { fy > 1.0 - h } else { fy < h })
            })
            .count()
    };
    corners
        .into_iter()
        .map(|(corner, right, upper)| (corner, covered(right, upper)))
        .min_by_key(|c| c.1)
        .expect("four corners")
}

/// The legend in the panel right of the plot, from (`x`, `y`): the same
/// entries, order and symbols as a legend in a corner (bands first).
pub(super) fn legend_panel(
    root: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    lines: &Runs,
    x: i32,
    y: i32,
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    let named = |band: bool| {
        lines
            .iter()
            .filter(move |(l, r)| {
                l.name.is_some() && !r.is_empty() && (l.style == Style::Band) == band
            })
            .map(|(l, _)| *l)
    };
    let entries: Vec<&Line> = named(true).chain(named(false)).collect();
    let step = 17;
    let height = 12 + step * entries.len() as i32;
    let right = x + LEGEND_PANEL as i32 - 24;
    root.draw(&Rectangle::new(
        [(x, y), (right, y + height)],
        WHITE.filled(),
    ))?;
    root.draw(&Rectangle::new([(x, y), (right, y + height)], BLACK))?;
    for (i, l) in entries.iter().enumerate() {
        let (sx, sy) = (x + 10, y + 14 + step * i as i32);
        let color = PALETTE[l.color % PALETTE.len()];
        match l.style {
            Style::Band => root.draw(&Rectangle::new(
                [(sx, sy - 5), (sx + 20, sy + 5)],
                color.mix(0.18).filled(),
            ))?,
            Style::Dashed => {
                for dx in [0, 12] {
                    root.draw(&PathElement::new(
                        vec![(sx + dx, sy), (sx + dx + 8, sy)],
                        color.stroke_width(2),
                    ))?;
                }
            }
            Style::Points => root.draw(&Circle::new((sx + 10, sy), 3, color.filled()))?,
            Style::Faint => root.draw(&PathElement::new(
                vec![(sx, sy), (sx + 20, sy)],
                RGBColor(190, 190, 190).stroke_width(1),
            ))?,
            Style::Line | Style::LinePoints => root.draw(&PathElement::new(
                vec![(sx, sy), (sx + 20, sy)],
                color.stroke_width(2),
            ))?,
        }
        root.draw(&Text::new(
            l.name.clone().unwrap_or_default(),
            (sx + 30, sy - 7),
            ("sans-serif", 14).into_font(),
        ))?;
    }
    Ok(())
}
