//! `rocking sweep`: shipped pipelines load, bad pipelines fail before any run,
//! capacities equal direct `rocking capacity` calls, output is byte-identical
//! at 1 and 2 threads, shards merge to the unsharded result, and a sweep
//! killed or interrupted mid-way resumes to the same tables.

use std::fs;
use std::path::Path;

use rocking::ida::{ImGrid, Spacing};
use rocking::physics::{simulate, Excitation, Model, RunSpec};
use rocking::pipeline::{self, StudyKind};
use rocking::stages::sweep::{
    read_capacities, read_ida, CASE_DELAY_ENV, FAULT_ENV, HOLD_ENV, INTERRUPT_ENV,
};

use crate::util::{
    direct_capacity, plain_at2_values, rocking, root, stderr, stdout, tempdir, write_at2,
    write_pipeline, TempDir,
};

#[test]
fn every_shipped_pipeline_loads() {
    let mut n = 0;
    for entry in fs::read_dir(root().join("pipelines")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let text = fs::read_to_string(&path).unwrap();
            let plan = pipeline::load_str(&text, &path).unwrap_or_else(|e| panic!("{e}"));
            match &plan.study {
                StudyKind::PulseMap(pp) => assert!(!pp.f.is_empty() && !pp.eta.is_empty()),
                StudyKind::Records(r) => assert!(!r.blocks.is_empty(), "{}", path.display()),
            }
            n += 1;
            if plan.name == "paper" {
                // The paper's grid: 12 p log-spaced 0.33–10, ε = 0.50, 0.55, …, 0.95, 200 levels.
                assert_eq!(plan.blocks().len(), 120);
                let ps: Vec<f64> = plan.blocks().iter().step_by(10).map(|b| b.p).collect();
                assert_eq!((ps[0], ps[11]), (0.33, 10.0));
                let eps: Vec<f64> = plan.blocks()[..10].iter().map(|b| b.eps).collect();
                for (k, e) in eps.iter().enumerate() {
                    assert!((e - (0.5 + 0.05 * k as f64)).abs() < 1e-12);
                }
                let rs = plan.records_study().unwrap();
                assert_eq!(rs.grid.count, 200);
                assert_eq!(rs.sets, ["far-field"]);
            }
        }
    }
    assert!(n >= 3);
}

const SMALL: &str = r#"ids = ["RSN1111_KOBE_NIS000", "RSN953_NORTHR_MUL009"]
[blocks]
p = [1.5, 4.0]
eps = [0.8]
[im]
count = 60
eta_min = 0.01
tol = 1e-4
trace_past_first = true
"#;

fn sweep(dir: &TempDir, pipeline: &Path, extra: &[&str]) -> std::process::Output {
    let out_dir = dir.path().join("out");
    let mut args = vec![
        "sweep",
        pipeline.to_str().unwrap(),
        "--outputs",
        out_dir.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    rocking(dir.path(), &args)
}

#[test]
fn capacities_equal_direct_capacity_calls_and_resurrections_are_counted() {
    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "small", SMALL);
    let out = sweep(&dir, &pipe, &[]);
    assert!(out.status.success(), "{}", stderr(&out));
    let caps = read_capacities(&dir.path().join("out/small")).unwrap();
    assert_eq!(caps.len(), 4);
    // Records sorted by id, then the blocks in plan order.
    let order: Vec<(&str, f64)> = caps.iter().map(|c| (c.record_id.as_str(), c.p)).collect();
    assert_eq!(
        order,
        [
            ("RSN1111_KOBE_NIS000", 1.5),
            ("RSN1111_KOBE_NIS000", 4.0),
            ("RSN953_NORTHR_MUL009", 1.5),
            ("RSN953_NORTHR_MUL009", 4.0)
        ]
    );
    for c in &caps {
        let record = format!("records/fema-p695/far-field/{}.AT2", c.record_id);
        let v = direct_capacity(&root(), &record, c.p, 0.8, 60);
        assert_eq!(c.eta_c, v["eta_c"].as_f64(), "{}", c.record_id);
        assert_eq!(c.eta_survived, v["eta_survived"].as_f64().unwrap());
        assert_eq!(c.level_survived, v["level_survived"].as_f64().unwrap());

        // Resurrections: levels stronger than the first overturning that
        // survive, counted here by running them one by one.
        let at2 = rocking::at2::parse(&fs::read(root().join(&record)).unwrap()).unwrap();
        let exc = Excitation::new(&at2.accel_g, at2.dt_s).unwrap();
        let grid = ImGrid {
            eta_max: 1.0,
            eta_min: 0.01,
            count: 60,
            spacing: Spacing::Log,
        };
        let first = c.level_overturned.unwrap();
        let survived = grid
            .levels()
            .unwrap()
            .into_iter()
            .filter(|&eta| eta < first)
            .filter(|&eta| {
                !simulate(&exc, &RunSpec::new(c.p, 0.8, eta, Model::LINEARIZED))
                    .unwrap()
                    .overturned()
            })
            .count();
        assert_eq!(
            c.resurrections,
            Some(survived as i64),
            "{} p = {}",
            c.record_id,
            c.p
        );
    }
    // IDA points: EDP is +∞ exactly where the run overturned, and every run of a case is there.
    let ida = read_ida(&dir.path().join("out/small")).unwrap();
    for c in &caps {
        let runs: Vec<_> = ida.iter().filter(|r| r.case_id == c.case_id).collect();
        assert_eq!(runs.len() as i64, c.runs);
        for r in runs {
            assert_eq!(r.edp.is_infinite(), r.overturned);
            assert_eq!(r.pga_scale, 1.0 / r.eta);
        }
    }
}

