//! Faults found by probing the tool as a hostile user would;
//! each test failed before the fix. (The lock faults are in `run`.)

use std::fs;
use std::path::{Path, PathBuf};

use rocking::stages::engine::{self, Freshness};
use rocking::stages::fingerprint::{self, Stale};
use rocking::stages::sweep::{read_capacities, DatasetError, FAULT_ENV, HOLD_ENV};
use rocking::stages::Study;

use crate::util::{bundled_records, rocking, root, stderr, stdout, tempdir, write_pipeline};

/// 3 records × 24 blocks = 72 cases: three chunks of 32.
const THREE_CHUNKS: &str = r#"ids = ["RSN1111_KOBE_NIS000", "RSN953_NORTHR_MUL009", "RSN1633_MANJIL_ABBAR--L"]
[blocks]
p = { from = 0.5, to = 8.0, count = 6, spacing = "log" }
eps = [0.6, 0.7, 0.8, 0.9]
[im]
count = 40
eta_min = 0.01
"#;

fn copy_dir(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for e in fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            fs::copy(e.path(), target).unwrap();
        }
    }
}

#[test]
fn absurd_sizes_are_refused_before_anything_is_allocated() {
    let dir = tempdir();
    let d = dir.path();
    let grid = "[blocks]\np = [1.0]\neps = [0.8]\n";
    for (body, key) in [
        (format!("{grid}[im]\ncount = 1000000000000\n"), "`im.count`"),
        (
            "[blocks]\np = { from = 1.0, to = 2.0, count = 1000000000000 }\neps = [0.8]\n".into(),
            "`blocks.p.count`",
        ),
        (
            format!("{grid}[convergence]\nlevels = [10, 1000000000000]\n"),
            "`convergence.levels`",
        ),
    ] {
        let pipe = write_pipeline(d, "huge", &body);
        let out = rocking(d, &["run", pipe.to_str().unwrap(), "--outputs", "out"]);
        // Exit code 1 and a message, not an allocation abort (134).
        assert_eq!(out.status.code(), Some(1), "{body}: {}", stderr(&out));
        assert!(stderr(&out).contains(key), "{body}: {}", stderr(&out));
    }
    let record = root().join("records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2");
    let out = rocking(
        d,
        &[
            "capacity",
            "--record",
            record.to_str().unwrap(),
            "--p",
            "2",
            "--eps",
            "0.8",
            "--levels",
            "1000000000000",
        ],
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("levels is more than"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn a_part_copied_over_another_chunk_is_recomputed() {
    let reference = tempdir();
    let ref_pipe = write_pipeline(reference.path(), "r", THREE_CHUNKS);
    let out = rocking(
        reference.path(),
        &["sweep", ref_pipe.to_str().unwrap(), "--outputs", "out"],
    );
    assert!(out.status.success(), "{}", stderr(&out));

    let dir = tempdir();
    let d = dir.path();
    let pipe = write_pipeline(d, "r", THREE_CHUNKS);
    // Crash after two chunks are saved, then copy chunk 0's IDA part over
    // chunk 1's (the message named chunk 1's untouched capacity part).
    let crashed = std::process::Command::new(env!("CARGO_BIN_EXE_rocking"))
        .args(["sweep", pipe.to_str().unwrap(), "--outputs", "out"])
        .env(FAULT_ENV, "2")
        .env(HOLD_ENV, "0")
        .current_dir(d)
        .output()
        .unwrap();
    assert!(!crashed.status.success());
    let parts = d.join("out/r/parts");
    fs::copy(
        parts.join("ida-000000.parquet"),
        parts.join("ida-000001.parquet"),
    )
    .unwrap();
    let resumed = rocking(d, &["sweep", pipe.to_str().unwrap(), "--outputs", "out"]);
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    let log = stderr(&resumed);
    assert!(
        log.contains("ida-000001.parquet of chunk 1 is not that chunk's")
            && log.contains("recomputing"),
        "the corrupt part is logged: {log}"
    );
    assert!(
        stdout(&resumed).contains("(32 resumed from an earlier run)"),
        "only chunk 0 is trusted: {}",
        stdout(&resumed)
    );
    let caps = read_capacities(&d.join("out/r")).unwrap();
    let ids: Vec<i64> = caps.iter().map(|c| c.case_id).collect();
    assert_eq!(ids, (0..72).collect::<Vec<i64>>(), "every case once");
    assert_eq!(
        caps,
        read_capacities(&reference.path().join("out/r")).unwrap()
    );
}

#[test]
fn shards_beside_an_unsharded_sweep_are_refused() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = write_pipeline(d, "s", THREE_CHUNKS);
    let p = pipe.to_str().unwrap();
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let out = rocking(d, &["sweep", p, "--outputs", "sharded", "--shard", &shard]);
        assert!(out.status.success(), "{}", stderr(&out));
    }
    let out = rocking(d, &["sweep", p, "--outputs", "whole"]);
    assert!(out.status.success(), "{}", stderr(&out));
    // Shard tables copied beside the unsharded ones: two versions of one sweep.
    for e in fs::read_dir(d.join("sharded/s")).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        if name.contains(".shard-") {
            fs::copy(
                d.join("sharded/s").join(&name),
                d.join("whole/s").join(&name),
            )
            .unwrap();
        }
    }
    let e = read_capacities(&d.join("whole/s")).unwrap_err();
    assert!(matches!(e, DatasetError::Mixed { shards: 6, .. }), "{e}");
    let out = rocking(d, &["reduce", p, "--outputs", "whole"]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("holds both the unsharded sweep tables") && err.contains("remove one set"),
        "{err}"
    );
    // The complete set of shards alone is a fresh sweep for the later stages.
    let out = rocking(d, &["reduce", p, "--outputs", "sharded"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("sweep        skipped: fresh (3 shards)"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn hints_name_what_the_command_accepts() {
    let dir = tempdir();
    let d = dir.path();
    // A bad AT2 file under a pipeline: the hint is about the pipeline, not
    // `--skip-bad`, which sweep and run do not take.
    fs::create_dir_all(d.join("bad")).unwrap();
    fs::copy(
        root().join("records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2"),
        d.join("bad/RSN1111_KOBE_NIS000.AT2"),
    )
    .unwrap();
    fs::write(
        d.join("bad/BAD.AT2"),
        "H\nX\nACCELERATION IN G\nNPTS=  3, DT= .01 SEC\n1 2\n",
    )
    .unwrap();
    fs::write(
        d.join("b.toml"),
        "[records]\nat2 = [\"bad\"]\n[blocks]\np = [1.0]\neps = [0.8]\n",
    )
    .unwrap();
    for cmd in ["sweep", "run"] {
        let out = rocking(d, &[cmd, "b.toml", "--outputs", "out"]);
        let err = stderr(&out);
        assert!(!out.status.success());
        assert!(!err.contains("--skip-bad"), "{cmd}: {err}");
        assert!(
            err.contains("BAD.AT2:5") && err.contains("records.at2"),
            "{cmd}: {err}"
        );
    }
    let out = rocking(d, &["ingest", "bad", "--out", "x.parquet"]);
    assert!(stderr(&out).contains("--skip-bad"), "{}", stderr(&out));

    // fragility --from a pipeline whose fit has not run says to run the fit.
    fs::write(
        d.join("g.toml"),
        "[records]\nat2 = [\"bad\"]\n[blocks]\np = [1.0, 2.0, 3.0]\neps = [0.6, 0.7, 0.8]\n",
    )
    .unwrap();
    let out = rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "1",
            "--pga",
            "0.3",
            "--from",
            "g.toml",
            "--outputs",
            "out",
        ],
    );
    let err = stderr(&out);
    assert!(
        err.contains("rocking fit g.toml") && !err.contains("reduce"),
        "{err}"
    );
    // …and one that cannot have a fit says so.
    let out = rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "1",
            "--pga",
            "0.3",
            "--from",
            "b.toml",
            "--outputs",
            "out",
        ],
    );
    assert!(stderr(&out).contains("no regression"), "{}", stderr(&out));

    // A stocky block without --eps: Housner's ε is what is negative.
    let out = rocking(d, &["fragility", "--b", "5", "--h", "0.1", "--pga", "0.3"]);
    let err = stderr(&out);
    assert!(!out.status.success());
    assert!(
        err.contains("Housner's ε") && err.contains("give --eps"),
        "{err}"
    );
    assert!(!err.contains("--eps = "), "{err}");
}

