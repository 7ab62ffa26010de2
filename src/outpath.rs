//! An output path checked before anything is computed: its extension names
//! its format, and it is none of the command's inputs, nor resolves to one
//! through links (`risk --inventory inv.csv --out inv.csv` once replaced the
//! inventory with a table and exited 0); it lies outside every study folder
//! (whose tables are the inputs of its later stages and of `--from`, and
//! which a running study locks); and it can be written (a folder, read-only
//! or not one, refused at once rather than after the runs).

use std::path::{Path, PathBuf};

/// An output path refused, naming the flag.
#[derive(Debug, thiserror::Error)]
pub enum OutPathError {
    #[error("{flag} {}: give a .{want} file", path.display())]
    Extension {
        flag: &'static str,
        path: PathBuf,
        want: &'static str,
    },
    #[error(
        "{flag} {}: it is {} (an input of this command); refusing to overwrite an input",
        path.display(),
        input.display()
    )]
    IsInput {
        flag: &'static str,
        path: PathBuf,
        input: PathBuf,
    },
    #[error("{flag} {}: it is a folder; give a file", path.display())]
    IsFolder { flag: &'static str, path: PathBuf },
    #[error(
        "{flag} {}: it is inside the study folder {}, which only its stages write (its \
         tables are the inputs of its later stages and of `--from`); give a path outside it",
        path.display(),
        study.display()
    )]
    InStudy {
        flag: &'static str,
        path: PathBuf,
        study: PathBuf,
    },
    #[error("{flag} {}: cannot write in {}", path.display(), folder.display())]
    NotWritable {
        flag: &'static str,
        path: PathBuf,
        folder: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// What marks a study folder: the folder of its stages' fingerprints, made
/// when a run takes the study's lock.
pub const STUDY_MARK: &str = ".fingerprints";

/// Checks that `out` (given by `flag`) ends in `.want`, is none of
/// `inputs` (comparing resolved paths, so that a link or `./x` is caught),
/// lies outside every study folder and can be written.
pub fn check(
    flag: &'static str,
    out: &Path,
    want: &'static str,
    inputs: &[&Path],
) -> Result<(), OutPathError> {
    check_is_no_input(flag, out, want, inputs)?;
    let parent = out.parent().filter(|p| !p.as_os_str().is_empty());
    check_place(flag, out, parent.unwrap_or(Path::new(".")))
}

/// [`check`] but for the place: a stage's own table, in its study folder.
pub fn check_is_no_input(
    flag: &'static str,
    out: &Path,
    want: &'static str,
    inputs: &[&Path],
) -> Result<(), OutPathError> {
    let ext = out.extension().and_then(|e| e.to_str());
    if !ext.is_some_and(|e| e.eq_ignore_ascii_case(want)) {
        return Err(OutPathError::Extension {
            flag,
            path: out.to_path_buf(),
            want,
        });
    }
    let path = || out.to_path_buf();
    if out.is_dir() {
        return Err(OutPathError::IsFolder { flag, path: path() });
    }
    if let Ok(target) = out.canonicalize() {
        if let Some(input) = inputs
            .iter()
            .find(|i| i.canonicalize().is_ok_and(|i| i == target))
        {
            return Err(OutPathError::IsInput {
                flag,
                path: path(),
                input: input.to_path_buf(),
            });
        }
    }
    Ok(())
}

/// Checks that the folder `out` (given by `flag`: an export's) is outside
/// every study folder and can be written.
pub fn check_folder(flag: &'static str, out: &Path) -> Result<(), OutPathError> {
    check_place(flag, out, out)
}

/// Checks that `out`, to be written in the folder `within` (made by the
/// writer where it is not there yet), lies outside every study folder and
/// that the nearest folder of it that exists can be written.
fn check_place(flag: &'static str, out: &Path, within: &Path) -> Result<(), OutPathError> {
    let path = || out.to_path_buf();
    let mut folder = within.to_path_buf();
    while !folder.exists() {
        match folder.parent().filter(|p| !p.as_os_str().is_empty()) {
            Some(up) => folder = up.to_path_buf(),
            None => folder = PathBuf::from("."),
        }
    }
    let folder = folder.canonicalize().unwrap_or(folder);
    if let Some(study) = folder.ancestors().find(|a| a.join(STUDY_MARK).is_dir()) {
        return Err(OutPathError::InStudy {
            flag,
            path: path(),
            study: study.to_path_buf(),
        });
    }
    writable(&folder).map_err(|source| OutPathError::NotWritable {
        flag,
        path: path(),
        folder,
        source,
    })
}

/// Whether a file can be made in `folder`: one is made and removed.
fn writable(folder: &Path) -> std::io::Result<()> {
    if !folder.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::NotADirectory,
            "it is a file, not a folder",
        ));
    }
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let probe = folder.join(format!(".rocking-probe-{}-{nanos}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)?;
    std::fs::remove_file(&probe)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_input_is_refused_through_a_link_and_a_wrong_extension_too() {
        let dir = std::env::temp_dir().join(format!("rocking-outpath-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let input = dir.join("inv.parquet");
        std::fs::write(&input, "x").unwrap();
        let link = dir.join("link.parquet");
        let _ = std::fs::remove_file(&link);
        #[cfg(unix)]
        std::os::unix::fs::symlink(&input, &link).unwrap();
        let inputs = [input.as_path()];
        assert!(matches!(
            check("--out", &input, "parquet", &inputs),
            Err(OutPathError::IsInput { .. })
        ));
        #[cfg(unix)]
        assert!(matches!(
            check("--out", &link, "parquet", &inputs),
            Err(OutPathError::IsInput { .. })
        ));
        let e = check("--out", &dir.join("inv.csv"), "parquet", &inputs).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "--out {}: give a .parquet file",
                dir.join("inv.csv").display()
            )
        );
        assert!(check("--out", &dir.join("new.parquet"), "parquet", &inputs).is_ok());
        assert!(check("--plot", &dir.join("NEW.SVG"), "svg", &inputs).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_a_study_and_a_place_that_cannot_be_written_are_refused_at_once() {
        let dir = std::env::temp_dir().join(format!("rocking-outpath-w-{}", std::process::id()));
        let study = dir.join("outputs/quick");
        std::fs::create_dir_all(study.join(STUDY_MARK)).unwrap();
        std::fs::create_dir_all(dir.join("t.parquet")).unwrap();
        std::fs::write(dir.join("inv.csv"), "x").unwrap();
        let refused = |out: PathBuf| check("--out", &out, "parquet", &[]).unwrap_err();
        assert!(matches!(
            refused(dir.join("t.parquet")),
            OutPathError::IsFolder { .. }
        ));
        // In the study, in a folder of it, in one not made yet.
        for inside in [
            "outputs/quick/capacities.parquet",
            "outputs/quick/figures/x.parquet",
            "outputs/quick/new/deeper/x.parquet",
        ] {
            match refused(dir.join(inside)) {
                OutPathError::InStudy { study: s, .. } => {
                    assert_eq!(s, study.canonicalize().unwrap(), "{inside}")
                }
                e => panic!("{inside}: {e}"),
            }
        }
        // Beside it, and in folders not made yet, it is fine.
        assert!(check("--out", &dir.join("outputs/risk.parquet"), "parquet", &[]).is_ok());
        assert!(check("--out", &dir.join("a/b/c.parquet"), "parquet", &[]).is_ok());
        assert!(!dir.join("a").exists(), "the check makes no folder");
        // A file taken for a folder.
        let e = refused(dir.join("inv.csv/x.parquet"));
        assert!(matches!(e, OutPathError::NotWritable { .. }), "{e}");
        assert!(e.to_string().starts_with("--out "), "{e}");
        // A place nobody writes, root included.
        #[cfg(target_os = "linux")]
        assert!(matches!(
            refused(PathBuf::from("/proc/x.parquet")),
            OutPathError::NotWritable { .. }
        ));
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().flatten().collect();
        assert_eq!(left.len(), 3, "no probe is left: {left:?}");
        let left: Vec<_> = std::fs::read_dir(dir.join("outputs"))
            .unwrap()
            .flatten()
            .collect();
        assert_eq!(left.len(), 1, "no probe is left: {left:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
