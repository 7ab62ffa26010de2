//! Fit stage: capacity fractiles → the two-step regression (docs/MODEL.md §6).
//!
//! Reads `capacity_fractiles.parquet` (from reduce), fits
//! `η_c,q(p) = a (1 − e^{−bp})^c` per ε and fractile (step 1), then a(ε)
//! linear and b(ε), c(ε) quadratic per fractile over the converged step-1
//! fits (step 2). Writes `fit_step1.parquet`, `fit_coefficients.parquet` (the
//! fitted polynomials beside the paper's) and `fit_comparison.parquet`
//! (data, step 1, step 2 and the paper's η_c over the grid). Reruns only
//! when its input's bytes changed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::fit::{curve, fit_curve, polyfit, polyval, CurveFit};
use crate::fragility::{paper, FractileLaw};
use crate::pipeline::Plan;
use crate::stages::reduce::{all_current, fingerprint, ReduceError};
use crate::tables::summary::{
    f, fo, i, s, Value, CAPACITY_FRACTILES, FIT_COEFFICIENTS, FIT_COMPARISON, FIT_STEP1,
};
use crate::tables::TableError;

pub const META_INPUT: &str = "rocking.fit.input";

#[derive(Debug, thiserror::Error)]
pub enum FitError {
    #[error("{0} does not exist: run `rocking reduce` on this pipeline first")]
    MissingInput(PathBuf),
    #[error(transparent)]
    Reduce(#[from] ReduceError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("the fit needs the p × ε grid of `[blocks]`; this pipeline has physical `[[block]]` entries")]
    NotAGrid,
    #[error("the fit needs at least 3 values of p and of ε; this grid has {0} × {1}")]
    TooSmall(usize, usize),
}

#[derive(Debug, Clone)]
pub struct FitReport {
    pub dir: PathBuf,
    pub up_to_date: bool,
    /// Step-1 fits that converged, of all.
    pub converged: (usize, usize),
    /// Fitted laws (16, 50, 84 %), if step 2 had enough converged points.
    pub laws: Vec<FractileLaw>,
}

/// Why the regression cannot be fitted to this pipeline's blocks, if it cannot.
pub fn not_applicable(plan: &Plan) -> Option<String> {
    if plan.blocks.iter().any(|b| !b.name.is_empty()) {
        return Some("the pipeline has physical blocks, not a p × ε grid".into());
    }
    let count = |v: Vec<f64>| crate::stats::distinct(v).len();
    let np = count(plan.blocks.iter().map(|b| b.p).collect());
    let ne = count(plan.blocks.iter().map(|b| b.eps).collect());
    (np < 3 || ne < 3).then(|| {
        format!("the regression needs at least 3 values of p and of ε (the grid has {np} × {ne})")
    })
}

pub fn outputs(dir: &Path) -> [PathBuf; 3] {
    [
        dir.join("fit_step1.parquet"),
        dir.join("fit_coefficients.parquet"),
        dir.join("fit_comparison.parquet"),
    ]
}

/// Reads the fitted laws of a pipeline's output folder.
pub fn read_laws(dir: &Path) -> Result<Vec<FractileLaw>, FitError> {
    let path = dir.join("fit_coefficients.parquet");
    if !path.exists() {
        return Err(FitError::MissingInput(path));
    }
    let rows = FIT_COEFFICIENTS.read(&path)?;
    let (src, q, name) = (
        FIT_COEFFICIENTS.col("source"),
        FIT_COEFFICIENTS.col("quantile"),
        FIT_COEFFICIENTS.col("coefficient"),
    );
    let cs = [
        FIT_COEFFICIENTS.col("c0"),
        FIT_COEFFICIENTS.col("c1"),
        FIT_COEFFICIENTS.col("c2"),
    ];
    let mut laws: Vec<FractileLaw> = Vec::new();
    for row in rows.iter().filter(|r| r[src].s() == "fitted") {
        let quantile = row[q].f().unwrap_or(f64::NAN);
        let coeffs: Vec<f64> = cs.iter().filter_map(|&k| row[k].f()).collect();
        let law = match laws.iter_mut().find(|l| l.quantile == quantile) {
            Some(l) => l,
            None => {
                laws.push(FractileLaw {
                    quantile,
                    a: vec![],
                    b: vec![],
                    c: vec![],
                });
                laws.last_mut().expect("just pushed")
            }
        };
        match row[name].s() {
            "a" => law.a = coeffs,
            "b" => law.b = coeffs,
            _ => law.c = coeffs,
        }
    }
    Ok(laws)
}

pub fn run(plan: &Plan, outputs_root: &Path, force: bool) -> Result<FitReport, FitError> {
    let dir = outputs_root.join(&plan.name);
    if plan.blocks.iter().any(|b| !b.name.is_empty()) {
        return Err(FitError::NotAGrid);
    }
    let input = dir.join("capacity_fractiles.parquet");
    if !input.exists() {
        return Err(FitError::MissingInput(input));
    }
    let input_hash = fingerprint(
        std::slice::from_ref(&input),
        &["fit_step1/1 fit_coefficients/1 fit_comparison/1"],
    )?;
    let outs = outputs(&dir);
    if !force && all_current(&outs, META_INPUT, &input_hash) {
        return Ok(FitReport {
            dir,
            up_to_date: true,
            converged: (0, 0),
            laws: vec![],
        });
    }

    // (ε, q) → [(p, η_c)], in ε and q order (f64 keys as bits keep exact values).
    let rows = CAPACITY_FRACTILES.read(&input)?;
    let (cp, ce, cq, cv) = (
        CAPACITY_FRACTILES.col("p"),
        CAPACITY_FRACTILES.col("eps"),
        CAPACITY_FRACTILES.col("quantile"),
        CAPACITY_FRACTILES.col("eta_c"),
    );
    let mut groups: BTreeMap<(u64, u64), Vec<(f64, f64)>> = BTreeMap::new();
    for r in &rows {
        let (p, e, q, v) = (r[cp].f(), r[ce].f(), r[cq].f(), r[cv].f());
        if let (Some(p), Some(e), Some(q), Some(v)) = (p, e, q, v) {
            groups
                .entry((q.to_bits(), e.to_bits()))
                .or_default()
                .push((p, v));
        }
    }
    let eps_values: Vec<f64> = {
        let mut v: Vec<f64> = rows.iter().filter_map(|r| r[ce].f()).collect();
        v.sort_by(|a, b| a.total_cmp(b));
        v.dedup();
        v
    };
    let n_p = groups.values().next().map_or(0, |v| v.len());
    if n_p < 3 || eps_values.len() < 3 {
        return Err(FitError::TooSmall(n_p, eps_values.len()));
    }

    // Step 1.
    let mut step1: BTreeMap<(u64, u64), CurveFit> = BTreeMap::new();
    let mut step1_rows = Vec::new();
    for (&(qb, eb), pts) in &groups {
        let (ps, ys): (Vec<f64>, Vec<f64>) = pts.iter().cloned().unzip();
        let fit = fit_curve(&ps, &ys);
        let ok = fit.stop.converged();
        let num = |v: f64| fo(Some(v).filter(|x| x.is_finite()));
        step1_rows.push(vec![
            f(f64::from_bits(eb)),
            f(f64::from_bits(qb)),
            num(fit.a),
            num(fit.b),
            num(fit.c),
            num(fit.rms),
            i(fit.iterations as i64),
            s(fit.stop.as_str()),
            Value::B(ok),
        ]);
        step1.insert((qb, eb), fit);
    }
    let converged = (
        step1.values().filter(|f| f.stop.converged()).count(),
        step1.len(),
    );

    // Step 2, per fractile, over the converged step-1 fits.
    let mut coeff_rows = Vec::new();
    let mut laws = Vec::new();
    let quantiles: Vec<u64> = {
        let mut q: Vec<u64> = groups.keys().map(|k| k.0).collect();
        q.dedup();
        q
    };
    let padded = |c: Option<Vec<f64>>| -> [Value; 3] {
        let c = c.unwrap_or_default();
        [
            fo(c.first().copied()),
            fo(c.get(1).copied()),
            fo(c.get(2).copied()),
        ]
    };
    for &qb in &quantiles {
        let pts: Vec<(f64, &CurveFit)> = step1
            .iter()
            .filter(|((q, _), fit)| *q == qb && fit.stop.converged())
            .map(|((_, e), fit)| (f64::from_bits(*e), fit))
            .collect();
        let eps: Vec<f64> = pts.iter().map(|p| p.0).collect();
        let a = polyfit(&eps, &pts.iter().map(|p| p.1.a).collect::<Vec<_>>(), 1);
        let b = polyfit(&eps, &pts.iter().map(|p| p.1.b).collect::<Vec<_>>(), 2);
        let c = polyfit(&eps, &pts.iter().map(|p| p.1.c).collect::<Vec<_>>(), 2);
        let q = f64::from_bits(qb);
        for (name, co) in [("a", &a), ("b", &b), ("c", &c)] {
            let mut row = vec![s("fitted"), f(q), s(name)];
            row.extend(padded(co.clone()));
            coeff_rows.push(row);
        }
        if let (Some(a), Some(b), Some(c)) = (a, b, c) {
            laws.push(FractileLaw {
                quantile: q,
                a,
                b,
                c,
            });
        }
    }
    for law in paper() {
        for (name, co) in [("a", &law.a), ("b", &law.b), ("c", &law.c)] {
            let mut row = vec![s("paper"), f(law.quantile), s(name)];
            row.extend(padded(Some(co.clone())));
            coeff_rows.push(row);
        }
    }

    // Data against step 1, step 2 and the paper, over the grid.
    let published = paper();
    let mut comparison = Vec::new();
    for (&(qb, eb), pts) in &groups {
        let (q, e) = (f64::from_bits(qb), f64::from_bits(eb));
        let s1 = step1.get(&(qb, eb)).filter(|f| f.stop.converged());
        let law = laws.iter().find(|l| l.quantile == q);
        let pub_law = published.iter().find(|l| (l.quantile - q).abs() < 1e-9);
        for &(p, v) in pts {
            comparison.push(vec![
                f(p),
                f(e),
                f(q),
                f(v),
                fo(s1.map(|s| curve(s.a, s.b, s.c, p))),
                fo(law.map(|l| curve(polyval(&l.a, e), polyval(&l.b, e), polyval(&l.c, e), p))),
                f(pub_law.map_or(f64::NAN, |l| l.eta_c(p, e))),
            ]);
        }
    }

    let settings = vec![(META_INPUT.to_string(), input_hash)];
    FIT_STEP1.write(&outs[0], &step1_rows, &settings)?;
    FIT_COEFFICIENTS.write(&outs[1], &coeff_rows, &settings)?;
    FIT_COMPARISON.write(&outs[2], &comparison, &settings)?;
    Ok(FitReport {
        dir,
        up_to_date: false,
        converged,
        laws,
    })
}
