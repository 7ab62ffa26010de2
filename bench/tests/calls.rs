//! The `calls` section against the `rocking` binary it times (built by
//! `cargo build --release` at the repository's root, as CI does before
//! running these tests).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn bundled_records() -> PathBuf {
    root().join("records/fema-p695")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A fresh folder, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn tempdir() -> TempDir {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "rocking-bench-test-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).unwrap();
    TempDir(dir)
}

/// The harness with `args`, timing the root's release `rocking` binary.
fn bench_bin(args: &[&str]) -> Output {
    let rocking = root().join("target/release/rocking");
    assert!(
        rocking.is_file(),
        "{}: build the rocking binary first (cargo build --release at the root)",
        rocking.display()
    );
    Command::new(env!("CARGO_BIN_EXE_rocking-bench"))
        .args(args)
        .arg("--rocking")
        .arg(&rocking)
        .current_dir(root())
        .output()
        .expect("the harness runs")
}

/// `rocking-bench --sections calls` times `rocking capacity` as a new
/// process per call: in the quick run, the first three far-field records
/// (by name) at p = 2. The row's figures must be ordered (fastest ≤ median
/// ≤ slowest), the slowest must be one of those records, and a record the
/// command refuses must stop the benchmark with the call and its error.
#[test]
fn bench_times_capacity_calls_and_reports_a_failing_call() {
    let dir = tempdir();
    let bench = |records: &std::path::Path, reps: &str| {
        bench_bin(&[
            "--quick",
            "--sections",
            "calls",
            "--reps",
            reps,
            "--records",
            records.to_str().unwrap(),
            "--out-dir",
            dir.path().to_str().unwrap(),
        ])
    };
    let records = bundled_records();
    let out = bench(&records, "3");
    assert!(out.status.success(), "{}", stderr(&out));
    let md = std::fs::read_to_string(dir.path().join("BENCHMARKS.md")).unwrap();
    let row = md
        .lines()
        .find(|l| l.starts_with("| 2 | 3 |"))
        .unwrap_or_else(|| panic!("no row for p = 2 over 3 records:\n{md}"));
    // | p | records | median | mean | fastest | slowest (record) | within 3 ms | loop | batch |
    let cells: Vec<&str> = row.split('|').map(str::trim).collect();
    let ms = |cell: &str| -> f64 {
        let t = cell.split(" ms").next().unwrap();
        t.parse().unwrap_or_else(|_| panic!("{cell:?} in {row}"))
    };
    let (median, mean) = (ms(cells[3]), ms(cells[4]));
    let (fastest, slowest) = (ms(cells[5]), ms(cells[6]));
    assert!(
        0.0 < fastest && fastest <= median && median <= slowest,
        "{row}"
    );
    // A mean lies between the extremes (to the table's 0.01 ms rounding).
    assert!(fastest <= mean && mean <= slowest, "{row}");
    let mut files: Vec<String> = std::fs::read_dir(records.join("far-field"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|f| f.ends_with(".AT2"))
        .collect();
    files.sort();
    let first_three: Vec<&str> = files[..3]
        .iter()
        .map(|f| f.trim_end_matches(".AT2"))
        .collect();
    assert!(
        first_three.iter().any(|r| row.contains(&format!("({r})"))),
        "{row} names none of {first_three:?}"
    );
    let within: usize = cells[7].strip_suffix(" of 3").unwrap().parse().unwrap();
    assert!(within <= 3, "{row}");
    // The loop is the three records' calls added up: three times their mean
    // (to the 1 ms rounding of the column); the batch call took some time.
    let (looped, batch) = (ms(cells[8]), ms(cells[9]));
    assert!((looped - 3.0 * mean).abs() <= 0.5 + 0.015, "{row}");
    assert!(batch > 0.0, "{row}");

    let bad = tempdir();
    std::fs::create_dir(bad.path().join("far-field")).unwrap();
    std::fs::write(bad.path().join("far-field/BROKEN.AT2"), "not a record\n").unwrap();
    let out = bench(bad.path(), "1");
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("capacity --record") && err.contains("BROKEN.AT2"),
        "{err}"
    );
    assert!(err.contains("failed"), "{err}");
}

/// An absurd repetition count is refused before anything runs.
#[test]
fn absurd_repetitions_are_refused() {
    let dir = tempdir();
    let out = bench_bin(&[
        "--reps",
        "1000000000000",
        "--quick",
        "--out-dir",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("--reps"), "{}", stderr(&out));
}
