//! The FEMA P-58 workflow with the real tools (`ROCKING_ENGINES`: the
//! engines' venv, with OpenSeesPy beside pelicun, as `.ci/run` makes it):
//! an OpenSeesPy model of a small nonlinear building writes its floors'
//! motions by recorders; the tool states two FEMA P-58 bookcases'
//! fragilities in PFV from those motions and exports them to pelicun; then,
//! per floor, from the same demand sample (each record's PFV there):
//!
//! 1. pelicun's P(falls over) with FEMA's own components (E.20.22.104a and
//!    .106a of the DLML), a finding;
//! 2. pelicun's with the tool's exported components, which must be the
//!    tool's own P at those demands within pelicun's sampling error;
//! 3. the tool run directly on each recorded floor motion, at its own
//!    scale, counting the overturned: by the paper's rule (the record's
//!    first overturning, its certified capacity, at or below its scale)
//!    within the fragility's band; in one run at that scale, a single
//!    sample of the rocking, never above the band (fewer where a record
//!    that overturned the block at a weaker scale leaves it standing at
//!    its own; a chaotic record may topple it in a narrow window the IDA's
//!    levels stepped over, counted and reported).

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

use crate::util::{
    bundled_records, peak_velocity, rocking, root, stderr, stdout, tempdir, write_at2,
};

/// The FEMA P-58 bookcases (DLML E.20.22.104a and .106a, "12-5/8 in deep x
/// 56 in tall" and "x 81-1/4 in tall"): half-width and half-height (m) of
/// the depth (the direction they topple in) and height.
const BOOKCASES: [(&str, f64, f64); 2] = [
    ("E.20.22.104a", 0.5 * 12.625 * 0.0254, 0.5 * 56.0 * 0.0254),
    ("E.20.22.106a", 0.5 * 12.625 * 0.0254, 0.5 * 81.25 * 0.0254),
];

/// 16 far-field records, the first component of each of the first 16
/// events of the bundled set.
fn records(dir: &Path) -> Vec<PathBuf> {
    let mut all: Vec<PathBuf> = fs::read_dir(bundled_records().join("far-field"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "AT2"))
        .collect();
    all.sort();
    let picked: Vec<PathBuf> = all.into_iter().step_by(2).take(16).collect();
    fs::create_dir_all(dir).unwrap();
    picked
}

/// A floor's motion from a recorder file: column `k` (1-based after time),
/// m/s², and its step.
fn column(path: &Path, k: usize) -> (Vec<f64>, f64) {
    let text = fs::read_to_string(path).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect();
    let n = rows.len();
    let dt = (rows[n - 1][0] - rows[0][0]) / (n - 1) as f64;
    (rows.iter().map(|r| r[k]).collect(), dt)
}

/// The PFV (cm/s) of a piecewise-linear acceleration (m/s²).
fn pfv_cm_s(a: &[f64], h: f64) -> f64 {
    100.0 * peak_velocity(a, h)
}

/// The folder of FEMA P-58's component data in the DLML pelicun installs.
fn dlml(venv: &Path) -> PathBuf {
    venv.join("lib")
        .read_dir()
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| p.join("site-packages/dlml/data/seismic/building/component/FEMA P-58 2nd Edition"))
        .find(|p| p.is_dir())
        .unwrap()
}

/// pelicun's share of "falls over" (damage state 1 or above) for a
/// component of `csv` at each PFV level (cm/s), 20,000 realisations each.
fn pelicun_shares(venv: &Path, csv: &Path, id: &str, levels: &[f64]) -> Vec<f64> {
    let script = root().join("tests/engines/pelicun_damage.py");
    let out = Command::new(venv.join("bin/python"))
        .arg(&script)
        .arg(csv)
        .args([id, "20000", "PFV", "cmps"])
        .args(levels.iter().map(|l| l.to_string()))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    v["shares"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let s: Vec<f64> = s
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            s[1..].iter().sum()
        })
        .collect()
}

