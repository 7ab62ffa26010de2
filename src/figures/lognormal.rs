//! The lognormality figures: normal probability plots of ln η_c for the
//! worst and the best fitting block by the Lilliefors test (paper Fig. 9).

use super::figure::Figure;
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::stats;
use crate::study::StudyData;

/// Fig. 9: lognormal probability plots, the worst and the best fitting block.
pub(super) fn lognormal_plots(d: &StudyData) -> Vec<Figure> {
    let n_blocks = d.records_plan().blocks.len();
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
    // One block tested: one figure (the best and the worst were the same
    // figure twice).
    let best = if ranked.len() > 1 {
        ranked.last()
    } else {
        None
    };
    for (tag, row) in [("poor", ranked.first()), ("good", best)] {
        let Some(row) = row else { continue };
        let (p, e) = (row.p, row.eps);
        let k = d
            .records_plan()
            .blocks
            .iter()
            .position(|b| b.p == p && b.eps == e)
            .unwrap_or(0);
        let of_block = || d.caps.iter().filter(|c| c.case_id as usize % n_blocks == k);
        let mut logs: Vec<f64> = of_block().filter_map(|c| c.eta_c).map(f64::ln).collect();
        let records = of_block().count();
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
                    "Normal probability plot of ln η_c, p = {p:.3} 1/s, ε = {e:.2} (Lilliefors {})",
                    p_value_text(row.p_value.unwrap_or(f64::NAN))
                ),
                x_desc: "ln η_c".into(),
                y_desc: "standard normal quantile".into(),
                x_scale: Scale::Linear,
                y_scale: Scale::Linear,
                x_range: None,
                y_range: None,
                x_ticks: None,
                lines: vec![
                    Line {
                        name: Some("records".into()),
                        points: pts,
                        style: Style::Points,
                        hue: Hue::Series(0),
                    },
                    Line {
                        name: Some("lognormal fit".into()),
                        points: fitted,
                        style: Style::Line,
                        hue: Hue::Ink,
                    },
                ],
            },
            caption: caption(tag, best.is_some(), logs.len(), records, row.p_value),
        });
    }
    out
}

/// Fig. 9's caption: which block, and of how many of its records (a sample
/// cut where some never overturned); the best of blocks that all fail the
/// test is said to fail it too.
fn caption(tag: &str, two: bool, plotted: usize, records: usize, p_value: Option<f64>) -> String {
    let which = match (tag, two) {
        ("good", _) => "The best fitting block by the Lilliefors test",
        (_, true) => "The worst fitting block by the Lilliefors test",
        _ => "The one block the Lilliefors test was run on",
    };
    let sample = if plotted == records {
        "every record".to_string()
    } else {
        format!(
            "the {plotted} of its {records} records that overturned (the others never did \
             down to the grid's last level: the sample is cut there, and the test sees the cut)"
        )
    };
    let fails = match (tag, p_value) {
        ("good", Some(pv)) if pv < 0.05 => {
            " Lognormality is rejected at 5 % for this block too: no block passes."
        }
        _ => "",
    };
    format!("{which}: ln η_c of {sample} against normal quantiles (paper Fig. 9).{fails}")
}

