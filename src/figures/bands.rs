//! Bootstrap bands in figures: a band's outline, the ε values a banded
//! figure draws, and each capacity fractile against p with its band and the
//! paper's law (paper Fig. 8 per fractile).

use super::figure::Figure;
use super::shared::{law_at, PAPER_EQ, Q_NAMES, Q_VALUES};
use crate::fragility;
use crate::plot::{Chart, Line, Scale, Style};
use crate::study::StudyData;
use crate::tables::reduce::CapacityBandRow;

/// A band's outline from (x, lo, hi) in x order: the lower edge left to
/// right, then the upper edge back ([`Style::Band`]).
pub(super) fn outline(rows: &[(f64, f64, f64)]) -> Vec<(f64, f64)> {
    rows.iter()
        .map(|r| (r.0, r.1))
        .chain(rows.iter().rev().map(|r| (r.0, r.2)))
        .collect()
}

/// The ε values a banded figure draws: the grid's first, middle and last.
pub(super) fn band_eps(es: &[f64]) -> Vec<(usize, f64)> {
    let mut picks = vec![0, es.len() / 2, es.len() - 1];
    picks.dedup();
    picks.into_iter().map(|i| (i, es[i])).collect()
}

/// Fig. 8 per fractile with its bootstrap band and the paper's law.
pub(super) fn capacity_bands(d: &StudyData) -> Vec<Figure> {
    let Some(bands) = d.bands.as_ref().filter(|_| d.is_grid()) else {
        return Vec::new();
    };
    let (ps, es) = d.ps_and_eps();
    let paper = fragility::paper();
    let p_dense = crate::fit::p_curve(&ps);
    let level = bands.first().map_or(0.9, |b| b.level);
    Q_VALUES
        .iter()
        .enumerate()
        .map(|(qi, &q)| {
            let mut lines = Vec::new();
            for (k, (_, e)) in band_eps(&es).into_iter().enumerate() {
                let rows: Vec<&CapacityBandRow> = bands
                    .iter()
                    .filter(|b| b.quantile == q && b.eps == e)
                    .collect();
                let band: Vec<(f64, f64, f64)> = rows.iter().map(|b| (b.p, b.lo, b.hi)).collect();
                lines.push(Line {
                    name: Some(format!("{:.0} % band, ε = {e:.2}", 100.0 * level)),
                    points: outline(&band),
                    style: Style::Band,
                    color: k,
                });
                lines.push(Line {
                    name: Some(format!("this study, ε = {e:.2}")),
                    points: rows.iter().map(|b| (b.p, b.eta_c)).collect(),
                    style: Style::LinePoints,
                    color: k,
                });
                lines.push(Line {
                    name: Some(format!("paper Eq. {}, ε = {e:.2}", PAPER_EQ[qi])),
                    points: p_dense
                        .iter()
                        .map(|&p| (p, law_at(&paper[qi], p, e)))
                        .collect(),
                    style: Style::Dashed,
                    color: k,
                });
            }
            Figure {
                file: format!("fig08_capacity_bands_q{}.svg", (100.0 * q).round()),
                chart: Chart {
                    title: format!(
                        "Capacity η_c,{} with its bootstrap band",
                        (100.0 * q).round()
                    ),
                    x_desc: "p (1/s)".into(),
                    y_desc: format!("η_c,{}", (100.0 * q).round()),
                    x_scale: Scale::Log,
                    y_scale: Scale::Linear,
                    x_range: None,
                    y_range: Some((0.0, 1.0)),
                    lines,
                },
                caption: format!(
                    "The {} fractile of η_c against p for three ε (lines), its {:.0} % percentile \
                     bootstrap band (shaded; {} resamples of whole {}s) and the paper's Eq. {} \
                     (dashed) (paper Fig. 8).",
                    Q_NAMES[qi],
                    100.0 * level,
                    bands.first().map_or(0, |b| b.resamples),
                    bands
                        .first()
                        .map_or("pair", |b| crate::label::Label::label(b.unit)),
                    PAPER_EQ[qi]
                ),
            }
        })
        .collect()
}
