//! The sweep's cases: what every case needs, prepared once ([`Prepared`]:
//! the records' excitations and each block's run specification), one case's
//! IDA and capacity ([`run_case`]), and the counts of the work done.

use std::collections::BTreeSet;

use rayon::prelude::*;

use super::error::SweepError;
use super::layout::{
    plan_hash, RecordKeys, CHUNK_CASES, META_CHUNK, META_PLAN, META_PLAN_HASH, META_RECORD_KEYS,
    META_SETTINGS, META_SHARD,
};
use crate::ida;
use crate::physics::Excitation;
use crate::pipeline::{BlockSpec, Plan};
use crate::records;
use crate::stages::stage::{Shard, Study};
use crate::tables::records::RecordRow;
use crate::tables::sweep::{CapacityRow, IdaRow};

/// The blocks' reasons for their models (resolved with the plan), each once.
fn model_reasons(blocks: &[BlockSpec]) -> Vec<String> {
    let why: BTreeSet<&str> = blocks.iter().map(|b| b.model_why.as_str()).collect();
    why.into_iter().map(String::from).collect()
}

/// Everything a chunk needs, prepared once: the records, their
/// excitations, and the blocks (the plan's, or the `example` stage's one).
pub(in crate::stages) struct Prepared {
    pub(in crate::stages) records: Vec<RecordRow>,
    excitations: Vec<Excitation>,
    /// On a floor: each record's PFA/PGA.
    amplification: Vec<Option<f64>>,
    pub(super) blocks: Vec<BlockSpec>,
    grid: ida::ImGrid,
    tol: f64,
    trace: ida::Trace,
    pub(super) hash: String,
    /// Each record's key ([`RecordKeys`]), in record order.
    pub(super) record_keys: Vec<String>,
    plan_json: String,
    pub(in crate::stages) n_cases: usize,
}

impl Prepared {
    /// The plan's records with `blocks`; also the models' reasons.
    pub(in crate::stages) fn new(
        study: &Study,
        blocks: &[BlockSpec],
    ) -> Result<(Prepared, Vec<String>), SweepError> {
        let plan = &study.plan;
        let records = records::select(plan, &study.records_table())?;
        let rs = plan.records_study().map_err(records::SelectError::from)?;
        let models = model_reasons(blocks);
        let (excitations, amplification) = records
            .par_iter()
            .map(|r| {
                records::felt(rs.floor.as_ref(), r).map_err(|source| SweepError::Record {
                    record: r.record_id.clone(),
                    source,
                })
            })
            .collect::<Result<Vec<_>, _>>()?
            .into_iter()
            .unzip();
        let prepared = Prepared {
            hash: plan_hash(plan, &records),
            record_keys: {
                let keys = RecordKeys::new(plan);
                records.par_iter().map(|r| keys.of(r)).collect()
            },
            plan_json: plan.portable_json().to_string(),
            n_cases: records.len() * blocks.len(),
            records,
            excitations,
            amplification,
            blocks: blocks.to_vec(),
            grid: rs.grid,
            tol: rs.tol,
            trace: rs.trace,
        };
        Ok((prepared, models))
    }

    pub(super) fn chunk_cases(&self, c: usize) -> std::ops::Range<usize> {
        let start = c * CHUNK_CASES;
        start..(start + CHUNK_CASES).min(self.n_cases)
    }

    pub(super) fn metadata(
        &self,
        plan: &Plan,
        chunk: Option<usize>,
        shard: Option<Shard>,
    ) -> Vec<(String, String)> {
        let mut s = vec![
            (META_PLAN_HASH.to_string(), self.hash.clone()),
            (META_PLAN.to_string(), self.plan_json.clone()),
            (META_SETTINGS.to_string(), plan.sweep_settings()),
        ];
        if chunk.is_none() {
            s.push(RecordKeys::entry(
                META_RECORD_KEYS,
                &self.records,
                &self.record_keys,
            ));
        }
        if let Some(c) = chunk {
            s.push((META_CHUNK.to_string(), c.to_string()));
        }
        if let Some(sh) = shard {
            s.push((META_SHARD.to_string(), sh.to_string()));
        }
        s
    }
}

