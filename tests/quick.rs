//! The quick study end to end (slow: `ROCKING_SLOW=1`, which CI sets):
//!
//! - **users see no change**: every table of the quick study has the
//!   schema and the data (every value, bit for bit) of the reference, in
//!   every column it had. `tests/snapshots/quick_tables.txt` holds, per
//!   table, its schema, row count and the SHA-256 of an exact dump of those
//!   columns, made with
//!   `ROCKING_BLESS=1 ROCKING_QUICK_FROM=<outputs/quick> cargo test --release quick`
//!   from outputs checked independently each time (polars `equals` on every
//!   table against the previous version; where a change of the stepper
//!   moved rounding, every verdict, capacity and certification identical
//!   and θmax/α within 1e-13 but for a few sensitive runs; the history is
//!   in git). Columns added since are allowed only as listed in [`ADDED`],
//!   with what they add. Key-value metadata (versions, settings) is not
//!   compared.
//! - **analysts can query the outputs**: the polars and DuckDB
//!   queries of `outputs/README.md` run against the study's folder, and
//!   their answers equal the tool's own tables (medians from the raw
//!   capacities against `capacity_fractiles`, resurrection shares from the
//!   raw runs against `overturn_fraction`). Python with polars and duckdb
//!   comes from `ROCKING_PYTHON` (`.ci/run` installs them in a venv) or
//!   `python3`; under `ROCKING_SLOW` a missing module fails the test.

use std::path::{Path, PathBuf};
use std::process::Command;

use rocking::tables::fit::{Coefficient, FitCoefficientRow, Source};
use rocking::tables::read;
use rocking::tables::reduce::{CapacityFractileRow, OverturnFractionRow};
use sha2::{Digest, Sha256};

use crate::util::{columns_of, dump_columns, rocking, root, schema_of, snapshot, stderr, tempdir};

/// Columns added to a table of the quick study since the reference was
/// made, with what they add.
const ADDED: &[(&str, &[&str], &str)] = &[
    (
        "capacities.parquet",
        &[
            "certified",
            "certification",
            "certification_note",
            "integrator",
            "rtol",
        ],
        "certified capacities, and the integrator that found them",
    ),
    (
        "capacities.parquet",
        &["pfa_over_pga", "slides_first"],
        "a block on a building's floor, and one that slides before it rocks",
    ),
    (
        "ida_points.parquet",
        &["slide_max_m"],
        "the slide of a block run by the slide-rock model (empty for a rocking model)",
    ),
];

/// Schema, rows and digest of one table's `columns` (all when `None`).
fn digest(path: &Path, columns: Option<&[String]>) -> String {
    let dump = dump_columns(path, true, columns);
    let hash: String = Sha256::digest(dump.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    format!(
        "rows {}\tsha256 {hash}\t{}",
        dump.lines().count() - 1,
        schema_of(path, columns)
    )
}

/// Every table of `dir`, in full, one line each (the reference's form).
fn digests(dir: &Path) -> String {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".parquet"))
        .collect();
    names.sort();
    names
        .iter()
        .map(|n| format!("{n}\t{}\n", digest(&dir.join(n), None)))
        .collect()
}

/// Checks every table of `dir` against the reference: the reference's
/// columns bit for bit, and no other column than those of [`ADDED`].
fn compare_with_reference(dir: &Path) {
    let reference =
        std::fs::read_to_string(root().join("tests/snapshots/quick_tables.txt")).unwrap();
    let mut tables = 0;
    for line in reference.lines() {
        let mut fields = line.split('\t');
        let name = fields.next().unwrap();
        let schema = line.rsplit('\t').next().unwrap();
        let columns: Vec<String> = schema
            .split("; ")
            .map(|c| c.split(' ').next().unwrap().to_string())
            .collect();
        let path = dir.join(name);
        let now = format!("{name}\t{}", digest(&path, Some(&columns)));
        assert_eq!(
            now, line,
            "{name} differs from the pre-redesign version in its columns"
        );
        let allowed: Vec<&str> = ADDED
            .iter()
            .filter(|(t, _, _)| *t == name)
            .flat_map(|(_, cols, _)| cols.iter().copied())
            .collect();
        for c in columns_of(&path) {
            assert!(
                columns.contains(&c) || allowed.contains(&c.as_str()),
                "{name}: column `{c}` is new; add it to ADDED with the issue that adds it"
            );
        }
        tables += 1;
    }
    assert_eq!(
        tables, 15,
        "the reference lists every table of the quick study"
    );
}

