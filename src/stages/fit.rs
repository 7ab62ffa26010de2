//! Fit stage: capacity fractiles → the two-step regression (docs/MODEL.md §6).
//!
//! Reads `capacity_fractiles.parquet` (from reduce), fits
//! `η_c,q(p) = a (1 − e^{−bp})^c` per ε and fractile (step 1), then a(ε)
//! linear and b(ε), c(ε) quadratic per fractile over the converged step-1
//! fits (step 2). Writes `fit_step1.parquet`, `fit_coefficients.parquet` (the
//! fitted polynomials beside the paper's) and `fit_comparison.parquet`
//! (data, step 1, step 2 and the paper's η_c over the grid).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use crate::fit::{curve, fit_curve, polyfit, polyval, CurveFit};
use crate::fragility::{paper, FractileLaw};
use crate::pipeline::Plan;
use crate::tables::fit::{Coefficient, FitCoefficientRow, FitComparisonRow, FitStep1Row, Source};
use crate::tables::reduce::CapacityFractileRow;
use crate::tables::{self, TableError};

/// The fit stage.
pub struct Fit;

pub const OUTPUTS: [&str; 3] = [
    "fit_step1.parquet",
    "fit_coefficients.parquet",
    "fit_comparison.parquet",
];

impl Stage for Fit {
    fn name(&self) -> &'static str {
        "fit"
    }

    fn about(&self) -> &'static str {
        "Fit the two-step regression η_c = a(1 − e^{−bp})^c, a, b, c polynomial in ε"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        not_applicable(&study.plan)
    }

    fn settings(&self, _study: &Study) -> serde_json::Value {
        serde_json::Value::Null
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        Ok(vec![study.path("capacity_fractiles.parquet")])
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        OUTPUTS.iter().map(|n| study.path(n)).collect()
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx.study)?)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum FitError {
    #[error("{0} does not exist: run `rocking fit {1}` (or `rocking run {1}`) first")]
    NoFit(PathBuf, String),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("the fit needs at least 3 values of p and of ε; this grid has {0} × {1}")]
    TooSmall(usize, usize),
    #[error("{0}")]
    NotApplicable(String),
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

/// The fitted laws (16, 50, 84 %) of a study folder. `pipeline` names the
/// pipeline in the message when the fit has not been run.
pub fn read_laws(dir: &Path, pipeline: &str) -> Result<Vec<FractileLaw>, FitError> {
    let path = dir.join("fit_coefficients.parquet");
    if !path.exists() {
        return Err(FitError::NoFit(path, pipeline.to_string()));
    }
    Ok(laws_of(&tables::read::<FitCoefficientRow>(&path)?))
}

/// The fitted laws among coefficient rows (quantiles in order of appearance).
pub fn laws_of(rows: &[FitCoefficientRow]) -> Vec<FractileLaw> {
    let mut laws: Vec<FractileLaw> = Vec::new();
    for row in rows.iter().filter(|r| r.source == Source::Fitted) {
        let coeffs: Vec<f64> = [row.c0, row.c1, row.c2].into_iter().flatten().collect();
        let law = match laws.iter_mut().position(|l| l.quantile == row.quantile) {
            Some(k) => &mut laws[k],
            None => {
                laws.push(FractileLaw {
                    quantile: row.quantile,
                    a: vec![],
                    b: vec![],
                    c: vec![],
                });
                laws.last_mut().expect("just pushed")
            }
        };
        match row.coefficient {
            Coefficient::A => law.a = coeffs,
            Coefficient::B => law.b = coeffs,
            Coefficient::C => law.c = coeffs,
        }
    }
    laws
}

/// (ε, q) as exact bits → [(p, η_c)], in ε and q order.
type Groups = BTreeMap<(u64, u64), Vec<(f64, f64)>>;

