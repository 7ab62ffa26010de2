//! Ingest stage: PEER AT2 files (and an optional manifest) → the records table.
//!
//! Glue only: finds the files, reads them, hands the bytes to [`crate::at2`],
//! joins the manifest and writes through [`crate::tables::records`]. Prints
//! nothing; the caller reports the returned [`IngestReport`].
//!
//! Order: rows are sorted by record id (the file stem, unique), so the table
//! does not depend on the order of the paths given or of the directory walk.
//! Any bad file fails the whole stage and nothing is written, unless
//! `skip_bad` is set, in which case the bad files are listed in the report.

use std::collections::BTreeMap;
use std::fmt;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use sha2::{Digest, Sha256};

use crate::at2;
use crate::manifest::{self, Manifest, RecordMeta};
use crate::motion;
use crate::tables::{self, records::RecordRow};

/// What to ingest and where to write it.
#[derive(Debug, Clone)]
pub struct IngestConfig {
    /// Files, or folders searched recursively for `*.AT2` (any case).
    pub paths: Vec<PathBuf>,
    pub manifest: Option<PathBuf>,
    pub out: PathBuf,
    pub skip_bad: bool,
}

/// A file that could not be ingested, and why.
#[derive(Debug)]
pub struct BadFile {
    pub path: PathBuf,
    pub problem: Problem,
}

#[derive(Debug)]
pub enum Problem {
    Read(io::Error),
    Parse(at2::At2Error),
    /// The manifest's NPTS or DT disagrees with the file.
    ManifestMismatch {
        manifest: PathBuf,
        line: u64,
        what: String,
    },
    DuplicateId {
        other: PathBuf,
    },
}

impl fmt::Display for BadFile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.path.display();
        match &self.problem {
            Problem::Read(e) => write!(f, "{path}: cannot read: {e}"),
            Problem::Parse(e) => write!(f, "{path}:{}: {}", e.line, e.kind),
            Problem::ManifestMismatch {
                manifest,
                line,
                what,
            } => {
                write!(
                    f,
                    "{path}: disagrees with {}:{line}: {what}",
                    manifest.display()
                )
            }
            Problem::DuplicateId { other } => write!(
                f,
                "{path}: same record id (file stem) as {}; record ids must be unique",
                other.display()
            ),
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum IngestError {
    #[error("{path}: {source}")]
    Path { path: PathBuf, source: io::Error },
    #[error("no AT2 files found in {0}")]
    NoFiles(String),
    #[error("manifest {path}: {source}")]
    Manifest {
        path: PathBuf,
        source: manifest::ManifestError,
    },
    #[error(
        "{} bad file(s); nothing was written (use --skip-bad to ingest the rest):\n  {}",
        .0.len(),
        .0.iter().map(|b| b.to_string()).collect::<Vec<_>>().join("\n  ")
    )]
    BadFiles(Vec<BadFile>),
    #[error("every file was bad; nothing was written:\n  {}", .0.iter().map(|b| b.to_string()).collect::<Vec<_>>().join("\n  "))]
    AllBad(Vec<BadFile>),
    #[error(transparent)]
    Table(#[from] tables::TableError),
}

/// What ingest did.
#[derive(Debug)]
pub struct IngestReport {
    pub out: PathBuf,
    pub records: usize,
    pub samples: usize,
    /// Records per manifest set (`(none)` for records without one).
    pub per_set: BTreeMap<String, usize>,
    pub skipped: Vec<BadFile>,
    /// Ingested records the manifest does not list.
    pub not_in_manifest: Vec<String>,
    /// Manifest columns that were not understood and so not stored.
    pub ignored_manifest_columns: Vec<String>,
}

/// Records read and checked, not yet written.
#[derive(Debug)]
pub struct Collected {
    pub rows: Vec<RecordRow>,
    pub skipped: Vec<BadFile>,
    pub not_in_manifest: Vec<String>,
    pub ignored_manifest_columns: Vec<String>,
}

/// Reads, checks and joins the records, without writing: the part of ingest
/// that the sweep also uses when a pipeline names AT2 files directly.
pub fn collect(
    paths: &[PathBuf],
    manifest_path: Option<&Path>,
    skip_bad: bool,
) -> Result<Collected, IngestError> {
    let files = discover(paths)?;
    let manifest = match manifest_path {
        Some(path) => Some((path.to_path_buf(), load_manifest(path)?)),
        None => None,
    };

    let results: Vec<Result<RecordRow, BadFile>> = files.par_iter().map(|p| read_one(p)).collect();
    let mut rows = Vec::with_capacity(results.len());
    let mut bad = Vec::new();
    for r in results {
        match r {
            Ok(row) => rows.push(row),
            Err(b) => bad.push(b),
        }
    }

    // Record ids are file stems: two files with one stem are both refused.
    rows.sort_by(|a, b| a.record_id.cmp(&b.record_id).then(a.source.cmp(&b.source)));
    let mut unique: Vec<RecordRow> = Vec::with_capacity(rows.len());
    for row in rows {
        match unique.last() {
            Some(prev) if prev.record_id == row.record_id => bad.push(BadFile {
                path: PathBuf::from(&row.source),
                problem: Problem::DuplicateId {
                    other: PathBuf::from(&prev.source),
                },
            }),
            _ => unique.push(row),
        }
    }
    let mut rows = unique;

    let mut not_in_manifest = Vec::new();
    if let Some((manifest_path, manifest)) = &manifest {
        let mut joined = Vec::with_capacity(rows.len());
        for mut row in rows {
            match manifest.entries.get(&row.record_id) {
                None => {
                    not_in_manifest.push(row.record_id.clone());
                    joined.push(row);
                }
                Some(entry) => match check_against_manifest(&row, entry) {
                    Some(what) => bad.push(BadFile {
                        path: PathBuf::from(&row.source),
                        problem: Problem::ManifestMismatch {
                            manifest: manifest_path.clone(),
                            line: entry.line,
                            what,
                        },
                    }),
                    None => {
                        row.meta = entry.meta.clone();
                        joined.push(row);
                    }
                },
            }
        }
        rows = joined;
    }

    bad.sort_by(|a, b| a.path.cmp(&b.path));
    if !bad.is_empty() && !skip_bad {
        return Err(IngestError::BadFiles(bad));
    }
    if rows.is_empty() {
        return Err(IngestError::AllBad(bad));
    }
    Ok(Collected {
        rows,
        skipped: bad,
        not_in_manifest,
        ignored_manifest_columns: manifest.map(|(_, m)| m.ignored_columns).unwrap_or_default(),
    })
}

