//! Draws a [`Chart`] as SVG: the canvas, the axes of its scales with their
//! ticks, every series in its style (bands first, under every line) and the
//! legend beside the plot.

use plotters::coord::ranged1d::Ranged;
use plotters::prelude::*;

use super::axes::{
    axis_range, log_values, tick_label, ticks, Scale, CANVAS, EVERY_MANTISSA, FONT_DESC, FONT_TICK,
    FONT_TITLE,
};
use super::chart::{runs, Chart, Line, Run, Style};
use super::error::{draw_err, PlotError};
use super::legend::{has_legend, legend_panel, LEGEND_PANEL};

/// One axis as drawn: plotters sees a linear axis, in log10 of the values
/// on a log scale, with our ticks as its key points.
struct Axis {
    scale: Scale,
    /// The drawn range (log10 on a log axis).
    range: (f64, f64),
    /// The ticks, drawn (log10 on a log axis) and as labelled.
    ticks: Vec<(f64, f64)>,
    /// Faint lines between ticks: every mantissa 1–9 on a log axis.
    minor: Vec<f64>,
}

impl Axis {
    fn new(scale: Scale, given: Option<(f64, f64)>, lo: f64, hi: f64, at: Option<&[f64]>) -> Axis {
        let (a, b) = axis_range(scale, given, lo, hi);
        let values = match at {
            Some(t) => t.iter().copied().filter(|&v| v >= a && v <= b).collect(),
            None => ticks(scale, a, b),
        };
        let to = |v: f64| drawn(scale, v);
        // Faint lines at every mantissa, on log axes of up to six decades.
        let minor = match scale {
            Scale::Log if (b / a).log10() <= 6.0 => log_values(a, b, &EVERY_MANTISSA, 1),
            _ => Vec::new(),
        };
        Axis {
            scale,
            range: (to(a), to(b)),
            ticks: values.into_iter().map(|v| (to(v), v)).collect(),
            minor: minor.into_iter().map(to).collect(),
        }
    }

    /// A data value where plotters draws it.
    fn at(&self, v: f64) -> f64 {
        drawn(self.scale, v)
    }

    /// The label of the tick drawn at `v`: the value it stands for.
    fn label(&self, v: f64) -> String {
        self.ticks
            .iter()
            .find(|t| (t.0 - v).abs() <= 1e-9 * (1.0 + v.abs()))
            .map_or(String::new(), |t| tick_label(t.1))
    }

    fn coord(&self) -> Ticked {
        Ticked {
            range: self.range,
            bold: self.ticks.iter().map(|t| t.0).collect(),
            light: self.minor.clone(),
        }
    }
}

/// Where a value is drawn on an axis of `scale`: log10 of it on a log axis.
fn drawn(scale: Scale, v: f64) -> f64 {
    match scale {
        Scale::Linear => v,
        Scale::Log => v.log10(),
    }
}

/// A linear coordinate whose key points are ours: the ticks (labelled,
/// with a grid line) and the faint lines between them.
struct Ticked {
    range: (f64, f64),
    bold: Vec<f64>,
    light: Vec<f64>,
}

impl Ranged for Ticked {
    type FormatOption = plotters::coord::ranged1d::DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let f = (v - self.range.0) / (self.range.1 - self.range.0);
        limit.0 + (f * (limit.1 - limit.0) as f64).round() as i32
    }

    fn key_points<H: plotters::coord::ranged1d::KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.light.clone()
        } else {
            self.bold.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.range.0..self.range.1
    }
}

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
    let xa = Axis::new(
        chart.x_scale,
        chart.x_range,
        x0,
        x1,
        chart.x_ticks.as_deref(),
    );
    let ya = Axis::new(chart.y_scale, chart.y_range, y0, y1, None);
    // Every chart is drawn on one canvas; a legend takes a panel right of
    // the plot, so it never covers data.
    let legend = has_legend(&lines);
    let (width, height) = CANVAS;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(&err)?;
        let body = titled(&root, &chart.title).map_err(&err)?;
        let mut builder = ChartBuilder::on(&body);
        builder
            .margin(18)
            .margin_right(if legend { 18 + LEGEND_PANEL } else { 24 })
            .x_label_area_size(60)
            .y_label_area_size(85);
        let mut c = builder
            .build_cartesian_2d(xa.coord(), ya.coord())
            .map_err(&err)?;
        c.configure_mesh()
            .x_desc(chart.x_desc.as_str())
            .y_desc(chart.y_desc.as_str())
            .x_label_formatter(&|v| xa.label(*v))
            .y_label_formatter(&|v| ya.label(*v))
            .label_style(("sans-serif", FONT_TICK))
            .axis_desc_style(("sans-serif", FONT_DESC))
            .bold_line_style(RGBColor(200, 200, 200))
            .light_line_style(RGBColor(238, 238, 238))
            .draw()
            .map_err(&err)?;
        // Bands first, under every line.
        let by_layer = lines
            .iter()
            .filter(|(l, _)| l.style == Style::Band)
            .chain(lines.iter().filter(|(l, _)| l.style != Style::Band));
        for (l, runs) in by_layer {
            for run in runs {
                let run: Run = run.iter().map(|&(x, y)| (xa.at(x), ya.at(y))).collect();
                draw_run(&mut c, l, &run, &chart.title)?;
            }
        }
        if legend {
            legend_panel(&root, &lines, (width - LEGEND_PANEL) as i32, 50).map_err(&err)?;
        }
        root.present().map_err(&err)?;
    }
    Ok(svg)
}

