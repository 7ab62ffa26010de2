//! The report's section of a study with a logic tree (`[tree]`): the
//! example block on each branch, the mean and its dispersion split, and
//! which branch set moves the capacity most (docs/MODEL.md §19).

use std::fmt::Write as _;

use crate::figures::tree::branches;
use crate::study::StudyData;
use crate::tree::{self, Mixture};

/// `## How sure: the example block over the tree`.
pub(super) fn tree_section(w: &mut String, d: &StudyData) {
    let (Some(b), Some(t)) = (branches(d), d.plan.tree()) else {
        return;
    };
    let _ = writeln!(w, "## How sure: the example block over the logic tree\n");
    let _ = writeln!(
        w,
        "The example block on each of the tree's {} branches, over every record \
         (`tree_capacities.parquet`), each branch's fragility a lognormal by the fractiles of \
         its capacities in {im}{def}; the mean is their weighted mixture (not a lognormal: stated by \
         its median and the β through its Φ(±1) levels, 15.87 and 84.13 %), the dispersion \
         split as FEMA P-58 states it (docs/MODEL.md §19). The same with `rocking fragility \
         --from PIPELINE.toml --direct --tree …{flag} --if-not-lognormal lognormal` for any \
         block (without it, a branch whose capacities fail the lognormal check is its records' \
         own curve there).\n",
        b.weights.len(),
        im = b.im.short(),
        // `fragility --direct` fits by type 7: said where the study differs.
        def = match d.plan.records_study().map(|p| p.fractile) {
            Ok(def) if def != crate::stats::FractileDef::Type7 => format!(
                " (the study's fractiles, {}, as its damage states; `fragility --direct` takes \
                 type 7)",
                def.name()
            ),
            _ => String::new(),
        },
        flag = if b.im == crate::im::Im::Pfa {
            " --im pfa"
        } else {
            ""
        },
    );
    let _ = writeln!(
        w,
        "| branch | weight | ε | model | median {} (g) | β |\n|---|---|---|---|---|---|",
        b.im.short()
    );
    for ((br, fit), label) in t.branches.iter().zip(&b.fits).zip(&b.labels) {
        let _ = writeln!(
            w,
            "| {label} | {:.4} | {:.4} | {} | {:.4} | {:.3} |",
            br.weight,
            br.block.eps,
            match br.block.run.model.equation {
                crate::physics::Equation::Linearized => "linearised",
                crate::physics::Equation::Nonlinear { .. } => "nonlinear",
                crate::physics::Equation::SlideRock { .. } => "slide-rock",
            },
            fit.median,
            fit.beta
        );
    }
    let parts = b.parts();
    let (m, beta) = Mixture {
        parts: &parts,
        below: &[],
    }
    .median_beta();
    let lognormals: Vec<(f64, f64)> = b.fits.iter().map(|l| (l.median, l.beta)).collect();
    let split = tree::beta_split(&lognormals, &b.weights);
    let opt = |v: Option<f64>, d: usize| v.map_or("—".into(), |v| format!("{v:.d$}"));
    let _ = writeln!(
        w,
        "| **mean (the mixture)** | 1 | | | {} | {} (equivalent) |\n",
        opt(m, 4),
        opt(beta, 3)
    );
    if let Some(s) = split {
        let _ = writeln!(
            w,
            "FEMA P-58's split: β_rtr = {:.3} (the records), β_m = {:.3} (the tree), β_total = \
             {:.3} about {:.4} g.\n",
            s.beta_rtr, s.beta_m, s.beta_total, s.median
        );
    }
    let medians: Vec<f64> = b.fits.iter().map(|l| l.median).collect();
    for s in tree::swings(&t.tree, &medians) {
        let _ = writeln!(
            w,
            "- {}: the median capacity ranges {:.4}–{:.4} g over its branches ({:+.0} %).",
            s.set,
            s.low,
            s.high,
            100.0 * (s.high / s.low - 1.0)
        );
    }
    let _ = writeln!(w);
}
