//! `rocking fragility`: the block's fragility (the one function
//! [`crate::ops::damage::of_block`] makes for every command, its one state
//! overturning) at the levels asked.

use super::error::FragilityError;
use super::request::{check, laws_and_records, Request};
use super::RunModel;
use crate::damage::DamageStates;
use crate::im::Im;
use crate::ops::damage;
use crate::ops::tree as ops_tree;

/// One level of the answer.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Point {
    /// The level, in the IM's unit.
    pub iml: f64,
    /// For PGA: the level again (g), and the block's η there.
    pub pga_g: Option<f64>,
    pub eta: Option<f64>,
    pub probability: f64,
    /// With `--direct`: the share of records whose capacity the block exceeds.
    pub empirical: Option<f64>,
    /// With a tree of several branches: the branches' probabilities'
    /// weighted quantiles (5, 16, 50, 84, 95 %); `probability` is then
    /// their weighted mean.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quantiles: Option<Vec<f64>>,
}

/// The answer.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Assessment {
    pub b_m: f64,
    pub h_m: f64,
    pub alpha_rad: f64,
    pub p: f64,
    pub eps: f64,
    /// The IM (`pga`, `pgv`, `sa(1.0)`, …) and its unit.
    pub im: String,
    pub unit: &'static str,
    /// `paper`, the pipeline file, or `direct` (the records' capacities).
    pub source: String,
    /// How the fragility is made: `fractile`, `mle`, `empirical` (the
    /// records' curve), `regression` (the paper's or a study's) or
    /// `moments` (a study's IM table, where its damage states hold no
    /// overturning: exp(mean ln), the standard deviation).
    pub fit: String,
    /// With `--direct`: the records folder (or pipeline) the block ran through.
    pub records_folder: Option<String>,
    /// The median capacity in the IM's unit (the records' 50 % fractile
    /// for the records' curve).
    pub median: f64,
    /// For PGA: the median η_c.
    pub eta_c_median: Option<f64>,
    /// The lognormal's β; none (NaN, null in JSON) for the records' curve.
    pub beta: f64,
    /// With `--direct`: the lognormal check of the records' capacities,
    /// Lilliefors' p of their logarithms (below 0.05 the lognormal is
    /// rejected, and the fragility is their own curve unless asked
    /// otherwise).
    pub lognormal_p: Option<f64>,
    /// Records run with `--direct` (with `--orientation random`, every pair
    /// at every angle; with `worst`, the pairs).
    pub records: Option<usize>,
    /// With `--orientation random|worst`: the pairs and angles run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orientation: Option<String>,
    /// With `--direct`: the model the records were run with, and why.
    pub model: Option<String>,
    pub points: Vec<Point>,
    /// On a floor: the building's modes (`T,ζ,Γφ; …`); levels and
    /// capacities are then the ground's, or in PFA and PFV the floor
    /// motion's own.
    pub floor: Option<String>,
    /// The base's friction coefficient, when given.
    pub mu: Option<f64>,
    /// With `mu`: whether the block slides before it rocks (μ ≤ b/h).
    pub slides_first: Option<bool>,
    /// Where the regression is stretched for this block (none with
    /// `--direct`), and a block that slides first.
    pub warnings: Vec<String>,
    /// With `--tree`: each branch's fragility, the mixture's median and
    /// equivalent β, the dispersion split. With several branches the
    /// answer's `median`, `beta` and probabilities are the mixture's (`fit`
    /// is `mixture`, `eps` null).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tree: Option<crate::ops::tree::TreeInfo>,
}

/// Checks the request and computes the fragility: the block's one
/// fragility (overturning, [`damage::of_block`]) by the fit asked; with a
/// tree, each branch's and their mixture.
pub fn assess(req: &Request) -> Result<Assessment, FragilityError> {
    let block = check(req)?;
    let (laws, records) = laws_and_records(
        &req.from,
        req.direct,
        &req.progress,
        req.tree.as_ref().map_or(1, |t| t.paths().len()),
        req.floor.as_ref(),
        req.orient_for(req.im),
    )?;
    let base = RunModel::of_command(req.auto_tol, records.as_ref());
    let Some(tree) = &req.tree else {
        return one(req, &block, &laws, records.as_ref(), base.on(req.mu)).map(|(a, _)| a);
    };
    let mut parts = Vec::new();
    let mut answers = Vec::new();
    for path in tree.paths() {
        let (eps, model) = ops_tree::branch(&path, req.b_m, req.h_m, req.eps, base)?;
        let b = super::block(req.b_m, req.h_m, eps)?;
        let (a, fragility) = one(req, &b, &laws, records.as_ref(), model.on(req.mu))?;
        parts.push(ops_tree::Part {
            path,
            eps: b.eps,
            fragility,
            median: a.median.is_finite().then_some(a.median),
            beta: a.beta.is_finite().then_some(a.beta),
        });
        answers.push(a);
    }
    Ok(mixed(req, tree, parts, answers))
}

