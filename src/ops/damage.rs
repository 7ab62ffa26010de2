//! A block's fragility for each damage state, in one IM: from the records'
//! own runs (`--direct`: every state, both fits), or from a study
//! (`--from PIPELINE.toml`: overturning from its regression or IM table, as
//! `fragility` and `risk` take it, the other states from its damage table);
//! the paper's regression gives overturning only.

use super::fragility::{DirectRecords, FragilityError, Laws, Request};
use super::im_fragility::DamageTable;
use crate::block::Block;
use crate::damage::{self, Criterion, DamageStates, FitMethod, Lognormal, StateCapacity};
use crate::im::{self, Im};
use crate::stats::FractileDef;

/// One state's fragility.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StateFragility {
    pub name: String,
    /// `θmax/α ≥ 0.1` or `overturned`.
    pub criterion: String,
    /// The θmax/α threshold; none for overturning.
    pub threshold: Option<f64>,
    /// By the paper's fractiles (or the regression, which is its fit).
    pub fractile: Option<Lognormal>,
    /// By censored maximum likelihood (`--direct` only).
    pub mle: Option<Lognormal>,
    /// Records that reach the state within the runs (`--direct` only).
    pub reached: Option<usize>,
}

impl StateFragility {
    /// The lognormal of `method`.
    pub fn by(&self, method: FitMethod) -> Option<Lognormal> {
        match method {
            FitMethod::Fractile => self.fractile,
            FitMethod::MaxLikelihood => self.mle,
        }
    }
}

/// A block's damage-state fragilities.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DamageFragility {
    pub im: String,
    pub unit: &'static str,
    /// `paper`, the pipeline file, or `direct`.
    pub source: String,
    /// Records run (`--direct`).
    pub records: Option<usize>,
    /// The model the records were run with, and why (`--direct`).
    pub model: Option<String>,
    pub states: Vec<StateFragility>,
    pub warnings: Vec<String>,
}

/// The fractile definition of the records' fits (`--direct`): numpy's and
/// R's default, as the paper's.
const DIRECT_FRACTILE: FractileDef = FractileDef::Type7;

/// The block's fragility for each of `states` in `im`.
pub fn of_block(
    block: &Block,
    states: &DamageStates,
    im: Im,
    laws: &Laws,
    direct: Option<&DirectRecords>,
    auto_tol: f64,
) -> Result<DamageFragility, FragilityError> {
    match direct {
        Some(records) => from_records(block, states, im, records, auto_tol),
        None => from_regression(block, states, im, laws, auto_tol),
    }
}

/// Overturning from the regression (in PGA) or the study's IM table, as
/// `fragility` and `risk` take it; the other states, and overturning's
/// maximum-likelihood fit, from the study's damage table carried to the
/// block. The paper's regression gives overturning only.
fn from_regression(
    block: &Block,
    states: &DamageStates,
    im: Im,
    laws: &Laws,
    auto_tol: f64,
) -> Result<DamageFragility, FragilityError> {
    let need_table = states
        .states()
        .iter()
        .any(|s| s.criterion != Criterion::Overturned);
    let table = |m| {
        if need_table {
            laws.damage_table(im, m)
        } else {
            Ok(None)
        }
    };
    let fractile_table = table(FitMethod::Fractile)?;
    let mle_table = table(FitMethod::MaxLikelihood)?;
    let mut warnings = super::fragility::alpha_warning(block, auto_tol)
        .into_iter()
        .collect::<Vec<_>>();
    let mut out = Vec::with_capacity(states.states().len());
    for s in states.states() {
        let from_table =
            |t: &Option<DamageTable>, w: &mut Vec<String>| -> Result<_, FragilityError> {
                let Some(t) = t else { return Ok(None) };
                let l = t.capacity(block, s)?;
                w.extend(l.warnings);
                Ok(Some(Lognormal {
                    median: l.median,
                    beta: l.beta,
                }))
            };
        let (fractile, mle) = match s.criterion {
            Criterion::Overturned => {
                let l = match overturning(block, im, laws, auto_tol, &mut warnings) {
                    Ok(l) => l,
                    // A study too small for a regression: its damage table.
                    Err(FragilityError::NoFit { .. }) if fractile_table.is_some() => {
                        from_table(&fractile_table, &mut warnings)?.expect("a table")
                    }
                    Err(e) => return Err(e),
                };
                // The table's overturning by maximum likelihood, where it has one.
                let mle = from_table(&mle_table, &mut Vec::new()).ok().flatten();
                (Some(l), mle)
            }
            Criterion::Rotation(_) => {
                let Some(f) = from_table(&fractile_table, &mut warnings)? else {
                    return Err(FragilityError::StatesNeedRecords {
                        from: laws.name.clone(),
                        state: s.name.clone(),
                    });
                };
                (
                    Some(f),
                    from_table(&mle_table, &mut Vec::new()).ok().flatten(),
                )
            }
        };
        out.push(StateFragility {
            name: s.name.clone(),
            criterion: s.describe(),
            threshold: s.threshold(),
            fractile,
            mle,
            reached: None,
        });
    }
    warnings.sort();
    warnings.dedup();
    Ok(DamageFragility {
        im: im.name(),
        unit: im.unit(),
        source: laws.name.clone(),
        records: None,
        model: None,
        states: out,
        warnings,
    })
}

