//! Report stage: the figures (SVG) and `report.md` of a pipeline's run.

use std::fmt::Write as _;
use std::path::Path;

use crate::figures::{convergence_levels, figures, StudyData};
use crate::fragility::{self, FractileLaw};
use crate::pipeline::Plan;
use crate::plot;
use crate::stages::fit;
use crate::stages::run::{sweep_tables, Stage};
use crate::stats::distinct;
use crate::tables::atomic_write;
use crate::tables::summary::{
    Flat, Value, CAPACITY_FRACTILES, CONVERGENCE, FIT_STEP1, HORIZONTAL, LOGNORMAL,
};

fn get(t: &Flat, row: &[Value], col: &str) -> f64 {
    t.get(row, col)
}

/// Writes `dir/figures/*.svg` and `dir/report.md`.
pub fn write(
    plan: &Plan,
    pipeline: &Path,
    dir: &Path,
    times: &[(Stage, Option<f64>)],
) -> Result<(), String> {
    let read = |t: &Flat, name: &str| t.read(&dir.join(name)).map_err(|e| e.to_string());
    let (caps, ida) = sweep_tables(dir)?;
    let horizontal = read(&HORIZONTAL, "fractiles_horizontal.parquet")?;
    let cap_fr = read(&CAPACITY_FRACTILES, "capacity_fractiles.parquet")?;
    let lognormal = read(&LOGNORMAL, "lognormal.parquet")?;
    // Fit tables left from an earlier grid are not this study's.
    let has_fit =
        fit::not_applicable(plan).is_none() && fit::outputs(dir).iter().all(|p| p.exists());
    let step1 = if has_fit {
        read(&FIT_STEP1, "fit_step1.parquet")?
    } else {
        Vec::new()
    };
    let laws: Vec<FractileLaw> = if has_fit {
        fit::read_laws(dir).map_err(|e| e.to_string())?
    } else {
        Vec::new()
    };
    let convergence = if plan.convergence.is_empty() {
        None
    } else {
        Some(read(&CONVERGENCE, "capacity_convergence.parquet")?)
    };
    let data = StudyData {
        plan,
        caps: &caps,
        ida: &ida,
        horizontal: &horizontal,
        capacity_fractiles: &cap_fr,
        lognormal: &lognormal,
        fit_step1: &step1,
        laws: &laws,
        convergence: convergence.as_deref(),
    };
    let figs = figures(&data);
    let fig_dir = dir.join("figures");
    for f in &figs {
        let svg = plot::render(&f.chart).map_err(|e| format!("{}: {e}", f.file))?;
        atomic_write(&fig_dir.join(&f.file), svg.as_bytes()).map_err(|e| e.to_string())?;
    }

    let mut md = String::new();
    let w = &mut md;
    let _ = writeln!(w, "# Study `{}`\n", plan.name);
    if !plan.description.is_empty() {
        let _ = writeln!(w, "{}\n", plan.description);
    }
    let _ = writeln!(
        w,
        "Pipeline `{}`, rocking {}. Tables beside this report; columns are documented in the rocking README.\n",
        pipeline.display(),
        env!("CARGO_PKG_VERSION")
    );

    // Settings.
    let n_blocks = plan.blocks.len();
    let n_records = caps.len() / n_blocks.max(1);
    let ps = distinct(plan.blocks.iter().map(|b| b.p).collect());
    let es = distinct(plan.blocks.iter().map(|b| b.eps).collect());
    let fmt_list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(w, "## Settings\n");
    let _ = writeln!(w, "| setting | value |\n|---|---|");
    let _ = writeln!(
        w,
        "| records | {n_records}{} |",
        if plan.sets.is_empty() {
            String::new()
        } else {
            format!(" ({})", plan.sets.join(", "))
        }
    );
    let _ = writeln!(
        w,
        "| model | {:?}, overturning {} |",
        plan.model, plan.overturn
    );
    let _ = writeln!(
        w,
        "| blocks | {n_blocks}: p = {} 1/s; ε = {} |",
        fmt_list(&ps),
        fmt_list(&es)
    );
    let _ = writeln!(
        w,
        "| IM grid | {} {:?}-spaced levels of η from {} down to {}, capacity refined to Δη = {} |",
        plan.grid.count, plan.grid.spacing, plan.grid.eta_max, plan.grid.eta_min, plan.tol
    );
    let _ = writeln!(w, "| fractiles | Hyndman–Fan {:?} |\n", plan.fractile);

    // Runtime and counts.
    let _ = writeln!(w, "## Runtime and counts\n");
    let _ = writeln!(w, "| stage | time (s) |\n|---|---:|");
    for (s, t) in times {
        if let Some(t) = t {
            let _ = writeln!(w, "| {} | {t:.2} |", s.name());
        }
    }
    let overturned = ida.iter().filter(|r| r.overturned).count();
    let _ = writeln!(
        w,
        "\n{} capacities from {} simulations ({} of them overturned); {} of the record × block cases never overturned down to η = {}.\n",
        caps.len(),
        ida.len(),
        overturned,
        caps.iter().filter(|c| c.eta_c.is_none()).count(),
        plan.grid.eta_min
    );

    // Capacity fractiles.
    let grid_blocks = plan.blocks.iter().all(|b| b.name.is_empty());
    let _ = writeln!(w, "## Capacity fractiles\n");
    if grid_blocks {
        for (q, label) in [(0.5, "median η_c,50"), (0.16, "η_c,16"), (0.84, "η_c,84")] {
            let _ = writeln!(w, "{label}, rows p (1/s), columns ε:\n");
            let _ = writeln!(
                w,
                "| p \\ ε | {} |",
                es.iter()
                    .map(|e| format!("{e:.2}"))
                    .collect::<Vec<_>>()
                    .join(" | ")
            );
            let _ = writeln!(w, "|---:|{}", "---:|".repeat(es.len()));
            for &p in &ps {
                let cells: Vec<String> = es
                    .iter()
                    .map(|&e| {
                        cap_fr
                            .iter()
                            .find(|r| {
                                get(&CAPACITY_FRACTILES, r, "p") == p
                                    && get(&CAPACITY_FRACTILES, r, "eps") == e
                                    && get(&CAPACITY_FRACTILES, r, "quantile") == q
                            })
                            .map_or("".into(), |r| {
                                format!("{:.4}", get(&CAPACITY_FRACTILES, r, "eta_c"))
                            })
                    })
                    .collect();
                let _ = writeln!(w, "| {p:.3} | {} |", cells.join(" | "));
            }
            let _ = writeln!(w);
        }
        // Against the paper's Eq. 10.
        let law = &fragility::paper()[1];
        let ratios: Vec<f64> = cap_fr
            .iter()
            .filter(|r| {
                get(&CAPACITY_FRACTILES, r, "quantile") == 0.5
                    && get(&CAPACITY_FRACTILES, r, "p") >= 0.5
            })
            .map(|r| {
                let (p, e) = (
                    get(&CAPACITY_FRACTILES, r, "p"),
                    get(&CAPACITY_FRACTILES, r, "eps"),
                );
                (get(&CAPACITY_FRACTILES, r, "eta_c") / law.eta_c(p, e) - 1.0).abs()
            })
            .collect();
        if !ratios.is_empty() {
            let _ = writeln!(
                w,
                "Against the paper's Eq. 10: mean |η_c,50 / Eq. 10 − 1| = {:.1} % over the {} blocks with p ≥ 0.5 1/s.\n",
                100.0 * ratios.iter().sum::<f64>() / ratios.len() as f64,
                ratios.len()
            );
        }
    } else {
        let _ = writeln!(
            w,
            "| block | p | ε | η_c,16 | η_c,50 | η_c,84 |\n|---|---:|---:|---:|---:|---:|"
        );
        for b in &plan.blocks {
            let at = |q: f64| {
                cap_fr
                    .iter()
                    .find(|r| {
                        r[CAPACITY_FRACTILES.col("block")].s() == b.name
                            && get(&CAPACITY_FRACTILES, r, "quantile") == q
                    })
                    .map_or(f64::NAN, |r| get(&CAPACITY_FRACTILES, r, "eta_c"))
            };
            let _ = writeln!(
                w,
                "| {} | {:.3} | {:.3} | {:.4} | {:.4} | {:.4} |",
                b.name,
                b.p,
                b.eps,
                at(0.16),
                at(0.5),
                at(0.84)
            );
        }
        let _ = writeln!(w);
    }

    // Lognormality.
    let tested = lognormal
        .iter()
        .filter(|r| get(&LOGNORMAL, r, "p_value").is_finite())
        .count();
    let kept = lognormal
        .iter()
        .filter(|r| {
            get(&LOGNORMAL, r, "p_value").is_finite()
                && !matches!(r[LOGNORMAL.col("rejected_5pct")], Value::B(true))
        })
        .count();
    let _ = writeln!(w, "## Lognormality of η_c\n");
    let _ = writeln!(
        w,
        "The Lilliefors test does not reject lognormality at 5 % in **{kept} of {tested}** blocks ({:.0} %; the paper found about 80 %). p-values: Dallal–Wilkinson (1986), Stephens (1974) above 0.1, as R's `nortest`.\n",
        100.0 * kept as f64 / tested.max(1) as f64
    );

    // Fit.
    if !laws.is_empty() {
        let conv = step1
            .iter()
            .filter(|r| matches!(r[FIT_STEP1.col("converged")], Value::B(true)))
            .count();
        let _ = writeln!(w, "## Regression η_c = a(1 − e^(−bp))^c\n");
        let _ = writeln!(
            w,
            "Step 1 converged in {conv} of {} (ε, fractile) fits. Step 2, against the paper:\n",
            step1.len()
        );
        let _ = writeln!(w, "| fractile | | a = c0 + c1 ε | b = c0 + c1 ε + c2 ε² | c = c0 + c1 ε + c2 ε² |\n|---|---|---|---|---|");
        let fmt = |c: &[f64]| {
            c.iter()
                .map(|v| format!("{v:+.3}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        for (law, paper) in laws.iter().zip(fragility::paper().iter()) {
            let _ = writeln!(
                w,
                "| {:.0} % | fitted | {} | {} | {} |",
                100.0 * law.quantile,
                fmt(&law.a),
                fmt(&law.b),
                fmt(&law.c)
            );
            let _ = writeln!(
                w,
                "| | paper | {} | {} | {} |",
                fmt(&paper.a),
                fmt(&paper.b),
                fmt(&paper.c)
            );
        }
        let _ = writeln!(w);
    }

    // Convergence.
    if let Some(conv) = &convergence {
        let _ = writeln!(w, "## Capacity against IM-grid resolution\n");
        let summary = convergence_levels(conv);
        let levels: Vec<f64> = summary.iter().map(|c| c.levels).collect();
        let finest = levels.last().copied().unwrap_or(0.0);
        let _ = writeln!(
            w,
            "The capacity search repeated with {} levels; each record's η_c compared with the {finest}-level grid's.\n",
            levels.iter().map(|l| format!("{l}")).collect::<Vec<_>>().join(", ")
        );
        let _ = writeln!(w, "| levels | capacities that differ | mean abs. change | largest change | mean η_c,50 |\n|---:|---:|---:|---:|---:|");
        for c in &summary {
            let _ = writeln!(
                w,
                "| {} | {} of {} ({:.1} %) | {:.2e} | {:.3} | {:.4} |",
                c.levels,
                c.changed,
                c.total,
                100.0 * c.changed / c.total.max(1.0),
                c.mean_abs_change,
                c.max_abs_change,
                c.mean_q50
            );
        }
        let mean_q50 = |l: f64| {
            summary
                .iter()
                .find(|c| c.levels == l)
                .map_or(f64::NAN, |c| c.mean_q50)
        };
        let coarsest = levels.first().copied().unwrap_or(finest);
        let study = levels
            .iter()
            .copied()
            .find(|&l| l == plan.grid.count as f64)
            .unwrap_or(coarsest);
        let _ = writeln!(
            w,
            "\nA coarser grid can step over a thin island of overturning below the first one a finer grid finds, \
             so individual capacities move by much more than the refinement tolerance. The mean η_c,50 moves by \
             {:+.1} % from {study} levels (this study's grid) to {finest}, and by {:+.1} % from {coarsest} to {finest}: \
             capacities from a coarse grid are biased low.\n",
            100.0 * (mean_q50(finest) / mean_q50(study) - 1.0),
            100.0 * (mean_q50(finest) / mean_q50(coarsest) - 1.0),
        );
    }

    // Figures.
    let _ = writeln!(w, "## Figures\n");
    for f in &figs {
        let _ = writeln!(
            w,
            "![{}](figures/{})\n\n*{}*\n",
            f.chart.title, f.file, f.caption
        );
    }
    atomic_write(&dir.join("report.md"), md.as_bytes()).map_err(|e| e.to_string())
}
