//! `rocking run` and `rocking status`: cached stages that rerun for the
//! right reasons (settings, inputs and outputs changed behind the tool's
//! back, fingerprints missing or corrupted), the lock, and a snapshot of a
//! mini study's tables (rounded to 12 significant digits) whose capacities
//! are checked against direct `rocking capacity` runs.

use std::fs;
use std::path::{Path, PathBuf};

use rocking::tables::summary::{Flat, CAPACITY_FRACTILES, HORIZONTAL, LOGNORMAL};
use rocking::tables::sweep::read_capacities;

use crate::util::{bundled_records, rocking, root, stderr, stdout, tempdir};

const RECORDS: [&str; 3] = [
    "RSN1111_KOBE_NIS000",
    "RSN953_NORTHR_MUL009",
    "RSN1633_MANJIL_ABBAR--L",
];

/// A folder with copies of three far-field records and a 3 × 3 pipeline
/// (the smallest grid the regression accepts).
fn study(dir: &Path, eps: &str) -> PathBuf {
    let rec = dir.join("records");
    fs::create_dir_all(&rec).unwrap();
    for id in RECORDS {
        let src = bundled_records()
            .join("far-field")
            .join(format!("{id}.AT2"));
        if !rec.join(format!("{id}.AT2")).exists() {
            fs::copy(src, rec.join(format!("{id}.AT2"))).unwrap();
        }
    }
    let text = format!(
        "name = \"mini\"\n[records]\nat2 = [\"records\"]\n[blocks]\np = [1.5, 3.0, 6.0]\neps = [0.6, 0.75, {eps}]\n[im]\ncount = 40\neta_min = 0.01\n"
    );
    let path = dir.join("mini.toml");
    fs::write(&path, text).unwrap();
    path
}

fn run(dir: &Path, pipe: &Path) -> (String, String) {
    let out = rocking(dir, &["run", pipe.to_str().unwrap(), "--outputs", "out"]);
    assert!(out.status.success(), "{}", stderr(&out));
    (stdout(&out), stderr(&out))
}

/// The log line of a stage.
fn line<'a>(log: &'a str, stage: &str) -> &'a str {
    log.lines()
        .find(|l| l.starts_with(stage))
        .unwrap_or_else(|| panic!("no `{stage}` in:\n{log}"))
}

#[test]
fn stages_rerun_only_when_something_they_read_changed() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = study(d, "0.9");
    let (out, log) = run(d, &pipe);
    assert!(
        out.contains("ran ingest, sweep, reduce, fit, report"),
        "{out}"
    );
    assert!(line(&log, "convergence").contains("not needed"), "{log}");
    for f in [
        "records.parquet",
        "capacities.parquet",
        "capacity_fractiles.parquet",
        "fit_coefficients.parquet",
        "report.md",
        "figures/fig05_ida_curves.svg",
        "figures/fig08_capacity_curves.svg",
    ] {
        assert!(d.join("out/mini").join(f).exists(), "{f}");
    }

    // A second run is a no-op that says so; status agrees.
    let (out, _) = run(d, &pipe);
    assert!(out.contains("nothing to do"), "{out}");
    let status = stdout(&rocking(
        d,
        &["status", pipe.to_str().unwrap(), "--outputs", "out"],
    ));
    assert!(
        status
            .lines()
            .all(|l| l.contains("fresh") || l.contains("not needed")),
        "{status}"
    );

    // Editing ε reruns sweep, reduce, fit (and report) but not ingest.
    let pipe = study(d, "0.85");
    let status = stdout(&rocking(
        d,
        &["status", pipe.to_str().unwrap(), "--outputs", "out"],
    ));
    assert!(
        line(&status, "sweep").contains("stale: settings changed"),
        "{status}"
    );
    let (out, log) = run(d, &pipe);
    assert!(line(&log, "ingest").contains("skipped: fresh"), "{log}");
    assert!(
        line(&log, "sweep").contains("running: settings changed"),
        "{log}"
    );
    assert!(
        line(&log, "reduce").contains("running: input capacities.parquet changed"),
        "{log}"
    );
    assert!(out.contains("ran sweep, reduce, fit, report"), "{out}");

    // A missing and a corrupted fingerprint rerun their stage, saying why.
    let notes = d.join("out/mini/.fingerprints");
    fs::remove_file(notes.join("reduce.json")).unwrap();
    fs::write(notes.join("sweep.json"), "{ not json").unwrap();
    let (_, log) = run(d, &pipe);
    assert!(line(&log, "sweep").contains("unreadable"), "{log}");
    assert!(line(&log, "reduce").contains("no fingerprint"), "{log}");
    assert!(line(&log, "ingest").contains("fresh"), "{log}");

    // An input edited behind the tool's back reruns ingest and what follows.
    let at2 = d.join("records/RSN953_NORTHR_MUL009.AT2");
    let text = fs::read_to_string(&at2).unwrap();
    let edited = text.replacen(".3493050E-04", ".3493051E-04", 1);
    assert_ne!(text, edited, "the sample to edit is in the file");
    fs::write(&at2, edited).unwrap();
    let (_, log) = run(d, &pipe);
    assert!(
        line(&log, "ingest").contains("RSN953_NORTHR_MUL009.AT2 changed"),
        "{log}"
    );

    // An output changed behind its back reruns the stage that wrote it.
    let report = d.join("out/mini/report.md");
    fs::write(&report, "scribbled over").unwrap();
    let (_, log) = run(d, &pipe);
    assert!(
        line(&log, "report").contains("was changed since it was written"),
        "{log}"
    );
    assert!(line(&log, "sweep").contains("fresh"), "{log}");
}

