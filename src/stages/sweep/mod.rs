//! Sweep stage: the IDA of every (record, block) case of a pipeline →
//! `ida_points.parquet` and `capacities.parquet`.
//!
//! Cases are numbered in a fixed order (records by id, then blocks in plan
//! order) and grouped into chunks of [`CHUNK_CASES`]. Workers (rayon) take
//! the cases in order from one counter; a writer thread gathers each chunk's
//! results in case order and adds them to the final tables, in chunk order,
//! as soon as the chunk and every one before it are complete. From
//! [`CHECKPOINT_AFTER`] into the sweep on, it also saves each such chunk as
//! two part files under `parts/`, stamped with the plan's hash and the
//! chunk's index (the chunks completed before are held and saved then). No
//! worker waits for a chunk's slowest case or for a write. So:
//!
//! - **resume**: a rerun reuses a part only if its hash is current *and* its
//!   content is that chunk's (its case ids, one capacity per case, the runs
//!   each capacity counts); any other part is logged and recomputed;
//! - **determinism**: parts and final tables are byte-identical whatever the
//!   thread count;
//! - **sharding**: `--shard K/N` computes the chunks with index ≡ K−1 (mod N)
//!   and writes `*.shard-K-of-N.parquet`; [`dataset`] reads the N shards as
//!   one table, and refuses a folder that mixes shards and unsharded tables;
//! - **bounded memory**: only the chunks not yet complete are held (those
//!   from the oldest unfinished case on), and the completed ones not yet
//!   saved as parts (at most [`MAX_HELD_ROWS`] IDA rows); the final tables
//!   are written as the chunks complete, in chunk order (a resumed chunk
//!   read back from its parts), to temporary files that become the tables
//!   once the last chunk is in, so nothing is left to assemble at the end.

mod cases;
mod dataset;
mod error;
mod layout;
mod parts;
mod reuse;
mod writer;

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Instant;

pub(super) use cases::{run_blocks, run_case, CaseResult, Prepared};
pub use dataset::{dataset, is_level, read_capacities, read_ida, DatasetError};
pub use error::SweepError;
pub(super) use layout::RecordKeys;
pub use layout::{
    plan_hash, SweepMeta, CHUNK_CASES, META_CHUNK, META_PLAN, META_PLAN_HASH, META_SETTINGS,
    META_SHARD,
};
pub use writer::{
    CASE_DELAY_ENV, CHECKPOINT_AFTER, FAULT_ENV, HOLD_ENV, INTERRUPT_ENV, MAX_HELD_ROWS,
};

use super::stage::{BoxError, Context, Progress, Shard, Stage, Study, Summary};
use crate::tables;
use cases::Tally;
use layout::final_names;
use parts::{
    clean_up, part_paths, remove_stale_temporaries, remove_where, verify_part, PartProblem,
};
use writer::{ChunkWriter, Hold};

/// The sweep stage.
pub struct Sweep;

impl Stage for Sweep {
    fn name(&self) -> &'static str {
        "sweep"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        study.plan.pulse_map_skips()
    }

    fn about(&self) -> &'static str {
        "Run a pipeline's IDA study: every record × block, written as Parquet tables"
    }

    fn shardable(&self) -> bool {
        true
    }

    fn interrupted(&self, study: &Study) -> Option<String> {
        let saved = parts::saved_chunks(&study.path("parts"));
        (saved > 0).then(|| {
            format!(
                "an interrupted run saved {saved} chunk(s) in parts/, which a rerun resumes if \
                 the settings are the same"
            )
        })
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        study.plan.sweep_settings_json()
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        Ok(vec![study.records_table()])
    }

    fn outputs(&self, study: &Study, shard: Option<Shard>) -> Vec<PathBuf> {
        let (ida, cap) = final_names(shard);
        vec![study.path(&ida), study.path(&cap)]
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx)?)
    }
}

/// What a run of the sweep (or of one shard) works on, settled before any
/// case runs.
struct Setup {
    prep: Prepared,
    /// The folder of the part files.
    parts: PathBuf,
    /// This run's chunks, in order.
    mine: Vec<usize>,
    /// The cases of those chunks.
    cases_total: usize,
}

