//! The regression figures: each fractile's fitted law against the data, the
//! fit's band and the paper's law (paper Figs. 10–11), and each coefficient
//! of the law against ε.

use super::bands::{band_eps, outline};
use super::figure::Figure;
use super::shared::{capacity_points, eta_axis, law_at, ramp, PAPER_EQ, Q_NAMES, Q_VALUES};
use crate::fit::polyval;
use crate::fragility::{self, FractileLaw};
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::study::StudyData;

/// Fig. 10 (median) and Fig. 11 (16 % and 84 %): a fractile's regression
/// against the data, with the fit's bootstrap band and the paper's law.
pub(super) fn regressions(d: &StudyData) -> Vec<Figure> {
    if !d.is_grid() {
        return Vec::new();
    }
    [1, 0, 2]
        .into_iter()
        .filter_map(|qi| regression(d, qi))
        .collect()
}

fn regression(d: &StudyData, qi: usize) -> Option<Figure> {
    let q = Q_VALUES[qi];
    let law = d.laws.iter().find(|l| l.quantile == q && l.is_complete())?;
    let (ps, es) = d.ps_and_eps();
    let p_dense = crate::fit::p_curve(&ps);
    let paper = &fragility::paper()[qi];
    let bands = d.fit_bands.as_ref();
    let mut lines = Vec::new();
    // Whether a band leaves the frame's 0–1: η_c cannot (η = 1 is uplift).
    let mut cut = false;
    for (_, e) in band_eps(&es) {
        if let Some(b) = bands {
            let rows: Vec<(f64, f64, f64)> = b
                .eta_c(q, e)
                .iter()
                .filter_map(|r| Some((r.p, r.lo?, r.hi?)))
                .collect();
            cut |= rows.iter().any(|&(_, lo, hi)| lo < 0.0 || hi > 1.0);
            lines.push(Line {
                name: Some(format!("fit's band, ε = {e:.2}")),
                points: outline(&rows),
                style: Style::Band,
                hue: ramp(&es, e),
            });
        }
        lines.push(Line {
            name: Some(format!("data, ε = {e:.2}")),
            points: capacity_points(&d.capacity_fractiles, e, q, |r| Some(r.eta_c)),
            style: Style::Points,
            hue: ramp(&es, e),
        });
        lines.push(Line {
            name: Some(format!("fit, ε = {e:.2}")),
            points: p_dense.iter().map(|&p| (p, law_at(law, p, e))).collect(),
            style: Style::Line,
            hue: ramp(&es, e),
        });
        lines.push(Line {
            name: Some(format!("paper Eq. {}, ε = {e:.2}", PAPER_EQ[qi])),
            points: p_dense.iter().map(|&p| (p, law_at(paper, p, e))).collect(),
            style: Style::Dashed,
            hue: ramp(&es, e),
        });
    }
    let pct = (100.0 * q).round();
    let band_note = bands.map_or(String::new(), |b| {
        let level = b.rows.first().map_or(0.9, |r| r.level);
        let cut_note = match cut {
            true => format!(
                " and cut by the frame where it leaves 0–1: there more than {:.0} % of the \
                 resamples' laws give a value no capacity takes (η_c ≤ 0, or above 1, where \
                 the block would overturn without uplifting; `fit_bands.parquet` holds them), \
                 as a refitted a(ε), b(ε), c(ε) can swing between few ε",
                100.0 * (1.0 - level) / 2.0
            ),
            false => String::new(),
        };
        format!(
            ", its {:.0} % bootstrap band (shaded: {} of {} resamples refitted through both \
             steps{cut_note})",
            100.0 * level,
            b.laws_complete.0,
            b.laws_complete.1
        )
    });
    Some(Figure {
        file: if qi == 1 {
            "fig10_regression_median.svg".into()
        } else {
            format!("fig11_regression_q{pct}.svg")
        },
        chart: Chart {
            title: format!("η_c,{pct}: data, this study's regression and the paper's"),
            x_desc: "p (1/s)".into(),
            y_desc: eta_axis(d, &format!("η_c,{pct}")),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, 1.0)),
            x_ticks: None,
            lines,
        },
        caption: format!(
            "The {} fractile of η_c of the records (points) for three ε, this study's \
             law a(ε)·(1 − exp(−b(ε)·p))^c(ε) (lines){band_note} and the paper's Eq. {} (dashed) \
             (paper Fig. {}).",
            Q_NAMES[qi],
            PAPER_EQ[qi],
            if qi == 1 { 10 } else { 11 }
        ),
    })
}

