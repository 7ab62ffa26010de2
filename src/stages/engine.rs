//! Runs the stages of a study in registry order, each only when it is
//! stale (or forced), under the study folder's lock, and saves each stage's
//! fingerprint after it succeeds. `rocking run`, `rocking status`, `--from`,
//! `--to` and the per-stage commands (`rocking sweep`, `reduce`, …) all go
//! through here: one cache, one lock.

use std::time::Instant;

use super::fingerprint;
pub use super::fingerprint::Freshness;
use super::lock::{Lock, LockError, Scope};
pub use super::reason::{Reason, Skip, Stale};
use super::stage::{BoxError, Context, Reporter, Shard, Stage, StageEvent, Study};
use super::STAGES;

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Lock(#[from] LockError),
    #[error(
        "stage `{stage}` failed; the tables it finished are whole, the rest are missing or of \
         an earlier run, and the stage is not marked done: the next run redoes it"
    )]
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
        "`{stage}`: {why}; run them with `rocking {stage} {args} --shard K/{n}`, \
         or recompute the whole stage here, unsharded, with `rocking {stage} {args} --force`"
    )]
    ShardsIncomplete {
        stage: &'static str,
        why: String,
        n: usize,
        /// The pipeline and `--outputs`, as a shell reads them.
        args: String,
    },
    #[error("cannot mark {} as a study's folder", .0.display())]
    Mark(std::path::PathBuf, #[source] std::io::Error),
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
    #[error("--threads 0: give one worker thread or more")]
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

impl RunOptions {
    /// `rocking run`'s options (and Python's `run`): every stage through
    /// `to`, forcing all of them, or `from` and every later one.
    pub fn run(
        to: Option<&'static dyn Stage>,
        from: Option<&'static dyn Stage>,
        force: bool,
        threads: Option<usize>,
        command: String,
    ) -> RunOptions {
        RunOptions {
            target: to.map_or(Target::All, Target::Through),
            force: match (force, from) {
                (true, _) => Force::All,
                (false, Some(f)) => Force::From(f),
                (false, None) => Force::Nothing,
            },
            shard: None,
            threads,
            command,
        }
    }
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
        /// The first lines that are the stage's headline results.
        headline: usize,
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

/// Every stage's freshness, in order. A stage that is fresh itself but
/// reads from a stage that will run first is shown as waiting on it.
pub fn status(study: &Study) -> Vec<(&'static str, Freshness)> {
    let mut out: Vec<(&'static str, Freshness)> = Vec::new();
    for &stage in STAGES {
        let mut f = fingerprint::freshness(stage, study, None);
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
    mark_study(&study.dir)?;
    #[cfg(target_os = "linux")]
    remove_dead_temporaries(&study.dir);
    with_threads(opts.threads, || {
        let mut results = Vec::new();
        let mut forced_from = false;
        for (i, &stage) in stages.iter().enumerate() {
            if let Force::From(f) = opts.force {
                forced_from |= f.name() == stage.name();
            }
            let fresh = fingerprint::freshness(stage, study, None);
            let reason = match fresh {
                Freshness::NotNeeded(why) => {
                    fingerprint::forget(study, stage);
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
                    if let Some(Stale::ShardsIncomplete { n, .. }) = why
                        .iter()
                        .find(|w| matches!(w, Stale::ShardsIncomplete { .. }))
                    {
                        return Err(RunError::ShardsIncomplete {
                            stage: stage.name(),
                            // Every reason: the shards' own (settings
                            // changed, say), then which are not fresh.
                            why: Reason::Stale(why.clone()).to_string(),
                            n: *n,
                            args: format!(
                                "{} --outputs {}",
                                crate::cluster::shell_word(&study.pipeline),
                                crate::cluster::shell_word(
                                    study.dir.parent().unwrap_or(&study.dir)
                                )
                            ),
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
    mark_study(&study.dir)?;
    with_threads(opts.threads, || {
        let mut results = Vec::new();
        for &stage in before {
            match fingerprint::freshness(stage, study, None) {
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
        let reason = match (
            opts.force,
            fingerprint::freshness(target, study, Some(shard)),
        ) {
            (Force::Nothing, Freshness::Stale(why)) => Reason::Stale(why),
            (Force::Nothing, _) => {
                skip(&mut results, reporter, target, Skip::Fresh);
                return Ok(results);
            }
            _ => Reason::Forced,
        };
        results.push(run_one(study, target, Some(shard), reason, reporter)?);
        Ok(results)
    })
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
        forced: matches!(reason, Reason::Forced | Reason::From(_)),
    };
    let started = Instant::now();
    let summary = stage.run(&cx).map_err(|source| RunError::Stage {
        stage: name,
        source,
    })?;
    let seconds = started.elapsed().as_secs_f64();
    fingerprint::save(stage, study, shard, &summary.also_wrote, seconds, &reason).map_err(
        |source| RunError::Note {
            stage: name,
            source,
        },
    )?;
    reporter.stage(name, &StageEvent::Done { seconds });
    Ok(StageResult {
        stage: name,
        outcome: Outcome::Ran {
            reason,
            seconds,
            lines: summary.lines,
            headline: summary.headline,
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

/// Marks `dir` as a study's folder from the moment a run holds it (its
/// fingerprints' folder, which every stage writes into), so that no
/// command's own output is written into it ([`crate::outpath`]).
fn mark_study(dir: &std::path::Path) -> Result<(), RunError> {
    let mark = dir.join(crate::outpath::STUDY_MARK);
    std::fs::create_dir_all(&mark).map_err(|e| RunError::Mark(mark, e))
}

/// Removes the temporary files (`.NAME.tmp-PID`) that writers killed before
/// their rename left in the study's folder, its figures and its
/// fingerprints: under the study's exclusive lock no one else writes there,
/// and a writer still alive here (/proc) keeps its file. A shard's tables
/// are left alone: a shard may run on another node. (The sweep's parts are
/// the sweep's to clean, shard by shard.)
#[cfg(target_os = "linux")]
fn remove_dead_temporaries(dir: &std::path::Path) {
    for folder in [
        dir.to_path_buf(),
        dir.join("figures"),
        dir.join(crate::outpath::STUDY_MARK),
    ] {
        let Ok(entries) = std::fs::read_dir(&folder) else {
            continue;
        };
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let dead = crate::tables::orphaned_temporary(&name)
                .is_some_and(|table| !name.starts_with(".lock") && !table.contains(".shard-"));
            if dead && entry.file_type().is_ok_and(|t| t.is_file()) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}
