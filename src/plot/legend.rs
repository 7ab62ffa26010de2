//! The legend: a panel right of the plot, on every chart that names a
//! series, so it never covers data and every figure keeps one canvas.

use plotters::prelude::*;

use super::axes::FONT_LEGEND;
use super::chart::{Line, Runs, Style};

/// Width (px) of the panel right of the plot that holds the legend.
pub(super) const LEGEND_PANEL: u32 = 330;

/// Whether a chart has a legend: two named series or more with something
/// drawn (one series is named by the axis it is drawn against).
pub(super) fn has_legend(lines: &Runs) -> bool {
    lines
        .iter()
        .filter(|(l, r)| l.name.is_some() && !r.is_empty())
        .count()
        >= 2
}

/// The legend in the panel right of the plot, from (`x`, `y`): named
/// series in their order, bands first, each with its symbol.
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
    let step = FONT_LEGEND as i32 + 6;
    let height = 12 + step * entries.len() as i32;
    let right = x + LEGEND_PANEL as i32 - 18;
    root.draw(&Rectangle::new(
        [(x, y), (right, y + height)],
        WHITE.filled(),
    ))?;
    root.draw(&Rectangle::new([(x, y), (right, y + height)], BLACK))?;
    for (i, l) in entries.iter().enumerate() {
        let (sx, sy) = (x + 10, y + 6 + step / 2 + step * i as i32);
        let color = l.hue.rgb();
        match l.style {
            Style::Band => root.draw(&Rectangle::new(
                [(sx, sy - 5), (sx + 24, sy + 5)],
                color.mix(0.18).filled(),
            ))?,
            Style::Dashed => {
                for dx in [0, 14] {
                    root.draw(&PathElement::new(
                        vec![(sx + dx, sy), (sx + dx + 9, sy)],
                        color.stroke_width(2),
                    ))?;
                }
            }
            Style::Points => root.draw(&Circle::new((sx + 12, sy), 3, color.filled()))?,
            Style::Faint => root.draw(&PathElement::new(
                vec![(sx, sy), (sx + 24, sy)],
                RGBColor(190, 190, 190).stroke_width(1),
            ))?,
            Style::Line => root.draw(&PathElement::new(
                vec![(sx, sy), (sx + 24, sy)],
                color.stroke_width(2),
            ))?,
            Style::LinePoints => {
                root.draw(&PathElement::new(
                    vec![(sx, sy), (sx + 24, sy)],
                    color.stroke_width(2),
                ))?;
                root.draw(&Circle::new((sx + 12, sy), 3, color.filled()))?
            }
        }
        root.draw(&Text::new(
            l.name.clone().unwrap_or_default(),
            (sx + 34, sy - FONT_LEGEND as i32 / 2),
            ("sans-serif", FONT_LEGEND).into_font(),
        ))?;
    }
    Ok(())
}
