//! Which files a list of paths names: files as given, folders walked
//! recursively for AT2 files or text motions (any case; a `manifest.csv`
//! skipped), sorted and without duplicates.

use std::fs;
use std::path::{Path, PathBuf};

use std::io;

/// Why the paths name no file to read.
#[derive(Debug, thiserror::Error)]
pub enum DiscoverError {
    #[error("{path}")]
    Path {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("no AT2 files found in {0}{1}")]
    NoFiles(String, String),
    #[error("no text motion files (*.out, *.txt, *.dat, *.csv) found in {0}")]
    NoTextFiles(String),
}

/// The extensions of text motion files in a folder.
pub const TEXT_EXTENSIONS: &[&str] = &["out", "txt", "dat", "csv"];

/// The AT2 files named by `paths`: files as given, folders walked recursively
/// for `*.AT2` in any case. Sorted, without duplicates.
pub fn discover(paths: &[PathBuf]) -> Result<Vec<PathBuf>, DiscoverError> {
    discover_with(paths, &["at2"], |names| {
        DiscoverError::NoFiles(names, String::new())
    })
    .map_err(|e| match (e, discover_text(paths)) {
        // Text motions where AT2 files were looked for: their unit is
        // what reads them.
        (DiscoverError::NoFiles(names, _), Ok(text)) => DiscoverError::NoFiles(
            names,
            format!(
                ", but {} text motion file(s) (*.out, *.txt, *.dat, *.csv): text records are \
                     read with their unit (--records-unit of fragility, risk or export, or a \
                     pipeline's `[records] text` with \
                     `unit`)",
                text.len()
            ),
        ),
        (e, _) => e,
    })
}

/// The text motion files named by `paths` (folders walked for
/// [`TEXT_EXTENSIONS`]).
pub fn discover_text(paths: &[PathBuf]) -> Result<Vec<PathBuf>, DiscoverError> {
    discover_with(paths, TEXT_EXTENSIONS, DiscoverError::NoTextFiles)
}

/// The files named by `paths`: files as given, folders walked recursively
/// for the `extensions` in any case (a `manifest.csv` skipped). Sorted,
/// without duplicates.
fn discover_with(
    paths: &[PathBuf],
    extensions: &[&str],
    none: fn(String) -> DiscoverError,
) -> Result<Vec<PathBuf>, DiscoverError> {
    let mut found = Vec::new();
    for path in paths {
        let meta = fs::metadata(path).map_err(|source| DiscoverError::Path {
            path: path.clone(),
            source,
        })?;
        if meta.is_dir() {
            walk(path, extensions, &mut found)?;
        } else {
            found.push(path.clone());
        }
    }
    found.sort();
    found.dedup();
    if found.is_empty() {
        let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
        return Err(none(names.join(", ")));
    }
    Ok(found)
}

fn walk(dir: &Path, extensions: &[&str], found: &mut Vec<PathBuf>) -> Result<(), DiscoverError> {
    let entries = fs::read_dir(dir).map_err(|source| DiscoverError::Path {
        path: dir.into(),
        source,
    })?;
    for entry in entries {
        let entry = entry.map_err(|source| DiscoverError::Path {
            path: dir.into(),
            source,
        })?;
        let path = entry.path();
        let meta = fs::metadata(&path).map_err(|source| DiscoverError::Path {
            path: path.clone(),
            source,
        })?;
        let manifest = path
            .file_name()
            .is_some_and(|n| n.eq_ignore_ascii_case("manifest.csv"));
        if meta.is_dir() {
            walk(&path, extensions, found)?;
        } else if !manifest && has_extension(&path, extensions) {
            found.push(path);
        }
    }
    Ok(())
}

/// Whether `path` ends in one of `extensions` (without the dot, any case).
pub fn has_extension(path: &Path, extensions: &[&str]) -> bool {
    path.extension()
        .is_some_and(|e| extensions.iter().any(|x| e.eq_ignore_ascii_case(x)))
}
