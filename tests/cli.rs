//! `rocking simulate` and `rocking capacity` end to end: JSON output, the
//! definitions they promise (η_c overturns, the bracket's top survives),
//! Housner's closed form through the CLI, history files and bad input.

use serde_json::Value;

use crate::util::{at2_text, bundled_records, rocking, root, stderr, tempdir};

fn json(out: &std::process::Output) -> Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

const KOBE: &str = "records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2";

#[test]
fn capacity_is_the_first_overturning_and_its_bracket_survives() {
    for (p, eps, model) in [("2", "0.8", "linearized"), ("5", "0.6", "nonlinear")] {
        let mut args = vec![
            "capacity", "--record", KOBE, "--p", p, "--eps", eps, "--model", model, "--json",
        ];
        if model == "nonlinear" {
            args.extend(["--alpha", "0.2"]);
        }
        let cap = json(&rocking(&root(), &args));
        let eta_c = cap["eta_c"].as_f64().unwrap();
        let top = cap["eta_survived"].as_f64().unwrap();
        assert!(top > eta_c && top - eta_c <= 1e-4, "{cap}");
        assert_eq!(cap["record_id"], "RSN1111_KOBE_NIS000");
        assert!(cap["runs"].as_u64().unwrap() > 5);
        // Every grid level above the first overturning survived: check the
        // definitions through `simulate`.
        let sim = |eta: f64| {
            let eta = eta.to_string();
            let mut a = vec![
                "simulate", "--record", KOBE, "--p", p, "--eps", eps, "--eta", &eta, "--model",
                model, "--json",
            ];
            if model == "nonlinear" {
                a.extend(["--alpha", "0.2"]);
            }
            json(&rocking(&root(), &a))
        };
        assert_eq!(sim(eta_c)["overturned"], true);
        assert_eq!(sim(top)["overturned"], false);
        assert_eq!(
            sim(cap["level_survived"].as_f64().unwrap())["overturned"],
            false
        );
    }
}

#[test]
fn housner_through_the_command_line() {
    // ψ̈ = 1 for the whole 1 s record: overturns iff η < 1 − e^{−p}.
    let dir = tempdir();
    let ones: Vec<&str> = vec![".1000000E+01"; 101];
    std::fs::write(
        dir.path().join("RECT.AT2"),
        at2_text(
            "ACCELERATION TIME SERIES IN UNITS OF G",
            "NPTS=  101, DT=   .0100 SEC",
            &ones,
        ),
    )
    .unwrap();
    let cap = json(&rocking(
        dir.path(),
        &[
            "capacity", "--record", "RECT.AT2", "--p", "2", "--eps", "0.9", "--tol", "1e-11",
            "--json",
        ],
    ));
    let exact = 1.0 - (-2.0f64).exp();
    assert!(
        (cap["eta_c"].as_f64().unwrap() - exact).abs() < 2e-11,
        "{cap}"
    );
}

#[test]
fn history_files_hold_every_event_in_time_order() {
    let dir = tempdir();
    let csv = dir.path().join("h.csv");
    let pq = dir.path().join("h.parquet");
    for (path, every) in [(&csv, "5"), (&pq, "1")] {
        let out = rocking(
            &root(),
            &[
                "simulate",
                "--record",
                KOBE,
                "--p",
                "2",
                "--eps",
                "0.8",
                "--eta",
                "0.3",
                "--history",
                path.to_str().unwrap(),
                "--history-every",
                every,
                "--json",
            ],
        );
        let report = json(&out);
        assert!(path.exists());
        if path == &csv {
            let text = std::fs::read_to_string(path).unwrap();
            let mut lines = text.lines();
            assert_eq!(lines.next(), Some("t_s,x,v_per_s,pivot,psi,event"));
            let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
            let times: Vec<f64> = rows.iter().map(|r| r[0].parse().unwrap()).collect();
            assert!(
                times.windows(2).all(|w| w[1] >= w[0]),
                "time never goes back"
            );
            let impacts = rows
                .iter()
                .filter(|r| r[5] == "impact" || r[5] == "rest")
                .count() as u64;
            assert_eq!(impacts, report["impacts"].as_u64().unwrap());
            assert!(rows.iter().any(|r| r[5] == "uplift"));
            let first_uplift: f64 = rows.iter().find(|r| r[5] == "uplift").unwrap()[0]
                .parse()
                .unwrap();
            assert_eq!(first_uplift, report["first_uplift_s"].as_f64().unwrap());
            // |x| never exceeds θmax/α at the recorded points, and x = 0 at impacts.
            let max = report["theta_max_over_alpha"].as_f64().unwrap();
            for r in &rows {
                let x: f64 = r[1].parse().unwrap();
                assert!(x.abs() <= max);
                if r[5] == "impact" {
                    assert_eq!(x, 0.0);
                }
            }
        }
    }
    let rows: Vec<rocking::tables::history::HistoryRow> = rocking::tables::read(&pq).unwrap();
    assert!(rows.len() > 100);
    assert!(
        rows.windows(2).all(|w| w[1].t_s >= w[0].t_s),
        "time never goes back"
    );
}

