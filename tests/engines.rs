//! `rocking export` proven against the real engines (`ROCKING_ENGINES`: a
//! venv with OpenQuake engine 3.26 and pelicun 3.10, which `.ci/run`
//! installs): OpenQuake's `classical_damage` on the exported NRML against
//! `rocking risk` and against its own discrete formula, and pelicun's damage
//! model on the exported CSV against the lognormals the export states.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

use crate::util::{rocking, root, stderr, stdout, tempdir};

/// The engines' venv, or `None` (the test is skipped) when unset.
pub(crate) fn engines() -> Option<PathBuf> {
    let Ok(venv) = std::env::var("ROCKING_ENGINES") else {
        eprintln!("skipped: set ROCKING_ENGINES to a venv with openquake.engine and pelicun (.ci/run makes one)");
        return None;
    };
    let venv = PathBuf::from(venv);
    assert!(
        venv.join("bin/oq").exists(),
        "ROCKING_ENGINES={} has no bin/oq",
        venv.display()
    );
    Some(venv)
}

/// Φ, from statrs (as scipy's, which OpenQuake uses, accurate to ~1e-16).
fn phi(x: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, Normal};
    Normal::standard().cdf(x)
}

/// A hazard-curve CSV in OpenQuake's layout: three sites, power laws
/// λ(a) = k0·a^−k at 100 IMLs log-spaced over 0.25–5 g, poe in 50 years.
/// Every IML lies above the uplift PGA (g·tan α ≤ 0.222 g) of the blocks
/// tested, so OpenQuake's noDamageLimit never sets a probability to 0.
fn hazard(path: &Path) -> (Vec<f64>, Vec<Vec<f64>>) {
    let sites = [
        (21.73, 38.25, 1e-3, 2.2),
        (23.73, 37.98, 4e-4, 2.6),
        (22.0, 38.0, 2e-3, 3.0),
    ];
    hazard_in(path, "PGA", 0.25, 5.0, &sites)
}

/// The same in `imt`, the IMLs over [lo, hi] in its unit, one site per
/// (lon, lat, k0, k).
fn hazard_in(
    path: &Path,
    imt: &str,
    lo: f64,
    hi: f64,
    sites: &[(f64, f64, f64, f64)],
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let imls: Vec<f64> = (0..100)
        .map(|i| lo * (hi / lo).powf(i as f64 / 99.0))
        .collect();
    hazard_at(path, imt, &imls, sites)
}

/// The same at the given IMLs.
fn hazard_at(
    path: &Path,
    imt: &str,
    imls: &[f64],
    sites: &[(f64, f64, f64, f64)],
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let places: Vec<(f64, f64)> = sites.iter().map(|s| (s.0, s.1)).collect();
    let rate = |k: usize, a: f64| sites[k].2 * a.powf(-sites[k].3);
    (
        imls.to_vec(),
        hazard_of(path, imt, imls, &places, rate, false),
    )
}

/// A hazard-curve CSV at `imls`, one row per (lon, lat) of `sites` with
/// the poe in 50 years of the annual rate `rate(site, a)`; with `ids`, led
/// by a `custom_site_id` column as OpenQuake's own exports are. The poes
/// as the file states them (ten digits), which OpenQuake reads.
fn hazard_of(
    path: &Path,
    imt: &str,
    imls: &[f64],
    sites: &[(f64, f64)],
    rate: impl Fn(usize, f64) -> f64,
    ids: bool,
) -> Vec<Vec<f64>> {
    let mut text = format!(
        "#,,,,\"generated_by='rocking tests', start_date='2026-01-01T00:00:00', checksum=0, kind='mean', investigation_time=50.0, imt='{imt}'\"\n{}lon,lat,depth",
        if ids { "custom_site_id," } else { "" }
    );
    for a in imls {
        text.push_str(&format!(",poe-{a}"));
    }
    text.push('\n');
    let mut poes = Vec::new();
    for (k, &(lon, lat)) in sites.iter().enumerate() {
        let p: Vec<f64> = imls
            .iter()
            .map(|&a| -(-50.0 * rate(k, a)).exp_m1())
            .map(|v| format!("{v:.9e}").parse().unwrap())
            .collect();
        if ids {
            text.push_str(&format!("site{k}x,"));
        }
        text.push_str(&format!("{lon},{lat},0.0"));
        for v in &p {
            text.push_str(&format!(",{v:.9e}"));
        }
        text.push('\n');
        poes.push(p);
    }
    fs::write(path, text).unwrap();
    poes
}

/// OpenQuake's classical_damage for one fragility curve F at the hazard's
/// IMLs (openquake/risklib/scientific.py `classical_damage`, steps per
/// interval 1): the rates of occurrence are differences of the padded
/// midpoints of the rates of exceedance, P = 1 − exp(−T Σ rate·F). The
/// poes as OpenQuake holds them: read as float32 (readinput.py
/// `get_pmap_from_csv`) and kept as a float32 probability of no exceedance
/// 1 − poe, a poe of 1 then taken as 0.9999999999999999; at a low-hazard
/// site (poe ~ 1e-6) that rounding alone moves the answer by tenths of a
/// per cent (reproduced here to OpenQuake's seven printed digits).
fn discrete(imls: &[f64], poes: &[f64], f: impl Fn(f64) -> f64, t_haz: f64, t: f64) -> f64 {
    let afoe: Vec<f64> = poes
        .iter()
        .map(|&p| {
            let held = 1.0 - f64::from(1.0f32 - p as f32);
            let held = if held == 1.0 {
                0.9999999999999999
            } else {
                held
            };
            -(1.0 - held).ln() / t_haz
        })
        .collect();
    let n = afoe.len();
    let mut padded = vec![afoe[0]];
    padded.extend(&afoe);
    padded.push(afoe[n - 1]);
    let mids: Vec<f64> = padded.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
    let fx: f64 = (0..n).map(|i| (mids[i] - mids[i + 1]) * f(imls[i])).sum();
    -(-fx * t).exp_m1()
}