#[test]
fn quick_study_is_unchanged_and_answers_the_documented_queries() {
    if std::env::var("ROCKING_SLOW").is_err() {
        eprintln!("skipped: set ROCKING_SLOW=1 to run the quick study");
        return;
    }
    let dir = tempdir();
    let outputs = dir.path().join("outputs");
    let folder = match std::env::var("ROCKING_QUICK_FROM") {
        Ok(from) => PathBuf::from(from),
        Err(_) => {
            // The README's main job, from the repository root (the records
            // table stores the AT2 paths as the pipeline reached them).
            let out = rocking(
                &root(),
                &[
                    "run",
                    "pipelines/quick.toml",
                    "--outputs",
                    outputs.to_str().unwrap(),
                ],
            );
            assert!(out.status.success(), "{}", stderr(&out));
            outputs.join("quick")
        }
    };
    if std::env::var("ROCKING_QUICK_FROM").is_ok() {
        // Making the reference from a given folder (see the module doc).
        snapshot("quick_tables.txt", &digests(&folder));
        return;
    }
    compare_with_reference(&folder);
    analyst_queries(dir.path(), "quick", &folder);
    horizontal_is_the_kth_overturning(&folder);
    reads_as_prose(&folder);
    // The paper's grid (p log-spaced: 2.1213…, ε a linear range): the same
    // queries answer, by the blocks' indices and by a stated ε value.
    let out = rocking(
        &root(),
        &[
            "fit",
            "pipelines/paper.toml",
            "--outputs",
            outputs.to_str().unwrap(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    analyst_queries(dir.path(), "paper", &outputs.join("paper"));
    horizontal_is_the_kth_overturning(&outputs.join("paper"));
}

/// The report names things as a reader does: no TeX source (`^{`, `_{`, a
/// backslash command, A_g) and no Rust name of a setting (`Linearized`,
/// `Type7`, `Log`, `Some(…)`) in report.md or report.html.
fn reads_as_prose(folder: &Path) {
    for file in ["report.md", "report.html"] {
        let text = std::fs::read_to_string(folder.join(file)).unwrap();
        for bad in [
            "^{",
            "_{",
            "A_g",
            "$",
            "Linearized",
            "Nonlinear",
            "Type7",
            "Type5",
            "Log-spaced",
            "Linear-spaced",
            "Some(",
            "None",
            "Pair",
            "Record ",
            "Static",
            "Dynamic",
        ] {
            assert!(!text.contains(bad), "{file} holds `{bad}`");
        }
        let tex = text
            .as_bytes()
            .windows(2)
            .any(|w| w[0] == b'\\' && w[1].is_ascii_alphabetic());
        assert!(!tex, "{file} holds a TeX command");
    }
}

/// Fig. 7's horizontal capacity q-fractile is, exactly, the grid level at
/// which the k-th least fragile record (the k-th smallest such level) first
/// overturned, k = ⌈1 + (n − 1)q⌉ (type 7): the q-fractile of θmax/α given
/// η is +∞ once all records but k − 1 are (+∞ in an interpolation is +∞
/// whatever its weight). Both it and the
/// vertical fractile (between the (k − 1)-th and k-th capacities) are at
/// most the k-th capacity (a record's η_c is at least the level it first
/// overturned at); which is larger depends on the gap between the records.
fn horizontal_is_the_kth_overturning(folder: &Path) {
    use rocking::tables::sweep::CapacityRow;
    let caps: Vec<CapacityRow> = read(&folder.join("capacities.parquet")).unwrap();
    let fractiles: Vec<CapacityFractileRow> =
        read(&folder.join("capacity_fractiles.parquet")).unwrap();
    let mut checked = 0;
    for f in &fractiles {
        let mut first: Vec<f64> = caps
            .iter()
            .filter(|c| c.p == f.p && c.eps == f.eps)
            .map(|c| c.level_overturned.unwrap_or(0.0))
            .collect();
        let mut eta_c: Vec<f64> = caps
            .iter()
            .filter(|c| c.p == f.p && c.eps == f.eps)
            .map(|c| c.eta_c.unwrap_or(0.0))
            .collect();
        first.sort_by(|a, b| a.total_cmp(b));
        eta_c.sort_by(|a, b| a.total_cmp(b));
        let n = first.len();
        assert_eq!(n as i64, f.n_records);
        let k = (1.0 + (n - 1) as f64 * f.quantile).ceil() as usize;
        let kth = first[k - 1];
        let want = (kth > 0.0).then_some(kth);
        assert_eq!(
            f.eta_c_horizontal,
            want,
            "{}: p = {}, ε = {}, q = {}",
            folder.display(),
            f.p,
            f.eps,
            f.quantile
        );
        assert!(f.eta_c <= eta_c[k - 1] && kth <= eta_c[k - 1]);
        checked += 1;
    }
    assert!(checked >= 36, "{checked}");
}

/// The Python program: every `python` block of outputs/README.md, every
/// `sql` block through DuckDB, and a JSON line of the answers to check.
fn program(study: &str) -> String {
    let readme = std::fs::read_to_string(root().join("outputs/README.md"))
        .unwrap()
        .replace("outputs/quick/", &format!("outputs/{study}/"));
    let blocks = |lang: &str| -> Vec<String> {
        let fence = format!("```{lang}\n");
        readme
            .split(&fence)
            .skip(1)
            .map(|rest| rest.split("```").next().unwrap().to_string())
            .collect()
    };
    let (py, sql) = (blocks("python"), blocks("sql"));
    assert!(
        !py.is_empty() && sql.len() >= 3,
        "the README shows its queries"
    );
    let mut prog = py.join("\n");
    prog.push_str("\nimport duckdb, json\n");
    for (i, q) in sql.iter().enumerate() {
        prog.push_str(&format!("sql_{i} = duckdb.sql({q:?}).fetchall()\n"));
    }
    prog.push_str(
        "print(json.dumps({\n\
         'records': records.select('record_id', 'pga_g').rows(),\n\
         'median': median.rows(),\n\
         'share': share.select('eta', 'share_overturned').rows(),\n\
         'one': one.rows(),\n\
         'sql_median': sql_0,\n\
         'sql_at_eps': sql_1,\n\
         'sql_coefficients': sql_2,\n\
         }))\n",
    );
    prog
}

/// Runs the README's queries on the study `study` (in `cwd/outputs`,
/// which is `folder`) and checks their answers against its tables.
fn analyst_queries(cwd: &Path, study: &str, folder: &Path) {
    let python = std::env::var("ROCKING_PYTHON").unwrap_or_else(|_| "python3".into());
    let probe = Command::new(&python)
        .args(["-c", "import polars, duckdb"])
        .output();
    if !probe.as_ref().is_ok_and(|o| o.status.success()) {
        panic!(
            "{python} cannot import polars and duckdb (`.ci/run` installs them; locally: \
             python3 -m venv v && v/bin/pip install polars duckdb, then ROCKING_PYTHON=v/bin/python)"
        );
    }
    let out = Command::new(&python)
        .args(["-c", &program(study)])
        .current_dir(cwd)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "the README's queries fail:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let answers: serde_json::Value = serde_json::from_str(stdout.lines().last().unwrap())
        .unwrap_or_else(|e| panic!("{e}: {stdout}"));

    // Strongest record first, as the records table says, of the study's
    // set (the table holds every set ingested).
    let mut records: Vec<rocking::tables::records::RecordRow> =
        read(&folder.join("records.parquet")).unwrap();
    records.retain(|r| r.meta.set.as_deref() == Some("far-field"));
    assert_eq!(records.len(), 44);
    let strongest = records
        .iter()
        .max_by(|a, b| a.pga_g.total_cmp(&b.pga_g))
        .unwrap();
    assert_eq!(
        answers["records"][0][0].as_str(),
        Some(strongest.record_id.as_str())
    );
    assert_eq!(answers["records"].as_array().unwrap().len(), records.len());

    // polars' median and DuckDB's quantile_cont interpolate between order
    // statistics as Hyndman–Fan type 7 does, the quick study's definition:
    // the 50 % capacity fractile, computed independently. Tolerance: one
    // rounding of the mean of the two middle values.
    let fractiles: Vec<CapacityFractileRow> =
        read(&folder.join("capacity_fractiles.parquet")).unwrap();
    let median_of = |p: f64, e: f64| {
        fractiles
            .iter()
            .find(|r| r.p == p && r.eps == e && r.quantile == 0.5)
            .unwrap()
            .eta_c
    };
    let n_blocks = fractiles.len() / 3;
    for key in ["median", "sql_median"] {
        let rows = answers[key].as_array().unwrap();
        assert_eq!(rows.len(), n_blocks, "{key}: one row per block");
        for r in rows {
            let (p, e, v) = (
                r[0].as_f64().unwrap(),
                r[1].as_f64().unwrap(),
                r[2].as_f64().unwrap(),
            );
            let ours = median_of(p, e);
            assert!(
                (v - ours).abs() <= 2.0 * f64::EPSILON * ours,
                "{key} p = {p} ε = {e}: {v} vs capacity_fractiles {ours}"
            );
        }
    }

    // The share overturned under the resurrection rule, from the raw runs,
    // equals overturn_fraction at every level that was run: both are a count
    // over 44, to an ulp (polars' column division is not always correctly
    // rounded: 5/44 comes out one ulp high).
    let fraction: Vec<OverturnFractionRow> =
        read(&folder.join("overturn_fraction.parquet")).unwrap();
    let share = answers["share"].as_array().unwrap();
    assert!(share.len() > 20, "{share:?}");
    // The block picked by its indices: the grid's third p, second ε.
    let blocks: Vec<rocking::tables::reduce::BlockRow> =
        read(&folder.join("blocks.parquet")).unwrap();
    let ps = rocking::stats::distinct(blocks.iter().map(|b| b.p).collect());
    let es = rocking::stats::distinct(blocks.iter().map(|b| b.eps).collect());
    let (bp, be) = (ps[2], es[1]);
    assert_eq!(answers["one"], serde_json::json!([[bp, be]]));
    for r in share {
        let (eta, s) = (r[0].as_f64().unwrap(), r[1].as_f64().unwrap());
        let row = fraction
            .iter()
            .find(|f| f.p == bp && f.eps == be && f.eta == eta)
            .unwrap_or_else(|| panic!("no level η = {eta}"));
        let ours = row.fraction_resurrection;
        assert!(
            (s - ours).abs() <= 2.0 * f64::EPSILON * ours.max(f64::MIN_POSITIVE),
            "η = {eta}: {s} vs overturn_fraction {ours}"
        );
    }

    // ε = 0.7 by its value: every p's three fractiles, as the table holds them.
    let at = answers["sql_at_eps"].as_array().unwrap();
    let want: Vec<&CapacityFractileRow> = fractiles.iter().filter(|f| f.eps == 0.7).collect();
    assert_eq!(at.len(), want.len());
    assert_eq!(at.len(), 3 * ps.len(), "every p at ε = 0.7");
    for r in at {
        let (p, q, v) = (r[0].as_f64(), r[1].as_f64(), r[2].as_f64());
        assert!(want
            .iter()
            .any(|f| Some(f.p) == p && Some(f.quantile) == q && Some(f.eta_c) == v));
    }

    // The coefficient rows DuckDB selects are the fit's, unchanged.
    let coeffs: Vec<FitCoefficientRow> = read(&folder.join("fit_coefficients.parquet")).unwrap();
    let rows = answers["sql_coefficients"].as_array().unwrap();
    assert_eq!(rows.len(), 6);
    for r in rows {
        let source = match r[0].as_str().unwrap() {
            "fitted" => Source::Fitted,
            _ => Source::Paper,
        };
        let coefficient = match r[1].as_str().unwrap() {
            "a" => Coefficient::A,
            "b" => Coefficient::B,
            _ => Coefficient::C,
        };
        let ours = coeffs
            .iter()
            .find(|c| c.source == source && c.coefficient == coefficient && c.quantile == 0.5)
            .unwrap();
        assert_eq!(r[2].as_f64(), ours.c0);
        assert_eq!(r[4].as_f64(), ours.c2);
    }
}