/// Overturning's lognormal from the regression (PGA) or the IM table.
fn overturning(
    block: &Block,
    im: Im,
    laws: &Laws,
    auto_tol: f64,
    warnings: &mut Vec<String>,
) -> Result<Lognormal, FragilityError> {
    if im == Im::Pga {
        let (eta50, beta) = laws.median_beta(block)?;
        warnings.extend(super::fragility::warnings(block, auto_tol));
        Ok(Lognormal {
            median: block.alpha() / eta50,
            beta,
        })
    } else {
        let l = laws.im_table(im)?.capacity(block)?;
        warnings.extend(l.warnings);
        Ok(Lognormal {
            median: l.median,
            beta: l.beta,
        })
    }
}

fn from_records(
    block: &Block,
    states: &DamageStates,
    im: Im,
    records: &DirectRecords,
    auto_tol: f64,
) -> Result<DamageFragility, FragilityError> {
    let def = DIRECT_FRACTILE;
    let (runs, why) = records.runs(block, auto_tol)?;
    let alpha = block.alpha();
    let ims = (im != Im::Pga).then(|| records.ims());
    let per_record: Vec<Vec<StateCapacity>> = runs
        .iter()
        .map(|c| {
            let points = c.points.iter();
            let runs = points.map(|p| (p.eta, p.outcome.max_abs_x, p.outcome.overturned()));
            damage::capacities(states, runs, c.eta_c)
        })
        .collect();
    let n = states.states().len();
    let fits = match ims {
        None => damage::fit_states(
            n,
            &per_record,
            |_, eta| Some(im::pga_of_eta(eta, alpha)),
            def,
        ),
        Some(ims) => damage::fit_states(
            n,
            &per_record,
            |k, eta| im::of_eta(im, eta, alpha, &ims[k]),
            def,
        ),
    }
    .ok_or(FragilityError::NoPeriod(im.name()))?;
    let out = states
        .states()
        .iter()
        .zip(fits)
        .map(|(s, f)| StateFragility {
            name: s.name.clone(),
            criterion: s.describe(),
            threshold: s.threshold(),
            fractile: f.fractile,
            mle: f.mle,
            reached: Some(f.reached),
        })
        .collect();
    Ok(DamageFragility {
        im: im.name(),
        unit: im.unit(),
        source: "direct".into(),
        records: Some(runs.len()),
        model: Some(why),
        states: out,
        warnings: Vec::new(),
    })
}

/// Warnings where a heavier state's fitted curve (by `method`) rises above
/// a lighter one's.
pub fn crossings(f: &DamageFragility, method: FitMethod) -> Vec<String> {
    f.states
        .windows(2)
        .filter_map(|w| {
            let (x, p) = crate::damage::crossing(&w[0].by(method)?, &w[1].by(method)?)?;
            Some(format!(
                "the fitted curves of `{}` and `{}` cross at {} {} (P = {:.2} %): on one side \
                 the heavier state is the likelier, which no record is; there OpenQuake gives a \
                 state a negative share and pelicun (capacities sampled together) counts it in \
                 the heavier state",
                w[0].name,
                w[1].name,
                crate::im::level_text(x),
                f.unit,
                100.0 * p
            ))
        })
        .collect()
}

/// `fragility --states`: each state's probability of being reached at
/// each level, by one method.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StatesAssessment {
    pub b_m: f64,
    pub h_m: f64,
    pub alpha_rad: f64,
    pub p: f64,
    pub eps: f64,
    /// `fractile` or `mle`: the fit the probabilities use.
    pub method: &'static str,
    pub fragility: DamageFragility,
    pub points: Vec<StatesPoint>,
}

/// One level: P(state reached | IM = iml) for each state, in order; `None`
/// where the method has no fit of the state.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StatesPoint {
    pub iml: f64,
    pub probabilities: Vec<Option<f64>>,
}

/// The block's damage-state fragilities at the request's levels.
pub fn assess(
    req: &Request,
    states: &DamageStates,
    method: FitMethod,
) -> Result<StatesAssessment, FragilityError> {
    let block = super::fragility::check(req)?;
    let (laws, records) = super::fragility::laws_and_records(
        &req.from,
        req.direct,
        &req.progress,
        1,
        req.floor.as_ref(),
    )?;
    let mut fragility = of_block(
        &block,
        states,
        req.im,
        &laws,
        records.as_ref(),
        req.auto_tol,
    )?;
    let crossed = crossings(&fragility, method);
    fragility.warnings.extend(crossed);
    if let Some(mu) = req
        .mu
        .filter(|&mu| crate::block::slides_first(mu, block.alpha()))
    {
        fragility
            .warnings
            .push(crate::block::sliding_warning(mu, block.alpha()));
    }
    let points = req
        .levels
        .iter()
        .map(|&x| StatesPoint {
            iml: x,
            probabilities: fragility
                .states
                .iter()
                .map(|s| s.by(method).map(|l| l.cdf(x)))
                .collect(),
        })
        .collect();
    Ok(StatesAssessment {
        b_m: req.b_m,
        h_m: req.h_m,
        alpha_rad: block.alpha(),
        p: block.p(),
        eps: block.eps,
        method: method.name(),
        fragility,
        points,
    })
}
