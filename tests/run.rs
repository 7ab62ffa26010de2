//! `rocking run` and `rocking status`: cached stages that rerun for the
//! right reasons (settings, inputs and outputs changed behind the tool's
//! back, fingerprints missing or corrupted), the lock, and a snapshot of a
//! mini study's tables (rounded to 12 significant digits) whose capacities
//! are checked against direct `rocking capacity` runs.

use std::fs;
use std::path::{Path, PathBuf};

use rocking::stages::sweep::read_capacities;

use crate::util::{
    bundled_records, direct_capacity, dump_table, rocking, snapshot, stderr, stdout, tempdir,
    write_pipeline,
};

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
        out.contains("ran ingest, sweep, reduce, ims, damage, fit, report"),
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
            .filter(|l| !l.starts_with("outputs of"))
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
    assert!(
        out.contains("ran sweep, reduce, ims, damage, fit, report"),
        "{out}"
    );

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

    // A study made by a build of other sources (the physics can change
    // within a version): the note holds this build's sources' hash, and a
    // note of another build's reruns its stage.
    let sweep_note = notes.join("sweep.json");
    let note = fs::read_to_string(&sweep_note).unwrap();
    let ours = format!(
        "rocking {} (sources {})",
        env!("CARGO_PKG_VERSION"),
        env!("ROCKING_SOURCE_HASH")
    );
    assert!(note.contains(&ours), "{note}");
    // `rocking --version` names the same build, so a user can tell which
    // build made a study.
    let version = rocking(d, &["--version"]);
    assert_eq!(String::from_utf8_lossy(&version.stdout).trim(), ours);
    let theirs = format!(
        "rocking {} (sources 0123456789abcdef)",
        env!("CARGO_PKG_VERSION")
    );
    fs::write(&sweep_note, note.replace(&ours, &theirs)).unwrap();
    let (_, log) = run(d, &pipe);
    assert!(
        line(&log, "sweep").contains("the tool changed (its version or its sources)"),
        "{log}"
    );
    assert!(line(&log, "ingest").contains("fresh"), "{log}");
}

/// A pipeline over all 44 far-field records with enough work (a few
/// seconds on one thread) for a second command to meet it while it runs.
fn busy_study(dir: &Path) -> PathBuf {
    let rec = bundled_records();
    let text = format!(
        "name = \"busy\"\n[records]\nat2 = [\"{}\"]\nmanifest = \"{}\"\nsets = [\"far-field\"]\n\
         [blocks]\np = [0.5, 1.0, 2.0, 4.0]\neps = [0.6, 0.75, 0.9]\n\
         [convergence]\nlevels = [100, 200, 400, 800]\n",
        rec.join("far-field").display(),
        rec.join("manifest.csv").display()
    );
    let path = dir.join("busy.toml");
    fs::write(&path, text).unwrap();
    path
}