#[test]
fn opensees_floors_to_rocking_to_pelicun() {
    let Ok(venv) = std::env::var("ROCKING_ENGINES") else {
        eprintln!("skipped: set ROCKING_ENGINES to the engines' venv with openseespy (.ci/run)");
        return;
    };
    let venv = PathBuf::from(venv);
    let dir = tempdir();
    let d = dir.path();
    let floors = d.join("floors");
    let ground = records(&floors);
    // The building under every record scaled to a PGA of 0.25 g.
    let out = Command::new(venv.join("bin/python"))
        .arg(root().join("tests/engines/opensees_floors.py"))
        .arg(&floors)
        .arg("0.25")
        .args(&ground)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let model: Value = serde_json::from_slice(&out.stdout).unwrap();
    let t1 = model["periods"][0].as_f64().unwrap();
    assert!((t1 - 0.5).abs() < 0.01, "T1 = {t1}");
    let yielded = model["records"]
        .as_object()
        .unwrap()
        .values()
        .filter(|r| r["yielded"] == true)
        .count();
    assert!(yielded >= ground.len() / 2, "{model}");
    let dlml = dlml(&venv).join("fragility.csv");
    let files: Vec<PathBuf> = ground
        .iter()
        .map(|g| floors.join(format!("{}.out", g.file_stem().unwrap().to_string_lossy())))
        .collect();
    let mut report = vec![format!(
        "{} records at PGA 0.25 g, T1 = {t1:.3} s, {yielded} yielding; per floor and bookcase: \
         FEMA's P(falls over) in pelicun, the tool's component in pelicun, the tool's own P, \
         the direct count",
        ground.len()
    )];
    for floor in 1..=3 {
        let motions: Vec<(Vec<f64>, f64)> = files.iter().map(|f| column(f, floor)).collect();
        let demands: Vec<f64> = motions.iter().map(|(a, h)| pfv_cm_s(a, *h)).collect();
        let at: Vec<String> = demands.iter().map(|x| x.to_string()).collect();
        for (fema, b, h) in BOOKCASES {
            let (b_s, h_s, column) = (b.to_string(), h.to_string(), floor.to_string());
            let source = [
                "--b",
                &b_s,
                "--h",
                &h_s,
                "--direct",
                "--records",
                floors.to_str().unwrap(),
                "--records-unit",
                "m/s2",
                "--records-column",
                &column,
                "--im",
                "pfv",
            ];
            let export_dir = d.join(format!("export-{fema}-{floor}"));
            let exported = rocking(
                d,
                &[
                    &[
                        "export",
                        "--format",
                        "pelicun",
                        "--out",
                        export_dir.to_str().unwrap(),
                    ][..],
                    &source,
                    &["--states", "overturned=overturned", "--json"],
                ]
                .concat(),
            );
            assert!(exported.status.success(), "{}", stderr(&exported));
            let exported: Value = serde_json::from_str(&stdout(&exported)).unwrap();
            let id = exported[0]["taxonomy"].as_str().unwrap().to_string();
            let own = rocking(
                d,
                &[
                    &["fragility"][..],
                    &source,
                    &["--at", &at.join(","), "--json"],
                ]
                .concat(),
            );
            assert!(own.status.success(), "{}", stderr(&own));
            let own: Value = serde_json::from_str(&stdout(&own)).unwrap();
            let p_own: Vec<f64> = own["points"]
                .as_array()
                .unwrap()
                .iter()
                .map(|p| p["probability"].as_f64().unwrap())
                .collect();
            let ours = pelicun_shares(&venv, &export_dir.join("fragility.csv"), &id, &demands);
            let theirs = pelicun_shares(&venv, &dlml, fema, &demands);
            let n = demands.len() as f64;
            let mean = |v: &[f64]| v.iter().sum::<f64>() / n;
            // The tool's component in pelicun is the tool's fragility: each
            // level's share within 0.01 (3 binomial standard errors of
            // 20,000 draws at most 0.0035).
            for (i, (got, want)) in ours.iter().zip(&p_own).enumerate() {
                assert!(
                    (got - want).abs() < 0.01,
                    "floor {floor}, {fema}, record {i}: pelicun {got} against the tool {want}"
                );
            }
            // The direct count: each motion at its own scale, run once;
            // and by the paper's rule (a record overturns the block at a
            // scale if its first overturning, the capacity η_c, is at or
            // below it: η at its own scale, α/PGA, at most η_c).
            let alpha = (b / h).atan();
            let (mut direct, mut by_rule, mut windows) = (0, 0, 0);
            for (k, (a, dt)) in motions.iter().enumerate() {
                let at2 = d.join(format!("floor{floor}-{k}.AT2"));
                let in_g: Vec<f64> = a.iter().map(|x| x / 9.80665).collect();
                write_at2(&at2, &in_g, *dt);
                let pga = a.iter().fold(0.0f64, |m, x| m.max(x.abs())) / 9.80665;
                let block = [
                    "--record",
                    at2.to_str().unwrap(),
                    "--b",
                    &b_s,
                    "--h",
                    &h_s,
                    "--eps",
                    "housner",
                    "--model",
                    "nonlinear",
                    "--json",
                ];
                let run = rocking(
                    d,
                    &[&["simulate", "--pga", &pga.to_string()][..], &block].concat(),
                );
                assert!(run.status.success(), "{}", stderr(&run));
                let run: Value = serde_json::from_str(&stdout(&run)).unwrap();
                let cap = rocking(d, &[&["capacity"][..], &block].concat());
                assert!(cap.status.success(), "{}", stderr(&cap));
                let cap: Value = serde_json::from_str(&stdout(&cap)).unwrap();
                let eta_c = cap["eta_c"].as_f64().unwrap();
                let overturns = alpha / pga <= eta_c;
                let overturned = run["overturned"] == true;
                direct += usize::from(overturned);
                by_rule += usize::from(overturns);
                // Overturned in the one run, though the IDA's first
                // overturning is at a stronger level: a narrow window of
                // overturning its levels stepped over (a chaotic record).
                windows += usize::from(overturned && !overturns);
            }
            // The paper's count within the fragility's band: the count of
            // independent Bernoulli(p_i) trials, its mean ± 3 standard
            // deviations (and one record for the count's discreteness).
            let expected: f64 = p_own.iter().sum();
            let sd = p_own.iter().map(|p| p * (1.0 - p)).sum::<f64>().sqrt();
            assert!(
                (by_rule as f64 - expected).abs() <= 3.0 * sd + 1.0,
                "floor {floor}, {fema}: {by_rule} overturned against {expected:.2} ± {sd:.2}"
            );
            // One run at each record's own scale is one sample of the
            // rocking: never above the band (the rule counts a record once
            // it has overturned the block at any weaker scale), below it
            // where records leave the block standing at their own scale
            // after overturning it at a weaker one.
            assert!(
                direct as f64 <= expected + 3.0 * sd + 1.0,
                "floor {floor}, {fema}: {direct} overturned in one run against {expected:.2} ± \
                 {sd:.2}"
            );
            report.push(format!(
                "floor {floor} {fema} (b {b:.4} m, h {h:.4} m): mean PFV {:.1} cm/s, FEMA \
                 {:.3}, tool in pelicun {:.3}, tool {:.3}; of {} records {by_rule} overturn by \
                 the paper's rule (band {expected:.1} ± {:.1}), {direct} in one run at their \
                 own scale ({windows} of them above the IDA's first overturning)",
                demands.iter().sum::<f64>() / n,
                mean(&theirs),
                mean(&ours),
                mean(&p_own),
                demands.len(),
                3.0 * sd + 1.0
            ));
        }
    }
    eprintln!("{}", report.join("\n"));
}

