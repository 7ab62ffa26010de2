//! `risk --gmf DIR`: risk from OpenQuake's event-based ground-motion
//! fields. Each block's one fragility evaluated at every event's motion at
//! every site; the annual rate as OpenQuake's event-based damage states it
//! (Σ over events ÷ the effective investigation time); how many items of
//! the inventory fall in one event ([`crate::events`]); and, with
//! `--vector`, the two-parameter fragility P(OT | PGA, PGV/PGA) beside the
//! scalar one. docs/MODEL.md §20.

use serde::Serialize;

use super::answer::{BlockInfo, FragilityInfo};
use super::error::RiskError;
use super::fields::read_fields;
use super::inventory::entries;
use super::request::{EventsAsk, Request};
use crate::events::{self, Together};
use crate::gmf::Fields;
use crate::im::Im;
use crate::ops::damage;
use crate::ops::fragility::{self, RunModel};

/// Above this many sites the count over every site together (one
/// convolution per site per event) is not stated; each site's is.
pub const MAX_TOTAL_SITES: usize = 50;

/// The return periods (years) at which the number of items is stated.
pub const RETURN_PERIODS: [f64; 5] = [50.0, 100.0, 475.0, 975.0, 2475.0];

/// One block at one site.
#[derive(Debug, Clone, Serialize)]
pub struct EventSite {
    pub site: usize,
    /// OpenQuake's `custom_site_id`.
    pub id: String,
    pub lon: f64,
    pub lat: f64,
    /// Σ over events of P(OT | the event's IM) ÷ the effective time (1/year).
    pub annual_rate: f64,
    pub return_period_years: Option<f64>,
    pub p_overturn_in_years: f64,
    /// With `--vector`: the same by P(OT | PGA, PGV/PGA).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub annual_rate_vector: Option<f64>,
}

/// With `--states`: one damage state's rate at every site (1/year), from
/// its fragility as `risk --states` makes it.
#[derive(Debug, Clone, Serialize)]
pub struct StateRates {
    pub state: String,
    pub criterion: String,
    pub annual_rates: Vec<f64>,
}

/// One block at every site.
#[derive(Debug, Clone, Serialize)]
pub struct EventsBlock {
    pub block: BlockInfo,
    pub fragility: FragilityInfo,
    /// With `--vector`: the two-parameter capacity of the block.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vector: Option<crate::im::efficiency::VectorFit>,
    pub sites: Vec<EventSite>,
    /// With `--states`: each state's rate at each site.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub states: Vec<StateRates>,
}

/// How many of the inventory's items fall in one event, at one site or
/// over all sites.
#[derive(Debug, Clone, Serialize)]
pub struct Counts {
    /// The site (index); `None`: every site together.
    pub site: Option<usize>,
    pub items: usize,
    /// The expected number that fall in one event, and per year.
    pub expected_per_event: f64,
    pub expected_per_year: f64,
    /// The rate (1/year) of k or more items falling in one event, k = 0, 1, …
    pub rate_at_least: Vec<f64>,
    /// (return period in years, the number of items at it).
    pub at_return_periods: Vec<(f64, usize)>,
}

/// The answer.
#[derive(Debug, Clone, Serialize)]
pub struct EventsAssessment {
    pub gmf: String,
    pub events: usize,
    /// The effective investigation time (years) and where it came from.
    pub eff_years: f64,
    pub eff_years_from: String,
    pub im: String,
    pub unit: &'static str,
    pub together: Together,
    pub years: f64,
    pub blocks: Vec<EventsBlock>,
    /// Per site, then (with several sites) all sites together (sites apart
    /// are independent given their fields).
    pub counts: Vec<Counts>,
    pub warnings: Vec<String>,
}

/// Each (event, site)'s value of `im` (0 where OpenQuake wrote none, below
/// its minimum intensity), event-major.
fn values_of(fields: &Fields, im: Im) -> Option<Vec<f64>> {
    let k = fields.ims.iter().position(|&i| i == im)?;
    let n = fields.sites.len();
    let mut out = vec![0.0; fields.events.len() * n];
    for (e, s, v) in &fields.values {
        out[e * n + s] = v[k];
    }
    Some(out)
}

