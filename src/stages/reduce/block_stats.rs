//! The statistics of one block over its records, by the rule the reduce
//! stage applies to every block: horizontal fractiles and overturning
//! fractions, vertical fractiles, capacity fractiles and the lognormal check.

use super::error::ReduceError;
use crate::pipeline::{BlockSpec, Plan, RecordsPlan};
use crate::stages::sweep;
use crate::stats;
use crate::stats::FractileDef;
use crate::tables::reduce::{
    CapacityFractileRow, HorizontalRow, LognormalRow, OverturnFractionRow, VerticalRow,
};
use crate::tables::sweep::{CapacityRow, IdaRow};

pub const QUANTILES: [f64; 3] = [0.16, 0.5, 0.84];
/// EDP levels of the vertical statistics: 0.05, 0.10, …, 1.
pub const EDP_LEVELS: usize = 20;

/// One record's IDA for one block, at the grid levels.
pub(super) struct RecordIda<'a> {
    pub(super) cap: &'a CapacityRow,
    /// (η, EDP, overturned) at the grid levels that were run, in order.
    levels: Vec<(f64, f64, bool)>,
    /// Index of the first level that overturned.
    first_over: Option<usize>,
}

impl<'a> RecordIda<'a> {
    /// A case's capacity and its runs (any order of kinds; levels in order).
    pub(super) fn new(cap: &'a CapacityRow, runs: &[&IdaRow]) -> RecordIda<'a> {
        let levels: Vec<(f64, f64, bool)> = runs
            .iter()
            .filter(|r| sweep::is_level(r))
            .map(|r| (r.eta, r.edp, r.overturned))
            .collect();
        let first_over = levels.iter().position(|l| l.2);
        RecordIda {
            cap,
            levels,
            first_over,
        }
    }
}

/// The plan's grid levels (a plan that resolved has a valid grid).
pub(super) fn grid_levels(plan: &RecordsPlan) -> Result<Vec<f64>, ReduceError> {
    plan.grid
        .levels()
        .map_err(|e| ReduceError::Mismatch(e.to_string()))
}

/// The IDA points of each of `n_cases` cases (case ids 0 … n_cases − 1),
/// in table order.
pub(in crate::stages) fn split_by_case(
    ida: &[IdaRow],
    n_cases: usize,
) -> Result<Vec<Vec<&IdaRow>>, ReduceError> {
    let mut by_case: Vec<Vec<&IdaRow>> = vec![Vec::new(); n_cases];
    for r in ida {
        let slot = usize::try_from(r.case_id)
            .ok()
            .and_then(|k| by_case.get_mut(k))
            .ok_or_else(|| {
                ReduceError::Mismatch(format!(
                    "IDA point of case {} beyond the capacities",
                    r.case_id
                ))
            })?;
        slot.push(r);
    }
    Ok(by_case)
}

/// The horizontal fractiles of one block, by the rule the stage applies to
/// every block, from its records' capacities (in record order) and runs
/// (cases numbered 0, 1, … as the capacities): the `example` stage's Fig. 5
/// curves.
pub(in crate::stages) fn horizontal_of_block(
    plan: &Plan,
    block: &BlockSpec,
    caps: &[CapacityRow],
    ida: &[IdaRow],
) -> Result<Vec<HorizontalRow>, ReduceError> {
    let plan = plan.records_study()?;
    let levels = grid_levels(plan)?;
    let by_case = split_by_case(ida, caps.len())?;
    let records: Vec<RecordIda> = caps
        .iter()
        .zip(&by_case)
        .map(|(c, runs)| RecordIda::new(c, runs))
        .collect();
    check_block(block, &records, levels.len())?;
    let mut out = Tables::default();
    horizontal(plan.fractile, block, &levels, &records, &mut out);
    Ok(out.horizontal)
}

/// Every output table, one row vector each.
#[derive(Default)]
pub(super) struct Tables {
    pub(super) horizontal: Vec<HorizontalRow>,
    pub(super) vertical: Vec<VerticalRow>,
    pub(super) capacity: Vec<CapacityFractileRow>,
    pub(super) lognormal: Vec<LognormalRow>,
    pub(super) fraction: Vec<OverturnFractionRow>,
    /// Blocks where lognormality is not rejected at 5 %, of those tested.
    pub(super) pass: (usize, usize),
}

pub(super) fn check_block(
    block: &BlockSpec,
    records: &[RecordIda],
    n_levels: usize,
) -> Result<(), ReduceError> {
    for r in records {
        if r.cap.p != block.p || r.cap.eps != block.eps {
            return Err(ReduceError::Mismatch(format!(
                "case {} is p = {}, ε = {} in the tables but p = {}, ε = {} in the pipeline",
                r.cap.case_id, r.cap.p, r.cap.eps, block.p, block.eps
            )));
        }
        let needed = r.first_over.map_or(n_levels, |f| f + 1);
        if r.levels.len() < needed {
            return Err(ReduceError::Mismatch(format!(
                "case {} has too few level runs",
                r.cap.case_id
            )));
        }
    }
    Ok(())
}

fn fractiles(sorted: &[f64], def: FractileDef) -> [f64; 3] {
    QUANTILES.map(|q| stats::fractile(sorted, q, def).expect("at least one record"))
}

/// Horizontal statistics (EDP given η, +∞ at and beyond a record's first
/// overturning) and overturning fractions; returns each level's η and EDP
/// fractiles for the capacity's horizontal counterpart.
pub(super) fn horizontal(
    def: FractileDef,
    block: &BlockSpec,
    levels: &[f64],
    records: &[RecordIda],
    out: &mut Tables,
) -> Vec<(f64, [f64; 3])> {
    let n_records = records.len();
    let mut h_q = Vec::with_capacity(levels.len());
    for (j, &eta) in levels.iter().enumerate() {
        let mut edp: Vec<f64> = records
            .iter()
            .map(|r| {
                if r.first_over.is_some_and(|fo| j >= fo) {
                    f64::INFINITY
                } else {
                    r.levels[j].1
                }
            })
            .collect();
        edp.sort_by(|a, b| a.total_cmp(b));
        let n_over = edp.iter().filter(|e| e.is_infinite()).count();
        let q = fractiles(&edp, def);
        out.horizontal.push(HorizontalRow {
            block: block.name.clone(),
            p: block.p,
            eps: block.eps,
            level: j as i64,
            eta,
            edp_q16: q[0],
            edp_q50: q[1],
            edp_q84: q[2],
            n_records: n_records as i64,
            n_overturned: n_over as i64,
        });
        h_q.push((eta, q));
        // Plain fraction: needs a run of every record at this level.
        let plain: Option<usize> = records
            .iter()
            .map(|r| r.levels.get(j).map(|l| usize::from(l.2)))
            .sum::<Option<usize>>();
        out.fraction.push(OverturnFractionRow {
            block: block.name.clone(),
            p: block.p,
            eps: block.eps,
            level: j as i64,
            eta,
            fraction_plain: plain.map(|c| c as f64 / n_records as f64),
            fraction_resurrection: n_over as f64 / n_records as f64,
        });
    }
    h_q
}

/// Vertical statistics: the first (largest) η at which each record's EDP reaches e.
pub(super) fn vertical(
    plan: &RecordsPlan,
    block: &BlockSpec,
    records: &[RecordIda],
    out: &mut Tables,
) {
    for k in 1..=EDP_LEVELS {
        let e = k as f64 / EDP_LEVELS as f64;
        let mut etas = Vec::with_capacity(records.len());
        let mut not_reached = 0;
        for r in records {
            match first_eta_reaching(r, plan.grid.eta_max, e) {
                Some(eta) => etas.push(eta),
                None => {
                    etas.push(0.0);
                    not_reached += 1;
                }
            }
        }
        etas.sort_by(|a, b| a.total_cmp(b));
        let q = fractiles(&etas, plan.fractile);
        out.vertical.push(VerticalRow {
            block: block.name.clone(),
            p: block.p,
            eps: block.eps,
            edp: e,
            eta_q16: q[0],
            eta_q50: q[1],
            eta_q84: q[2],
            n_records: records.len() as i64,
            n_not_reached: not_reached,
        });
    }
}

/// Capacity fractiles of η_c over the records (a record that never
/// overturned counts as η_c = 0, stronger than any level), and the
/// horizontal counterpart: the largest level whose EDP fractile is ≥ 1.
pub(super) fn capacity_fractiles(
    def: FractileDef,
    block: &BlockSpec,
    records: &[RecordIda],
    h_q: &[(f64, [f64; 3])],
    out: &mut Tables,
) -> [f64; 3] {
    let mut eta_c: Vec<f64> = records.iter().map(|r| r.cap.eta_c.unwrap_or(0.0)).collect();
    let censored = records.iter().filter(|r| r.cap.eta_c.is_none()).count();
    eta_c.sort_by(|a, b| a.total_cmp(b));
    let q_eta = fractiles(&eta_c, def);
    for (qi, &q) in QUANTILES.iter().enumerate() {
        let horiz = h_q
            .iter()
            .find(|(_, hq)| hq[qi] >= 1.0)
            .map(|(eta, _)| *eta);
        out.capacity.push(CapacityFractileRow {
            block: block.name.clone(),
            p: block.p,
            eps: block.eps,
            quantile: q,
            eta_c: q_eta[qi],
            eta_c_horizontal: horiz,
            n_records: records.len() as i64,
            n_censored: censored as i64,
        });
    }
    q_eta
}

/// Lognormality of η_c (Lilliefors) and the two estimates of median and β.
pub(super) fn lognormal(
    block: &BlockSpec,
    records: &[RecordIda],
    q_eta: [f64; 3],
    out: &mut Tables,
) {
    let logs: Vec<f64> = records
        .iter()
        .filter_map(|r| r.cap.eta_c)
        .map(f64::ln)
        .collect();
    let test = stats::lilliefors(&logs);
    let (mean, sd) = if logs.len() >= 2 {
        stats::mean_sd(&logs)
    } else {
        (f64::NAN, f64::NAN)
    };
    let ok = |v: f64| (v.is_finite() && v > 0.0).then_some(v);
    let beta_fr = match (ok(q_eta[0]), ok(q_eta[2])) {
        (Some(a), Some(b)) => Some(stats::beta_of_fractiles(a, b)),
        _ => None,
    };
    let rejected = test.is_some_and(|t| t.p_value < crate::damage::LOGNORMAL_CHECK_LEVEL);
    if test.is_some() {
        out.pass.1 += 1;
        out.pass.0 += usize::from(!rejected);
    }
    out.lognormal.push(LognormalRow {
        block: block.name.clone(),
        p: block.p,
        eps: block.eps,
        n: logs.len() as i64,
        median_sample: mean.is_finite().then(|| mean.exp()),
        beta_sample: sd.is_finite().then_some(sd),
        median_fractile: ok(q_eta[1]),
        beta_fractile: beta_fr,
        lilliefors_d: test.map(|t| t.d),
        p_value: test.map(|t| t.p_value),
        critical_d_5pct: (logs.len() >= 5)
            .then(|| stats::lilliefors_critical_value(logs.len(), 0.05)),
        rejected_5pct: rejected,
    });
}

/// The first (largest) η at which the record's IDA curve reaches EDP `e`,
/// interpolating linearly between grid levels; the curve starts at
/// (η_max, 0) and ends at (η_c, 1) if the record overturns.
fn first_eta_reaching(r: &RecordIda, eta_max: f64, e: f64) -> Option<f64> {
    // Nothing moves at η ≥ 1 (the uplift threshold of either model), so a grid
    // that starts there starts at EDP = 0; one that starts lower starts at its
    // first level.
    let mut prev = (eta_max >= 1.0).then_some((eta_max, 0.0));
    let end = r.first_over.unwrap_or(r.levels.len());
    let tail = r.cap.eta_c.map(|c| (c, 1.0));
    for point in r.levels[..end].iter().map(|l| (l.0, l.1)).chain(tail) {
        if point.1 >= e {
            return Some(match prev {
                Some(prev) => prev.0 + (e - prev.1) / (point.1 - prev.1) * (point.0 - prev.0),
                None => point.0,
            });
        }
        prev = Some(point);
    }
    None
}