/// The nine FEMA P-58 contents the tool compares with (`rocking contents`)
/// are the DLML's rows as pelicun installs them: id, demand (Peak Floor
/// Velocity in m/s, offset 0, non-directional), median and β, and the
/// sizes in each description ("… is 12-5/8" deep x 56" tall").
#[test]
fn the_fema_contents_are_the_dlmls_rows() {
    let Ok(venv) = std::env::var("ROCKING_ENGINES") else {
        eprintln!("skipped: set ROCKING_ENGINES to the engines' venv (.ci/run)");
        return;
    };
    let base = dlml(Path::new(&venv));
    let csv = fs::read_to_string(base.join("fragility.csv")).unwrap();
    let meta: Value =
        serde_json::from_str(&fs::read_to_string(base.join("fragility.json")).unwrap()).unwrap();
    let inches = |text: &str| -> f64 {
        // "12-5/8" → 12.625, "81-1/4" → 81.25, "56" → 56.
        let (whole, frac) = text.split_once('-').unwrap_or((text, ""));
        let frac = frac.split_once('/').map_or(0.0, |(a, b)| {
            a.parse::<f64>().unwrap() / b.parse::<f64>().unwrap()
        });
        whole.parse::<f64>().unwrap() + frac
    };
    for c in rocking::contents::FEMA_P58 {
        let row: Vec<&str> = csv
            .lines()
            .find(|l| l.starts_with(&format!("{},", c.id)))
            .unwrap()
            .split(',')
            .collect();
        assert_eq!(
            &row[2..7],
            ["Peak Floor Velocity", "mps", "0", "0", "lognormal"],
            "{}",
            c.id
        );
        assert_eq!(row[7].parse::<f64>().unwrap(), c.median_mps, "{}", c.id);
        assert_eq!(row[8].parse::<f64>().unwrap(), c.beta, "{}", c.id);
        let comments = meta[c.id]["Comments"].as_str().unwrap();
        let sizes = comments
            .split(" is ")
            .nth(1)
            .unwrap()
            .split(" tall")
            .next()
            .unwrap();
        let (depth, height) = sizes.split_once("\" deep x ").unwrap();
        let height = height.trim_end_matches('"');
        assert_eq!(
            (inches(depth), inches(height)),
            (c.depth_in, c.height_in),
            "{}",
            c.id
        );
    }
}