#[test]
fn thread_counts_beyond_the_cores_are_refused() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = write_pipeline(
        d,
        "t",
        "ids = [\"RSN1111_KOBE_NIS000\"]\n[blocks]\np = [1.0]\neps = [0.8]\n",
    );
    for (n, want) in [
        ("100000", "100000 worker threads is more than"),
        ("0", "--threads 0: give one worker thread or more"),
    ] {
        let out = rocking(d, &["sweep", pipe.to_str().unwrap(), "--threads", n]);
        assert_eq!(out.status.code(), Some(1), "{n}");
        assert!(stderr(&out).contains(want), "{}", stderr(&out));
    }
}

#[test]
fn file_contents_in_messages_are_escaped() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("EVIL.AT2"),
        "H\nX\nVELOCITY \u{1b}[31mRED\u{1b}[2J\0 IN CM/S\nNPTS=  3, DT= .01 SEC\n1 2 3\n",
    )
    .unwrap();
    let out = rocking(d, &["ingest", "EVIL.AT2", "--out", "x.parquet"]);
    let err = stderr(&out);
    assert!(!out.status.success());
    assert!(!err.contains('\u{1b}') && !err.contains('\0'), "{err:?}");
    assert!(
        err.contains("\\u{1b}[31mRED") && err.contains("\\u{0}"),
        "{err}"
    );
}

#[test]
fn manifest_errors_name_the_file_line() {
    let dir = tempdir();
    let d = dir.path();
    let src = root().join("records/fema-p695/far-field");
    for id in ["RSN1111_KOBE_NIS000", "RSN953_NORTHR_MUL009"] {
        fs::copy(src.join(format!("{id}.AT2")), d.join(format!("{id}.AT2"))).unwrap();
    }
    // CRLF endings, the bad cell on line 3 of the file (the header is line 1).
    fs::write(
        d.join("m.csv"),
        "year,file\r\n1999,RSN1111_KOBE_NIS000.AT2\r\n19x9,RSN953_NORTHR_MUL009.AT2\r\n",
    )
    .unwrap();
    let out = rocking(
        d,
        &["ingest", ".", "--manifest", "m.csv", "--out", "x.parquet"],
    );
    assert!(
        stderr(&out).contains("line 3: column `year`"),
        "{}",
        stderr(&out)
    );
}

/// The 3 × 3 mini study of `run`, with its records copied beside it.
fn mini(dir: &Path) -> PathBuf {
    let rec = dir.join("records");
    fs::create_dir_all(&rec).unwrap();
    for id in ["RSN1111_KOBE_NIS000", "RSN953_NORTHR_MUL009"] {
        fs::copy(
            bundled_records().join(format!("far-field/{id}.AT2")),
            rec.join(format!("{id}.AT2")),
        )
        .unwrap();
    }
    let path = dir.join("mini.toml");
    fs::write(
        &path,
        "name = \"mini\"\n[records]\nat2 = [\"records\"]\n[blocks]\np = [1.5, 3.0, 6.0]\n\
         eps = [0.6, 0.75, 0.9]\n[im]\ncount = 30\neta_min = 0.01\n",
    )
    .unwrap();
    path
}

#[test]
fn a_copied_output_folder_and_another_working_folder_stay_fresh() {
    let dir = tempdir();
    let d = dir.path();
    mini(d);
    let out = rocking(d, &["run", "mini.toml", "--outputs", "out"]);
    assert!(out.status.success(), "{}", stderr(&out));
    copy_dir(&d.join("out/mini"), &d.join("copy/mini"));
    let out = rocking(d, &["run", "mini.toml", "--outputs", "copy"]);
    assert!(stdout(&out).contains("nothing to do"), "{}", stderr(&out));
    // The same study from another working folder, the pipeline named by an
    // absolute path.
    fs::create_dir_all(d.join("elsewhere")).unwrap();
    let out = rocking(
        &d.join("elsewhere"),
        &[
            "run",
            d.join("mini.toml").to_str().unwrap(),
            "--outputs",
            d.join("out").to_str().unwrap(),
        ],
    );
    assert!(stdout(&out).contains("nothing to do"), "{}", stderr(&out));
}

/// The temporary files a killed writer left before its rename (a table's,
/// a figure's, a fingerprint's) are removed by the next run of the study,
/// which holds its lock; one whose writer lives is kept, and so is a shard's
/// (its writer may be on another node). They survived
/// every later run, `--force` too.
#[test]
#[cfg(target_os = "linux")]
fn a_killed_writers_temporaries_are_removed_by_the_next_run() {
    let dir = tempdir();
    let d = dir.path();
    mini(d);
    let run = || {
        rocking(
            d,
            &["run", "mini.toml", "--outputs", "out", "--to", "ingest"],
        )
    };
    assert!(run().status.success());
    let study = d.join("out/mini");
    // A pid above Linux's largest (2²² = 4,194,304): no process has it.
    let dead = [
        study.join(".records.parquet.tmp-4194305"),
        study.join("figures/.fig05_ida_curves.svg.tmp-4194305"),
        study.join(".fingerprints/.ingest.json.tmp-4194305"),
    ];
    let alive = study.join(format!(".blocks.parquet.tmp-{}", std::process::id()));
    // A shard's table, whose writer may be on another node.
    let shard = study.join(".capacities.shard-1-of-2.parquet.tmp-4194305");
    for path in dead.iter().chain([&alive, &shard]) {
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, "half").unwrap();
    }
    let again = run();
    assert!(
        stdout(&again).contains("nothing to do"),
        "{}",
        stderr(&again)
    );
    for path in &dead {
        assert!(!path.exists(), "{}", path.display());
    }
    assert!(alive.exists() && shard.exists());
}

/// `status` while a run holds the study says who runs it (the stages it
/// lists are as the last finished stage left them), and says nothing of the
/// kind once the holder is gone.
#[test]
#[cfg(target_os = "linux")]
fn status_names_a_run_under_way() {
    let dir = tempdir();
    let d = dir.path();
    mini(d);
    let status = || stdout(&rocking(d, &["status", "mini.toml", "--outputs", "out"]));
    let study = d.join("out/mini");
    fs::create_dir_all(&study).unwrap();
    let (mut holder, host) = crate::util::live_lock(&study.join(".lock"), "rocking run mini.toml");
    let text = status();
    holder.kill().unwrap();
    holder.wait().unwrap();
    assert!(
        text.contains(&format!(
            "running now: `rocking run mini.toml` (pid {} on {}",
            holder.id(),
            host
        )),
        "{text}"
    );
    assert!(!status().contains("running now"));
}

