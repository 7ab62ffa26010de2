//! Sweep stage: the IDA of every (record, block) case of a pipeline.
//!
//! Glue between the plan, the records, [`crate::ida`] and the sweep tables.
//! Cases are numbered in a fixed order (records by id, then blocks in plan
//! order) and grouped into chunks of [`CHUNK_CASES`]. Each chunk is computed in
//! parallel (rayon, results collected in case order) and written as two part
//! files under `DIR/<name>/parts/`, each written to a temporary name and
//! renamed, and stamped with the plan's hash. So:
//!
//! - **resume**: a rerun reuses every part whose hash matches and computes
//!   only the rest; an interrupted run leaves whole parts or nothing;
//! - **determinism**: parts and final tables are byte-identical whatever the
//!   thread count;
//! - **sharding**: `--shard K/N` computes the chunks with index ≡ K−1 (mod N)
//!   and writes `*.shard-K-of-N.parquet`; [`dataset`] reads the N shards as
//!   one table;
//! - **bounded memory**: one chunk of results at a time; the final tables are
//!   concatenated part by part.

use std::collections::BTreeSet;
use std::fmt;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use rayon::prelude::*;
use sha2::{Digest, Sha256};

use crate::ida::{self, RunKind};
use crate::physics::{Excitation, Model, PhysicsError, RunSpec};
use crate::pipeline::{Plan, RecordSource};
use crate::stages::ingest;
use crate::tables::records::RecordRow;
use crate::tables::sweep::{self as t, CapacityRow, IdaRow};
use crate::tables::{self, TableError};

/// Cases per chunk (and per part file).
pub const CHUNK_CASES: usize = 32;

/// Metadata key holding the plan hash in every sweep table.
pub const META_PLAN_HASH: &str = "rocking.sweep.plan_hash";
pub const META_PLAN: &str = "rocking.sweep.plan";
pub const META_SHARD: &str = "rocking.sweep.shard";
/// The settings that determine the results ([`Plan::sweep_settings`]).
pub const META_SETTINGS: &str = "rocking.sweep.settings";

/// Environment variable for fault-injection tests: abort the process (as a
/// crash would) after writing this many chunks.
pub const FAULT_ENV: &str = "ROCKING_FAULT_AFTER_CHUNKS";

/// The K-th of N parts of a sweep (1 ≤ K ≤ N).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

impl FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("shard `{s}`: expected K/N with 1 ≤ K ≤ N, e.g. 2/8");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let (k, n) = (
            k.trim().parse::<usize>().map_err(|_| bad())?,
            n.trim().parse::<usize>().map_err(|_| bad())?,
        );
        if k == 0 || n == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

#[derive(Debug, Clone)]
pub struct SweepConfig {
    pub plan: Plan,
    /// Outputs root; tables go to `outputs/<plan name>/`.
    pub outputs: PathBuf,
    pub shard: Option<Shard>,
    /// Worker threads (default: rayon's, one per core).
    pub threads: Option<usize>,
}

#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error(
        "records table {0} does not exist; write it with `rocking ingest … --out {0}`, \
         or point `records.at2` of the pipeline at AT2 folders"
    )]
    MissingRecords(PathBuf),
    #[error(transparent)]
    Ingest(#[from] ingest::IngestError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("{0}")]
    Selection(String),
    #[error("block p = {p}, ε = {eps}: {source}")]
    Block {
        p: f64,
        eps: f64,
        source: PhysicsError,
    },
    #[error("record {record}: {source}")]
    Record {
        record: String,
        source: PhysicsError,
    },
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: io::Error },
    #[error("cannot start {0} worker threads: {1}")]
    Threads(usize, String),
    #[error("{0}")]
    Dataset(String),
}

/// Progress of a sweep, for the caller to show.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    pub cases_done: usize,
    pub cases_total: usize,
    /// Runs computed by this invocation so far.
    pub runs: u64,
    /// Cases found done in parts from an earlier run.
    pub cases_resumed: usize,
    /// Sample intervals integrated by this invocation so far.
    pub intervals: u64,
}

#[derive(Debug, Clone)]
pub struct SweepReport {
    pub dir: PathBuf,
    pub records: usize,
    pub blocks: usize,
    /// Cases in this shard (all cases if unsharded).
    pub cases: usize,
    pub cases_resumed: usize,
    /// Runs computed by this invocation.
    pub runs: u64,
    /// Sample intervals integrated by this invocation.
    pub intervals: u64,
    pub ida_path: PathBuf,
    pub capacities_path: PathBuf,
    pub plan_hash: String,
    /// Models used, with why (for the log).
    pub models: Vec<String>,
}

