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
use crate::tables::fit::{
    BandCurve, Coefficient, FitBandRow, FitCoefficientRow, FitComparisonRow, FitStep1Row, Source,
};
use crate::tables::reduce::{CapacityFractileRow, CapacityResampleRow};
use crate::tables::{self, TableError};

/// The fit stage.
pub struct Fit;

pub const OUTPUTS: [&str; 3] = [
    "fit_step1.parquet",
    "fit_coefficients.parquet",
    "fit_comparison.parquet",
];

/// The bands of the fitted curves, written when the pipeline has `[uncertainty]`.
pub const BANDS: &str = "fit_bands.parquet";

/// Metadata keys of `fit_bands.parquet`: step-1 fits converged over all
/// resamples, and resamples whose refit gave all three laws ("k of n").
pub const META_STEP1: &str = "rocking.fit.bands.step1_converged";
pub const META_LAWS: &str = "rocking.fit.bands.laws_complete";

impl Stage for Fit {
    fn name(&self) -> &'static str {
        "fit"
    }

    fn about(&self) -> &'static str {
        "Fit the two-step regression η_c = a·(1 − exp(−b·p))^c, a, b, c polynomial in ε"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        not_applicable(&study.plan)
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        // The band level; the resamples come in through their table.
        match study.plan.uncertainty() {
            None => serde_json::Value::Null,
            Some(u) => serde_json::json!({ "band_level": u.level }),
        }
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        let mut inputs = vec![study.path("capacity_fractiles.parquet")];
        if study.plan.uncertainty().is_some() {
            inputs.push(study.path(super::reduce::RESAMPLES));
        }
        Ok(inputs)
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        let bands = study.plan.uncertainty().map(|_| BANDS);
        OUTPUTS
            .iter()
            .chain(&bands)
            .map(|n| study.path(n))
            .collect()
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
    if let Some(why) = plan.pulse_map_skips() {
        return Some(why);
    }
    if plan.records_study().is_ok_and(|r| !r.is_grid()) {
        return Some("the pipeline has physical blocks, not a p × ε grid".into());
    }
    let count = |v: Vec<f64>| crate::stats::distinct(v).len();
    let np = count(plan.blocks().iter().map(|b| b.p).collect());
    let ne = count(plan.blocks().iter().map(|b| b.eps).collect());
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
    let groups = group(rows.iter().map(|r| (r.quantile, r.eps, r.p, r.eta_c)));
    let n_eps = crate::stats::distinct(rows.iter().map(|r| r.eps).collect()).len();
    let n_p = groups.values().next().map_or(0, |v| v.len());
    if n_p < 3 || n_eps < 3 {
        return Err(FitError::TooSmall(n_p, n_eps));
    }
    let (step1, step1_rows) = step1(&groups);
    let converged = step1.values().filter(|f| f.stop.converged()).count();
    let (laws, coeff_rows) = step2(&groups, &step1);
    let comparison = compare(&groups, &step1, &laws);
    let bands = match study.plan.uncertainty() {
        Some(u) => Some(bands(study, u, &laws)?),
        None => None,
    };
    let settings: Vec<(String, String)> = Vec::new();
    tables::write(&study.path(OUTPUTS[0]), &step1_rows, &settings)?;
    tables::write(&study.path(OUTPUTS[1]), &coeff_rows, &settings)?;
    tables::write(&study.path(OUTPUTS[2]), &comparison, &settings)?;

    let mut lines = vec![format!(
        "step 1: {converged} of {} fits converged",
        step1.len()
    )];
    if let Some(b) = &bands {
        let meta = vec![
            (
                META_STEP1.to_string(),
                format!("{} of {}", b.step1_converged, b.step1_fits),
            ),
            (
                META_LAWS.to_string(),
                format!("{} of {}", b.complete, b.resamples),
            ),
        ];
        tables::write(&study.path(BANDS), &b.rows, &meta)?;
        lines.push(format!(
            "bands: {} resamples refitted; step 1 converged in {} of {} fits ({:.1} %); all three laws in {} resamples ({:.1} %)",
            b.resamples,
            b.step1_converged,
            b.step1_fits,
            100.0 * b.step1_converged as f64 / b.step1_fits.max(1) as f64,
            b.complete,
            100.0 * b.complete as f64 / b.resamples.max(1) as f64,
        ));
    }
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
        "wrote fit_step1, fit_coefficients, fit_comparison{} in {}",
        if bands.is_some() { ", fit_bands" } else { "" },
        study.dir.display()
    ));
    Ok(Summary {
        // The coefficients, not where they were written.
        headline: lines.len() - 1,
        lines,
        also_wrote: Vec::new(),
    })
}