/// A pipeline that is not UTF-8 is refused naming the line of its first
/// bad byte (it said only "stream did not contain valid UTF-8").
#[test]
fn a_pipeline_not_in_utf8_is_refused_at_its_line() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("latin1.toml"),
        b"name = \"x\"\n[records]\n# Z\xfcrich\nat2 = [\"r\"]\n",
    )
    .unwrap();
    let out = rocking(d, &["status", "latin1.toml"]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("latin1.toml: cannot read the pipeline")
            && stderr(&out).contains("line 3: not UTF-8 text"),
        "{}",
        stderr(&out)
    );
}

/// The report prints the other stages' run times, and reruns when one of
/// them ran again: it said "settings changed", which no setting had; it
/// says why (here the reduce stage's note given another time, as a rerun
/// of it would), and its settings are still checked.
#[test]
fn the_report_says_it_reruns_for_the_run_times_it_shows() {
    let dir = tempdir();
    let d = dir.path();
    mini(d);
    let run = |d: &Path| rocking(d, &["run", "mini.toml", "--outputs", "out"]);
    assert!(run(d).status.success());
    let note = d.join("out/mini/.fingerprints/reduce.json");
    let mut json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(&note).unwrap()).unwrap();
    json["seconds"] = serde_json::json!(json["seconds"].as_f64().unwrap() + 1.0);
    fs::write(&note, json.to_string()).unwrap();
    let err = stderr(&run(d));
    assert!(
        err.contains(
            "report       running: another stage ran again, and the run times it shows changed"
        ) && !err.contains("settings changed")
            && !err.contains("reduce       running"),
        "{err}"
    );
    let toml = fs::read_to_string(d.join("mini.toml")).unwrap();
    fs::write(
        d.join("mini.toml"),
        format!("description = \"another\"\n{toml}"),
    )
    .unwrap();
    let err = stderr(&run(d));
    assert!(
        err.contains("report       running: settings changed"),
        "{err}"
    );
}

#[test]
fn a_figure_deleted_or_edited_by_hand_is_drawn_again() {
    let dir = tempdir();
    let d = dir.path();
    mini(d);
    assert!(rocking(d, &["run", "mini.toml", "--outputs", "out"])
        .status
        .success());
    let fig = d.join("out/mini/figures/fig08_capacity_curves.svg");
    let original = fs::read(&fig).unwrap();
    fs::remove_file(&fig).unwrap();
    let study = Study::load(&d.join("mini.toml"), &d.join("out")).unwrap();
    let report = engine::status(&study)
        .into_iter()
        .find(|(s, _)| *s == "report")
        .unwrap()
        .1;
    assert_eq!(
        report,
        Freshness::Stale(vec![Stale::OutputMissing(
            "figures/fig08_capacity_curves.svg".into()
        )])
    );
    let out = rocking(d, &["run", "mini.toml", "--outputs", "out"]);
    assert!(
        stderr(&out)
            .contains("report       running: output figures/fig08_capacity_curves.svg is missing"),
        "{}",
        stderr(&out)
    );
    assert_eq!(fs::read(&fig).unwrap(), original, "drawn again, the same");
    fs::write(d.join("out/mini/figures/fig05_ida_curves.svg"), "<svg/>").unwrap();
    // A user's own figure beside them is not the report's to remove (it
    // once was: every .svg the report had not just drawn went).
    fs::write(d.join("out/mini/figures/mine.svg"), "<svg/>").unwrap();
    let out = rocking(d, &["run", "mini.toml", "--outputs", "out"]);
    assert!(d.join("out/mini/figures/mine.svg").exists());
    assert!(
        stderr(&out).contains("output figures/fig05_ida_curves.svg was changed"),
        "{}",
        stderr(&out)
    );
    let out = rocking(d, &["run", "mini.toml", "--outputs", "out"]);
    assert!(stdout(&out).contains("nothing to do"), "{}", stdout(&out));
}

#[test]
fn stale_reasons_are_typed() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = mini(d);
    assert!(rocking(d, &["run", "mini.toml", "--outputs", "out"])
        .status
        .success());
    let text = fs::read_to_string(&pipe).unwrap().replace("0.9]", "0.85]");
    fs::write(&pipe, text).unwrap();
    let study = Study::load(&pipe, &d.join("out")).unwrap();
    let status: Vec<(&str, Freshness)> = engine::status(&study);
    let of = |name: &str| status.iter().find(|(s, _)| *s == name).unwrap().1.clone();
    assert_eq!(of("ingest"), Freshness::Fresh);
    assert_eq!(of("sweep"), Freshness::Stale(vec![Stale::SettingsChanged]));
    assert!(matches!(of("convergence"), Freshness::NotNeeded(_)));
    // Reduce's own inputs are unchanged (the sweep has not rerun yet), but
    // it reads the sweep's outputs, which will change: it waits on it.
    assert_eq!(of("reduce"), Freshness::Waits("sweep"));
    // The report shows the settings: they are its own.
    assert_eq!(of("report"), Freshness::Stale(vec![Stale::SettingsChanged]));
    // A missing input of a stage that has never run names the file.
    let other = Study::load(&pipe, &d.join("elsewhere")).unwrap();
    match fingerprint::freshness(engine::find("reduce").unwrap(), &other, None) {
        Freshness::Stale(why) => assert!(
            why.contains(&Stale::InputMissing("capacities.parquet".into())),
            "{why:?}"
        ),
        f => panic!("{f:?}"),
    }
}

/// Asserts that no cause in the error chain printed on stderr repeats the
/// text of a line above it (a wrapper printing its source's message).
fn assert_causes_are_not_repeated(err: &str) {
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    for (i, l) in lines.iter().enumerate() {
        if let Some(cause) = l.trim().strip_prefix("caused by: ") {
            for earlier in &lines[..i] {
                assert!(
                    !earlier.contains(cause),
                    "`{cause}` is printed twice:\n{err}"
                );
            }
        }
    }
}

#[test]
fn error_causes_are_printed_once() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(d.join("garbage.parquet"), "not a parquet file").unwrap();
    fs::write(
        d.join("g.toml"),
        "[records]\ntable = \"garbage.parquet\"\n[blocks]\np = [1.0]\neps = [0.8]\n",
    )
    .unwrap();
    let out = rocking(d, &["sweep", "g.toml", "--outputs", "out"]);
    let err = stderr(&out);
    assert!(!out.status.success());
    assert!(
        err.contains("garbage.parquet") && err.contains("caused by:"),
        "{err}"
    );
    assert_causes_are_not_repeated(&err);
    // A pipeline that cannot be read, a manifest with a bad cell.
    let out = rocking(d, &["run", "missing.toml"]);
    assert_causes_are_not_repeated(&stderr(&out));
    fs::write(d.join("m.csv"), "year,file\n19x9,a.AT2\n").unwrap();
    fs::copy(
        root().join("records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2"),
        d.join("a.AT2"),
    )
    .unwrap();
    let out = rocking(d, &["ingest", "a.AT2", "--manifest", "m.csv"]);
    let err = stderr(&out);
    assert!(err.contains("line 2"), "{err}");
    assert_causes_are_not_repeated(&err);
}

