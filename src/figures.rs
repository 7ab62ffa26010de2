//! The study's figures, as chart specifications built from its results (pure).
//!
//! [`FIGURES`] lists one function per figure (or per family of figures),
//! in the order the report shows them. Each takes the loaded
//! [`StudyData`] and returns its figures, none when the study cannot have
//! them (a fit figure without a fit, say). Adding a figure is one function
//! here and one line in the list.
//!
//! Numbering follows the source paper: Fig. 5 (every record's IDA curve with
//! the 16/50/84 % fractiles), Fig. 6 (median IDA curves across p), Fig. 7
//! (horizontal against vertical capacity fractiles), Fig. 8 (capacity
//! curves), Fig. 9 (lognormal probability plots), Figs. 10–11 (the
//! regression against the data), then a fragility curve and the capacity
//! convergence study.

use crate::fit::{curve, polyval};
use crate::fragility::{self, FractileLaw};
use crate::ida::RunKind;
use crate::plot::{Chart, Line, Scale, Style};
use crate::stats;
use crate::study::{PulseData, StudyData};
use crate::tables::convergence::ConvergenceRow;
use crate::tables::reduce::{CapacityBandRow, CapacityFractileRow, HorizontalRow};

/// A figure: its file name (without folder), the chart, and a caption.
pub struct Figure {
    pub file: String,
    pub chart: Chart,
    pub caption: String,
}

/// A function drawing one figure or a family of figures.
pub type FigureFn = fn(&StudyData) -> Vec<Figure>;

/// Every figure, in report order.
pub const FIGURES: &[FigureFn] = &[
    ida_curves,
    median_ida_across_p,
    horizontal_vs_vertical,
    capacity_curves,
    capacity_bands,
    regressions,
    regression_coefficients,
    lognormal_plots,
    fragility_example,
    convergence_share,
    convergence_mean,
];

/// All figures of a study.
pub fn all(d: &StudyData) -> Vec<Figure> {
    FIGURES.iter().flat_map(|f| f(d)).collect()
}

/// The capacity-convergence table summed over blocks, one entry per grid resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvergenceLevel {
    pub levels: f64,
    /// (record, block) capacities that differ from the finest grid's, and of how many.
    pub changed: f64,
    pub total: f64,
    /// Mean over blocks of the mean |Δη_c|; largest |Δη_c| anywhere.
    pub mean_abs_change: f64,
    pub max_abs_change: f64,
    /// Mean over blocks of η_c,50.
    pub mean_q50: f64,
}

/// Summarises `capacity_convergence` rows per resolution, coarsest first.
pub fn convergence_levels(conv: &[ConvergenceRow]) -> Vec<ConvergenceLevel> {
    stats::distinct(conv.iter().map(|r| r.levels as f64).collect())
        .into_iter()
        .map(|l| {
            let rows: Vec<&ConvergenceRow> = conv.iter().filter(|r| r.levels as f64 == l).collect();
            let n = rows.len().max(1) as f64;
            let sum = |f: fn(&ConvergenceRow) -> f64| rows.iter().map(|r| f(r)).sum::<f64>();
            ConvergenceLevel {
                levels: l,
                changed: sum(|r| r.n_changed as f64),
                total: sum(|r| r.n_records as f64),
                mean_abs_change: sum(|r| r.mean_abs_change) / n,
                max_abs_change: rows.iter().map(|r| r.max_abs_change).fold(0.0, f64::max),
                mean_q50: sum(|r| r.eta_c_q50) / n,
            }
        })
        .collect()
}

/// The block drawn in the single-block figures: the middle p and ε of the grid.
fn middle(d: &StudyData) -> (usize, f64, f64) {
    let (ps, es) = d.ps_and_eps();
    let (p, e) = (ps[ps.len() / 2], es[es.len() / 2]);
    let blocks = &d.plan.blocks;
    let bi = blocks
        .iter()
        .position(|b| b.p == p && b.eps == e)
        .unwrap_or(0);
    (bi, blocks[bi].p, blocks[bi].eps)
}

const Q_NAMES: [&str; 3] = ["16 %", "50 %", "84 %"];
const Q_VALUES: [f64; 3] = [0.16, 0.5, 0.84];
/// The paper's equation of each fractile's law: Eq. 11 (16 %), Eq. 10
/// (median), Eq. 12 (84 %).
pub const PAPER_EQ: [usize; 3] = [11, 10, 12];

