//! Helpers shared by the integration tests.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root (where Cargo.toml is).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The bundled FEMA P695 records folder.
pub fn bundled_records() -> PathBuf {
    root().join("records/fema-p695")
}

/// Runs the `rocking` binary with `args` in `cwd`.
pub fn rocking(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rocking"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("the rocking binary runs")
}

pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// An AT2 reader written independently of `rocking::at2`, for the bundled
/// files only (NGA-West2 layout): skip four lines, parse every token.
pub fn plain_at2_values(path: &Path) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .skip(4)
        .flat_map(|l| l.split_whitespace())
        .map(|t| t.parse::<f64>().unwrap())
        .collect()
}

/// A small AT2 file in the NGA-West2 layout.
pub fn at2_text(units: &str, npts_line: &str, values: &[&str]) -> String {
    let mut s = format!("TEST RECORD\nTEST EVENT, TEST STATION, 000\n{units}\n{npts_line}\n");
    for chunk in values.chunks(5) {
        s.push_str(&chunk.join("  "));
        s.push('\n');
    }
    s
}
