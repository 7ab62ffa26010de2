//! The fragility figure: the probability of overturning of an example block
//! against PGA, from this study's regression (with its band) and the paper's.

use super::bands::outline;
use super::figure::Figure;
use crate::fragility;
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::study::StudyData;

/// The fragility of an example block, from this study's fit and the paper's.
pub(super) fn fragility_example(d: &StudyData) -> Vec<Figure> {
    // A floor study's capacities are in its floor's peak, not the paper's
    // PGA, and text records' in their own peak; a study of named blocks has
    // no regression, and its own blocks' fragilities are in the damage
    // section: the paper's curve of an example cabinet would speak of none.
    if d.peak() != crate::im::Im::Pga || !d.is_grid() {
        return Vec::new();
    }
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
            hue: Hue::Series(0),
        });
    }
    for (name, laws, paper) in [
        ("this study", d.laws.to_vec(), false),
        ("paper", fragility::paper().to_vec(), true),
    ] {
        if let Some((m, beta)) = fragility::median_beta(&laws, block.p(), block.eps) {
            lines.push(Line {
                name: Some(name.into()),
                points: pgas
                    .iter()
                    .map(|&g| (g, fragility::probability(m, beta, &block, g)))
                    .collect(),
                // The paper's curve dashed, in the colour of the data it models.
                style: if paper { Style::Dashed } else { Style::Line },
                hue: Hue::Series(0),
            });
        }
    }
    if lines.is_empty() {
        return Vec::new();
    }
    // This study's curve beyond its blocks is an extrapolation: said as
    // `rocking fragility --from` warns of it.
    let stretched = match d.laws.is_empty() {
        true => Vec::new(),
        false => fragility::stretched(&block, Some(&d.records_plan().blocks)),
    };
    let stretched = match stretched.is_empty() {
        true => String::new(),
        false => format!(
            " This study's curve is extrapolated: {}.",
            stretched.join("; ")
        ),
    };
    vec![Figure {
        file: "fragility_example.svg".into(),
        chart: Chart {
            title: format!(
                "Fragility of a block of half-width b = 0.25 m, half-height h = 1 m (α = {:.3} rad, p = {:.2} 1/s, ε = {:.2})",
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
            x_ticks: None,
            lines,
        },
        caption: format!(
            "Probability of overturning of an example block (a 0.5 m × 2 m cabinet, \
             Housner's ε) from {}{}.{stretched}",
            match d.laws.is_empty() {
                true => "the paper's regression alone: this study has none (a regression \
                         needs a p × ε grid of at least 3 × 3, fitted by the fit stage)",
                false => "this study's regression and the paper's",
            },
            if band.is_empty() {
                ""
            } else {
                ", with the band of this study's curve over the bootstrap resamples (shaded; \
                 `fit_bands.parquet`)"
            }
        ),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::grid_study;
    use crate::study::FitBands;
    use crate::tables::fit::{BandCurve, FitBandRow};

    /// The example block's median PGA by the paper's Eq. 10: α g / η_c,50.
    fn paper_median_pga() -> f64 {
        let (b, h): (f64, f64) = (0.25, 1.0);
        let alpha = (b / h).atan();
        let p = (3.0 * 9.80665 / (4.0 * b.hypot(h))).sqrt();
        let e = 1.0 - 1.5 * alpha.sin().powi(2);
        let a = 0.44 + 0.43 * e;
        let bb = 0.56 - 1.14 * e + 1.25 * e * e;
        let c = 1.66 - 0.38 * e + 1.4 * e * e;
        alpha / (a * (1.0 - (-bb * p).exp()).powf(c))
    }

    #[test]
    fn without_a_fit_the_papers_curve_alone_crosses_one_half_at_its_median() {
        let figs = fragility_example(&grid_study(&[1.0], &[0.5]));
        assert_eq!(figs.len(), 1);
        assert_eq!(figs[0].file, "fragility_example.svg");
        let c = &figs[0].chart;
        assert_eq!(c.lines.len(), 1);
        let paper = &c.lines[0];
        assert_eq!(
            (paper.name.as_deref(), paper.style),
            (Some("paper"), Style::Dashed)
        );
        // PGA 0.01 g to 1.20 g in steps of 0.01 g.
        assert_eq!(paper.points.len(), 120);
        assert!((paper.points[0].0 - 0.01).abs() < 1e-15);
        assert!((paper.points[119].0 - 1.2).abs() < 1e-12);
        let median = paper_median_pga();
        assert!(median > 0.01 && median < 1.2, "{median}");
        for &(g, prob) in &paper.points {
            assert!((0.0..=1.0).contains(&prob));
            if (g - median).abs() > 1e-6 {
                assert_eq!(prob > 0.5, g > median, "{g} g: {prob}");
            }
        }
        assert_eq!(c.y_range, Some((0.0, 1.0)));
        // The caption says the curve is the paper's alone.
        assert!(
            figs[0]
                .caption
                .contains("from the paper's regression alone: this study has none"),
            "{}",
            figs[0].caption
        );
    }

    /// A study of named blocks has no example fragility: the paper's curve
    /// of a cabinet it does not hold was drawn in how-sure's report.
    #[test]
    fn no_example_for_a_study_of_named_blocks() {
        let d = crate::figures::fixture::block_study();
        assert!(fragility_example(&d).is_empty());
    }

    /// Nor for a grid over text records, whose η is of their own peak (a
    /// floor's PFA): it was drawn against PGA beside the paper's ground
    /// curve.
    #[test]
    fn no_example_for_a_grid_over_text_records() {
        let mut d = grid_study(&[1.0, 2.0], &[0.5, 0.9]);
        assert!(!fragility_example(&d).is_empty());
        d.stood_on = true;
        assert!(fragility_example(&d).is_empty());
    }

    #[test]
    fn this_studys_curve_and_its_band_come_first() {
        let mut d = grid_study(&[1.0], &[0.5]);
        d.laws = fragility::paper().to_vec();
        let row = |g, lo, hi| FitBandRow {
            curve: BandCurve::Fragility,
            quantile: None,
            p: 0.0,
            eps: 0.0,
            pga_g: Some(g),
            value: None,
            lo: Some(lo),
            hi: Some(hi),
            used: 10,
            level: 0.8,
            resamples: 10,
        };
        d.fit_bands = Some(FitBands {
            rows: vec![row(0.1, 0.1, 0.3), row(0.2, 0.2, 0.4)],
            step1_converged: (1, 1),
            laws_complete: (1, 1),
        });
        let figs = fragility_example(&d);
        let c = &figs[0].chart;
        let names: Vec<_> = c.lines.iter().map(|l| l.name.clone().unwrap()).collect();
        assert_eq!(names, ["this study's 80 % band", "this study", "paper"]);
        assert_eq!(
            c.lines[0].points,
            [(0.1, 0.1), (0.2, 0.2), (0.2, 0.4), (0.1, 0.3)]
        );
        // The study's laws are the paper's: the same curve.
        assert_eq!(c.lines[1].points, c.lines[2].points);
        assert!(figs[0].caption.contains("fit_bands.parquet"));
        // The example block (ε = 1 − 1.5·sin²(atan 0.25) = 0.912, p = 2.671
        // 1/s) lies beyond this one-block grid: its curve is extrapolated.
        assert!(
            figs[0]
                .caption
                .contains("This study's curve is extrapolated: ε = 0.912 is outside the study's 0.5–0.5; p = 2.671 1/s is outside the study's 1–1 1/s."),
            "{}",
            figs[0].caption
        );
        // Inside a grid that holds it, nothing is said.
        let mut inside = grid_study(&[1.0, 4.0], &[0.5, 0.95]);
        inside.laws = fragility::paper().to_vec();
        assert!(!fragility_example(&inside)[0]
            .caption
            .contains("extrapolated"));
    }
}