/// Horizontal fractile curve q (0, 1, 2) of a block as (EDP, 1/η), ending at
/// EDP = 1 where the fractile becomes +∞.
fn fractile_curve(rows: &[HorizontalRow], p: f64, e: f64, qi: usize) -> Vec<(f64, f64)> {
    let mut pts = vec![(0.0, 1.0)];
    for r in rows.iter().filter(|r| r.p == p && r.eps == e) {
        let edp = [r.edp_q16, r.edp_q50, r.edp_q84][qi];
        if edp.is_infinite() || edp >= 1.0 {
            pts.push((1.0, 1.0 / r.eta));
            break;
        }
        pts.push((edp, 1.0 / r.eta));
    }
    pts
}

/// (p, η_c) of one fractile at one ε, from capacity_fractiles.
fn capacity_points(
    rows: &[CapacityFractileRow],
    e: f64,
    q: f64,
    value: fn(&CapacityFractileRow) -> Option<f64>,
) -> Vec<(f64, f64)> {
    rows.iter()
        .filter(|r| r.eps == e && r.quantile == q)
        .map(|r| (r.p, value(r).unwrap_or(f64::NAN)))
        .collect()
}

/// Fig. 5: every record's IDA curve for one block, and the fractiles.
fn ida_curves(d: &StudyData) -> Vec<Figure> {
    // The pipeline's example block when it names one, else the grid's middle.
    let (p_mid, e_mid, caps, ida, horizontal, which) = match &d.example {
        Some(x) => (
            x.block.p,
            x.block.eps,
            x.caps.iter().collect::<Vec<_>>(),
            &x.ida,
            &x.horizontal,
            "the pipeline's example block (`[example]`)",
        ),
        None => {
            let n_blocks = d.plan.blocks.len();
            let (bi, p, e) = middle(d);
            let caps = d
                .caps
                .iter()
                .filter(|c| c.case_id as usize % n_blocks == bi)
                .collect();
            (p, e, caps, &d.ida, &d.horizontal, "the grid's middle block")
        }
    };
    let mut lines = Vec::new();
    let mut cap_max: f64 = 0.0;
    for c in &caps {
        let mut pts = vec![(0.0, 1.0)];
        for r in ida
            .iter()
            .filter(|r| r.case_id == c.case_id && r.run_kind == RunKind::Level)
        {
            if r.overturned {
                break;
            }
            pts.push((r.edp, r.pga_scale));
        }
        if let Some(ec) = c.eta_c {
            pts.push((1.0, 1.0 / ec));
        }
        lines.push(Line {
            name: None,
            points: pts,
            style: Style::Faint,
            color: 0,
        });
    }
    for (qi, q_name) in Q_NAMES.iter().enumerate() {
        let pts = fractile_curve(horizontal, p_mid, e_mid, qi);
        cap_max = cap_max.max(pts.last().map_or(0.0, |p| p.1));
        lines.push(Line {
            name: Some(format!("{q_name} fractile")),
            points: pts,
            style: Style::Line,
            color: qi + 1,
        });
    }
    vec![Figure {
        file: "fig05_ida_curves.svg".into(),
        chart: Chart {
            title: format!(
                "IDA curves of {} records, p = {p_mid:.3} 1/s, ε = {e_mid:.2}",
                caps.len()
            ),
            x_desc: "θmax / α".into(),
            y_desc: "A_g / (α g) = 1/η".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.0, 1.05)),
            y_range: Some((0.0, 1.4 * cap_max.max(1.0))),
            lines,
        },
        caption: format!(
            "Every record's IDA curve for {which} (grey: θmax/α against the intensity until the \
             first overturning, which is drawn at θmax/α = 1) and the 16/50/84 % horizontal \
             fractiles under the resurrection rule (paper Fig. 5)."
        ),
    }]
}

/// Fig. 6: median IDA curves across p.
fn median_ida_across_p(d: &StudyData) -> Vec<Figure> {
    if !d.is_grid() {
        return Vec::new();
    }
    let (ps, _) = d.ps_and_eps();
    let (_, _, e_mid) = middle(d);
    let lines = ps
        .iter()
        .enumerate()
        .map(|(k, &p)| Line {
            name: Some(format!("p = {p:.2} 1/s")),
            points: fractile_curve(&d.horizontal, p, e_mid, 1),
            style: Style::Line,
            color: k,
        })
        .collect();
    vec![Figure {
        file: "fig06_median_ida_across_p.svg".into(),
        chart: Chart {
            title: format!("Median IDA curves across p, ε = {e_mid:.2}"),
            x_desc: "θmax / α (50 % fractile)".into(),
            y_desc: "A_g / (α g) = 1/η".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Log,
            x_range: Some((0.0, 1.05)),
            y_range: None,
            lines,
        },
        caption: "The 50 % horizontal fractile IDA curve for each p at the middle ε (paper \
                  Fig. 6): smaller blocks (larger p) overturn at lower intensity."
            .into(),
    }]
}

