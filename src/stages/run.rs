//! `rocking run`: the whole study as cached stages (ingest → sweep →
//! convergence → reduce → fit → report).
//!
//! Each stage has a fingerprint (cargo's design): named parts, each a hash
//! of the stage's resolved settings, of each input file's bytes, of the
//! schema and crate versions; never file times. After a stage succeeds its
//! fingerprint and the hashes of its outputs are written to
//! `DIR/<name>/.fingerprints/<stage>.json`. A stage is fresh when that note
//! exists, parses, has the same parts, and its outputs exist unchanged;
//! otherwise the differing parts say why it reruns. One run at a time per
//! output folder: a lock file with the owner's PID.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::pipeline::{Plan, RecordSource};
use crate::stages::{convergence, fit, ingest, reduce, report, sweep};
use crate::tables::{self, sweep as st};

/// The stages, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    Ingest,
    Sweep,
    Convergence,
    Reduce,
    Fit,
    Report,
}

impl Stage {
    pub const ALL: [Stage; 6] = [
        Stage::Ingest,
        Stage::Sweep,
        Stage::Convergence,
        Stage::Reduce,
        Stage::Fit,
        Stage::Report,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Stage::Ingest => "ingest",
            Stage::Sweep => "sweep",
            Stage::Convergence => "convergence",
            Stage::Reduce => "reduce",
            Stage::Fit => "fit",
            Stage::Report => "report",
        }
    }

    pub fn parse(s: &str) -> Option<Stage> {
        Stage::ALL.into_iter().find(|st| st.name() == s)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(
        "another `rocking run` (pid {pid}) is working on {dir}; wait for it to finish, or remove {lock} if that process is gone"
    )]
    Locked {
        pid: String,
        dir: PathBuf,
        lock: PathBuf,
    },
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{stage}: {message}")]
    Stage {
        stage: &'static str,
        message: String,
    },
}

fn stage_err(stage: Stage) -> impl Fn(String) -> RunError {
    move |message| RunError::Stage {
        stage: stage.name(),
        message,
    }
}

/// The saved note of a stage that succeeded.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Note {
    pub stage: String,
    pub parts: BTreeMap<String, String>,
    pub outputs: BTreeMap<String, String>,
    pub seconds: f64,
    pub reason: String,
}

/// Whether a stage must run, and why.
#[derive(Debug, Clone, PartialEq)]
pub enum Freshness {
    Fresh,
    Stale(String),
    /// The pipeline does not need this stage.
    NotNeeded(String),
}