/// Waits until the lock at `path` is `child`'s (the running command has
/// taken it; a lock left by an earlier holder does not count).
fn wait_for(path: &Path, child: &mut std::process::Child) {
    for _ in 0..600 {
        let holder = fs::read(path)
            .ok()
            .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
            .and_then(|v| v["pid"].as_u64());
        if holder == Some(u64::from(child.id())) {
            return;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the first command ended before taking its lock"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    panic!("{} never appeared", path.display());
}

#[test]
fn every_writer_takes_the_study_lock() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = busy_study(d);
    let p = pipe.to_str().unwrap();
    let lock = d.join("out/busy/.lock");
    // Two sweeps at once used to collide on the part files; a sweep beside
    // a run was not refused.
    for holder in ["run", "sweep"] {
        let mut first = std::process::Command::new(env!("CARGO_BIN_EXE_rocking"))
            .args([holder, p, "--outputs", "out", "--threads", "1"])
            .current_dir(d)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        wait_for(&lock, &mut first);
        // Every command that writes into the folder is refused while it
        // holds the lock, and says who holds it.
        for args in [
            vec!["sweep", p, "--outputs", "out"],
            vec!["sweep", p, "--outputs", "out", "--shard", "1/2"],
            vec!["run", p, "--outputs", "out"],
            vec!["reduce", p, "--outputs", "out"],
        ] {
            let out = rocking(d, &args);
            let err = stderr(&out);
            assert!(
                !out.status.success(),
                "{args:?} ran beside `rocking {holder}`"
            );
            assert!(
                err.contains("is in use") && err.contains(&format!("pid {}", first.id())),
                "{args:?}: {err}"
            );
            assert!(
                err.contains(&format!("rocking {holder}")),
                "names the holder's command: {err}"
            );
        }
        // Killed, its lock stays behind but no longer counts.
        first.kill().unwrap();
        first.wait().unwrap();
        assert!(lock.exists(), "a killed {holder} leaves its lock");
    }
    let out = rocking(
        d,
        &[
            "run",
            p,
            "--outputs",
            "out",
            "--to",
            "sweep",
            "--threads",
            "1",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!lock.exists(), "released at the end");
}

#[test]
fn a_lock_that_is_not_a_live_rocking_is_taken_over() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = study(d, "0.9");
    let p = pipe.to_str().unwrap();
    let lock = d.join("out/mini/.lock");
    fs::create_dir_all(lock.parent().unwrap()).unwrap();
    let me = std::process::id().to_string();
    for (what, content) in [
        ("empty", ""),
        ("garbage", "}{ not a lock"),
        ("a bare dead pid", "999999999"),
        ("pid 1 (init, not this tool)", "1"),
        ("this test's pid (alive, not this tool)", me.as_str()),
    ] {
        fs::write(&lock, content).unwrap();
        let out = rocking(d, &["run", p, "--outputs", "out", "--to", "ingest"]);
        assert!(out.status.success(), "{what}: {}", stderr(&out));
        assert!(!lock.exists(), "{what}: released at the end");
    }
    // A live rocking's lock in the owner format: a shard lock held by a
    // second process refuses the exclusive lock.
    let owner = serde_json::json!({
        "pid": 999999999u32, "host": "another-host", "started_ticks": 0u64,
        "since_unix_s": 0u64, "command": "rocking sweep x.toml --shard 1/4"
    });
    let shard_lock = d.join("out/mini/.lock.shard-1-of-4");
    fs::write(&shard_lock, owner.to_string()).unwrap();
    let out = rocking(d, &["run", p, "--outputs", "out"]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("another-host") && err.contains("--shard 1/4"),
        "a lock from another host is obeyed and named: {err}"
    );
    assert!(!err.contains("pid )"), "{err}");
    // A shard of another count is refused too (their chunks overlap).
    let out = rocking(d, &["sweep", p, "--outputs", "out", "--shard", "1/3"]);
    assert!(stderr(&out).contains("--shard 1/4"), "{}", stderr(&out));
    // A remote lock untouched for longer than REMOTE_TTL (its node died) is taken over.
    let an_hour_ago = std::time::SystemTime::now() - std::time::Duration::from_secs(3600);
    fs::File::options()
        .append(true)
        .open(&shard_lock)
        .unwrap()
        .set_modified(an_hour_ago)
        .unwrap();
    let out = rocking(d, &["run", p, "--outputs", "out"]);
    assert!(out.status.success(), "{}", stderr(&out));
    // A remote lock of this very Slurm array task (a requeue on another
    // node) is taken over at once.
    fs::remove_file(&shard_lock).unwrap();
    let mine = serde_json::json!({
        "pid": 4242u32, "host": "dead-node", "started_ticks": 0u64, "since_unix_s": 0u64,
        "command": "rocking sweep mini.toml --shard 1/1", "job": "slurm 77_1"
    });
    fs::write(d.join("out/mini/.lock.shard-1-of-1"), mine.to_string()).unwrap();
    let requeued = |task: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_rocking"))
            .args(["sweep", p, "--outputs", "out", "--shard", "1/1", "--force"])
            .env("SLURM_ARRAY_JOB_ID", "77")
            .env("SLURM_ARRAY_TASK_ID", task)
            .current_dir(d)
            .output()
            .unwrap()
    };
    let out = requeued("2");
    assert!(!out.status.success(), "another task of the array obeys it");
    let out = requeued("1");
    assert!(out.status.success(), "{}", stderr(&out));
}

