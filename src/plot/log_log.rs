//! The log–log chart of named series (markers joined by a line), as the
//! benchmark's speed-against-error plot draws it.

use plotters::prelude::*;

use super::axes::{Hue, CANVAS, FONT_LEGEND, FONT_TICK};
use super::error::{draw_err, PlotError};

/// One named series of (x, y) points, drawn as markers joined by a line.
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// A log–log chart of several series. Non-positive or non-finite values are
/// clamped to `floor` (errors that are exactly zero still show, at the
/// bottom). Returns the SVG document.
pub fn log_log(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
    floor: f64,
) -> Result<String, PlotError> {
    let err = draw_err(title);
    let clean = |v: f64| if v.is_finite() && v > floor { v } else { floor };
    let all: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter().map(|&(x, y)| (clean(x), clean(y))))
        .collect();
    if all.is_empty() {
        return Err(PlotError::Empty {
            title: title.to_string(),
        });
    }
    let (xmin, xmax) = all
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (ymin, ymax) = all
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let (x0, x1) = (xmin / 2.0, xmax * 2.0);
    let (y0, y1) = (ymin / 10.0, ymax * 10.0);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, CANVAS).into_drawing_area();
        root.fill(&WHITE).map_err(&err)?;
        let body = super::render::titled(&root, title).map_err(&err)?;
        let mut chart = ChartBuilder::on(&body)
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(&err)?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", FONT_TICK))
            .draw()
            .map_err(&err)?;
        for (i, s) in series.iter().enumerate() {
            let color = Hue::Series(i).rgb();
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .map(|&(x, y)| (clean(x), clean(y)))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                .map_err(&err)?
                .label(s.name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
                .map_err(&err)?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .border_style(BLACK)
            .background_style(WHITE.mix(0.9))
            .label_font(("sans-serif", FONT_LEGEND))
            .draw()
            .map_err(&err)?;
        root.present().map_err(&err)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_an_svg_with_every_series_named() {
        let s = [
            Series {
                name: "alpha".into(),
                points: vec![(1e-6, 1e-3), (1e-5, 1e-6)],
            },
            Series {
                name: "beta".into(),
                points: vec![(2e-6, 0.0), (3e-5, 1e-9)],
            },
        ];
        let svg = log_log("t", "time (s)", "error", &s, 1e-16).unwrap();
        assert!(svg.starts_with("<svg"));
        assert!(svg.contains("alpha") && svg.contains("beta") && svg.contains("time (s)"));
    }
}