fn sha_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn file_hash(path: &Path) -> Result<String, String> {
    fs::read(path)
        .map(|b| sha_hex(&b))
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Where everything of a pipeline lives.
pub struct Layout {
    pub dir: PathBuf,
}

impl Layout {
    pub fn new(plan: &Plan, outputs: &Path) -> Self {
        Layout {
            dir: outputs.join(&plan.name),
        }
    }
    fn note(&self, stage: Stage) -> PathBuf {
        self.dir
            .join(".fingerprints")
            .join(format!("{}.json", stage.name()))
    }
    pub fn records(&self, plan: &Plan) -> PathBuf {
        match &plan.records {
            RecordSource::Table(p) => p.clone(),
            RecordSource::At2 { .. } => self.dir.join("records.parquet"),
        }
    }
    fn outputs(&self, stage: Stage, plan: &Plan) -> Vec<PathBuf> {
        match stage {
            Stage::Ingest => vec![self.dir.join("records.parquet")],
            Stage::Sweep => vec![
                self.dir.join("ida_points.parquet"),
                self.dir.join("capacities.parquet"),
            ],
            Stage::Convergence => vec![self.dir.join("capacity_convergence.parquet")],
            Stage::Reduce => reduce::outputs(&self.dir).to_vec(),
            Stage::Fit => fit::outputs(&self.dir).to_vec(),
            Stage::Report => {
                let _ = plan;
                vec![self.dir.join("report.md")]
            }
        }
    }
}

/// The fingerprint parts of a stage as things stand, or why it cannot run yet.
fn parts(stage: Stage, plan: &Plan, layout: &Layout) -> Result<BTreeMap<String, String>, String> {
    let mut p = BTreeMap::new();
    p.insert(
        "versions".to_string(),
        format!("rocking {}; tables v1", env!("CARGO_PKG_VERSION")),
    );
    let input = |p: &mut BTreeMap<String, String>, name: &str, path: &Path| -> Result<(), String> {
        if !path.exists() {
            return Err(format!("input {} does not exist yet", path.display()));
        }
        p.insert(format!("input {name}"), file_hash(path)?);
        Ok(())
    };
    match stage {
        Stage::Ingest => {
            let RecordSource::At2 { paths, manifest } = &plan.records else {
                unreachable!("checked by needed()")
            };
            p.insert(
                "settings".into(),
                sha_hex(format!("{paths:?} {manifest:?}").as_bytes()),
            );
            let files = ingest::discover(paths).map_err(|e| e.to_string())?;
            for f in files.iter().chain(manifest) {
                input(&mut p, &f.display().to_string(), f)?;
            }
        }
        Stage::Sweep => {
            p.insert("settings".into(), sha_hex(plan.sweep_settings().as_bytes()));
            input(&mut p, "records.parquet", &layout.records(plan))?;
        }
        Stage::Convergence => {
            p.insert(
                "settings".into(),
                sha_hex(
                    format!(
                        "{} {:?} {:?}",
                        plan.sweep_settings(),
                        plan.convergence,
                        plan.fractile
                    )
                    .as_bytes(),
                ),
            );
            input(&mut p, "records.parquet", &layout.records(plan))?;
        }
        Stage::Reduce => {
            p.insert("settings".into(), format!("{:?}", plan.fractile));
            input(
                &mut p,
                "ida_points.parquet",
                &layout.dir.join("ida_points.parquet"),
            )?;
            input(
                &mut p,
                "capacities.parquet",
                &layout.dir.join("capacities.parquet"),
            )?;
        }
        Stage::Fit => {
            input(
                &mut p,
                "capacity_fractiles.parquet",
                &layout.dir.join("capacity_fractiles.parquet"),
            )?;
        }
        Stage::Report => {
            p.insert(
                "settings".into(),
                sha_hex(
                    serde_json::to_string(plan)
                        .expect("plan serialises")
                        .as_bytes(),
                ),
            );
            let mut inputs: Vec<PathBuf> = vec![
                layout.dir.join("ida_points.parquet"),
                layout.dir.join("capacities.parquet"),
            ];
            inputs.extend(reduce::outputs(&layout.dir));
            inputs.extend(fit::outputs(&layout.dir).into_iter().filter(|f| f.exists()));
            if !plan.convergence.is_empty() {
                inputs.push(layout.dir.join("capacity_convergence.parquet"));
            }
            for f in &inputs {
                let name = f
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                input(&mut p, &name, f)?;
            }
            // Run times of the stages appear in the report.
            for s in [
                Stage::Ingest,
                Stage::Sweep,
                Stage::Convergence,
                Stage::Reduce,
                Stage::Fit,
            ] {
                if let Ok(n) = read_note(layout, s) {
                    p.insert(format!("time {}", s.name()), format!("{:.3}", n.seconds));
                }
            }
        }
    }
    Ok(p)
}

/// Why a stage is not needed by this pipeline, if it is not.
fn not_needed(stage: Stage, plan: &Plan) -> Option<String> {
    match stage {
        Stage::Ingest if matches!(plan.records, RecordSource::Table(_)) => {
            Some("the pipeline reads a records table directly".into())
        }
        Stage::Convergence if plan.convergence.is_empty() => {
            Some("the pipeline has no [convergence] levels".into())
        }
        Stage::Fit => fit::not_applicable(plan),
        _ => None,
    }
}

fn read_note(layout: &Layout, stage: Stage) -> Result<Note, String> {
    let path = layout.note(stage);
    let text =
        fs::read_to_string(&path).map_err(|_| "never run here (no fingerprint)".to_string())?;
    serde_json::from_str(&text)
        .map_err(|e| format!("its fingerprint {} is unreadable ({e})", path.display()))
}

/// Is `stage` fresh? (Without running anything.)
pub fn freshness(stage: Stage, plan: &Plan, layout: &Layout) -> Freshness {
    if let Some(why) = not_needed(stage, plan) {
        return Freshness::NotNeeded(why);
    }
    let now = match parts(stage, plan, layout) {
        Ok(p) => p,
        Err(why) => return Freshness::Stale(why),
    };
    let note = match read_note(layout, stage) {
        Ok(n) => n,
        Err(why) => return Freshness::Stale(why),
    };
    let mut why = Vec::new();
    for (k, v) in &now {
        match note.parts.get(k) {
            None => why.push(format!("{k} is new")),
            Some(old) if old != v => why.push(format!("{k} changed")),
            _ => {}
        }
    }
    for k in note.parts.keys().filter(|k| !now.contains_key(*k)) {
        why.push(format!("{k} is gone"));
    }
    for out in layout.outputs(stage, plan) {
        let name = out.display().to_string();
        match (out.exists(), note.outputs.get(&name)) {
            (false, _) => why.push(format!("output {name} is missing")),
            (true, Some(h)) if file_hash(&out).ok().as_ref() != Some(h) => {
                why.push(format!("output {name} was changed since it was written"))
            }
            (true, None) => why.push(format!("output {name} is not in the fingerprint")),
            _ => {}
        }
    }
    if why.is_empty() {
        Freshness::Fresh
    } else {
        Freshness::Stale(why.join("; "))
    }
}

/// Holds a lock file (`DIR/<name>/.lock`, or one per shard) while alive.
///
/// Taken by hard-linking a file that already holds our PID, so the lock never
/// exists empty; a lock whose PID is not a running process (on this machine)
/// is stale and taken over; an unreadable one counts as held. Released only
/// if it still holds our PID.
pub struct Lock {
    path: PathBuf,
    pid: String,
}

impl Lock {
    pub fn take(dir: &Path, name: &str) -> Result<Lock, RunError> {
        fs::create_dir_all(dir).map_err(|source| RunError::Io {
            path: dir.into(),
            source,
        })?;
        let path = dir.join(name);
        let pid = std::process::id().to_string();
        let tmp = dir.join(format!("{name}.tmp-{pid}"));
        fs::write(&tmp, &pid).map_err(|source| RunError::Io {
            path: tmp.clone(),
            source,
        })?;
        let result = (|| {
            for _ in 0..3 {
                match fs::hard_link(&tmp, &path) {
                    Ok(()) => {
                        return Ok(Lock {
                            path: path.clone(),
                            pid: pid.clone(),
                        })
                    }
                    Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                        let owner = fs::read_to_string(&path)
                            .unwrap_or_default()
                            .trim()
                            .to_string();
                        let dead = owner.parse::<u32>().is_ok()
                            && Path::new("/proc").exists()
                            && !Path::new("/proc").join(&owner).exists();
                        if !dead {
                            return Err(RunError::Locked {
                                pid: owner,
                                dir: dir.into(),
                                lock: path.clone(),
                            });
                        }
                        // The owner is gone (killed): the lock is stale.
                        let _ = fs::remove_file(&path);
                    }
                    Err(source) => {
                        return Err(RunError::Io {
                            path: path.clone(),
                            source,
                        })
                    }
                }
            }
            Err(RunError::Locked {
                pid: "?".into(),
                dir: dir.into(),
                lock: path.clone(),
            })
        })();
        let _ = fs::remove_file(&tmp);
        result
    }
}

