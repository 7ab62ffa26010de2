//! What a stage is: the [`Stage`] trait every stage implements in its own
//! file, and what the engine hands it ([`Study`], [`Context`]) and gets back
//! ([`Summary`]).
//!
//! A stage states all its facts in one place: its name and help text, why a
//! pipeline may not need it, the settings and the input files its outputs
//! depend on (hashed into its fingerprint), the files it writes, and how it
//! runs. The engine ([`super::engine`]) does the rest: freshness, the lock,
//! fingerprints, threads, the order.

use std::error::Error;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

pub use super::reason::StageEvent;
use crate::pipeline::{Plan, RecordSource};

/// A boxed error with its cause chain intact (each stage has its own typed
/// error; the engine only carries it).
pub type BoxError = Box<dyn Error + Send + Sync + 'static>;

/// One stage of a study.
pub trait Stage: Sync {
    /// Name on the command line, in logs and in `.fingerprints/<name>.json`.
    fn name(&self) -> &'static str;

    /// One line for `rocking --help` (and the long help of its command).
    fn about(&self) -> &'static str;

    /// Whether `rocking <name> PIPELINE.toml` exists. Ingest's command
    /// (`rocking ingest PATH…`) takes files, not a pipeline.
    fn has_command(&self) -> bool {
        true
    }

    /// Whether it can run as the K-th of N shards (`--shard K/N`).
    fn shardable(&self) -> bool {
        false
    }

    /// What an interrupted run of it left that a rerun resumes (the sweep's
    /// saved chunks), in words, for a stage that never finished here.
    fn interrupted(&self, _study: &Study) -> Option<String> {
        None
    }

    /// Why this pipeline does not need the stage, if it does not.
    fn not_needed(&self, _study: &Study) -> Option<String> {
        None
    }

    /// The settings its outputs depend on, hashed into its fingerprint.
    /// Paths in it are relative to the pipeline's folder ([`Plan::relative`]).
    fn settings(&self, study: &Study) -> serde_json::Value;

    /// The files whose bytes its outputs depend on, hashed into its fingerprint.
    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError>;

    /// The files it always writes (for a shard, that shard's files). Files
    /// it writes only sometimes (figures) are returned by [`Stage::run`].
    fn outputs(&self, study: &Study, shard: Option<Shard>) -> Vec<PathBuf>;

    /// Runs the stage. Prints nothing: progress and notes go to
    /// `cx.reporter`, results come back in the [`Summary`].
    fn run(&self, cx: &Context) -> Result<Summary, BoxError>;
}

impl fmt::Debug for dyn Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl PartialEq for dyn Stage {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

/// A pipeline and where its outputs live.
#[derive(Debug, Clone)]
pub struct Study {
    pub plan: Plan,
    /// The pipeline file.
    pub pipeline: PathBuf,
    /// `<outputs>/<name>/`: every table, figure, note and lock of the study.
    pub dir: PathBuf,
}

/// A pipeline file that cannot be loaded.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("{path}: cannot read the pipeline")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error(transparent)]
    Pipeline(#[from] crate::pipeline::PipelineError),
    #[error("--outputs {}: {} is a file, not a folder", outputs.display(), file.display())]
    OutputsFile { outputs: PathBuf, file: PathBuf },
    /// The pipeline's records, or what it writes, as they cannot be:
    /// an input missing, a set or id no record has, an input inside the
    /// study's folder.
    #[error("{}: {problem}", pipeline.display())]
    Records {
        pipeline: PathBuf,
        /// What is wrong, naming the key.
        problem: String,
    },
}

impl Study {
    /// Reads and resolves a pipeline file; its outputs go to `<outputs>/<name>/`.
    pub fn load(pipeline: &Path, outputs: &Path) -> Result<Study, LoadError> {
        let bytes = std::fs::read(pipeline).map_err(|source| LoadError::Read {
            path: pipeline.into(),
            source,
        })?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
            let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
            LoadError::Read {
                path: pipeline.into(),
                source: std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!("line {line}: not UTF-8 text (a pipeline is TOML, which is UTF-8)"),
                ),
            }
        })?;
        let plan = crate::pipeline::load_str(&text, pipeline)?;
        let study = Study::new(plan, pipeline, outputs);
        let loaded = super::load::Loaded {
            plan: &study.plan,
            pipeline,
            dir: &study.dir,
        };
        super::load::check(&loaded, outputs).map_err(|r| match r {
            super::load::Refusal::OutputsFile(file) => LoadError::OutputsFile {
                outputs: outputs.into(),
                file,
            },
            super::load::Refusal::Records(problem) => LoadError::Records {
                pipeline: pipeline.into(),
                problem,
            },
        })?;
        Ok(study)
    }

    pub fn new(plan: Plan, pipeline: &Path, outputs: &Path) -> Self {
        let dir = outputs.join(&plan.name);
        Study {
            plan,
            pipeline: pipeline.to_path_buf(),
            dir,
        }
    }

    /// A file of the study's folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Whether the blocks stand on the study's records themselves
    /// ([`crate::records::stood_on`]); its records table is read only
    /// where it is the records' source and no `[floor]` decides first.
    pub fn stood_on(&self) -> bool {
        let Ok(rs) = self.plan.records_study() else {
            return false;
        };
        rs.floor.is_none()
            && crate::records::stood_on(
                rs,
                &crate::records::rows_if_table(&self.plan, &self.records_table()),
            )
    }

    /// The records table the sweep reads: the pipeline's own table, or the
    /// one the ingest stage writes into the study's folder.
    pub fn records_table(&self) -> PathBuf {
        match self.plan.records_study().map(|r| &r.records) {
            Ok(RecordSource::Table(p)) => p.clone(),
            _ => self.path("records.parquet"),
        }
    }

    /// How fingerprints name a file: relative to the study's folder when it
    /// is inside it, else relative to the pipeline's folder (so a copied
    /// output folder, or a run from another directory, keeps its fingerprints).
    pub fn name_of(&self, path: &Path) -> String {
        match path.strip_prefix(&self.dir) {
            Ok(rel) => rel.display().to_string(),
            Err(_) => self.plan.relative(path),
        }
    }
}