/// Where the fields' values of `im` look like another unit (the rule of
/// the hazard's IMLs, [`crate::hazard::unit_slip`]): their median where
/// OpenQuake wrote one (above its minimum intensity) and their largest.
fn unit_slip(values: &[f64], im: Im) -> Option<String> {
    let mut written: Vec<f64> = values.iter().copied().filter(|&v| v > 0.0).collect();
    written.sort_by(f64::total_cmp);
    let (median, largest) = (*written.get(written.len() / 2)?, *written.last()?);
    let range = format!(
        "the fields' {} has a median of {} {unit} where written, and reaches {} {unit}",
        im.short(),
        crate::im::level_text(median),
        crate::im::level_text(largest),
        unit = im.unit()
    );
    crate::hazard::unit_slip(im, median, largest, &range)
}

/// Assesses every block at every site of the fields.
pub fn assess_events(req: &Request, ask: &EventsAsk) -> Result<EventsAssessment, RiskError> {
    crate::physics::check_auto_tol(req.auto_tol).map_err(RiskError::AutoTol)?;
    super::check_years(req.years)?;
    if req.site.is_some() || req.component.is_some() {
        return Err(RiskError::Gmf(
            "--site and --component are a hazard file's; --gmf states every site of the fields, \
             in OpenQuake's IMTs"
                .into(),
        ));
    }
    let super::fields::ReadFields {
        fields,
        eff_years,
        from,
        warnings: job_warnings,
    } = read_fields(ask)?;
    let im = req.im.unwrap_or(Im::Pga);
    let values = values_of(&fields, im).ok_or_else(|| {
        RiskError::Gmf(format!(
            "{}: the fields have no {} (they have {})",
            ask.dir.display(),
            im.short(),
            fields
                .ims
                .iter()
                .map(|i| i.short())
                .collect::<Vec<_>>()
                .join(", ")
        ))
    })?;
    let vector_values = match ask.vector {
        true => Some(
            values_of(&fields, Im::Pga)
                .zip(values_of(&fields, Im::Pgv))
                .ok_or_else(|| RiskError::Gmf("--vector needs the fields' PGA and PGV".into()))?,
        ),
        false => None,
    };
    let blocks = entries(&req.blocks)?;
    let (laws, records) = fragility::laws_and_records(
        &req.from,
        req.direct,
        &req.progress,
        blocks.len(),
        req.floor.as_ref(),
        req.orient,
    )?;
    let (n_sites, n_events) = (fields.sites.len(), fields.events.len());
    let at = At {
        fields: &fields,
        eff_years,
        im,
        values: &values,
        vector_values: vector_values.as_ref(),
        laws: &laws,
        records: records.as_ref(),
    };
    // Each block's P at every (event, site).
    let mut probs: Vec<Vec<f64>> = Vec::with_capacity(blocks.len());
    let mut out = Vec::with_capacity(blocks.len());
    let mut warnings: Vec<String> = job_warnings;
    warnings.extend(unit_slip(&values, im));
    for e in &blocks {
        let (mut b, p) = one_block(req, e, &at, &mut warnings)?;
        if let Some(states) = &ask.states {
            b.states = state_rates(req, e, &at, states)?;
        }
        out.push(b);
        probs.push(p);
    }
    let counts = counts(&probs, n_events, n_sites, eff_years, ask.together);
    Ok(EventsAssessment {
        gmf: ask.dir.display().to_string(),
        events: n_events,
        eff_years,
        eff_years_from: from,
        im: im.name(),
        unit: im.unit(),
        together: ask.together,
        years: req.years,
        blocks: out,
        counts,
        warnings,
    })
}

/// What every block's assessment over the fields shares.
struct At<'a> {
    fields: &'a Fields,
    eff_years: f64,
    im: Im,
    /// `im` at every (event, site), event-major; PGA and PGV for `--vector`.
    values: &'a [f64],
    vector_values: Option<&'a (Vec<f64>, Vec<f64>)>,
    laws: &'a fragility::Laws,
    records: Option<&'a fragility::DirectRecords>,
}

