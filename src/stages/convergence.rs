//! Convergence stage: the capacity search repeated at several IM-grid
//! resolutions (pipeline key `[convergence] levels`) →
//! `convergence_capacities.parquet` (each search's capacity) and
//! `capacity_convergence.parquet` (each block's summary).
//!
//! The capacity is the first overturning met as intensity rises, and the set
//! of intensities at which a block overturns can have thin islands: a finer
//! grid can land on an island a coarser one stepped over, and so find a
//! larger η_c. For each block and resolution this writes the fractiles of
//! η_c over the records and how many records' η_c moved against the finest
//! grid (by more than twice the refinement tolerance), with the mean and
//! largest move.

use std::collections::BTreeMap;
use std::path::PathBuf;

use rayon::prelude::*;

use super::fingerprint;
use super::reduce::QUANTILES;
use super::stage::{BoxError, Context, Progress, Shard, Stage, Study, Summary};
use super::sweep::RecordKeys;
use crate::ida::{self, ImGrid};
use crate::physics::{Excitation, PhysicsError, RunSpec};
use crate::pipeline::{BlockSpec, RecordsPlan};
use crate::records::{self, SelectError};
use crate::stats;
use crate::tables::convergence::{ConvergenceCaseRow, ConvergenceRow};
use crate::tables::records::RecordRow;
use crate::tables::{self, TableError};

