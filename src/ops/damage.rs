//! A block's fragility for each damage state, in one IM: from the records'
//! own runs (`--direct`: every state, both fits), or from a regression
//! (the paper's or a pipeline's: overturning only).

use super::fragility::{warnings, DirectRecords, FragilityError, Laws};
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

/// The block's fragility for each of `states` in `im`.
pub fn of_block(
    block: &Block,
    states: &DamageStates,
    im: Im,
    laws: &Laws,
    direct: Option<&DirectRecords>,
    def: FractileDef,
    auto_tol: f64,
) -> Result<DamageFragility, FragilityError> {
    match direct {
        Some(records) => from_records(block, states, im, records, def, auto_tol),
        None => from_regression(block, states, im, laws, auto_tol),
    }
}

fn from_regression(
    block: &Block,
    states: &DamageStates,
    im: Im,
    laws: &Laws,
    auto_tol: f64,
) -> Result<DamageFragility, FragilityError> {
    if let Some(s) = states
        .states()
        .iter()
        .find(|s| s.criterion != Criterion::Overturned)
    {
        return Err(FragilityError::StatesNeedRecords {
            from: laws.name.clone(),
            state: s.name.clone(),
        });
    }
    let (lognormal, w) = if im == Im::Pga {
        let (eta50, beta) = laws.median_beta(block)?;
        let l = Lognormal {
            median: block.alpha() / eta50,
            beta,
        };
        (l, warnings(block, auto_tol))
    } else {
        let l = laws.im_table(im)?.capacity(block)?;
        let mut w = l.warnings;
        w.extend(super::fragility::alpha_warning(block, auto_tol));
        (
            Lognormal {
                median: l.median,
                beta: l.beta,
            },
            w,
        )
    };
    Ok(DamageFragility {
        im: im.name(),
        unit: im.unit(),
        source: laws.name.clone(),
        records: None,
        model: None,
        states: states
            .states()
            .iter()
            .map(|s| StateFragility {
                name: s.name.clone(),
                criterion: s.describe(),
                threshold: None,
                fractile: Some(lognormal),
                mle: None,
                reached: None,
            })
            .collect(),
        warnings: w,
    })
}

fn from_records(
    block: &Block,
    states: &DamageStates,
    im: Im,
    records: &DirectRecords,
    def: FractileDef,
    auto_tol: f64,
) -> Result<DamageFragility, FragilityError> {
    let (runs, why) = records.runs(block, auto_tol)?;
    let alpha = block.alpha();
    let ims = (im != Im::Pga).then(|| records.ims());
    let in_im = |eta: f64, k: usize| -> Result<f64, FragilityError> {
        match ims {
            None => Ok(im::pga_of_eta(eta, alpha)),
            Some(ims) => {
                im::of_eta(im, eta, alpha, &ims[k]).ok_or(FragilityError::NoPeriod(im.name()))
            }
        }
    };
    let per_record: Vec<Vec<StateCapacity>> = runs
        .iter()
        .map(|c| damage::capacities(states, &c.points, c.eta_c))
        .collect();
    let mut out = Vec::with_capacity(states.states().len());
    for (j, s) in states.states().iter().enumerate() {
        let (mut reached, mut censored, mut all) = (Vec::new(), Vec::new(), Vec::new());
        for (k, caps) in per_record.iter().enumerate() {
            match caps[j] {
                StateCapacity::Reached(eta) => {
                    let v = in_im(eta, k)?;
                    reached.push(v);
                    all.push(v);
                }
                StateCapacity::NotReached(eta) => {
                    censored.push(in_im(eta, k)?);
                    all.push(f64::INFINITY);
                }
            }
        }
        out.push(StateFragility {
            name: s.name.clone(),
            criterion: s.describe(),
            threshold: match s.criterion {
                Criterion::Rotation(x) => Some(x),
                Criterion::Overturned => None,
            },
            fractile: damage::fractile_method(&all, def),
            mle: damage::max_likelihood(&reached, &censored),
            reached: Some(reached.len()),
        });
    }
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