#[test]
fn mini_study_snapshot() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = study(d, "0.9");
    run(d, &pipe);
    let folder = d.join("out/mini");
    // The capacities, checked against direct `rocking capacity` runs of the same blocks.
    let caps = read_capacities(&folder).unwrap();
    let mut text = String::from("record_id\tp\teps\teta_c\teta_survived\truns\n");
    for c in &caps {
        let record = d.join("records").join(format!("{}.AT2", c.record_id));
        let v = direct_capacity(d, record.to_str().unwrap(), c.p, c.eps, 40);
        assert_eq!(
            c.eta_c,
            v["eta_c"].as_f64(),
            "{} p = {} ε = {}",
            c.record_id,
            c.p,
            c.eps
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
    // The report as the pure renderer makes it from the loaded tables
    // (run times and version fixed, so that only the study shows).
    let study = rocking::stages::Study::load(&pipe, &d.join("out")).unwrap();
    let times = [
        ("ingest", Some(1.0)),
        ("sweep", None),
        ("reduce", Some(0.5)),
    ];
    let mut data = rocking::stages::report::load(&study, &times).unwrap();
    data.version = "(version)".into();
    let figures = rocking::figures::all(&data);
    // Figs. 5–8, the 84 % regression (Fig. 11), the coefficients a, b, c and
    // the fragility example, the damage states, the two IM figures; no Fig. 9 (the Lilliefors test needs 5
    // records, the mini study has 3), no Fig. 10 nor the 16 % regression
    // (too few converged step-1 fits of those fractiles for their b and c),
    // no convergence figures (no [convergence]), no bands (no [uncertainty]).
    let files: Vec<&str> = figures.iter().map(|f| f.file.as_str()).collect();
    assert_eq!(files.len(), 12, "{files:?}");
    assert!(files.contains(&"fig11_regression_q84.svg"), "{files:?}");
    assert!(!files.iter().any(|f| f.starts_with("fig09")
        || f.starts_with("fig10")
        || f.ends_with("q16.svg")
        || f.contains("convergence")
        || f.contains("bands")));
    snapshot("mini_report.md", &rocking::report::render(&data, &figures));
    for (snap, table) in [
        ("mini_capacity_fractiles.tsv", "capacity_fractiles.parquet"),
        ("mini_lognormal.tsv", "lognormal.parquet"),
        (
            "mini_fractiles_horizontal.tsv",
            "fractiles_horizontal.parquet",
        ),
    ] {
        snapshot(snap, &dump_table(&folder.join(table), false));
    }
}

#[test]
fn a_stage_command_runs_only_the_stages_it_reads_from() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = study(d, "0.9");
    let text = fs::read_to_string(&pipe).unwrap() + "[convergence]\nlevels = [10, 20]\n";
    fs::write(&pipe, text).unwrap();
    let p = pipe.to_str().unwrap();
    // reduce reads the sweep, which reads the ingested records: the
    // convergence study, though stale and earlier in the run, is not needed.
    let out = rocking(d, &["reduce", p, "--outputs", "out"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let log = stderr(&out);
    for stage in ["ingest", "sweep", "reduce"] {
        assert!(line(&log, stage).contains("running"), "{log}");
    }
    assert!(!log.contains("convergence"), "{log}");
    assert!(stdout(&out).contains("reduced 3 records × 9 blocks"));
    // The report reads the convergence table, so its command runs it.
    let out = rocking(d, &["report", p, "--outputs", "out"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let log = stderr(&out);
    assert!(line(&log, "convergence").contains("running"), "{log}");
    assert!(line(&log, "fit").contains("running"), "{log}");
    assert!(line(&log, "sweep").contains("skipped: fresh"), "{log}");
    let status = stdout(&rocking(d, &["status", p, "--outputs", "out"]));
    // Every stage of a records study is fresh; the pulse map's, the
    // example's (no `[example]`) and the tree's (no `[tree]`) are not needed.
    assert!(
        status.lines().skip(1).all(|l| l.contains("fresh")
            || (l.starts_with("pulses") || l.starts_with("example") || l.starts_with("tree"))
                && l.contains("not needed")),
        "{status}"
    );
}

/// A stage that fails after writing some of its tables says what it left
/// (the finished tables whole, the others missing) and is not marked done:
/// `status` shows it stale and the next run redoes it.
#[test]
fn a_stage_failing_midway_says_what_it_left_and_reruns() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = write_pipeline(
        d,
        "mid",
        "ids = [\"RSN1111_KOBE_NIS000\", \"RSN169_IMPVALL_H-DLT352\"]\n\
         [blocks]\np = [1.0, 2.0]\neps = [0.9]\n[im]\ncount = 20\n",
    );
    let p = pipe.to_str().unwrap();
    let run = || rocking(d, &["run", p, "--outputs", "out", "--to", "reduce"]);
    // A folder where reduce's fourth table goes: its write fails.
    std::fs::create_dir_all(d.join("out/mid/lognormal.parquet/x")).unwrap();
    let out = run();
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("stage `reduce` failed") && err.contains("the next run redoes it"),
        "{err}"
    );
    assert!(
        d.join("out/mid/capacity_fractiles.parquet").exists(),
        "written before"
    );
    let status = stdout(&rocking(d, &["status", p, "--outputs", "out"]));
    let line = status
        .lines()
        .find(|l| l.starts_with("reduce"))
        .unwrap_or("");
    assert!(line.contains("stale"), "{status}");
    std::fs::remove_dir_all(d.join("out/mid/lognormal.parquet")).unwrap();
    let out = run();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).contains("reduce"), "{}", stdout(&out));
    assert!(d.join("out/mid/lognormal.parquet").is_file());
}