/// A pipeline of 3 records × 24 blocks = 72 cases: three chunks of 32.
const THREE_CHUNKS: &str = r#"ids = ["RSN1111_KOBE_NIS000", "RSN953_NORTHR_MUL009", "RSN1633_MANJIL_ABBAR--L"]
[blocks]
p = { from = 0.5, to = 8.0, count = 6, spacing = "log" }
eps = [0.6, 0.7, 0.8, 0.9]
[im]
count = 40
eta_min = 0.01
"#;

#[test]
fn output_is_byte_identical_at_one_and_two_threads() {
    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "t", THREE_CHUNKS);
    let mut files = Vec::new();
    for threads in ["1", "2"] {
        let out_dir = dir.path().join(format!("out{threads}"));
        let out = rocking(
            dir.path(),
            &[
                "sweep",
                pipe.to_str().unwrap(),
                "--outputs",
                out_dir.to_str().unwrap(),
                "--threads",
                threads,
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        files.push((
            fs::read(out_dir.join("t/ida_points.parquet")).unwrap(),
            fs::read(out_dir.join("t/capacities.parquet")).unwrap(),
        ));
    }
    assert!(files[0].0 == files[1].0, "ida_points differ");
    assert!(files[0].1 == files[1].1, "capacities differ");
}

#[test]
fn three_shards_merge_to_the_unsharded_result() {
    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "s", THREE_CHUNKS);
    let whole = sweep(&dir, &pipe, &[]);
    assert!(whole.status.success(), "{}", stderr(&whole));
    let expected_caps = read_capacities(&dir.path().join("out/s")).unwrap();
    let expected_ida = read_ida(&dir.path().join("out/s")).unwrap();

    let sharded = tempdir();
    let pipe = write_pipeline(sharded.path(), "s", THREE_CHUNKS);
    let folder = sharded.path().join("out/s");
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let out = sweep(&sharded, &pipe, &["--shard", &shard]);
        assert!(out.status.success(), "{}", stderr(&out));
        if k < 3 {
            // An incomplete set of shards is refused, naming what is missing.
            let e = read_capacities(&folder).unwrap_err().to_string();
            assert!(e.contains("missing") && e.contains("/3"), "{e}");
        }
    }
    assert_eq!(read_capacities(&folder).unwrap(), expected_caps);
    assert_eq!(read_ida(&folder).unwrap(), expected_ida);
}

#[test]
fn a_killed_sweep_resumes_to_the_same_tables() {
    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "r", THREE_CHUNKS);
    let reference = tempdir();
    let ref_pipe = write_pipeline(reference.path(), "r", THREE_CHUNKS);
    assert!(sweep(&reference, &ref_pipe, &[]).status.success());

    // Crash (abort) right after the first chunk is saved (each chunk saved
    // as it completes).
    let crashed = crash(&dir, &pipe, &[(FAULT_ENV, "1"), (HOLD_ENV, "0")]);
    assert!(!crashed.status.success());
    let folder = dir.path().join("out/r");
    assert!(
        !folder.join("capacities.parquet").exists(),
        "no final table after a crash"
    );
    assert_eq!(
        part_files(&folder),
        ["cap-000000.parquet", "ida-000000.parquet"],
        "one whole chunk (two files), nothing half-written"
    );
    // The final tables are written as the chunks come in, to temporary
    // files that only a completed sweep renames into place.
    assert_eq!(
        temporaries(&folder).len(),
        2,
        "the killed run's unfinished final tables: {:?}",
        temporaries(&folder)
    );

    let resumed = sweep(&dir, &pipe, &[]);
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    let text = String::from_utf8_lossy(&resumed.stdout);
    assert!(text.contains("(32 resumed from an earlier run)"), "{text}");
    assert_same_tables(&folder, &reference.path().join("out/r"));
    assert!(
        !folder.join("parts").exists(),
        "parts are cleaned up once the tables are in place"
    );
    assert!(
        temporaries(&folder).is_empty(),
        "the killed run's temporaries are removed: {:?}",
        temporaries(&folder)
    );
}