impl Drop for Lock {
    fn drop(&mut self) {
        if fs::read_to_string(&self.path).is_ok_and(|owner| owner.trim() == self.pid) {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// What happened to one stage in a run.
#[derive(Debug, Clone)]
pub struct StageResult {
    pub stage: Stage,
    pub ran: bool,
    /// Why it ran, or why not.
    pub reason: String,
    pub seconds: f64,
}

pub struct RunConfig {
    pub plan: Plan,
    pub pipeline_path: PathBuf,
    pub outputs: PathBuf,
    pub force: bool,
    pub from: Option<Stage>,
}

/// Runs every stale stage in order; `log` hears about each as it starts.
pub fn run(
    cfg: &RunConfig,
    mut log: impl FnMut(&StageResult),
) -> Result<Vec<StageResult>, RunError> {
    let plan = &cfg.plan;
    let layout = Layout::new(plan, &cfg.outputs);
    let _lock = Lock::take(&layout.dir, ".lock")?;
    let mut results = Vec::new();
    for stage in Stage::ALL {
        let fresh = freshness(stage, plan, &layout);
        let forced = cfg.force || cfg.from.is_some_and(|f| stage >= f);
        let reason = match (&fresh, forced) {
            (Freshness::NotNeeded(why), _) => {
                let r = StageResult {
                    stage,
                    ran: false,
                    reason: format!("not needed: {why}"),
                    seconds: 0.0,
                };
                log(&r);
                results.push(r);
                continue;
            }
            (_, true) => {
                if cfg.force {
                    "forced (--force)".to_string()
                } else {
                    format!("forced (--from {})", cfg.from.map_or("", |f| f.name()))
                }
            }
            (Freshness::Stale(why), false) => why.clone(),
            (Freshness::Fresh, false) => {
                let r = StageResult {
                    stage,
                    ran: false,
                    reason: "fresh".into(),
                    seconds: 0.0,
                };
                log(&r);
                results.push(r);
                continue;
            }
        };
        log(&StageResult {
            stage,
            ran: true,
            reason: reason.clone(),
            seconds: 0.0,
        });
        let started = Instant::now();
        run_stage(stage, cfg, &layout, &results)?;
        let seconds = started.elapsed().as_secs_f64();
        // Fingerprint after success only; inputs re-hashed now that they are final.
        let parts = parts(stage, plan, &layout).map_err(stage_err(stage))?;
        let mut outputs = BTreeMap::new();
        for out in layout.outputs(stage, plan) {
            outputs.insert(
                out.display().to_string(),
                file_hash(&out).map_err(stage_err(stage))?,
            );
        }
        let note = Note {
            stage: stage.name().into(),
            parts,
            outputs,
            seconds,
            reason: reason.clone(),
        };
        let path = layout.note(stage);
        let text = serde_json::to_string_pretty(&note).expect("note serialises");
        if let Some(parent) = path.parent() {
            fs::create_dir_all(parent).map_err(|source| RunError::Io {
                path: parent.into(),
                source,
            })?;
        }
        tables::atomic_write(&path, text.as_bytes())
            .map_err(|e| stage_err(stage)(e.to_string()))?;
        results.push(StageResult {
            stage,
            ran: true,
            reason,
            seconds,
        });
    }
    Ok(results)
}

fn run_stage(
    stage: Stage,
    cfg: &RunConfig,
    layout: &Layout,
    done: &[StageResult],
) -> Result<(), RunError> {
    let plan = &cfg.plan;
    let err = stage_err(stage);
    // Later stages read the ingested table, not the AT2 files again.
    let mut table_plan = plan.clone();
    table_plan.records = RecordSource::Table(layout.records(plan));
    match stage {
        Stage::Ingest => {
            let RecordSource::At2 { paths, manifest } = &plan.records else {
                return Ok(());
            };
            let config = ingest::IngestConfig {
                paths: paths.clone(),
                manifest: manifest.clone(),
                out: layout.dir.join("records.parquet"),
                skip_bad: false,
            };
            ingest::run(&config).map_err(|e| err(e.to_string()))?;
        }
        Stage::Sweep => {
            let config = sweep::SweepConfig {
                plan: table_plan,
                outputs: cfg.outputs.clone(),
                shard: None,
                threads: None,
            };
            sweep::run(&config, |_| {}).map_err(|e| err(e.to_string()))?;
        }
        Stage::Convergence => {
            let records = sweep::load_records(&table_plan).map_err(|e| err(e.to_string()))?;
            convergence::run(
                plan,
                &records,
                &layout.dir.join("capacity_convergence.parquet"),
            )
            .map_err(|e| err(e.to_string()))?;
        }
        Stage::Reduce => {
            reduce::run(plan, &cfg.outputs, true).map_err(|e| err(e.to_string()))?;
        }
        Stage::Fit => {
            fit::run(plan, &cfg.outputs, true).map_err(|e| err(e.to_string()))?;
        }
        Stage::Report => {
            let times: Vec<(Stage, Option<f64>)> = Stage::ALL[..5]
                .iter()
                .map(|&s| (s, read_note(layout, s).ok().map(|n| n.seconds)))
                .collect();
            let _ = done;
            report::write(plan, &cfg.pipeline_path, &layout.dir, &times).map_err(err)?;
        }
    }
    Ok(())
}

/// The ida_points and capacities of a run's folder (for the report).
pub fn sweep_tables(dir: &Path) -> Result<(Vec<st::CapacityRow>, Vec<st::IdaRow>), String> {
    let caps = sweep::read_capacities(dir).map_err(|e| e.to_string())?;
    let ida = sweep::read_ida(dir).map_err(|e| e.to_string())?;
    Ok((caps, ida))
}