/// Fig. 7: horizontal against vertical capacity fractiles.
fn horizontal_vs_vertical(d: &StudyData) -> Vec<Figure> {
    if !d.is_grid() {
        return Vec::new();
    }
    let (_, _, e_mid) = middle(d);
    let cf = &d.capacity_fractiles;
    let mut lines = Vec::new();
    for (qi, &q) in Q_VALUES.iter().enumerate() {
        lines.push(Line {
            name: Some(format!("{} vertical", Q_NAMES[qi])),
            points: capacity_points(cf, e_mid, q, |r| Some(r.eta_c)),
            style: Style::Line,
            color: qi,
        });
        lines.push(Line {
            name: Some(format!("{} horizontal", Q_NAMES[qi])),
            points: capacity_points(cf, e_mid, q, |r| r.eta_c_horizontal),
            style: Style::Points,
            color: qi,
        });
    }
    vec![Figure {
        file: "fig07_horizontal_vs_vertical.svg".into(),
        chart: Chart {
            title: format!("Capacity fractiles, horizontal against vertical, ε = {e_mid:.2}"),
            x_desc: "p (1/s)".into(),
            y_desc: "η_c".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            x_range: None,
            y_range: None,
            lines,
        },
        caption: "Capacity fractiles from the records' η_c (vertical statistics, lines) and from \
                  the horizontal EDP fractiles reaching overturning (points, at grid resolution) \
                  (paper Fig. 7): they coincide up to the grid step."
            .into(),
    }]
}

/// Fig. 8: capacity curves.
fn capacity_curves(d: &StudyData) -> Vec<Figure> {
    if !d.is_grid() {
        return Vec::new();
    }
    let (ps, es) = d.ps_and_eps();
    let mut lines: Vec<Line> = es
        .iter()
        .enumerate()
        .map(|(k, &e)| Line {
            name: Some(format!("ε = {e:.2}")),
            points: capacity_points(&d.capacity_fractiles, e, 0.5, |r| Some(r.eta_c)),
            style: Style::LinePoints,
            color: k,
        })
        .collect();
    // The paper draws the full-cycle rectangle's Mode 0 wall beside the
    // median (t_d = 1 s, so f = p): the shape its regression is built on.
    if !ps.is_empty() {
        lines.push(Line {
            name: Some("Eq. 6: (1 − exp(−p·1 s))²".into()),
            points: crate::fit::p_curve(&ps)
                .into_iter()
                .map(|p| (p, crate::pulse::full_cycle_eq6(p)))
                .collect(),
            style: Style::Dashed,
            color: 9,
        });
    }
    vec![Figure {
        file: "fig08_capacity_curves.svg".into(),
        chart: Chart {
            title: "Median capacity η_c,50 against p".into(),
            x_desc: "p (1/s)".into(),
            y_desc: "η_c,50".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, 1.0)),
            lines,
        },
        caption: "The median capacity against the block's frequency parameter, one curve per ε, \
                  with the full-cycle rectangular pulse's Mode 0 wall (Eq. 6, t_d = 1 s) dashed \
                  as the paper draws it (paper Fig. 8)."
            .into(),
    }]
}

/// A band's outline from (x, lo, hi) in x order: the lower edge left to
/// right, then the upper edge back ([`Style::Band`]).
fn outline(rows: &[(f64, f64, f64)]) -> Vec<(f64, f64)> {
    rows.iter()
        .map(|r| (r.0, r.1))
        .chain(rows.iter().rev().map(|r| (r.0, r.2)))
        .collect()
}

/// The ε values a banded figure draws: the grid's first, middle and last.
fn band_eps(es: &[f64]) -> Vec<(usize, f64)> {
    let mut picks = vec![0, es.len() / 2, es.len() - 1];
    picks.dedup();
    picks.into_iter().map(|i| (i, es[i])).collect()
}

