//! Figures as SVG text (plotters' SVG backend; no fonts or bitmaps needed).
//! Pure: returns the SVG as a `String`; the caller writes it.

use std::error::Error;

use plotters::prelude::*;

/// A figure that could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("{title}: nothing to plot")]
    Empty { title: String },
    #[error("{title}: drawing failed")]
    Draw {
        title: String,
        #[source]
        source: Box<dyn Error + Send + Sync>,
    },
}

/// Maps a plotters error to [`PlotError::Draw`] for the chart `title`.
fn draw_err<E: Error + Send + Sync + 'static>(title: &str) -> impl Fn(E) -> PlotError + '_ {
    move |e| PlotError::Draw {
        title: title.to_string(),
        source: Box::new(e),
    }
}

/// One named series of (x, y) points, drawn as markers joined by a line.
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

const PALETTE: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(0, 0, 128),
    RGBColor(128, 0, 0),
];

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
        let root = SVGBackend::with_string(&mut svg, (900, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(&err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 22))
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
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(&err)?;
        for (i, s) in series.iter().enumerate() {
            let color = PALETTE[i % PALETTE.len()];
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
            .label_font(("sans-serif", 15))
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

/// Axis scale. Log axes are drawn as log10 of the values on a linear axis,
/// labelled with the values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scale {
    Linear,
    Log,
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Line,
    Points,
    LinePoints,
    /// A thin light-grey line (one of many, such as every record's IDA curve).
    Faint,
    /// A dashed line (a published curve beside this study's).
    Dashed,
    /// A filled area in a light tint of the colour: the points trace its
    /// outline (a band's lower edge left to right, then its upper edge back).
    Band,
}

/// One series of a [`Chart`].
#[derive(Debug, Clone)]
pub struct Line {
    /// Legend entry; `None` keeps it out of the legend.
    pub name: Option<String>,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// Palette index (ignored for `Faint`).
    pub color: usize,
}

/// A 2-D chart with labelled axes and a legend.
#[derive(Debug, Clone)]
pub struct Chart {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub x_scale: Scale,
    pub y_scale: Scale,
    /// Axis ranges in data units; `None` fits the data.
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    pub lines: Vec<Line>,
}

fn keep(scale: Scale, v: f64) -> bool {
    v.is_finite() && (scale == Scale::Linear || v > 0.0)
}

fn tick_label(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e4).contains(&a) {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// The axis range in data units: the given one, or the data's with a margin
/// (multiplicative on a log axis).
fn axis_range(scale: Scale, given: Option<(f64, f64)>, lo: f64, hi: f64) -> (f64, f64) {
    if let Some((a, b)) = given.filter(|(a, b)| keep(scale, *a) && keep(scale, *b) && b > a) {
        return (a, b);
    }
    match scale {
        Scale::Linear => {
            let pad = if hi > lo { 0.03 * (hi - lo) } else { 0.5 };
            (lo - pad, hi + pad)
        }
        Scale::Log => {
            if hi > lo {
                let f = (hi / lo).powf(0.03);
                (lo / f, hi * f)
            } else {
                (lo / 2.0, hi * 2.0)
            }
        }
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

/// The legend in the panel right of the plot, from (`x`, `y`): the same
/// entries, order and symbols as a legend in a corner (bands first).
fn legend_panel(
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

/// Each line's unbroken runs: what an axis cannot show is dropped, and a
/// dropped point splits its line.
fn runs(chart: &Chart) -> Vec<(&Line, Vec<Run>)> {
    chart
        .lines
        .iter()
        .map(|l| {
            let mut runs = vec![Vec::new()];
            for &(x, y) in &l.points {
                if keep(chart.x_scale, x) && keep(chart.y_scale, y) {
                    runs.last_mut().expect("one run").push((x, y));
                } else {
                    runs.push(Vec::new());
                }
            }
            runs.retain(|r| !r.is_empty());
            (l, runs)
        })
        .collect()
}

/// Width (px) of the panel beside the plot that holds a legend no corner
/// of the plot can take without covering data.
const LEGEND_PANEL: u32 = 300;

/// The corner of the plot where the legend covers the fewest data points
/// (upper right, upper left, lower right, lower left on ties), judged in
/// axis fractions: the legend spans about 40 % of the width and 5 % of the
/// height per entry; and how many points it covers there.
fn legend_placement(chart: &Chart, lines: &Runs) -> (SeriesLabelPosition, usize) {
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

/// An unbroken stretch of a line.
type Run = Vec<(f64, f64)>;
type Runs<'a> = [(&'a Line, Vec<Run>)];

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
        let color = PALETTE[l.color % PALETTE.len()];
        let faint = RGBColor(190, 190, 190);
        for (k, run) in runs.iter().enumerate() {
            let legend = k == 0 && l.name.is_some();
            if l.style == Style::Band {
                let fill = color.mix(0.18);
                let s = c
                    .draw_series(std::iter::once(Polygon::new(run.clone(), fill.filled())))
                    .map_err(&err)?;
                if legend {
                    any_legend = true;
                    s.label(l.name.clone().unwrap_or_default())
                        .legend(move |(x, y)| {
                            Rectangle::new([(x, y - 5), (x + 20, y + 5)], fill.filled())
                        });
                }
                continue;
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
                continue;
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

/// A horizontal bar chart: one labelled bar per entry, top to bottom in the
/// order given (the deaggregation of a rate by PGA, a ranking of blocks).
#[derive(Debug, Clone)]
pub struct Bars {
    pub title: String,
    /// What the bars measure (the x axis).
    pub x_desc: String,
    pub x_scale: Scale,
    /// (label, value); values that the axis cannot show (≤ 0 on a log axis,
    /// not finite) are left without a bar.
    pub bars: Vec<(String, f64)>,
}

/// Renders a [`Bars`] chart as SVG.
pub fn render_bars(chart: &Bars) -> Result<String, PlotError> {
    let err = draw_err(&chart.title);
    let shown: Vec<f64> = chart
        .bars
        .iter()
        .map(|b| b.1)
        .filter(|&v| keep(chart.x_scale, v))
        .collect();
    if shown.is_empty() {
        return Err(PlotError::Empty {
            title: chart.title.clone(),
        });
    }
    let hi = shown.iter().cloned().fold(f64::MIN, f64::max);
    let lo = shown.iter().cloned().fold(f64::MAX, f64::min);
    // Bars start at 0 on a linear axis, at a decade below the smallest on a log one.
    let (xa, xb) = match chart.x_scale {
        Scale::Linear => (0.0, if hi > 0.0 { hi * 1.08 } else { 1.0 }),
        Scale::Log => (
            10f64.powf((lo.log10() - 0.5).floor()),
            10f64.powf((hi.log10() + 0.3).ceil()),
        ),
    };
    let n = chart.bars.len();
    let labels: Vec<String> = chart.bars.iter().map(|b| b.0.clone()).collect();
    let longest = labels.iter().map(|l| l.chars().count()).max().unwrap_or(4);
    let height = (160 + 28 * n).clamp(300, 1600) as u32;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, height)).into_drawing_area();
        root.fill(&WHITE).map_err(&err)?;
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(&chart.title, ("sans-serif", 20))
            .margin(18)
            .x_label_area_size(50)
            .y_label_area_size((8 * longest as u32 + 20).clamp(60, 400));
        // Bar k is drawn around y = n − 1 − k, so the first bar is on top.
        let y_of = move |k: usize| (n - 1 - k) as f64;
        let label_at = move |y: &f64| {
            let k = n as f64 - 1.0 - y.round();
            if (y - y.round()).abs() < 1e-6 && k >= 0.0 && (k as usize) < n {
                labels[k as usize].clone()
            } else {
                String::new()
            }
        };
        macro_rules! body {
            ($x:expr) => {{
                let mut c = builder
                    .build_cartesian_2d($x, -0.6f64..(n as f64 - 0.4))
                    .map_err(&err)?;
                c.configure_mesh()
                    .x_desc(chart.x_desc.as_str())
                    .x_label_formatter(&|v| tick_label(*v))
                    .y_labels(n.max(2))
                    .y_label_formatter(&label_at)
                    .label_style(("sans-serif", 13))
                    .axis_desc_style(("sans-serif", 15))
                    .light_line_style(WHITE.mix(0.0))
                    .draw()
                    .map_err(&err)?;
                let color = PALETTE[0];
                c.draw_series(chart.bars.iter().enumerate().filter_map(|(k, b)| {
                    keep(chart.x_scale, b.1).then(|| {
                        Rectangle::new(
                            [(xa, y_of(k) - 0.35), (b.1, y_of(k) + 0.35)],
                            color.filled(),
                        )
                    })
                }))
                .map_err(&err)?;
            }};
        }
        match chart.x_scale {
            Scale::Linear => body!(xa..xb),
            Scale::Log => body!((xa..xb).log_scale()),
        }
        root.present().map_err(&err)?;
    }
    Ok(svg)
}