/// `rocking sweep` of `pipe` into `dir/out`, with `env` set.
fn crash(dir: &TempDir, pipe: &Path, env: &[(&str, &str)]) -> std::process::Output {
    let out_dir = dir.path().join("out");
    std::process::Command::new(env!("CARGO_BIN_EXE_rocking"))
        .args([
            "sweep",
            pipe.to_str().unwrap(),
            "--outputs",
            out_dir.to_str().unwrap(),
        ])
        .envs(env.iter().copied())
        .current_dir(dir.path())
        .output()
        .unwrap()
}

/// Both sweep tables in `folder` equal those in `reference` to the byte.
fn assert_same_tables(folder: &Path, reference: &Path) {
    for table in ["ida_points.parquet", "capacities.parquet"] {
        let a = fs::read(folder.join(table)).unwrap();
        let b = fs::read(reference.join(table)).unwrap();
        assert!(a == b, "{table} differs after resuming");
    }
}

/// The names in `dir` that `keep` accepts, sorted (none if there is no
/// such folder).
fn file_names(dir: &Path, keep: impl Fn(&str) -> bool) -> Vec<String> {
    let mut names: Vec<String> = match fs::read_dir(dir) {
        Ok(entries) => entries
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| keep(n))
            .collect(),
        Err(_) => Vec::new(),
    };
    names.sort();
    names
}

/// The files under `folder/parts`.
fn part_files(folder: &Path) -> Vec<String> {
    file_names(&folder.join("parts"), |_| true)
}

/// A sweep holds the chunks it completes in its first seconds instead of
/// saving them as parts (a short sweep is quicker to redo than to
/// checkpoint), then saves the held ones, in order, with the chunk that
/// makes saving due. A crash loses the held chunks only, and the rerun
/// gives the uninterrupted sweep's tables to the byte either way.
#[test]
fn held_chunks_are_saved_in_order_once_due_and_a_crash_loses_only_them() {
    let reference = tempdir();
    let ref_pipe = write_pipeline(reference.path(), "r", THREE_CHUNKS);
    assert!(sweep(&reference, &ref_pipe, &[]).status.success());
    // Crashed once two chunks are complete: by default (this sweep takes a
    // fraction of a second, against `CHECKPOINT_AFTER`'s 10 s) and with two
    // chunks held, nothing is saved yet and the rerun does it all; with one
    // held, it is saved with the second, both whole.
    for (hold, saved, resumed) in [
        (None, vec![], 0),
        (Some("2"), vec![], 0),
        (Some("1"), vec![0, 1], 64),
    ] {
        let dir = tempdir();
        let pipe = write_pipeline(dir.path(), "r", THREE_CHUNKS);
        let mut env = vec![(FAULT_ENV, "2")];
        env.extend(hold.map(|h| (HOLD_ENV, h)));
        let crashed = crash(&dir, &pipe, &env);
        assert!(!crashed.status.success(), "{hold:?}");
        let folder = dir.path().join("out/r");
        let expected: Vec<String> = ["cap", "ida"]
            .iter()
            .flat_map(|k| saved.iter().map(move |c| format!("{k}-{c:06}.parquet")))
            .collect();
        assert_eq!(part_files(&folder), expected, "{hold:?}");
        let rerun = sweep(&dir, &pipe, &[]);
        assert!(rerun.status.success(), "{}", stderr(&rerun));
        let text = String::from_utf8_lossy(&rerun.stdout);
        assert!(
            text.contains(&format!("({resumed} resumed from an earlier run)")),
            "{hold:?}: {text}"
        );
        assert_same_tables(&folder, &reference.path().join("out/r"));
    }
}

/// The hidden temporary files in `dir` (`.NAME.tmp-PID`).
fn temporaries(dir: &Path) -> Vec<String> {
    file_names(dir, |n| n.starts_with('.') && n.contains(".tmp-"))
}

