//! Ingest: PEER AT2 files (and an optional manifest) → the records table.
//!
//! Two users: the `rocking ingest PATH…` command ([`run`]) and the ingest
//! stage of a pipeline whose records are AT2 files ([`Ingest`], writing
//! `<study>/records.parquet`).
//!
//! Glue only: the records found, read and checked by [`crate::records`]
//! (files, manifest, duplicates), written through
//! [`crate::tables::records`]. Prints nothing; the caller reports the
//! returned [`IngestReport`].
//!
//! Order: rows are sorted by record id (the file stem, unique), so the table
//! does not depend on the order of the paths given or of the directory walk.
//! Any bad file fails the whole stage and nothing is written, unless the
//! caller asks to skip bad files ([`OnBad::Skip`]), in which case they are
//! listed in the report.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use crate::pipeline::RecordSource;
pub use crate::records::{collect, discover, BadFile, CollectError, OnBad, PIPELINE_HINT};
use crate::tables;

/// The ingest stage of a pipeline that names AT2 files.
pub struct Ingest;

impl Stage for Ingest {
    fn name(&self) -> &'static str {
        "ingest"
    }

    fn about(&self) -> &'static str {
        "Read the pipeline's AT2 files into <study>/records.parquet"
    }

    fn has_command(&self) -> bool {
        false
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        if let Some(why) = study.plan.pulse_map_skips() {
            return Some(why);
        }
        matches!(
            study.plan.records_study().map(|r| &r.records),
            Ok(RecordSource::Table(_))
        )
        .then(|| "the pipeline reads a records table directly".to_string())
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        match study.plan.records_study().map(|r| &r.records) {
            Ok(RecordSource::At2 { paths, manifest }) => serde_json::json!({
                "paths": paths.iter().map(|p| study.plan.relative(p)).collect::<Vec<_>>(),
                "manifest": manifest.as_deref().map(|m| study.plan.relative(m)),
            }),
            Ok(
                source @ RecordSource::Text {
                    paths,
                    manifest,
                    ground,
                    ..
                },
            ) => serde_json::json!({
                "paths": paths.iter().map(|p| study.plan.relative(p)).collect::<Vec<_>>(),
                "manifest": manifest.as_deref().map(|m| study.plan.relative(m)),
                "text": source.text().map(|t| t.to_string()),
                "ground": ground.as_deref().map(|g| study.plan.relative(g)),
            }),
            _ => serde_json::Value::Null,
        }
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        let (paths, manifest, text) = match study.plan.records_study().map(|r| &r.records) {
            Ok(RecordSource::At2 { paths, manifest }) => (paths, manifest, None),
            Ok(
                source @ RecordSource::Text {
                    paths, manifest, ..
                },
            ) => (paths, manifest, source.text()),
            _ => return Ok(Vec::new()),
        };
        let mut files = match &text {
            None => discover(paths).map_err(CollectError::from)?,
            Some(t) => {
                let mut all = crate::records::discover_text(paths).map_err(CollectError::from)?;
                if let Some(g) = &t.ground {
                    let g = std::slice::from_ref(g);
                    all.extend(discover(g).unwrap_or_default());
                    all.extend(crate::records::discover_text(g).unwrap_or_default());
                }
                all
            }
        };
        files.extend(manifest.iter().cloned());
        Ok(files)
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        vec![study.path("records.parquet")]
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        let (paths, manifest, text) = match cx.study.plan.records_study().map(|r| &r.records) {
            Ok(RecordSource::At2 { paths, manifest }) => (paths, manifest, None),
            Ok(
                source @ RecordSource::Text {
                    paths, manifest, ..
                },
            ) => (paths, manifest, source.text()),
            _ => return Ok(Summary::default()),
        };
        let config = IngestConfig {
            paths: paths.clone(),
            manifest: manifest.clone(),
            out: cx.study.path("records.parquet"),
            on_bad: OnBad::Refuse(PIPELINE_HINT),
            text,
        };
        let report = run(&config)?;
        for col in &report.ignored_manifest_columns {
            cx.reporter
                .note("ingest", &format!("manifest column `{col}` is not stored"));
        }
        for line in report.warnings() {
            cx.reporter.note("ingest", &line);
        }
        Ok(Summary {
            lines: vec![format!(
                "ingested {} records ({} samples) into {}",
                report.records,
                report.samples,
                report.out.display()
            )],
            headline: 0,
            also_wrote: Vec::new(),
        })
    }
}

