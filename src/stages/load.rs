//! The checks of a pipeline on load, before any stage runs or writes: the
//! outputs' folders are folders, no input lies where the stages write
//! (the pipeline file included), every file or
//! folder the records name exists, and `records.sets` and `records.ids`
//! select records the pipeline's files have. Each refusal names the
//! pipeline and its key; the sweep's own selection
//! ([`crate::records::select`]) stays the definition of what is selected.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use crate::pipeline::{Plan, RecordSource};
use crate::records::collect;

/// A loaded pipeline as the checks see it: its plan, its file and the
/// study's folder.
pub(super) struct Loaded<'a> {
    pub plan: &'a Plan,
    pub pipeline: &'a Path,
    pub dir: &'a Path,
}

/// Why a pipeline is refused on load.
pub(super) enum Refusal {
    /// A file where the outputs' root or the study's folder should be.
    OutputsFile(PathBuf),
    /// An input, in words that name its key.
    Records(String),
}

/// Every check of a loaded pipeline, in order.
pub(super) fn check(study: &Loaded<'_>, outputs: &Path) -> Result<(), Refusal> {
    // The outputs' root and the study's folder must be folders where
    // they exist (a file there gave "cannot take the lock: Not a
    // directory", and `status` called every stage stale).
    if let Some(file) = [outputs, study.dir].into_iter().find(|p| p.is_file()) {
        return Err(Refusal::OutputsFile(file.into()));
    }
    let inputs = inputs(study);
    outside(study, &inputs).map_err(Refusal::Records)?;
    if let Some((key, path)) = inputs.iter().find(|(_, p)| !p.exists()) {
        return Err(Refusal::Records(format!(
            "`{key}` = {}: no such file or folder",
            path.display()
        )));
    }
    known_sets(study).map_err(Refusal::Records)?;
    known_ids(study).map_err(Refusal::Records)
}

/// The files and folders the pipeline's records are read from, each with
/// its key (a records table is the sweep's to find, or to say how to
/// write: only where it lies is checked here).
fn inputs(study: &Loaded<'_>) -> Vec<(&'static str, PathBuf)> {
    let Ok(records) = study.plan.records_study() else {
        return Vec::new();
    };
    let mut named = Vec::new();
    match &records.records {
        RecordSource::Table(_) => {}
        RecordSource::At2 { paths, manifest } => {
            named.extend(paths.iter().map(|p| ("records.at2", p.clone())));
            named.extend(manifest.iter().map(|m| ("records.manifest", m.clone())));
        }
        RecordSource::Text {
            paths,
            manifest,
            ground,
            ..
        } => {
            named.extend(paths.iter().map(|p| ("records.text", p.clone())));
            named.extend(manifest.iter().map(|m| ("records.manifest", m.clone())));
            named.extend(ground.iter().map(|g| ("records.ground", g.clone())));
        }
    }
    named
}

/// `path` made absolute, its links resolved as far as it exists: two
/// spellings of one place compare equal, whether or not it exists yet.
fn resolved(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut rest = Vec::new();
    let mut at = absolute.as_path();
    loop {
        if let Ok(real) = std::fs::canonicalize(at) {
            return rest.iter().rev().fold(real, |p, part| p.join(part));
        }
        match (at.parent(), at.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                at = parent;
            }
            _ => return absolute,
        }
    }
}

/// No input inside the study's folder, where the stages write their
/// tables, `report.md`, `report.html` and `figures/` (the first stage to
/// write a name overwrites it), the pipeline file included.
fn outside(study: &Loaded<'_>, inputs: &[(&'static str, PathBuf)]) -> Result<(), String> {
    let dir = resolved(study.dir);
    let table = match study.plan.records_study().map(|r| &r.records) {
        Ok(RecordSource::Table(t)) => Some(("records.table", t.clone())),
        _ => None,
    };
    let all = inputs.iter().cloned().chain(table);
    for (key, path) in all {
        let at = resolved(&path);
        if at.starts_with(&dir) {
            return Err(format!(
                "`{key}` = {} is inside the study's folder {}, where its stages write their \
                 tables, report and figures (a sweep's capacities.parquet would overwrite a \
                 table of that name): keep the records outside it, or give --outputs elsewhere",
                path.display(),
                study.dir.display()
            ));
        }
    }
    if resolved(study.pipeline).starts_with(&dir) {
        return Err(format!(
            "the pipeline file is inside the study's folder {}, where its stages write their \
             tables, report.md, report.html and figures/: keep it outside, or give --outputs \
             elsewhere",
            study.dir.display()
        ));
    }
    Ok(())
}

/// A set of `records.sets` that the pipeline's manifest does not name: a
/// typo (`far-feild`) ran the ingest and was refused by the sweep, as the
/// sweep's failure. Checked where the manifest can be read (an unreadable
/// one is the ingest's to report, by its line).
fn known_sets(study: &Loaded<'_>) -> Result<(), String> {
    let Ok(records) = study.plan.records_study() else {
        return Ok(());
    };
    let (RecordSource::At2 {
        manifest: Some(manifest),
        ..
    }
    | RecordSource::Text {
        manifest: Some(manifest),
        ..
    }) = &records.records
    else {
        return Ok(());
    };
    let Ok(m) = collect::load_manifest(manifest) else {
        return Ok(());
    };
    let have: BTreeSet<&str> = m
        .entries
        .values()
        .filter_map(|e| e.meta.set.as_deref())
        .collect();
    match records.sets.iter().find(|s| !have.contains(s.as_str())) {
        Some(set) => Err(format!(
            "`records.sets` names \"{set}\", which no record of the manifest {} has; \
             available: {}",
            manifest.display(),
            have.into_iter().collect::<Vec<_>>().join(", ")
        )),
        None => Ok(()),
    }
}

/// An id of `records.ids` that no file of `records.at2` or `records.text`
/// bears (a record's id is its file's stem): it ran the ingest and failed
/// the sweep, without the pipeline's name.
fn known_ids(study: &Loaded<'_>) -> Result<(), String> {
    let Ok(records) = study.plan.records_study() else {
        return Ok(());
    };
    if records.ids.is_empty() {
        return Ok(());
    }
    let (key, files) = match &records.records {
        RecordSource::At2 { paths, .. } => ("records.at2", crate::records::discover(paths)),
        RecordSource::Text { paths, .. } => ("records.text", crate::records::discover_text(paths)),
        RecordSource::Table(_) => return Ok(()),
    };
    // No files at all is the ingest's to report.
    let Ok(files) = files else { return Ok(()) };
    let stems: BTreeSet<String> = files.iter().map(|f| collect::record_id(f)).collect();
    let missing: Vec<&str> = records
        .ids
        .iter()
        .filter(|id| !stems.contains(id.as_str()))
        .map(String::as_str)
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    Err(format!(
        "`records.ids` names {}, which no file of `{key}` bears (a record's id is its file's \
         name without the extension, {} files)",
        missing.join(", "),
        stems.len()
    ))
}
