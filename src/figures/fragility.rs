//! The fragility figure: the probability of overturning of an example block
//! against PGA, from this study's regression (with its band) and the paper's.

use super::bands::outline;
use super::figure::Figure;
use crate::fragility;
use crate::plot::{Chart, Line, Scale, Style};
use crate::study::StudyData;

/// The fragility of an example block, from this study's fit and the paper's.
pub(super) fn fragility_example(d: &StudyData) -> Vec<Figure> {
    let block = fragility::example_block();
    let pgas = fragility::example_pgas();
    let mut lines = Vec::new();
    let band: Vec<(f64, f64, f64)> = d.fit_bands.as_ref().map_or(Vec::new(), |b| {
        b.fragility()
            .iter()
            .filter_map(|r| Some((r.pga_g?, r.lo?, r.hi?)))
            .collect()
    });
    if !band.is_empty() {
        lines.push(Line {
            name: Some(format!(
                "this study's {:.0} % band",
                100.0
                    * d.fit_bands
                        .as_ref()
                        .and_then(|b| b.rows.first())
                        .map_or(0.9, |r| r.level)
            )),
            points: outline(&band),
            style: Style::Band,
            color: 0,
        });
    }
    for (name, laws, color) in [
        ("this study", d.laws.to_vec(), 0),
        ("paper", fragility::paper().to_vec(), 1),
    ] {
        if let Some((m, beta)) = fragility::median_beta(&laws, block.p(), block.eps) {
            lines.push(Line {
                name: Some(name.into()),
                points: pgas
                    .iter()
                    .map(|&g| (g, fragility::probability(m, beta, block.alpha(), g)))
                    .collect(),
                style: if color == 0 {
                    Style::Line
                } else {
                    Style::Dashed
                },
                color,
            });
        }
    }
    if lines.is_empty() {
        return Vec::new();
    }
    vec![Figure {
        file: "fragility_example.svg".into(),
        chart: Chart {
            title: format!(
                "Fragility of a block b = 0.25 m, h = 1.0 m (α = {:.3} rad, p = {:.2} 1/s, ε = {:.2})",
                block.alpha(),
                block.p(),
                block.eps
            ),
            x_desc: "PGA (g)".into(),
            y_desc: "P(overturn | PGA)".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.0, 1.2)),
            y_range: Some((0.0, 1.0)),
            lines,
        },
        caption: format!(
            "Probability of overturning of an example block (a 0.5 m × 2 m cabinet, \
             Housner's ε) from this study's regression and the paper's{}.",
            if band.is_empty() {
                ""
            } else {
                ", with the band of this study's curve over the bootstrap resamples (shaded; \
                 `fit_bands.parquet`)"
            }
        ),
    }]
}