/// Final table names of an unsharded run or of one shard.
fn final_names(shard: Option<Shard>) -> (String, String) {
    match shard {
        None => ("ida_points.parquet".into(), "capacities.parquet".into()),
        Some(s) => (
            format!("ida_points.shard-{}-of-{}.parquet", s.k, s.n),
            format!("capacities.shard-{}-of-{}.parquet", s.k, s.n),
        ),
    }
}

/// Loads the plan's records, filtered by set and id, sorted by id.
pub fn load_records(plan: &Plan) -> Result<Vec<RecordRow>, SweepError> {
    let rows = match &plan.records {
        RecordSource::Table(path) => {
            if !path.exists() {
                return Err(SweepError::MissingRecords(path.clone()));
            }
            tables::records::read(path)?
        }
        RecordSource::At2 { paths, manifest } => {
            if let Some(m) = manifest {
                if !m.exists() {
                    return Err(SweepError::Io {
                        path: m.clone(),
                        source: io::Error::new(io::ErrorKind::NotFound, "manifest not found"),
                    });
                }
            }
            ingest::collect(paths, manifest.as_deref(), false)?.rows
        }
    };
    let available_sets: BTreeSet<String> = rows.iter().filter_map(|r| r.meta.set.clone()).collect();
    for set in &plan.sets {
        if !available_sets.contains(set) {
            return Err(SweepError::Selection(format!(
                "`records.sets` names \"{set}\", which no record has; available: {}",
                if available_sets.is_empty() {
                    "none (the records carry no set: give a manifest)".to_string()
                } else {
                    available_sets
                        .iter()
                        .cloned()
                        .collect::<Vec<_>>()
                        .join(", ")
                }
            )));
        }
    }
    let ids: BTreeSet<&str> = rows.iter().map(|r| r.record_id.as_str()).collect();
    let missing: Vec<&str> = plan
        .ids
        .iter()
        .map(String::as_str)
        .filter(|id| !ids.contains(id))
        .collect();
    if !missing.is_empty() {
        return Err(SweepError::Selection(format!(
            "`records.ids`: no record {}",
            missing.join(", ")
        )));
    }
    let mut selected: Vec<RecordRow> = rows
        .into_iter()
        .filter(|r| {
            plan.sets.is_empty() || r.meta.set.as_ref().is_some_and(|s| plan.sets.contains(s))
        })
        .filter(|r| plan.ids.is_empty() || plan.ids.contains(&r.record_id))
        .collect();
    if selected.is_empty() {
        return Err(SweepError::Selection(
            "the record selection is empty".into(),
        ));
    }
    selected.sort_by(|a, b| a.record_id.cmp(&b.record_id));
    Ok(selected)
}