#[test]
fn a_second_run_at_once_is_refused_and_a_dead_lock_is_taken_over() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = study(d, "0.9");
    fs::create_dir_all(d.join("out/mini")).unwrap();
    // A live process (this test) holds the lock.
    fs::write(d.join("out/mini/.lock"), std::process::id().to_string()).unwrap();
    let out = rocking(d, &["run", pipe.to_str().unwrap(), "--outputs", "out"]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains(&format!("(pid {})", std::process::id())),
        "{}",
        stderr(&out)
    );
    assert!(!d.join("out/mini/capacities.parquet").exists());
    // A lock left by a process that is gone does not block.
    fs::write(d.join("out/mini/.lock"), "999999999").unwrap();
    let (out, _) = run(d, &pipe);
    assert!(out.contains("ran"), "{out}");
    assert!(!d.join("out/mini/.lock").exists(), "released at the end");
}

/// Rows of a table as text, floats to 12 significant digits.
fn dump(t: &Flat, path: &Path) -> String {
    let mut s = t.columns.iter().map(|c| c.0).collect::<Vec<_>>().join("\t");
    s.push('\n');
    for row in t.read(path).unwrap() {
        let cells: Vec<String> = row
            .iter()
            .map(|v| match v {
                rocking::tables::summary::Value::F(Some(x)) if x.is_finite() => format!("{x:.11e}"),
                rocking::tables::summary::Value::F(Some(x)) => format!("{x}"),
                rocking::tables::summary::Value::F(None)
                | rocking::tables::summary::Value::I(None) => "null".into(),
                rocking::tables::summary::Value::I(Some(i)) => i.to_string(),
                rocking::tables::summary::Value::S(s) => format!("{s:?}"),
                rocking::tables::summary::Value::B(b) => b.to_string(),
            })
            .collect();
        s.push_str(&cells.join("\t"));
        s.push('\n');
    }
    s
}

/// Compares with `tests/snapshots/<name>`; `ROCKING_BLESS=1` (re)writes it.
fn snapshot(name: &str, text: &str) {
    let path = root().join("tests/snapshots").join(name);
    if std::env::var("ROCKING_BLESS").is_ok() {
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(&path, text).unwrap();
        return;
    }
    let expected = fs::read_to_string(&path).unwrap_or_else(|_| {
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
            "snapshot {name} differs (rerun with ROCKING_BLESS=1 once reviewed):\n{}",
            diff.join("\n")
        );
    }
}

#[test]
fn mini_study_snapshot() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = study(d, "0.9");
    run(d, &pipe);
    let folder = d.join("out/mini");
    // The capacities, checked against direct `rocking capacity` runs of the same blocks.
    let caps = read_capacities(&[folder.join("capacities.parquet")]).unwrap();
    let mut text = String::from("record_id\tp\teps\teta_c\teta_survived\truns\n");
    for c in &caps {
        let record = d.join("records").join(format!("{}.AT2", c.record_id));
        let (p, e) = (c.p.to_string(), c.eps.to_string());
        let direct = rocking(
            d,
            &[
                "capacity",
                "--record",
                record.to_str().unwrap(),
                "--p",
                &p,
                "--eps",
                &e,
                "--levels",
                "40",
                "--eta-min",
                "0.01",
                "--json",
            ],
        );
        let v: serde_json::Value = serde_json::from_slice(&direct.stdout).unwrap();
        assert_eq!(
            c.eta_c,
            v["eta_c"].as_f64(),
            "{} p = {p} ε = {e}",
            c.record_id
        );
        assert_eq!(c.runs as u64, v["runs"].as_u64().unwrap());
        text.push_str(&format!(
            "{}\t{}\t{}\t{:.11e}\t{:.11e}\t{}\n",
            c.record_id,
            c.p,
            c.eps,
            c.eta_c.unwrap_or(f64::NAN),
            c.eta_survived,
            c.runs
        ));
    }
    snapshot("mini_capacities.tsv", &text);
    snapshot(
        "mini_capacity_fractiles.tsv",
        &dump(
            &CAPACITY_FRACTILES,
            &folder.join("capacity_fractiles.parquet"),
        ),
    );
    snapshot(
        "mini_lognormal.tsv",
        &dump(&LOGNORMAL, &folder.join("lognormal.parquet")),
    );
    snapshot(
        "mini_fractiles_horizontal.tsv",
        &dump(&HORIZONTAL, &folder.join("fractiles_horizontal.parquet")),
    );
}