#[test]
fn a_killed_sweeps_temporary_tables_go_with_the_tables_they_would_have_replaced() {
    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "k", THREE_CHUNKS);
    let folder = dir.path().join("out/k");
    let killed = |extra: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rocking"))
            .args(["sweep", pipe.to_str().unwrap(), "--outputs", "out"])
            .args(extra)
            .env(FAULT_ENV, "1")
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(!out.status.success());
    };
    // An unsharded run killed after its first chunk leaves its two tables
    // half-written under hidden names; a sharded sweep supersedes them.
    killed(&[]);
    let left = temporaries(&folder);
    assert_eq!(left.len(), 2, "{left:?}");
    assert!(
        left.iter()
            .all(|n| n.starts_with(".ida_points.parquet.tmp-")
                || n.starts_with(".capacities.parquet.tmp-")),
        "{left:?}"
    );
    let shard = sweep(&dir, &pipe, &["--shard", "1/2"]);
    assert!(shard.status.success(), "{}", stderr(&shard));
    assert_eq!(temporaries(&folder), Vec::<String>::new());
    // A shard killed the same way: the next unsharded sweep supersedes its
    // temporaries with the shard tables.
    killed(&["--shard", "2/2"]);
    let left = temporaries(&folder);
    assert_eq!(left.len(), 2, "{left:?}");
    assert!(
        left.iter()
            .all(|n| n.contains(".shard-2-of-2.parquet.tmp-")),
        "{left:?}"
    );
    let whole = sweep(&dir, &pipe, &["--force"]);
    assert!(whole.status.success(), "{}", stderr(&whole));
    assert_eq!(temporaries(&folder), Vec::<String>::new());
    assert!(folder.join("capacities.parquet").exists());
    assert!(!folder.join("capacities.shard-1-of-2.parquet").exists());
}

#[test]
fn bad_pipelines_fail_before_any_run_naming_the_key() {
    let dir = tempdir();
    let grid = "[blocks]\np = [1.0]\neps = [0.8]\n";
    let cases: Vec<(String, &str)> = vec![
        (
            format!("{grid}[im]\ncount = 10\nsteps = 3\n"),
            "unknown field `steps`",
        ),
        (
            "[blocks]\np = [1.0]\neps = [0.0]\n".into(),
            "ε must be in (0, 1]",
        ),
        (
            "[blocks]\np = [-2.0]\neps = [0.8]\n".into(),
            "`blocks.p`: p = -2 1/s is outside [0.01, 1000] 1/s",
        ),
        (
            // Once accepted: the report stage then spun for minutes.
            "[blocks]\np = [0.5, 1.0, 1e300]\neps = [0.8]\n".into(),
            "`blocks.p`: p = 1e300 1/s is outside [0.01, 1000] 1/s",
        ),
        (
            format!("sets = [\"mars\"]\n{grid}"),
            "available: far-field, near-field-no-pulse, near-field-pulse",
        ),
        (
            format!("ids = [\"NOPE\"]\n{grid}"),
            "bad5.toml: `records.ids` names NOPE, which no file of `records.at2` bears",
        ),
    ];
    for (i, (body, expected)) in cases.iter().enumerate() {
        let name = format!("bad{i}");
        let pipe = write_pipeline(dir.path(), &name, body);
        let out = sweep(&dir, &pipe, &[]);
        assert!(!out.status.success(), "{body}");
        let err = stderr(&out);
        assert!(err.contains(expected), "expected `{expected}` in: {err}");
        assert!(!dir
            .path()
            .join("out")
            .join(&name)
            .join("capacities.parquet")
            .exists());
    }
    // A records table that does not exist.
    let pipe = dir.path().join("missing.toml");
    fs::write(
        &pipe,
        format!("[records]\ntable = \"nowhere/records.parquet\"\n{grid}"),
    )
    .unwrap();
    let out = sweep(&dir, &pipe, &[]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("nowhere/records.parquet") && stderr(&out).contains("rocking ingest"),
        "{}",
        stderr(&out)
    );
    // The name of an unknown key comes with the file.
    let out = sweep(&dir, &dir.path().join("bad0.toml"), &[]);
    assert!(stderr(&out).contains("bad0.toml"), "{}", stderr(&out));
}

/// What the command prints when Ctrl-C stopped it.
const INTERRUPTED: &str = "interrupted (Ctrl-C): every file written is whole";