/// The tree's answer: a one-branch tree's is its branch's; otherwise every
/// level's probability the branches' weighted mean (each cut as its own
/// answer is), with its quantiles
/// (the records' shares weighted alike), and the median and β the
/// mixture's (its equivalent lognormal's).
fn mixed(
    req: &Request,
    tree: &crate::tree::Tree,
    parts: Vec<ops_tree::Part>,
    answers: Vec<Assessment>,
) -> Assessment {
    let info = ops_tree::info(tree, &parts);
    let weights: Vec<f64> = parts.iter().map(|p| p.path.weight).collect();
    let shares: Vec<Option<f64>> = (0..req.levels.len())
        .map(|k| {
            let each: Option<Vec<f64>> = answers.iter().map(|a| a.points[k].empirical).collect();
            each.map(|e| crate::tree::weighted_mean(&e, &weights))
        })
        .collect();
    let warnings = ops_tree::merge_warnings(
        &parts
            .iter()
            .zip(&answers)
            .map(|(p, a)| (p.path.label.as_str(), &a.warnings[..]))
            .collect::<Vec<_>>(),
    );
    // Each branch's probability at each level as its own answer states it
    // (0 below the level its block cannot move at, as `risk --tree` cuts
    // each branch).
    let each: Vec<Vec<f64>> = (0..req.levels.len())
        .map(|k| answers.iter().map(|a| a.points[k].probability).collect())
        .collect();
    let mut a = answers.into_iter().next().expect("a tree has a branch");
    a.warnings = warnings;
    if parts.len() > 1 {
        for (k, point) in a.points.iter_mut().enumerate() {
            let ps = &each[k];
            point.probability = crate::tree::weighted_mean(ps, &weights);
            point.quantiles = Some(ops_tree::quantiles(ps, &weights));
            point.empirical = shares[k];
        }
        a.median = info.mean_median.unwrap_or(f64::INFINITY);
        a.beta = info.mean_beta.unwrap_or(f64::NAN);
        a.eta_c_median = (a.im == "pga").then(|| a.alpha_rad / a.median);
        a.fit = "mixture".into();
        a.eps = f64::NAN;
        a.lognormal_p = None;
        a.model = None;
    }
    a.tree = Some(info);
    a
}

/// One block's fragility at the levels asked, and the function itself.
fn one(
    req: &Request,
    block: &crate::block::Block,
    laws: &super::Laws,
    records: Option<&super::DirectRecords>,
    model: RunModel,
) -> Result<(Assessment, crate::risk::Fragility), FragilityError> {
    let (alpha, p, eps) = (block.alpha(), block.p(), block.eps);
    let im = req.im;
    let f = damage::of_block(
        block,
        &DamageStates::overturning(),
        im,
        laws,
        records,
        model,
        req.fit(),
    )?;
    let method = f.method;
    let state = &f.states[0];
    let fragility = state
        .fragility(method)
        .ok_or_else(|| damage::no_fit(&f, state, method))?;
    let (median, beta) = state.median_beta(method);
    // More than half the records never reach it: the median lies beyond.
    let (median, beta) = (median.unwrap_or(f64::INFINITY), beta.unwrap_or(f64::NAN));
    // Below the level the block cannot move at, 0, as `risk` counts it.
    let cut = damage::zero_below(block, im, records.and_then(|r| r.floor()), f.slides_on_mu);
    let points = req
        .levels
        .iter()
        .map(|&x| Point {
            iml: x,
            pga_g: (im == Im::Pga).then_some(x),
            eta: (im == Im::Pga).then(|| alpha / x),
            probability: damage::probability_above(&fragility, x, cut),
            empirical: state
                .capacities
                .as_ref()
                .map(|t| t.partition_point(|&c| c < x) as f64 / t.len() as f64),
            quantiles: None,
        })
        .collect();
    let mut warnings = f.warnings.clone();
    warnings.extend(crate::hazard::levels_slip(im, &req.levels));
    let slides_first = req.mu.map(|mu| crate::block::slides_first(mu, alpha));
    warnings.extend(f.unmodelled_sliding(req.mu, alpha));
    Ok((
        Assessment {
            b_m: req.b_m,
            h_m: req.h_m,
            alpha_rad: alpha,
            p,
            eps,
            im: im.name(),
            unit: im.unit(),
            source: f.source.clone(),
            fit: f.fit_name(method).to_string(),
            records_folder: f.records_folder.clone(),
            median,
            eta_c_median: (im == Im::Pga).then(|| alpha / median),
            beta,
            lognormal_p: state.lognormal_p,
            records: f.records,
            orientation: f.orientation.clone(),
            model: f.model.clone(),
            points,
            floor: f.floor.clone(),
            mu: req.mu,
            slides_first,
            warnings,
            tree: None,
        },
        fragility,
    ))
}