/// Hash of everything that determines the sweep's output.
pub fn plan_hash(plan: &Plan, records: &[RecordRow]) -> String {
    let mut h = Sha256::new();
    h.update(env!("CARGO_PKG_VERSION").as_bytes());
    h.update(format!(
        "ida_points/{} capacities/{}",
        t::IDA_KIND.schema_version,
        t::CAPACITY_KIND.schema_version
    ));
    // Only what changes the results: not the name, where the records are, or reduce's settings.
    h.update(plan.sweep_settings().as_bytes());
    for r in records {
        h.update(r.record_id.as_bytes());
        h.update(r.sha256.as_bytes());
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// The model of each block, resolved once.
/// Each block's run specification and model name, and the reasons for the models.
type BlockSpecs = (Vec<(RunSpec, &'static str)>, Vec<String>);

fn block_specs(plan: &Plan) -> Result<BlockSpecs, SweepError> {
    let mut specs = Vec::new();
    let mut why = BTreeSet::new();
    for b in &plan.blocks {
        let (model, reason) = plan
            .model
            .resolve(b.alpha_rad, plan.rtol, plan.auto_tol)
            .map_err(|source| SweepError::Block {
                p: b.p,
                eps: b.eps,
                source,
            })?;
        let spec = RunSpec {
            overturn: plan.overturn,
            ..RunSpec::new(b.p, b.eps, 1.0, model)
        };
        spec.validate().map_err(|source| SweepError::Block {
            p: b.p,
            eps: b.eps,
            source,
        })?;
        why.insert(reason);
        specs.push((spec, model.name()));
    }
    Ok((specs, why.into_iter().collect()))
}

fn alpha_of(model: Model) -> Option<f64> {
    match model {
        Model::Nonlinear { alpha_rad, .. } => Some(alpha_rad),
        Model::Rk4 { alpha_rad, .. } => alpha_rad,
        Model::Linearized => None,
    }
}

/// Runs the sweep, reporting progress after each chunk.
pub fn run(
    config: &SweepConfig,
    mut progress: impl FnMut(&Progress),
) -> Result<SweepReport, SweepError> {
    let plan = &config.plan;
    let records = load_records(plan)?;
    let (specs, models) = block_specs(plan)?;
    let excitations: Vec<Excitation> = records
        .par_iter()
        .map(|r| {
            Excitation::new(&r.accel_g, r.dt_s).map_err(|source| SweepError::Record {
                record: r.record_id.clone(),
                source,
            })
        })
        .collect::<Result<_, _>>()?;
    let hash = plan_hash(plan, &records);
    let dir = config.outputs.join(&plan.name);
    let parts = dir.join("parts");
    fs::create_dir_all(&parts).map_err(|source| SweepError::Io {
        path: parts.clone(),
        source,
    })?;

    let n_blocks = plan.blocks.len();
    let n_cases = records.len() * n_blocks;
    let n_chunks = n_cases.div_ceil(CHUNK_CASES);
    let mine: Vec<usize> = (0..n_chunks)
        .filter(|c| config.shard.is_none_or(|s| c % s.n == s.k - 1))
        .collect();
    let cases_total: usize = mine.iter().map(|&c| chunk_len(c, n_cases)).sum();
    remove_stale_temporaries(&parts, &mine)?;
    let plan_json = serde_json::to_string(plan).expect("plan serialises");
    let settings = |shard: Option<Shard>| {
        let mut s = vec![
            (META_PLAN_HASH.to_string(), hash.clone()),
            (META_PLAN.to_string(), plan_json.clone()),
            (META_SETTINGS.to_string(), plan.sweep_settings()),
        ];
        if let Some(sh) = shard {
            s.push((META_SHARD.to_string(), sh.to_string()));
        }
        s
    };

    let pool = match config.threads {
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| SweepError::Threads(n, e.to_string()))?,
        ),
        None => None,
    };
    let fault_after: Option<usize> = std::env::var(FAULT_ENV).ok().and_then(|v| v.parse().ok());

    let mut done = Progress {
        cases_done: 0,
        cases_total,
        runs: 0,
        cases_resumed: 0,
        intervals: 0,
    };
    let mut written = 0usize;
    progress(&done);
    for &c in &mine {
        let (ida_part, cap_part) = part_paths(&parts, c);
        let len = chunk_len(c, n_cases);
        if part_is_current(&cap_part, &hash) && part_is_current(&ida_part, &hash) {
            done.cases_done += len;
            done.cases_resumed += len;
            progress(&done);
            continue;
        }
        let cases: Vec<usize> = (c * CHUNK_CASES..c * CHUNK_CASES + len).collect();
        let compute = || {
            cases
                .par_iter()
                .map(|&case| {
                    let (ri, bi) = (case / n_blocks, case % n_blocks);
                    run_case(
                        case,
                        &records[ri],
                        &excitations[ri],
                        &plan.blocks[bi].name,
                        specs[bi],
                        plan,
                    )
                })
                .collect::<Result<Vec<_>, _>>()
        };
        let results = match &pool {
            Some(p) => p.install(compute),
            None => compute(),
        }?;
        let mut ida_rows = Vec::new();
        let mut cap_rows = Vec::with_capacity(results.len());
        for (ida, cap, intervals) in results {
            done.runs += ida.len() as u64;
            done.intervals += intervals;
            ida_rows.extend(ida);
            cap_rows.push(cap);
        }
        let batch_err = |path: &Path| {
            let path = path.to_path_buf();
            move |source| TableError::Arrow { path, source }
        };
        let ida_batch = t::ida_batch(&ida_rows).map_err(batch_err(&ida_part))?;
        let mut w = tables::AtomicTableWriter::create(
            &ida_part,
            t::IDA_KIND,
            t::ida_schema(),
            &settings(None),
        )?;
        w.write(&ida_batch)?;
        w.commit()?;
        let cap_batch = t::capacity_batch(&cap_rows).map_err(batch_err(&cap_part))?;
        let mut w = tables::AtomicTableWriter::create(
            &cap_part,
            t::CAPACITY_KIND,
            t::capacity_schema(),
            &settings(None),
        )?;
        w.write(&cap_batch)?;
        w.commit()?;
        written += 1;
        done.cases_done += len;
        progress(&done);
        if fault_after.is_some_and(|n| written >= n) {
            // Fault injection for the resume tests: die as a crash would.
            std::process::abort();
        }
    }

    // Concatenate the parts into the final tables, then drop the parts.
    let (ida_name, cap_name) = final_names(config.shard);
    let ida_path = dir.join(ida_name);
    let cap_path = dir.join(cap_name);
    let ida_parts: Vec<PathBuf> = mine.iter().map(|&c| part_paths(&parts, c).0).collect();
    let cap_parts: Vec<PathBuf> = mine.iter().map(|&c| part_paths(&parts, c).1).collect();
    tables::concat(
        &ida_path,
        t::IDA_KIND,
        t::ida_schema(),
        &ida_parts,
        &settings(config.shard),
    )?;
    tables::concat(
        &cap_path,
        t::CAPACITY_KIND,
        t::capacity_schema(),
        &cap_parts,
        &settings(config.shard),
    )?;
    for p in ida_parts.iter().chain(&cap_parts) {
        let _ = fs::remove_file(p);
    }
    let _ = fs::remove_dir(&parts); // only if empty (other shards may still write here)
    match config.shard {
        // The unsharded tables supersede any shards, and shards supersede
        // unsharded tables: the dataset is whichever was written last.
        None => remove_shard_tables(&dir)?,
        Some(_) => {
            let (ida, cap) = final_names(None);
            let _ = fs::remove_file(dir.join(ida));
            let _ = fs::remove_file(dir.join(cap));
        }
    }

    Ok(SweepReport {
        dir,
        records: records.len(),
        blocks: n_blocks,
        cases: cases_total,
        cases_resumed: done.cases_resumed,
        runs: done.runs,
        intervals: done.intervals,
        ida_path,
        capacities_path: cap_path,
        plan_hash: hash,
        models,
    })
}

fn chunk_len(c: usize, n_cases: usize) -> usize {
    CHUNK_CASES.min(n_cases - c * CHUNK_CASES)
}

fn part_paths(parts: &Path, c: usize) -> (PathBuf, PathBuf) {
    (
        parts.join(format!("ida-{c:06}.parquet")),
        parts.join(format!("cap-{c:06}.parquet")),
    )
}

fn part_is_current(path: &Path, hash: &str) -> bool {
    path.exists()
        && tables::read_metadata(path)
            .map(|kv| kv.iter().any(|(k, v)| k == META_PLAN_HASH && v == hash))
            .unwrap_or(false)
}

/// Removes temporary files left by a killed run (`.ida-000042.parquet.tmp-PID`),
/// only for this shard's chunks: other shards may be writing beside it.
fn remove_stale_temporaries(dir: &Path, mine: &[usize]) -> Result<(), SweepError> {
    let mine: BTreeSet<usize> = mine.iter().copied().collect();
    let entries = fs::read_dir(dir).map_err(|source| SweepError::Io {
        path: dir.into(),
        source,
    })?;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let chunk = name
            .strip_prefix(".ida-")
            .or_else(|| name.strip_prefix(".cap-"))
            .and_then(|r| r.split('.').next())
            .and_then(|c| c.parse::<usize>().ok());
        // The writer's PID ends the name: a live writer's file is not stale.
        let pid = name
            .rsplit(".tmp-")
            .next()
            .filter(|_| name.contains(".tmp-"));
        let writer_alive = pid.is_some_and(|p| Path::new("/proc").join(p).exists());
        if name.contains(".tmp-") && !writer_alive && chunk.is_some_and(|c| mine.contains(&c)) {
            let _ = fs::remove_file(e.path());
        }
    }
    Ok(())
}

/// After an unsharded run, shard tables of an earlier sharded run are stale.
fn remove_shard_tables(dir: &Path) -> Result<(), SweepError> {
    let entries = fs::read_dir(dir).map_err(|source| SweepError::Io {
        path: dir.into(),
        source,
    })?;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.contains(".shard-") && name.ends_with(".parquet") {
            let _ = fs::remove_file(e.path());
        }
    }
    Ok(())
}