/// Runs the sweep (or one shard of it).
fn run(cx: &Context) -> Result<Summary, SweepError> {
    let started = Instant::now();
    let study = cx.study;
    let plan = &study.plan;
    let setup = prepare(cx)?;
    let after = |var: &str| {
        std::env::var(var)
            .ok()
            .and_then(|v| v.parse::<usize>().ok())
    };
    let (fault_after, interrupt_after) = (after(FAULT_ENV), after(INTERRUPT_ENV));
    let delay = after(CASE_DELAY_ENV).map(|ms| std::time::Duration::from_millis(ms as u64));
    let hold = match std::env::var(HOLD_ENV).ok().and_then(|v| v.parse().ok()) {
        Some(n) => Hold::Chunks(n),
        None => Hold::Until(started + CHECKPOINT_AFTER),
    };

    let mut tally = Tally::default();
    let report = |t: &Tally| {
        cx.reporter.progress(&Progress {
            stage: "sweep",
            done: t.cases_done as u64,
            total: setup.cases_total as u64,
            resumed: (t.cases_resumed + t.cases_reused) as u64,
            runs: t.runs,
        })
    };
    report(&tally);
    let (todo, resumed) = resume(cx, &setup, &mut tally, &report);
    let mut cases: Vec<usize> = todo
        .iter()
        .flat_map(|&c| setup.prep.chunk_cases(c))
        .collect();
    let reused = reused(cx, &setup.prep, &cases);
    if !reused.is_empty() {
        let taken: BTreeSet<usize> = reused.iter().map(|(c, _)| *c).collect();
        cases.retain(|c| !taken.contains(c));
    }
    let (ida_name, cap_name) = final_names(cx.shard);
    let (ida_path, cap_path) = (study.path(&ida_name), study.path(&cap_name));
    // A killed run's temporaries of this run's tables (the lock refuses any
    // other writer of them).
    remove_where(&study.dir, |name| {
        crate::tables::temporary_of(name).is_some_and(|(t, _pid)| t == ida_name || t == cap_name)
    })?;
    let final_meta = setup.prep.metadata(plan, None, cx.shard);
    let (prep, parts, mine, report) = (&setup.prep, &setup.parts, &setup.mine, &report);
    let (ida_path, cap_path) = (&ida_path, &cap_path);
    let writer = move || {
        Ok(ChunkWriter {
            prep,
            plan,
            parts,
            fault_after,
            interrupt_after,
            report,
            order: mine.iter().copied().collect(),
            resumed,
            ida: tables::Appender::create(ida_path, &final_meta)?,
            cap: tables::Appender::create(cap_path, &final_meta)?,
            pending: BTreeMap::new(),
            hold,
            held: Vec::new(),
            completed: 0,
            tally,
        })
    };
    let tally = run_chunks(&cases, prep, writer, reused, delay)?;
    let superseded = clean_up(study, &setup.mine, cx.shard)?;
    let mut done = summary(cx, &setup, &tally, started, ida_path, cap_path);
    if let Some(line) = superseded_line(&superseded, cx.shard) {
        done.lines.push(line);
    }
    Ok(done)
}

/// Prepares the cases, makes the parts folder, and picks this run's chunks
/// (all, or one shard's), removing the temporaries a killed run left of
/// their parts.
/// How many chunks of [`CHUNK_CASES`] cases the sweep of `study` has: the
/// most shards that have work (`submit` refuses an array of more tasks
/// than that before submitting it). Reads the records table.
pub fn chunks(study: &Study) -> Result<usize, SweepError> {
    let records = crate::records::select(&study.plan, &study.records_table())?;
    Ok((records.len() * study.plan.blocks().len()).div_ceil(CHUNK_CASES))
}

