//! The horizontal bar chart: one labelled bar per entry, top to bottom
//! (the deaggregation of a rate by PGA, a ranking of blocks).

use plotters::prelude::*;

use super::axes::{keep, tick_label, Hue, Scale, CANVAS, FONT_DESC, FONT_TICK};
use super::error::{draw_err, PlotError};

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
        let root = SVGBackend::with_string(&mut svg, (CANVAS.0, height)).into_drawing_area();
        root.fill(&WHITE).map_err(&err)?;
        let body = super::render::titled(&root, &chart.title).map_err(&err)?;
        let mut builder = ChartBuilder::on(&body);
        builder
            .margin(18)
            .x_label_area_size(50)
            .y_label_area_size((9 * longest as u32 + 24).clamp(60, 450));
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
                    .label_style(("sans-serif", FONT_TICK))
                    .axis_desc_style(("sans-serif", FONT_DESC))
                    .light_line_style(WHITE.mix(0.0))
                    .draw()
                    .map_err(&err)?;
                let color = Hue::Series(0).rgb();
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