/// Fig. 8 per fractile with its bootstrap band and the paper's law.
fn capacity_bands(d: &StudyData) -> Vec<Figure> {
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

/// The fractile's law evaluated at (p, ε).
fn law_at(law: &FractileLaw, p: f64, e: f64) -> f64 {
    curve(
        polyval(&law.a, e),
        polyval(&law.b, e),
        polyval(&law.c, e),
        p,
    )
}

/// Fig. 10 (median) and Fig. 11 (16 % and 84 %): a fractile's regression
/// against the data, with the fit's bootstrap band and the paper's law.
fn regressions(d: &StudyData) -> Vec<Figure> {
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
fn regression_coefficients(d: &StudyData) -> Vec<Figure> {
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

/// Fig. 9: lognormal probability plots, the worst and the best fitting block.
fn lognormal_plots(d: &StudyData) -> Vec<Figure> {
    let n_blocks = d.plan.blocks.len();
    let mut ranked: Vec<_> = d
        .lognormal
        .iter()
        .filter(|r| r.p_value.is_some_and(f64::is_finite))
        .collect();
    ranked.sort_by(|a, b| {
        let pv = |r: &&crate::tables::reduce::LognormalRow| r.p_value.unwrap_or(f64::NAN);
        pv(a).total_cmp(&pv(b))
    });
    let mut out = Vec::new();
    for (tag, row) in [("poor", ranked.first()), ("good", ranked.last())] {
        let Some(row) = row else { continue };
        let (p, e) = (row.p, row.eps);
        let k = d
            .plan
            .blocks
            .iter()
            .position(|b| b.p == p && b.eps == e)
            .unwrap_or(0);
        let mut logs: Vec<f64> = d
            .caps
            .iter()
            .filter(|c| c.case_id as usize % n_blocks == k)
            .filter_map(|c| c.eta_c)
            .map(f64::ln)
            .collect();
        logs.sort_by(|a, b| a.total_cmp(b));
        if logs.len() < 3 {
            continue;
        }
        let n = logs.len() as f64;
        let pts: Vec<(f64, f64)> = logs
            .iter()
            .enumerate()
            .map(|(i, &x)| (x, stats::normal_quantile((i as f64 + 0.5) / n)))
            .collect();
        let (mean, sd) = stats::mean_sd(&logs);
        let (lo, hi) = (logs[0], logs[logs.len() - 1]);
        let fitted = vec![(lo, (lo - mean) / sd), (hi, (hi - mean) / sd)];
        out.push(Figure {
            file: format!("fig09_lognormal_{tag}.svg"),
            chart: Chart {
                title: format!(
                    "Normal probability plot of ln η_c, p = {p:.3} 1/s, ε = {e:.2} (Lilliefors p = {:.3})",
                    row.p_value.unwrap_or(f64::NAN)
                ),
                x_desc: "ln η_c".into(),
                y_desc: "standard normal quantile".into(),
                x_scale: Scale::Linear,
                y_scale: Scale::Linear,
                x_range: None,
                y_range: None,
                lines: vec![
                    Line {
                        name: Some("records".into()),
                        points: pts,
                        style: Style::Points,
                        color: 0,
                    },
                    Line {
                        name: Some("lognormal fit".into()),
                        points: fitted,
                        style: Style::Line,
                        color: 1,
                    },
                ],
            },
            caption: format!(
                "The {} fitting block by the Lilliefors test: ln η_c of every record against normal quantiles (paper Fig. 9).",
                if tag == "good" { "best" } else { "worst" }
            ),
        });
    }
    out
}

/// The fragility of an example block, from this study's fit and the paper's.
fn fragility_example(d: &StudyData) -> Vec<Figure> {
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

/// Share of capacities that move against the finest grid, per resolution.
fn convergence_share(d: &StudyData) -> Vec<Figure> {
    let Some(conv) = &d.convergence else {
        return Vec::new();
    };
    let share: Vec<(f64, f64)> = convergence_levels(conv)
        .iter()
        .map(|c| (c.levels, c.changed / c.total.max(1.0)))
        .collect();
    let top = share.iter().map(|s| s.1).fold(0.05, f64::max) * 1.2;
    vec![Figure {
        file: "capacity_convergence.svg".into(),
        chart: Chart {
            title: "Capacity against IM-grid resolution".into(),
            x_desc: "levels in the IM grid".into(),
            y_desc: "share of (record, block) capacities that differ from the finest grid's".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, top)),
            lines: vec![Line {
                name: Some("share changed".into()),
                points: share,
                style: Style::LinePoints,
                color: 0,
            }],
        },
        caption: "How many records' capacities move (by more than twice the refinement \
                  tolerance) against the finest grid, as the grid is refined."
            .into(),
    }]
}

/// Mean |Δη_c| against the finest grid, per resolution.
fn convergence_mean(d: &StudyData) -> Vec<Figure> {
    let Some(conv) = &d.convergence else {
        return Vec::new();
    };
    let mean: Vec<(f64, f64)> = convergence_levels(conv)
        .iter()
        .map(|c| (c.levels, c.mean_abs_change))
        .collect();
    vec![Figure {
        file: "capacity_convergence_mean.svg".into(),
        chart: Chart {
            title: "Mean |Δη_c| against the finest grid".into(),
            x_desc: "levels in the IM grid".into(),
            y_desc: "mean |η_c − η_c(finest)|".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: None,
            lines: vec![Line {
                name: Some("mean over records and blocks".into()),
                points: mean,
                style: Style::LinePoints,
                color: 1,
            }],
        },
        caption: "Mean absolute change of η_c against the finest grid.".into(),
    }]
}

/// A function drawing one figure or a family of figures of a pulse map.
pub type PulseFigureFn = fn(&PulseData) -> Vec<Figure>;

/// Every figure of a pulse map (`[pulses]` pipelines), in report order:
/// the paper's Fig. 2 (waveforms), Fig. 3 (walls: safe above, overturning
/// below) and Fig. 4 (the areas of each mode).
pub const PULSE_FIGURES: &[PulseFigureFn] = &[pulse_waveforms, pulse_walls, pulse_modes];

/// All figures of a pulse map.
pub fn all_pulse(d: &PulseData) -> Vec<Figure> {
    PULSE_FIGURES.iter().flat_map(|f| f(d)).collect()
}

/// Fig. 2: ψ̈ against t/t_d for each of the map's pulse shapes.
fn pulse_waveforms(d: &PulseData) -> Vec<Figure> {
    let Some(pp) = &d.plan.pulses else {
        return Vec::new();
    };
    let lobes = pp.cycle.lobes();
    let lines = pp
        .shapes
        .iter()
        .enumerate()
        .map(|(k, shape)| {
            let mut pts = vec![(0.0, 0.0)];
            for (l, sign) in [1.0, -1.0].into_iter().take(lobes).enumerate() {
                for i in 0..=400 {
                    let u = i as f64 / 400.0;
                    pts.push((l as f64 + u, sign * shape.lobe(u)));
                }
            }
            pts.push((lobes as f64, 0.0));
            Line {
                name: Some(match shape.beta() {
                    Some(b) => format!("β = {b}"),
                    None => "rectangle".into(),
                }),
                points: pts,
                style: Style::Line,
                color: k,
            }
        })
        .collect();
    vec![Figure {
        file: "fig02_pulse_waveforms.svg".into(),
        chart: Chart {
            title: format!("Pulse waveforms ({} cycle)", pp.cycle.name()),
            x_desc: "t / t_d".into(),
            y_desc: "ψ̈ = ü_g / A_p".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.0, lobes as f64)),
            y_range: Some(if lobes == 1 { (0.0, 1.1) } else { (-1.1, 1.1) }),
            lines,
        },
        caption: "The pulse shapes of this map: the paper's exponential pulse (Eq. 4) for each β \
                  (β → −∞ the rectangle, β = 0 the triangle, β → +∞ a spike), one lobe of \
                  duration t_d, or the lobe followed by its negative (paper Fig. 2)."
            .into(),
    }]
}