fn run(study: &Study) -> Result<Summary, FitError> {
    if let Some(why) = not_applicable(&study.plan) {
        return Err(FitError::NotApplicable(why));
    }
    let rows: Vec<CapacityFractileRow> = tables::read(&study.path("capacity_fractiles.parquet"))?;
    let mut groups: Groups = BTreeMap::new();
    for r in &rows {
        groups
            .entry((r.quantile.to_bits(), r.eps.to_bits()))
            .or_default()
            .push((r.p, r.eta_c));
    }
    let n_eps = crate::stats::distinct(rows.iter().map(|r| r.eps).collect()).len();
    let n_p = groups.values().next().map_or(0, |v| v.len());
    if n_p < 3 || n_eps < 3 {
        return Err(FitError::TooSmall(n_p, n_eps));
    }
    let (step1, step1_rows) = step1(&groups);
    let converged = step1.values().filter(|f| f.stop.converged()).count();
    let (laws, coeff_rows) = step2(&groups, &step1);
    let comparison = compare(&groups, &step1, &laws);
    let settings: Vec<(String, String)> = Vec::new();
    tables::write(&study.path(OUTPUTS[0]), &step1_rows, &settings)?;
    tables::write(&study.path(OUTPUTS[1]), &coeff_rows, &settings)?;
    tables::write(&study.path(OUTPUTS[2]), &comparison, &settings)?;

    let mut lines = vec![format!(
        "step 1: {converged} of {} fits converged",
        step1.len()
    )];
    let fmt = |c: &[f64]| {
        c.iter()
            .map(|v| format!("{v:+.3}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    for law in &laws {
        lines.push(format!(
            "q = {:.2}: a {} | b {} | c {}",
            law.quantile,
            fmt(&law.a),
            fmt(&law.b),
            fmt(&law.c)
        ));
        if let Some(pl) = paper()
            .iter()
            .find(|l| (l.quantile - law.quantile).abs() < 1e-9)
        {
            lines.push(format!(
                "  paper:  a {} | b {} | c {}",
                fmt(&pl.a),
                fmt(&pl.b),
                fmt(&pl.c)
            ));
        }
    }
    lines.push(format!(
        "wrote fit_step1, fit_coefficients, fit_comparison in {}",
        study.dir.display()
    ));
    Ok(Summary {
        lines,
        also_wrote: Vec::new(),
    })
}

/// Step 1: one curve per (ε, fractile).
fn step1(groups: &Groups) -> (BTreeMap<(u64, u64), CurveFit>, Vec<FitStep1Row>) {
    let mut fits = BTreeMap::new();
    let mut rows = Vec::new();
    let finite = |v: f64| Some(v).filter(|x| x.is_finite());
    for (&(qb, eb), pts) in groups {
        let (ps, ys): (Vec<f64>, Vec<f64>) = pts.iter().cloned().unzip();
        let fit = fit_curve(&ps, &ys);
        rows.push(FitStep1Row {
            eps: f64::from_bits(eb),
            quantile: f64::from_bits(qb),
            a: finite(fit.a),
            b: finite(fit.b),
            c: finite(fit.c),
            rms: finite(fit.rms),
            iterations: fit.iterations as i64,
            stop: fit.stop,
            converged: fit.stop.converged(),
        });
        fits.insert((qb, eb), fit);
    }
    (fits, rows)
}

/// Step 2, per fractile, over the converged step-1 fits; then the paper's rows.
fn step2(
    groups: &Groups,
    step1: &BTreeMap<(u64, u64), CurveFit>,
) -> (Vec<FractileLaw>, Vec<FitCoefficientRow>) {
    let mut rows = Vec::new();
    let mut laws = Vec::new();
    let mut quantiles: Vec<u64> = groups.keys().map(|k| k.0).collect();
    quantiles.dedup();
    let row = |source, quantile, coefficient, c: Option<&Vec<f64>>| FitCoefficientRow {
        source,
        quantile,
        coefficient,
        c0: c.and_then(|c| c.first().copied()),
        c1: c.and_then(|c| c.get(1).copied()),
        c2: c.and_then(|c| c.get(2).copied()),
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
        for (name, co) in [
            (Coefficient::A, &a),
            (Coefficient::B, &b),
            (Coefficient::C, &c),
        ] {
            rows.push(row(Source::Fitted, q, name, co.as_ref()));
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
        for (name, co) in [
            (Coefficient::A, &law.a),
            (Coefficient::B, &law.b),
            (Coefficient::C, &law.c),
        ] {
            rows.push(row(Source::Paper, law.quantile, name, Some(co)));
        }
    }
    (laws, rows)
}

/// Data against step 1, step 2 and the paper, over the grid.
fn compare(
    groups: &Groups,
    step1: &BTreeMap<(u64, u64), CurveFit>,
    laws: &[FractileLaw],
) -> Vec<FitComparisonRow> {
    let published = paper();
    let mut rows = Vec::new();
    for (&(qb, eb), pts) in groups {
        let (q, e) = (f64::from_bits(qb), f64::from_bits(eb));
        let s1 = step1.get(&(qb, eb)).filter(|f| f.stop.converged());
        let law = laws.iter().find(|l| l.quantile == q);
        let pub_law = published.iter().find(|l| (l.quantile - q).abs() < 1e-9);
        for &(p, v) in pts {
            rows.push(FitComparisonRow {
                p,
                eps: e,
                quantile: q,
                eta_c_data: v,
                eta_c_step1: s1.map(|s| curve(s.a, s.b, s.c, p)),
                eta_c_fit: law
                    .map(|l| curve(polyval(&l.a, e), polyval(&l.b, e), polyval(&l.c, e), p)),
                eta_c_paper: pub_law.map_or(f64::NAN, |l| l.eta_c(p, e)),
            });
        }
    }
    rows
}