/// A sweep stopped as Ctrl-C stops it, once its first chunk is complete
/// and before the 10 s after which chunks are saved as they complete,
/// keeps that chunk as parts (it was lost before: the rerun started
/// over), says it was interrupted with the shell's code for SIGINT, and
/// the rerun resumes to the uninterrupted sweep's tables, to the byte.
#[test]
fn an_interrupted_sweep_keeps_its_completed_chunks_and_resumes_to_the_same_tables() {
    let reference = tempdir();
    let ref_pipe = write_pipeline(reference.path(), "i", THREE_CHUNKS);
    assert!(sweep(&reference, &ref_pipe, &[]).status.success());

    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "i", THREE_CHUNKS);
    let stopped = std::process::Command::new(env!("CARGO_BIN_EXE_rocking"))
        .args([
            "sweep",
            pipe.to_str().unwrap(),
            "--outputs",
            "out",
            "--threads",
            "2",
        ])
        .env(INTERRUPT_ENV, "1")
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(stopped.status.code(), Some(130), "{}", stderr(&stopped));
    assert!(
        stderr(&stopped).contains(INTERRUPTED),
        "{}",
        stderr(&stopped)
    );
    let folder = dir.path().join("out/i");
    assert!(!folder.join("capacities.parquet").exists());
    // Two workers are on the second chunk's first cases when the first
    // completes: it alone is whole.
    assert_eq!(
        part_files(&folder),
        ["cap-000000.parquet", "ida-000000.parquet"]
    );
    let resumed = sweep(&dir, &pipe, &[]);
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    let text = String::from_utf8_lossy(&resumed.stdout);
    assert!(text.contains("(32 resumed from an earlier run)"), "{text}");
    assert_same_tables(&folder, &reference.path().join("out/i"));
    assert!(
        temporaries(&folder).is_empty(),
        "{:?}",
        temporaries(&folder)
    );
}

/// 10 records × 64 blocks = 640 cases: twenty chunks.
const TWENTY_CHUNKS: &str = r#"ids = ["RSN1111_KOBE_NIS000", "RSN953_NORTHR_MUL009", "RSN1633_MANJIL_ABBAR--L", "RSN1158_KOCAELI_DZC180", "RSN1148_KOCAELI_ARC000", "RSN169_IMPVALL_H-DLT262", "RSN174_IMPVALL_H-E11140", "RSN1244_CHICHI_CHY101-E", "RSN1485_CHICHI_TCU045-E", "RSN721_SUPERST_B-ICC000"]
[blocks]
p = { from = 0.5, to = 8.0, count = 8, spacing = "log" }
eps = { from = 0.6, to = 0.95, count = 8 }
[im]
count = 100
eta_min = 0.005
"#;

/// Ctrl-C itself (SIGINT from outside, as a terminal sends it) reaches the
/// runs: the sweep stops early, says so, ends by SIGINT (the shell's 130),
/// and resumes from what it saved to the uninterrupted tables.
#[test]
#[cfg(unix)]
fn ctrl_c_stops_a_sweep_that_then_resumes_to_the_same_tables() {
    signal_stops_a_sweep_that_then_resumes(libc::SIGINT, "-INT", INTERRUPTED);
}

/// SIGTERM, what Slurm sends at a time limit, on preemption and on
/// `scancel` (the generated script requeues a preempted task), and SIGHUP,
/// a closed terminal: the same stop, so that the next run resumes. (After
/// SIGHUP only the output that went to a terminal goes to /dev/null; the
/// pipes here keep theirs.)
#[test]
#[cfg(unix)]
fn sigterm_and_sighup_stop_a_sweep_as_ctrl_c_does() {
    signal_stops_a_sweep_that_then_resumes(
        libc::SIGTERM,
        "-TERM",
        "interrupted (SIGTERM): every file written is whole",
    );
    signal_stops_a_sweep_that_then_resumes(
        libc::SIGHUP,
        "-HUP",
        "interrupted (SIGHUP): every file written is whole",
    );
}