type Plot<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<Ticked, Ticked>>;

/// The canvas below its title, which is centred over the whole canvas (not
/// over the plot beside a legend panel, where a long title ran off the
/// left edge) in a font small enough for it to fit: about 0.55 of the
/// font size a character, at most 22 px, at least 12.
pub(super) fn titled<'a>(
    root: &DrawingArea<SVGBackend<'a>, plotters::coord::Shift>,
    title: &str,
) -> Result<
    DrawingArea<SVGBackend<'a>, plotters::coord::Shift>,
    DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>,
> {
    let width = root.dim_in_pixel().0 as f64 - 40.0;
    let chars = title.chars().count().max(1) as f64;
    let size = (width / (0.55 * chars))
        .floor()
        .clamp(12.0, FONT_TITLE as f64) as u32;
    root.titled(title, ("sans-serif", size))
}

/// Draws one unbroken run (in drawn coordinates) of line `l` in its style.
/// A run of one point, which a line cannot show (one block of its ε, a
/// series cut by the axis to one point), is drawn as a dot.
fn draw_run(c: &mut Plot<'_, '_>, l: &Line, run: &Run, title: &str) -> Result<(), PlotError> {
    let err = draw_err(title);
    let color = l.hue.rgb();
    if let ([p], Style::Line | Style::Dashed | Style::Faint) = (&run[..], l.style) {
        let dot = match l.style {
            Style::Faint => Circle::new(*p, 2, RGBColor(190, 190, 190).filled()),
            _ => Circle::new(*p, 3, color.filled()),
        };
        c.draw_series(std::iter::once(dot)).map_err(&err)?;
        return Ok(());
    }
    match l.style {
        Style::Band => {
            c.draw_series(std::iter::once(Polygon::new(
                run.clone(),
                color.mix(0.18).filled(),
            )))
            .map_err(&err)?;
        }
        Style::Dashed => {
            c.draw_series(DashedLineSeries::new(
                run.iter().copied(),
                9,
                5,
                color.stroke_width(2),
            ))
            .map_err(&err)?;
        }
        Style::Faint => {
            c.draw_series(LineSeries::new(
                run.iter().copied(),
                RGBColor(190, 190, 190).stroke_width(1),
            ))
            .map_err(&err)?;
        }
        Style::Line | Style::LinePoints | Style::Points => {
            if l.style != Style::Points {
                c.draw_series(LineSeries::new(run.iter().copied(), color.stroke_width(2)))
                    .map_err(&err)?;
            }
            if l.style != Style::Line {
                c.draw_series(run.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(&err)?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::Hue;

    /// The x of the `<text>` element holding `name`.
    fn text_x(svg: &str, name: &str) -> f64 {
        let at = svg.find(&format!("\n{name}\n</text>")).expect("the entry");
        let open = svg[..at].rfind("<text x=\"").expect("its element") + 9;
        svg[open..].split('"').next().unwrap().parse().unwrap()
    }

    /// Every `<text>` of the SVG.
    fn texts(svg: &str) -> Vec<&str> {
        svg.split("</text>")
            .filter_map(|t| t.rsplit('>').next())
            .map(str::trim)
            .collect()
    }

    fn chart(lines: Vec<Line>, x_scale: Scale) -> Chart {
        Chart {
            title: "t".into(),
            x_desc: "x".into(),
            y_desc: "y".into(),
            x_scale,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: None,
            x_ticks: None,
            lines,
        }
    }

    fn line(name: Option<&str>, points: Vec<(f64, f64)>) -> Line {
        Line {
            name: name.map(Into::into),
            points,
            style: Style::Points,
            hue: Hue::Series(0),
        }
    }

    /// Every chart has one canvas, with or without a legend, so a report
    /// scales every figure alike; a legend sits right of the plot, every
    /// entry beyond its right edge (canvas − panel), never on the data.
    #[test]
    fn one_canvas_and_the_legend_beside_the_plot() {
        let diagonal: Vec<(f64, f64)> = (0..=20).map(|k| (k as f64, k as f64)).collect();
        for name in [None, Some("diagonal")] {
            let both = vec![
                line(name, diagonal.clone()),
                line(Some("twice"), diagonal.clone()),
            ];
            let svg = render(&chart(both, Scale::Linear)).unwrap();
            let head = format!("<svg width=\"{}\" height=\"{}\"", CANVAS.0, CANVAS.1);
            assert!(svg.starts_with(&head), "{}", &svg[..60]);
            if let Some(n) = name {
                assert!(text_x(&svg, n) > (CANVAS.0 - LEGEND_PANEL) as f64);
            }
        }
    }

    /// A long title fits on the canvas: it starts right of the left edge
    /// and its font shrinks to fit (the example fragility's title once
    /// began "agility of a block…", its start off the canvas).
    #[test]
    fn a_long_title_stays_on_the_canvas() {
        let title = "Fragility of a block of half-width b = 0.25 m, half-height h = 1 m \
                     (α = 0.245 rad, p = 2.67 1/s, ε = 0.91)";
        let mut c = chart(
            vec![line(Some("a"), vec![(0.0, 0.0), (1.0, 1.0)])],
            Scale::Linear,
        );
        c.title = title.into();
        let svg = render(&c).unwrap();
        let at = svg.find(&format!("\n{title}\n</text>")).expect("the title");
        let element = &svg[svg[..at].rfind("<text").unwrap()..at];
        let attr = |name: &str| -> f64 {
            let from = element.find(&format!("{name}=\"")).expect(name) + name.len() + 2;
            element[from..]
                .split('"')
                .next()
                .unwrap()
                .trim_end_matches("px")
                .parse()
                .unwrap()
        };
        let size = attr("font-size");
        // Half the title's width at ~0.55 em a character, either side of x
        // when centred (plotters anchors a caption at its middle).
        let half = 0.55 * size * title.chars().count() as f64 / 2.0;
        let x = attr("x");
        assert!(
            x - half >= 0.0 && x + half <= CANVAS.0 as f64,
            "x {x}, size {size}"
        );
    }

    /// A line of one point (each named block its own ε) is drawn as a dot
    /// where its point is; it was an invisible polyline of one vertex.
    #[test]
    fn a_line_of_one_point_is_a_dot() {
        for style in [Style::Line, Style::Dashed, Style::Faint] {
            let lone = Line {
                style,
                ..line(Some("lone"), vec![(1.0, 1.0)])
            };
            let other = line(Some("other"), vec![(0.0, 0.0), (2.0, 2.0)]);
            let svg = render(&chart(vec![lone, other], Scale::Linear)).unwrap();
            // The points style draws its two dots; the lone line one more,
            // midway between them (the plot is linear in both axes).
            let centres: Vec<(f64, f64)> = svg
                .split("<circle ")
                .skip(1)
                .map(|c| {
                    let attr = |n: &str| -> f64 {
                        let from = c.find(&format!("{n}=\"")).unwrap() + n.len() + 2;
                        c[from..].split('"').next().unwrap().parse().unwrap()
                    };
                    (attr("cx"), attr("cy"))
                })
                .collect();
            let near = |c: (f64, f64), a: (f64, f64), b: (f64, f64)| {
                (c.0 - (a.0 + b.0) / 2.0).abs() <= 1.0 && (c.1 - (a.1 + b.1) / 2.0).abs() <= 1.0
            };
            let midway = centres.iter().enumerate().any(|(i, &a)| {
                centres[i + 1..]
                    .iter()
                    .any(|&b| a != b && centres.iter().any(|&c| c != a && c != b && near(c, a, b)))
            });
            assert!(midway, "{style:?}: no dot midway among {centres:?}");
        }
    }

    /// A log axis from 0.33 to 10 is labelled 0.5, 1, 2, 5 and 10, each
    /// once (plotters' own log mesh printed "10" twice and nothing below 1).
    #[test]
    fn a_log_axis_labels_each_tick_once() {
        let pts = vec![(0.33, 300.0), (10.0, 700.0)];
        let mut c = chart(vec![line(None, pts)], Scale::Log);
        c.x_range = Some((0.33, 10.0));
        let svg = render(&c).unwrap();
        let t = texts(&svg);
        for label in ["0.5", "1", "2", "5", "10"] {
            assert_eq!(
                t.iter().filter(|s| **s == label).count(),
                1,
                "{label} in {t:?}"
            );
        }
        // Given ticks replace them: levels that double, the last one included.
        c.x_range = Some((20.0, 2000.0));
        c.x_ticks = Some(vec![25.0, 50.0, 100.0, 200.0, 400.0, 800.0, 1600.0]);
        let svg = render(&c).unwrap();
        let t = texts(&svg);
        assert!(t.contains(&"1600") && t.contains(&"25"), "{t:?}");
        assert!(!t.contains(&"1000"), "{t:?}");
    }
}
