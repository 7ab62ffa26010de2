//! Capacity convergence: the capacity search repeated at several IM-grid
//! resolutions (pipeline key `[convergence] levels`).
//!
//! The capacity is the first overturning met as intensity rises, and the set
//! of intensities at which a block overturns can have thin islands: a finer
//! grid can land on an island a coarser one stepped over, and so find a
//! larger η_c. For each block and resolution this writes the fractiles of
//! η_c over the records and how many records' η_c moved against the finest
//! grid (by more than twice the refinement tolerance), with the mean and
//! largest move.

use std::path::Path;

use rayon::prelude::*;

use crate::ida::{self, ImGrid};
use crate::physics::RunSpec;
use crate::pipeline::Plan;
use crate::stages::reduce::QUANTILES;
use crate::stages::sweep::SweepError;
use crate::stats;
use crate::tables::records::RecordRow;
use crate::tables::summary::{f, i, s, CONVERGENCE};
use crate::tables::TableError;

#[derive(Debug, thiserror::Error)]
pub enum ConvergenceError {
    #[error(transparent)]
    Sweep(#[from] SweepError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("{0}")]
    Physics(#[from] crate::physics::PhysicsError),
}

/// Runs the study on `records` and writes `dest`. Returns the number of runs.
pub fn run(plan: &Plan, records: &[RecordRow], dest: &Path) -> Result<u64, ConvergenceError> {
    let excitations = records
        .par_iter()
        .map(|r| crate::physics::Excitation::new(&r.accel_g, r.dt_s))
        .collect::<Result<Vec<_>, _>>()?;
    let mut rows = Vec::new();
    let mut runs = 0u64;
    for block in &plan.blocks {
        let (model, _) = plan
            .model
            .resolve(block.alpha_rad, plan.rtol, plan.auto_tol)?;
        let spec = RunSpec {
            overturn: plan.overturn,
            ..RunSpec::new(block.p, block.eps, 1.0, model)
        };
        // η_c per resolution per record (0 when the block survives every level).
        let per_grid: Vec<Vec<(f64, usize)>> = plan
            .convergence
            .iter()
            .map(|&count| {
                let grid = ImGrid { count, ..plan.grid };
                excitations
                    .par_iter()
                    .map(|exc| {
                        ida::capacity(exc, &spec, &grid, plan.tol)
                            .map(|c| (c.eta_c.unwrap_or(0.0), c.runs()))
                    })
                    .collect::<Result<Vec<_>, _>>()
            })
            .collect::<Result<_, _>>()?;
        let finest = per_grid.last().expect("two or more resolutions");
        for (&count, caps) in plan.convergence.iter().zip(&per_grid) {
            runs += caps.iter().map(|c| c.1 as u64).sum::<u64>();
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
            rows.push(vec![
                s(&block.name),
                f(block.p),
                f(block.eps),
                i(count as i64),
                f(q[0]),
                f(q[1]),
                f(q[2]),
                i(etas.len() as i64),
                i(changed as i64),
                f(moves.iter().sum::<f64>() / moves.len() as f64),
                f(moves.iter().cloned().fold(0.0, f64::max)),
            ]);
        }
    }
    CONVERGENCE.write(
        dest,
        &rows,
        &[(
            "rocking.convergence.levels".into(),
            format!("{:?}", plan.convergence),
        )],
    )?;
    Ok(runs)
}
