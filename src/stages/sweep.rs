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

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc;
use std::time::Instant;

use rayon::prelude::*;

use super::records::{self, SelectError};
use super::stage::{BoxError, Context, Progress, Shard, Stage, Study, Summary};
use crate::ida::{self, RunKind};
use crate::physics::{Excitation, PhysicsError, RunSpec};
use crate::pipeline::{BlockSpec, Plan};
use crate::tables::records::RecordRow;
use crate::tables::sweep::{CapacityRow, IdaRow};
use crate::tables::{self, TableError};

/// Cases per chunk (and per part file).
pub const CHUNK_CASES: usize = 32;

/// Metadata keys of every sweep table.
pub const META_PLAN_HASH: &str = "rocking.sweep.plan_hash";
pub const META_PLAN: &str = "rocking.sweep.plan";
pub const META_SHARD: &str = "rocking.sweep.shard";
/// The settings that determine the results ([`Plan::sweep_settings`]).
pub const META_SETTINGS: &str = "rocking.sweep.settings";
/// The chunk a part file holds.
pub const META_CHUNK: &str = "rocking.sweep.chunk";

/// What a sweep table's metadata says about how it was made.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SweepMeta {
    pub plan_hash: Option<String>,
    /// [`Plan::sweep_settings`] of the plan that made it.
    pub settings: Option<String>,
    /// The chunk a part file holds.
    pub chunk: Option<String>,
}

impl SweepMeta {
    /// Reads the metadata of a sweep table or part file (its footer only).
    pub fn read(path: &Path) -> Result<SweepMeta, TableError> {
        let kv = tables::read_metadata(path)?;
        let get = |key: &str| kv.iter().find(|(k, _)| k == key).map(|(_, v)| v.clone());
        Ok(SweepMeta {
            plan_hash: get(META_PLAN_HASH),
            settings: get(META_SETTINGS),
            chunk: get(META_CHUNK),
        })
    }
}

/// Environment variable for fault-injection tests: abort the process (as a
/// crash would) once this many chunks are complete (and those due saved).
pub const FAULT_ENV: &str = "ROCKING_FAULT_AFTER_CHUNKS";

/// How long a sweep runs before it saves its first parts. Saving a chunk
/// (two Parquet files created, encoded, synced and renamed, then deleted at
/// the end) costs the writer thread about 2 ms of CPU, taken from the
/// workers on a machine with as many cores as workers: saving all 165 of
/// the paper sweep's chunks made it 3 % slower (docs/BENCHMARKS.md), and a
/// sweep shorter than this is quicker to redo than to save. The chunks
/// completed before are saved at the first case's result after it, and
/// from then on every chunk as it completes: beyond the unfinished chunks,
/// which a crash always loses, it loses at most this much work.
pub const CHECKPOINT_AFTER: std::time::Duration = std::time::Duration::from_secs(10);

/// The most IDA rows held unsaved (about 130 MB as Arrow arrays): a sweep
/// that completes this many before [`CHECKPOINT_AFTER`] saves them then.
pub const MAX_HELD_ROWS: usize = 1_000_000;

/// Environment variable for tests: hold exactly this many first chunks
/// (instead of [`CHECKPOINT_AFTER`]'s worth) before saving any; `0` saves
/// every chunk as it completes.
pub const HOLD_ENV: &str = "ROCKING_HOLD_CHUNKS";

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

#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error(transparent)]
    Records(#[from] SelectError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("block p = {p}, ε = {eps}")]
    Block {
        p: f64,
        eps: f64,
        #[source]
        source: PhysicsError,
    },
    #[error("record {record}")]
    Record {
        record: String,
        #[source]
        source: PhysicsError,
    },
    #[error("{path}")]
    Io {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    #[error(
        "--shard {shard}: the sweep has {chunks} chunk(s) of {CHUNK_CASES} cases, so at most \
         {chunks} shards have work; give N ≤ {chunks}"
    )]
    TooManyShards { shard: Shard, chunks: usize },
}

