//! The bundled far-field records the benchmark runs on: one by its name, or
//! `n` spread over the set.

use std::path::{Path, PathBuf};

use super::options::{BenchError, BenchOptions};
use rocking::physics::Excitation;
use rocking::records;

pub(super) fn load(dir: &Path, stem: &str) -> Result<Excitation, BenchError> {
    let path = dir.join("far-field").join(format!("{stem}.AT2"));
    Ok(records::load(&path)?.exc)
}

/// `n` far-field records spread over the set (every k-th by file name).
pub(super) fn spread_records(
    args: &BenchOptions,
    n_records: usize,
) -> Result<Vec<Excitation>, BenchError> {
    Ok(named_records(args, n_records)?
        .into_iter()
        .map(|r| r.1)
        .collect())
}

/// `n` far-field records spread over the set (every k-th by file name), with their ids.
pub(super) fn named_records(
    args: &BenchOptions,
    n_records: usize,
) -> Result<Vec<(String, Excitation)>, BenchError> {
    let files = far_field_files(args)?;
    let step = (files.len() / n_records).max(1);
    let mut recs = Vec::new();
    for f in files.iter().step_by(step).take(n_records) {
        let stem = f
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let exc = load(&args.records, &stem)?;
        recs.push((stem, exc));
    }
    Ok(recs)
}

/// The first `n` far-field records by name, loaded.
pub(super) fn first_far_field(
    args: &BenchOptions,
    n: usize,
) -> Result<Vec<Excitation>, BenchError> {
    far_field_files(args)?
        .iter()
        .take(n)
        .map(|f| Ok(rocking::records::load(f)?.exc))
        .collect()
}

/// The far-field AT2 files under `args.records`, sorted by name.
pub(super) fn far_field_files(args: &BenchOptions) -> Result<Vec<PathBuf>, BenchError> {
    let dir = args.records.join("far-field");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|source| BenchError::List {
            path: dir.clone(),
            source,
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("at2")))
        .collect();
    files.sort();
    Ok(files)
}
