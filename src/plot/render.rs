//! Draws a [`Chart`] as SVG: the canvas, the axes of its scales, every
//! series in its style (bands first, under every line) and the legend.

use plotters::prelude::*;

use super::axes::{axis_range, tick_label, Scale, PALETTE};
use super::chart::{runs, Chart, Line, Run, Runs, Style};
use super::error::{draw_err, PlotError};
use super::legend::{legend_panel, legend_placement, LEGEND_PANEL};

pub fn render(chart: &Chart) -> Result<String, PlotError> {
    let err = draw_err(&chart.title);
    let lines = runs(chart);
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in lines.iter().flat_map(|(_, r)| r.iter().flatten()) {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if x0 > x1 {
        return Err(PlotError::Empty {
            title: chart.title.clone(),
        });
    }
    let (xa, xb) = axis_range(chart.x_scale, chart.x_range, x0, x1);
    let (ya, yb) = axis_range(chart.y_scale, chart.y_range, y0, y1);
    // The legend goes in a corner it leaves free of data, or, when every
    // corner holds some, beside the plot on a wider canvas.
    let legend = lines
        .iter()
        .any(|(l, r)| l.name.is_some() && !r.is_empty())
        .then(|| legend_placement(chart, &lines));
    let beside = legend.as_ref().is_some_and(|(_, covered)| *covered > 0);
    let width = if beside { 900 + LEGEND_PANEL } else { 900 };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, 620)).into_drawing_area();
        root.fill(&WHITE).map_err(&err)?;
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(&chart.title, ("sans-serif", 20))
            .margin(18)
            .margin_right(if beside { 18 + LEGEND_PANEL } else { 18 })
            .x_label_area_size(55)
            .y_label_area_size(75);
        let legend = legend.map(|(corner, _)| if beside { None } else { Some(corner) });
        // plotters types log and linear axes differently: one body, four instantiations.
        match (chart.x_scale, chart.y_scale) {
            (Scale::Linear, Scale::Linear) => {
                draw(&mut builder, xa..xb, ya..yb, chart, &lines, legend)?
            }
            (Scale::Log, Scale::Linear) => draw(
                &mut builder,
                (xa..xb).log_scale(),
                ya..yb,
                chart,
                &lines,
                legend,
            )?,
            (Scale::Linear, Scale::Log) => draw(
                &mut builder,
                xa..xb,
                (ya..yb).log_scale(),
                chart,
                &lines,
                legend,
            )?,
            (Scale::Log, Scale::Log) => draw(
                &mut builder,
                (xa..xb).log_scale(),
                (ya..yb).log_scale(),
                chart,
                &lines,
                legend,
            )?,
        }
        if beside {
            legend_panel(&root, &lines, 900, 50).map_err(&err)?;
        }
        root.present().map_err(&err)?;
    }
    Ok(svg)
}

fn draw<'b, X, Y>(
    builder: &mut ChartBuilder<'_, 'b, SVGBackend<'b>>,
    x: X,
    y: Y,
    chart: &Chart,
    lines: &Runs,
    // None: no legend; Some(None): beside the plot; Some(Some(c)): in corner c.
    legend: Option<Option<SeriesLabelPosition>>,
) -> Result<(), PlotError>
where
    X: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    Y: plotters::coord::ranged1d::AsRangedCoord<Value = f64>,
    X::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
    Y::CoordDescType: plotters::coord::ranged1d::ValueFormatter<f64>,
{
    let err = draw_err(&chart.title);
    let mut c = builder.build_cartesian_2d(x, y).map_err(&err)?;
    c.configure_mesh()
        .x_desc(chart.x_desc.as_str())
        .y_desc(chart.y_desc.as_str())
        .x_label_formatter(&|v| tick_label(*v))
        .y_label_formatter(&|v| tick_label(*v))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(&err)?;
    let mut any_legend = false;
    // Bands first, under every line.
    let by_layer = lines
        .iter()
        .filter(|(l, _)| l.style == Style::Band)
        .chain(lines.iter().filter(|(l, _)| l.style != Style::Band));
    for (l, runs) in by_layer {
        for (k, run) in runs.iter().enumerate() {
            any_legend |= draw_run(&mut c, l, run, k == 0 && l.name.is_some(), &chart.title)?;
        }
    }
    if let (true, Some(Some(place))) = (any_legend, legend) {
        c.configure_series_labels()
            .position(place)
            .border_style(BLACK)
            .background_style(WHITE.mix(0.85))
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(&err)?;
    }
    Ok(())
}

