//! `rocking simulate` and `rocking capacity` end to end: JSON output, the
//! definitions they promise (η_c overturns, the bracket's top survives),
//! Housner's closed form through the CLI, history files and bad input.

use serde_json::Value;

use crate::util::{at2_text, bundled_records, rocking, root, stderr, stdout, tempdir};

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
    // Refined that far, the capacity is right, but its certification cannot
    // tell the rectangle's sharp edge from chaos: said, where 1e-4 is not.
    for (tol, warned) in [("1e-11", true), ("1e-4", false)] {
        let out = rocking(
            dir.path(),
            &[
                "capacity", "--record", "RECT.AT2", "--p", "2", "--eps", "0.9", "--tol", tol,
            ],
        );
        let e = stderr(&out);
        assert_eq!(
            e.contains("warning: --tol: a search tolerance of"),
            warned,
            "{tol}: {e}"
        );
    }
    // At the top of the range of p the arithmetic still holds:
    // 1 − e^{−1000} = 1 to the last bit.
    let cap = json(&rocking(
        dir.path(),
        &[
            "capacity", "--record", "RECT.AT2", "--p", "1000", "--eps", "0.9", "--tol", "1e-11",
            "--json",
        ],
    ));
    assert!(
        (cap["eta_c"].as_f64().unwrap() - 1.0).abs() < 2e-11,
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
            assert_eq!(
                lines.next(),
                Some("t_s,x,v_per_s,pivot,psi,slide_m,slide_velocity_m_per_s,event")
            );
            let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
            // Every real column reads as a float, never as an integer (a
            // bare `0` made polars and pandas guess a column of integers).
            for r in &rows {
                for k in [0, 1, 2, 4, 5, 6] {
                    assert!(r[k].parse::<i64>().is_err(), "{}: {r:?}", r[k]);
                }
            }
            let times: Vec<f64> = rows.iter().map(|r| r[0].parse().unwrap()).collect();
            assert!(
                times.windows(2).all(|w| w[1] >= w[0]),
                "time never goes back"
            );
            // One `impact` row per impact counted (the one that settles the
            // block has its own, before the `rest` row).
            let impacts = rows.iter().filter(|r| r[7] == "impact").count() as u64;
            assert_eq!(impacts, report["impacts"].as_u64().unwrap());
            assert!(rows.iter().any(|r| r[7] == "uplift"));
            let first_uplift: f64 = rows.iter().find(|r| r[7] == "uplift").unwrap()[0]
                .parse()
                .unwrap();
            assert_eq!(first_uplift, report["first_uplift_s"].as_f64().unwrap());
            // |x| never exceeds θmax/α at the recorded points, and x = 0 at impacts.
            let max = report["theta_max_over_alpha"].as_f64().unwrap();
            for r in &rows {
                let x: f64 = r[1].parse().unwrap();
                assert!(x.abs() <= max);
                if r[7] == "impact" {
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
        // Once: η_c = 0.0025 "certified" at 1e7, "uplift at 7.11 s" with
        // θmax/α = 0 at 1e10, θmax/α = 0 at α = 1e-308.
        ("1e7", "0.8", &[], "outside [0.01, 1000] 1/s"),
        ("1e10", "0.8", &[], "outside [0.01, 1000] 1/s"),
        (
            "2",
            "0.8",
            &["--model", "nonlinear", "--alpha", "1e-308"],
            "outside [0.001, π/2)",
        ),
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
    // An extreme value is echoed short, as typed: three hundred zeros once
    // stood for 1e-300.
    let base = ["capacity", "--record", KOBE, "--p", "2"];
    let out = rocking(
        &root(),
        &[&base[..], &["--eps", "0.8", "--eta-min", "1e-300"]].concat(),
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("--eta-min 1e-300: give an η in [1e-12, 1)"),
        "{}",
        stderr(&out)
    );
    let out = rocking(
        &root(),
        &[
            "simulate", "--record", KOBE, "--p", "2", "--eps", "1e-300", "--eta", "0.3",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("p = 2 1/s, ε = 1e-300, η = 0.3 ("),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

/// Options that mean something only beside another did nothing without
/// it, and the answer came back as if they had been taken: a pulse's
/// `--td` or `--cycle` beside a record, `--history-every` without a
/// history, text records' `--records-unit` (or column, or ground) without
/// the runs that read them, `--outputs` with the paper's regression, the
/// records' fit (`--method empirical`, `--if-not-lognormal`) without their
/// runs, export's `--years` without the job a hazard brings. Each is
/// refused, naming the option it needs; with it, it runs.
#[test]
fn an_option_that_would_do_nothing_is_refused() {
    let block = ["--p", "2", "--eps", "0.8", "--eta", "0.3"];
    let statue = ["--b", "0.2", "--h", "0.9", "--pga", "0.3"];
    let dir = crate::util::tempdir();
    let out_dir = dir.path().join("x");
    let out_dir = out_dir.to_str().unwrap();
    let nrml_dir = dir.path().join("n");
    let nrml_dir = nrml_dir.to_str().unwrap();
    let cases: &[(&str, &[&str], &[&str], &str)] = &[
        ("simulate", &["--record", KOBE], &["--td", "0.5"], "--pulse"),
        (
            "simulate",
            &["--record", KOBE],
            &["--cycle", "full"],
            "--pulse",
        ),
        ("capacity", &["--record", KOBE], &["--td", "0.5"], "--pulse"),
        (
            "simulate",
            &["--record", KOBE],
            &["--history-every", "5"],
            "--history",
        ),
        ("fragility", &[], &["--records-unit", "g"], "add it"),
        (
            "fragility",
            &[],
            &["--records-column", "2"],
            "--records-unit",
        ),
        (
            "risk",
            &["--hazard", "records/hazard/synthetic-site.csv"],
            &["--records-unit", "m/s2"],
            "--direct",
        ),
        (
            "fragility",
            &[],
            &["--outputs", "elsewhere"],
            "--from PIPELINE.toml",
        ),
        (
            "export",
            &["--format", "pelicun", "--out", out_dir],
            &["--outputs", "elsewhere"],
            "--from",
        ),
        // The records' own fit and its fallback need their runs: the
        // paper's regression gives a lognormal whatever was asked.
        (
            "fragility",
            &[],
            &["--if-not-lognormal", "lognormal"],
            "--if-not-lognormal lognormal: the lognormal check is of the records' own capacities; add --direct",
        ),
        (
            "risk",
            &["--hazard", "records/hazard/synthetic-site.csv"],
            &["--if-not-lognormal", "curve"],
            "add --direct",
        ),
        (
            "fragility",
            &[],
            &["--method", "empirical"],
            "--method empirical: the records' own curve needs their runs; add --direct",
        ),
        (
            "export",
            &["--format", "nrml", "--out", nrml_dir],
            &["--if-not-lognormal", "lognormal"],
            "add --direct",
        ),
        // The job's investigation time goes into a job.ini that only a
        // hazard brings.
        (
            "export",
            &["--format", "nrml", "--out", nrml_dir],
            &["--years", "1"],
            "--years 1: the risk investigation time of OpenQuake's job.ini, written only with --hazard",
        ),
        (
            "export",
            &["--format", "pelicun", "--out", out_dir],
            &["--years", "50"],
            "--format nrml",
        ),
    ];
    for (command, base, extra, needs) in cases {
        let mut args = vec![*command];
        args.extend_from_slice(base);
        let blocks: &[&str] = match *command {
            "simulate" => &block,
            "capacity" => &block[..4],
            "fragility" => &statue,
            _ => &statue[..4],
        };
        args.extend_from_slice(blocks);
        let out = rocking(&root(), &args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        args.extend_from_slice(extra);
        let out = rocking(&root(), &args);
        assert!(!out.status.success(), "{args:?} was taken");
        assert!(stderr(&out).contains(needs), "{args:?}: {}", stderr(&out));
    }
    // With what they need they run.
    let pulse = [
        "simulate", "--pulse", "rect", "--td", "0.5", "--cycle", "full",
    ];
    let out = rocking(&root(), &[&pulse[..], &block[..]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
}

/// A command's summary is its own: clap takes the doc comment above the
/// command's `Args`, and a comment of a shared group (flattened) or of a
/// function written between them became the summary without a word
/// (`submit` read "A pipeline and where its outputs go"). No summary in
/// `rocking --help` is the first line of a shared group's doc.
#[test]
fn every_command_summarises_itself() {
    let args = std::fs::read_to_string(root().join("src/bin/rocking/commands/args.rs")).unwrap();
    let lines: Vec<&str> = args.lines().collect();
    let groups: Vec<String> = lines
        .iter()
        .enumerate()
        .filter(|(_, l)| l.starts_with("pub struct ") && l.contains("Args"))
        .filter_map(|(k, _)| {
            let mut first = None;
            for l in lines[..k].iter().rev() {
                match l.strip_prefix("/// ") {
                    Some(text) => first = Some(text.to_string()),
                    None if l.starts_with("#[") => continue,
                    None => break,
                }
            }
            first
        })
        .collect();
    assert!(groups.len() >= 6, "{groups:?}");
    let help = stdout(&rocking(&root(), &["--help"]));
    let commands: Vec<&str> = help
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| !l.is_empty())
        .filter(|l| l.starts_with("  ") && !l.starts_with("    "))
        .collect();
    assert!(commands.len() >= 20, "{help}");
    for c in commands {
        let summary = c.split_whitespace().skip(1).collect::<Vec<_>>().join(" ");
        for g in &groups {
            let start: String = g.split_whitespace().take(5).collect::<Vec<_>>().join(" ");
            assert!(
                !summary.starts_with(&start),
                "{c}: a shared group's doc ({g})"
            );
        }
    }
}

/// `rocking capacity --help` and `rocking help capacity` describe the same
/// command, and a bad flag is refused with the command's usage.
#[test]
fn capacity_help_and_errors_come_from_the_command_tree() {
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

/// JSON lines of stdout.
fn json_lines(out: &std::process::Output) -> Vec<Value> {
    assert!(out.status.success(), "{}", stderr(out));
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect()
}

/// A batch over records × blocks prints, line by line, exactly what the
/// single calls print for each record and block (the same search and
/// certification, only spread over the cores differently), in record
/// order with the blocks inner; its `--out` table holds the same numbers.
#[test]
fn capacity_batch_equals_the_single_calls() {
    let dir = tempdir();
    let far = root().join("records/fema-p695/far-field");
    let mut files: Vec<_> = std::fs::read_dir(&far)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("at2")))
        .collect();
    files.sort();
    let picked = [&files[0], &files[7], &files[30]];
    let out_table = dir.path().join("caps.parquet");
    let mut args = vec!["capacity", "--record"];
    let picked_str: Vec<String> = picked.iter().map(|p| p.display().to_string()).collect();
    args.extend(picked_str.iter().map(String::as_str));
    args.extend(["--p", "0.5,3", "--eps", "0.7,0.9", "--json", "--out"]);
    args.push(out_table.to_str().unwrap());
    let batch = json_lines(&rocking(&root(), &args));
    assert_eq!(batch.len(), 3 * 4);
    let mut k = 0;
    for file in &picked_str {
        for p in ["0.5", "3"] {
            for eps in ["0.7", "0.9"] {
                let one = json(&rocking(
                    &root(),
                    &[
                        "capacity", "--record", file, "--p", p, "--eps", eps, "--json",
                    ],
                ));
                assert_eq!(batch[k], one, "line {k}: {file} p {p} ε {eps}");
                k += 1;
            }
        }
    }
    let rows: Vec<rocking::tables::sweep::CapacityRow> = rocking::tables::read(&out_table).unwrap();
    assert_eq!(rows.len(), batch.len());
    for (row, line) in rows.iter().zip(&batch) {
        assert_eq!(row.record_id, line["record_id"].as_str().unwrap());
        assert_eq!(row.eta_c, line["eta_c"].as_f64());
        assert_eq!(row.runs as u64, line["runs"].as_u64().unwrap());
    }
    // A folder gives all its records, in path order, one line each.
    let folder = json_lines(&rocking(
        &root(),
        &[
            "capacity",
            "--record",
            far.to_str().unwrap(),
            "--p",
            "2",
            "--eps",
            "0.7",
            "--json",
        ],
    ));
    assert_eq!(folder.len(), files.len());
    let stems: Vec<String> = files
        .iter()
        .map(|f| f.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    let ids: Vec<&str> = folder
        .iter()
        .map(|l| l["record_id"].as_str().unwrap())
        .collect();
    assert_eq!(ids, stems);
}

/// A block given by its dimensions: α = atan(b/h), p = √(3g/(4R)) and
/// Housner's ε by hand, the full sizes twice the half ones, and the PGA at
/// the capacity α/η_c (g); `simulate --pga` runs at η = α/PGA.
#[test]
fn capacity_and_simulate_take_a_physical_block_and_a_pga() {
    let (b, h) = (0.2f64, 1.0f64);
    let half = json(&rocking(
        &root(),
        &[
            "capacity", "--record", KOBE, "--b", "0.2", "--h", "1", "--eps", "housner", "--json",
        ],
    ));
    let full = json(&rocking(
        &root(),
        &[
            "capacity", "--record", KOBE, "--width", "0.4", "--height", "2", "--eps", "housner",
            "--json",
        ],
    ));
    assert_eq!(half, full);
    let alpha = (b / h).atan();
    let p = (3.0 * 9.80665 / (4.0 * (b * b + h * h).sqrt())).sqrt();
    let eps = 1.0 - 1.5 * alpha.sin().powi(2);
    assert!((half["alpha_rad"].as_f64().unwrap() - alpha).abs() < 1e-15);
    assert!((half["p"].as_f64().unwrap() - p).abs() < 1e-12);
    assert!((half["eps"].as_f64().unwrap() - eps).abs() < 1e-15);
    let eta_c = half["eta_c"].as_f64().unwrap();
    assert!((half["pga_c_g"].as_f64().unwrap() - alpha / eta_c).abs() < 1e-15);
    // The PGA a little above the capacity's overturns it, a little below the
    // surviving level's does not: the same verdicts as η.
    let sim = |pga: f64| {
        let pga = pga.to_string();
        json(&rocking(
            &root(),
            &[
                "simulate", "--record", KOBE, "--b", "0.2", "--h", "1", "--eps", "housner",
                "--pga", &pga, "--json",
            ],
        ))
    };
    let at = sim(alpha / eta_c);
    assert!((at["eta"].as_f64().unwrap() - eta_c).abs() <= 1e-15 * eta_c);
    assert_eq!(at["overturned"], true);
    let survived = half["eta_survived"].as_f64().unwrap();
    assert_eq!(sim(alpha / survived)["overturned"], false);
    // Refusals name what is missing.
    let out = rocking(
        &root(),
        &[
            "simulate", "--record", KOBE, "--p", "2", "--eps", "0.7", "--pga", "0.3",
        ],
    );
    assert!(
        stderr(&out).contains("--pga needs the block's slenderness"),
        "{}",
        stderr(&out)
    );
    let out = rocking(
        &root(),
        &["capacity", "--record", KOBE, "--p", "2", "--eps", "housner"],
    );
    assert!(
        stderr(&out).contains("--eps housner needs the block's dimensions"),
        "{}",
        stderr(&out)
    );
    let out = rocking(
        &root(),
        &[
            "capacity", "--record", KOBE, "--b", "0.2,0.3", "--h", "1", "--eps", "0.8",
        ],
    );
    assert!(
        stderr(&out).contains("--b has 2 values and --h 1"),
        "{}",
        stderr(&out)
    );
    let out = rocking(
        &root(),
        &[
            "simulate", "--record", KOBE, "--p", "2,3", "--eps", "0.8", "--eta", "0.5",
        ],
    );
    assert!(stderr(&out).contains("2 blocks given"), "{}", stderr(&out));
}

/// A block of known α run with the linearised model (`capacity`'s and
/// `simulate`'s default) where its error, 0.45·α², exceeds `--auto-tol`
/// is warned of on stderr, JSON or not (the other answers run `auto`,
/// which would run the nonlinear equation there): for b/h = 0.2,
/// α = 0.1974 rad and 0.45·α² = 1.75e-2 > 1e-2; not at b/h = 0.1
/// (4.4e-3), not under `--model auto`, not for p and ε alone.
#[test]
fn the_linearised_model_beyond_its_accepted_error_is_warned_of() {
    let warned = |args: &[&str]| {
        let out = rocking(
            &root(),
            &[&["capacity", "--record", KOBE, "--json"][..], args].concat(),
        );
        assert!(out.status.success(), "{}", stderr(&out));
        stderr(&out)
    };
    let said = |args: &[&str]| warned(args).contains("the linearised model errs by about");
    let text = warned(&["--b", "0.2", "--h", "1", "--eps", "0.8"]);
    assert!(
        text.contains("the linearised model errs by about 1.8e-2 in η_c at α = 0.1974"),
        "{text}"
    );
    assert!(!said(&["--b", "0.1", "--h", "1", "--eps", "0.8"]));
    assert!(!said(&[
        "--b", "0.2", "--h", "1", "--eps", "0.8", "--model", "auto"
    ]));
    assert!(!said(&["--p", "2", "--eps", "0.8"]));
    assert!(said(&["--p", "2", "--alpha", "0.2", "--eps", "0.8"]));
    let loose = [
        "--b",
        "0.2",
        "--h",
        "1",
        "--eps",
        "0.8",
        "--auto-tol",
        "0.02",
    ];
    assert!(!said(&loose));
}

/// `--out` never overwrites a record it reads, and must be a Parquet file.
#[test]
fn capacity_out_refuses_an_input_and_a_wrong_extension() {
    let dir = tempdir();
    let rec = dir.path().join("R.AT2");
    std::fs::copy(root().join(KOBE), &rec).unwrap();
    let before = std::fs::read(&rec).unwrap();
    let r = rec.to_str().unwrap();
    let out = rocking(
        dir.path(),
        &[
            "capacity", "--record", r, "--p", "2", "--eps", "0.7", "--out", r,
        ],
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("give a .parquet file"),
        "{}",
        stderr(&out)
    );
    let link = dir.path().join("link.parquet");
    std::os::unix::fs::symlink(&rec, &link).unwrap();
    let out = rocking(
        dir.path(),
        &[
            "capacity",
            "--record",
            r,
            "--p",
            "2",
            "--eps",
            "0.7",
            "--out",
            link.to_str().unwrap(),
        ],
    );
    assert!(
        stderr(&out).contains("refusing to overwrite an input"),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read(&rec).unwrap(), before);
}

/// An output that is one of the command's inputs is refused before
/// anything is written, and the input keeps its bytes (each of these once
/// replaced the input and exited 0).
#[test]
fn outputs_never_overwrite_inputs() {
    let dir = tempdir();
    let d = dir.path();
    let copy = |from: &str, to: &str| std::fs::copy(root().join(from), d.join(to)).unwrap();
    copy("records/hazard/museum-inventory.csv", "inv.csv");
    copy("records/hazard/synthetic-site.csv", "h.csv");
    copy(KOBE, "X.AT2");
    copy(KOBE, "r.csv");
    std::fs::write(d.join("m.csv"), "record_id,set\nX,far-field\n").unwrap();
    let cases: &[(&[&str], &str, &str)] = &[
        (
            &[
                "risk",
                "--hazard",
                "h.csv",
                "--inventory",
                "inv.csv",
                "--out",
                "inv.csv",
            ],
            "inv.csv",
            "--out inv.csv: give a .parquet file",
        ),
        (
            &[
                "risk", "--hazard", "h.csv", "--b", "0.2", "--h", "1", "--plot", "h.csv",
            ],
            "h.csv",
            "--plot h.csv: give a .svg file",
        ),
        (
            &["ingest", "X.AT2", "--out", "X.AT2"],
            "X.AT2",
            "--out X.AT2: give a .parquet file",
        ),
        (
            &["ingest", "X.AT2", "--manifest", "m.csv", "--out", "m.csv"],
            "m.csv",
            "--out m.csv: give a .parquet file",
        ),
        (
            &[
                "simulate",
                "--record",
                "r.csv",
                "--p",
                "2",
                "--eps",
                "0.9",
                "--eta",
                "0.3",
                "--history",
                "./r.csv",
            ],
            "r.csv",
            "refusing to overwrite an input",
        ),
    ];
    for (args, input, expected) in cases {
        let before = std::fs::read(d.join(input)).unwrap();
        let out = rocking(d, args);
        assert!(!out.status.success(), "{args:?}");
        assert!(
            stderr(&out).contains(expected),
            "{args:?}: {}",
            stderr(&out)
        );
        assert_eq!(std::fs::read(d.join(input)).unwrap(), before, "{args:?}");
    }
    // The table as an input of a second run, reached through a link.
    let ok = rocking(d, &["ingest", "X.AT2", "--out", "r.parquet"]);
    assert!(ok.status.success(), "{}", stderr(&ok));
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(d.join("X.AT2"), d.join("x.parquet")).unwrap();
        let before = std::fs::read(d.join("X.AT2")).unwrap();
        let out = rocking(d, &["ingest", "X.AT2", "--out", "x.parquet"]);
        assert!(
            stderr(&out).contains("refusing to overwrite an input"),
            "{}",
            stderr(&out)
        );
        assert_eq!(std::fs::read(d.join("X.AT2")).unwrap(), before);
    }
}

/// An output inside a study folder is refused before any run, however
/// deep and whether the study is at rest (its fingerprints) or running (its
/// lock, which marks it): `risk --from … --out <study>/fit_coefficients.parquet` once
/// replaced the fit it had just read, and `ingest --out` a running study's
/// records table. So is a folder given for a file, and a place that cannot
/// be written (a read-only folder's refusal came after every run, and the
/// runs were lost).
#[test]
fn outputs_stay_out_of_study_folders_and_are_checked_before_the_runs() {
    let dir = tempdir();
    let d = dir.path();
    let at_rest = d.join("out/quick");
    std::fs::create_dir_all(at_rest.join(".fingerprints")).unwrap();
    std::fs::write(at_rest.join("capacities.parquet"), "the sweep").unwrap();
    std::fs::create_dir_all(d.join("folder.parquet")).unwrap();
    let kobe = root().join(KOBE);
    let kobe = kobe.to_str().unwrap();
    let capacity = |out: &str| {
        let o = rocking(
            d,
            &[
                "capacity", "--record", kobe, "--p", "2", "--eps", "0.7", "--out", out,
            ],
        );
        assert!(!o.status.success(), "{out}");
        stderr(&o)
    };
    for (out, says) in [
        ("out/quick/capacities.parquet", "inside the study folder"),
        ("out/quick/figures/new/c.parquet", "inside the study folder"),
        ("folder.parquet", "it is a folder"),
        #[cfg(target_os = "linux")]
        ("/proc/c.parquet", "cannot write in /proc"),
    ] {
        let e = capacity(out);
        assert!(
            e.contains(&format!("--out {out}: ")) && e.contains(says),
            "{out}: {e}"
        );
    }
    assert_eq!(
        std::fs::read(at_rest.join("capacities.parquet")).unwrap(),
        b"the sweep"
    );
    let history = rocking(
        d,
        &[
            "simulate",
            "--record",
            kobe,
            "--p",
            "2",
            "--eps",
            "0.7",
            "--eta",
            "0.3",
            "--history",
            "out/quick/h.csv",
        ],
    );
    assert!(
        stderr(&history).contains("inside the study folder"),
        "{}",
        stderr(&history)
    );
    let export = rocking(
        d,
        &[
            "export",
            "--format",
            "pelicun",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--out",
            "out/quick/x",
        ],
    );
    assert!(
        stderr(&export).contains("inside the study folder"),
        "{}",
        stderr(&export)
    );
    let mut left: Vec<String> = std::fs::read_dir(&at_rest)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, [".fingerprints", "capacities.parquet"]);
    // A study a run made (its folder is marked when the run takes its lock).
    let pipeline = root().join("pipelines/quick.toml");
    let run = rocking(
        d,
        &[
            "run",
            pipeline.to_str().unwrap(),
            "--to",
            "ingest",
            "--outputs",
            "studies",
        ],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let table = d.join("studies/quick/records.parquet");
    let before = std::fs::read(&table).unwrap();
    let ingest = rocking(
        d,
        &["ingest", kobe, "--out", "studies/quick/records.parquet"],
    );
    assert!(
        stderr(&ingest).contains("inside the study folder"),
        "{}",
        stderr(&ingest)
    );
    assert_eq!(std::fs::read(&table).unwrap(), before);
}

/// A history shows the fate its run reports when the block overturns after
/// the record has ended (it once stopped at `record_end`, x = 0.51, while
/// the run said "overturned at 1.48 s"). After the record the linearised
/// block rocks freely about pivot 1: x(τ) = 1 + (x₀ − 1) cosh pτ + (v₀/p) sinh pτ.
#[test]
fn a_history_follows_an_overturn_after_the_record() {
    let dir = tempdir();
    let csv = dir.path().join("h.csv");
    let args = |criterion: &'static str| {
        let mut a = vec![
            "simulate",
            "--pulse",
            "rect",
            "--cycle",
            "half",
            "--p",
            "0.5",
            "--eps",
            "0.9",
            "--eta",
            "0.2",
            "--json",
            "--overturn",
            criterion,
            "--history",
        ];
        a.push(csv.to_str().unwrap());
        a
    };
    let read_rows = || -> Vec<(f64, f64, String)> {
        let text = std::fs::read_to_string(&csv).unwrap();
        text.lines()
            .skip(1)
            .map(|l| {
                let r: Vec<&str> = l.split(',').collect();
                (
                    r[0].parse().unwrap(),
                    r[1].parse().unwrap(),
                    r[7].to_string(),
                )
            })
            .collect()
    };
    let report = json(&rocking(&root(), &args("static")));
    assert_eq!(report["overturn_after_record"], true);
    let t_over = report["overturn_time_s"].as_f64().unwrap();
    let rows = read_rows();
    let end = rows.iter().position(|r| r.2 == "record_end").unwrap();
    let last = rows.last().unwrap();
    assert_eq!((last.0, last.2.as_str()), (t_over, "overturn"), "{last:?}");
    assert!(
        (last.1 - 1.0).abs() < 1e-12,
        "at the static limit: {last:?}"
    );
    assert!(rows.len() - end > 20, "the free motion is sampled");
    // Against the closed form from the record's end (x₀, v₀ from the file).
    let text = std::fs::read_to_string(&csv).unwrap();
    let at_end: Vec<f64> = text
        .lines()
        .nth(end + 1)
        .unwrap()
        .split(',')
        .take(3)
        .map(|c| c.parse().unwrap())
        .collect();
    let (t0, x0, v0, p) = (at_end[0], at_end[1], at_end[2], 0.5f64);
    for (t, x, _) in &rows[end + 1..] {
        let tau = t - t0;
        let exact = 1.0 + (x0 - 1.0) * (p * tau).cosh() + v0 / p * (p * tau).sinh();
        assert!((x - exact).abs() < 1e-9, "t = {t}: {x} vs {exact}");
    }
    // Under `escape` the fate is decided at the record's end, and shown there.
    let report = json(&rocking(&root(), &args("escape")));
    let t_over = report["overturn_time_s"].as_f64().unwrap();
    let rows = read_rows();
    let last = rows.last().unwrap();
    assert_eq!((last.0, last.2.as_str()), (t_over, "overturn"), "{last:?}");
}

/// Two records of one file stem in two folders are two records of one id:
/// `capacity --record DIR` refuses them, naming both, as `ingest` does.
#[test]
fn capacity_refuses_two_records_of_one_stem() {
    let dir = tempdir();
    let kobe = bundled_records().join("far-field/RSN1111_KOBE_NIS000.AT2");
    for sub in ["a", "b"] {
        std::fs::create_dir(dir.path().join(sub)).unwrap();
        std::fs::copy(&kobe, dir.path().join(sub).join("RSN1111_KOBE_NIS000.AT2")).unwrap();
    }
    let out = rocking(
        &root(),
        &[
            "capacity",
            "--record",
            dir.path().to_str().unwrap(),
            "--p",
            "2",
            "--eps",
            "0.7",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert!(
        err.contains("two records of one id `RSN1111_KOBE_NIS000`")
            && err.contains("/a/")
            && err.contains("/b/"),
        "{err}"
    );
}

/// A reader that stops early (`rocking risk … | head -1`) closed the pipe
/// and the next print panicked ("failed printing to stdout: Broken pipe",
/// exit 101, a backtrace). The command now ends as `cat` does, by the
/// signal, and says nothing: here its pipe is closed before it prints.
#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_the_command_quietly() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};
    for args in [
        &[
            "risk",
            "--hazard",
            "records/hazard/synthetic-openquake.csv",
            "--b",
            "0.2",
            "--h",
            "1",
        ][..],
        &["ims", "--record", KOBE],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_rocking"))
            .args(args)
            .current_dir(root())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(
            out.status.signal(),
            Some(13),
            "{args:?}: {:?} {err}",
            out.status
        );
    }
}

/// A refused number is echoed as given, in exponent form where the plain
/// one runs to hundreds of digits (`1e300`, not 301 of them): each message
/// stays a line.
#[test]
fn refused_extreme_numbers_are_echoed_short() {
    let dir = crate::util::tempdir();
    let kobe = crate::util::bundled_records().join("far-field/RSN1111_KOBE_NIS000.AT2");
    let base = [
        "capacity",
        "--record",
        kobe.to_str().unwrap(),
        "--p",
        "2",
        "--eps",
        "0.7",
        "--model",
        "nonlinear",
    ];
    for (extra, echo) in [
        (&["--alpha", "1e-300"][..], "α = 1e-300 rad"),
        (&["--alpha", "0.2", "--floor", "0.5,1e300,1"], "ζ = 1e300"),
        (
            &["--alpha", "0.2", "--overturn", "cap:1e300"],
            "c·α = 2e299 rad",
        ),
        (&["--alpha", "0.2", "--mu", "1e300"], "μ = 1e300"),
        (
            &["--alpha", "0.2", "--floor", "1e300,0.05,1"],
            "T = 1e300 s",
        ),
    ] {
        let out = crate::util::rocking(dir.path(), &[&base[..], extra].concat());
        assert!(!out.status.success());
        let e = crate::util::stderr(&out);
        assert!(e.contains(echo), "{extra:?}: {e}");
        assert!(e.lines().all(|l| l.chars().count() < 400), "{extra:?}: {e}");
    }
}
