//! `rocking ingest`: the bundled records against their manifest and files,
//! bad input, atomic output and a stable row order.

use std::collections::HashMap;
use std::fs;

use rocking::tables::records;

use crate::util::{
    at2_text, bundled_records, plain_at2_values, rocking, root, stderr, stdout, tempdir, TempDir,
};

/// Manifest rows keyed by file stem, read with the csv crate by column name
/// (independently of `rocking::manifest`).
fn manifest_by_stem() -> HashMap<String, HashMap<String, String>> {
    let mut reader = csv::Reader::from_path(bundled_records().join("manifest.csv")).unwrap();
    let headers = reader.headers().unwrap().clone();
    reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            let row: HashMap<String, String> = headers
                .iter()
                .zip(r.iter())
                .map(|(h, v)| (h.to_string(), v.to_string()))
                .collect();
            let stem = row["file"]
                .rsplit('/')
                .next()
                .unwrap()
                .trim_end_matches(".AT2")
                .to_string();
            (stem, row)
        })
        .collect()
}

/// A record the manifest lists in a set whose files are ingested, but
/// without a file of its own, was passed over without a word (a pair run
/// on one component): `ingest` and a pipeline's run name it; the sets of
/// no file ingested (the near-field ones, beside a far-field folder) are
/// not named.
#[test]
fn a_manifest_record_without_its_file_is_named() {
    let dir = tempdir();
    let far = dir.path().join("far-field");
    std::fs::create_dir(&far).unwrap();
    let gone = "RSN953_NORTHR_MUL279";
    for e in std::fs::read_dir(bundled_records().join("far-field")).unwrap() {
        let path = e.unwrap().path();
        if path.file_stem().unwrap() != gone {
            std::fs::copy(&path, far.join(path.file_name().unwrap())).unwrap();
        }
    }
    let manifest = bundled_records().join("manifest.csv");
    let out = dir.path().join("records.parquet");
    let run = rocking(
        dir.path(),
        &[
            "ingest",
            far.to_str().unwrap(),
            "--manifest",
            manifest.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let err = stderr(&run);
    assert!(
        err.contains("warning: 1 record(s) the manifest lists in a set ingested have no file")
            && err.contains(gone),
        "{err}"
    );
    assert!(!err.contains("RSN1063"), "a near-field record named: {err}");
    let pipeline = dir.path().join("p.toml");
    std::fs::write(
        &pipeline,
        format!(
            "name = \"p\"\n[records]\nat2 = [\"{}\"]\nmanifest = \"{}\"\n[blocks]\np = [2.0]\neps = [0.8]\n",
            far.display(),
            manifest.display()
        ),
    )
    .unwrap();
    let run = rocking(
        dir.path(),
        &["run", pipeline.to_str().unwrap(), "--to", "ingest"],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let all = format!("{}{}", stdout(&run), stderr(&run));
    assert!(all.contains(gone) && all.contains("have no file"), "{all}");
}

#[test]
fn bundled_records_match_manifest_and_files() {
    let dir = tempdir();
    let out = dir.path().join("records.parquet");
    let run = rocking(
        &root(),
        &[
            "ingest",
            "records/fema-p695",
            "--manifest",
            "records/fema-p695/manifest.csv",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(run.status.success(), "{}", stderr(&run));

    let rows = records::read(&out).unwrap();
    let manifest = manifest_by_stem();
    assert_eq!(rows.len(), 100);
    assert_eq!(manifest.len(), 100);

    for row in &rows {
        let m = &manifest[&row.record_id];
        let npts: usize = m["npts"].parse().unwrap();
        let dt: f64 = m["dt"].parse().unwrap();
        let pga: f64 = m["pga_g"].parse().unwrap();
        assert_eq!(row.accel_g.len(), npts, "{}", row.record_id);
        assert_eq!(row.dt_s, dt, "{}", row.record_id);
        // The manifest prints PGA to 6 decimals: half a unit in the last place.
        assert!(
            (row.pga_g - pga).abs() <= 0.5e-6 + 1e-15,
            "{}: {} vs {pga}",
            row.record_id,
            row.pga_g
        );
        assert_eq!(row.meta.set.as_deref(), Some(m["set"].as_str()));
        assert_eq!(row.meta.rsn, Some(m["rsn"].parse().unwrap()));
        assert_eq!(row.meta.event.as_deref(), Some(m["event"].as_str()));
        assert_eq!(
            row.meta.normalization_factor,
            Some(m["normalization_factor"].parse().unwrap())
        );
        // Duration is (N − 1)·dt and the PGA time is on the sample grid.
        assert_eq!(row.duration_s, (npts - 1) as f64 * dt);
        let k = (row.pga_time_s / dt).round() as usize;
        assert_eq!(row.accel_g[k].abs(), row.pga_g);
        assert_eq!(row.sha256.len(), 64);
    }

    // Stable order: sorted by record id.
    let ids: Vec<&str> = rows.iter().map(|r| r.record_id.as_str()).collect();
    let mut sorted = ids.clone();
    sorted.sort();
    assert_eq!(ids, sorted);

    // Samples value by value against an independent reading of the files,
    // including the longest record (18,000 samples) and a 0.0024 s one.
    for stem in [
        "RSN953_NORTHR_MUL009",
        "RSN1602_DUZCE_BOL000",
        "RSN1111_KOBE_NIS000",
    ]
    .into_iter()
    .chain(
        rows.iter()
            .filter(|r| r.accel_g.len() == 18000)
            .take(1)
            .map(|r| r.record_id.as_str()),
    )
    .chain(
        rows.iter()
            .filter(|r| r.dt_s < 0.0025)
            .take(1)
            .map(|r| r.record_id.as_str()),
    ) {
        let row = rows.iter().find(|r| r.record_id == stem).unwrap();
        let file = bundled_records().join(&manifest[stem]["file"]);
        let expected = plain_at2_values(&file);
        assert_eq!(row.accel_g.len(), expected.len(), "{stem}");
        for (i, (a, b)) in row.accel_g.iter().zip(&expected).enumerate() {
            assert_eq!(a.to_bits(), b.to_bits(), "{stem} sample {i}");
        }
    }
}

/// Writes `files` (name, text) into a fresh folder.
fn folder(files: &[(&str, &str)]) -> TempDir {
    let dir = tempdir();
    for (name, text) in files {
        let path = dir.path().join(name);
        fs::create_dir_all(path.parent().unwrap()).unwrap();
        fs::write(path, text).unwrap();
    }
    dir
}

const UNITS_G: &str = "ACCELERATION TIME SERIES IN UNITS OF G";

#[test]
fn bad_file_fails_everything_and_leaves_previous_output_untouched() {
    let good = at2_text(UNITS_G, "NPTS=   3, DT=   .0100 SEC", &[".1", "-.2", ".05"]);
    let short = at2_text(UNITS_G, "NPTS=   4, DT=   .0100 SEC", &[".1", "-.2", ".05"]);
    let dir = folder(&[("a/GOOD.AT2", &good), ("b/SHORT.at2", &short)]);
    let out = dir.path().join("out/records.parquet");
    fs::create_dir_all(out.parent().unwrap()).unwrap();
    fs::write(&out, b"previous output").unwrap();

    let run = rocking(dir.path(), &["ingest", ".", "--out", "out/records.parquet"]);
    assert!(!run.status.success());
    let err = stderr(&run);
    // Names the file and the line (the last line, 5, holds the third value).
    assert!(err.contains("SHORT.at2:5:"), "{err}");
    assert!(err.contains("NPTS = 4") && err.contains("3 value"), "{err}");
    assert_eq!(fs::read(&out).unwrap(), b"previous output");
    // No temporary file is left behind.
    assert_eq!(fs::read_dir(out.parent().unwrap()).unwrap().count(), 1);

    let run = rocking(
        dir.path(),
        &["ingest", ".", "--out", "out/records.parquet", "--skip-bad"],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    assert!(stderr(&run).contains("skipped:") && stderr(&run).contains("SHORT.at2"));
    let rows = records::read(&out).unwrap();
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0].record_id, "GOOD");
    assert_eq!(rows[0].accel_g, vec![0.1, -0.2, 0.05]);
    assert_eq!(rows[0].pga_g, 0.2);
    assert_eq!(rows[0].pga_time_s, 0.01);
    // Without a manifest the metadata columns are empty.
    assert_eq!(rows[0].meta, rocking::manifest::RecordMeta::default());
}

#[test]
fn every_bad_file_is_reported_with_its_line() {
    let cases: &[(&str, String, &str)] = &[
        ("EMPTY.AT2", String::new(), "EMPTY.AT2:1: the file is empty"),
        (
            "NONUM.AT2",
            at2_text(UNITS_G, "NPTS=   2, DT=   .0100 SEC", &["0.1", "O.2"]),
            "NONUM.AT2:5: `O.2` is not a number",
        ),
        (
            "NAN.AT2",
            at2_text(UNITS_G, "NPTS=   2, DT=   .0100 SEC", &["0.1", "NaN"]),
            "NAN.AT2:5: `NaN` is not a finite number",
        ),
        (
            "MANY.AT2",
            at2_text(UNITS_G, "NPTS=   2, DT=   .0100 SEC", &["1", "2", "3"]),
            "MANY.AT2:5: more values than NPTS = 2",
        ),
        (
            "NODT.AT2",
            at2_text(UNITS_G, "NPTS=   2", &["1", "2"]),
            "NODT.AT2:4: no DT",
        ),
        (
            "ZERODT.AT2",
            at2_text(UNITS_G, "NPTS=   2, DT=   0.0 SEC", &["1", "2"]),
            "ZERODT.AT2:4: DT = 0 s",
        ),
        (
            "VEL.AT2",
            at2_text(
                "VELOCITY TIME SERIES IN UNITS OF CM/S",
                "NPTS=   2, DT=   .0100 SEC",
                &["1", "2"],
            ),
            "VEL.AT2:3: the units line",
        ),
    ];
    let files: Vec<(&str, &str)> = cases.iter().map(|(n, t, _)| (*n, t.as_str())).collect();
    let dir = folder(&files);
    let run = rocking(dir.path(), &["ingest", ".", "--out", "records.parquet"]);
    assert!(!run.status.success());
    let err = stderr(&run);
    assert!(
        err.contains(&format!("{} bad file(s)", cases.len())),
        "{err}"
    );
    for (_, _, expected) in cases {
        assert!(err.contains(expected), "missing `{expected}` in:\n{err}");
    }
    assert!(!dir.path().join("records.parquet").exists());

    // All bad with --skip-bad: still an error, still nothing written.
    let run = rocking(
        dir.path(),
        &["ingest", ".", "--out", "records.parquet", "--skip-bad"],
    );
    assert!(!run.status.success());
    assert!(
        stderr(&run).contains("every file was bad"),
        "{}",
        stderr(&run)
    );
    assert!(!dir.path().join("records.parquet").exists());
}

#[test]
fn old_layouts_and_crlf_read_alike() {
    let values = ["-.2483657E-03", "-2.4836570E-04", ".5000000E+00", "0.25"];
    let west2 = at2_text(
        UNITS_G,
        "NPTS=    4, DT=   .0200 SEC,   0 POLE @ 30.0 HZ",
        &values,
    );
    let cdmg = format!(
        "PEER STRONG MOTION DATABASE RECORD. PROCESSING BY CDMG.\nX\n\
         ACCELERATION TIME HISTORY IN UNITS OF G. FILTER POINTS: HP=0.07 Hz LP=23.0 Hz\n\
         NPTS=  4, DT= .02000 SEC\n{}\n",
        values.join(" ")
    );
    let old_nga = format!(
        "PEER NGA STRONG MOTION DATABASE RECORD\nX\nACCELERATION TIME HISTORY IN UNITS OF G\n\
         \x20    4    0.0200    NPTS, DT\n{}\n{}\n",
        values[..3].join(" "),
        values[3]
    );
    let crlf = west2.replace('\n', "\r\n");
    let dir = folder(&[
        ("W2.AT2", &west2),
        ("CDMG.AT2", &cdmg),
        ("OLD.AT2", &old_nga),
        ("CRLF.AT2", &crlf),
        ("VEL.VT2", "not read: only *.AT2 files are searched for"),
    ]);
    // One motion in four layouts: read together they would be one record
    // under four names (refused), so each is read on its own.
    let mut rows = Vec::new();
    for id in ["CDMG", "CRLF", "OLD", "W2"] {
        let (file, out) = (format!("{id}.AT2"), format!("{id}.parquet"));
        let run = rocking(dir.path(), &["ingest", &file, "--out", &out]);
        assert!(run.status.success(), "{}", stderr(&run));
        rows.extend(records::read(&dir.path().join(out)).unwrap());
    }
    let together = rocking(dir.path(), &["ingest", ".", "--out", "r.parquet"]);
    assert!(!together.status.success());
    assert!(
        stderr(&together).contains("3 bad file(s)")
            && stderr(&together).contains("the same motion as ./CDMG.AT2"),
        "{}",
        stderr(&together)
    );
    assert!(!dir.path().join("r.parquet").exists());
    for r in &rows {
        assert_eq!(
            r.accel_g,
            vec![-2.483657e-4, -2.483657e-4, 0.5, 0.25],
            "{}",
            r.record_id
        );
        assert_eq!(r.dt_s, 0.02);
        assert_eq!(r.pga_g, 0.5);
        assert_eq!(r.pga_time_s, 0.04);
        assert_eq!(r.duration_s, 0.06);
    }
    assert_eq!(rows[2].header_layout, "positional");
    assert_eq!(rows[0].header_layout, "keyed");
    assert!(!rows[1].header[3].ends_with('\r'));
}

#[test]
fn output_does_not_depend_on_argument_order() {
    let a = at2_text(UNITS_G, "NPTS= 2, DT= .01 SEC", &["1", "2"]);
    let b = at2_text(UNITS_G, "NPTS= 3, DT= .02 SEC", &["3", "-4", "5"]);
    let dir = folder(&[("x/A.AT2", &a), ("y/B.AT2", &b)]);
    let one = rocking(dir.path(), &["ingest", "x", "y", "--out", "1.parquet"]);
    let two = rocking(
        dir.path(),
        &["ingest", "y", "x/A.AT2", "x", "--out", "2.parquet"],
    );
    assert!(one.status.success() && two.status.success());
    // Same rows, same bytes (the paths setting differs, so compare rows).
    let r1 = records::read(&dir.path().join("1.parquet")).unwrap();
    let r2 = records::read(&dir.path().join("2.parquet")).unwrap();
    assert_eq!(r1, r2);
    assert_eq!(r1.len(), 2, "x/A.AT2 given twice is ingested once");
    // No manifest was given: the summary does not blame one.
    let said = String::from_utf8_lossy(&one.stdout);
    assert!(said.contains("2 without a set (no --manifest)"), "{said}");
}

#[test]
fn duplicate_stems_and_manifest_mismatches_are_refused() {
    let a = at2_text(UNITS_G, "NPTS= 2, DT= .01 SEC", &["1", "2"]);
    let dir = folder(&[("x/A.AT2", &a), ("y/A.AT2", &a)]);
    let run = rocking(dir.path(), &["ingest", ".", "--out", "r.parquet"]);
    assert!(!run.status.success());
    assert!(stderr(&run).contains("same record id"), "{}", stderr(&run));

    // One record, A.AT2, ingested with the manifest given.
    let with_manifest = |manifest: &str| {
        let dir = folder(&[("A.AT2", &a), ("manifest.csv", manifest)]);
        let args = [
            "ingest",
            "A.AT2",
            "--manifest",
            "manifest.csv",
            "--out",
            "r.parquet",
        ];
        rocking(dir.path(), &args)
    };
    let run = with_manifest("set,npts,dt,file\ntest,3,0.01,A.AT2\n");
    assert!(!run.status.success());
    let err = stderr(&run);
    assert!(
        err.contains("manifest.csv:2") && err.contains("npts = 3"),
        "{err}"
    );
    // The PGA is held to its printing, half a unit in its last digit, or
    // 0.1 %: 2.0 passes for the file's 2 g, 2.0019999 (a float32's noise,
    // or a truncation) too; 1.99 and 10 (another record's, or another
    // unit) are refused.
    for (pga, passes) in [
        ("2.0", true),
        ("2.00", true),
        ("2.0019999", true),
        ("1.99", false),
        ("10", false),
    ] {
        let run = with_manifest(&format!("set,npts,pga_g,file\ntest,2,{pga},A.AT2\n"));
        assert_eq!(run.status.success(), passes, "{pga}: {}", stderr(&run));
        if !passes {
            let err = stderr(&run);
            let says = format!("manifest pga_g = {pga} g, the file's peak 2 g");
            assert!(err.contains(&says), "{err}");
        }
    }

    let run = with_manifest("set,npts,file\ntest,2x,A.AT2\n");
    assert!(!run.status.success());
    let err = stderr(&run);
    assert!(
        err.contains("manifest.csv") && err.contains("line 2") && err.contains("`npts`"),
        "{err}"
    );
}

#[test]
fn missing_path_is_named() {
    let dir = tempdir();
    let run = rocking(
        dir.path(),
        &["ingest", "no-such-folder", "--out", "r.parquet"],
    );
    assert!(!run.status.success());
    assert!(stderr(&run).contains("no-such-folder"), "{}", stderr(&run));
}
