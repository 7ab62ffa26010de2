//! Records found and read: the AT2 files a list of paths names (folders
//! walked for `*.AT2`, any case), or text columns with a declared unit
//! ([`crate::columns`]: folders walked for `*.out`, `*.txt`, `*.dat`,
//! `*.csv`), each parsed, checked against a manifest, record ids (file
//! stems) unique. Shared by the ingest stage, a pipeline that reads AT2
//! files directly, `capacity --record` and `--direct`.

use std::fmt;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::at2;
use crate::columns::{self, ColumnsError, TextRecords};
use crate::manifest::{self, Manifest, RecordMeta};
use crate::motion;
use crate::tables::records::RecordRow;

use super::discover::{discover, discover_text, has_extension, DiscoverError, TEXT_EXTENSIONS};

/// What to say when a pipeline's AT2 files are bad.
pub const PIPELINE_HINT: &str =
    "fix them, or take them out of the folders the pipeline's `records.at2` names";

/// What to do with files that cannot be ingested.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OnBad {
    /// Ingest the rest and list them in the report.
    Skip,
    /// Fail, write nothing, and end the message with this hint.
    Refuse(&'static str),
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
    Text(ColumnsError),
    /// The ground motion of a relative record.
    Ground(String),
    /// The manifest's NPTS or DT disagrees with the file.
    ManifestMismatch {
        manifest: PathBuf,
        line: u64,
        what: String,
    },
    DuplicateId {
        other: PathBuf,
    },
    /// The same samples at the same time step as another file's.
    DuplicateMotion {
        other: PathBuf,
    },
}

impl fmt::Display for BadFile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.path.display();
        match &self.problem {
            Problem::Read(e) => write!(f, "{path}: cannot read: {e}"),
            Problem::Parse(e) => write!(f, "{path}:{}: {}", e.line, e.kind),
            Problem::Text(e) if e.line == 0 => write!(f, "{path}: {}", e.kind),
            Problem::Ground(what) => write!(f, "{path}: {what}"),
            Problem::Text(e) => write!(f, "{path}:{}: {}", e.line, e.kind),
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
            Problem::DuplicateMotion { other } => write!(
                f,
                "{path}: the same motion as {} (every sample and the time step equal): a \
                 suite counts each record once",
                other.display()
            ),
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum CollectError {
    #[error("{path}")]
    Path {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error(transparent)]
    Discover(#[from] DiscoverError),
    #[error("manifest {path}")]
    Manifest {
        path: PathBuf,
        #[source]
        source: manifest::ManifestError,
    },
    #[error(
        "{} bad file(s); nothing was written ({hint}):\n  {}",
        .files.len(),
        .files.iter().map(|b| b.to_string()).collect::<Vec<_>>().join("\n  ")
    )]
    BadFiles {
        files: Vec<BadFile>,
        hint: &'static str,
    },
    #[error("every file was bad; nothing was written:\n  {}", .0.iter().map(|b| b.to_string()).collect::<Vec<_>>().join("\n  "))]
    AllBad(Vec<BadFile>),
}

/// Records read and checked, not yet written.
#[derive(Debug)]
pub struct Collected {
    pub rows: Vec<RecordRow>,
    pub skipped: Vec<BadFile>,
    pub not_in_manifest: Vec<String>,
    /// Records the manifest lists in a set the files have, with no file
    /// (a file missing from a set; sorted): a set's other records pass
    /// without them, a pair without its other component.
    pub no_file: Vec<String>,
    pub ignored_manifest_columns: Vec<String>,
    /// What the files suggest without being refused (a relative text
    /// record whose clock looks offset from its ground's).
    pub warnings: Vec<String>,
}

/// Reads, checks and joins the records, without writing: the part of ingest
/// that the sweep also uses when a pipeline names AT2 files directly.
pub fn collect(
    paths: &[PathBuf],
    manifest_path: Option<&Path>,
    on_bad: OnBad,
) -> Result<Collected, CollectError> {
    collect_as(paths, manifest_path, on_bad, None)
}