#[cfg(unix)]
fn signal_stops_a_sweep_that_then_resumes(signal: libc::c_int, kill_flag: &str, says: &str) {
    let reference = tempdir();
    let ref_pipe = write_pipeline(reference.path(), "c", TWENTY_CHUNKS);
    assert!(sweep(&reference, &ref_pipe, &[]).status.success());

    let dir = tempdir();
    let pipe = write_pipeline(dir.path(), "c", TWENTY_CHUNKS);
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_rocking"));
    // A SIGINT the tests inherit as ignored (a background job of a script)
    // would stay ignored in the command, as it should: the child starts
    // with the default action, as a terminal's foreground job does.
    // SAFETY: signal(2) is async-signal-safe, as pre_exec requires.
    unsafe {
        use std::os::unix::process::CommandExt;
        command.pre_exec(move || {
            libc::signal(signal, libc::SIG_DFL);
            Ok(())
        });
    }
    let child = command
        .args(["sweep", pipe.to_str().unwrap(), "--outputs", "out"])
        .env(HOLD_ENV, "0")
        // 640 cases 10 ms apart on each worker: 3 s at least, time for
        // the signal to find the sweep running on a loaded machine.
        .env(CASE_DELAY_ENV, "10")
        .current_dir(dir.path())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let folder = dir.path().join("out/c");
    let first = folder.join("parts/cap-000000.parquet");
    let t0 = std::time::Instant::now();
    while !first.exists() && t0.elapsed() < std::time::Duration::from_secs(60) {
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let kill = std::process::Command::new("kill")
        .args([kill_flag, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let stopped = child.wait_with_output().unwrap();
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(
        stopped.status.signal(),
        Some(signal),
        "{:?}: {}",
        stopped.status,
        stderr(&stopped)
    );
    assert!(stderr(&stopped).contains(says), "{}", stderr(&stopped));
    assert!(!folder.join("capacities.parquet").exists());
    let kept = part_files(&folder).len() / 2;
    assert!((1..20).contains(&kept), "{kept} chunks saved");
    // `status` says what the interrupted run saved (it said "never run").
    let status = rocking(
        dir.path(),
        &["status", pipe.to_str().unwrap(), "--outputs", "out"],
    );
    let said = format!("never finished here: an interrupted run saved {kept} chunk(s)");
    assert!(
        stdout(&status).contains(&said),
        "{said}: {}",
        stdout(&status)
    );

    let resumed = sweep(&dir, &pipe, &[]);
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    let text = String::from_utf8_lossy(&resumed.stdout);
    let note = format!("({} resumed from an earlier run)", kept * 32);
    assert!(text.contains(&note), "{note}: {text}");
    assert_same_tables(&folder, &reference.path().join("out/c"));
}

/// Work that runs no simulation does not hear the stop (here `ims` of a
/// long record, whose mean period is a DFT over every bin): the watch ends
/// it by the signal five seconds after it, saying so, where SIGTERM once
/// waited for the work to finish and then exited 0.
#[test]
#[cfg(unix)]
fn a_command_deaf_to_the_stop_is_ended_by_the_signal_after_a_grace() {
    use std::os::unix::process::{CommandExt, ExitStatusExt};
    let dir = tempdir();
    // A pair of 1,000,000 samples each: its RotD (15 periods × 180 angles,
    // linear in the count) takes some 27 s on the project's machine, far
    // beyond the grace on any machine, and the oscillators do not listen
    // for the stop.
    let (record, pair) = (dir.path().join("long.AT2"), dir.path().join("long-90.AT2"));
    for (path, phase) in [(&record, 0.0), (&pair, 1.0)] {
        let accel: Vec<f64> = (0..1_000_000)
            .map(|k| 0.1 * (k as f64 * 0.01 + phase).sin())
            .collect();
        crate::util::write_at2(path, &accel, 0.005);
    }
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_rocking"));
    // SAFETY: signal(2) is async-signal-safe, as pre_exec requires.
    unsafe {
        command.pre_exec(|| {
            libc::signal(libc::SIGTERM, libc::SIG_DFL);
            Ok(())
        });
    }
    let child = command
        .args(["ims", "--record", record.to_str().unwrap()])
        .args(["--pair", pair.to_str().unwrap()])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(500));
    let t0 = std::time::Instant::now();
    let kill = std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let stopped = child.wait_with_output().unwrap();
    let waited = t0.elapsed().as_secs_f64();
    assert_eq!(
        stopped.status.signal(),
        Some(libc::SIGTERM),
        "{}",
        stderr(&stopped)
    );
    assert!(
        stderr(&stopped)
            .contains("interrupted (SIGTERM): the work under way did not stop within 5 s"),
        "{}",
        stderr(&stopped)
    );
    // The grace, and no more than a loaded machine's delay past it.
    assert!((4.9..30.0).contains(&waited), "{waited} s");
}

/// A rerun after records were added, removed and edited computes only the
/// changed records' cases, in the sweep and in the convergence stage, and
/// takes the rest from the previous tables; the tables equal, byte for
/// byte, those of a study of the same records from scratch (the
/// independent truth: every case computed). The added record sorts first,
/// so every kept case's number moves. Forced, or with the previous tables
/// not as the stage wrote them, nothing is taken. The convergence stage's
/// capacities at the sweep's own resolution are the sweep's (another
/// stage's search), and its medians are those of its records' capacities.
#[test]
fn a_rerun_computes_only_the_records_that_changed() {
    let dir = tempdir();
    let recs = dir.path().join("recs");
    fs::create_dir(&recs).unwrap();
    let far = root().join("records/fema-p695/far-field");
    let values = |stem: &str| plain_at2_values(&far.join(format!("{stem}.AT2")));
    let scaled = |stem: &str, k: f64| -> Vec<f64> { values(stem).iter().map(|a| k * a).collect() };
    let stems = [
        "RSN1111_KOBE_NIS000",
        "RSN953_NORTHR_MUL009",
        "RSN848_LANDERS_CLW-LN",
    ];
    for stem in stems {
        write_at2(&recs.join(format!("{stem}.AT2")), &values(stem), 0.01);
    }
    let body = "[records]\nat2 = [\"recs\"]\n[blocks]\np = [1.5, 4.0]\neps = [0.8]\n\
                [im]\ncount = 60\neta_min = 0.01\n[convergence]\nlevels = [30, 60]\n";
    let pipe = dir.path().join("inc.toml");
    fs::write(&pipe, format!("name = \"inc\"\n{body}")).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["run", "inc.toml", "--outputs", "out", "--to", "convergence"];
        args.extend_from_slice(extra);
        let out = rocking(dir.path(), &args);
        assert!(out.status.success(), "{}", stderr(&out));
        crate::util::stdout(&out) + &stderr(&out)
    };
    let first = run(&[]);
    assert!(!first.contains("from the previous"), "{first}");
    let study = dir.path().join("out/inc");
    let kept = fs::read(study.join("capacities.parquet")).unwrap();
    // Added (first by id), removed, edited in place.
    write_at2(
        &recs.join("A_KOBE_SCALED.AT2"),
        &scaled(stems[0], 0.9),
        0.01,
    );
    fs::remove_file(recs.join(format!("{}.AT2", stems[1]))).unwrap();
    write_at2(
        &recs.join(format!("{}.AT2", stems[2])),
        &scaled(stems[2], 1.1),
        0.01,
    );
    let second = run(&[]);
    for said in [
        "sweep: took the rows of 1 of 3 records (2 cases) from the previous sweep",
        "convergence: took the capacities of 1 of 3 records from the previous run",
    ] {
        assert!(second.contains(said), "{second}");
    }
    // The same records from scratch, in another folder.
    let fresh = tempdir();
    let fresh_recs = fresh.path().join("recs");
    fs::create_dir(&fresh_recs).unwrap();
    for entry in fs::read_dir(&recs).unwrap() {
        let path = entry.unwrap().path();
        fs::copy(&path, fresh_recs.join(path.file_name().unwrap())).unwrap();
    }
    fs::write(
        fresh.path().join("inc.toml"),
        format!("name = \"inc\"\n{body}"),
    )
    .unwrap();
    let args = ["run", "inc.toml", "--outputs", "out", "--to", "convergence"];
    let out = rocking(fresh.path(), &args);
    assert!(out.status.success(), "{}", stderr(&out));
    let tables = [
        "capacities.parquet",
        "ida_points.parquet",
        "convergence_capacities.parquet",
        "capacity_convergence.parquet",
    ];
    let same = |table: &str| {
        let (a, b) = (study.join(table), fresh.path().join("out/inc").join(table));
        fs::read(a).unwrap() == fs::read(b).unwrap()
    };
    for table in tables {
        assert!(same(table), "{table} differs");
    }
    let caps = read_capacities(&study).unwrap();
    assert_eq!(caps.len(), 6);
    assert!(caps.iter().enumerate().all(|(i, c)| c.case_id == i as i64));
    // The convergence stage's capacities at 60 levels are the sweep's; its
    // median over the 3 records (type 7: the middle one) is theirs.
    let conv: Vec<rocking::tables::convergence::ConvergenceCaseRow> =
        rocking::tables::read(&study.join("convergence_capacities.parquet")).unwrap();
    assert_eq!(conv.len(), 3 * 2 * 2);
    let at_60: Vec<_> = conv.iter().filter(|r| r.levels == 60).collect();
    for (c, r) in caps.iter().zip(&at_60) {
        assert_eq!((&c.record_id, c.p, c.eta_c), (&r.record_id, r.p, r.eta_c));
    }
    let summary: Vec<rocking::tables::convergence::ConvergenceRow> =
        rocking::tables::read(&study.join("capacity_convergence.parquet")).unwrap();
    for s in &summary {
        let mut etas: Vec<f64> = conv
            .iter()
            .filter(|r| (r.p, r.levels) == (s.p, s.levels))
            .map(|r| r.eta_c.unwrap_or(0.0))
            .collect();
        etas.sort_by(f64::total_cmp);
        assert_eq!(etas.len(), 3);
        assert_eq!(s.eta_c_q50, etas[1], "p = {}, {} levels", s.p, s.levels);
    }
    // Forced: everything computed, the same tables.
    let forced = run(&["--force"]);
    assert!(!forced.contains("from the previous"), "{forced}");
    for table in tables {
        assert!(same(table), "{table} differs after --force");
    }
    // The first sweep's table put back in place of the last one's: readable,
    // its keys those of records unchanged since, but not what the last
    // sweep wrote, so nothing is taken from it.
    fs::write(study.join("capacities.parquet"), &kept).unwrap();
    write_at2(
        &recs.join("A_KOBE_SCALED.AT2"),
        &scaled(stems[0], 0.8),
        0.01,
    );
    let tampered = run(&[]);
    assert!(!tampered.contains("sweep: took the rows"), "{tampered}");
    // A changed block with a record added: nothing taken; nor with --from.
    fs::write(
        &pipe,
        format!(
            "name = \"inc\"\n{}",
            body.replace("eps = [0.8]", "eps = [0.7]")
        ),
    )
    .unwrap();
    write_at2(
        &recs.join("B_LANDERS_SCALED.AT2"),
        &scaled(stems[2], 0.7),
        0.01,
    );
    let edited = run(&[]);
    assert!(!edited.contains("from the previous"), "{edited}");
    write_at2(
        &recs.join("C_LANDERS_SCALED.AT2"),
        &scaled(stems[2], 0.6),
        0.01,
    );
    let from = run(&["--from", "sweep"]);
    assert!(!from.contains("from the previous"), "{from}");
}

/// Every key that changes a sweep's rows makes it stale, and so keeps a
/// rerun from taking rows computed under the old value: a block's kinetic
/// friction `mu_k` (it changes every slide), the orientation's `angle_step`
/// (it changes which rotated motions the study has). Each run from scratch
/// in another folder gives the tables the edited study's rerun gives.
#[test]
fn editing_mu_k_or_the_angle_step_reruns_the_sweep() {
    let cases = [
        (
            "ids = [\"RSN1111_KOBE_NIS000\", \"RSN848_LANDERS_CLW-LN\"]\n[model]\n\
             kind = \"slide-rock\"\n[[block]]\nname = \"rack\"\nb = 0.3\nh = 1.0\neps = 0.75\n\
             mu = 0.2\n[im]\ncount = 40\n",
            ("mu = 0.2\n", "mu = 0.2\nmu_k = 0.12\n"),
        ),
        (
            "ids = [\"RSN1111_KOBE_NIS000\", \"RSN1111_KOBE_NIS090\"]\norientation = \"random\"\n\
             angle_step = 60\n[[block]]\nname = \"statue\"\nb = 0.2\nh = 0.9\neps = 0.9\n\
             [im]\ncount = 40\n",
            ("angle_step = 60\n", "angle_step = 45\n"),
        ),
    ];
    for (body, (from, to)) in cases {
        let dir = tempdir();
        let pipe = write_pipeline(dir.path(), "edit", body);
        let run = |cwd: &Path, pipe: &Path| {
            let args = [
                "run",
                pipe.to_str().unwrap(),
                "--outputs",
                "out",
                "--to",
                "sweep",
            ];
            let out = rocking(cwd, &args);
            assert!(out.status.success(), "{}", stderr(&out));
            crate::util::stdout(&out) + &stderr(&out)
        };
        run(dir.path(), &pipe);
        let text = fs::read_to_string(&pipe).unwrap();
        assert!(text.contains(from), "{text}");
        fs::write(&pipe, text.replace(from, to)).unwrap();
        let again = run(dir.path(), &pipe);
        assert!(again.contains("settings changed"), "{to}: {again}");
        let fresh = tempdir();
        let fresh_pipe = write_pipeline(fresh.path(), "edit", &body.replace(from, to));
        run(fresh.path(), &fresh_pipe);
        for table in ["capacities.parquet", "ida_points.parquet"] {
            let a = fs::read(dir.path().join("out/edit").join(table)).unwrap();
            let b = fs::read(fresh.path().join("out/edit").join(table)).unwrap();
            assert!(a == b, "{to}: {table} differs from a study from scratch");
        }
    }
}