/// Draws one unbroken run of line `l` in its style; with `legend` (the
/// line's first run, when it is named), labels it for the legend. Whether
/// it added a legend entry.
fn draw_run<X, Y>(
    c: &mut ChartContext<'_, SVGBackend<'_>, Cartesian2d<X, Y>>,
    l: &Line,
    run: &Run,
    legend: bool,
    title: &str,
) -> Result<bool, PlotError>
where
    X: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
{
    let err = draw_err(title);
    let color = PALETTE[l.color % PALETTE.len()];
    let faint = RGBColor(190, 190, 190);
    let mut any_legend = false;
    if l.style == Style::Band {
        let fill = color.mix(0.18);
        let s = c
            .draw_series(std::iter::once(Polygon::new(run.clone(), fill.filled())))
            .map_err(&err)?;
        if legend {
            any_legend = true;
            s.label(l.name.clone().unwrap_or_default())
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], fill.filled()));
        }
        return Ok(any_legend);
    }
    if l.style == Style::Dashed {
        let s = c
            .draw_series(DashedLineSeries::new(
                run.iter().copied(),
                8,
                5,
                color.stroke_width(2),
            ))
            .map_err(&err)?;
        if legend {
            any_legend = true;
            s.label(l.name.clone().unwrap_or_default())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 8, y)], color.stroke_width(2))
                });
        }
        return Ok(any_legend);
    }
    if matches!(l.style, Style::Line | Style::LinePoints | Style::Faint) {
        let (col, width) = if l.style == Style::Faint {
            (faint, 1)
        } else {
            (color, 2)
        };
        let s = c
            .draw_series(LineSeries::new(
                run.iter().copied(),
                col.stroke_width(width),
            ))
            .map_err(&err)?;
        if legend {
            any_legend = true;
            s.label(l.name.clone().unwrap_or_default())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(width))
                });
        }
    }
    if matches!(l.style, Style::Points | Style::LinePoints) {
        let s = c
            .draw_series(run.iter().map(|&p| Circle::new(p, 3, color.filled())))
            .map_err(&err)?;
        if legend && l.style == Style::Points {
            any_legend = true;
            s.label(l.name.clone().unwrap_or_default())
                .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
        }
    }
    Ok(any_legend)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The x of the `<text>` element holding `name`.
    fn text_x(svg: &str, name: &str) -> f64 {
        let at = svg.find(&format!("\n{name}\n</text>")).expect("the entry");
        let open = svg[..at].rfind("<text x=\"").expect("its element") + 9;
        svg[open..].split('"').next().unwrap().parse().unwrap()
    }

    /// Legends never cover data. Points on the rising diagonal leave the
    /// upper-left corner free: the legend goes there, on the 900-px canvas.
    /// A band over the whole plot (its outline has vertices along every
    /// edge) leaves no corner free: the legend goes to a panel beside the
    /// plot, on a wider canvas, every entry right of the plot's right edge
    /// (900 − 18 px of margin).
    #[test]
    fn legend_takes_a_free_corner_or_goes_beside_the_plot() {
        let line = |name: &str, style, points| Line {
            name: Some(name.into()),
            points,
            style,
            color: 0,
        };
        let chart = |lines| Chart {
            title: "t".into(),
            x_desc: "x".into(),
            y_desc: "y".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.0, 1.0)),
            y_range: Some((0.0, 1.0)),
            lines,
        };
        let ks = (0..=20).map(|k| k as f64 / 20.0);
        let diagonal = line(
            "diagonal",
            Style::Points,
            ks.clone().map(|v| (v, v)).collect(),
        );
        let svg = render(&chart(vec![diagonal.clone()])).unwrap();
        assert!(svg.starts_with("<svg width=\"900\""), "{}", &svg[..60]);
        assert!(text_x(&svg, "diagonal") < 450.0, "upper left");
        let outline = ks
            .clone()
            .map(|x| (x, 0.0))
            .chain(ks.rev().map(|x| (x, 1.0)))
            .collect();
        let svg = render(&chart(vec![
            line("everywhere", Style::Band, outline),
            diagonal,
        ]))
        .unwrap();
        assert!(
            svg.starts_with(&format!("<svg width=\"{}\"", 900 + LEGEND_PANEL)),
            "{}",
            &svg[..60]
        );
        for name in ["everywhere", "diagonal"] {
            assert!(text_x(&svg, name) > 882.0, "{name} beside the plot");
        }
    }
}
