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

/// Writes `dir/<name>.toml`: a pipeline named `name` over the bundled
/// records (by absolute path, with their manifest), `body` after `[records]`.
pub fn write_pipeline(dir: &Path, name: &str, body: &str) -> PathBuf {
    let rec = bundled_records();
    let text = format!(
        "name = \"{name}\"\n[records]\nat2 = [\"{}\"]\nmanifest = \"{}\"\n{body}",
        rec.display(),
        rec.join("manifest.csv").display()
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// An AT2 file in the NGA-West2 layout holding `accel` (g) exactly: every
/// value in Rust's shortest round-trip form, read back correctly rounded.
pub fn write_at2(path: &Path, accel: &[f64], dt: f64) {
    let mut s = format!(
        "FLOOR MOTION\nTEST\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= {}, DT= {dt} SEC\n",
        accel.len()
    );
    for chunk in accel.chunks(5) {
        let line: Vec<String> = chunk.iter().map(|a| format!("{a:e}")).collect();
        s.push_str(&line.join("  "));
        s.push('\n');
    }
    std::fs::write(path, s).unwrap();
}

/// The peak velocity of a piecewise-linear acceleration `a` sampled every
/// `h` s (in `a`'s unit × s): the velocity's largest magnitude at the
/// samples and where the acceleration crosses 0, written independently of
/// the tool's.
pub fn peak_velocity(a: &[f64], h: f64) -> f64 {
    let (mut v, mut peak) = (0.0f64, 0.0f64);
    for w in a.windows(2) {
        if w[0] * w[1] < 0.0 {
            let tau = -w[0] * h / (w[1] - w[0]);
            peak = peak.max((v + w[0] * tau / 2.0).abs());
        }
        v += 0.5 * h * (w[0] + w[1]);
        peak = peak.max(v.abs());
    }
    peak
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

/// A Parquet table as text, read with the `parquet` crate directly (not
/// through rocking's typed readers): a header of column names, then one
/// line per row, tab-separated. Floats to 12 significant digits, or, with
/// `exact`, in Rust's shortest round-trip form (so equal text is equal
/// bits); strings quoted; `null` for an empty cell; lists in brackets.
pub fn dump_table(path: &Path, exact: bool) -> String {
    dump_columns(path, exact, None)
}

/// [`dump_table`] of the named columns only (in that order), or of all.
pub fn dump_columns(path: &Path, exact: bool, only: Option<&[String]>) -> String {
    use arrow_array::cast::AsArray;
    use arrow_array::types::{Float64Type, Int64Type, Int8Type};
    use arrow_array::{Array, ArrayRef};
    use arrow_schema::DataType;
    use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

    fn float(x: f64, exact: bool) -> String {
        match (exact, x.is_finite()) {
            (true, _) => format!("{x:?}"),
            (false, true) => format!("{x:.11e}"),
            (false, false) => format!("{x}"),
        }
    }
    fn cell(col: &ArrayRef, i: usize, exact: bool) -> String {
        if col.is_null(i) {
            return "null".into();
        }
        match col.data_type() {
            DataType::Float64 => float(col.as_primitive::<Float64Type>().value(i), exact),
            DataType::Int64 => col.as_primitive::<Int64Type>().value(i).to_string(),
            DataType::Int8 => col.as_primitive::<Int8Type>().value(i).to_string(),
            DataType::Utf8 => format!("{:?}", col.as_string::<i32>().value(i)),
            DataType::Boolean => col.as_boolean().value(i).to_string(),
            DataType::List(_) => {
                let item = col.as_list::<i32>().value(i);
                let items: Vec<String> = (0..item.len()).map(|k| cell(&item, k, exact)).collect();
                format!("[{}]", items.join(","))
            }
            other => panic!("{}: no dump for {other}", path_hint()),
        }
    }
    fn path_hint() -> &'static str {
        "dump_table"
    }
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).unwrap();
    let schema = builder.schema().clone();
    let names: Vec<String> = match only {
        Some(names) => names.to_vec(),
        None => schema.fields().iter().map(|f| f.name().clone()).collect(),
    };
    let mut s = names.join("\t");
    s.push('\n');
    for batch in builder.build().unwrap() {
        let batch = batch.unwrap();
        let columns: Vec<&ArrayRef> = names
            .iter()
            .map(|n| {
                batch
                    .column_by_name(n)
                    .unwrap_or_else(|| panic!("{}: no column {n}", path.display()))
            })
            .collect();
        for i in 0..batch.num_rows() {
            let cells: Vec<String> = columns.iter().map(|c| cell(c, i, exact)).collect();
            s.push_str(&cells.join("\t"));
            s.push('\n');
        }
    }
    s
}

/// The schema of a Parquet file: `name type nullable` per column (of the
/// named columns only, in that order, when `only` is given).
pub fn schema_of(path: &Path, only: Option<&[String]>) -> String {
    use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
    let file = std::fs::File::open(path).unwrap();
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).unwrap();
    let schema = builder.schema();
    let fields: Vec<_> = match only {
        Some(names) => names
            .iter()
            .map(|n| schema.field_with_name(n).expect("column present").clone())
            .collect(),
        None => schema.fields().iter().map(|f| f.as_ref().clone()).collect(),
    };
    fields
        .iter()
        .map(|f| format!("{} {} {}", f.name(), f.data_type(), f.is_nullable()))
        .collect::<Vec<_>>()
        .join("; ")
}