/// Counts of the work done, for the summary.
#[derive(Default)]
pub(super) struct Tally {
    pub(super) cases_done: usize,
    pub(super) cases_resumed: usize,
    /// Cases whose rows were taken from the previous sweep's tables.
    pub(super) cases_reused: usize,
    pub(super) runs: u64,
    /// Runs the certification added (not in the IDA table).
    pub(super) check_runs: u64,
    pub(super) intervals: u64,
}

/// A case's IDA points and capacity, the runs its certification added,
/// and the sample intervals the search and its certification took (none
/// for a case `reused` from the previous sweep).
pub(in crate::stages) struct CaseResult {
    pub(in crate::stages) ida: Vec<IdaRow>,
    pub(in crate::stages) capacity: CapacityRow,
    pub(super) check_runs: usize,
    pub(super) intervals: u64,
    pub(super) reused: bool,
}

pub(in crate::stages) fn run_case(case: usize, prep: &Prepared) -> Result<CaseResult, SweepError> {
    let n_blocks = prep.blocks.len();
    let (ri, bi) = (case / n_blocks, case % n_blocks);
    let (record, spec, block) = (
        &prep.records[ri],
        prep.blocks[bi].run,
        &prep.blocks[bi].name,
    );
    let certified = ida::capacity_certified(
        &prep.excitations[ri],
        &spec,
        &prep.grid,
        prep.tol,
        prep.trace,
    )
    .map_err(|source| SweepError::Record {
        record: record.record_id.clone(),
        source,
    })?;
    let cap = &certified.capacity;
    let alpha_rad = spec.alpha();
    let model = spec.model.equation.kind();
    let ida = cap
        .points
        .iter()
        .map(|q| IdaRow {
            case_id: case as i64,
            record_id: record.record_id.clone(),
            block: block.clone(),
            p: spec.p,
            eps: spec.eps,
            alpha_rad,
            eta: q.eta,
            pga_scale: 1.0 / q.eta,
            edp: if q.outcome.overturned() {
                f64::INFINITY
            } else {
                q.outcome.max_abs_x
            },
            overturned: q.outcome.overturned(),
            impacts: q.outcome.impacts as i64,
            run_kind: q.kind,
            model,
            slide_max_m: spec
                .model
                .equation
                .friction()
                .map(|_| q.outcome.slide_max_m),
        })
        .collect();
    let row = CapacityRow {
        pfa_over_pga: prep.amplification[ri],
        slides_first: prep.blocks[bi].slides_first(),
        ..CapacityRow::of(case, &record.record_id, block, &spec, alpha_rad, &certified)
    };
    Ok(CaseResult {
        ida,
        capacity: row,
        check_runs: certified.extra.runs,
        intervals: cap.work().intervals + certified.extra.intervals,
        reused: false,
    })
}

/// Every case of `blocks` over the study's records, on every core, as the
/// stage `stage` (its model notes and progress, the runs counted as IDA
/// rows): the one loop of the stages that run a few blocks whole (the
/// example block, a tree's branches).
pub(in crate::stages) fn run_blocks(
    cx: &crate::stages::stage::Context,
    stage: &'static str,
    blocks: &[BlockSpec],
) -> Result<Vec<CaseResult>, SweepError> {
    let (prep, models) = Prepared::new(cx.study, blocks)?;
    for m in &models {
        cx.reporter.note(stage, &format!("model: {m}"));
    }
    let total = prep.n_cases as u64;
    let progress = |done: u64, runs: u64| {
        cx.reporter.progress(&crate::stages::stage::Progress {
            stage,
            done,
            total,
            resumed: 0,
            runs,
        })
    };
    progress(0, 0);
    let results = (0..prep.n_cases)
        .into_par_iter()
        .map(|case| run_case(case, &prep))
        .collect::<Result<Vec<_>, _>>()?;
    progress(total, results.iter().map(|r| r.ida.len() as u64).sum());
    Ok(results)
}
