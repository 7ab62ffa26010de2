//! The lognormality figures: normal probability plots of ln η_c for the
//! worst and the best fitting block by the Lilliefors test (paper Fig. 9).

use super::figure::Figure;
use crate::plot::{Chart, Line, Scale, Style};
use crate::stats;
use crate::study::StudyData;

/// Fig. 9: lognormal probability plots, the worst and the best fitting block.
pub(super) fn lognormal_plots(d: &StudyData) -> Vec<Figure> {
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