/// Runs the job in `dir` and reads the damage-state shares per asset.
fn openquake(venv: &Path, dir: &Path) -> Vec<(String, Vec<f64>)> {
    let data = dir.join("oqdata");
    fs::create_dir_all(&data).unwrap();
    let out = Command::new(venv.join("bin/oq"))
        .args(["run", "job.ini", "--exports", "csv"])
        .current_dir(dir)
        .env("CI", "true")
        .env("OQ_DISTRIBUTE", "no")
        .env("NUMBA_DISABLE_JIT", "1")
        .env("OQ_DATADIR", &data)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "oq run failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("damages-rlz")
        })
        .expect("oq exported its damages");
    let text = fs::read_to_string(csv).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let id = header.iter().position(|h| *h == "asset_id").unwrap();
    let states: Vec<usize> = (0..header.len())
        .filter(|&i| header[i].starts_with("contents-"))
        .collect();
    lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            let shares = states.iter().map(|&i| cells[i].parse().unwrap()).collect();
            (cells[id].to_string(), shares)
        })
        .collect()
}

/// The lognormals an export states, per block: (median, β) per state.
fn stated(json: &Value) -> Vec<Vec<(f64, f64)>> {
    json.as_array()
        .unwrap()
        .iter()
        .map(|b| {
            b["fragility"]["states"]
                .as_array()
                .unwrap()
                .iter()
                .map(|s| {
                    (
                        s["fractile"]["median"].as_f64().unwrap(),
                        s["fractile"]["beta"].as_f64().unwrap(),
                    )
                })
                .collect()
        })
        .collect()
}