/// A case's IDA points, its capacity, and the sample intervals it took.
type CaseResult = (Vec<IdaRow>, CapacityRow, u64);

fn run_case(
    case: usize,
    record: &RecordRow,
    exc: &Excitation,
    block: &str,
    (spec, model): (RunSpec, &'static str),
    plan: &Plan,
) -> Result<CaseResult, SweepError> {
    let cap =
        ida::capacity_traced(exc, &spec, &plan.grid, plan.tol, plan.trace).map_err(|source| {
            SweepError::Record {
                record: record.record_id.clone(),
                source,
            }
        })?;
    let alpha_rad = alpha_of(spec.model);
    let ida = cap
        .points
        .iter()
        .map(|q| IdaRow {
            case_id: case as i64,
            record_id: record.record_id.clone(),
            block: block.to_string(),
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
            run_kind: match q.kind {
                RunKind::Level => "level",
                RunKind::Refinement => "refinement",
            }
            .to_string(),
            model: model.to_string(),
        })
        .collect();
    let row = CapacityRow {
        case_id: case as i64,
        record_id: record.record_id.clone(),
        block: block.to_string(),
        p: spec.p,
        eps: spec.eps,
        alpha_rad,
        model: model.to_string(),
        eta_c: cap.eta_c,
        eta_survived: cap.eta_survived,
        level_survived: cap.level_survived,
        level_overturned: cap.level_overturned,
        runs: cap.points.len() as i64,
        resurrections: cap.resurrections.map(|r| r as i64),
    };
    let intervals = cap.points.iter().map(|q| q.outcome.intervals).sum();
    Ok((ida, row, intervals))
}

/// The sweep tables of a pipeline's output folder, as one dataset: the
/// unsharded tables if present, else all N shards (every one required, all
/// from the same plan). Returns (ida_points files, capacities files).
pub fn dataset(dir: &Path) -> Result<(Vec<PathBuf>, Vec<PathBuf>), SweepError> {
    let (ida, cap) = final_names(None);
    if dir.join(&cap).exists() && dir.join(&ida).exists() {
        return Ok((vec![dir.join(ida)], vec![dir.join(cap)]));
    }
    let entries = fs::read_dir(dir).map_err(|source| SweepError::Io {
        path: dir.into(),
        source,
    })?;
    let mut n_seen = BTreeSet::new();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if let Some(rest) = name
            .strip_prefix("capacities.shard-")
            .and_then(|r| r.strip_suffix(".parquet"))
        {
            if let Some((_, n)) = rest.split_once("-of-") {
                if let Ok(n) = n.parse::<usize>() {
                    n_seen.insert(n);
                }
            }
        }
    }
    let n = match n_seen.len() {
        0 => {
            return Err(SweepError::Dataset(format!(
                "{}: no sweep tables (run `rocking sweep` first)",
                dir.display()
            )))
        }
        1 => *n_seen.iter().next().expect("one"),
        _ => {
            return Err(SweepError::Dataset(format!(
                "{}: shard tables of different shard counts ({n_seen:?}); remove the stale ones",
                dir.display()
            )))
        }
    };
    let mut idas = Vec::new();
    let mut caps = Vec::new();
    let mut missing = Vec::new();
    let mut hashes = BTreeSet::new();
    for k in 1..=n {
        let (i, c) = final_names(Some(Shard { k, n }));
        let (i, c) = (dir.join(i), dir.join(c));
        if !(i.exists() && c.exists()) {
            missing.push(format!("{k}/{n}"));
            continue;
        }
        let kv = tables::read_metadata(&c)?;
        hashes.insert(
            kv.into_iter()
                .find(|(k, _)| k == META_PLAN_HASH)
                .map(|(_, v)| v)
                .unwrap_or_default(),
        );
        idas.push(i);
        caps.push(c);
    }
    if !missing.is_empty() {
        return Err(SweepError::Dataset(format!(
            "{}: shards {} of the sweep are missing; run them with `rocking sweep … --shard K/{n}`",
            dir.display(),
            missing.join(", ")
        )));
    }
    if hashes.len() > 1 {
        return Err(SweepError::Dataset(format!(
            "{}: the shards come from different plans; rerun the stale ones",
            dir.display()
        )));
    }
    Ok((idas, caps))
}

/// Capacities of a dataset, in case order (shards interleaved back).
pub fn read_capacities(dir: &Path) -> Result<Vec<CapacityRow>, SweepError> {
    let (_, caps) = dataset(dir)?;
    let mut rows = t::read_capacities(&caps)?;
    rows.sort_by_key(|r| r.case_id);
    Ok(rows)
}

/// IDA points of a dataset, in case order (run order within a case).
pub fn read_ida(dir: &Path) -> Result<Vec<IdaRow>, SweepError> {
    let (idas, _) = dataset(dir)?;
    let mut rows = t::read_ida(&idas)?;
    rows.sort_by_key(|r| r.case_id); // stable: keeps run order within a case
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_refuse_nonsense() {
        assert_eq!("2/8".parse::<Shard>(), Ok(Shard { k: 2, n: 8 }));
        for bad in ["0/3", "4/3", "3", "a/b", "1/0"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