/// A Lilliefors p-value as a title shows it: three decimals, or "p < 0.001"
/// (a p of 4e-5 read "p = 0.000").
fn p_value_text(p: f64) -> String {
    if p < 0.001 {
        "p < 0.001".into()
    } else {
        format!("p = {p:.3}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{cap, grid_study, lognormal};

    /// Two blocks, (1, 0.5) and (2, 0.5), with Lilliefors p-values 0.01
    /// (the worst) and 0.6 (the best); the worst has three capacities
    /// (cases 0, 2, 4), the best only two (cases 1, 3).
    fn study() -> StudyData {
        let mut d = grid_study(&[1.0, 2.0], &[0.5]);
        d.lognormal = vec![
            lognormal(1.0, 0.5, Some(0.01)),
            lognormal(2.0, 0.5, Some(0.6)),
            lognormal(2.0, 0.5, None),
        ];
        d.caps = vec![
            cap(0, Some(0.5)),
            cap(1, Some(0.5)),
            cap(2, Some(0.25)),
            cap(3, Some(0.5)),
            cap(4, Some(1.0)),
            cap(5, None),
        ];
        d
    }

    #[test]
    fn the_worst_block_is_plotted_and_a_block_of_two_records_is_not() {
        let figs = lognormal_plots(&study());
        assert_eq!(figs.len(), 1);
        assert_eq!(figs[0].file, "fig09_lognormal_poor.svg");
        let c = &figs[0].chart;
        assert_eq!(
            c.title,
            "Normal probability plot of ln η_c, p = 1.000 1/s, ε = 0.50 (Lilliefors p = 0.010)"
        );
        // ln η_c sorted: ln ¼, ln ½, 0, at the normal quantiles of 1/6, 1/2, 5/6.
        let ln2 = 2f64.ln();
        let z = 0.967_421_566_101_701; // Φ⁻¹(5/6)
        let pts = &c.lines[0].points;
        assert_eq!(pts.len(), 3);
        for ((x, y), (hx, hy)) in pts.iter().zip([(-2.0 * ln2, -z), (-ln2, 0.0), (0.0, z)]) {
            assert!((x - hx).abs() < 1e-15 && (y - hy).abs() < 1e-9, "{x}, {y}");
        }
        // The fitted normal: mean −ln 2, sample sd ln 2, so the ends at ∓1.
        let fit = &c.lines[1].points;
        assert!((fit[0].0 + 2.0 * ln2).abs() < 1e-15 && (fit[0].1 + 1.0).abs() < 1e-12);
        assert!(fit[1].0 == 0.0 && (fit[1].1 - 1.0).abs() < 1e-12);
    }

    /// One block tested: one figure, not the same one twice as the best and
    /// the worst; a record that never overturned is not among its points,
    /// and the caption says how many are (3 of 4, by hand).
    #[test]
    fn one_block_is_one_figure_and_its_cut_sample_is_said() {
        let mut d = grid_study(&[1.0], &[0.5]);
        d.lognormal = vec![lognormal(1.0, 0.5, Some(4e-5))];
        d.caps = vec![
            cap(0, Some(0.5)),
            cap(1, Some(0.25)),
            cap(2, None),
            cap(3, Some(1.0)),
        ];
        let figs = lognormal_plots(&d);
        assert_eq!(figs.len(), 1);
        assert_eq!(figs[0].chart.lines[0].points.len(), 3);
        assert!(figs[0].chart.title.ends_with("(Lilliefors p < 0.001)"));
        let caption = &figs[0].caption;
        assert!(
            caption.starts_with("The one block the Lilliefors test"),
            "{caption}"
        );
        assert!(
            caption.contains("the 3 of its 4 records that overturned"),
            "{caption}"
        );
    }

    /// The best of two blocks that both fail the test (p 0.01 and 0.02)
    /// is said to fail it too: "best fitting" read as a pass.
    #[test]
    fn the_best_block_that_fails_too_is_said_to() {
        let mut d = study();
        d.lognormal[1] = lognormal(2.0, 0.5, Some(0.02));
        d.caps[5] = cap(5, Some(0.3));
        let figs = lognormal_plots(&d);
        assert_eq!(figs.len(), 2);
        assert!(
            figs[1]
                .caption
                .contains("rejected at 5 % for this block too"),
            "{}",
            figs[1].caption
        );
        assert!(!figs[0].caption.contains("rejected"));
        // Passing (p 0.6): nothing said.
        let mut d = study();
        d.caps[5] = cap(5, Some(0.3));
        assert!(!lognormal_plots(&d)[1].caption.contains("rejected"));
    }

    #[test]
    fn nothing_without_tested_blocks() {
        let mut d = study();
        d.lognormal.clear();
        assert!(lognormal_plots(&d).is_empty());
    }
}
