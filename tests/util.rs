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

/// A fresh folder under the system temp dir, removed on drop. (Hand-rolled
/// rather than the `tempfile` crate: a dev-dependency would change feature
/// unification and make `cargo test` rebuild dependencies `cargo run` built.)
pub struct TempDir(PathBuf);

impl TempDir {
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

pub fn tempdir() -> TempDir {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let dir = std::env::temp_dir().join(format!("rocking-test-{}-{n}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    TempDir(dir)
}

/// A bundled record (`set/STEM`), normalised for the solvers.
pub fn bundled(set_stem: &str) -> rocking::physics::Excitation {
    let path = bundled_records().join(format!("{set_stem}.AT2"));
    let at2 = rocking::at2::parse(&std::fs::read(&path).unwrap()).unwrap();
    rocking::physics::Excitation::new(&at2.accel_g, at2.dt_s).unwrap()
}

pub fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}
