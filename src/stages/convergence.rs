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

use super::records::{self, SelectError};
use super::reduce::QUANTILES;
use super::stage::{BoxError, Context, Progress, Shard, Stage, Study, Summary};
use crate::ida::{self, ImGrid};
use crate::physics::{Excitation, PhysicsError, RunSpec};
use crate::stats;
use crate::tables::convergence::ConvergenceRow;
use crate::tables::{self, TableError};

/// The convergence stage.
pub struct Convergence;

impl Stage for Convergence {
    fn name(&self) -> &'static str {
        "convergence"
    }

    fn about(&self) -> &'static str {
        "Repeat the capacity search at the grid resolutions of [convergence] levels"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        study
            .plan
            .convergence
            .is_empty()
            .then(|| "the pipeline has no [convergence] levels".to_string())
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        let plan = &study.plan;
        serde_json::json!({
            "sweep": plan.sweep_settings_json(),
            "levels": plan.convergence,
            "fractile": plan.fractile,
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
    let physics = |b: &crate::pipeline::BlockSpec| {
        let (p, eps) = (b.p, b.eps);
        move |source| ConvergenceError::Physics { p, eps, source }
    };
    let excitations = records
        .par_iter()
        .map(|r| {
            Excitation::new(&r.accel_g, r.dt_s).map_err(|source| ConvergenceError::Record {
                record: r.record_id.clone(),
                source,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut rows = Vec::new();
    let mut runs = 0u64;
    let total = (plan.blocks.len() * plan.convergence.len()) as u64;
    for (bi, block) in plan.blocks.iter().enumerate() {
        let (model, _) = plan
            .model
            .resolve(block.alpha_rad, plan.rtol, plan.auto_tol)
            .map_err(physics(block))?;
        let spec = RunSpec {
            overturn: plan.overturn,
            ..RunSpec::new(block.p, block.eps, 1.0, model)
        };
        // η_c per resolution per record (0 when the block survives every level).
        let mut per_grid: Vec<Vec<(f64, usize)>> = Vec::new();
        for (gi, &count) in plan.convergence.iter().enumerate() {
            let grid = ImGrid { count, ..plan.grid };
            let caps = excitations
                .par_iter()
                .map(|exc| {
                    ida::capacity_certified(exc, &spec, &grid, plan.tol, ida::Trace::StopAtFirst)
                        .map(|c| (c.capacity.eta_c.unwrap_or(0.0), c.capacity.runs()))
                })
                .collect::<Result<Vec<_>, _>>()
                .map_err(physics(block))?;
            runs += caps.iter().map(|c| c.1 as u64).sum::<u64>();
            per_grid.push(caps);
            cx.reporter.progress(&Progress {
                stage: "convergence",
                done: (bi * plan.convergence.len() + gi + 1) as u64,
                total,
                resumed: 0,
                runs,
            });
        }
        rows.extend(block_rows(cx.study, block, &per_grid));
    }
    let dest = cx.study.path("capacity_convergence.parquet");
    tables::write(
        &dest,
        &rows,
        &[(
            "rocking.convergence.levels".into(),
            format!("{:?}", plan.convergence),
        )],
    )?;
    Ok(Summary {
        lines: vec![format!(
            "capacity search at {:?} levels: {runs} runs; wrote {}",
            plan.convergence,
            dest.display()
        )],
        also_wrote: Vec::new(),
    })
}

/// One row per resolution of one block, against the finest grid.
fn block_rows(
    study: &Study,
    block: &crate::pipeline::BlockSpec,
    per_grid: &[Vec<(f64, usize)>],
) -> Vec<ConvergenceRow> {
    let plan = &study.plan;
    let finest = per_grid.last().expect("two or more resolutions");
    plan.convergence
        .iter()
        .zip(per_grid)
        .map(|(&count, caps)| {
            let mut etas: Vec<f64> = caps.iter().map(|c| c.0).collect();
            let moves: Vec<f64> = caps
                .iter()
                .zip(finest)
                .map(|(a, b)| (a.0 - b.0).abs())
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