/// The walls of one family along f: (f, η_w) and (f, closed form).
fn family_walls(
    d: &PulseData,
    beta: Option<f64>,
    eps: f64,
    pick: impl Fn(&crate::tables::pulse::PulseWallRow) -> Option<f64>,
) -> Vec<(f64, f64)> {
    d.walls_of(beta, eps)
        .filter_map(|w| pick(w).map(|e| (w.f, e)))
        .collect()
}

/// Fig. 3: each family's wall η_w against f, with the paper's closed form.
fn pulse_walls(d: &PulseData) -> Vec<Figure> {
    let mut lines = Vec::new();
    for (k, (beta, eps, label)) in d.families().into_iter().enumerate() {
        lines.push(Line {
            name: Some(format!("{label}: η_w by simulation")),
            points: family_walls(d, beta, eps, |w| w.eta_w),
            style: Style::Line,
            color: k,
        });
        let closed = family_walls(d, beta, eps, |w| {
            w.closed_form
                .filter(|_| w.closed_form_kind() == Some(crate::pulse::WallKind::Any))
        });
        if !closed.is_empty() {
            let eq = d
                .walls
                .iter()
                .find_map(|w| w.closed_form_equation.clone())
                .unwrap_or_default();
            lines.push(Line {
                name: Some(format!("{label}: {eq}")),
                points: closed,
                style: Style::Dashed,
                color: k,
            });
        }
    }
    if lines.iter().all(|l| l.points.is_empty()) {
        return Vec::new();
    }
    let criterion = d
        .walls
        .first()
        .map_or(String::new(), |w| w.overturn.clone());
    vec![Figure {
        file: "fig03_pulse_walls.svg".into(),
        chart: Chart {
            title: format!("Safety walls (criterion {criterion})"),
            x_desc: "f = p t_d".into(),
            y_desc: "η = α g / A_p".into(),
            x_scale: Scale::Log,
            y_scale: Scale::Linear,
            x_range: None,
            y_range: Some((0.0, 1.0)),
            lines,
        },
        caption: "The largest η at which the block overturns (its safety wall η_w) against f, one \
                  curve per family: the block is safe above its curve and overturns just below it; \
                  the paper's closed form dashed where one applies (Eq. 3 the rectangle, Eq. 5 the \
                  exponential half cycle; paper Fig. 3)."
            .into(),
    }]
}