#[test]
fn an_incomplete_or_resharded_sweep_is_not_redone_behind_the_users_back() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = write_pipeline(d, "s", THREE_CHUNKS);
    let p = pipe.to_str().unwrap();
    let sweep = |shard: &str| rocking(d, &["sweep", p, "--outputs", "out", "--shard", shard]);
    assert!(sweep("1/2").status.success());
    // One shard of two: `run` refuses to throw it away, and says what to do.
    let out = rocking(d, &["run", p, "--outputs", "out"]);
    let err = stderr(&out);
    assert!(!out.status.success());
    assert!(
        err.contains("run in 2 shards and shard 2/2 is missing")
            && err.contains(&format!("`rocking sweep {p} --outputs out --shard K/2`")),
        "{err}"
    );
    assert!(d.join("out/s/capacities.shard-1-of-2.parquet").exists());
    // Re-sharded into three: the shards of two are superseded, and the
    // first shard of three says which tables it removed (they went unsaid).
    for k in 1..=3 {
        let out = sweep(&format!("{k}/3"));
        assert!(out.status.success(), "{}", stderr(&out));
        let said = format!("{}{}", stdout(&out), stderr(&out));
        assert_eq!(
            said.contains(
                "removed the tables of 1 earlier shard (2 files): superseded by shard 1/3"
            ),
            k == 1,
            "{said}"
        );
    }
    assert!(!d.join("out/s/capacities.shard-1-of-2.parquet").exists());
    assert!(!d
        .join("out/s/.fingerprints/sweep.shard-1-of-2.json")
        .exists());
    let out = rocking(d, &["run", p, "--outputs", "out"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("sweep        skipped: fresh (3 shards)"),
        "{}",
        stderr(&out)
    );
    // The report's run times have the sweep: its shards' seconds, summed
    // (it had no row when the sweep was sharded).
    let md = fs::read_to_string(d.join("out/s/report.md")).unwrap();
    assert!(md.contains("| sweep (3 shards, summed) | "), "{md}");
    // More shards than chunks, or an absurd count, is refused.
    let out = sweep("4/4");
    assert!(
        stderr(&out).contains("the sweep has 3 chunk(s)"),
        "{}",
        stderr(&out)
    );
    let out = sweep("1/1000000000000");
    assert_eq!(out.status.code(), Some(2), "a usage error");
    assert!(
        stderr(&out).contains("at most 1000000 shards"),
        "{}",
        stderr(&out)
    );
    // --force recomputes the whole sweep unsharded.
    assert!(sweep("1/2").status.success());
    let out = rocking(
        d,
        &["run", p, "--outputs", "out", "--force", "--to", "sweep"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(d.join("out/s/capacities.parquet").exists());
    assert!(!d.join("out/s/capacities.shard-1-of-2.parquet").exists());
    // A run that stops at the sweep points at no report (the one there is
    // of an earlier state).
    assert!(!stdout(&out).contains("report"), "{}", stdout(&out));
}

#[test]
fn commands_refuse_what_cannot_mean_anything() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = write_pipeline(
        d,
        "phys",
        "ids = [\"RSN1111_KOBE_NIS000\"]\n[[block]]\nb = 0.2\nh = 1.0\neps = 0.8\n",
    );
    let p = pipe.to_str().unwrap();
    // A stage the pipeline does not need, before anything runs.
    for stage in ["fit", "convergence"] {
        let out = rocking(d, &[stage, p, "--outputs", "out"]);
        assert!(!out.status.success(), "{stage}");
        assert!(
            stderr(&out).contains(&format!("does not need `{stage}`")),
            "{}",
            stderr(&out)
        );
        assert!(
            !d.join("out/phys/capacities.parquet").exists(),
            "nothing ran"
        );
    }
    let out = rocking(
        d,
        &[
            "run",
            p,
            "--outputs",
            "out",
            "--from",
            "reduce",
            "--to",
            "sweep",
        ],
    );
    assert!(
        stderr(&out).contains("comes after --to"),
        "{}",
        stderr(&out)
    );
}

/// `simulate --model nonlinear --pga 1e50` (or `--eta 1e-50`) ran on and
/// on: the Taylor stepper's steps shrink with the forcing and, near
/// η = 1e-40, no longer end. Such intensities are refused, in a run and in
/// a grid; the exact stepper took them, and still takes η = 1e-12.
#[test]
fn intensities_beyond_any_record_are_refused_not_run_forever() {
    let dir = tempdir();
    let d = dir.path();
    let record = bundled_records().join("far-field/RSN1111_KOBE_NIS000.AT2");
    let record = record.to_str().unwrap();
    let base = [
        "simulate", "--record", record, "--b", "0.2", "--h", "0.9", "--eps", "0.7",
    ];
    for (how, value, model) in [
        ("--pga", "1e50", "nonlinear"),
        ("--eta", "1e-50", "nonlinear"),
        ("--eta", "1e-13", "linearized"),
    ] {
        let mut args = base.to_vec();
        args.extend([how, value, "--model", model]);
        let out = rocking(d, &args);
        assert!(!out.status.success(), "{how} {value}: {}", stdout(&out));
        assert!(stderr(&out).contains("is below 1e-12"), "{}", stderr(&out));
    }
    let mut args = base.to_vec();
    args.extend(["--eta", "1e-12", "--model", "linearized"]);
    let out = rocking(d, &args);
    assert!(out.status.success(), "{}", stderr(&out));
}

/// `run --outputs F` with F a file said "cannot take the lock caused by:
/// Not a directory"; with `<outputs>/<name>` a file, "File exists"; and
/// `status` there exited 0, every stage stale.
#[test]
fn an_outputs_path_that_is_a_file_is_named_as_one() {
    let dir = tempdir();
    let d = dir.path();
    let pipeline = root().join("pipelines/quick.toml");
    let pipeline = pipeline.to_str().unwrap();
    fs::write(d.join("f"), "a file").unwrap();
    fs::create_dir_all(d.join("o")).unwrap();
    fs::write(d.join("o/quick"), "a file").unwrap();
    for (outputs, file) in [("f", "f"), ("o", "o/quick")] {
        for command in ["run", "status"] {
            let out = rocking(d, &[command, pipeline, "--outputs", outputs]);
            assert!(!out.status.success(), "{command} --outputs {outputs}");
            let want = format!("--outputs {outputs}: {file} is a file, not a folder");
            assert!(stderr(&out).contains(&want), "{}", stderr(&out));
        }
    }
    assert_eq!(fs::read_to_string(d.join("o/quick")).unwrap(), "a file");
}

/// `contents` named options it does not have (`--direct`, `--records`,
/// `--period`), refused ζ = 1.5 only after every ground set had run (252
/// runs), and took one set name twice. Each is refused at once, naming the
/// option as given.
#[test]
fn contents_refuses_its_own_options_by_name_before_running() {
    let dir = tempdir();
    let d = dir.path();
    let ff = bundled_records().join("far-field");
    let set = format!("ff={}", ff.display());
    // A set with a bad AT2 file: its hint named --records, under --direct.
    fs::create_dir_all(d.join("bad")).unwrap();
    fs::write(d.join("bad/X.AT2"), "junk\n").unwrap();
    for (args, want) in [
        (
            vec!["contents", "--set", &set, "--auto-tol", "0"],
            "--auto-tol 0: auto tolerance 0 must be in (0, 1)".to_string(),
        ),
        (
            vec!["contents", "--set", "b=bad"],
            "1 bad file(s); nothing was written (fix them, or give --set a folder of good AT2 \
             files)"
                .to_string(),
        ),
        (
            vec!["contents", "--set", "a=nowhere"],
            "--set a=nowhere: not a folder".to_string(),
        ),
        (
            vec!["contents", "--set", &set, "--set", &set],
            format!("--set {set}: the name is given to another set too"),
        ),
        (
            vec!["contents", "--set", &set, "--zeta", "1.5", "--periods", "1"],
            "the building of --periods 1 s, --zeta 1.5, --gamma-phi 1.3".to_string(),
        ),
        // A negative number was refused by the parser as "unexpected
        // argument '-0'", a token never typed.
        (
            vec![
                "contents",
                "--set",
                &set,
                "--zeta",
                "-0.1",
                "--periods",
                "1",
            ],
            "the building of --periods 1 s, --zeta -0.1, --gamma-phi 1.3".to_string(),
        ),
        // A repeated period ran twice (one table column, two JSON rows).
        (
            vec!["contents", "--set", &set, "--periods", "0.5,1,0.5"],
            "--periods: 0.5 s is given twice (the 3rd and an earlier one)".to_string(),
        ),
    ] {
        let out = rocking(d, &args);
        assert!(!out.status.success(), "{args:?}");
        let e = stderr(&out);
        assert!(e.contains(&want), "{args:?}: {e}");
        assert!(
            !e.contains("--direct") && !e.contains("--records") && !e.contains("runs/s"),
            "{args:?}: {e}"
        );
    }
}

/// Refusals that did not name the option given: `capacity --tol 0`
/// ("capacity tolerance 0 must be positive", after reading the records),
/// `--levels 0` ("IM grid: at least one level"), `--eta-min 0`,
/// `fragility --pga 0` ("--at 0"), `run --threads 0` ("worker threads"),
/// `simulate --history h.txt` ("give a .parquet file", where .csv is taken
/// too).
#[test]
fn refusals_name_the_option_as_given() {
    let dir = tempdir();
    let d = dir.path();
    let record = bundled_records().join("far-field/RSN1111_KOBE_NIS000.AT2");
    let record = record.to_str().unwrap();
    let block = ["--b", "0.2", "--h", "0.9", "--eps", "0.7"];
    let pipeline = root().join("pipelines/quick.toml");
    let pipeline = pipeline.to_str().unwrap();
    let capacity = |extra: &[&'static str]| {
        let mut a = vec!["capacity", "--record", record];
        a.extend(block);
        a.extend(extra);
        a
    };
    let mut simulate = vec!["simulate", "--record", record, "--pga", "0.3"];
    simulate.extend(block);
    simulate.extend(["--history", "h.txt"]);
    let mut fragility = vec!["fragility", "--pga", "0.3,0"];
    fragility.extend(block);
    for (args, want) in [
        (
            capacity(&["--tol", "0"]),
            "--tol 0: give a positive width in η",
        ),
        (
            capacity(&["--levels", "0"]),
            "--levels 0: give one level or more",
        ),
        (
            capacity(&["--eta-min", "0"]),
            "--eta-min 0: give an η in [1e-12, 1)",
        ),
        (
            vec![
                "capacity", "--record", record, "--p", "2", "--eps", "0.7", "--alpha", "-0.1",
            ],
            "--alpha -0.1: the slenderness α is an angle in (0, π/2) rad",
        ),
        (fragility, "--pga 0: levels must be positive"),
        (
            vec!["run", pipeline, "--threads", "0", "--outputs", "o"],
            "--threads 0: give one worker thread or more",
        ),
        (simulate, "--history h.txt: give a .parquet or .csv file"),
    ] {
        let out = rocking(d, &args);
        assert!(!out.status.success(), "{args:?}");
        assert!(stderr(&out).contains(want), "{args:?}: {}", stderr(&out));
    }
    assert!(!d.join("h.txt").exists() && !d.join("o").exists());
}

/// A failed export left its `--out` folder behind, empty (with a lock's
/// leftovers at times); one the user made stays.
#[test]
fn a_failed_export_leaves_no_folder_it_made() {
    let dir = tempdir();
    let d = dir.path();
    let args = |out: &'static str| {
        vec![
            "export", "--format", "pelicun", "--b", "0.2", "--h", "0.9", "--states", "a=0.5",
            "--out", out,
        ]
    };
    let out = rocking(d, &args("made"));
    assert!(!out.status.success());
    assert!(stderr(&out).contains("paper's regression knows only overturning"));
    assert!(!d.join("made").exists());
    fs::create_dir_all(d.join("mine")).unwrap();
    assert!(!rocking(d, &args("mine")).status.success());
    assert!(d.join("mine").is_dir());
}