/// One block over the fields: its answer, and its P at every (event, site).
fn one_block(
    req: &Request,
    e: &super::InventoryBlock,
    at: &At,
    warnings: &mut Vec<String>,
) -> Result<(EventsBlock, Vec<f64>), RiskError> {
    let (fields, eff_years, im, values) = (at.fields, at.eff_years, at.im, at.values);
    let (records, vector_values) = (at.records, at.vector_values);
    let n_sites = fields.sites.len();
    let in_block = |source| RiskError::Block {
        name: e.name.clone(),
        source,
    };
    let fit = crate::damage::FitChoice {
        dispersion: crate::damage::Dispersion::Each,
        ..req.fit()
    };
    let overturning = crate::damage::DamageStates::overturning();
    let (block, f, cut) = fragility_at(req, e, at, &overturning, fit).map_err(in_block)?;
    let (frag, info) = super::assess::stated(&f, im).map_err(in_block)?;
    let p = probabilities(values, cut, &frag);
    let (vector, pv) = vector_of(req, e, &block, vector_values, records).map_err(|e| match e {
        VectorError::Block(source) => in_block(source),
        VectorError::Other(e) => e,
    })?;
    if let (Some(v), Some(pv)) = (&vector, &pv) {
        warnings.extend(extrapolation(v, pv, vector_values, &e.name));
    }
    let rates = site_rates(&p, n_sites, eff_years);
    let vector_rates = pv.as_ref().map(|pv| site_rates(pv, n_sites, eff_years));
    let sites = fields
        .sites
        .iter()
        .enumerate()
        .map(|(s, site)| {
            let annual_rate = rates[s];
            EventSite {
                site: s,
                id: site.id.clone(),
                lon: site.lon,
                lat: site.lat,
                annual_rate,
                return_period_years: (annual_rate > 0.0).then(|| 1.0 / annual_rate),
                p_overturn_in_years: crate::risk::probability_in(annual_rate, req.years),
                annual_rate_vector: vector_rates.as_ref().map(|r| r[s]),
            }
        })
        .collect();
    warnings.extend(f.warnings.iter().map(|w| format!("block {}: {w}", e.name)));
    if vector_values.is_some() && vector.is_none() {
        warnings.push(format!(
            "block {}: no vector fragility: fewer than 4 records overturn it, or one PGV/PGA for all",
            e.name
        ));
    }
    let info_block = super::assess::block_info(e, &block, records.and_then(|r| r.floor()));
    warnings.extend(
        f.unmodelled_sliding(e.mu, block.alpha())
            .map(|w| format!("block {}: {w}", e.name)),
    );
    let b = EventsBlock {
        block: info_block,
        fragility: info,
        vector,
        sites,
        states: Vec::new(),
    };
    Ok((b, p))
}

/// Each damage state's rate at every site: the block's states' fragilities
/// (one β by default, so that they never cross) at every event's motion.
fn state_rates(
    req: &Request,
    e: &super::InventoryBlock,
    at: &At,
    states: &crate::damage::DamageStates,
) -> Result<Vec<StateRates>, RiskError> {
    let in_block = |source| RiskError::Block {
        name: e.name.clone(),
        source,
    };
    let (_, f, cut) = fragility_at(req, e, at, states, req.fit()).map_err(in_block)?;
    let n_sites = at.fields.sites.len();
    f.states
        .iter()
        .map(|s| {
            let frag = s
                .fragility(f.method)
                .ok_or_else(|| in_block(damage::no_fit(&f, s, f.method)))?;
            Ok(StateRates {
                state: s.name.clone(),
                criterion: s.criterion.clone(),
                annual_rates: site_rates(
                    &probabilities(at.values, cut, &frag),
                    n_sites,
                    at.eff_years,
                ),
            })
        })
        .collect()
}

/// `frag` at every (event, site) value: 0 below `cut` and where the
/// fields have no motion.
fn probabilities(values: &[f64], cut: f64, frag: &crate::risk::Fragility) -> Vec<f64> {
    values
        .iter()
        .map(|&x| {
            if x <= 0.0 {
                0.0
            } else {
                crate::cut::probability_above(frag, x, Some(cut))
            }
        })
        .collect()
}

/// Each site's rate (1/year) from P at every (event, site), event-major:
/// Σ over events ÷ the effective time, as OpenQuake's event-based damage.
fn site_rates(p: &[f64], n_sites: usize, eff_years: f64) -> Vec<f64> {
    let n_events = p.len() / n_sites.max(1);
    (0..n_sites)
        .map(|s| (0..n_events).map(|ev| p[ev * n_sites + s]).sum::<f64>() / eff_years)
        .collect()
}

/// The block of inventory line `e`, its one fragility for `states` (on its
/// μ) and the level below which `risk` counts nothing.
fn fragility_at(
    req: &Request,
    e: &super::InventoryBlock,
    at: &At,
    states: &crate::damage::DamageStates,
    fit: crate::damage::FitChoice,
) -> Result<(crate::block::Block, damage::DamageFragility, f64), fragility::FragilityError> {
    let block = fragility::block(e.b_m, e.h_m, e.eps)?;
    let model = RunModel::of_command(req.auto_tol, at.records).on(e.mu);
    let f = damage::of_block(&block, states, at.im, at.laws, at.records, model, fit)?;
    let floor = at.records.and_then(|r| r.floor());
    let cut = damage::zero_below(&block, at.im, floor, f.slides_on_mu).unwrap_or(0.0);
    Ok((block, f, cut))
}

