//! `risk --states`: the annual rate at which each damage state is reached
//! at each site, from the states' lognormal fragilities
//! ([`crate::ops::damage`]) and the same hazard integral as overturning.

use serde::Serialize;

use super::answer::site_info;
use super::answer::BlockInfo;
use super::assess::{block_info, prepare, tails, Prepared};
use super::error::RiskError;
use super::request::Request;
use crate::damage::{DamageStates, FitMethod};
use crate::ops::damage;
use crate::ops::fragility;
use crate::risk;

/// One state at one site.
#[derive(Debug, Clone, Serialize)]
pub struct StateRisk {
    pub state: String,
    pub criterion: String,
    /// How its fragility is made: `fractile`, `mle`, `empirical`,
    /// `regression` or `moments`.
    pub fit: &'static str,
    /// The fragility's median (IM unit) and β (`None`: the method has no
    /// fit here, and no rate).
    pub median: Option<f64>,
    pub beta: Option<f64>,
    pub annual_rate: Option<f64>,
    pub return_period_years: Option<f64>,
    /// P(the state is reached at least once within `years`), Poisson.
    pub p_in_years: Option<f64>,
}

/// Every state at one site.
#[derive(Debug, Clone, Serialize)]
pub struct StatesSite {
    pub site: usize,
    pub lon: Option<f64>,
    pub lat: Option<f64>,
    pub states: Vec<StateRisk>,
}

/// One block's damage states at every site asked.
#[derive(Debug, Clone, Serialize)]
pub struct StatesAssessment {
    pub block: BlockInfo,
    /// `paper`, the pipeline file, or `direct`.
    pub source: String,
    pub im: String,
    pub unit: &'static str,
    /// `fractile`, `mle` or `empirical`: the fit integrated.
    pub method: &'static str,
    /// `common` (one β for the states) or `each`.
    pub dispersion: &'static str,
    /// The records folder `--direct` ran the blocks through.
    pub records_folder: Option<String>,
    pub records: Option<usize>,
    /// With `--direct`: the equation the records ran (`slide-rock` for a
    /// block with μ).
    pub equation: Option<&'static str>,
    pub years: f64,
    pub beyond: &'static str,
    pub sites: Vec<StatesSite>,
    pub warnings: Vec<String>,
}

/// Every block asked, each of `states` by `method`, at every site asked.
pub fn assess_states(
    req: &Request,
    states: &DamageStates,
    method: FitMethod,
) -> Result<Vec<StatesAssessment>, RiskError> {
    let Prepared {
        sites,
        im,
        entries,
        laws,
        records,
        warnings: hazard_notes,
    } = prepare(req)?;
    let mut out = Vec::new();
    for e in entries {
        let in_block = |source| RiskError::Block {
            name: e.name.clone(),
            source,
        };
        let block = fragility::block(e.b_m, e.h_m, e.eps).map_err(in_block)?;
        let mut f = damage::of_block(
            &block,
            states,
            im,
            &laws,
            records.as_ref(),
            crate::ops::fragility::RunModel::of_command(req.auto_tol, records.as_ref()).on(e.mu),
            crate::damage::FitChoice {
                method,
                ..req.fit()
            },
        )
        .map_err(in_block)?;
        let method = f.method;
        let floor = records.as_ref().and_then(|r| r.floor());
        let cut = damage::zero_below(&block, im, floor, f.slides_on_mu);
        let crossed = damage::crossings(&f, method, cut);
        let cut = cut.unwrap_or(0.0);
        f.warnings.extend(crossed);
        let unit = im.unit();
        let mut tail_notes = Vec::new();
        let sites = sites
            .iter()
            .map(|(k, curve)| StatesSite {
                site: *k,
                lon: curve.lon,
                lat: curve.lat,
                states: f
                    .states
                    .iter()
                    .map(|s| {
                        let (median, beta) = s.median_beta(method);
                        let rate = s.fragility(method).map(|frag| {
                            let r = risk::assess_above(curve, &frag, req.beyond, cut);
                            let info = site_info(*k, curve, &r, req.years);
                            tail_notes.extend(tails(&info, unit, Some(&s.name)));
                            r.annual_rate
                        });
                        StateRisk {
                            state: s.name.clone(),
                            criterion: s.criterion.clone(),
                            fit: s.fit_name(method),
                            median,
                            beta,
                            annual_rate: rate,
                            return_period_years: rate.filter(|r| *r > 0.0).map(|r| 1.0 / r),
                            p_in_years: rate.map(|r| risk::probability_in(r, req.years)),
                        }
                    })
                    .collect(),
            })
            .collect();
        let assessed = block_info(&e, &block, floor);
        f.warnings.extend(hazard_notes.iter().cloned());
        f.warnings.extend(tail_notes);
        f.warnings.extend(f.unmodelled_sliding(e.mu, block.alpha()));
        out.push(StatesAssessment {
            block: assessed,
            source: f.source,
            im: f.im,
            unit: f.unit,
            method: method.name(),
            dispersion: f.dispersion,
            records_folder: f.records_folder.clone(),
            records: f.records,
            equation: f.equation,
            years: req.years,
            beyond: crate::label::Label::label(req.beyond),
            sites,
            warnings: f.warnings,
        });
    }
    Ok(out)
}