/// `--eps` beside `--inventory` was ignored: every block took its own
/// column's ε (or Housner's), `risk` gave Housner's rate and `export` wrote
/// a median of 0.4484 g for ε = 0.5, whose own is 0.9156 g. Refused, as
/// `--mu` is, in `risk` and `export`.
#[test]
fn an_inventorys_eps_is_not_given_beside_it() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(d.join("i.csv"), "name,b,h\na,0.2,0.9\n").unwrap();
    let hazard = root().join("records/hazard/synthetic-site.csv");
    for args in [
        vec!["risk", "--hazard", hazard.to_str().unwrap()],
        vec!["export", "--format", "pelicun", "--out", "e"],
    ] {
        let mut args = args;
        args.extend(["--inventory", "i.csv", "--eps", "0.5"]);
        let out = rocking(d, &args);
        assert!(!out.status.success(), "{args:?}");
        assert!(
            stderr(&out).contains("--eps 0.5 is an inventory's column (`eps`): give it there"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
    assert!(!d.join("e").exists());
}

/// Options that did nothing where they were given, without a word: records
/// without `--direct` (the paper's regression answered), a seed without a
/// bootstrap, an angle step without orientations, a time or a tail rule
/// beside `--gmf` (the fields count their own years); and a step of 0.01°
/// (about 80 GB held at once), a "90 % band" of one resample.
#[test]
fn options_that_would_do_nothing_are_refused_by_name() {
    let dir = tempdir();
    let d = dir.path();
    let hazard = root().join("records/hazard/synthetic-site.csv");
    let hazard = hazard.to_str().unwrap();
    let gmf = root().join("records/gmf");
    let gmf = gmf.to_str().unwrap();
    let pulse = bundled_records().join("near-field-pulse");
    let pulse = pulse.to_str().unwrap();
    let block = ["--b", "0.2", "--h", "0.9"];
    for (args, says) in [
        (
            vec!["risk", "--hazard", hazard, "--records", pulse],
            "records are run with --direct",
        ),
        (
            vec!["fragility", "--pga", "0.3", "--records", pulse],
            "records are run with --direct",
        ),
        (
            vec!["risk", "--hazard", hazard, "--seed", "5"],
            "--seed 5 seeds --bootstrap's",
        ),
        (
            vec!["fragility", "--pga", "0.3", "--angle-step", "5"],
            "--angle-step 5 is the step",
        ),
        (
            vec![
                "fragility",
                "--pga",
                "0.3",
                "--direct",
                "--orientation",
                "random",
                "--angle-step",
                "0.01",
            ],
            "--angle-step 0.01: the angle step is in degrees, in [1, 180]",
        ),
        (
            vec!["risk", "--gmf", gmf, "--years", "10"],
            "--years 10 is for hazard curves",
        ),
        (
            vec!["risk", "--gmf", gmf, "--beyond", "stop"],
            "--beyond stop is for hazard curves",
        ),
        (
            vec!["risk", "--hazard", hazard, "--direct", "--bootstrap", "1"],
            "--bootstrap 1: a 90 % band needs at least 20 resamples",
        ),
    ] {
        let mut args = args;
        args.extend(block);
        let out = rocking(d, &args);
        assert!(!out.status.success(), "{args:?}");
        assert!(stderr(&out).contains(says), "{args:?}: {}", stderr(&out));
    }
}

/// An inventory in cm (`statue,20,90`) ran as a 180 m block without a
/// word (with `--direct`, 9.1e-7 /yr): every command now says its sizes
/// are a building's; a transformer's 1.2 m half-height is not.
#[test]
fn a_block_the_size_of_a_building_is_warned_of() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("cm.csv"),
        "name,b,h\nstatue_cm,20,90\ntransformer,0.6,1.2\n",
    )
    .unwrap();
    let hazard = root().join("records/hazard/synthetic-site.csv");
    let out = rocking(
        d,
        &[
            "risk",
            "--hazard",
            hazard.to_str().unwrap(),
            "--inventory",
            "cm.csv",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let e = stderr(&out);
    let warned: Vec<&str> = e
        .lines()
        .filter(|l| l.contains("a building's size"))
        .collect();
    assert_eq!(warned.len(), 1, "{e}");
    assert!(warned[0].contains("statue_cm") && warned[0].contains("were they given in cm?"));
    let out = rocking(d, &["fragility", "--b", "20", "--h", "90", "--pga", "0.3"]);
    assert!(
        stderr(&out).contains("a block 180 m tall is a building's size"),
        "{}",
        stderr(&out)
    );
    // A pipeline's [[block]] in cm ran without a word: its sweep says so
    // (the size from p and α, as the pipeline keeps it), of that block only.
    let pipeline = write_pipeline(
        d,
        "big",
        "ids = [\"RSN1111_KOBE_NIS000\"]\n\
         [[block]]\nname = \"statue_cm\"\nb = 20\nh = 90\neps = 0.9\n\
         [[block]]\nname = \"statue\"\nb = 0.2\nh = 0.9\neps = 0.9\n",
    );
    let out = rocking(
        d,
        &[
            "run",
            pipeline.to_str().unwrap(),
            "--to",
            "sweep",
            "--outputs",
            "o",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let all = format!("{}{}", stdout(&out), stderr(&out));
    let warned: Vec<&str> = all
        .lines()
        .filter(|l| l.contains("a building's size"))
        .collect();
    assert_eq!(warned.len(), 1, "{all}");
    assert!(
        warned[0].contains("block `statue_cm`: half-width 20 m, half-height 90 m: a block 180 m"),
        "{all}"
    );
    // `simulate` and `capacity` ran such a block without a word: they say
    // it once, however many ε it is run at; a statue's size is not.
    let kobe = root().join("records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2");
    let kobe = kobe.to_str().unwrap();
    for (b, h, warns) in [("20", "90", 1), ("0.2", "0.9", 0)] {
        let block = ["--record", kobe, "--b", b, "--h", h];
        let sim = [&["simulate"][..], &block, &["--eps", "0.9", "--pga", "0.3"]].concat();
        let cap = [
            &["capacity"][..],
            &block,
            &["--eps", "0.8,0.9", "--levels", "20"],
        ]
        .concat();
        for args in [sim, cap] {
            let out = rocking(d, &args);
            assert!(out.status.success(), "{args:?}: {}", stderr(&out));
            let e = stderr(&out);
            let said = e.matches("a block 180 m tall is a building's size").count();
            assert_eq!(said, warns, "{args:?}: {e}");
        }
    }
}

/// Levels given in another unit than the IM's: `fragility --pga` in m/s²
/// (P = 1 without a word), also with `--states`, and `--im pgv --at` in
/// m/s (P = 0). Each is warned of, with the factor; levels in the IM's unit
/// are not, nor a hazard curve whose tail runs past 5 g (its levels cover
/// the tail, where levels asked of `fragility` do not).
#[test]
fn levels_in_another_unit_are_warned_of() {
    let dir = tempdir();
    let d = dir.path();
    let says = |args: &[&str], what: &str| {
        let out = rocking(d, args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        stderr(&out).contains(what)
    };
    let m_s2 = "are they in m/s²? Divide them by 9.80665 for g";
    let frag = ["fragility", "--b", "0.2", "--h", "0.9", "--pga"];
    assert!(says(&[&frag[..], &["2.94,9.8"]].concat(), m_s2));
    assert!(!says(&[&frag[..], &["0.3,0.5,1"]].concat(), m_s2));
    let states = ["--direct", "--states", "rocking=0.1,overturned=overturned"];
    assert!(says(&[&frag[..], &["2.94,9.8"], &states].concat(), m_s2));
    // A PGA hazard in g whose tail reaches 8 g.
    let mut curve = String::from("pga_g,annual_rate\n");
    for (a, rate) in [(0.05, 1e-2), (0.5, 1e-3), (2.0, 2e-5), (8.0, 1e-8)] {
        curve.push_str(&format!("{a},{rate}\n"));
    }
    fs::write(d.join("tail.csv"), curve).unwrap();
    let risk = ["risk", "--hazard", "tail.csv", "--b", "0.2", "--h", "0.9"];
    assert!(!says(&risk, m_s2));
    let pgv = [&frag[..5], &["--im", "pgv", "--direct", "--at"]].concat();
    let m_s = "are they in m/s? Multiply them by 100 for cm/s";
    assert!(says(&[&pgv[..], &["0.3,0.5"]].concat(), m_s));
    assert!(!says(&[&pgv[..], &["30,50"]].concat(), m_s));
}

/// One record under two names (a copied AT2 file) ran twice and counted
/// twice in every fractile. It is a bad file now, named beside the one it
/// repeats: `--direct` refuses it, and `ingest --skip-bad` keeps one.
#[test]
fn one_motion_under_two_names_is_a_bad_file() {
    let dir = tempdir();
    let d = dir.path();
    let far = bundled_records().join("far-field");
    fs::create_dir_all(d.join("suite")).unwrap();
    for id in [
        "RSN1111_KOBE_NIS000",
        "RSN953_NORTHR_MUL009",
        "RSN848_LANDERS_CLW-LN",
        "RSN1148_KOCAELI_ARC000",
        "RSN1633_MANJIL_ABBAR--L",
    ] {
        fs::copy(
            far.join(format!("{id}.AT2")),
            d.join(format!("suite/{id}.AT2")),
        )
        .unwrap();
    }
    // The same samples under another header line and name: still one motion.
    let kobe = fs::read_to_string(far.join("RSN1111_KOBE_NIS000.AT2")).unwrap();
    let copy = kobe.replacen("Kobe", "Kobe (copy)", 1);
    assert_ne!(copy, kobe);
    fs::write(d.join("suite/KOBE_COPY.AT2"), copy).unwrap();
    let out = rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
            "suite",
            "--pga",
            "0.3",
        ],
    );
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("1 bad file(s)")
            && e.contains("suite/RSN1111_KOBE_NIS000.AT2: the same motion as suite/KOBE_COPY.AT2"),
        "{e}"
    );
    let out = rocking(
        d,
        &["ingest", "suite", "--skip-bad", "--out", "records.parquet"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let rows: Vec<rocking::tables::records::RecordRow> =
        rocking::tables::read(&d.join("records.parquet")).unwrap();
    assert_eq!(rows.len(), 5, "{}", stderr(&out));
}

/// μ = 1.5 was refused with `--direct` (the slide-rock model's range,
/// (0, 1.3]) and taken without it, and an inventory took μ = 5. One range
/// now, by the option or the inventory's line.
#[test]
fn friction_has_one_range_at_every_door() {
    let dir = tempdir();
    let d = dir.path();
    let want = "μ = 1.5 must be in (0, 1.3]";
    for direct in [false, true] {
        let mut args = vec![
            "fragility",
            "--b",
            "0.3",
            "--h",
            "1",
            "--mu",
            "1.5",
            "--pga",
            "0.5",
        ];
        if direct {
            args.push("--direct");
        }
        let out = rocking(d, &args);
        assert!(!out.status.success(), "{args:?}");
        assert!(
            stderr(&out).contains(&format!("--mu: friction coefficient {want}")),
            "{}",
            stderr(&out)
        );
    }
    fs::write(
        d.join("inv.csv"),
        "name,b,h,eps,mu\nstatue,0.2,0.9,0.9,0.5\nsafe,0.3,1.0,0.8,1.5\n",
    )
    .unwrap();
    let hazard = root().join("records/hazard/synthetic-site.csv");
    let out = rocking(
        d,
        &[
            "risk",
            "--hazard",
            hazard.to_str().unwrap(),
            "--inventory",
            "inv.csv",
        ],
    );
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("inv.csv:3: block `safe`: `mu`") && e.contains(want),
        "{e}"
    );
}

/// A set the manifest does not name (`far-feild`) passed `run --to ingest`,
/// which ingested every record, and was refused only by the sweep, as the
/// sweep's failure. It is refused on load, naming the pipeline, the
/// manifest and the sets it has, before any stage writes.
#[test]
fn a_set_the_manifest_lacks_is_refused_on_load() {
    let dir = tempdir();
    let d = dir.path();
    let pipeline = write_pipeline(
        d,
        "typo",
        "sets = [\"far-feild\"]\n[[block]]\nb = 0.2\nh = 0.9\neps = 0.9\n",
    );
    for args in [&["run", "--to", "ingest"][..], &["status"]] {
        let out = rocking(
            d,
            &[args, &[pipeline.to_str().unwrap(), "--outputs", "out"]].concat(),
        );
        assert!(!out.status.success(), "{args:?}");
        let e = stderr(&out);
        assert!(
            e.contains(
                "typo.toml: `records.sets` names \"far-feild\", which no record of the manifest"
            ) && e.contains("available: far-field, near-field-no-pulse, near-field-pulse"),
            "{e}"
        );
        assert!(!d.join("out").join("typo").exists());
    }
    // Spelled right, it ingests.
    let fixed = write_pipeline(
        d,
        "fixed",
        "sets = [\"far-field\"]\n[[block]]\nb = 0.2\nh = 0.9\neps = 0.9\n",
    );
    let out = rocking(
        d,
        &[
            "run",
            "--to",
            "ingest",
            fixed.to_str().unwrap(),
            "--outputs",
            "out",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
}

/// Inputs a pipeline names that no file answers were found by a stage:
/// `records.ids` naming no record ran the ingest and failed the sweep
/// without the pipeline's name, and a missing `records.at2` folder or
/// manifest gave a bare "No such file or directory". Each is refused on
/// load, naming the pipeline and the key, before any stage writes.
#[test]
fn records_no_file_answers_are_refused_on_load_by_key() {
    let dir = tempdir();
    let d = dir.path();
    let block = "[[block]]\nb = 0.2\nh = 0.9\neps = 0.9\n";
    let ids = write_pipeline(
        d,
        "ids",
        &format!("ids = [\"RSN1111_KOBE_NIS000\", \"NOPE\"]\n{block}"),
    );
    let missing = d.join("missing.toml");
    fs::write(
        &missing,
        format!("name = \"missing\"\n[records]\nat2 = [\"nope\"]\n{block}"),
    )
    .unwrap();
    let no_manifest = d.join("nomanifest.toml");
    fs::write(
        &no_manifest,
        format!(
            "name = \"nomanifest\"\n[records]\nat2 = [\"{}\"]\nmanifest = \"none.csv\"\n{block}",
            bundled_records().display()
        ),
    )
    .unwrap();
    for (pipeline, says) in [
        (
            &ids,
            "ids.toml: `records.ids` names NOPE, which no file of `records.at2` bears",
        ),
        (&missing, "missing.toml: `records.at2` = "),
        (&no_manifest, "nomanifest.toml: `records.manifest` = "),
    ] {
        for args in [&["run"][..], &["status"]] {
            let out = rocking(
                d,
                &[args, &[pipeline.to_str().unwrap(), "--outputs", "out"]].concat(),
            );
            assert!(!out.status.success(), "{args:?}");
            let e = stderr(&out);
            assert!(e.contains(says), "{args:?}: {e}");
            assert!(!d.join("out").exists(), "{e}");
        }
    }
}

/// A study folder that holds the pipeline file (outputs pointed at the
/// pipeline's own folder) had its `report.md` overwritten by the report
/// stage. Refused on load; the file is left as it was.
#[test]
fn a_pipeline_inside_its_studys_folder_is_refused() {
    let dir = tempdir();
    let d = dir.path();
    let own = d.join("own");
    fs::create_dir_all(&own).unwrap();
    let pipeline = write_pipeline(
        &own,
        "own",
        "sets = [\"far-field\"]\n[[block]]\nb = 0.2\nh = 0.9\neps = 0.9\n",
    );
    fs::write(own.join("report.md"), "my notes").unwrap();
    let out = rocking(
        &own,
        &["run", pipeline.to_str().unwrap(), "--outputs", ".."],
    );
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("own.toml: the pipeline file is inside the study's folder"),
        "{e}"
    );
    assert_eq!(
        fs::read_to_string(own.join("report.md")).unwrap(),
        "my notes"
    );
    assert_eq!(fs::read_dir(&own).unwrap().count(), 2);
}

/// Two pipelines of one name share a study folder; the second, without an
/// `[example]`, dropped the example stage's note but left its tables,
/// which an analyst of the folder took for the study's. A stage the
/// pipeline no longer needs takes its tables with it, those still as it
/// wrote them: one the user has changed since stays.
#[test]
fn a_stage_no_longer_needed_takes_its_own_tables_with_it() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = mini(d);
    let plain = fs::read_to_string(&pipe).unwrap();
    let with_example = format!("{plain}[example]\np = 2.0\neps = 0.7\n");
    let example = |name: &str| d.join("out/mini").join(name);
    for keep_one in [false, true] {
        fs::write(&pipe, &with_example).unwrap();
        let out = rocking(d, &["run", "mini.toml", "--outputs", "out"]);
        assert!(out.status.success(), "{}", stderr(&out));
        let tables = rocking::stages::example::OUTPUTS;
        assert!(tables.iter().all(|t| example(t).exists()));
        if keep_one {
            fs::write(example(tables[0]), b"the user's own notes").unwrap();
        }
        fs::write(&pipe, &plain).unwrap();
        let out = rocking(d, &["run", "mini.toml", "--outputs", "out"]);
        assert!(out.status.success(), "{}", stderr(&out));
        for (i, t) in tables.iter().enumerate() {
            assert_eq!(
                example(t).exists(),
                keep_one && i == 0,
                "{t}, kept one: {keep_one}"
            );
        }
        assert!(example("capacities.parquet").exists());
        let _ = fs::remove_file(example(tables[0]));
    }
}

/// A list or a mode that starts with a minus sign reaches the command's
/// own check: the parser took `-0.5,0.05,1.3` for an option and said
/// "unexpected argument '-0' found", a token never typed (Python gave the
/// library's refusal all along).
#[test]
fn lists_starting_with_a_minus_sign_reach_their_own_checks() {
    let d = &root();
    let kobe = "records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2";
    let sim = [
        "simulate", "--record", kobe, "--b", "0.2", "--h", "1", "--eps", "0.9", "--pga", "0.3",
    ];
    let with = |base: &[&'static str], more: &[&'static str]| {
        let mut a = base.to_vec();
        a.extend(more);
        a
    };
    let frag = ["fragility", "--b", "0.2", "--h", "0.9"];
    for (args, says) in [
        (
            with(&sim, &["--floor", "-0.5,0.05,1.3"]),
            "--floor: mode 1: period T = -0.5 s",
        ),
        (
            with(&sim, &["--building", "-0.5,0.05,1.3,1", "--level", "1"]),
            "--building: mode 1: period T = -0.5 s",
        ),
        (
            with(&frag, &["--pga", "-0.3,0.5"]),
            "--pga -0.3: levels must be positive",
        ),
        (
            with(&frag, &["--at", "-0.3,0.5"]),
            "--at -0.3: levels must be positive",
        ),
        (
            vec!["ims", "--record", kobe, "--period", "-1"],
            "--period -1: a period must be a positive number of seconds",
        ),
        // Taking values with a minus sign, an option takes the next option
        // for its value when its own is missing: said as such.
        (
            with(&sim, &["--floor", "--json"]),
            "a value is missing: `--json` is the next option",
        ),
        (
            vec!["fragility", "--b", "0.2", "--h", "--pga", "0.3"],
            "a value is required for '--h <m>'",
        ),
    ] {
        let out = rocking(d, &args);
        assert!(!out.status.success(), "{args:?}");
        let e = stderr(&out);
        assert!(
            e.contains(says) && !e.contains("unexpected argument"),
            "{args:?}: {e}"
        );
    }
}

/// A study in which no block overturns (its grid stops at η = 0.9) writes
/// its report: Fig. 7 has nothing a log axis can show (every fractile 0)
/// and is left out, where the report stage failed on it ("nothing to
/// plot"); every figure the report links is on disk.
#[test]
fn a_study_where_nothing_overturns_has_its_report() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = write_pipeline(
        d,
        "never",
        "ids = [\"RSN1111_KOBE_NIS000\", \"RSN953_NORTHR_MUL009\", \"RSN1633_MANJIL_ABBAR--L\"]\n\
         [blocks]\np = [0.5, 1.0]\neps = [0.7, 0.9]\n[im]\ncount = 10\neta_min = 0.9\n",
    );
    let out = rocking(d, &["run", pipe.to_str().unwrap(), "--outputs", "out"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let study = d.join("out/never");
    let caps = read_capacities(&study).unwrap();
    assert!(caps.iter().all(|c| c.eta_c.is_none()), "a block overturned");
    let md = fs::read_to_string(study.join("report.md")).unwrap();
    assert!(!md.contains("fig07"), "{md}");
    let linked: Vec<&str> = md
        .split("figures/")
        .skip(1)
        .filter_map(|s| s.split(".svg").next())
        .collect();
    assert!(!linked.is_empty());
    for name in linked {
        assert!(
            study.join(format!("figures/{name}.svg")).is_file(),
            "{name}"
        );
    }
}

/// A sweep run in shards whose settings then changed: `status` said "never
/// run here (no fingerprint)" and `run` redid the whole sweep here,
/// unsharded, where one shard of two stale made it refuse. Both shards
/// stale now read as one stale: the shards' reason, and a refusal that
/// says how to rerun them (or --force to run it here).
#[test]
fn a_sharded_sweep_whose_settings_changed_is_not_redone_here_unasked() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = write_pipeline(d, "s", THREE_CHUNKS);
    let p = pipe.to_str().unwrap();
    for shard in ["1/2", "2/2"] {
        let out = rocking(d, &["sweep", p, "--outputs", "out", "--shard", shard]);
        assert!(out.status.success(), "{}", stderr(&out));
    }
    // The same study with another tolerance.
    write_pipeline(d, "s", &format!("{THREE_CHUNKS}tol = 2e-4\n"));
    let out = rocking(d, &["status", p, "--outputs", "out"]);
    let said = format!("{}{}", stdout(&out), stderr(&out));
    let sweep_line = said
        .lines()
        .find(|l| l.starts_with("sweep"))
        .expect("a sweep line");
    assert!(
        sweep_line.contains("settings changed")
            && sweep_line.contains("shards 1/2, 2/2 are missing or stale")
            && !sweep_line.contains("never run here"),
        "{said}"
    );
    let out = rocking(d, &["run", p, "--outputs", "out", "--to", "sweep"]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("settings changed")
            && err.contains("--shard K/2")
            && err.contains(&format!("`rocking sweep {p} --outputs out --force`")),
        "{err}"
    );
    assert!(d.join("out/s/capacities.shard-1-of-2.parquet").exists());
    // Asked to, it runs here.
    let out = rocking(
        d,
        &["run", p, "--outputs", "out", "--to", "sweep", "--force"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
}

/// At ε = 1 no impact loses energy, so a block that barely lifts hops
/// without end; at p ≈ 855 1/s (a 10 µm block) the hops are so short that
/// a record's run reaches the event cap. That is the physics of ε = 1, not
/// a fault of the tool, and the refusal says so (it asked for a bug report).
#[test]
fn an_endless_chatter_at_eps_1_is_named_not_called_a_fault() {
    let dir = tempdir();
    let kobe = bundled_records().join("far-field/RSN1111_KOBE_NIS000.AT2");
    let args = [
        "capacity",
        "--record",
        kobe.to_str().unwrap(),
        "--b",
        "1e-6",
        "--h",
        "1e-5",
        "--model",
        "nonlinear",
        "--eps",
    ];
    let out = rocking(dir.path(), &[&args[..], &["1"]].concat());
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(e.contains("ε = 1 loses no energy at an impact"), "{e}");
    assert!(!e.contains("a fault of the tool"), "{e}");
    // With energy lost at each impact, the same block has a capacity.
    let out = rocking(dir.path(), &[&args[..], &["0.9", "--json"]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).contains("\"eta_c\""));
}