/// Why a block has no vector fragility.
enum VectorError {
    Block(crate::ops::fragility::FragilityError),
    Other(RiskError),
}

/// With `--vector`: the block's two-parameter capacity from the records'
/// runs, and its P at every (event, site) (0 below its uplift PGA).
fn vector_of(
    req: &Request,
    e: &super::InventoryBlock,
    block: &crate::block::Block,
    vector_values: Option<&(Vec<f64>, Vec<f64>)>,
    records: Option<&fragility::DirectRecords>,
) -> Result<(Option<crate::im::efficiency::VectorFit>, Option<Vec<f64>>), VectorError> {
    let Some((pga, pgv)) = vector_values else {
        return Ok((None, None));
    };
    let Some(r) = records else {
        return Err(VectorError::Other(RiskError::Gmf(
            "--vector fits P(OT | PGA, PGV/PGA) to the records' own capacities: add --direct"
                .into(),
        )));
    };
    // The block's one model (sliding where it can, on its μ), as its
    // scalar fragility's.
    let model = RunModel::of_command(req.auto_tol, Some(r)).on(e.mu);
    let (caps, _) = r.capacities(block, model).map_err(VectorError::Block)?;
    let (ran, _) = model.resolve(block).map_err(VectorError::Block)?;
    let eta: Vec<Option<f64>> = caps.iter().map(|&c| (c > 0.0).then_some(c)).collect();
    let Some(v) = crate::im::efficiency::vector_of_block(&eta, r.ims()) else {
        return Ok((None, None));
    };
    // The block cannot move below the level `risk` cuts at, whatever the IM:
    // the scalar rate's cut ([`fragility_at`]), none on a floor that filters.
    let slides_on_mu = ran.equation.friction().map(|f| f.mu_s);
    let uplift = damage::zero_below(block, Im::Pga, r.floor(), slides_on_mu).unwrap_or(0.0);
    let p = pga
        .iter()
        .zip(pgv)
        .map(|(&a, &g)| {
            if a < uplift {
                0.0
            } else {
                v.probability(block.alpha(), a, g)
            }
        })
        .collect();
    Ok((Some(v), Some(p)))
}

/// The count distributions: per site (the items of the inventory there,
/// falling together as `together` says), and over all sites (independent
/// given their fields: the convolution).
fn counts(
    probs: &[Vec<f64>],
    n_events: usize,
    n_sites: usize,
    eff_years: f64,
    together: Together,
) -> Vec<Counts> {
    let items = probs.len();
    let mut per_site: Vec<Vec<Vec<f64>>> = vec![Vec::with_capacity(n_events); n_sites];
    let mut all: Vec<Vec<f64>> = Vec::with_capacity(n_events);
    let total_too = n_sites <= MAX_TOTAL_SITES;
    for ev in 0..n_events {
        let mut total = vec![1.0];
        for (s, site) in per_site.iter_mut().enumerate() {
            let p: Vec<f64> = probs.iter().map(|b| b[ev * n_sites + s]).collect();
            // Its zeros past the last count it can reach dropped (most
            // events overturn few items): convolutions and sums over them
            // are unchanged to the bit, the rates padded back below.
            let mut pmf = events::count_pmf(&p, together);
            while pmf.len() > 1 && pmf.last() == Some(&0.0) {
                pmf.pop();
            }
            if total_too {
                total = events::convolve(&total, &pmf);
            }
            site.push(pmf);
        }
        all.push(total);
    }
    let stated = |site: Option<usize>, pmfs: &[Vec<f64>], n: usize| {
        let mut rates = events::exceedance_rates(pmfs, eff_years);
        if !pmfs.is_empty() {
            // As long as the untrimmed pmfs' (no events: one rate, of 0).
            rates.resize(n + 1, 0.0);
        }
        let mean_per_event: f64 = pmfs
            .iter()
            .map(|pmf| {
                pmf.iter()
                    .enumerate()
                    .map(|(k, q)| k as f64 * q)
                    .sum::<f64>()
            })
            .sum::<f64>()
            / pmfs.len().max(1) as f64;
        Counts {
            site,
            items: n,
            expected_per_event: mean_per_event,
            expected_per_year: mean_per_event * pmfs.len() as f64 / eff_years,
            at_return_periods: RETURN_PERIODS
                .iter()
                .map(|&t| (t, events::number_at(&rates, t)))
                .collect(),
            rate_at_least: rates,
        }
    };
    let mut out: Vec<Counts> = per_site
        .iter()
        .enumerate()
        .map(|(s, pmfs)| stated(Some(s), pmfs, items))
        .collect();
    if n_sites > 1 && n_sites <= MAX_TOTAL_SITES {
        out.push(stated(None, &all, items * n_sites));
    }
    out
}