/// As [`collect`], the files read as AT2 (`text` none) or as text columns.
pub fn collect_as(
    paths: &[PathBuf],
    manifest_path: Option<&Path>,
    on_bad: OnBad,
    text: Option<&TextRecords>,
) -> Result<Collected, CollectError> {
    let files = match text {
        None => discover(paths)?,
        Some(_) => discover_text(paths)?,
    };
    let manifest = match manifest_path {
        Some(path) => Some((path.to_path_buf(), load_manifest(path)?)),
        None => None,
    };

    let results: Vec<Result<(RecordRow, Option<String>), BadFile>> = files
        .par_iter()
        .map(|p| match text {
            None => read_one(p).map(|row| (row, None)),
            Some(spec) => read_text(p, spec),
        })
        .collect();
    let mut rows = Vec::with_capacity(results.len());
    let mut bad = Vec::new();
    let mut warnings = Vec::new();
    for r in results {
        match r {
            Ok((row, said)) => {
                rows.push(row);
                warnings.extend(said);
            }
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
    let mut rows = same_motions_out(unique, &mut bad);

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

    let no_file = manifest
        .as_ref()
        .map(|(_, m)| without_file(m, &rows, &bad))
        .unwrap_or_default();
    bad.sort_by(|a, b| a.path.cmp(&b.path));
    if let (false, OnBad::Refuse(hint)) = (bad.is_empty(), on_bad) {
        return Err(CollectError::BadFiles { files: bad, hint });
    }
    if rows.is_empty() {
        return Err(CollectError::AllBad(bad));
    }
    Ok(Collected {
        rows,
        skipped: bad,
        not_in_manifest,
        no_file,
        ignored_manifest_columns: manifest.map(|(_, m)| m.ignored_columns).unwrap_or_default(),
        warnings,
    })
}

/// The records `manifest` lists in a set some of `rows` are of, with
/// neither a row nor a bad file of their id: files missing from a set.
fn without_file(manifest: &Manifest, rows: &[RecordRow], bad: &[BadFile]) -> Vec<String> {
    let sets: std::collections::BTreeSet<&str> =
        rows.iter().filter_map(|r| r.meta.set.as_deref()).collect();
    let seen: std::collections::BTreeSet<&str> = rows
        .iter()
        .map(|r| r.record_id.as_str())
        .chain(
            bad.iter()
                .filter_map(|b| b.path.file_stem().and_then(|s| s.to_str())),
        )
        .collect();
    let mut out: Vec<String> = manifest
        .entries
        .iter()
        .filter(|(id, e)| {
            e.meta.set.as_deref().is_some_and(|s| sets.contains(s)) && !seen.contains(id.as_str())
        })
        .map(|(id, _)| id.clone())
        .collect();
    out.sort();
    out
}

/// `rows` (sorted by id) without those whose motion (time step and every
/// sample, to the bit) an earlier row has, each of those a bad file: one
/// record under two names would count twice in every fractile.
fn same_motions_out(rows: Vec<RecordRow>, bad: &mut Vec<BadFile>) -> Vec<RecordRow> {
    use std::hash::{Hash, Hasher};
    let key = |r: &RecordRow| {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        r.dt_s.to_bits().hash(&mut h);
        for a in &r.accel_g {
            a.to_bits().hash(&mut h);
        }
        h.finish()
    };
    let mut seen: std::collections::HashMap<u64, Vec<usize>> = std::collections::HashMap::new();
    let mut kept: Vec<RecordRow> = Vec::with_capacity(rows.len());
    for row in rows {
        let same = |r: &RecordRow| {
            r.dt_s.to_bits() == row.dt_s.to_bits()
                && r.accel_g.len() == row.accel_g.len()
                && r.accel_g
                    .iter()
                    .zip(&row.accel_g)
                    .all(|(a, b)| a.to_bits() == b.to_bits())
        };
        let slot = seen.entry(key(&row)).or_default();
        match slot.iter().find(|&&i| same(&kept[i])) {
            Some(&i) => bad.push(BadFile {
                path: PathBuf::from(&row.source),
                problem: Problem::DuplicateMotion {
                    other: PathBuf::from(&kept[i].source),
                },
            }),
            None => {
                slot.push(kept.len());
                kept.push(row);
            }
        }
    }
    kept
}

/// The manifest at `path`, read; errors name the file (and its line).
pub fn load_manifest(path: &Path) -> Result<Manifest, CollectError> {
    let file = fs::File::open(path).map_err(|source| CollectError::Path {
        path: path.into(),
        source,
    })?;
    manifest::read(io::BufReader::new(file)).map_err(|source| CollectError::Manifest {
        path: path.into(),
        source,
    })
}

fn read_one(path: &Path) -> Result<RecordRow, BadFile> {
    let bad = |problem| BadFile {
        path: path.to_path_buf(),
        problem,
    };
    let bytes = fs::read(path).map_err(|e| bad(Problem::Read(e)))?;
    let parsed = at2::parse(&bytes).map_err(|e| bad(Problem::Parse(e)))?;
    let layout = parsed.layout.as_str().to_string();
    Ok(row(
        path,
        &bytes,
        parsed.accel_g,
        parsed.dt_s,
        parsed.header,
        layout,
    ))
}

/// A record's id: its file's name without the extension (the stem), as
/// every reader names it and `records.ids` selects it.
pub fn record_id(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// A record's row: its id (the file stem), source, hash, samples and
/// peak, with the header lines and their layout.
fn row(
    path: &Path,
    bytes: &[u8],
    accel_g: Vec<f64>,
    dt_s: f64,
    header: [String; 4],
    header_layout: String,
) -> RecordRow {
    // Both readers refuse a file without samples.
    let peak = motion::peak(&accel_g, dt_s).expect("a record has samples");
    RecordRow {
        record_id: record_id(path),
        source: path.display().to_string(),
        sha256: crate::hash::sha256_hex(bytes),
        dt_s,
        pga_g: peak.pga_g,
        pga_time_s: peak.time_s,
        duration_s: motion::duration_s(accel_g.len(), dt_s),
        header,
        header_layout,
        meta: RecordMeta::default(),
        accel_g,
    }
}

/// The header layout of a record read from text columns (a structural
/// model's motion), as the records table keeps it.
pub const TEXT_LAYOUT: &str = "columns";

/// One text file of columns, read as `spec` says.
fn read_text(path: &Path, spec: &TextRecords) -> Result<(RecordRow, Option<String>), BadFile> {
    let bad = |problem| BadFile {
        path: path.to_path_buf(),
        problem,
    };
    let bytes = fs::read(path).map_err(|e| bad(Problem::Read(e)))?;
    let text = String::from_utf8_lossy(&bytes);
    let mut parsed = columns::parse(&text, spec).map_err(|e| bad(Problem::Text(e)))?;
    let mut late = None;
    if let Some(dir) = &spec.ground {
        let (ground, t0, dt) =
            read_ground(dir, path, spec).map_err(|what| bad(Problem::Ground(what)))?;
        // A ground that starts after the motion would be taken as 0 before
        // it: times offset between the two files, a wrong answer silently.
        if t0 > parsed.t0_s + dt * (1.0 + 1e-6) {
            return Err(bad(Problem::Ground(format!(
                "its ground starts at {t0} s, after the record's first time {} s: the two files' \
                 times must be of one clock (the ground applied from time 0, as OpenSees' `Path` \
                 applies it)",
                parsed.t0_s
            ))));
        }
        late = late_start(path, &parsed, &ground, t0, dt);
        columns::add_ground(&mut parsed, &ground, t0, dt);
    }
    // Run as a motion, it never lifts a block: a wrong column (a node's
    // displacement at a support) or an empty recorder, not a record.
    if parsed.accel_g.iter().all(|&a| a == 0.0) {
        return Err(bad(Problem::Text(columns::ColumnsError {
            line: 0,
            kind: format!(
                "every acceleration is 0{}: no motion to run (is the value column right?)",
                if spec.ground.is_some() {
                    ", the ground's added"
                } else {
                    ""
                }
            ),
        })));
    }
    // The four header lines of the table: how it was read, the file's
    // line of names, its first time, its samples and step.
    let header = [
        spec.to_string(),
        parsed.header.unwrap_or_default(),
        format!("first time {} s", parsed.t0_s),
        format!("NPTS= {}, DT= {} SEC", parsed.accel_g.len(), parsed.dt_s),
    ];
    Ok((
        row(
            path,
            &bytes,
            parsed.accel_g,
            parsed.dt_s,
            header,
            TEXT_LAYOUT.into(),
        ),
        late,
    ))
}

/// A relative record whose first time lies well after its ground's first
/// (more than two of the ground's steps), with the ground already moving
/// before it (a tenth of its peak or more): a structural model's recorder
/// starts with its analysis, so the two clocks are likely offset (a time
/// column shifted), and the floor motion, the relative values plus the
/// ground at the same times, would be wrong by a shift (+10 % in PFV
/// seen). Said, not refused: a recorder started late is possible.
fn late_start(
    path: &Path,
    record: &columns::ColumnMotion,
    ground: &[f64],
    t0: f64,
    dt: f64,
) -> Option<String> {
    let gap = record.t0_s - t0;
    if gap <= 2.0 * dt * (1.0 + 1e-6) {
        return None;
    }
    let peak = ground.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    let before = ((gap / dt).floor() as usize).min(ground.len());
    let early = ground[..before].iter().fold(0.0f64, |m, a| m.max(a.abs()));
    (peak > 0.0 && early >= 0.1 * peak).then(|| {
        format!(
            "{}: its first time {} s is {} s after its ground's first, {t0} s, and the ground \
             already moves before it ({:.0} % of its peak): a model's recorder starts with its \
             analysis, so are the two files' times of one clock? (the floor motion is the \
             record plus the ground at the same times)",
            path.display(),
            record.t0_s,
            crate::im::level_text(gap),
            100.0 * early / peak
        )
    })
}

/// The ground motion a relative record was run with: the file of its stem
/// in `dir`, an AT2 file (g, from time 0) or text columns (time and
/// acceleration in the records' unit). Its samples (g), first time, step.
fn read_ground(
    dir: &Path,
    record: &Path,
    spec: &TextRecords,
) -> Result<(Vec<f64>, f64, f64), String> {
    let stem = record.file_stem().unwrap_or_default();
    let mut found: Vec<std::path::PathBuf> = fs::read_dir(dir)
        .map_err(|e| format!("its ground, in {}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.file_stem() == Some(stem) && p.is_file())
        .filter(|p| has_extension(p, &["at2"]) || has_extension(p, TEXT_EXTENSIONS))
        .collect();
    found.sort();
    let found = match &found[..] {
        [one] => one.clone(),
        [] => {
            return Err(format!(
                "no ground motion of the same name in {} (an AT2 or text file): a relative \
                 acceleration needs the ground it was run with",
                dir.display()
            ))
        }
        [a, b, ..] => {
            return Err(format!(
                "two ground motions of its name in {}, {} and {}: which one it was run with is \
                 not known; keep one",
                dir.display(),
                a.display(),
                b.display()
            ))
        }
    };
    let bytes = fs::read(&found).map_err(|e| format!("{}: {e}", found.display()))?;
    if has_extension(&found, &["at2"]) {
        let g = at2::parse(&bytes)
            .map_err(|e| format!("{}:{}: {}", found.display(), e.line, e.kind))?;
        return Ok((g.accel_g, 0.0, g.dt_s));
    }
    let text = String::from_utf8_lossy(&bytes);
    let plain = TextRecords {
        unit: spec.unit,
        column: 1,
        ground: None,
    };
    let g = columns::parse(&text, &plain)
        .map_err(|e| format!("{}:{}: {e}", found.display(), e.line))?;
    Ok((g.accel_g, g.t0_s, g.dt_s))
}

/// NPTS must match exactly; DT to 1e-9 relative (a manifest may print 0.01
/// where the file says .0100); an AT2 file's PGA to the manifest's printing
/// (half a unit in its last digit: `0.42` for 0.415783) or 0.1 %, the
/// wider (`0.4157` truncated, `0.41578299` of a float32), where it was not
/// compared at all (another record's file, the pair's other component,
/// another unit, passed). A text record's is not held to it: its manifest
/// row may be its ground motion's.
fn check_against_manifest(row: &RecordRow, entry: &manifest::ManifestEntry) -> Option<String> {
    let text = row.header_layout == TEXT_LAYOUT;
    if let (Some(pga), Some(half), false) = (entry.pga_g, entry.pga_g_half_unit, text) {
        if (pga - row.pga_g).abs() > half.max(1e-3 * row.pga_g) {
            return Some(format!(
                "manifest pga_g = {pga} g, the file's peak {} g",
                row.pga_g
            ));
        }
    }
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