/// What the engine gives a running stage.
pub struct Context<'a> {
    pub study: &'a Study,
    /// `Some` when running as one shard of a sharded stage.
    pub shard: Option<Shard>,
    pub reporter: &'a dyn Reporter,
    /// Seconds each stage took when it last succeeded here, in run order
    /// (for the report).
    pub stage_seconds: Vec<(&'static str, Option<f64>)>,
    /// Run because `--force` or `--from` asked (not because it was stale):
    /// everything is computed again, nothing taken from its last outputs.
    pub forced: bool,
}

/// What a stage did, for the caller to show.
#[derive(Debug, Clone, Default)]
pub struct Summary {
    /// Lines for the user, most important first.
    pub lines: Vec<String>,
    /// How many of the first `lines` are the stage's headline results,
    /// which `rocking run` repeats once every stage is done (the
    /// lognormality share, the fitted coefficients); 0 for none.
    pub headline: usize,
    /// Files written beyond [`Stage::outputs`] (figures), to fingerprint.
    pub also_wrote: Vec<PathBuf>,
}

/// Work done so far by a running stage.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    pub stage: &'static str,
    /// Units of work done (cases for the sweep) and in all.
    pub done: u64,
    pub total: u64,
    /// Of `done`, found done by an earlier run.
    pub resumed: u64,
    /// Simulations run so far by this invocation.
    pub runs: u64,
}

/// Hears what the engine and the stages have to say while they run; the
/// CLI shows it. Every method has a silent default.
pub trait Reporter: Sync {
    /// A stage starts (`reason` says why) or is skipped.
    fn stage(&self, _stage: &'static str, _event: &StageEvent) {}
    /// Progress of the running stage.
    fn progress(&self, _progress: &Progress) {}
    /// A note worth telling the user (a model choice, a corrupt part recomputed).
    fn note(&self, _stage: &'static str, _text: &str) {}
}

/// The reporter that says nothing.
pub struct Silent;
impl Reporter for Silent {}

/// Most shards a stage may be split into (far more than any cluster's
/// nodes; the sweep refuses more shards than it has chunks anyway).
pub const MAX_SHARDS: usize = 1_000_000;

/// The K-th of N parts of a sharded stage (1 ≤ K ≤ N ≤ [`MAX_SHARDS`]).
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
        if n > MAX_SHARDS {
            return Err(format!("shard `{s}`: at most {MAX_SHARDS} shards"));
        }
        Ok(Shard { k, n })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl Shard {
    /// The tag in file names: `shard-K-of-N`.
    pub fn tag(self) -> String {
        format!("shard-{}-of-{}", self.k, self.n)
    }
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
