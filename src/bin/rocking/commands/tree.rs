//! How `fragility` and `risk` print a logic tree: its branches, the
//! mixture and the dispersion split, and each site's branch rates.

use rocking::im::level_text;
use rocking::ops::risk::{BootstrapInfo, BranchRate};
use rocking::ops::tree::TreeInfo;

/// The tree's branches, each with its fragility, and the mixture's.
pub fn print_tree(t: &TreeInfo, unit: &str) {
    println!(
        "logic tree {}: {} branch(es), the answer their weighted mean",
        t.tree,
        t.branches.len()
    );
    let opt = |v: Option<f64>, f: &dyn Fn(f64) -> String| v.map_or("—".into(), f);
    for b in &t.branches {
        // A median without a β: the branch is its records' own curve.
        let spread = match (b.median, b.beta) {
            (_, Some(v)) => format!("β {v:.3}"),
            (Some(_), None) => "the records' own curve".into(),
            (None, None) => "β —".into(),
        };
        println!(
            "  w {:<6} {:<28} ε = {:.4}: median {}, {spread}",
            format!("{:.4}", b.weight),
            b.branch,
            b.eps,
            opt(b.median, &|m| format!("{} {unit}", level_text(m))),
        );
    }
    if t.branches.len() > 1 {
        println!(
            "  mean (the mixture): median {}, equivalent β {} (ln(x84/x16)/2)",
            opt(t.mean_median, &|m| format!("{} {unit}", level_text(m))),
            opt(t.mean_beta, &|v| format!("{v:.3}")),
        );
    }
    if let Some(s) = &t.split {
        println!(
            "  FEMA P-58 split: β_rtr {:.3}, β_m {:.3}, β_total {:.3} about the median {} {unit}",
            s.beta_rtr,
            s.beta_m,
            s.beta_total,
            level_text(s.median)
        );
    }
}

/// A site's branch rates and their quantiles (1/year).
pub fn print_rates(branches: &[BranchRate], quantiles: &[f64], at: &[f64], mean: f64) {
    if branches.len() < 2 {
        return;
    }
    println!("  annual rate over the tree (1/yr): mean {mean:.3e}");
    for b in branches {
        println!(
            "    w {:.4}  {:<28} {:.3e}",
            b.weight, b.branch, b.annual_rate
        );
    }
    let q: Vec<String> = quantiles
        .iter()
        .zip(at)
        .map(|(q, v)| format!("{:.0} % {v:.3e}", 100.0 * q))
        .collect();
    println!("    quantiles: {}", q.join(", "));
}

/// The bootstrap: its resamples and the bands of the median and β.
pub fn print_bootstrap(b: &BootstrapInfo, unit: &str) {
    let band = |v: Option<[f64; 2]>, f: &dyn Fn(f64) -> String| {
        v.map_or("—".into(), |[lo, hi]| format!("{} – {}", f(lo), f(hi)))
    };
    println!(
        "bootstrap: {} resamples of the records by {} (seed {}, {} fitted); {:.0} % bands: median {}, β {}",
        b.resamples,
        b.unit,
        b.seed,
        b.fitted,
        100.0 * b.level,
        band(b.median_band, &|m| format!("{} {unit}", level_text(m))),
        band(b.beta_band, &|v| format!("{v:.3}")),
    );
}