/// Runs the ingest stage.
pub fn run(config: &IngestConfig) -> Result<IngestReport, IngestError> {
    let collected = collect(&config.paths, config.manifest.as_deref(), config.skip_bad)?;
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
        *per_set
            .entry(r.meta.set.clone().unwrap_or_else(|| "(none)".into()))
            .or_insert(0) += 1;
    }
    Ok(IngestReport {
        out: config.out.clone(),
        records: rows.len(),
        samples: rows.iter().map(|r| r.accel_g.len()).sum(),
        per_set,
        skipped: collected.skipped,
        not_in_manifest: collected.not_in_manifest,
        ignored_manifest_columns: collected.ignored_manifest_columns,
    })
}

fn load_manifest(path: &Path) -> Result<Manifest, IngestError> {
    let file = fs::File::open(path).map_err(|source| IngestError::Path {
        path: path.into(),
        source,
    })?;
    manifest::read(io::BufReader::new(file)).map_err(|source| IngestError::Manifest {
        path: path.into(),
        source,
    })
}

/// The AT2 files named by `paths`: files as given, folders walked recursively
/// for `*.AT2` in any case. Sorted, without duplicates.
pub fn discover(paths: &[PathBuf]) -> Result<Vec<PathBuf>, IngestError> {
    let mut found = Vec::new();
    for path in paths {
        let meta = fs::metadata(path).map_err(|source| IngestError::Path {
            path: path.clone(),
            source,
        })?;
        if meta.is_dir() {
            walk(path, &mut found)?;
        } else {
            found.push(path.clone());
        }
    }
    found.sort();
    found.dedup();
    if found.is_empty() {
        let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
        return Err(IngestError::NoFiles(names.join(", ")));
    }
    Ok(found)
}

fn walk(dir: &Path, found: &mut Vec<PathBuf>) -> Result<(), IngestError> {
    let entries = fs::read_dir(dir).map_err(|source| IngestError::Path {
        path: dir.into(),
        source,
    })?;
    for entry in entries {
        let entry = entry.map_err(|source| IngestError::Path {
            path: dir.into(),
            source,
        })?;
        let path = entry.path();
        let meta = fs::metadata(&path).map_err(|source| IngestError::Path {
            path: path.clone(),
            source,
        })?;
        if meta.is_dir() {
            walk(&path, found)?;
        } else if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("at2"))
        {
            found.push(path);
        }
    }
    Ok(())
}

fn read_one(path: &Path) -> Result<RecordRow, BadFile> {
    let bad = |problem| BadFile {
        path: path.to_path_buf(),
        problem,
    };
    let bytes = fs::read(path).map_err(|e| bad(Problem::Read(e)))?;
    let parsed = at2::parse(&bytes).map_err(|e| bad(Problem::Parse(e)))?;
    let peak =
        motion::peak(&parsed.accel_g, parsed.dt_s).expect("NPTS > 0 is checked by the parser");
    Ok(RecordRow {
        record_id: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        source: path.display().to_string(),
        sha256: hex(&Sha256::digest(&bytes)),
        dt_s: parsed.dt_s,
        pga_g: peak.pga_g,
        pga_time_s: peak.time_s,
        duration_s: motion::duration_s(parsed.accel_g.len(), parsed.dt_s),
        header: parsed.header,
        header_layout: parsed.layout.as_str().to_string(),
        meta: RecordMeta::default(),
        accel_g: parsed.accel_g,
    })
}

/// NPTS must match exactly; DT to 1e-9 relative (a manifest may print 0.01
/// where the file says .0100).
fn check_against_manifest(row: &RecordRow, entry: &manifest::ManifestEntry) -> Option<String> {
    if let Some(n) = entry.npts {
        if n as usize != row.accel_g.len() {
            return Some(format!(
                "manifest npts = {n}, file NPTS = {}",
                row.accel_g.len()
            ));
        }
    }
    if let Some(dt) = entry.dt_s {
        if (dt - row.dt_s).abs() > 1e-9 * row.dt_s {
            return Some(format!("manifest dt = {dt} s, file DT = {} s", row.dt_s));
        }
    }
    None
}

fn hex(bytes: &[u8]) -> String {
    use std::fmt::Write;
    bytes
        .iter()
        .fold(String::with_capacity(2 * bytes.len()), |mut s, b| {
            let _ = write!(s, "{b:02x}");
            s
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_hex_of_a_known_input() {
        // FIPS 180-2 test vector for "abc".
        assert_eq!(
            hex(&Sha256::digest(b"abc")),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