/// Final table names of an unsharded run or of one shard.
fn final_names(shard: Option<Shard>) -> (String, String) {
    match shard {
        None => ("ida_points.parquet".into(), "capacities.parquet".into()),
        Some(s) => (
            format!("ida_points.{}.parquet", s.tag()),
            format!("capacities.{}.parquet", s.tag()),
        ),
    }
}

/// Hash of everything that determines the sweep's output.
pub fn plan_hash(plan: &Plan, records: &[RecordRow]) -> String {
    let mut text = String::from(env!("CARGO_PKG_VERSION"));
    text.push_str(&format!(
        "ida_points/{} capacities/{}",
        <IdaRow as tables::Table>::KIND.schema_version,
        <CapacityRow as tables::Table>::KIND.schema_version
    ));
    // Only what changes the results: not the name, where the records are, or reduce's settings.
    text.push_str(&plan.sweep_settings());
    for r in records {
        text.push_str(&r.record_id);
        text.push_str(&r.sha256);
    }
    crate::hash::sha256_hex(text.as_bytes())
}

/// Each block's run specification, resolved once, and the reasons for the models.
fn block_specs(
    plan: &Plan,
    blocks: &[BlockSpec],
) -> Result<(Vec<RunSpec>, Vec<String>), SweepError> {
    let mut specs = Vec::new();
    let mut why = BTreeSet::new();
    for b in blocks {
        let block_err = |source| SweepError::Block {
            p: b.p,
            eps: b.eps,
            source,
        };
        let (model, reason) = plan
            .model
            .resolve(b.alpha_rad, plan.rtol, plan.auto_tol)
            .map_err(block_err)?;
        let spec = RunSpec {
            overturn: plan.overturn,
            ..RunSpec::new(b.p, b.eps, 1.0, model)
        };
        spec.validate().map_err(block_err)?;
        why.insert(reason);
        specs.push(spec);
    }
    Ok((specs, why.into_iter().collect()))
}

/// Everything a chunk needs, prepared once: the records, their
/// excitations, and the blocks (the plan's, or the `example` stage's one).
pub(super) struct Prepared {
    pub(super) records: Vec<RecordRow>,
    excitations: Vec<Excitation>,
    blocks: Vec<BlockSpec>,
    specs: Vec<RunSpec>,
    hash: String,
    plan_json: String,
    pub(super) n_cases: usize,
}

