//! The regression figures: each fractile's fitted law against the data, the
//! fit's band and the paper's law (paper Figs. 10–11), and each coefficient
//! of the law against ε.

use super::bands::{band_eps, outline};
use super::figure::Figure;
use super::shared::{capacity_points, law_at, PAPER_EQ, Q_NAMES, Q_VALUES};
use crate::fit::polyval;
use crate::fragility::{self, FractileLaw};
use crate::plot::{Chart, Line, Scale, Style};
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
    for (k, (_, e)) in band_eps(&es).into_iter().enumerate() {
        if let Some(b) = bands {
            let rows: Vec<(f64, f64, f64)> = b
                .eta_c(q, e)
                .iter()
                .filter_map(|r| Some((r.p, r.lo?, r.hi?)))
                .collect();
            lines.push(Line {
                name: Some(format!("fit's band, ε = {e:.2}")),
                points: outline(&rows),
                style: Style::Band,
                color: k,
            });
        }
        lines.push(Line {
            name: Some(format!("data, ε = {e:.2}")),
            points: capacity_points(&d.capacity_fractiles, e, q, |r| Some(r.eta_c)),
            style: Style::Points,
            color: k,
        });
        lines.push(Line {
            name: Some(format!("fit, ε = {e:.2}")),
            points: p_dense.iter().map(|&p| (p, law_at(law, p, e))).collect(),
            style: Style::Line,
            color: k,
        });
        lines.push(Line {
            name: Some(format!("paper Eq. {}, ε = {e:.2}", PAPER_EQ[qi])),
            points: p_dense.iter().map(|&p| (p, law_at(paper, p, e))).collect(),
            style: Style::Dashed,
            color: k,
        });
    }
    let pct = (100.0 * q).round();
    let band_note = bands.map_or(String::new(), |b| {
        let first = b.rows.first();
        format!(
            ", its {:.0} % bootstrap band (shaded: {} of {} resamples refitted through both steps)",
            100.0 * first.map_or(0.9, |r| r.level),
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
            y_desc: format!("η_c,{pct}"),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, 1.0)),
            lines,
        },
        caption: format!(
            "The {} fractile of η_c of the records (points) for three ε, this study's \
             a(ε)(1 − e^{{−b(ε)p}})^{{c(ε)}} (lines){band_note} and the paper's Eq. {} (dashed) \
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
            let pts = d
                .fit_step1
                .iter()
                .filter(|r| r.quantile == q)
                .map(|r| (r.eps, [r.a, r.b, r.c][ci].unwrap_or(f64::NAN)))
                .collect();
            lines.push(Line {
                name: Some(format!("{} step 1", Q_NAMES[qi])),
                points: pts,
                style: Style::Points,
                color: qi,
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
                    color: qi,
                });
            }
            let c = poly(&paper[qi]);
            lines.push(Line {
                name: Some(format!("{} paper", Q_NAMES[qi])),
                points: e_dense.iter().map(|&e| (e, polyval(&c, e))).collect(),
                style: Style::Line,
                color: qi + 3,
            });
        }
        out.push(Figure {
            file: format!("regression_coefficient_{coef}.svg"),
            chart: Chart {
                title: format!("Regression coefficient {coef}(ε)"),
                x_desc: "ε".into(),
                y_desc: coef.to_string(),
                x_scale: Scale::Linear,
                y_scale: Scale::Linear,
                x_range: None,
                y_range: None,
                lines,
            },
            caption: format!(
                "Step-1 values of {coef} per ε (points), this study's step-2 polynomial (lines) and the paper's."
            ),
        });
    }
    out
}
