//! An output path checked before anything is computed: its extension names
//! its format, and it is none of the command's inputs, nor resolves to one
//! through links (`risk --inventory inv.csv --out inv.csv` once replaced the
//! inventory with a table and exited 0).

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
}

/// Checks that `out` (given by `flag`) ends in `.want` and is none of
/// `inputs`, comparing resolved paths, so that a link or `./x` is caught.
pub fn check(
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
    let Ok(target) = out.canonicalize() else {
        return Ok(()); // not there yet: it cannot be an input
    };
    match inputs
        .iter()
        .find(|i| i.canonicalize().is_ok_and(|i| i == target))
    {
        Some(input) => Err(OutPathError::IsInput {
            flag,
            path: out.to_path_buf(),
            input: input.to_path_buf(),
        }),
        None => Ok(()),
    }
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
}