/// The share of the vector rate from events whose PGV/PGA lies outside the
/// records' range, as a warning when it is over a tenth.
fn extrapolation(
    v: &crate::im::efficiency::VectorFit,
    pv: &[f64],
    fields: Option<&(Vec<f64>, Vec<f64>)>,
    name: &str,
) -> Option<String> {
    let (pga, pgv) = fields?;
    let (lo, hi) = v.ratio_range_s;
    let (mut outside, mut total, mut all, mut beyond) = (0.0, 0.0, 0usize, 0usize);
    for ((&p, &a), &g) in pv.iter().zip(pga).zip(pgv) {
        if a <= 0.0 || g <= 0.0 {
            continue;
        }
        let r = crate::im::pgv_pga_s(a, g);
        all += 1;
        total += p;
        if !(lo..=hi).contains(&r) {
            outside += p;
            beyond += 1;
        }
    }
    let share = if total > 0.0 {
        outside / total
    } else {
        beyond as f64 / all.max(1) as f64
    };
    (share > 0.1).then(|| {
        format!(
            "block {name}: {:.0} % of the vector rate (and {beyond} of {all} motions) comes from \
             PGV/PGA outside the records' {lo:.3}–{hi:.3} s, where P(OT | PGA, PGV/PGA) is an \
             extrapolation of their regression",
            100.0 * share
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The counts with the pmfs' zero tails dropped and items of pᵢ = 0
    /// skipped are those of the dense computation, to the bit: each pmf by
    /// the Poisson-binomial recursion (or the same-record rule) over every
    /// item, the sites convolved over their full lengths. Most items feel
    /// nothing in most events here (p = 0), as in a real inventory.
    #[test]
    fn counts_are_the_dense_computation_s() {
        let (n_events, n_sites, items) = (40, 3, 25);
        let probs: Vec<Vec<f64>> = (0..items)
            .map(|b| {
                (0..n_events * n_sites)
                    .map(|k| {
                        let x = ((b * 7919 + k * 104_729) % 1000) as f64 / 1000.0;
                        if x < 0.8 {
                            0.0
                        } else {
                            (x - 0.8) * 5.0
                        }
                    })
                    .collect()
            })
            .collect();
        let dense_pmf = |p: &[f64], together: Together| -> Vec<f64> {
            match together {
                Together::Independent => {
                    let mut pmf = vec![0.0; p.len() + 1];
                    pmf[0] = 1.0;
                    for (i, &q) in p.iter().enumerate() {
                        for k in (0..=i + 1).rev() {
                            let from = if k > 0 { pmf[k - 1] * q } else { 0.0 };
                            pmf[k] = pmf[k] * (1.0 - q) + from;
                        }
                    }
                    pmf
                }
                Together::SameRecord => events::count_pmf(p, together),
            }
        };
        for together in [Together::Independent, Together::SameRecord] {
            let fast = counts(&probs, n_events, n_sites, 50.0, together);
            let mut per_site = vec![Vec::new(); n_sites];
            let mut all = Vec::new();
            for ev in 0..n_events {
                let mut total = vec![1.0];
                for (s, site) in per_site.iter_mut().enumerate() {
                    let p: Vec<f64> = probs.iter().map(|b| b[ev * n_sites + s]).collect();
                    let pmf = dense_pmf(&p, together);
                    total = events::convolve(&total, &pmf);
                    site.push(pmf);
                }
                all.push(total);
            }
            let mut pmfs: Vec<&Vec<Vec<f64>>> = per_site.iter().collect();
            pmfs.push(&all);
            assert_eq!(fast.len(), n_sites + 1);
            for (c, pmfs) in fast.iter().zip(pmfs) {
                let rates = events::exceedance_rates(pmfs, 50.0);
                assert_eq!(c.rate_at_least, rates, "{together:?}, site {:?}", c.site);
                let mean: f64 = pmfs
                    .iter()
                    .map(|pmf| {
                        pmf.iter()
                            .enumerate()
                            .map(|(k, q)| k as f64 * q)
                            .sum::<f64>()
                    })
                    .sum::<f64>()
                    / n_events as f64;
                assert_eq!(c.expected_per_event, mean);
            }
            // Some events do overturn items: the test is not of zeros alone.
            assert!(fast[0].expected_per_event > 0.1);
        }
    }
}