fn prepare(cx: &Context) -> Result<Setup, SweepError> {
    let study = cx.study;
    let plan = &study.plan;
    let (prep, models) = Prepared::new(study, plan.blocks())?;
    for m in &models {
        cx.reporter.note("sweep", &format!("model: {m}"));
    }
    // A block that slides before it rocks: its capacities assume it is
    // restrained against sliding (the report and `capacities.parquet`
    // mark it too).
    let rocking = |b: &&crate::pipeline::BlockSpec| b.run.model.equation.friction().is_none();
    for b in plan
        .blocks()
        .iter()
        .filter(|b| b.slides_first())
        .filter(rocking)
    {
        if let (Some(mu), Some(alpha)) = (b.mu, b.alpha_rad) {
            cx.reporter.note(
                "sweep",
                &format!(
                    "warning: block `{}`: {}",
                    b.name,
                    crate::block::sliding_warning(mu, alpha)
                ),
            );
        }
    }
    if let Ok(rs) = plan.records_study() {
        if let Some(w) = crate::ida::tol_warning(rs.tol, rs.grid.eta_max) {
            cx.reporter
                .note("sweep", &format!("warning: `im.tol`: {w}"));
        }
    }
    // A physical block larger than any free-standing object (given in cm,
    // say), as every command warns of it: its size from p and α.
    for b in plan.blocks().iter().filter(|b| !b.name.is_empty()) {
        let Some(alpha) = b.alpha_rad else { continue };
        let size =
            crate::block::Block::of_p_alpha(b.p, alpha, crate::block::Restitution::Value(b.eps));
        if let Some(w) = size.ok().as_ref().and_then(crate::block::size_warning) {
            cx.reporter
                .note("sweep", &format!("warning: block `{}`: {w}", b.name));
        }
    }
    let parts = study.path("parts");
    fs::create_dir_all(&parts).map_err(|source| SweepError::Io {
        path: parts.clone(),
        source,
    })?;
    let n_chunks = prep.n_cases.div_ceil(CHUNK_CASES);
    if let Some(s) = cx.shard.filter(|s| s.n > n_chunks) {
        return Err(SweepError::TooManyShards {
            shard: s,
            chunks: n_chunks,
        });
    }
    let mine: Vec<usize> = (0..n_chunks)
        .filter(|c| cx.shard.is_none_or(|s| c % s.n == s.k - 1))
        .collect();
    let cases_total: usize = mine.iter().map(|&c| prep.chunk_cases(c).len()).sum();
    remove_stale_temporaries(&parts, &mine)?;
    Ok(Setup {
        prep,
        parts,
        mine,
        cases_total,
    })
}

/// Keeps the chunks whose parts are already there and current (counted
/// as done and resumed); returns the chunks still to compute and those kept.
fn resume(
    cx: &Context,
    setup: &Setup,
    tally: &mut Tally,
    report: &impl Fn(&Tally),
) -> (Vec<usize>, BTreeSet<usize>) {
    let prep = &setup.prep;
    let (mut todo, mut resumed) = (Vec::new(), BTreeSet::new());
    for &c in &setup.mine {
        let (ida_part, cap_part) = part_paths(&setup.parts, c);
        let cases = prep.chunk_cases(c);
        match verify_part(&ida_part, &cap_part, &prep.hash, c, cases.clone()) {
            Ok(()) => {
                tally.cases_done += cases.len();
                tally.cases_resumed += cases.len();
                report(tally);
                resumed.insert(c);
                continue;
            }
            Err(PartProblem::Absent) => {}
            Err(PartProblem::Stale) => {}
            Err(PartProblem::Corrupt(part, why)) => cx.reporter.note(
                "sweep",
                &format!(
                    "part {} of chunk {c} is not that chunk's ({why}); recomputing it",
                    part.display()
                ),
            ),
        }
        todo.push(c);
    }
    (todo, resumed)
}

/// The results of the cases among `cases` that the previous sweep's
/// tables hold for unchanged records ([`reuse::previous`]), said in a note;
/// none (said too) where those tables cannot be read.
fn reused(cx: &Context, prep: &Prepared, cases: &[usize]) -> Vec<(usize, CaseResult)> {
    match reuse::previous(cx, prep, cases) {
        Ok((taken, 0)) => taken,
        Ok((taken, records)) => {
            cx.reporter.note(
                "sweep",
                &format!(
                    "took the rows of {} of {} records ({} cases) from the previous sweep: \
                     their motions, the blocks and the settings of the runs are as then",
                    records,
                    prep.records.len(),
                    taken.len()
                ),
            );
            taken
        }
        Err(reuse::NotTaken::Unreadable(e)) => {
            cx.reporter.note(
                "sweep",
                &format!("computing every case: the previous sweep's tables cannot be read ({e})"),
            );
            Vec::new()
        }
        Err(reuse::NotTaken::TooLarge(rows)) => {
            cx.reporter.note(
                "sweep",
                &format!(
                    "computing every case: the previous sweep's {rows} IDA rows are more than \
                     the {} a rerun takes into memory",
                    reuse::MAX_TAKEN_ROWS
                ),
            );
            Vec::new()
        }
    }
}