/// (fractile, ε, p, η_c) points → curves to fit, each in increasing p: the
/// fits' sums run in one order whatever the order of the blocks (listed
/// `p = [2.0, 5.0, 0.5]`, the coefficients moved in their eighth digit).
fn group(points: impl Iterator<Item = (f64, f64, f64, f64)>) -> Groups {
    let mut groups: Groups = BTreeMap::new();
    for (q, e, p, eta) in points {
        groups
            .entry((q.to_bits(), e.to_bits()))
            .or_default()
            .push((p, eta));
    }
    for curve in groups.values_mut() {
        curve.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    groups
}

/// The fit bands and what went into them.
struct Bands {
    rows: Vec<FitBandRow>,
    resamples: usize,
    /// Step-1 fits over all resamples, and how many converged.
    step1_fits: usize,
    step1_converged: usize,
    /// Resamples whose step 2 gave all three laws.
    complete: usize,
}

/// Every bootstrap resample of `capacity_resamples` refitted (step 1 and
/// step 2, as the point fit), in parallel and collected in resample order;
/// the laws evaluated along each ε's capacity curves and the example
/// block's fragility; percentile bands over the resamples with all three
/// laws.
fn bands(
    study: &Study,
    u: crate::pipeline::Uncertainty,
    laws: &[FractileLaw],
) -> Result<Bands, FitError> {
    let rows: Vec<CapacityResampleRow> = tables::read(&study.path(super::reduce::RESAMPLES))?;
    Ok(refit(&rows, laws, u.level))
}

/// [`bands`] on rows in resample order.
fn refit(rows: &[CapacityResampleRow], laws: &[FractileLaw], level: f64) -> Bands {
    use rayon::prelude::*;
    let by_resample: Vec<&[CapacityResampleRow]> =
        rows.chunk_by(|a, b| a.resample == b.resample).collect();
    // (step-1 fits, converged, the three laws when complete) per resample.
    let refits: Vec<(usize, usize, Option<Vec<FractileLaw>>)> = by_resample
        .par_iter()
        .map(|chunk| {
            let groups = group(chunk.iter().map(|r| (r.quantile, r.eps, r.p, r.eta_c)));
            let (fits, _) = step1(&groups);
            let converged = fits.values().filter(|f| f.stop.converged()).count();
            let (laws, _) = step2(&groups, &fits);
            let complete = laws.len() == 3 && laws.iter().all(FractileLaw::is_complete);
            (fits.len(), converged, complete.then_some(laws))
        })
        .collect();
    let usable: Vec<&[FractileLaw]> = refits.iter().filter_map(|r| r.2.as_deref()).collect();
    let ps = crate::stats::distinct(rows.iter().map(|r| r.p).collect());
    let es = crate::stats::distinct(rows.iter().map(|r| r.eps).collect());
    let resamples = by_resample.len();
    let mut out = Vec::new();
    let band = |values: &mut Vec<f64>| {
        let used = values.len() as i64;
        let b = (values.len() >= 2)
            .then(|| crate::stats::percentile_band(values, level))
            .flatten();
        (b.map(|b| b.0), b.map(|b| b.1), used)
    };
    fn law_of(laws: &[FractileLaw], q: f64) -> Option<&FractileLaw> {
        laws.iter().find(|l| l.quantile == q)
    }
    let mut values = Vec::with_capacity(usable.len());
    for q in super::reduce::QUANTILES {
        let point = law_of(laws, q).filter(|l| l.is_complete());
        // This fractile's law in every usable resample.
        let resampled: Vec<&FractileLaw> = usable.iter().filter_map(|l| law_of(l, q)).collect();
        for &e in &es {
            for p in crate::fit::p_curve(&ps) {
                values.clear();
                values.extend(
                    resampled
                        .iter()
                        .map(|l| l.eta_c(p, e))
                        .filter(|v| v.is_finite()),
                );
                let (lo, hi, used) = band(&mut values);
                out.push(FitBandRow {
                    curve: BandCurve::EtaC,
                    quantile: Some(q),
                    p,
                    eps: e,
                    pga_g: None,
                    value: point.map(|l| l.eta_c(p, e)),
                    lo,
                    hi,
                    used,
                    level,
                    resamples: resamples as i64,
                });
            }
        }
    }
    let block = crate::fragility::example_block();
    let (p, e) = (block.p(), block.eps);
    let point = crate::fragility::median_beta(laws, p, e);
    let resampled: Vec<(f64, f64)> = usable
        .iter()
        .filter_map(|l| crate::fragility::median_beta(l, p, e))
        .collect();
    for pga in crate::fragility::example_pgas() {
        values.clear();
        values.extend(
            resampled
                .iter()
                .map(|&(m, beta)| crate::fragility::probability(m, beta, &block, pga)),
        );
        let (lo, hi, used) = band(&mut values);
        out.push(FitBandRow {
            curve: BandCurve::Fragility,
            quantile: None,
            p,
            eps: e,
            pga_g: Some(pga),
            value: point.map(|(m, beta)| crate::fragility::probability(m, beta, &block, pga)),
            lo,
            hi,
            used,
            level,
            resamples: resamples as i64,
        });
    }
    Bands {
        rows: out,
        resamples,
        step1_fits: refits.iter().map(|r| r.0).sum(),
        step1_converged: refits.iter().map(|r| r.1).sum(),
        complete: usable.len(),
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's grid of p and ε (docs/MODEL.md §8).
    fn grid() -> (Vec<f64>, Vec<f64>) {
        let ps = (0..12)
            .map(|k| 0.33 * (10.0f64 / 0.33).powf(k as f64 / 11.0))
            .collect();
        let es = (0..10).map(|k| 0.5 + 0.05 * k as f64).collect();
        (ps, es)
    }

    /// The paper's three laws evaluated on the grid, as one resample's rows.
    fn paper_rows(resample: i64, scale: f64) -> Vec<CapacityResampleRow> {
        let (ps, es) = grid();
        let mut rows = Vec::new();
        for &eps in &es {
            for &p in &ps {
                for law in paper() {
                    rows.push(CapacityResampleRow {
                        resample,
                        block: String::new(),
                        p,
                        eps,
                        quantile: law.quantile,
                        eta_c: scale * law.eta_c(p, eps),
                    });
                }
            }
        }
        rows
    }

    /// Exact data recover the published coefficients through both steps:
    /// step 1 fits each ε's curve exactly (a, b, c are then the polynomials'
    /// values there), and step 2's polynomials are of the laws' own degrees.
    #[test]
    fn two_steps_recover_the_papers_coefficients_from_exact_data() {
        let rows = paper_rows(0, 1.0);
        let groups = group(rows.iter().map(|r| (r.quantile, r.eps, r.p, r.eta_c)));
        let (fits, _) = step1(&groups);
        assert!(fits.values().all(|f| f.stop.converged()));
        let (laws, _) = step2(&groups, &fits);
        assert_eq!(laws.len(), 3);
        for (law, want) in laws.iter().zip(paper()) {
            for (got, want) in [(&law.a, &want.a), (&law.b, &want.b), (&law.c, &want.c)] {
                for (g, w) in got.iter().zip(want) {
                    // Step 1's a, b, c to ~1e-7 (its tests), amplified by the
                    // quadratic's conditioning over ε ∈ [0.5, 0.95].
                    assert!(
                        (g - w).abs() < 1e-4,
                        "q = {}: {got:?} vs {want:?}",
                        law.quantile
                    );
                }
            }
        }
    }

    /// The blocks' order is not the fit's: the rows of the grid with p
    /// listed in another order (reversed, then shifted) give every
    /// coefficient to the bit (they differed in the eighth digit).
    #[test]
    fn the_fit_does_not_depend_on_the_order_of_the_blocks() {
        // Noisy data, so that the fits are not exact and their sums' order
        // shows.
        let mut rows = paper_rows(0, 1.0);
        for (k, r) in rows.iter_mut().enumerate() {
            r.eta_c *= 1.0 + 0.05 * ((k as f64) * 1.7).sin();
        }
        let fit = |rows: &[CapacityResampleRow]| {
            let groups = group(rows.iter().map(|r| (r.quantile, r.eps, r.p, r.eta_c)));
            let (fits, step1_rows) = step1(&groups);
            let (_, coefficients) = step2(&groups, &fits);
            (format!("{step1_rows:?}"), format!("{coefficients:?}"))
        };
        let mut other = rows.clone();
        other.reverse();
        other.rotate_left(7);
        assert_eq!(fit(&rows), fit(&other));
    }

    /// Resamples that all equal the data refit to the point fit: the bands
    /// collapse onto it. Resamples scaled by 0.9 … 1.1 scale a (and only a),
    /// so the band of η_c is the 5 % and 95 % scaled point values.
    #[test]
    fn bands_collapse_on_identical_resamples_and_scale_with_them() {
        let laws = paper().to_vec();
        let same: Vec<CapacityResampleRow> = (0..20).flat_map(|r| paper_rows(r, 1.0)).collect();
        let b = refit(&same, &laws, 0.9);
        assert_eq!((b.resamples, b.complete), (20, 20));
        assert_eq!(b.step1_converged, b.step1_fits);
        for row in &b.rows {
            let v = row.value.unwrap();
            let tol = 1e-5 * v.abs().max(1e-3);
            assert!(
                (row.lo.unwrap() - v).abs() < tol && (row.hi.unwrap() - v).abs() < tol,
                "{row:?}"
            );
            assert_eq!(row.used, 20);
        }
        // 21 resamples scaled 0.90, 0.91, …, 1.10: type-7 fractiles at 0.05
        // and 0.95 of 21 evenly spaced values are the 2nd and 20th: 0.91, 1.09.
        let scaled: Vec<CapacityResampleRow> = (0..21)
            .flat_map(|r| paper_rows(r, 0.9 + 0.01 * r as f64))
            .collect();
        let b = refit(&scaled, &laws, 0.9);
        for row in b.rows.iter().filter(|r| r.curve == BandCurve::EtaC) {
            let v = row.value.unwrap();
            assert!(
                (row.lo.unwrap() / v - 0.91).abs() < 1e-4
                    && (row.hi.unwrap() / v - 1.09).abs() < 1e-4,
                "{row:?}"
            );
        }
        // Scaling every fractile by k moves the example's fragility to
        // Φ((ln(kη50) − ln η)/β): P at PGA g under k equals P at g/k.
        let block = crate::fragility::example_block();
        let (m, beta) = crate::fragility::median_beta(&laws, block.p(), block.eps).unwrap();
        for row in b.rows.iter().filter(|r| r.curve == BandCurve::Fragility) {
            let g = row.pga_g.unwrap();
            let at = |k: f64| crate::fragility::probability(k * m, beta, &block, g);
            let (lo, hi) = (row.lo.unwrap(), row.hi.unwrap());
            let tol = 1e-6 + 1e-4 * hi;
            assert!(
                (lo - at(0.91)).abs() < tol && (hi - at(1.09)).abs() < tol,
                "{row:?}"
            );
        }
    }
}