/// Each coefficient against ε (step 1, this study's step 2, the paper's).
pub(super) fn regression_coefficients(d: &StudyData) -> Vec<Figure> {
    if !d.is_grid() {
        return Vec::new();
    }
    let (_, es) = d.ps_and_eps();
    let paper = fragility::paper();
    let e_dense: Vec<f64> = (0..=40)
        .map(|k| es[0] + (es[es.len() - 1] - es[0]) * k as f64 / 40.0)
        .collect();
    let mut out = Vec::new();
    for (ci, coef) in ["a", "b", "c"].iter().enumerate() {
        let poly = |l: &FractileLaw| -> Vec<f64> { [&l.a, &l.b, &l.c][ci].clone() };
        let mut lines = Vec::new();
        for (qi, &q) in Q_VALUES.iter().enumerate() {
            // Only the fits that converged, as step 2 takes them: a
            // diverged fit's a of 4e9 once flattened the others.
            let pts = d
                .fit_step1
                .iter()
                .filter(|r| r.quantile == q && r.converged)
                .map(|r| (r.eps, [r.a, r.b, r.c][ci].unwrap_or(f64::NAN)))
                .collect();
            lines.push(Line {
                name: Some(format!("{} step 1", Q_NAMES[qi])),
                points: pts,
                style: Style::Points,
                hue: Hue::Fractile(qi),
            });
            // A polynomial step 2 could not fit (too few converged fits) is not drawn.
            if let Some(c) = d
                .laws
                .iter()
                .find(|l| l.quantile == q)
                .map(poly)
                .filter(|c| !c.is_empty())
            {
                lines.push(Line {
                    name: Some(format!("{} fitted", Q_NAMES[qi])),
                    points: e_dense.iter().map(|&e| (e, polyval(&c, e))).collect(),
                    style: Style::Line,
                    hue: Hue::Fractile(qi),
                });
            }
            let c = poly(&paper[qi]);
            lines.push(Line {
                name: Some(format!("{} paper", Q_NAMES[qi])),
                points: e_dense.iter().map(|&e| (e, polyval(&c, e))).collect(),
                style: Style::Dashed,
                hue: Hue::Fractile(qi),
            });
        }
        let failed = d.fit_step1.iter().filter(|r| !r.converged).count();
        let left_out = match failed {
            0 => String::new(),
            n => format!(
                " The {n} step-1 fit{} that did not converge (`fit_step1.parquet`) {} not \
                 drawn, as step 2 leaves {} out.",
                if n == 1 { "" } else { "s" },
                if n == 1 { "is" } else { "are" },
                if n == 1 { "it" } else { "them" }
            ),
        };
        out.push(Figure {
            file: format!("regression_coefficient_{coef}.svg"),
            chart: Chart {
                title: format!("Regression coefficient {coef}(ε)"),
                x_desc: "ε".into(),
                y_desc: match *coef {
                    // b·p is dimensionless, p in 1/s.
                    "b" => "b (s)".to_string(),
                    c => format!("{c} (dimensionless)"),
                },
                x_scale: Scale::Linear,
                y_scale: Scale::Linear,
                x_range: None,
                y_range: None,
                x_ticks: None,
                lines,
            },
            caption: format!(
                "Step-1 values of {coef} per ε (points), this study's step-2 polynomial (lines) and the \
                 paper's (dashed), each fractile in its colour as in every figure.{left_out}"
            ),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{block_study, fractile, grid_study};
    use crate::fit::Stop;
    use crate::tables::fit::FitStep1Row;

    /// The median's law η_c = 0.5 (1 − e^{−p}) (a = 0.5, b = c = 1 at every ε).
    fn median_law() -> FractileLaw {
        FractileLaw {
            quantile: 0.5,
            a: vec![0.5],
            b: vec![1.0],
            c: vec![1.0],
        }
    }

    fn study() -> StudyData {
        let mut d = grid_study(&[1.0, 2.0], &[0.5, 0.9]);
        d.laws = vec![median_law()];
        d.capacity_fractiles = vec![fractile(1.0, 0.5, 0.5, 0.25), fractile(2.0, 0.5, 0.5, 0.5)];
        d.fit_step1 = vec![FitStep1Row {
            eps: 0.5,
            quantile: 0.5,
            a: Some(0.625),
            b: None,
            c: Some(1.5),
            rms: None,
            iterations: 3,
            stop: Stop::CostConverged,
            converged: true,
        }];
        d
    }

    #[test]
    fn a_fitted_fractile_is_drawn_against_its_data_and_the_papers_law() {
        // Only the median has a law: Fig. 10, no Fig. 11.
        let figs = regressions(&study());
        assert_eq!(figs.len(), 1);
        assert_eq!(figs[0].file, "fig10_regression_median.svg");
        let c = &figs[0].chart;
        assert_eq!(
            c.title,
            "η_c,50: data, this study's regression and the paper's"
        );
        assert_eq!((c.x_scale, c.y_range), (Scale::Log, Some((0.0, 1.0))));
        // Data, fit and paper for each of the two ε; no band without fit bands.
        assert_eq!(c.lines.len(), 6);
        assert!(c.lines.iter().all(|l| l.style != Style::Band));
        assert_eq!(c.lines[0].name.as_deref(), Some("data, ε = 0.50"));
        assert_eq!(c.lines[0].points, [(1.0, 0.25), (2.0, 0.5)]);
        let fit = &c.lines[1];
        assert_eq!(fit.name.as_deref(), Some("fit, ε = 0.50"));
        let (first, last) = (fit.points[0], fit.points[fit.points.len() - 1]);
        assert_eq!((first.0, last.0), (1.0, 2.0));
        assert!((first.1 - 0.5 * (1.0 - (-1.0f64).exp())).abs() < 1e-12);
        assert!((last.1 - 0.5 * (1.0 - (-2.0f64).exp())).abs() < 1e-12);
        assert_eq!(c.lines[2].name.as_deref(), Some("paper Eq. 10, ε = 0.50"));
        assert_eq!(c.lines[2].style, Style::Dashed);
    }

    #[test]
    fn no_regression_figure_without_a_complete_law_or_off_the_grid() {
        let mut d = study();
        d.laws[0].b.clear();
        assert!(regressions(&d).is_empty());
        d.laws.clear();
        assert!(regressions(&d).is_empty());
        let mut blocks = block_study();
        blocks.laws = vec![median_law()];
        assert!(regressions(&blocks).is_empty());
        assert!(regression_coefficients(&blocks).is_empty());
    }

    #[test]
    fn each_coefficient_is_drawn_from_step_1_step_2_and_the_paper() {
        let figs = regression_coefficients(&study());
        let files: Vec<_> = figs.iter().map(|f| f.file.as_str()).collect();
        assert_eq!(
            files,
            [
                "regression_coefficient_a.svg",
                "regression_coefficient_b.svg",
                "regression_coefficient_c.svg"
            ]
        );
        let a = &figs[0].chart;
        assert_eq!(
            (a.title.as_str(), a.y_desc.as_str()),
            ("Regression coefficient a(ε)", "a (dimensionless)")
        );
        assert_eq!(figs[1].chart.y_desc, "b (s)", "b·p is dimensionless");
        // Per fractile: step 1 and the paper's; the median has a step 2 too.
        assert_eq!(a.lines.len(), 7);
        let named = |n: &str| {
            a.lines
                .iter()
                .find(|l| l.name.as_deref() == Some(n))
                .unwrap()
        };
        assert_eq!(named("50 % step 1").points, [(0.5, 0.625)]);
        assert!(named("16 % step 1").points.is_empty());
        // Step 2 and the paper's along ε from 0.5 to 0.9 in 41 points.
        let fitted = named("50 % fitted");
        assert_eq!(fitted.points.len(), 41);
        assert!(fitted.points.iter().all(|p| p.1 == 0.5));
        assert!(fitted.points[0].0 == 0.5 && (fitted.points[40].0 - 0.9).abs() < 1e-12);
        // The paper's a of the median: 0.44 + 0.43ε.
        let paper = named("50 % paper");
        // The paper's curve dashed, in its fractile's colour, as this study's.
        assert_eq!((paper.style, paper.hue), (Style::Dashed, fitted.hue));
        assert_eq!(fitted.hue, crate::plot::Hue::Fractile(1));
        assert!((paper.points[0].1 - (0.44 + 0.43 * 0.5)).abs() < 1e-12);
        assert!((paper.points[40].1 - (0.44 + 0.43 * 0.9)).abs() < 1e-12);
        // Step 1 without b: not a number where b is drawn.
        let b = &figs[1].chart;
        let step1 = b
            .lines
            .iter()
            .find(|l| l.name.as_deref() == Some("50 % step 1"))
            .unwrap();
        assert!(step1.points[0].1.is_nan());
        assert!(!figs[0].caption.contains("did not converge"));
    }

    /// A band that leaves 0–1 (a resample's law below 0 at ε = 0.5, by
    /// hand) is said to be cut by the frame; one inside it is not.
    #[test]
    fn a_band_beyond_the_frame_is_said_to_be_cut() {
        use crate::study::FitBands;
        use crate::tables::fit::{BandCurve, FitBandRow};
        let with_band = |lo: f64, hi: f64| {
            let mut d = study();
            let row = |p| FitBandRow {
                curve: BandCurve::EtaC,
                quantile: Some(0.5),
                p,
                eps: 0.5,
                pga_g: None,
                value: Some(0.4),
                lo: Some(lo),
                hi: Some(hi),
                used: 10,
                level: 0.9,
                resamples: 10,
            };
            d.fit_bands = Some(FitBands {
                rows: vec![row(1.0), row(2.0)],
                step1_converged: (1, 1),
                laws_complete: (10, 10),
            });
            regressions(&d).remove(0).caption
        };
        let cut = with_band(-0.2, 0.6);
        assert!(
            cut.contains("cut by the frame") && cut.contains("more than 5 %"),
            "{cut}"
        );
        assert!(with_band(0.1, 1.3).contains("cut by the frame"));
        assert!(!with_band(0.1, 0.6).contains("cut by the frame"));
    }

    /// A step-1 fit that diverged (a = 4.2e9 in a one-record study) is
    /// not drawn among those that converged, and the caption says so.
    #[test]
    fn a_diverged_step_1_fit_is_left_out_and_said() {
        let mut d = study();
        d.fit_step1.push(FitStep1Row {
            eps: 0.9,
            a: Some(4.2e9),
            stop: Stop::Diverged,
            converged: false,
            ..d.fit_step1[0].clone()
        });
        let figs = regression_coefficients(&d);
        let step1 = figs[0]
            .chart
            .lines
            .iter()
            .find(|l| l.name.as_deref() == Some("50 % step 1"))
            .unwrap();
        assert_eq!(step1.points, [(0.5, 0.625)]);
        assert!(
            figs[0]
                .caption
                .contains("The 1 step-1 fit that did not converge"),
            "{}",
            figs[0].caption
        );
    }
}