/// Runs `cases` (after handing the writer the `reused` results) and
/// returns the writer's tally. Workers take cases in order
/// from one counter and hand each result to a writer thread, which adds a
/// chunk to the final tables as soon as its last case is in (and saves it
/// as parts once its [`Hold`] says so): no worker waits for a chunk's
/// slowest case or for the writes. The writer is made on its thread.
fn run_chunks<'a, R: Fn(&Tally) + 'a>(
    cases: &[usize],
    prep: &Prepared,
    writer: impl FnOnce() -> Result<ChunkWriter<'a, R>, SweepError> + Send,
    reused: Vec<(usize, CaseResult)>,
    delay: Option<std::time::Duration>,
) -> Result<Tally, SweepError> {
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let (tx, rx) = mpsc::channel::<(usize, Result<CaseResult, SweepError>)>();
    std::thread::scope(|ts| {
        let stop = &stop;
        let writer = ts.spawn(move || {
            let saved = (|| {
                let mut chunks = writer()?;
                for (case, result) in reused {
                    chunks.take(case, result)?;
                }
                let mut results = rx.iter().map(|(i, r)| (cases[i], r));
                while let Some((case, result)) = results.next() {
                    match result {
                        Ok(r) => chunks.take(case, r)?,
                        // A failed or interrupted sweep keeps the chunks it
                        // completed, however early: a rerun resumes there.
                        Err(e) => return Err(chunks.keep_completed(e, results)),
                    }
                }
                chunks.finish()
            })();
            if saved.is_err() {
                stop.store(true, Ordering::Relaxed);
            }
            saved
        });
        rayon::scope(|s| {
            for _ in 0..rayon::current_num_threads() {
                let tx = tx.clone();
                let next = &next;
                s.spawn(move |_| {
                    while !stop.load(Ordering::Relaxed) {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(&case) = cases.get(i) else { break };
                        if let Some(d) = delay {
                            std::thread::sleep(d);
                        }
                        let result = run_case(case, prep);
                        let failed = result.is_err();
                        if tx.send((i, result)).is_err() || failed {
                            stop.store(true, Ordering::Relaxed);
                        }
                    }
                });
            }
        });
        drop(tx);
        writer
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
    })
}

/// The sweep's summary: the work done, its speed, and the tables written.
/// What a sweep says of the tables it superseded and removed (`removed`,
/// file names): the unsharded tables, or the tables of shards of another
/// count (how many shards of which counts), by `shard` or the whole sweep.
fn superseded_line(removed: &[String], shard: Option<crate::stages::Shard>) -> Option<String> {
    if removed.is_empty() {
        return None;
    }
    let shard_sets: std::collections::BTreeSet<&str> = removed
        .iter()
        .filter_map(|n| n.split_once(".shard-").map(|(_, rest)| rest))
        .collect();
    let whole = removed.iter().filter(|n| !n.contains(".shard-")).count();
    let mut what = Vec::new();
    if whole > 0 {
        what.push(format!("the unsharded sweep's tables ({whole} files)"));
    }
    if !shard_sets.is_empty() {
        let files = removed.len() - whole;
        what.push(format!(
            "the tables of {} earlier shard{} ({files} files)",
            shard_sets.len(),
            if shard_sets.len() == 1 { "" } else { "s" }
        ));
    }
    Some(format!(
        "removed {}: superseded by {}",
        what.join(" and "),
        shard.map_or("this whole sweep".to_string(), |s| format!("shard {s}"))
    ))
}

fn summary(
    cx: &Context,
    setup: &Setup,
    tally: &Tally,
    started: Instant,
    ida_path: &std::path::Path,
    cap_path: &std::path::Path,
) -> Summary {
    let plan = &cx.study.plan;
    let secs = started.elapsed().as_secs_f64();
    let threads = rayon::current_num_threads();
    let mut lines = vec![format!(
        "swept {} records × {} blocks = {} cases{} ({} resumed from an earlier run{}): {} runs \
         (and {} more to certify them) in {:.1} s ({:.0} runs/s; {} sample intervals, {:.0} ns each \
         per thread)",
        setup.prep.records.len(),
        plan.blocks().len(),
        setup.cases_total,
        cx.shard.map_or(String::new(), |s| format!(" in shard {s}")),
        tally.cases_resumed,
        match tally.cases_reused {
            0 => String::new(),
            n => format!(", {n} taken from the previous sweep"),
        },
        tally.runs,
        tally.check_runs,
        secs,
        (tally.runs + tally.check_runs) as f64 / secs.max(1e-9),
        tally.intervals,
        secs * threads as f64 * 1e9 / (tally.intervals.max(1) as f64)
    )];
    lines.push(format!(
        "wrote {} and {}",
        ida_path.display(),
        cap_path.display()
    ));
    Summary {
        lines,
        headline: 0,
        also_wrote: Vec::new(),
    }
}