/// A records table kept inside the study's own folder was overwritten by
/// the sweep's `capacities.parquet` of the same path, and the next stage
/// refused its own input as "not a `records` table". A pipeline whose
/// records table lies in the folder its stages write to is refused by
/// every command that loads it, before anything is written, and the file
/// is left as it was.
#[test]
fn a_records_table_in_the_studys_own_folder_is_refused() {
    let dir = tempdir();
    let d = dir.path();
    let inside = d.join("out/t1/capacities.parquet");
    fs::create_dir_all(inside.parent().unwrap()).unwrap();
    fs::write(&inside, b"the user's records table").unwrap();
    let pipe = d.join("t1.toml");
    fs::write(
        &pipe,
        "name = \"t1\"\n[records]\ntable = \"out/t1/capacities.parquet\"\n[blocks]\np = [2.0]\neps = [0.7]\n",
    )
    .unwrap();
    for args in [&["run"][..], &["sweep"], &["status"]] {
        let out = rocking(d, &[args, &["t1.toml", "--outputs", "out"]].concat());
        assert!(!out.status.success(), "{args:?}");
        let e = stderr(&out);
        assert!(
            e.contains("`records.table` = ") && e.contains("is inside the study's folder"),
            "{args:?}: {e}"
        );
    }
    assert_eq!(fs::read(&inside).unwrap(), b"the user's records table");
    // The same table beside the outputs is taken (and read as a table).
    fs::rename(&inside, d.join("records.parquet")).unwrap();
    let beside =
        "name = \"t1\"\n[records]\ntable = \"records.parquet\"\n[blocks]\np = [2.0]\neps = [0.7]\n";
    fs::write(&pipe, beside).unwrap();
    let out = rocking(d, &["status", "t1.toml", "--outputs", "out"]);
    assert!(
        !stderr(&out).contains("inside the study's folder"),
        "{}",
        stderr(&out)
    );
}

/// A section taken out of the pipeline takes its tables with it: the
/// bands of `[uncertainty]` (written by reduce and fit, stages that still
/// run) and the example's damage tables (written by damage) stayed beside
/// the study's, the bands of a grid the study no longer had, and
/// `--force` kept them too. The folder now holds what a fresh run of the
/// pipeline writes, file for file; a table changed by hand is left alone.
#[test]
fn a_section_taken_out_takes_its_tables_with_it() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = study(d, "0.9");
    let plain = fs::read_to_string(&pipe).unwrap();
    let extra =
        "[uncertainty]\nresamples = 20\nunit = \"record\"\n[example]\np = 3.0\neps = 0.75\n";
    fs::write(&pipe, format!("{plain}{extra}")).unwrap();
    run(d, &pipe);
    let folder = d.join("out/mini");
    let tables = |folder: &Path| -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(folder)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".parquet"))
            .collect();
        names.sort();
        names
    };
    let with = tables(&folder);
    for t in ["capacity_bands.parquet", "example_damage_states.parquet"] {
        assert!(with.contains(&t.to_string()), "{with:?}");
    }
    // Taken out, with ε changed so that every stage reruns.
    fs::write(&pipe, plain.replace("0.9]", "0.92]")).unwrap();
    run(d, &pipe);
    let out = rocking(d, &["run", pipe.to_str().unwrap(), "--outputs", "fresh"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let fresh = tables(&d.join("fresh/mini"));
    assert_eq!(tables(&folder), fresh);
    for t in [
        "capacity_bands.parquet",
        "capacity_resamples.parquet",
        "example_damage_states.parquet",
    ] {
        assert!(!fresh.contains(&t.to_string()), "{fresh:?}");
    }
    // Back in, then out again with one of its tables edited since: kept.
    fs::write(&pipe, format!("{plain}{extra}")).unwrap();
    run(d, &pipe);
    let bands = folder.join("capacity_bands.parquet");
    let mut bytes = fs::read(&bands).unwrap();
    bytes.push(0);
    fs::write(&bands, &bytes).unwrap();
    fs::write(&pipe, &plain).unwrap();
    run(d, &pipe);
    assert!(bands.exists(), "a table changed by hand is the user's");
    assert!(!folder.join("example_damage_states.parquet").exists());
}