/// OpenQuake's probability of overturning within 50 years at three sites,
/// from the exported paper regression, against `rocking risk`, which
/// integrates the same lognormal exactly over the log-log interpolated
/// curve (`--beyond stop`: OpenQuake ignores the rate beyond the last IML).
/// OpenQuake's sum equals its discrete formula computed here to 2e-6
/// relative (hazard poes read as float32), so the difference from `rocking
/// risk` is that formula's discretisation alone: a midpoint rule in the
/// rate, with half-bins at both ends, on a grid of Δ ln a = 0.030. Its
/// error, of order Δ², is 0.05–0.08 % on these curves (measured); the
/// tolerance is 0.5 %. A mean and stddev taken as the median and β would
/// move OpenQuake's answer by several per cent.
#[test]
fn openquake_classical_damage_agrees_with_rocking_risk() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let (imls, poes) = hazard(&d.join("hazard.csv"));
    let job = d.join("job");
    let block = ["--b", "0.2", "--h", "0.9", "--eps", "0.85"];
    let out = rocking(
        d,
        &[
            &[
                "export",
                "--format",
                "nrml",
                "--hazard",
                "hazard.csv",
                "--out",
                "job",
                "--json",
            ][..],
            &block,
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let states = stated(&serde_json::from_str(&stdout(&out)).unwrap());
    let (median, beta) = states[0][0];
    let risk = rocking(
        d,
        &[
            &[
                "risk",
                "--hazard",
                "hazard.csv",
                "--beyond",
                "stop",
                "--json",
            ][..],
            &block,
        ]
        .concat(),
    );
    assert!(risk.status.success(), "{}", stderr(&risk));
    let risk: Value = serde_json::from_str(&stdout(&risk)).unwrap();
    assert!((risk["fragility"]["median"].as_f64().unwrap() - median).abs() < 1e-12);
    let oq = openquake(&venv, &job);
    assert_eq!(oq.len(), 3);
    for (k, (id, shares)) in oq.iter().enumerate() {
        assert_eq!(id, &format!("b0.2_h0.9_{k}"));
        let p_oq = shares[1];
        let f = |a: f64| phi((a / median).ln() / beta);
        let p_discrete = discrete(&imls, &poes[k], f, 50.0, 50.0);
        let p_risk = risk["sites"][k]["p_overturn_in_years"].as_f64().unwrap();
        assert!(
            (p_oq - p_discrete).abs() <= 2e-6 * p_discrete + 1e-9,
            "site {k}: OpenQuake {p_oq} against its formula {p_discrete}"
        );
        assert!(
            (p_oq - p_risk).abs() <= 0.005 * p_risk,
            "site {k}: OpenQuake {p_oq} against rocking risk {p_risk}"
        );
        assert!((shares[0] + shares[1] - 1.0).abs() < 1e-6);
    }
}

/// Every damage state of a block from its runs: OpenQuake's share of each
/// state at each site equals the difference of its discrete formula for
/// consecutive states (the lognormals the export prints), and the shares
/// sum to 1.
#[test]
fn openquake_reads_every_damage_state() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let (imls, poes) = hazard(&d.join("hazard.csv"));
    let out = rocking(
        d,
        &[
            "export",
            "--format",
            "nrml",
            "--hazard",
            "hazard.csv",
            "--out",
            "job",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
        ]
        .into_iter()
        .chain([root().join("records/fema-p695/far-field").to_str().unwrap()])
        .chain(["--json"])
        .collect::<Vec<_>>(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let states = &stated(&serde_json::from_str(&stdout(&out)).unwrap())[0];
    assert_eq!(states.len(), 3);
    let oq = openquake(&venv, &d.join("job"));
    for (k, (_, shares)) in oq.iter().enumerate() {
        let exceed: Vec<f64> = states
            .iter()
            .map(|&(m, b)| discrete(&imls, &poes[k], |a| phi((a / m).ln() / b), 50.0, 50.0))
            .collect();
        let mut want = vec![1.0 - exceed[0]];
        want.extend(exceed.windows(2).map(|w| w[0] - w[1]));
        want.push(exceed[2]);
        for (s, (got, want)) in shares.iter().zip(&want).enumerate() {
            assert!(
                (got - want).abs() <= 2e-6,
                "site {k}, state {s}: OpenQuake {got} against {want}"
            );
        }
        assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-6);
    }
}

/// In PGV: the block's states from its runs, exported in PGV (cm/s) with a
/// PGV hazard (λ(v) = k0·v^−k over 5–300 cm/s); OpenQuake's share of each
/// state equals its discrete formula for the stated lognormals, and its
/// probability of overturning agrees with `rocking risk --states --direct`
/// (the same lognormal, §11's exact integral) within 0.5 %: the grid is
/// coarser than in PGA (Δ ln v = 0.041), the discretisation error still
/// below 0.2 % (measured).
#[test]
fn openquake_reads_a_pgv_fragility() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let sites = [
        (21.73, 38.25, 1e-2 * 30f64.powf(2.2), 2.2),
        (23.73, 37.98, 4e-3 * 30f64.powf(2.6), 2.6),
    ];
    let (imls, poes) = hazard_in(&d.join("hazard.csv"), "PGV", 5.0, 300.0, &sites);
    let records = root().join("records/fema-p695/far-field");
    let block = [
        "--b",
        "0.2",
        "--h",
        "0.9",
        "--direct",
        "--records",
        records.to_str().unwrap(),
        "--json",
    ];
    let out = rocking(
        d,
        &[
            &[
                "export",
                "--format",
                "nrml",
                "--hazard",
                "hazard.csv",
                "--out",
                "job",
            ][..],
            &block,
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let json: Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(json[0]["fragility"]["im"], "pgv");
    assert_eq!(json[0]["fragility"]["unit"], "cm/s");
    let states = &stated(&json)[0];
    let xml = fs::read_to_string(d.join("job/fragility_model.xml")).unwrap();
    assert!(xml.contains("imt=\"PGV\""), "{xml}");
    let risk = rocking(
        d,
        &[
            &[
                "risk",
                "--hazard",
                "hazard.csv",
                "--beyond",
                "stop",
                "--states",
                "rocking=0.1,large_rocking=0.5,overturned=overturned",
            ][..],
            &block,
        ]
        .concat(),
    );
    assert!(risk.status.success(), "{}", stderr(&risk));
    let risk: Value = serde_json::from_str(&stdout(&risk)).unwrap();
    // OpenQuake clips each curve to [minIML, maxIML] of its function.
    let attr = |name: &str| -> f64 {
        let at = xml.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
        xml[at..at + xml[at..].find('"').unwrap()].parse().unwrap()
    };
    let (lo, hi) = (attr("minIML"), attr("maxIML"));
    let oq = openquake(&venv, &d.join("job"));
    assert_eq!(oq.len(), 2);
    for (k, (_, shares)) in oq.iter().enumerate() {
        let exceed: Vec<f64> = states
            .iter()
            .map(|&(m, b)| {
                let f = |a: f64| phi((a.clamp(lo, hi) / m).ln() / b);
                discrete(&imls, &poes[k], f, 50.0, 50.0)
            })
            .collect();
        let mut want = vec![1.0 - exceed[0]];
        want.extend(exceed.windows(2).map(|w| w[0] - w[1]));
        want.push(exceed[2]);
        // OpenQuake holds the curves in float32; here the light state's
        // curve rises where the hazard's rates are large (0.5 a year at
        // 5 cm/s), so its share sums larger rounded terms: measured 5e-6,
        // tolerance 2e-5 (2e-6 in PGA above).
        for (s, (got, want)) in shares.iter().zip(&want).enumerate() {
            assert!(
                (got - want).abs() <= 2e-5,
                "site {k}, state {s}: OpenQuake {got} against {want}"
            );
        }
        let ours = risk["sites"][k]["states"][2]["p_in_years"]
            .as_f64()
            .unwrap();
        assert!(
            (shares[3] - ours).abs() <= 0.005 * ours,
            "site {k}: OpenQuake {} against rocking risk --states {ours}",
            shares[3]
        );
    }
}

/// Where the export and `risk` once disagreed: a low-hazard site whose
/// steep curve starts below the block's uplift PGA (there `risk`
/// integrated the lognormal down to 0 g while the job cut it at
/// `noDamageLimit`, 3,400× apart), and a block on a floor (whose export
/// cut at the ground's uplift PGA, halving the overturning rate). Both
/// now apply one cut (MODEL.md §11): g·tan α on the ground, none on the
/// floor. OpenQuake equals its discrete formula with the cut (F = 0 at
/// IMLs ≤ noDamageLimit, scientific.py) to 2e-6, and `risk` within the
/// formula's own error: 300 IMLs over 0.02–3 g (Δ ln a = 0.0168), one of
/// them the cut itself. At the steep site the formula in float64 is 1.09 %
/// below `risk` (the step at the cut counts half a bin of the steepest
/// hazard) and OpenQuake's float32 another 0.34 % (measured); the
/// tolerance is 2 %. Without the cut in `risk` they were 3,400× apart.
#[test]
fn openquake_and_risk_agree_below_the_uplift_pga_and_on_a_floor() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let (b, h) = (0.2f64, 0.9f64);
    let cut = b / h;
    let mut imls: Vec<f64> = (0..299)
        .map(|i| 0.02 * (3.0f64 / 0.02).powf(i as f64 / 298.0))
        .collect();
    imls.push(cut);
    imls.sort_by(f64::total_cmp);
    // A steep, low-hazard site (k = 6: the uncut integrand peaks below
    // the uplift PGA) and a moderate one.
    let sites = [(21.73, 38.25, 1e-11, 6.0), (23.73, 37.98, 1e-4, 2.2)];
    let (imls, poes) = hazard_at(&d.join("hazard.csv"), "PGA", &imls, &sites);
    let records = root().join("records/fema-p695/far-field");
    let records = records.to_str().unwrap();
    for floor in [None, Some("0.5,0.05,1.3")] {
        let mut args = vec![
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
            records,
            "--json",
        ];
        if let Some(f) = floor {
            args.extend(["--floor", f]);
        }
        let job = format!("job-{}", floor.is_some());
        let mut export = vec![
            "export",
            "--format",
            "nrml",
            "--hazard",
            "hazard.csv",
            "--out",
            &job,
        ];
        export.extend(&args);
        let out = rocking(d, &export);
        assert!(out.status.success(), "{}", stderr(&out));
        let states = &stated(&serde_json::from_str(&stdout(&out)).unwrap())[0];
        let xml = fs::read_to_string(d.join(&job).join("fragility_model.xml")).unwrap();
        assert_eq!(xml.contains("noDamageLimit"), floor.is_none(), "{xml}");
        let mut risk = vec!["risk", "--hazard", "hazard.csv", "--beyond", "stop"];
        risk.extend(&args);
        let risk = rocking(d, &risk);
        assert!(risk.status.success(), "{}", stderr(&risk));
        let risk: Value = serde_json::from_str(&stdout(&risk)).unwrap();
        let (median, beta) = states[2];
        assert_eq!(risk["fragility"]["median"].as_f64(), Some(median));
        assert_eq!(risk["fragility"]["beta"].as_f64(), Some(beta));
        let limit = if floor.is_none() { cut } else { 0.0 };
        let oq = openquake(&venv, &d.join(&job));
        for (k, (_, shares)) in oq.iter().enumerate() {
            let f = |a: f64| {
                if a <= limit {
                    0.0
                } else {
                    phi((a / median).ln() / beta)
                }
            };
            let p_discrete = discrete(&imls, &poes[k], f, 50.0, 50.0);
            let p_oq = shares[3];
            let p_risk = risk["sites"][k]["p_overturn_in_years"].as_f64().unwrap();
            assert!(
                (p_oq - p_discrete).abs() <= 2e-6 * p_discrete + 1e-12,
                "floor {floor:?}, site {k}: OpenQuake {p_oq} against its formula {p_discrete}"
            );
            assert!(
                (p_oq - p_risk).abs() <= 0.02 * p_risk,
                "floor {floor:?}, site {k}: OpenQuake {p_oq} against rocking risk {p_risk}"
            );
        }
    }
}

/// pelicun's damage model on the exported CSV, 20,000 realisations at five
/// PGAs: the share at or above each damage state against the stated
/// lognormals. pelicun samples the states' capacities perfectly
/// correlated and assigns the highest state exceeded, so the share at or
/// above state k is the largest exceedance probability of the states from
/// k up (equal to state k's own where the curves do not cross). Its
/// sampling (Latin hypercube) errs by less than a binomial standard error,
/// at most 0.0035 for 20,000 draws; the tolerance is 0.01. Overturning is
/// also checked against `rocking fragility` for the paper regression.
#[test]
fn pelicun_damage_states_agree_with_the_fragility() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let pgas = ["0.2", "0.3", "0.45", "0.7", "1.2"];
    let script = root().join("tests/engines/pelicun_damage.py");
    let shares = |folder: &str, id: &str| -> Vec<Vec<f64>> {
        let out = Command::new(venv.join("bin/python"))
            .arg(&script)
            .arg(d.join(folder).join("fragility.csv"))
            .args([id, "20000", "PGA", "g"])
            .args(pgas)
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
            .map(|r| {
                r.as_array()
                    .unwrap()
                    .iter()
                    .map(|x| x.as_f64().unwrap())
                    .collect()
            })
            .collect()
    };
    let at_or_above = |s: &[f64], k: usize| s[k..].iter().sum::<f64>();

    // Every state, from the block's runs.
    let records = root().join("records/fema-p695/far-field");
    let out = rocking(
        d,
        &[
            "export",
            "--format",
            "pelicun",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
            records.to_str().unwrap(),
            "--out",
            "direct",
            "--json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let states = &stated(&serde_json::from_str(&stdout(&out)).unwrap())[0];
    let got = shares("direct", "b0.2_h0.9");
    for (i, pga) in pgas.iter().enumerate() {
        let a: f64 = pga.parse().unwrap();
        let exceed: Vec<f64> = states.iter().map(|&(m, b)| phi((a / m).ln() / b)).collect();
        for k in 0..3 {
            let want = exceed[k..].iter().cloned().fold(0.0, f64::max);
            let share = at_or_above(&got[i], k + 1);
            assert!(
                (share - want).abs() < 0.01,
                "PGA {a} g, state {}: pelicun {share} against {want}",
                k + 1
            );
        }
    }

    // Overturning from the paper's regression, against `rocking fragility`.
    let out = rocking(
        d,
        &[
            "export", "--format", "pelicun", "--b", "0.2", "--h", "0.9", "--eps", "0.85", "--out",
            "paper",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let got = shares("paper", "b0.2_h0.9");
    let frag = rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--eps",
            "0.85",
            "--pga",
            &pgas.join(","),
            "--json",
        ],
    );
    let frag: Value = serde_json::from_str(&stdout(&frag)).unwrap();
    for (i, point) in frag["points"].as_array().unwrap().iter().enumerate() {
        let want = point["probability"].as_f64().unwrap();
        assert!(
            (got[i][1] - want).abs() < 0.01,
            "PGA {}: pelicun {} against rocking fragility {want}",
            pgas[i],
            got[i][1]
        );
    }
}

/// The records' curve into pelicun: for the museum inventory from its runs
/// (the default states), a block is written as `multilinear_CDF` exactly
/// where its heaviest state's capacities fail the lognormal check
/// (Lilliefors p < 0.05, as the JSON reports it), and as lognormals
/// elsewhere; both kinds occur. For a block written as curves, pelicun's
/// share of each state at five PGAs (20,000 realisations each) equals the
/// tool's own P(state | PGA) by its curve (`fragility --states --method
/// empirical`) within 0.01: the binomial standard error is at most 0.0035,
/// and pelicun interpolates the points linearly as the tool does.
#[test]
fn pelicun_takes_the_records_curve_where_a_lognormal_does_not_fit() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    // The museum's blocks held against sliding (its μ column left out):
    // the rack and the transformer, which slide first, would never rock.
    let museum = fs::read_to_string(root().join("records/hazard/museum-inventory.csv")).unwrap();
    let held: String = museum
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
        .collect();
    let inventory = d.join("held.csv");
    fs::write(&inventory, held).unwrap();
    let records = root().join("records/fema-p695/far-field");
    let out = rocking(
        d,
        &[
            "export",
            "--format",
            "pelicun",
            "--inventory",
            inventory.to_str().unwrap(),
            "--direct",
            "--records",
            records.to_str().unwrap(),
            "--out",
            "inv",
            "--json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let json: Value = serde_json::from_str(&stdout(&out)).unwrap();
    let csv = fs::read_to_string(d.join("inv/fragility.csv")).unwrap();
    let mut curves = Vec::new();
    let mut lognormals = 0;
    for b in json.as_array().unwrap() {
        let id = b["taxonomy"].as_str().unwrap();
        let states = b["fragility"]["states"].as_array().unwrap();
        let p = states.last().unwrap()["lognormal_p"].as_f64().unwrap();
        let row = csv
            .lines()
            .find(|l| l.starts_with(&format!("{id},")))
            .unwrap();
        let families = row.matches("multilinear_CDF").count();
        let curve = b["written_as"] == "curve";
        assert_eq!(curve, p < 0.05, "{id} (p = {p})");
        if p < 0.05 {
            assert_eq!(families, 3, "{id} (p = {p}): {row}");
            assert!(!row.contains("lognormal"), "{row}");
            curves.push((id.to_string(), b["block"].clone()));
        } else {
            assert_eq!(families, 0, "{id} (p = {p}): {row}");
            lognormals += 1;
        }
    }
    assert!(!curves.is_empty() && lognormals > 0, "{curves:?}");
    let pgas = ["0.25", "0.35", "0.5", "0.7", "1.0"];
    let script = root().join("tests/engines/pelicun_damage.py");
    for (id, block) in &curves {
        let run = Command::new(venv.join("bin/python"))
            .arg(&script)
            .arg(d.join("inv/fragility.csv"))
            .args([id.as_str(), "20000", "PGA", "g"])
            .args(pgas)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let got: Value = serde_json::from_slice(&run.stdout).unwrap();
        let num = |v: &Value| v.as_f64().map(|x| x.to_string()).unwrap_or_default();
        let eps = block["eps"].as_f64().unwrap().to_string();
        let frag = rocking(
            d,
            &[
                "fragility",
                "--b",
                &num(&block["b_m"]),
                "--h",
                &num(&block["h_m"]),
                "--eps",
                &eps,
                "--direct",
                "--records",
                records.to_str().unwrap(),
                "--states",
                "rocking=0.1,large_rocking=0.5,overturned=overturned",
                "--method",
                "empirical",
                "--pga",
                &pgas.join(","),
                "--json",
            ],
        );
        assert!(frag.status.success(), "{}", stderr(&frag));
        let frag: Value = serde_json::from_str(&stdout(&frag)).unwrap();
        for (i, point) in frag["points"].as_array().unwrap().iter().enumerate() {
            let shares: Vec<f64> = got["shares"][i]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            for k in 0..3 {
                let want = point["probabilities"][k].as_f64().unwrap();
                let share: f64 = shares[k + 1..].iter().sum();
                assert!(
                    (share - want).abs() < 0.01,
                    "{id}, PGA {}, state {}: pelicun {share} against the curve {want}",
                    pgas[i],
                    k + 1
                );
            }
        }
    }
}

/// The records' curve into OpenQuake: the statue with ε = 0.85, whose
/// capacities fail the lognormal check, is written as a discrete function
/// (its states on one list of levels); OpenQuake's share of each state at
/// each of three sites equals its discrete formula for the curves it was
/// given (linear between the levels, held beyond them) to 2e-6, and its
/// probability of each state in 50 years agrees with `rocking risk
/// --states --direct --beyond stop`, which integrates the same curves
/// exactly, within 1 %: OpenQuake's midpoint rule on Δ ln a = 0.030 meets
/// the curves' kinks (measured: −0.02 to +0.25 %).
#[test]
fn openquake_takes_the_records_curve_as_a_discrete_function() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let (imls, poes) = hazard(&d.join("hazard.csv"));
    let records = root().join("records/fema-p695/far-field");
    let states = "rocking=0.1,large_rocking=0.5,overturned=overturned";
    let block = [
        "--b",
        "0.2",
        "--h",
        "0.9",
        "--eps",
        "0.85",
        "--direct",
        "--records",
        records.to_str().unwrap(),
        "--states",
        states,
        "--json",
    ];
    let out = rocking(
        d,
        &[
            &[
                "export",
                "--format",
                "nrml",
                "--hazard",
                "hazard.csv",
                "--out",
                "job",
            ][..],
            &block,
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let xml = fs::read_to_string(d.join("job/fragility_model.xml")).unwrap();
    assert!(xml.contains(r#"format="discrete""#), "{xml}");
    assert!(xml.contains(r#"lossCategory="contents""#), "{xml}");
    // The levels and each state's probabilities, as written.
    let numbers = |tag: &str, from: usize| -> (Vec<f64>, usize) {
        let open = xml[from..].find(&format!("<{tag}")).unwrap() + from;
        let start = open + xml[open..].find('>').unwrap() + 1;
        let end = start + xml[start..].find('<').unwrap();
        let v = xml[start..end]
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        (v, end)
    };
    let (levels, mut at) = numbers("imls", 0);
    let mut curves = Vec::new();
    for _ in 0..3 {
        let (p, end) = numbers("poes", at);
        assert_eq!(p.len(), levels.len());
        curves.push(p);
        at = end;
    }
    let interp = |c: &[f64], a: f64| -> f64 {
        let a = a.clamp(levels[0], *levels.last().unwrap());
        let i = levels
            .partition_point(|&x| x <= a)
            .clamp(1, levels.len() - 1);
        let (x0, x1) = (levels[i - 1], levels[i]);
        c[i - 1] + (c[i] - c[i - 1]) * (a - x0) / (x1 - x0)
    };
    let risk = rocking(
        d,
        &[
            &["risk", "--hazard", "hazard.csv", "--beyond", "stop"][..],
            &block,
        ]
        .concat(),
    );
    assert!(risk.status.success(), "{}", stderr(&risk));
    let risk: Value = serde_json::from_str(&stdout(&risk)).unwrap();
    assert_eq!(risk["method"], "empirical", "{risk}");
    let oq = openquake(&venv, &d.join("job"));
    assert_eq!(oq.len(), 3);
    for (k, (_, shares)) in oq.iter().enumerate() {
        for (s, c) in curves.iter().enumerate() {
            let formula = discrete(&imls, &poes[k], |a| interp(c, a), 50.0, 50.0);
            let p_oq: f64 = shares[s + 1..].iter().sum();
            assert!(
                (p_oq - formula).abs() <= 2e-6,
                "site {k}, state {s}: OpenQuake {p_oq} against its formula {formula}"
            );
            let p_risk = risk["sites"][k]["states"][s]["p_in_years"]
                .as_f64()
                .unwrap();
            assert!(
                (p_oq - p_risk).abs() <= 0.01 * p_risk,
                "site {k}, state {s}: OpenQuake {p_oq} against rocking risk {p_risk}"
            );
        }
    }
}

/// A block on a floor exported in FEMA P-58's floor demands: pelicun
/// reads the component as the DLML's contents are read (demand type "Peak
/// Floor Velocity" or "Peak Floor Acceleration") and, with the demand
/// fixed at five levels of PFV and of PFA, 20,000 realisations each, gives
/// each state's share at or above it as the stated lognormals do, within
/// 0.01 (three binomial standard errors at most 0.0035: as above).
#[test]
fn pelicun_reads_floor_demand_components() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let script = root().join("tests/engines/pelicun_damage.py");
    let records = root().join("records/fema-p695/far-field");
    for (im, kind, unit, levels) in [
        ("pfv", "PFV", "cmps", ["20", "35", "50", "70", "100"]),
        ("pfa", "PFA", "g", ["0.3", "0.45", "0.6", "0.8", "1.1"]),
    ] {
        let out = rocking(
            d,
            &[
                "export",
                "--format",
                "pelicun",
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--direct",
                "--records",
                records.to_str().unwrap(),
                "--floor",
                "0.5,0.05,1.3",
                "--im",
                im,
                "--out",
                im,
                "--json",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        let states = &stated(&serde_json::from_str(&stdout(&out)).unwrap())[0];
        let csv = fs::read_to_string(d.join(im).join("fragility.csv")).unwrap();
        let demand = if im == "pfv" {
            "Peak Floor Velocity,cmps"
        } else {
            "Peak Floor Acceleration,g"
        };
        assert!(csv.contains(demand), "{csv}");
        let run = Command::new(venv.join("bin/python"))
            .arg(&script)
            .arg(d.join(im).join("fragility.csv"))
            .args(["b0.2_h0.9", "20000", kind, unit])
            .args(levels)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
        let v: Value = serde_json::from_slice(&run.stdout).unwrap();
        for (i, level) in levels.iter().enumerate() {
            let x: f64 = level.parse().unwrap();
            let shares: Vec<f64> = v["shares"][i]
                .as_array()
                .unwrap()
                .iter()
                .map(|s| s.as_f64().unwrap())
                .collect();
            for (k, &(m, b)) in states.iter().enumerate() {
                let want = phi((x / m).ln() / b);
                let got: f64 = shares[k + 1..].iter().sum();
                assert!(
                    (got - want).abs() < 0.01,
                    "{im} {x}, state {}: pelicun {got} against {want}",
                    k + 1
                );
            }
        }
    }
}

/// The guide's export example prints what the guide shows, writes the
/// files it names, and OpenQuake runs them.
#[test]
fn the_guides_export_example_is_what_the_tool_prints() {
    let readme = fs::read_to_string(root().join("docs/guide.md")).unwrap();
    let command = "cargo run --release -- export --format nrml --b 0.2 --h 0.9 --direct --hazard records/hazard/synthetic-openquake.csv --out outputs/statue-nrml";
    let at = readme.find(command).expect("the guide shows the export");
    // The fits, up to the files written (here into another folder).
    let shown = readme[at..]
        .split("```text\n")
        .nth(1)
        .and_then(|r| r.split("```").next())
        .and_then(|r| r.split("wrote ").next())
        .unwrap();
    let dir = tempdir();
    let out_dir = dir.path().join("statue-nrml");
    let mut args: Vec<&str> = command
        .trim_start_matches("cargo run --release -- ")
        .split_whitespace()
        .collect();
    let n = args.len();
    args[n - 1] = out_dir.to_str().unwrap();
    let out = rocking(&root(), &args);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stdout(&out).starts_with(shown),
        "update the guide:\n{}",
        stdout(&out)
    );
    for f in [
        "fragility_model.xml",
        "exposure_model.xml",
        "assets.csv",
        "hazard_curves.csv",
        "job.ini",
    ] {
        assert!(out_dir.join(f).exists(), "{f}");
    }
    // And OpenQuake runs it as the README says (its TOML metadata reader
    // once refused the bundled file's quoted apostrophe).
    // The file's 14 IMLs are coarse: the job's midpoint sum counts several
    // per cent more than `risk --beyond stop`'s integral (the guide said
    // they agree within 0.1 %), and the export says by how much.
    let warned = stderr(&out);
    let said = warned
        .lines()
        .find(|l| l.contains("by a midpoint rule"))
        .unwrap_or_else(|| panic!("the export warns of the coarse sum:\n{warned}"));
    let number_after = |key: &str| -> f64 {
        let rest = &said[said.find(key).unwrap() + key.len()..];
        rest.split(|c: char| !(c.is_ascii_digit() || ".e-".contains(c)))
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let (site, job_rate) = (
        number_after("at site ") as usize,
        number_after("the job counts "),
    );
    if let Some(venv) = engines() {
        let oq = openquake(&venv, &out_dir);
        assert_eq!(oq.len(), 3);
        for (_, shares) in &oq {
            assert_eq!(shares.len(), 4);
            assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-6);
        }
        // OpenQuake's rate of overturning at the site named, against the
        // warning's: within its four printed digits and the job's float32
        // poes (tenths of a per cent at most, `openquake_classical_damage`).
        let p_oq = oq[site].1[3];
        let oq_rate = -(-p_oq).ln_1p() / 50.0;
        assert!(
            (oq_rate / job_rate - 1.0).abs() < 5e-3,
            "site {site}: OpenQuake {oq_rate:e}/yr, the warning {job_rate:e}/yr"
        );
    }
}

/// Refusals name what is wrong: states out of order, an IM the engine
/// has no name for, states a regression cannot give, a plain hazard for
/// OpenQuake's job, an output folder that holds an input; and a block
/// outside the regression is warned about as `risk` does.
#[test]
fn export_refusals_name_what_is_wrong() {
    let dir = tempdir();
    let d = dir.path();
    let fails = |args: &[&str], what: &str| {
        let out = rocking(d, args);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(stderr(&out).contains(what), "{args:?}: {}", stderr(&out));
    };
    let block = [
        "export", "--b", "0.2", "--h", "0.9", "--eps", "0.85", "--out", "x",
    ];
    fails(
        &[&block[..], &["--format", "nrml", "--states", "a=0.5,b=0.1"]].concat(),
        "`b` (θmax/α ≥ 0.1) follows `a` (θmax/α ≥ 0.5)",
    );
    // Every record slides 1 cm, several at the first level: the records'
    // curve jumps there (it was refused as "stops below 1", beside "44 of
    // 44 records reach it").
    fails(
        &[
            "export",
            "--format",
            "pelicun",
            "--b",
            "0.3",
            "--h",
            "1.0",
            "--mu",
            "0.2",
            "--direct",
            "--states",
            "slide=0.01m,overturned=overturned",
            "--out",
            "x",
        ],
        "records reach `slide` first at one level",
    );
    fails(
        &[
            &block[..],
            &["--format", "pelicun", "--im", "avgsa", "--direct"],
        ]
        .concat(),
        "pelicun: a fragility in avgsa is not exported (pelicun's damage model has no demand \
         type for it); export in PGA, PGV, SA(T), PFA, PFV, RotD50 PGA, RotD50 PGV or RotD50 SA(T)",
    );
    // OpenQuake has PGD; the export says so, and why it is not offered
    // (once: "OpenQuake has no IM for pgd").
    fails(
        &[&block[..], &["--format", "nrml", "--im", "pgd", "--direct"]].concat(),
        "OpenQuake calls it PGD, but the job runs on hazard curves",
    );
    fails(
        &[
            &block[..],
            &[
                "--format",
                "nrml",
                "--states",
                "light=0.2,overturned=overturned",
            ],
        ]
        .concat(),
        "damage state `light`: paper's regression knows only overturning",
    );
    fs::write(
        d.join("plain.csv"),
        "pga_g,annual_rate\n0.1,0.01\n0.2,0.001\n",
    )
    .unwrap();
    fails(
        &[&block[..], &["--format", "nrml", "--hazard", "plain.csv"]].concat(),
        "a plain `<im>,annual_rate` file has neither",
    );
    fs::create_dir(d.join("in")).unwrap();
    let oq = fs::read_to_string(root().join("records/hazard/synthetic-openquake.csv")).unwrap();
    fs::write(d.join("in/h.csv"), oq).unwrap();
    fails(
        &[
            "export", "--format", "nrml", "--b", "0.2", "--h", "0.9", "--hazard", "in/h.csv",
            "--out", "in",
        ],
        "holds in/h.csv, an input of this command",
    );
    // Outside the regression (ε = 0.97): the warning `risk` gives.
    let out = rocking(
        d,
        &[
            "export", "--format", "nrml", "--b", "0.2", "--h", "0.9", "--eps", "0.97", "--out", "y",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("ε = 0.970 is outside the regression"),
        "{}",
        stderr(&out)
    );
}

/// A logic tree exported to OpenQuake: each branch's fragility function and
/// a taxonomy mapping with the weights, so that `classical_damage` computes
/// the mean itself. Its P(overturned in 50 years) at each site equals the
/// weighted mean of its discrete formula over the branches (2e-6, float32
/// poes) and `rocking risk --tree`'s mean probability within 1.5 % (the
/// formula's discretisation, 0.05–0.08 % per branch, as above).
#[test]
fn openquake_computes_the_mean_over_an_exported_tree() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let (imls, poes) = hazard(&d.join("hazard.csv"));
    let block = ["--b", "0.2", "--h", "0.9", "--tree", "restitution-tests"];
    let out = rocking(
        d,
        &[
            &[
                "export",
                "--format",
                "nrml",
                "--hazard",
                "hazard.csv",
                "--out",
                "job",
                "--json",
            ][..],
            &block,
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let exported: Value = serde_json::from_str(&stdout(&out)).unwrap();
    let branches = exported[0]["tree"]["branches"].as_array().unwrap().clone();
    assert_eq!(branches.len(), 3);
    let mapping = fs::read_to_string(d.join("job/taxonomy_mapping.csv")).unwrap();
    assert_eq!(mapping.lines().count(), 4, "{mapping}");
    // Each branch's lognormal, from the fragility model the export wrote.
    let xml = fs::read_to_string(d.join("job/fragility_model.xml")).unwrap();
    let params: Vec<(f64, f64)> = xml
        .match_indices("<params ")
        .map(|(i, _)| {
            let tag = &xml[i..i + xml[i..].find("/>").unwrap()];
            let attr = |name: &str| -> f64 {
                let at = tag.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
                tag[at..at + tag[at..].find('"').unwrap()].parse().unwrap()
            };
            // NRML's logncdf states the variable's mean and stddev.
            let (mean, sd) = (attr("mean"), attr("stddev"));
            let beta = (1.0 + (sd / mean).powi(2)).ln().sqrt();
            (mean / (beta * beta / 2.0).exp(), beta)
        })
        .collect();
    assert_eq!(params.len(), 3, "{xml}");
    let risk = rocking(
        d,
        &[
            &[
                "risk",
                "--hazard",
                "hazard.csv",
                "--beyond",
                "stop",
                "--json",
            ][..],
            &block,
        ]
        .concat(),
    );
    assert!(risk.status.success(), "{}", stderr(&risk));
    let risk: Value = serde_json::from_str(&stdout(&risk)).unwrap();
    // The functions written are the branches `risk` integrates.
    for (b, &(median, beta)) in risk["fragility"]["tree"]["branches"]
        .as_array()
        .unwrap()
        .iter()
        .zip(&params)
    {
        assert!((b["median"].as_f64().unwrap() / median - 1.0).abs() < 1e-9);
        assert!((b["beta"].as_f64().unwrap() / beta - 1.0).abs() < 1e-9);
    }
    let oq = openquake(&venv, &d.join("job"));
    assert_eq!(oq.len(), 3);
    for (k, (_, shares)) in oq.iter().enumerate() {
        let p_oq = shares[1];
        let p_formula: f64 = branches
            .iter()
            .zip(&params)
            .map(|(b, &(median, beta))| {
                let f = |a: f64| phi((a / median).ln() / beta);
                b["weight"].as_f64().unwrap() * discrete(&imls, &poes[k], f, 50.0, 50.0)
            })
            .sum();
        let p_risk = risk["sites"][k]["p_overturn_in_years"].as_f64().unwrap();
        assert!(
            (p_oq - p_formula).abs() <= 2e-6 * p_formula + 1e-9,
            "site {k}: OpenQuake {p_oq} against its formula {p_formula}"
        );
        assert!(
            (p_oq - p_risk).abs() <= 0.015 * p_risk,
            "site {k}: OpenQuake {p_oq} against rocking risk --tree {p_risk}"
        );
    }
}

/// A hazard whose first IMLs OpenQuake reads as poe = 1 (single precision)
/// for a block on a floor, where no cut hides them: the export's warning
/// states the rate the job counts beyond the curve read below 1, and the
/// engine itself measures it, the job as written against the job given the
/// curve from its first IML read below 1 (the same fragility). One site,
/// λ = 1e-3·a^−2.2 over 0.02–3 g: its first 25 IMLs read as 1. The two
/// jobs' rates differ by the warned rate to the warning's four digits and
/// OpenQuake's seven (tolerance 2e-3 of it); the trimmed job has no
/// warning.
#[test]
fn openquake_counts_what_the_export_warns_of_where_poes_read_as_one() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let site = [(23.73, 38.0, 1e-3, 2.2)];
    let (imls, _) = hazard_in(&d.join("hazard.csv"), "PGA", 0.02, 3.0, &site);
    let records = root().join("records/fema-p695/far-field");
    let export = |hazard: &str, job: &str| -> Value {
        let out = rocking(
            d,
            &[
                "export",
                "--format",
                "nrml",
                "--hazard",
                hazard,
                "--out",
                job,
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--direct",
                "--records",
                records.to_str().unwrap(),
                "--floor",
                "0.5,0.05,1.3",
                "--json",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_str(&stdout(&out)).unwrap()
    };
    let full = export("hazard.csv", "job");
    let warnings = full[0]["fragility"]["warnings"].as_array().unwrap();
    let warning = warnings
        .iter()
        .filter_map(Value::as_str)
        .find(|w| w.contains("single precision"))
        .unwrap_or_else(|| panic!("no warning of poes read as 1: {warnings:?}"));
    let number_after = |key: &str| -> f64 {
        let rest = &warning[warning.find(key).unwrap() + key.len()..];
        rest.split([' ', '/']).next().unwrap().parse().unwrap()
    };
    let saturated = number_after("its first ") as usize;
    let warned = number_after("that adds ");
    assert_eq!(saturated, 25, "{warning}");
    // The curve from its first IML read below 1, the same IMLs after it.
    let text = fs::read_to_string(d.join("hazard.csv")).unwrap();
    let trimmed: Vec<String> = text
        .lines()
        .map(|l| {
            if l.starts_with('#') {
                return l.to_string();
            }
            let cells: Vec<&str> = l.split(',').collect();
            [&cells[..3], &cells[3 + saturated..]].concat().join(",")
        })
        .collect();
    fs::write(d.join("trimmed.csv"), trimmed.join("\n") + "\n").unwrap();
    assert_eq!(imls.len() - saturated, 75);
    let cut = export("trimmed.csv", "job-trimmed");
    let left = cut[0]["fragility"]["warnings"].as_array().unwrap();
    assert!(
        !left
            .iter()
            .any(|w| w.as_str().unwrap().contains("single precision")),
        "{left:?}"
    );
    // The state the warning names (the one its poes read as 1 add the most
    // to, every state checked): P(reached) sums its share and the heavier
    // ones' (OpenQuake's columns: no_damage, rocking, large_rocking,
    // overturned).
    let named = warning.split("the rate of `").nth(1).unwrap();
    let named = &named[..named.find('`').unwrap()];
    let from = 1 + ["rocking", "large_rocking", "overturned"]
        .iter()
        .position(|s| *s == named)
        .unwrap_or_else(|| panic!("{named}: {warning}"));
    let rate = |job: &str| {
        let p: f64 = openquake(&venv, &d.join(job))[0].1[from..].iter().sum();
        -(-p).ln_1p() / 50.0
    };
    let (with, without) = (rate("job"), rate("job-trimmed"));
    let counted = with - without;
    assert!(
        (counted - warned).abs() <= 2e-3 * warned,
        "OpenQuake counts {counted}/yr more with the saturated IMLs; the export warned of {warned}"
    );
}

/// A hazard file that ends in probabilities of 0, as OpenQuake writes
/// above the largest ground motion its model reaches (its own exports
/// leading with `custom_site_id`, which its `hazard_curves_csv` reader
/// takes for a poe: the job's copy drops it). Here each site's curve is a
/// power law to 0.5 g, flat to 0.8 g (no event between) and 0 from the
/// next IML: the events exceeding 0.8 g lie in the file's last bin.
/// OpenQuake counts them there; `risk` had called them "beyond the last
/// IML", extrapolated them by default and dropped them under `--beyond
/// stop`. They are now the file's own piece, spread evenly in PGA up to
/// its 0, under either rule, so the two rules agree. OpenQuake equals its
/// discrete formula to 2e-6; `risk` differs from it by that formula's
/// rule (each IML's fragility for the bin around it) on Δ ln a = 0.0137,
/// measured 0.02 and 0.05 %; the tolerance is 0.5 %, while the piece is
/// over a tenth of each site's rate.
#[test]
fn openquake_and_risk_agree_on_a_hazard_that_ends_in_zeros() {
    let Some(venv) = engines() else { return };
    let dir = tempdir();
    let d = dir.path();
    let imls: Vec<f64> = (0..300)
        .map(|i| 0.05 * (3.0f64 / 0.05).powf(i as f64 / 299.0))
        .collect();
    let sites = [(21.73, 38.25, 2e-3, 2.2), (23.73, 37.98, 5e-4, 3.0)];
    let places: Vec<(f64, f64)> = sites.iter().map(|s| (s.0, s.1)).collect();
    let rate = |k: usize, a: f64| {
        let (k0, slope) = (sites[k].2, sites[k].3);
        match a {
            a if a <= 0.5 => k0 * a.powf(-slope),
            a if a <= 0.8 => k0 * 0.5f64.powf(-slope),
            _ => 0.0,
        }
    };
    let poes = hazard_of(&d.join("hazard.csv"), "PGA", &imls, &places, rate, true);
    let block = ["--b", "0.2", "--h", "0.9"];
    let out = rocking(
        d,
        &[
            &[
                "export",
                "--format",
                "nrml",
                "--hazard",
                "hazard.csv",
                "--out",
                "job",
                "--json",
            ][..],
            &block,
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        !stderr(&out).contains("counts nothing beyond"),
        "{}",
        stderr(&out)
    );
    let (median, beta) = stated(&serde_json::from_str(&stdout(&out)).unwrap())[0][0];
    let risk = |beyond: &str| -> Value {
        let out = rocking(
            d,
            &[
                &[
                    "risk",
                    "--hazard",
                    "hazard.csv",
                    "--beyond",
                    beyond,
                    "--json",
                ][..],
                &block,
            ]
            .concat(),
        );
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_str(&stdout(&out)).unwrap()
    };
    let (stop, extrapolate) = (risk("stop"), risk("extrapolate"));
    let cut = 0.2 / 0.9;
    let oq = openquake(&venv, &d.join("job"));
    assert_eq!(oq.len(), sites.len());
    for (k, (_, shares)) in oq.iter().enumerate() {
        let f = |a: f64| {
            if a <= cut {
                0.0
            } else {
                phi((a / median).ln() / beta)
            }
        };
        let p_discrete = discrete(&imls, &poes[k], f, 50.0, 50.0);
        let p_oq = shares[1];
        assert!(
            (p_oq - p_discrete).abs() <= 2e-6 * p_discrete + 1e-9,
            "site {k}: OpenQuake {p_oq} against its formula {p_discrete}"
        );
        let site = &stop["sites"][k];
        let p_risk = site["p_overturn_in_years"].as_f64().unwrap();
        assert!(
            (p_oq - p_risk).abs() <= 0.005 * p_risk,
            "site {k}: OpenQuake {p_oq} against rocking risk {p_risk}"
        );
        // The file's last piece (before the empty bin past its 0) weighs.
        let bins = site["deaggregation"].as_array().unwrap();
        let piece = bins[bins.len() - 2]["annual_rate"].as_f64().unwrap();
        assert!(
            piece > 0.1 * site["annual_rate"].as_f64().unwrap(),
            "{site}"
        );
        // Nothing lies beyond a file's 0: the rules agree.
        assert_eq!(stop["sites"][k], extrapolate["sites"][k]);
    }
}
