//! Convergence stage: the capacity search repeated at several IM-grid
//! resolutions (pipeline key `[convergence] levels`) →
//! `capacity_convergence.parquet`.
//!
//! The capacity is the first overturning met as intensity rises, and the set
//! of intensities at which a block overturns can have thin islands: a finer
//! grid can land on an island a coarser one stepped over, and so find a
//! larger η_c. For each block and resolution this writes the fractiles of
//! η_c over the records and how many records' η_c moved against the finest
//! grid (by more than twice the refinement tolerance), with the mean and
//! largest move.

use std::path::PathBuf;

use rayon::prelude::*;

use super::reduce::QUANTILES;
use super::stage::{BoxError, Context, Progress, Shard, Stage, Study, Summary};
use crate::ida::{self, ImGrid};
use crate::physics::{Excitation, PhysicsError, RunSpec};
use crate::pipeline::{BlockSpec, RecordsPlan};
use crate::records::{self, SelectError};
use crate::stats;
use crate::tables::convergence::ConvergenceRow;
use crate::tables::{self, TableError};

/// The convergence stage.
pub struct Convergence;

/// Blocks searched together, their (block, record) pairs in parallel.
const BLOCKS_PER_GROUP: usize = 4;

impl Stage for Convergence {
    fn name(&self) -> &'static str {
        "convergence"
    }

    fn about(&self) -> &'static str {
        "Repeat the capacity search at the grid resolutions of [convergence] levels"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        if let Some(why) = study.plan.pulse_map_skips() {
            return Some(why);
        }
        study
            .plan
            .convergence()
            .is_empty()
            .then(|| "the pipeline has no [convergence] levels".to_string())
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        let plan = &study.plan;
        serde_json::json!({
            "sweep": plan.sweep_settings_json(),
            "levels": plan.convergence(),
            "fractile": plan.records_study().ok().map(|r| r.fractile),
        })
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        Ok(vec![study.records_table()])
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        vec![study.path("capacity_convergence.parquet")]
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx)?)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ConvergenceError {
    #[error(transparent)]
    Records(#[from] SelectError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("record {record}")]
    Record {
        record: String,
        #[source]
        source: PhysicsError,
    },
    #[error("block p = {p}, ε = {eps}")]
    Physics {
        p: f64,
        eps: f64,
        #[source]
        source: PhysicsError,
    },
}

fn run(cx: &Context) -> Result<Summary, ConvergenceError> {
    let plan = &cx.study.plan;
    let records = records::select(plan, &cx.study.records_table())?;
    let rs = plan.records_study().map_err(SelectError::from)?;
    let excitations = records
        .par_iter()
        .map(|r| {
            records::felt(rs.floor.as_ref(), r)
                .map(|(exc, _)| exc)
                .map_err(|source| ConvergenceError::Record {
                    record: r.record_id.clone(),
                    source,
                })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let (mut runs, mut shared) = (0u64, 0u64);
    let total = rs.blocks.len() as u64;
    // Finest grid first: the coarser grids' levels are among its levels (to
    // the bit), so their searches find most of their runs already done.
    let mut order: Vec<usize> = (0..rs.convergence.len()).collect();
    order.sort_by_key(|&gi| std::cmp::Reverse(rs.convergence[gi]));
    let n_records = excitations.len();
    let mut done = 0u64;
    // A few blocks at a time, every (block, record) pair in parallel: the
    // threads stay busy to the end of each group (records differ in length
    // tenfold), and progress is reported after each group. A group takes
    // blocks spread over the plan (every n-th), not neighbours: blocks of
    // small p search many more levels than those of large p, so groups of
    // neighbours made the rate, and the ETA, drift fourfold over the run.
    let n_blocks = rs.blocks.len();
    let n_groups = n_blocks.div_ceil(BLOCKS_PER_GROUP);
    let mut per_block: Vec<Vec<ConvergenceRow>> = vec![Vec::new(); n_blocks];
    for group in 0..n_groups {
        let members: Vec<usize> = (group..n_blocks).step_by(n_groups).collect();
        let pairs: Vec<(usize, usize)> = members
            .iter()
            .flat_map(|&bi| (0..n_records).map(move |ri| (bi, ri)))
            .collect();
        let results = search_pairs(rs, &excitations, &order, &pairs)?;
        for (k, &bi) in members.iter().enumerate() {
            let per_record = &results[k * n_records..(k + 1) * n_records];
            runs += per_record.iter().map(|r| r.1).sum::<u64>();
            shared += per_record.iter().map(|r| r.2).sum::<u64>();
            let per_grid: Vec<Vec<f64>> = (0..rs.convergence.len())
                .map(|gi| per_record.iter().map(|r| r.0[gi]).collect())
                .collect();
            per_block[bi] = block_rows(rs, &rs.blocks[bi], &per_grid);
        }
        done += members.len() as u64;
        cx.reporter.progress(&Progress {
            stage: "convergence",
            done,
            total,
            resumed: 0,
            runs,
        });
    }
    let rows: Vec<ConvergenceRow> = per_block.into_iter().flatten().collect();
    let dest = cx.study.path("capacity_convergence.parquet");
    tables::write(
        &dest,
        &rows,
        &[(
            "rocking.convergence.levels".into(),
            format!("{:?}", rs.convergence),
        )],
    )?;
    Ok(Summary {
        lines: vec![format!(
            "capacity search at {:?} levels: {runs} simulations (the searches' {shared} runs \
             share the levels the grids have in common); wrote {}",
            rs.convergence,
            dest.display()
        )],
        headline: 0,
        also_wrote: Vec::new(),
    })
}

/// The error of a block's physics.
fn physics(b: &BlockSpec) -> impl Fn(PhysicsError) -> ConvergenceError {
    let (p, eps) = (b.p, b.eps);
    move |source| ConvergenceError::Physics { p, eps, source }
}

/// Per (block, record): η_c per resolution (0 when the block survives
/// every level), the simulations done, and the runs the searches asked for.
type PerRecord = (Vec<f64>, u64, u64);

/// The searches of `pairs` (block, record), in parallel, each at every
/// resolution in `order`, sharing one record's runs across resolutions.
fn search_pairs(
    plan: &RecordsPlan,
    excitations: &[Excitation],
    order: &[usize],
    pairs: &[(usize, usize)],
) -> Result<Vec<PerRecord>, ConvergenceError> {
    pairs
        .par_iter()
        .map(|&(bi, ri)| {
            let exc = &excitations[ri];
            let mut memo = ida::Runs::new(exc);
            let mut etas = vec![0.0; plan.convergence.len()];
            let mut asked = 0u64;
            for &gi in order {
                let grid = ImGrid {
                    count: plan.convergence[gi],
                    ..plan.grid
                };
                let c = search(&mut memo, &plan.blocks[bi].run, &grid, plan.tol)
                    .map_err(physics(&plan.blocks[bi]))?;
                etas[gi] = c.eta_c.unwrap_or(0.0);
                asked += c.runs() as u64;
            }
            Ok((etas, memo.work().runs as u64, asked))
        })
        .collect::<Result<Vec<PerRecord>, ConvergenceError>>()
}

/// The capacity at one resolution. With a tolerance-controlled integrator
/// it is the certified one (its decisive runs rerun tighter, the search
/// redone if a verdict flips). With the exact stepper certification cannot
/// move η_c, only flag it chaotic, and this table reports no flags (the
/// sweep's `capacities.parquet` carries them): the plain search, which
/// finds the same η_c without the chaos probe's two runs per decisive run
/// (a quarter of this stage's time on the paper grid).
fn search(
    memo: &mut ida::Runs,
    spec: &RunSpec,
    grid: &ImGrid,
    tol: f64,
) -> Result<ida::Capacity, PhysicsError> {
    match spec.model.integrator {
        crate::physics::Integrator::Exact => {
            ida::capacity_in(memo, spec, grid, tol, ida::Trace::StopAtFirst)
        }
        _ => Ok(
            ida::capacity_certified_in(memo, spec, grid, tol, ida::Trace::StopAtFirst)?.capacity,
        ),
    }
}

/// One row per resolution of one block, against the finest grid.
fn block_rows(
    plan: &RecordsPlan,
    block: &crate::pipeline::BlockSpec,
    per_grid: &[Vec<f64>],
) -> Vec<ConvergenceRow> {
    let finest = per_grid.last().expect("two or more resolutions");
    plan.convergence
        .iter()
        .zip(per_grid)
        .map(|(&count, caps)| {
            let mut etas = caps.clone();
            let moves: Vec<f64> = caps
                .iter()
                .zip(finest)
                .map(|(a, b)| (a - b).abs())
                .collect();
            let changed = moves.iter().filter(|&&m| m > 2.0 * plan.tol).count();
            etas.sort_by(|a, b| a.total_cmp(b));
            let q: Vec<f64> = QUANTILES
                .iter()
                .map(|&q| stats::fractile(&etas, q, plan.fractile).expect("records"))
                .collect();
            ConvergenceRow {
                block: block.name.clone(),
                p: block.p,
                eps: block.eps,
                levels: count as i64,
                eta_c_q16: q[0],
                eta_c_q50: q[1],
                eta_c_q84: q[2],
                n_records: etas.len() as i64,
                n_changed: changed as i64,
                mean_abs_change: moves.iter().sum::<f64>() / moves.len() as f64,
                max_abs_change: moves.iter().cloned().fold(0.0, f64::max),
            }
        })
        .collect()
}