impl Prepared {
    /// The plan's records with `blocks`; also the models' reasons.
    pub(super) fn new(
        study: &Study,
        blocks: &[BlockSpec],
    ) -> Result<(Prepared, Vec<String>), SweepError> {
        let plan = &study.plan;
        let records = records::select(plan, &study.records_table())?;
        let (specs, models) = block_specs(plan, blocks)?;
        let excitations = records
            .par_iter()
            .map(|r| {
                Excitation::new(&r.accel_g, r.dt_s).map_err(|source| SweepError::Record {
                    record: r.record_id.clone(),
                    source,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let prepared = Prepared {
            hash: plan_hash(plan, &records),
            plan_json: plan.portable_json().to_string(),
            n_cases: records.len() * blocks.len(),
            records,
            excitations,
            blocks: blocks.to_vec(),
            specs,
        };
        Ok((prepared, models))
    }

    fn chunk_cases(&self, c: usize) -> std::ops::Range<usize> {
        let start = c * CHUNK_CASES;
        start..(start + CHUNK_CASES).min(self.n_cases)
    }

    fn metadata(
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
struct Tally {
    cases_done: usize,
    cases_resumed: usize,
    runs: u64,
    /// Runs the certification added (not in the IDA table).
    check_runs: u64,
    intervals: u64,
}

/// Gathers finished cases into their chunks and adds each chunk, in order,
/// to the final tables as soon as it and every chunk before it are
/// complete (a resumed chunk from its parts); the tables are committed once
/// the last chunk is in, so the sweep's end has no tables left to assemble.
/// A slow case holds back only the writes, not the workers. The completed
/// chunks are saved as parts, in order, once [`Hold`] allows (checked at
/// every case's result; those held first): the saved parts are always the
/// first chunks of the sweep, as a crash leaves them.
struct ChunkWriter<'a, R> {
    prep: &'a Prepared,
    plan: &'a Plan,
    parts: &'a Path,
    /// Fault injection: abort once this many chunks are complete (and
    /// those due saved).
    fault_after: Option<usize>,
    report: &'a R,
    /// The chunks still to add to the final tables, in order.
    order: VecDeque<usize>,
    /// Those of them whose parts an earlier run saved.
    resumed: BTreeSet<usize>,
    /// The final tables, written as the chunks come in.
    ida: tables::Appender<IdaRow>,
    cap: tables::Appender<CapacityRow>,
    /// Chunks with some cases in, by index: each case's result in its slot.
    pending: BTreeMap<usize, Vec<Option<CaseResult>>>,
    /// When the completed chunks start being saved as parts.
    hold: Hold,
    /// Chunks complete but not saved yet, in order.
    held: Vec<Held>,
    /// Chunks this run completed.
    completed: usize,
    tally: Tally,
}

/// A completed chunk's rows, as added to the final tables.
struct Held {
    chunk: usize,
    ida: tables::Batches<IdaRow>,
    cap: tables::Batches<CapacityRow>,
}

/// When a sweep starts saving the chunks it completes as parts.
#[derive(Debug, Clone, Copy)]
enum Hold {
    /// At this instant, or once [`MAX_HELD_ROWS`] IDA rows are held.
    Until(Instant),
    /// Once more than this many chunks are complete ([`HOLD_ENV`]).
    Chunks(usize),
}

impl Hold {
    /// Whether the held chunks are saved now, with `completed` chunks
    /// complete and `held_rows` IDA rows held.
    fn due(self, completed: usize, held_rows: usize, now: Instant) -> bool {
        match self {
            Hold::Until(t) => held_rows >= MAX_HELD_ROWS || now >= t,
            Hold::Chunks(n) => completed > n,
        }
    }
}

impl<R: Fn(&Tally)> ChunkWriter<'_, R> {
    /// Takes one case's result, adds the chunks it completes to the final
    /// tables, and saves the held chunks as parts if that is due (also
    /// while a slow case holds the next chunk back).
    fn take(&mut self, case: usize, result: CaseResult) -> Result<(), SweepError> {
        let c = case / CHUNK_CASES;
        let range = self.prep.chunk_cases(c);
        self.pending
            .entry(c)
            .or_insert_with(|| range.clone().map(|_| None).collect())[case - range.start] =
            Some(result);
        self.flush()?;
        self.checkpoint()
    }

    /// Saves the held chunks as parts, in order, if [`Hold`] says so.
    fn checkpoint(&mut self) -> Result<(), SweepError> {
        let held_rows = self.held.iter().map(|h| h.ida.rows()).sum();
        if self.held.is_empty() || !self.hold.due(self.completed, held_rows, Instant::now()) {
            return Ok(());
        }
        for h in self.held.drain(..) {
            let (ida_part, cap_part) = part_paths(self.parts, h.chunk);
            let meta = self.prep.metadata(self.plan, Some(h.chunk), None);
            tables::write_batches(&ida_part, &h.ida, &meta)?;
            tables::write_batches(&cap_part, &h.cap, &meta)?;
        }
        Ok(())
    }

    /// Adds the chunks at the front of the order that are complete (or
    /// were resumed) to the final tables, holding the new ones to be saved
    /// as parts.
    fn flush(&mut self) -> Result<(), SweepError> {
        while let Some(&c) = self.order.front() {
            if self.resumed.contains(&c) {
                let (ida_part, cap_part) = part_paths(self.parts, c);
                self.ida.table(&ida_part)?;
                self.cap.table(&cap_part)?;
            } else {
                let complete = self
                    .pending
                    .get(&c)
                    .is_some_and(|slots| slots.iter().all(Option::is_some));
                if !complete {
                    break;
                }
                let results = self.pending.remove(&c).into_iter().flatten().flatten();
                self.save(c, results)?;
            }
            self.order.pop_front();
        }
        Ok(())
    }

    /// Commits the final tables once every chunk is in.
    fn finish(mut self) -> Result<Tally, SweepError> {
        self.flush()?;
        if let Some(c) = self.order.front() {
            // Only reached when a worker stopped early, which reports its own error.
            return Err(SweepError::Io {
                path: self.parts.to_path_buf(),
                source: io::Error::other(format!("chunk {c} was never completed")),
            });
        }
        self.ida.commit()?;
        self.cap.commit()?;
        Ok(self.tally)
    }

    /// Adds chunk `c`, from its cases' results in case order, to the final
    /// tables, and saves it as parts with the chunks held before it once
    /// [`Hold`] allows; else holds it.
    fn save(
        &mut self,
        c: usize,
        results: impl Iterator<Item = CaseResult>,
    ) -> Result<(), SweepError> {
        let mut ida_rows = Vec::new();
        let mut cap_rows = Vec::with_capacity(CHUNK_CASES);
        for r in results {
            self.tally.runs += r.ida.len() as u64;
            self.tally.check_runs += r.check_runs as u64;
            self.tally.intervals += r.intervals;
            ida_rows.extend(r.ida);
            cap_rows.push(r.capacity);
        }
        let ida = self.ida.rows_as_read(&ida_rows)?;
        let cap = self.cap.rows_as_read(&cap_rows)?;
        self.held.push(Held { chunk: c, ida, cap });
        self.completed += 1;
        self.checkpoint()?;
        self.tally.cases_done += cap_rows.len();
        (self.report)(&self.tally);
        if self.fault_after.is_some_and(|n| self.completed >= n) {
            // Fault injection for the resume tests: die as a crash would.
            std::process::abort();
        }
        Ok(())
    }
}

/// Runs the sweep (or one shard of it).
fn run(cx: &Context) -> Result<Summary, SweepError> {
    let started = Instant::now();
    let study = cx.study;
    let plan = &study.plan;
    let (prep, models) = Prepared::new(study, &plan.blocks)?;
    for m in &models {
        cx.reporter.note("sweep", &format!("model: {m}"));
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
    let fault_after: Option<usize> = std::env::var(FAULT_ENV).ok().and_then(|v| v.parse().ok());
    let hold = match std::env::var(HOLD_ENV).ok().and_then(|v| v.parse().ok()) {
        Some(n) => Hold::Chunks(n),
        None => Hold::Until(started + CHECKPOINT_AFTER),
    };

    let mut tally = Tally::default();
    let report = |t: &Tally| {
        cx.reporter.progress(&Progress {
            stage: "sweep",
            done: t.cases_done as u64,
            total: cases_total as u64,
            resumed: t.cases_resumed as u64,
            runs: t.runs,
        })
    };
    report(&tally);
    // Chunks whose parts are already there and current are kept.
    let (mut todo, mut resumed) = (Vec::new(), BTreeSet::new());
    for &c in &mine {
        let (ida_part, cap_part) = part_paths(&parts, c);
        let cases = prep.chunk_cases(c);
        match verify_part(&ida_part, &cap_part, &prep.hash, c, cases.clone()) {
            Ok(()) => {
                tally.cases_done += cases.len();
                tally.cases_resumed += cases.len();
                report(&tally);
                resumed.insert(c);
                continue;
            }
            Err(PartProblem::Absent) => {}
            Err(PartProblem::Stale) => {}
            Err(PartProblem::Corrupt(why)) => cx.reporter.note(
                "sweep",
                &format!(
                    "part {} of chunk {c} is not that chunk's ({why}); recomputing it",
                    cap_part.display()
                ),
            ),
        }
        todo.push(c);
    }
    let cases: Vec<usize> = todo.iter().flat_map(|&c| prep.chunk_cases(c)).collect();
    let (ida_name, cap_name) = final_names(cx.shard);
    let (ida_path, cap_path) = (study.path(&ida_name), study.path(&cap_name));
    // A killed run's temporaries of this run's tables (the lock refuses any
    // other writer of them).
    remove_where(&study.dir, |name| {
        temporary_of(name).is_some_and(|(t, _pid)| t == ida_name || t == cap_name)
    })?;
    // Workers take cases in order from one counter and hand each result to
    // a writer thread, which adds a chunk to the final tables as soon as its
    // last case is in (and saves it as parts once `hold` says so): no worker
    // waits for a chunk's slowest case or for the writes.
    let next = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let (tx, rx) = mpsc::channel::<(usize, Result<CaseResult, SweepError>)>();
    let final_meta = prep.metadata(plan, None, cx.shard);
    let tally = std::thread::scope(|ts| {
        let (cases, prep, parts, report, stop) = (&cases, &prep, &parts, &report, &stop);
        let (ida_path, cap_path, mine) = (&ida_path, &cap_path, &mine);
        let writer = ts.spawn(move || {
            let saved = (|| {
                let mut chunks = ChunkWriter {
                    prep,
                    plan,
                    parts,
                    fault_after,
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
                };
                for (i, result) in rx.iter() {
                    chunks.take(cases[i], result?)?;
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
                        let result = run_case(case, prep, plan);
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
    })?;
    clean_up(study, &mine, cx.shard)?;
    let secs = started.elapsed().as_secs_f64();
    let threads = rayon::current_num_threads();
    let mut lines = vec![format!(
        "swept {} records × {} blocks = {} cases{} ({} resumed from an earlier run): {} runs \
         (and {} more to certify them) in {:.1} s ({:.0} runs/s; {} sample intervals, {:.0} ns each \
         per thread)",
        prep.records.len(),
        plan.blocks.len(),
        cases_total,
        cx.shard.map_or(String::new(), |s| format!(" in shard {s}")),
        tally.cases_resumed,
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
    Ok(Summary {
        lines,
        also_wrote: Vec::new(),
    })
}

/// Once the final tables are in place: removes this run's parts, and the
/// tables the new ones supersede (shards after an unsharded run and the
/// reverse).
fn clean_up(study: &Study, mine: &[usize], shard: Option<Shard>) -> Result<(), SweepError> {
    let parts = study.path("parts");
    for &c in mine {
        let (ida_part, cap_part) = part_paths(&parts, c);
        let _ = fs::remove_file(ida_part);
        let _ = fs::remove_file(cap_part);
    }
    // Only if empty (other shards may still write here).
    let _ = fs::remove_dir(&parts);
    // The tables this run supersedes, and the temporaries a killed run left
    // of them: after an unsharded run every shard's; after a shard of N,
    // the unsharded tables and the shards of another count (a re-sharded
    // sweep). The lock refuses every other writer of those names.
    let (ida, cap) = final_names(None);
    let superseded = |table: &str| {
        let a_shard = table.contains(".shard-") && table.ends_with(".parquet");
        match shard {
            None => a_shard,
            Some(done) => {
                table == ida
                    || table == cap
                    || a_shard && !table.ends_with(&format!("-of-{}.parquet", done.n))
            }
        }
    };
    remove_where(&study.dir, |name| {
        superseded(temporary_of(name).map_or(name, |(table, _pid)| table))
    })
}

/// The file a hidden temporary was being written as and its writer's pid
/// (`.NAME.tmp-PID` → `(NAME, PID)`).
fn temporary_of(name: &str) -> Option<(&str, &str)> {
    name.strip_prefix('.')?.rsplit_once(".tmp-")
}

fn part_paths(parts: &Path, c: usize) -> (PathBuf, PathBuf) {
    (
        parts.join(format!("ida-{c:06}.parquet")),
        parts.join(format!("cap-{c:06}.parquet")),
    )
}

/// Why a part cannot be reused.
enum PartProblem {
    Absent,
    /// From another plan (the settings changed): recomputed silently.
    Stale,
    /// Current plan, wrong content (copied over, truncated): recomputed and logged.
    Corrupt(String),
}

/// Trusts a chunk's parts by what they hold: the current plan's hash, this
/// chunk's index, one capacity per case of the chunk in order, and exactly
/// the runs each capacity counts.
fn verify_part(
    ida_part: &Path,
    cap_part: &Path,
    hash: &str,
    chunk: usize,
    cases: std::ops::Range<usize>,
) -> Result<(), PartProblem> {
    if !(ida_part.exists() && cap_part.exists()) {
        return Err(PartProblem::Absent);
    }
    for p in [ida_part, cap_part] {
        let meta =
            SweepMeta::read(p).map_err(|e| PartProblem::Corrupt(format!("unreadable: {e}")))?;
        if meta.plan_hash.as_deref() != Some(hash) {
            return Err(PartProblem::Stale);
        }
        if meta.chunk != Some(chunk.to_string()) {
            return Err(PartProblem::Corrupt(format!(
                "its metadata says chunk {}",
                meta.chunk.as_deref().unwrap_or("(none)")
            )));
        }
    }
    let corrupt = |e: TableError| PartProblem::Corrupt(e.to_string());
    let caps: Vec<CapacityRow> = tables::read(cap_part).map_err(corrupt)?;
    let expected: Vec<i64> = cases.map(|c| c as i64).collect();
    let got: Vec<i64> = caps.iter().map(|c| c.case_id).collect();
    if got != expected {
        return Err(PartProblem::Corrupt(format!(
            "it holds cases {}, expected {}",
            span(&got),
            span(&expected)
        )));
    }
    let ida: Vec<IdaRow> = tables::read(ida_part).map_err(corrupt)?;
    let mut counts = vec![0i64; caps.len()];
    for r in &ida {
        let k = r.case_id - expected[0];
        if k < 0 || k as usize >= counts.len() {
            return Err(PartProblem::Corrupt(format!(
                "its IDA points include case {}",
                r.case_id
            )));
        }
        counts[k as usize] += 1;
    }
    if let Some((c, n)) = caps.iter().zip(&counts).find(|(c, n)| c.runs != **n) {
        return Err(PartProblem::Corrupt(format!(
            "case {} counts {} runs but has {n} IDA points",
            c.case_id, c.runs
        )));
    }
    Ok(())
}

fn span(ids: &[i64]) -> String {
    match (ids.first(), ids.last()) {
        (Some(a), Some(b)) => format!("{a}–{b}"),
        _ => "none".into(),
    }
}

/// Removes the files of `dir` whose names `stale` picks.
fn remove_where(dir: &Path, stale: impl Fn(&str) -> bool) -> Result<(), SweepError> {
    let entries = fs::read_dir(dir).map_err(|source| SweepError::Io {
        path: dir.into(),
        source,
    })?;
    for e in entries.flatten() {
        if stale(&e.file_name().to_string_lossy()) {
            let _ = fs::remove_file(e.path());
        }
    }
    Ok(())
}

/// Removes temporary files left by a killed run (`.ida-000042.parquet.tmp-PID`),
/// only for this shard's chunks: other shards may be writing beside it.
fn remove_stale_temporaries(dir: &Path, mine: &[usize]) -> Result<(), SweepError> {
    let mine: BTreeSet<usize> = mine.iter().copied().collect();
    remove_where(dir, |name| {
        // The writer's PID ends the name: a live writer's file is not stale.
        let Some((part, pid)) = temporary_of(name) else {
            return false;
        };
        let chunk = part
            .strip_prefix("ida-")
            .or_else(|| part.strip_prefix("cap-"))
            .and_then(|r| r.split('.').next())
            .and_then(|c| c.parse::<usize>().ok());
        let writer_alive = Path::new("/proc").join(pid).exists();
        !writer_alive && chunk.is_some_and(|c| mine.contains(&c))
    })
}

/// A case's IDA points and capacity, the runs its certification added,
/// and the sample intervals the search and its certification took.
pub(super) struct CaseResult {
    pub(super) ida: Vec<IdaRow>,
    pub(super) capacity: CapacityRow,
    check_runs: usize,
    intervals: u64,
}

pub(super) fn run_case(
    case: usize,
    prep: &Prepared,
    plan: &Plan,
) -> Result<CaseResult, SweepError> {
    let n_blocks = prep.blocks.len();
    let (ri, bi) = (case / n_blocks, case % n_blocks);
    let (record, spec, block) = (&prep.records[ri], prep.specs[bi], &prep.blocks[bi].name);
    let certified = ida::capacity_certified(
        &prep.excitations[ri],
        &spec,
        &plan.grid,
        plan.tol,
        plan.trace,
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
        })
        .collect();
    let row = CapacityRow {
        case_id: case as i64,
        record_id: record.record_id.clone(),
        block: block.clone(),
        p: spec.p,
        eps: spec.eps,
        alpha_rad,
        model,
        eta_c: cap.eta_c,
        eta_survived: cap.eta_survived,
        level_survived: cap.level_survived,
        level_overturned: cap.level_overturned,
        runs: cap.points.len() as i64,
        resurrections: cap.resurrections.map(|r| r as i64),
        certified: certified.certification.certified(),
        certification: certified.certification.kind(),
        certification_note: certified.certification.to_string(),
        rtol: certified.model.integrator.rtol(),
    };
    Ok(CaseResult {
        ida,
        capacity: row,
        check_runs: certified.extra.runs,
        intervals: cap.points.iter().map(|q| q.outcome.intervals).sum::<u64>()
            + certified.extra.intervals,
    })
}

/// A folder's sweep tables cannot be read as one dataset.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    #[error("{0}: no sweep tables (run `rocking sweep` first)")]
    NoTables(PathBuf),
    #[error(
        "{dir}: holds both the unsharded sweep tables (ida_points.parquet, capacities.parquet) and \
         {shards} shard table(s) (*.shard-K-of-N.parquet); they are two versions of the same sweep: \
         remove one set"
    )]
    Mixed { dir: PathBuf, shards: usize },
    #[error("{dir}: shard tables of different shard counts ({counts}); remove the stale ones")]
    ShardCounts { dir: PathBuf, counts: String },
    #[error("{dir}: shards {missing} of the sweep are missing; run them with `rocking sweep … --shard K/{n}`")]
    MissingShards {
        dir: PathBuf,
        missing: String,
        n: usize,
    },
    #[error("{dir}: the shards come from different plans; rerun the stale ones")]
    ShardPlans { dir: PathBuf },
    #[error("{dir}: only one of ida_points.parquet and capacities.parquet is there; rerun `rocking sweep`")]
    HalfTables { dir: PathBuf },
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("{path}")]
    Io {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
}

/// The sweep tables of a study folder, as one dataset: the unsharded tables,
/// or all N shards (every one required, all from the same plan), never a mix.
/// Returns (ida_points files, capacities files).
pub fn dataset(dir: &Path) -> Result<(Vec<PathBuf>, Vec<PathBuf>), DatasetError> {
    let entries = fs::read_dir(dir).map_err(|source| DatasetError::Io {
        path: dir.into(),
        source,
    })?;
    let mut shard_files = 0;
    let mut counts = BTreeSet::new();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name
            .strip_prefix("capacities.shard-")
            .or_else(|| name.strip_prefix("ida_points.shard-"))
            .and_then(|r| r.strip_suffix(".parquet"))
        else {
            continue;
        };
        shard_files += 1;
        if let Some(n) = rest
            .split_once("-of-")
            .and_then(|(_, n)| n.parse::<usize>().ok())
        {
            counts.insert(n);
        }
    }
    let (ida, cap) = final_names(None);
    let (ida, cap) = (dir.join(ida), dir.join(cap));
    match (ida.exists(), cap.exists(), shard_files) {
        (true, true, 0) => return Ok((vec![ida], vec![cap])),
        (true, _, s) | (_, true, s) if s > 0 => {
            return Err(DatasetError::Mixed {
                dir: dir.into(),
                shards: s,
            })
        }
        (true, false, _) | (false, true, _) => {
            return Err(DatasetError::HalfTables { dir: dir.into() })
        }
        _ => {}
    }
    let n = match counts.len() {
        0 => return Err(DatasetError::NoTables(dir.into())),
        1 => *counts.iter().next().expect("one"),
        _ => {
            return Err(DatasetError::ShardCounts {
                dir: dir.into(),
                counts: counts
                    .iter()
                    .map(|n| format!("of {n}"))
                    .collect::<Vec<_>>()
                    .join(", "),
            })
        }
    };
    let mut idas = Vec::new();
    let mut caps = Vec::new();
    let mut missing = Vec::new();
    let mut hashes = BTreeSet::new();
    // Shards are looked for up to N, but never more than ten past the ones
    // that exist: a file name claiming a huge N must not make this loop long.
    let mut k = 0;
    while k < n && missing.len() < 10 {
        k += 1;
        let (i, c) = final_names(Some(Shard { k, n }));
        let (i, c) = (dir.join(i), dir.join(c));
        if !(i.exists() && c.exists()) {
            missing.push(format!("{k}/{n}"));
            continue;
        }
        hashes.insert(SweepMeta::read(&c)?.plan_hash.unwrap_or_default());
        idas.push(i);
        caps.push(c);
    }
    if !missing.is_empty() {
        if k < n {
            missing.push("…".into());
        }
        return Err(DatasetError::MissingShards {
            dir: dir.into(),
            missing: missing.join(", "),
            n,
        });
    }
    if hashes.len() > 1 {
        return Err(DatasetError::ShardPlans { dir: dir.into() });
    }
    Ok((idas, caps))
}

/// Capacities of a dataset, in case order (shards interleaved back).
pub fn read_capacities(dir: &Path) -> Result<Vec<CapacityRow>, DatasetError> {
    let (_, caps) = dataset(dir)?;
    let mut rows: Vec<CapacityRow> = tables::read_all(&caps)?;
    rows.sort_by_key(|r| r.case_id);
    Ok(rows)
}

/// IDA points of a dataset, in case order (run order within a case).
pub fn read_ida(dir: &Path) -> Result<Vec<IdaRow>, DatasetError> {
    let (idas, _) = dataset(dir)?;
    let mut rows: Vec<IdaRow> = tables::read_all(&idas)?;
    rows.sort_by_key(|r| r.case_id); // stable: keeps run order within a case
    Ok(rows)
}

/// Runs kinds written by the sweep, for readers that filter grid levels.
pub fn is_level(r: &IdaRow) -> bool {
    r.run_kind == RunKind::Level
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn held_chunks_are_due_at_the_instant_or_the_row_limit_or_past_the_count() {
        let t0 = Instant::now();
        let until = Hold::Until(t0 + Duration::from_secs(10));
        // Before the instant, only the row limit makes saving due.
        assert!(!until.due(500, MAX_HELD_ROWS - 1, t0));
        assert!(until.due(1, MAX_HELD_ROWS, t0));
        // From the instant on, whatever is held.
        assert!(until.due(1, 0, t0 + Duration::from_secs(10)));
        assert!(!until.due(1, 0, t0 + Duration::from_millis(9_999)));
        // Holding two chunks: the third is the first saved, with both.
        let two = Hold::Chunks(2);
        assert!(!two.due(1, MAX_HELD_ROWS, t0));
        assert!(!two.due(2, 0, t0));
        assert!(two.due(3, 0, t0));
        assert!(Hold::Chunks(0).due(1, 0, t0));
    }
}