/// Fig. 4: per family, the map's points by outcome (safe, Mode 0, Mode 1,
/// Mode 2 or more), with the Mode 0 wall and Eq. 6 where it applies.
fn pulse_modes(d: &PulseData) -> Vec<Figure> {
    let mut figs = Vec::new();
    for (beta, eps, label) in d.families() {
        let cells: Vec<_> = d.cells_of(beta, eps).collect();
        if cells.is_empty() {
            continue;
        }
        let class = |name: &str, color: usize, keep: &dyn Fn(bool, i64) -> bool| Line {
            name: Some(name.into()),
            points: cells
                .iter()
                .filter(|c| keep(c.overturned, c.impacts))
                .map(|c| (c.f, c.eta))
                .collect(),
            style: Style::Points,
            color,
        };
        let mut lines = vec![
            class("Mode 0 (no impact)", 1, &|o, i| o && i == 0),
            class("Mode 1 (one impact)", 2, &|o, i| o && i == 1),
            class("Mode 2 or more", 4, &|o, i| o && i >= 2),
        ];
        lines.retain(|l| !l.points.is_empty());
        lines.push(Line {
            name: Some("η_w,0 by simulation".into()),
            points: family_walls(d, beta, eps, |w| w.eta_w_mode0),
            style: Style::Line,
            color: 0,
        });
        let eq6 = family_walls(d, beta, eps, |w| {
            w.closed_form
                .filter(|_| w.closed_form_of.as_deref() == Some("eta_w_mode0"))
        });
        if !eq6.is_empty() {
            lines.push(Line {
                name: Some("Eq. 6: (1 − exp(−f))²".into()),
                points: eq6,
                style: Style::Dashed,
                color: 3,
            });
        }
        let slug = match beta {
            Some(b)
                if d.families().len() > d.plan.pulses.as_ref().map_or(1, |p| p.shapes.len()) =>
            {
                format!("beta{b}_eps{eps:.2}")
            }
            Some(b) => format!("beta{b}"),
            None => format!("eps{eps:.2}"),
        };
        let eta_min = cells.iter().map(|c| c.eta).fold(f64::INFINITY, f64::min);
        figs.push(Figure {
            file: format!("fig04_modes_{slug}.svg"),
            chart: Chart {
                title: format!("Overturning modes, {label}"),
                x_desc: "f = p t_d".into(),
                y_desc: "η = α g / A_p".into(),
                x_scale: Scale::Log,
                y_scale: Scale::Log,
                x_range: None,
                y_range: Some((eta_min * 0.9, 1.0)),
                lines,
            },
            caption: format!(
                "Each point of the map where the block overturns, by the impacts before it does \
                 (Mode 0: forward, no impact; Mode 1: after one impact and reversal), for {label}; \
                 unmarked points are safe. The line is the Mode 0 wall found by simulation, \
                 Eq. 6 dashed where it applies (paper Fig. 4)."
            ),
        });
    }
    figs
}