/// The hint of `rocking ingest`.
pub const SKIP_BAD_HINT: &str = "use --skip-bad to ingest the rest";

/// What to ingest and where to write it.
#[derive(Debug, Clone)]
pub struct IngestConfig {
    /// Files, or folders searched recursively for `*.AT2` (any case).
    pub paths: Vec<PathBuf>,
    pub manifest: Option<PathBuf>,
    pub out: PathBuf,
    pub on_bad: OnBad,
    /// Text files of columns read so (none: AT2 files).
    pub text: Option<crate::columns::TextRecords>,
}

#[derive(Debug, thiserror::Error)]
pub enum IngestError {
    #[error(transparent)]
    OutPath(#[from] crate::outpath::OutPathError),
    #[error(transparent)]
    Collect(#[from] CollectError),
    #[error(transparent)]
    Table(#[from] tables::TableError),
}

/// What ingest did.
#[derive(Debug)]
pub struct IngestReport {
    pub out: PathBuf,
    pub records: usize,
    pub samples: usize,
    /// Records per manifest set (`None`: records without one).
    pub per_set: BTreeMap<Option<String>, usize>,
    pub skipped: Vec<BadFile>,
    /// Ingested records the manifest does not list.
    pub not_in_manifest: Vec<String>,
    /// Records the manifest lists in an ingested set, with no file.
    pub no_file: Vec<String>,
    /// Manifest columns that were not understood and so not stored.
    pub ignored_manifest_columns: Vec<String>,
    /// What the files suggest without being refused (a relative text
    /// record's clock offset from its ground's).
    pub files: Vec<String>,
}

impl IngestReport {
    /// What a user should hear of the records and the manifest: records
    /// it does not list, and records it lists in an ingested set that
    /// have no file.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        if !self.not_in_manifest.is_empty() {
            out.push(format!(
                "{} record(s) not in the manifest (their metadata columns are empty): {}",
                self.not_in_manifest.len(),
                self.not_in_manifest.join(", ")
            ));
        }
        if !self.no_file.is_empty() {
            out.push(format!(
                "{} record(s) the manifest lists in a set ingested have no file, and the set is \
                 run without them (a pair without its other component): {}",
                self.no_file.len(),
                self.no_file.join(", ")
            ));
        }
        out.extend(self.files.iter().cloned());
        out
    }
}

impl IngestConfig {
    /// The files and folders it reads: its output must be none of them.
    pub fn inputs(&self) -> Vec<&Path> {
        let mut inputs: Vec<&Path> = self.paths.iter().map(PathBuf::as_path).collect();
        inputs.extend(self.manifest.as_deref());
        inputs
    }
}

/// Runs the ingest stage (the `ingest` command checks where its `--out`
/// lies first, [`crate::outpath::check`]).
pub fn run(config: &IngestConfig) -> Result<IngestReport, IngestError> {
    crate::outpath::check_is_no_input("--out", &config.out, "parquet", &config.inputs())?;
    let collected = crate::records::collect_as(
        &config.paths,
        config.manifest.as_deref(),
        config.on_bad,
        config.text.as_ref(),
    )?;
    let rows = collected.rows;
    let mut settings = vec![(
        "rocking.ingest.paths".to_string(),
        config
            .paths
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join("\n"),
    )];
    if let Some(m) = &config.manifest {
        settings.push(("rocking.ingest.manifest".into(), m.display().to_string()));
    }
    tables::records::write(&config.out, &rows, &settings)?;

    let mut per_set = BTreeMap::new();
    for r in &rows {
        *per_set.entry(r.meta.set.clone()).or_insert(0) += 1;
    }
    Ok(IngestReport {
        out: config.out.clone(),
        records: rows.len(),
        samples: rows.iter().map(|r| r.accel_g.len()).sum(),
        per_set,
        skipped: collected.skipped,
        not_in_manifest: collected.not_in_manifest,
        no_file: collected.no_file,
        ignored_manifest_columns: collected.ignored_manifest_columns,
        files: collected.warnings,
    })
}
