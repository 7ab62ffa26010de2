//! Runs the stages of a study in registry order, each only when it is
//! stale (or forced), under the study folder's lock, and saves each stage's
//! fingerprint after it succeeds. `rocking run`, `rocking status`, `--from`,
//! `--to` and the per-stage commands (`rocking sweep`, `reduce`, …) all go
//! through here: one cache, one lock.

use std::fmt;
use std::time::Instant;

use super::fingerprint::{self, Note};
use super::lock::{Lock, LockError, Scope};
pub use super::reason::{Reason, Skip, Stale};
use super::stage::{BoxError, Context, Reporter, Shard, Stage, StageEvent, Study};
use super::STAGES;
use crate::tables;

/// Whether a stage must run, and why.
#[derive(Debug, Clone, PartialEq)]
pub enum Freshness {
    Fresh,
    /// Fresh as a complete set of N shards.
    FreshShards(usize),
    Stale(Vec<Stale>),
    /// Fresh itself, but it reads from this stage, which is stale: it will
    /// run once that one has (shown by `status`).
    Waits(&'static str),
    /// The pipeline does not need this stage (why).
    NotNeeded(String),
}

impl fmt::Display for Freshness {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Freshness::Fresh => f.write_str("fresh"),
            Freshness::FreshShards(n) => write!(f, "fresh ({n} shards)"),
            Freshness::Stale(why) => write!(f, "stale: {}", Reason::Stale(why.clone())),
            Freshness::Waits(on) => {
                write!(f, "stale: it reads `{on}`'s outputs, which will change")
            }
            Freshness::NotNeeded(why) => write!(f, "not needed: {why}"),
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Lock(#[from] LockError),
    #[error("stage `{stage}` failed")]
    Stage {
        stage: &'static str,
        #[source]
        source: BoxError,
    },
    #[error("stage `{stage}` succeeded but its fingerprint could not be saved")]
    Note {
        stage: &'static str,
        #[source]
        source: BoxError,
    },
    #[error(
        "`{stage}`: {why}; run them with `rocking {stage} {pipeline} --shard K/{n}`, \
         or recompute the whole stage unsharded with --force"
    )]
    ShardsIncomplete {
        stage: &'static str,
        why: String,
        n: usize,
        pipeline: String,
    },
    #[error("this pipeline does not need `{stage}`: {why}")]
    NotNeeded { stage: &'static str, why: String },
    #[error("--from {from} comes after --to {to}: nothing would be forced")]
    FromAfterTo {
        from: &'static str,
        to: &'static str,
    },
    #[error("stage `{0}` cannot be split into shards")]
    NotShardable(&'static str),
    #[error(
        "{asked} worker threads is more than {max} (4 × the {cores} cores here): more threads \
         than cores only add overhead"
    )]
    TooManyThreads {
        asked: usize,
        max: usize,
        cores: usize,
    },
    #[error("worker threads must be at least 1")]
    NoThreads,
    #[error("cannot start {threads} worker threads")]
    Threads {
        threads: usize,
        #[source]
        source: rayon::ThreadPoolBuildError,
    },
}

/// Which stages a run covers.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum Target {
    /// Every stage (`rocking run`).
    #[default]
    All,
    /// This stage and every stage before it (`rocking run --to STAGE`).
    Through(&'static dyn Stage),
    /// This stage and the earlier stages it reads from, transitively
    /// (`rocking <stage>`): the sweep's command does not run the
    /// convergence study, the report's does.
    For(&'static dyn Stage),
}

/// Which stages to run, and which to force.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    pub target: Target,
    /// What to force: `--force` of `run` (every stage), `--from`, or the
    /// `--force` of a stage command (its stage only).
    pub force: Force,
    /// Run the target stage as one shard.
    pub shard: Option<Shard>,
    /// Worker threads (default: one per core).
    pub threads: Option<usize>,
    /// The command, for the lock file and messages.
    pub command: String,
}

/// What `--force` and `--from` ask.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum Force {
    #[default]
    Nothing,
    /// Every stage run.
    All,
    /// The last stage run (the target of a stage command).
    Target,
    /// This stage and every later one.
    From(&'static dyn Stage),
}

/// What happened to one stage.
#[derive(Debug, Clone)]
pub struct StageResult {
    pub stage: &'static str,
    pub outcome: Outcome,
}

#[derive(Debug, Clone)]
pub enum Outcome {
    Ran {
        reason: Reason,
        seconds: f64,
        lines: Vec<String>,
    },
    Skipped(Skip),
}

/// The stage registered under `name`.
pub fn find(name: &str) -> Option<&'static dyn Stage> {
    STAGES.iter().copied().find(|s| s.name() == name)
}