#[test]
fn bad_input_is_named() {
    let cases: &[(&str, &str, &[&str], &str)] = &[
        ("2", "1.5", &[], "ε = 1.5"),
        ("-1", "0.8", &[], "p = -1"),
        ("2", "0.8", &["--model", "nonlinear"], "--alpha"),
        ("2", "0.8", &["--overturn", "cap:0.5"], "≥ 1"),
        ("2", "0.8", &["--overturn", "sideways"], "valid: static"),
        ("2", "0.8", &["--overturn", "on-side"], "nonlinear model"),
    ];
    for (p, eps, extra, expected) in cases {
        let mut args = vec![
            "simulate", "--record", KOBE, "--p", p, "--eps", eps, "--eta", "0.3",
        ];
        args.extend_from_slice(extra);
        let out = rocking(&root(), &args);
        assert!(!out.status.success(), "{args:?}");
        assert!(
            stderr(&out).contains(expected),
            "{args:?}: {}",
            stderr(&out)
        );
    }
    let out = rocking(
        &root(),
        &[
            "capacity", "--record", "nope.AT2", "--p", "2", "--eps", "0.8",
        ],
    );
    assert!(!out.status.success() && stderr(&out).contains("nope.AT2"));
    assert!(bundled_records().exists());
}

/// `rocking capacity` parses with its own parser alone (it starts faster);
/// `rocking help capacity` goes through the whole command tree. Both must
/// describe the same command, and refuse a bad flag as the tree does.
#[test]
fn the_quick_capacity_parser_is_the_trees() {
    let quick = rocking(&root(), &["capacity", "--help"]);
    let tree = rocking(&root(), &["help", "capacity"]);
    assert!(quick.status.success() && tree.status.success());
    assert!(String::from_utf8_lossy(&quick.stdout).contains("--record"));
    assert_eq!(quick.stdout, tree.stdout);
    let out = rocking(&root(), &["capacity", "--p", "2", "--bogus"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("unexpected argument '--bogus'"));
    assert!(stderr(&out).contains("Usage: rocking capacity"));
}

/// `rocking bench --sections calls` times `rocking capacity` as a new
/// process per call: in the quick run, the first three far-field records
/// (by name) at p = 2. The row's figures must be ordered (fastest ≤ median
/// ≤ slowest), the slowest must be one of those records, and a record the
/// command refuses must stop the benchmark with the call and its error.
#[test]
fn bench_times_capacity_calls_and_reports_a_failing_call() {
    let dir = tempdir();
    let bench = |records: &std::path::Path, reps: &str| {
        rocking(
            &root(),
            &[
                "bench",
                "--quick",
                "--sections",
                "calls",
                "--reps",
                reps,
                "--records",
                records.to_str().unwrap(),
                "--out-dir",
                dir.path().to_str().unwrap(),
            ],
        )
    };
    let records = bundled_records();
    let out = bench(&records, "3");
    assert!(out.status.success(), "{}", stderr(&out));
    let md = std::fs::read_to_string(dir.path().join("BENCHMARKS.md")).unwrap();
    let row = md
        .lines()
        .find(|l| l.starts_with("| 2 | 3 |"))
        .unwrap_or_else(|| panic!("no row for p = 2 over 3 records:\n{md}"));
    // | p | records | median | mean | fastest | slowest (record) | within 3 ms |
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
