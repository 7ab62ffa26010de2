//! Bootstrap bands in figures: a band's outline, the ε values a banded
//! figure draws, and each capacity fractile against p with its band and the
//! paper's law (paper Fig. 8 per fractile).

use super::figure::Figure;
use super::shared::{eta_axis, law_at, ramp, PAPER_EQ, Q_NAMES, Q_VALUES};
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
            for (_, e) in band_eps(&es) {
                let rows: Vec<&CapacityBandRow> = bands
                    .iter()
                    .filter(|b| b.quantile == q && b.eps == e)
                    .collect();
                let band: Vec<(f64, f64, f64)> = rows.iter().map(|b| (b.p, b.lo, b.hi)).collect();
                lines.push(Line {
                    name: Some(format!("{:.0} % band, ε = {e:.2}", 100.0 * level)),
                    points: outline(&band),
                    style: Style::Band,
                    hue: ramp(&es, e),
                });
                lines.push(Line {
                    name: Some(format!("this study, ε = {e:.2}")),
                    points: rows.iter().map(|b| (b.p, b.eta_c)).collect(),
                    style: Style::LinePoints,
                    hue: ramp(&es, e),
                });
                lines.push(Line {
                    name: Some(format!("paper Eq. {}, ε = {e:.2}", PAPER_EQ[qi])),
                    points: p_dense
                        .iter()
                        .map(|&p| (p, law_at(&paper[qi], p, e)))
                        .collect(),
                    style: Style::Dashed,
                    hue: ramp(&es, e),
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
                    y_desc: eta_axis(d, &format!("η_c,{}", (100.0 * q).round())),
                    x_scale: Scale::Log,
                    y_scale: Scale::Linear,
                    x_range: None,
                    y_range: Some((0.0, 1.0)),
                    x_ticks: None,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{band, block_study, grid_study};

    #[test]
    fn an_outline_runs_along_the_lower_edge_and_back_along_the_upper() {
        let rows = [(1.0, 0.1, 0.3), (2.0, 0.2, 0.5)];
        assert_eq!(
            outline(&rows),
            [(1.0, 0.1), (2.0, 0.2), (2.0, 0.5), (1.0, 0.3)]
        );
        assert!(outline(&[]).is_empty());
    }

    #[test]
    fn banded_figures_draw_the_first_middle_and_last_eps_once_each() {
        assert_eq!(band_eps(&[0.5]), [(0, 0.5)]);
        assert_eq!(band_eps(&[0.5, 0.9]), [(0, 0.5), (1, 0.9)]);
        assert_eq!(
            band_eps(&[0.5, 0.6, 0.7, 0.8]),
            [(0, 0.5), (2, 0.7), (3, 0.8)]
        );
    }

    /// The median's band at ε = 0.5 over p = 1, 2; nothing else tabulated.
    fn study() -> StudyData {
        let mut d = grid_study(&[1.0, 2.0], &[0.5, 0.9]);
        d.bands = Some(vec![
            band(1.0, 0.5, 0.5, 0.3, 0.2, 0.4),
            band(2.0, 0.5, 0.5, 0.35, 0.25, 0.45),
        ]);
        d
    }

    #[test]
    fn each_fractile_gets_its_band_its_values_and_the_papers_law() {
        let figs = capacity_bands(&study());
        let files: Vec<_> = figs.iter().map(|f| f.file.as_str()).collect();
        assert_eq!(
            files,
            [
                "fig08_capacity_bands_q16.svg",
                "fig08_capacity_bands_q50.svg",
                "fig08_capacity_bands_q84.svg"
            ]
        );
        let c = &figs[1].chart;
        assert_eq!(c.title, "Capacity η_c,50 with its bootstrap band");
        // Three lines for each of the two ε.
        assert_eq!(c.lines.len(), 6);
        assert_eq!(c.lines[0].name.as_deref(), Some("90 % band, ε = 0.50"));
        assert_eq!(c.lines[0].style, Style::Band);
        assert_eq!(
            c.lines[0].points,
            [(1.0, 0.2), (2.0, 0.25), (2.0, 0.45), (1.0, 0.4)]
        );
        assert_eq!(c.lines[1].points, [(1.0, 0.3), (2.0, 0.35)]);
        // The paper's Eq. 10 at ε = 0.5, p = 1: a = 0.44 + 0.43ε,
        // b = 0.56 − 1.14ε + 1.25ε², c = 1.66 − 0.38ε + 1.4ε².
        let paper = &c.lines[2];
        assert_eq!(paper.name.as_deref(), Some("paper Eq. 10, ε = 0.50"));
        let e: f64 = 0.5;
        let (a, b, cc) = (
            0.44 + 0.43 * e,
            0.56 - 1.14 * e + 1.25 * e * e,
            1.66 - 0.38 * e + 1.4 * e * e,
        );
        let by_hand = a * (1.0 - (-b * 1.0f64).exp()).powf(cc);
        assert_eq!(paper.points[0].0, 1.0);
        assert!((paper.points[0].1 - by_hand).abs() < 1e-12);
        // ε = 0.9 has no band rows: empty band and values.
        assert!(c.lines[3].points.is_empty() && c.lines[4].points.is_empty());
        assert!(figs[0].chart.lines[0].points.is_empty());
    }

    #[test]
    fn no_band_figures_without_bands_or_off_the_grid() {
        let mut d = study();
        d.bands = None;
        assert!(capacity_bands(&d).is_empty());
        let mut blocks = block_study();
        blocks.bands = study().bands;
        assert!(capacity_bands(&blocks).is_empty());
    }
}