/// "ingest, sweep, …": the registered names, for messages.
pub fn names() -> String {
    STAGES
        .iter()
        .map(|s| s.name())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Is `stage` fresh? (Runs nothing.)
pub fn freshness(stage: &dyn Stage, study: &Study) -> Freshness {
    if let Some(why) = stage.not_needed(study) {
        return Freshness::NotNeeded(why);
    }
    let now = match fingerprint::parts(stage, study) {
        Ok(p) => p,
        Err(why) => return Freshness::Stale(why),
    };
    let whole = fingerprint::note_path(study, stage.name(), None);
    let why = match fingerprint::read_note(study, &whole) {
        Ok(note) => {
            let declared = stage.outputs(study, None);
            let why = fingerprint::compare(&now, &note, study, &declared);
            if why.is_empty() {
                return Freshness::Fresh;
            }
            why
        }
        Err(why) => vec![why],
    };
    if stage.shardable() {
        match shard_state(stage, study, &now) {
            Shards::None => {}
            Shards::Complete(n) => return Freshness::FreshShards(n),
            Shards::Incomplete { n, missing } => {
                let mut why = why;
                why.push(Stale::ShardsIncomplete { n, missing });
                return Freshness::Stale(why);
            }
        }
    }
    Freshness::Stale(why)
}

/// What the shard notes of a sharded stage say.
enum Shards {
    /// No shard has a fresh note.
    None,
    /// Every shard of N is fresh.
    Complete(usize),
    /// Some shards of N are fresh, these are not.
    Incomplete { n: usize, missing: Vec<usize> },
}

fn shard_state(
    stage: &dyn Stage,
    study: &Study,
    now: &std::collections::BTreeMap<String, String>,
) -> Shards {
    let notes = fingerprint::shard_notes(study, stage.name());
    let Some(n) = notes.last().map(|(s, _)| s.n) else {
        return Shards::None;
    };
    let fresh: std::collections::BTreeSet<usize> = notes
        .iter()
        .filter(|(s, _)| s.n == n)
        .filter(|(s, path)| {
            fingerprint::read_note(study, path).is_ok_and(|note| {
                let declared = stage.outputs(study, Some(*s));
                fingerprint::compare(now, &note, study, &declared).is_empty()
            })
        })
        .map(|(s, _)| s.k)
        .collect();
    match fresh.len() {
        0 => Shards::None,
        k if k == n => Shards::Complete(n),
        _ => Shards::Incomplete {
            n,
            // At most N − 1 of them, and N is bounded by the number of chunks.
            missing: (1..=n).filter(|k| !fresh.contains(k)).collect(),
        },
    }
}

/// Every stage's freshness, in order. A stage that is fresh itself but
/// reads from a stage that will run first is shown as waiting on it.
pub fn status(study: &Study) -> Vec<(&'static str, Freshness)> {
    let mut out: Vec<(&'static str, Freshness)> = Vec::new();
    for &stage in STAGES {
        let mut f = freshness(stage, study);
        if f == Freshness::Fresh {
            let upstream = covered(study, Target::For(stage));
            if let Some(&(name, _)) = out.iter().find(|(name, g)| {
                matches!(g, Freshness::Stale(_) | Freshness::Waits(_))
                    && upstream.iter().any(|u| u.name() == *name)
            }) {
                f = Freshness::Waits(name);
            }
        }
        out.push((stage.name(), f));
    }
    out
}

/// Where a stage stands in the registry.
fn index_of(stage: &dyn Stage) -> usize {
    STAGES
        .iter()
        .position(|s| s.name() == stage.name())
        .expect("a registered stage")
}

/// The stages a run covers, in order.
fn covered(study: &Study, target: Target) -> Vec<&'static dyn Stage> {
    let index = index_of;
    match target {
        Target::All => STAGES.to_vec(),
        Target::Through(t) => STAGES[..=index(t)].to_vec(),
        Target::For(t) => {
            let last = index(t);
            let mut needed = vec![false; last + 1];
            needed[last] = true;
            let mut wanted = produced_names(t.inputs(study).unwrap_or_default());
            for i in (0..last).rev() {
                let outs = produced_names(STAGES[i].outputs(study, None));
                if outs.iter().any(|o| wanted.contains(o)) {
                    needed[i] = true;
                    wanted.extend(produced_names(STAGES[i].inputs(study).unwrap_or_default()));
                }
            }
            (0..=last)
                .filter(|&i| needed[i])
                .map(|i| STAGES[i])
                .collect()
        }
    }
}

/// Files as the stage that writes them names them: a shard's table counts
/// as the unsharded table it is part of.
fn produced_names(files: Vec<std::path::PathBuf>) -> Vec<std::path::PathBuf> {
    files
        .into_iter()
        .map(|f| {
            let name = f
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            match name.split_once(".shard-") {
                Some((stem, rest)) => {
                    let ext = rest.rsplit_once('.').map_or("", |(_, e)| e);
                    f.with_file_name(format!("{stem}.{ext}"))
                }
                None => f,
            }
        })
        .collect()
}

/// Runs the stale (or forced) stages the target covers, in order.
pub fn run(
    study: &Study,
    opts: &RunOptions,
    reporter: &dyn Reporter,
) -> Result<Vec<StageResult>, RunError> {
    match (opts.target, opts.force) {
        (Target::For(t), _) => {
            if let Some(why) = t.not_needed(study) {
                return Err(RunError::NotNeeded {
                    stage: t.name(),
                    why,
                });
            }
        }
        (Target::Through(to), Force::From(from)) if index_of(from) > index_of(to) => {
            return Err(RunError::FromAfterTo {
                from: from.name(),
                to: to.name(),
            });
        }
        _ => {}
    }
    let stages = covered(study, opts.target);
    let last = stages.len() - 1;
    if let Some(n) = opts.threads {
        check_threads(n)?;
    }
    if let Some(shard) = opts.shard {
        return run_shard(study, &stages, shard, opts, reporter);
    }
    let _lock = Lock::take(&study.dir, Scope::Exclusive, &opts.command)?;
    with_threads(opts.threads, || {
        let mut results = Vec::new();
        let mut forced_from = false;
        for (i, &stage) in stages.iter().enumerate() {
            if let Force::From(f) = opts.force {
                forced_from |= f.name() == stage.name();
            }
            let fresh = freshness(stage, study);
            let reason = match fresh {
                Freshness::NotNeeded(why) => {
                    // A note left from when the pipeline needed it is not this study's.
                    let _ = std::fs::remove_file(fingerprint::note_path(study, stage.name(), None));
                    skip(&mut results, reporter, stage, Skip::NotNeeded(why));
                    continue;
                }
                _ if opts.force == Force::All => Reason::Forced,
                _ if opts.force == Force::Target && i == last => Reason::Forced,
                _ if forced_from => Reason::From(match opts.force {
                    Force::From(f) => f.name(),
                    _ => unreachable!("forced_from is set by Force::From only"),
                }),
                Freshness::Stale(why) => {
                    if let Some(Stale::ShardsIncomplete { n, missing }) = why
                        .iter()
                        .find(|w| matches!(w, Stale::ShardsIncomplete { .. }))
                    {
                        return Err(RunError::ShardsIncomplete {
                            stage: stage.name(),
                            why: Stale::ShardsIncomplete {
                                n: *n,
                                missing: missing.clone(),
                            }
                            .to_string(),
                            n: *n,
                            pipeline: study.pipeline.display().to_string(),
                        });
                    }
                    Reason::Stale(why)
                }
                // (`freshness` never says Waits: only `status` does.)
                Freshness::Fresh | Freshness::Waits(_) => {
                    skip(&mut results, reporter, stage, Skip::Fresh);
                    continue;
                }
                Freshness::FreshShards(n) => {
                    skip(&mut results, reporter, stage, Skip::FreshShards(n));
                    continue;
                }
            };
            results.push(run_one(study, stage, None, reason, reporter)?);
        }
        Ok(results)
    })
}

fn skip(
    results: &mut Vec<StageResult>,
    reporter: &dyn Reporter,
    stage: &'static dyn Stage,
    why: Skip,
) {
    reporter.stage(stage.name(), &StageEvent::Skipped(why.clone()));
    results.push(StageResult {
        stage: stage.name(),
        outcome: Outcome::Skipped(why),
    });
}

/// One shard of the last stage, under that shard's lock. Stale stages
/// before it run first, also under the shard's lock: the N shards of a
/// batch array may all find ingest stale and run it side by side, which is
/// safe because its output is deterministic and written atomically.
fn run_shard(
    study: &Study,
    stages: &[&'static dyn Stage],
    shard: Shard,
    opts: &RunOptions,
    reporter: &dyn Reporter,
) -> Result<Vec<StageResult>, RunError> {
    let (&target, before) = stages.split_last().expect("at least one stage");
    if !target.shardable() {
        return Err(RunError::NotShardable(target.name()));
    }
    let _lock = Lock::take(&study.dir, Scope::Shard(shard), &opts.command)?;
    with_threads(opts.threads, || {
        let mut results = Vec::new();
        for &stage in before {
            match freshness(stage, study) {
                Freshness::NotNeeded(why) => {
                    skip(&mut results, reporter, stage, Skip::NotNeeded(why))
                }
                Freshness::Fresh | Freshness::Waits(_) => {
                    skip(&mut results, reporter, stage, Skip::Fresh)
                }
                Freshness::FreshShards(n) => {
                    skip(&mut results, reporter, stage, Skip::FreshShards(n))
                }
                Freshness::Stale(why) => {
                    results.push(run_one(study, stage, None, Reason::Stale(why), reporter)?)
                }
            }
        }
        let reason = match (opts.force, freshness_of_shard(target, study, shard)) {
            (Force::Nothing, None) => {
                skip(&mut results, reporter, target, Skip::Fresh);
                return Ok(results);
            }
            (Force::Nothing, Some(why)) => Reason::Stale(why),
            _ => Reason::Forced,
        };
        results.push(run_one(study, target, Some(shard), reason, reporter)?);
        Ok(results)
    })
}

/// `None` when the shard's own note is fresh, else why not.
fn freshness_of_shard(stage: &dyn Stage, study: &Study, shard: Shard) -> Option<Vec<Stale>> {
    let now = match fingerprint::parts(stage, study) {
        Ok(p) => p,
        Err(why) => return Some(why),
    };
    let path = fingerprint::note_path(study, stage.name(), Some(shard));
    match fingerprint::read_note(study, &path) {
        Ok(note) => {
            let why = fingerprint::compare(&now, &note, study, &stage.outputs(study, Some(shard)));
            (!why.is_empty()).then_some(why)
        }
        Err(why) => Some(vec![why]),
    }
}

/// Runs one stage and saves its fingerprint.
fn run_one(
    study: &Study,
    stage: &'static dyn Stage,
    shard: Option<Shard>,
    reason: Reason,
    reporter: &dyn Reporter,
) -> Result<StageResult, RunError> {
    let name = stage.name();
    reporter.stage(name, &StageEvent::Running(reason.clone()));
    let cx = Context {
        study,
        shard,
        reporter,
        stage_seconds: fingerprint::recorded_seconds(study, STAGES),
    };
    let started = Instant::now();
    let summary = stage.run(&cx).map_err(|source| RunError::Stage {
        stage: name,
        source,
    })?;
    let seconds = started.elapsed().as_secs_f64();
    // Inputs are hashed again now that they are final.
    let note_err = |source: BoxError| RunError::Note {
        stage: name,
        source,
    };
    let parts = fingerprint::parts(stage, study)
        .map_err(|why| note_err(Reason::Stale(why).to_string().into()))?;
    let mut written = stage.outputs(study, shard);
    written.extend(summary.also_wrote.iter().cloned());
    let outputs = fingerprint::hash_outputs(study, &written).map_err(|e| note_err(e.into()))?;
    let note = Note {
        stage: name.into(),
        shard: shard.map(|s| s.to_string()),
        parts,
        outputs,
        seconds,
        reason: reason.to_string(),
    };
    let path = fingerprint::note_path(study, name, shard);
    let text = serde_json::to_string_pretty(&note).expect("a note serialises");
    tables::atomic_write(&path, text.as_bytes()).map_err(|e| note_err(e.into()))?;
    // A whole run supersedes shard notes, and a shard the whole run's note.
    match shard {
        None => {
            for (_, p) in fingerprint::shard_notes(study, name) {
                let _ = std::fs::remove_file(p);
            }
        }
        Some(done) => {
            let _ = std::fs::remove_file(fingerprint::note_path(study, name, None));
            for (other, p) in fingerprint::shard_notes(study, name) {
                if other.n != done.n {
                    let _ = std::fs::remove_file(p);
                }
            }
        }
    }
    reporter.stage(name, &StageEvent::Done { seconds });
    Ok(StageResult {
        stage: name,
        outcome: Outcome::Ran {
            reason,
            seconds,
            lines: summary.lines,
        },
    })
}

/// Refuses 0 threads and more than 4 per core (a hundred thousand threads
/// would take minutes to start and gain nothing).
pub fn check_threads(n: usize) -> Result<(), RunError> {
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let max = 4 * cores;
    match n {
        0 => Err(RunError::NoThreads),
        n if n > max => Err(RunError::TooManyThreads {
            asked: n,
            max,
            cores,
        }),
        _ => Ok(()),
    }
}

/// Runs `f` on a pool of `threads` workers (rayon's global pool by default).
fn with_threads<T>(
    threads: Option<usize>,
    f: impl FnOnce() -> Result<T, RunError> + Send,
) -> Result<T, RunError>
where
    T: Send,
{
    match threads {
        None => f(),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|source| RunError::Threads { threads: n, source })?
            .install(f),
    }
}