/// The column names of a Parquet file.
pub fn columns_of(path: &Path) -> Vec<String> {
    use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
    let file = std::fs::File::open(path).unwrap();
    let builder = ParquetRecordBatchReaderBuilder::try_new(file).unwrap();
    builder
        .schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect()
}

/// Compares `text` with `tests/snapshots/<name>`; `ROCKING_BLESS=1` (re)writes
/// it. Bless only output that has been reviewed.
pub fn snapshot(name: &str, text: &str) {
    let path = root().join("tests/snapshots").join(name);
    if std::env::var("ROCKING_BLESS").is_ok() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
        return;
    }
    let expected = std::fs::read_to_string(&path).unwrap_or_else(|_| {
        panic!(
            "no snapshot {}; review the output and bless it with ROCKING_BLESS=1",
            path.display()
        )
    });
    if expected != text {
        let diff: Vec<String> = expected
            .lines()
            .zip(text.lines())
            .filter(|(a, b)| a != b)
            .take(5)
            .map(|(a, b)| format!("- {a}\n+ {b}"))
            .collect();
        panic!(
            "snapshot {name} differs (rerun with ROCKING_BLESS=1 once reviewed):\n{}{}",
            diff.join("\n"),
            if expected.lines().count() != text.lines().count() {
                format!(
                    "\n({} lines expected, {} now)",
                    expected.lines().count(),
                    text.lines().count()
                )
            } else {
                String::new()
            }
        );
    }
}

/// `rocking capacity --json` on one AT2 record (a path from `cwd`) at p and
/// ε, over `levels` log-spaced levels down to η = 0.01: the direct answer a
/// stage's capacities are held to.
pub fn direct_capacity(
    cwd: &Path,
    record: &str,
    p: f64,
    eps: f64,
    levels: usize,
) -> serde_json::Value {
    let (p, eps, levels) = (p.to_string(), eps.to_string(), levels.to_string());
    let out = rocking(
        cwd,
        &[
            "capacity",
            "--record",
            record,
            "--p",
            &p,
            "--eps",
            &eps,
            "--levels",
            &levels,
            "--eta-min",
            "0.01",
            "--json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Standard normal CDF, written here so that the checks do not lean on the
/// tool's own Φ: the Maclaurin series of erf for |z| < 2 and the continued
/// fraction of erfc (Lentz's method) beyond, both to about 1e-16.
pub fn phi(x: f64) -> f64 {
    // Series of erf for small |z|, continued fraction of erfc for large.
    let z = x / std::f64::consts::SQRT_2;
    if z.abs() < 2.0 {
        let mut term = z;
        let mut sum = z;
        for n in 1..200 {
            term *= -z * z / n as f64;
            let add = term / (2 * n + 1) as f64;
            sum += add;
            if add.abs() < 1e-17 * sum.abs() {
                break;
            }
        }
        0.5 * (1.0 + 2.0 / std::f64::consts::PI.sqrt() * sum)
    } else {
        // erfc(|z|) by Lentz's continued fraction.
        let a = z.abs();
        let mut f = a;
        let (mut c, mut d) = (a, 0.0);
        for n in 1..300 {
            let an = n as f64 / 2.0;
            d = a + an * d;
            d = 1.0 / d;
            c = a + an / c;
            let delta = c * d;
            f *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        let erfc = (-a * a).exp() / (f * std::f64::consts::PI.sqrt());
        if z > 0.0 {
            1.0 - 0.5 * erfc
        } else {
            0.5 * erfc
        }
    }
}

/// Cornell's closed form of λ = ∫_c^∞ Φ(ln(a/m)/β) |dλ(a)| on a power-law
/// hazard λ(a) = k0·a^−k, the lognormal cut to 0 below `c` (0: none): by
/// parts, P(c)λ(c) + k0·E[A^−k; A > c] over the lognormal A, that is
/// P(c)·k0·c^−k + k0·m^−k·e^{k²β²/2}·Φ((ln(m/c) − kβ²)/β).
pub fn cornell_above(k0: f64, k: f64, m: f64, beta: f64, c: f64) -> f64 {
    let full = k0 * m.powf(-k) * (k * k * beta * beta / 2.0).exp();
    if c <= 0.0 {
        return full;
    }
    phi((c / m).ln() / beta) * k0 * c.powf(-k) + full * phi(((m / c).ln() - k * beta * beta) / beta)
}

/// A lock at `lock` held by a live process (a `sleep` started here, which
/// the caller kills) as `command` on this host: what a running `rocking`
/// leaves, its start time read from /proc as the tool checks it. Returns
/// the holder and the host's name. (Linux: it reads /proc.)
pub fn live_lock(lock: &Path, command: &str) -> (std::process::Child, String) {
    let holder = std::process::Command::new("sleep")
        .arg("30")
        .spawn()
        .unwrap();
    let stat = std::fs::read_to_string(format!("/proc/{}/stat", holder.id())).unwrap();
    let ticks: u64 = stat[stat.rfind(')').unwrap() + 1..]
        .split_whitespace()
        .nth(19)
        .unwrap()
        .parse()
        .unwrap();
    let host = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap();
    let host = host.trim().to_string();
    let owner = serde_json::json!({
        "pid": holder.id(), "host": host, "started_ticks": ticks,
        "since_unix_s": 0, "command": command, "process": "sleep"
    });
    std::fs::write(lock, owner.to_string()).unwrap();
    (holder, host)
}