/// The table of every search's capacity, and its metadata key of the
/// records' keys.
const CASES: &str = "convergence_capacities.parquet";
const META_RECORD_KEYS: &str = "rocking.convergence.record_keys";

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
        vec![
            study.path(CASES),
            study.path("capacity_convergence.parquet"),
        ]
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
    let sweep_keys = RecordKeys::new(plan);
    let keys: Vec<String> = records
        .par_iter()
        .map(|r| record_key(&sweep_keys, &rs.convergence, r))
        .collect();
    let known = known(cx, rs, &records, &keys);
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
    // η_c by record, block and resolution (plan order).
    let mut etas = vec![vec![Vec::new(); n_blocks]; n_records];
    for group in 0..n_groups {
        let members: Vec<usize> = (group..n_blocks).step_by(n_groups).collect();
        let pairs: Vec<(usize, usize)> = members
            .iter()
            .flat_map(|&bi| (0..n_records).map(move |ri| (bi, ri)))
            .filter(|(_, ri)| !known.contains_key(ri))
            .collect();
        for ((bi, ri), r) in pairs
            .iter()
            .zip(search_pairs(rs, &excitations, &order, &pairs)?)
        {
            runs += r.1;
            shared += r.2;
            etas[*ri][*bi] = r.0;
        }
        for (&ri, found) in &known {
            for &bi in &members {
                etas[ri][bi] = found[bi].clone();
            }
        }
        for &bi in &members {
            let per_grid: Vec<Vec<f64>> = (0..rs.convergence.len())
                .map(|gi| etas.iter().map(|e| e[bi][gi]).collect())
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
    let (dest, cases) = write(cx, rs, (&records, &keys), &etas, &rows)?;
    Ok(Summary {
        lines: vec![format!(
            "capacity search at {:?} levels: {runs} simulations (the searches' {shared} runs \
             share the levels the grids have in common); wrote {} and {}",
            rs.convergence,
            dest.display(),
            cases.display()
        )],
        headline: 0,
        also_wrote: Vec::new(),
    })
}

/// Writes the stage's two tables: every search's capacity (`etas` by
/// record, block and resolution, with the `records`' keys) and the blocks'
/// `rows`; returns their paths (the summary's, the capacities').
fn write(
    cx: &Context,
    rs: &RecordsPlan,
    (records, keys): (&[RecordRow], &[String]),
    etas: &[Vec<Vec<f64>>],
    rows: &[ConvergenceRow],
) -> Result<(PathBuf, PathBuf), TableError> {
    let levels = format!("{:?}", rs.convergence);
    let levels_meta = ("rocking.convergence.levels".to_string(), levels);
    let cases = cx.study.path(CASES);
    let keys_meta = RecordKeys::entry(META_RECORD_KEYS, records, keys);
    let metadata = [levels_meta.clone(), keys_meta];
    tables::write(&cases, &case_rows(rs, records, etas), &metadata)?;
    let dest = cx.study.path("capacity_convergence.parquet");
    tables::write(&dest, rows, &[levels_meta])?;
    Ok((dest, cases))
}

/// A record's key for this stage: the sweep's (its motion bit for bit, the
/// settings but for the selection) and the resolutions.
fn record_key(sweep: &RecordKeys, levels: &[usize], r: &RecordRow) -> String {
    let text = format!("{} {levels:?}", sweep.of(r));
    crate::hash::sha256_hex(text.as_bytes())
}

/// η_c by block and resolution of the records the previous run searched
/// as they are now (their key unchanged), by record index, said in a
/// note; none when forced (`--force`, `--from`) or when the previous
/// tables are not as the stage wrote them.
fn known(
    cx: &Context,
    rs: &RecordsPlan,
    records: &[RecordRow],
    keys: &[String],
) -> BTreeMap<usize, Vec<Vec<f64>>> {
    if cx.forced || !fingerprint::outputs_as_written(cx.study, &Convergence) {
        return BTreeMap::new();
    }
    match previous(&cx.study.path(CASES), rs, records, keys) {
        Ok(known) => {
            if !known.is_empty() {
                cx.reporter.note(
                    "convergence",
                    &format!(
                        "took the capacities of {} of {} records from the previous run: \
                         their motions, the blocks and the settings of the searches are as then",
                        known.len(),
                        records.len()
                    ),
                );
            }
            known
        }
        Err(e) => {
            cx.reporter.note(
                "convergence",
                &format!("searching every record: the previous {CASES} cannot be read ({e})"),
            );
            BTreeMap::new()
        }
    }
}

/// [`known`] from the previous table at `path`: a record is taken if its
/// key is the one the table holds and its rows are its blocks' and
/// resolutions' in order.
fn previous(
    path: &std::path::Path,
    rs: &RecordsPlan,
    records: &[RecordRow],
    keys: &[String],
) -> Result<BTreeMap<usize, Vec<Vec<f64>>>, TableError> {
    let Some(old) = RecordKeys::written(path, META_RECORD_KEYS)? else {
        return Ok(BTreeMap::new());
    };
    let unchanged: Vec<usize> = (0..records.len())
        .filter(|&ri| old.get(&records[ri].record_id) == Some(&keys[ri]))
        .collect();
    if unchanged.is_empty() {
        return Ok(BTreeMap::new());
    }
    let rows: Vec<ConvergenceCaseRow> = tables::read(path)?;
    let mut by_record: BTreeMap<&str, Vec<&ConvergenceCaseRow>> = BTreeMap::new();
    for row in &rows {
        by_record.entry(&row.record_id).or_default().push(row);
    }
    let (nb, ng) = (rs.blocks.len(), rs.convergence.len());
    let mut out = BTreeMap::new();
    for ri in unchanged {
        let Some(rows) = by_record.get(records[ri].record_id.as_str()) else {
            continue;
        };
        let fits = rows.len() == nb * ng
            && rows.iter().enumerate().all(|(k, r)| {
                let b = &rs.blocks[k / ng];
                (&r.block, r.p, r.eps) == (&b.name, b.p, b.eps)
                    && r.levels == rs.convergence[k % ng] as i64
            });
        if fits {
            let etas = (0..nb)
                .map(|bi| {
                    (0..ng)
                        .map(|gi| rows[bi * ng + gi].eta_c.unwrap_or(0.0))
                        .collect()
                })
                .collect();
            out.insert(ri, etas);
        }
    }
    Ok(out)
}

/// The rows of [`ConvergenceCaseRow`]: records, blocks, resolutions.
fn case_rows(
    rs: &RecordsPlan,
    records: &[RecordRow],
    etas: &[Vec<Vec<f64>>],
) -> Vec<ConvergenceCaseRow> {
    let mut rows = Vec::new();
    for (r, per_block) in records.iter().zip(etas) {
        for (b, per_grid) in rs.blocks.iter().zip(per_block) {
            for (&levels, &eta) in rs.convergence.iter().zip(per_grid) {
                rows.push(ConvergenceCaseRow {
                    record_id: r.record_id.clone(),
                    block: b.name.clone(),
                    p: b.p,
                    eps: b.eps,
                    levels: levels as i64,
                    eta_c: (eta > 0.0).then_some(eta),
                });
            }
        }
    }
    rows
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
