//! `rocking risk` end to end: the rate of overturning against Cornell's
//! closed form (a power-law hazard with a lognormal fragility) and against
//! an independent quadrature written here (an OpenQuake file with several
//! sites); `--direct` against the records' own capacities from `rocking
//! capacity`; the inventory table and figure; every refusal of the hazard
//! file, naming file and line.

use std::fs;
use std::path::Path;

use rocking::tables::read;
use rocking::tables::risk::RiskRow;
use serde_json::Value;

use crate::util::{bundled_records, cornell_above, phi, rocking, root, stderr, stdout, tempdir};

fn json(out: &std::process::Output) -> Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

/// `pga_g,annual_rate` of λ(a) = k0 a^(−k) at IMLs log-spaced over [lo, hi].
fn power_law_file(path: &Path, k0: f64, k: f64, lo: f64, hi: f64, n: usize) {
    let mut s = String::from("pga_g,annual_rate\n");
    for i in 0..n {
        let a = lo * (hi / lo).powf(i as f64 / (n - 1) as f64);
        s.push_str(&format!("{a:?},{:?}\n", k0 * a.powf(-k)));
    }
    fs::write(path, s).unwrap();
}

#[test]
fn power_law_hazard_gives_cornells_closed_form() {
    let dir = tempdir();
    let d = dir.path();
    let (k0, k) = (2e-4, 2.6);
    // The paper's fragility of this block has its median near 0.45 g and
    // β near 0.26: a curve from 0.005 g (9β below) is complete below, and
    // extrapolation is exact for a power law.
    power_law_file(&d.join("h.csv"), k0, k, 0.005, 3.0, 30);
    let v = json(&rocking(
        d,
        &[
            "risk", "--hazard", "h.csv", "--b", "0.2", "--h", "0.9", "--json",
        ],
    ));
    let m = v["fragility"]["median"].as_f64().unwrap();
    let beta = v["fragility"]["beta"].as_f64().unwrap();
    // The block cannot move below its uplift PGA c = g·tan α = b/h g: P is
    // cut there (MODEL.md §13).
    let expected = cornell_above(k0, k, m, beta, 0.2 / 0.9);
    let site = &v["sites"][0];
    let got = site["annual_rate"].as_f64().unwrap();
    assert!((got / expected - 1.0).abs() < 1e-9, "{got} vs {expected}");
    assert!((site["return_period_years"].as_f64().unwrap() * got - 1.0).abs() < 1e-12);
    let p50 = 1.0 - (-50.0 * got).exp();
    assert!((site["p_overturn_in_years"].as_f64().unwrap() - p50).abs() < 1e-15);
    // The deaggregation adds up, and what lies beyond 3 g is the tail of
    // the same closed form: k0 e^{…} [1 − Φ((ln 3 − ln m + kβ²)/β)] + P(3)λ(3).
    let bins = site["deaggregation"].as_array().unwrap();
    let total: f64 = bins
        .iter()
        .map(|b| b["annual_rate"].as_f64().unwrap())
        .sum();
    assert!((total / got - 1.0).abs() < 1e-12);
    let beyond = bins.last().unwrap()["annual_rate"].as_f64().unwrap();
    let x = ((3.0f64).ln() - m.ln() + k * beta * beta) / beta;
    let tail = k0 * m.powf(-k) * (k * k * beta * beta / 2.0).exp() * (1.0 - phi(x))
        + phi(((3.0f64).ln() - m.ln()) / beta) * k0 * 3f64.powf(-k);
    assert!((beyond / tail - 1.0).abs() < 1e-6, "{beyond} vs {tail}");
    assert!((site["share_beyond_last_iml"].as_f64().unwrap() - beyond / got).abs() < 1e-12);
    // With --beyond stop that share is not counted.
    let v = json(&rocking(
        d,
        &[
            "risk", "--hazard", "h.csv", "--b", "0.2", "--h", "0.9", "--beyond", "stop", "--json",
        ],
    ));
    let stopped = v["sites"][0]["annual_rate"].as_f64().unwrap();
    assert!(((got - stopped) / beyond - 1.0).abs() < 1e-9);
}

/// ∫ P |dλ| over a ≥ `cut` by the midpoint rule on 20,000 steps in ln a
/// a segment, the hazard interpolated log-log between `imls` (nothing
/// beyond the last): an implementation independent of the tool's closed
/// forms.
fn quadrature(imls: &[f64], rates: &[f64], m: f64, beta: f64, cut: f64) -> f64 {
    let mut sum = 0.0;
    for w in 0..imls.len() - 1 {
        let (a0, a1, r0, r1) = (imls[w], imls[w + 1], rates[w], rates[w + 1]);
        let k = (r0 / r1).ln() / (a1 / a0).ln();
        if a1 <= cut {
            continue;
        }
        let from = a0.max(cut);
        let steps = 20_000;
        let h = (a1 / from).ln() / steps as f64;
        for j in 0..steps {
            let u = from.ln() + (j as f64 + 0.5) * h;
            let lam = r0 * (-k * (u - a0.ln())).exp();
            sum += phi((u - m.ln()) / beta) * k * lam * h;
        }
    }
    sum
}

#[test]
fn openquake_sites_against_quadrature() {
    let dir = tempdir();
    let d = dir.path();
    let imls = [0.005, 0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.8, 1.2, 2.0];
    let poes = [
        [
            1.0, 0.99, 0.7, 0.35, 0.12, 0.05, 0.015, 0.004, 0.001, 0.0002,
        ],
        [
            0.999, 0.95, 0.5, 0.2, 0.06, 0.02, 0.004, 0.0008, 0.0001, 0.0,
        ],
    ];
    let mut text = String::from(
        "#,,,,,\"generated_by='OpenQuake engine 3.16.0', start_date='2026-01-01', checksum=3, kind='mean', investigation_time=50.0, imt='PGA'\"\n",
    );
    text.push_str("lon,lat,depth");
    for a in imls {
        text.push_str(&format!(",poe-{a}"));
    }
    text.push('\n');
    for (s, row) in poes.iter().enumerate() {
        text.push_str(&format!("{}.5,{}.25,0.0", 20 + s, 38 + s));
        for p in row {
            text.push_str(&format!(",{p}"));
        }
        text.push('\n');
    }
    fs::write(d.join("hazard_curve-mean-PGA_7.csv"), &text).unwrap();
    let v = json(&rocking(
        d,
        &[
            "risk",
            "--hazard",
            "hazard_curve-mean-PGA_7.csv",
            "--b",
            "0.25",
            "--h",
            "1",
            "--beyond",
            "stop",
            "--json",
        ],
    ));
    let m = v["fragility"]["median"].as_f64().unwrap();
    let beta = v["fragility"]["beta"].as_f64().unwrap();
    let sites = v["sites"].as_array().unwrap();
    assert_eq!(sites.len(), 2);
    for (s, site) in sites.iter().enumerate() {
        assert_eq!(site["site"], s);
        assert_eq!(site["lon"].as_f64(), Some(20.5 + s as f64));
        assert_eq!(site["lat"].as_f64(), Some(38.25 + s as f64));
        // λ = −ln(1 − poe)/50, keeping the finite positive rates.
        let keep: Vec<(f64, f64)> = imls
            .iter()
            .zip(poes[s])
            .filter(|&(_, p)| p > 0.0 && p < 1.0)
            .map(|(&a, p): (&f64, f64)| (a, -(1.0 - p).ln() / 50.0))
            .collect();
        let (a, r): (Vec<f64>, Vec<f64>) = keep.into_iter().unzip();
        // Site 1's file ends in a 0 at 2 g: its events from 1.2 g are the
        // file's, spread evenly in PGA up to 2 g (nothing beyond: the same
        // under `--beyond stop`): their rate times the mean P over the
        // piece, by the midpoint rule.
        let closing = match s {
            1 => {
                let (lo, hi, n) = (1.2, 2.0, 20_000);
                let mean: f64 = (0..n)
                    .map(|j| phi(((lo + (j as f64 + 0.5) * (hi - lo) / n as f64) / m).ln() / beta))
                    .sum::<f64>()
                    / n as f64;
                r.last().unwrap() * mean
            }
            _ => 0.0,
        };
        // Cut at the block's uplift PGA, b/h g (MODEL.md §13).
        let expected = quadrature(&a, &r, m, beta, 0.25) + closing;
        let got = site["annual_rate"].as_f64().unwrap();
        assert!(
            (got / expected - 1.0).abs() < 1e-8,
            "site {s}: {got} vs {expected}"
        );
        assert_eq!(site["first_iml"].as_f64(), Some(a[0]));
        let end = if s == 1 { 2.0 } else { *a.last().unwrap() };
        assert_eq!(site["last_iml"].as_f64(), Some(end));
        assert_eq!(site["imls_dropped"], if s == 0 { 1 } else { 0 });
    }
    // The same numbers as OpenQuake's 84 % quantile curve: the same rates,
    // said to be that curve's and not the mean's (the mean file says
    // nothing of it).
    let mean = rocking(
        d,
        &[
            "risk",
            "--hazard",
            "hazard_curve-mean-PGA_7.csv",
            "--b",
            "0.25",
            "--h",
            "1",
        ],
    );
    assert!(!String::from_utf8_lossy(&mean.stderr).contains("not the mean hazard"));
    fs::write(
        d.join("hazard_curve-quantile_0.84-PGA_7.csv"),
        text.replace("kind='mean'", "kind='quantile-0.84'"),
    )
    .unwrap();
    let args = |file: &'static str| {
        [
            "risk", "--hazard", file, "--b", "0.25", "--h", "1", "--beyond", "stop", "--json",
        ]
    };
    let out = rocking(d, &args("hazard_curve-quantile_0.84-PGA_7.csv"));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("the 84 % quantile of the hazard over OpenQuake's logic tree (kind='quantile-0.84'), not the mean hazard"),
        "{err}"
    );
    assert_eq!(err.matches("not the mean hazard").count(), 1, "{err}");
    assert_eq!(json(&out)["sites"], v["sites"]);
}

#[test]
fn direct_uses_the_records_own_capacities() {
    let dir = tempdir();
    let d = dir.path();
    let recs = d.join("recs");
    fs::create_dir_all(&recs).unwrap();
    let ids = [
        "RSN1111_KOBE_NIS000",
        "RSN953_NORTHR_MUL009",
        "RSN1633_MANJIL_ABBAR--L",
    ];
    for id in ids {
        fs::copy(
            bundled_records().join(format!("far-field/{id}.AT2")),
            recs.join(format!("{id}.AT2")),
        )
        .unwrap();
    }
    let (k0, k) = (1e-4, 2.2);
    power_law_file(&d.join("h.csv"), k0, k, 0.001, 5.0, 40);
    // A slender block (α = 0.1 rad): the linearised model, so `capacity`'s
    // default model is the one --direct picks.
    let (b, h) = ("0.1", "1.0");
    let v = json(&rocking(
        d,
        &[
            "risk",
            "--hazard",
            "h.csv",
            "--b",
            b,
            "--h",
            h,
            "--eps",
            "0.8",
            "--direct",
            "--records",
            "recs",
            "--method",
            "empirical",
            "--json",
        ],
    ));
    assert_eq!(v["fragility"]["fit"], "empirical");
    assert_eq!(v["fragility"]["source"], "direct");
    assert_eq!(v["fragility"]["records_folder"], "recs");
    assert_eq!(v["fragility"]["records"], 3);
    // Three records: the one warning is that the fit rests on few.
    let warnings = v["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0]
        .as_str()
        .unwrap()
        .contains("3 records (fewer than 10)"));
    // The records' curve rises linearly from 0 at the smallest overturning
    // PGA t = α/η_c to 1/2 at the middle one and 1 at the largest: on
    // λ = k₀a^(−k), λ_OT = Σ ramps ∫ P kλ/a da + λ(t₃), each ramp's
    // integral from its antiderivative.
    let alpha = 0.1f64.atan();
    let p = (3.0 * 9.80665 / (4.0 * (0.01f64 + 1.0).sqrt())).sqrt();
    let mut t = Vec::new();
    for id in ids {
        let cap = json(&rocking(
            d,
            &[
                "capacity",
                "--record",
                recs.join(format!("{id}.AT2")).to_str().unwrap(),
                "--p",
                &p.to_string(),
                "--eps",
                "0.8",
                "--json",
            ],
        ));
        t.push(alpha / cap["eta_c"].as_f64().unwrap());
    }
    t.sort_by(f64::total_cmp);
    let rate = |a: f64| k0 * a.powf(-k);
    // ∫_{x1}^{x2} (p1 + s (a − x1)) k k₀ a^(−k−1) da.
    let ramp = |x1: f64, x2: f64, p1: f64, p2: f64| {
        let s = (p2 - p1) / (x2 - x1);
        let anti = |a: f64| k * k0 * (a.powf(1.0 - k) / (1.0 - k) + x1 * a.powf(-k) / k);
        p1 * (rate(x1) - rate(x2)) + s * (anti(x2) - anti(x1))
    };
    let expected = ramp(t[0], t[1], 0.0, 0.5) + ramp(t[1], t[2], 0.5, 1.0) + rate(t[2]);
    let got = v["sites"][0]["annual_rate"].as_f64().unwrap();
    assert!((got / expected - 1.0).abs() < 1e-9, "{got} vs {expected}");
}

/// `risk.parquet` stated a lognormal's median and β beside a rate from the
/// records' own curve (`--method empirical`), and named no fit: its β
/// (0.452) described a fragility the rate (2.69e-4 against the lognormal's
/// 3.70e-4) did not use. The table now names the fit, and the records'
/// curve has no β; a lognormal's row keeps the β `fragility` states.
#[test]
fn the_risk_table_names_the_fit_its_rate_integrates() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(d.join("inv.csv"), "name,b,h,eps\nA,0.25,1.0,0.8\n").unwrap();
    let hazard = root().join("records/hazard/synthetic-site.csv");
    let table = |method: &str| -> RiskRow {
        let out = rocking(
            d,
            &[
                "risk",
                "--hazard",
                hazard.to_str().unwrap(),
                "--inventory",
                "inv.csv",
                "--direct",
                "--method",
                method,
                "--out",
                "r.parquet",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        read::<RiskRow>(&d.join("r.parquet")).unwrap().remove(0)
    };
    let (curve, lognormal) = (table("empirical"), table("fractile"));
    assert_eq!((curve.fit.as_str(), curve.beta), ("empirical", None));
    assert_eq!(lognormal.fit, "fractile");
    assert_ne!(curve.annual_rate, lognormal.annual_rate);
    let f = rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.25",
            "--h",
            "1.0",
            "--eps",
            "0.8",
            "--direct",
            "--pga",
            "0.3",
            "--json",
        ],
    );
    let f: serde_json::Value = serde_json::from_slice(&f.stdout).unwrap();
    assert_eq!(lognormal.beta, f["beta"].as_f64());
    assert_eq!(lognormal.median, f["median"].as_f64());
}

#[test]
fn an_inventory_becomes_a_table_and_a_ranking() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("h.csv"),
        "pga_g,annual_rate\n0.05,0.05\n0.1,0.01\n0.2,0.002\n0.4,0.0003\n0.8,0.00003\n",
    )
    .unwrap();
    fs::write(
        d.join("blocks.csv"),
        "name,b,h,eps\n\"statue, marble\",0.2,0.9,\nrack,0.3,1.0,0.75\nslab,1.0,0.5,0.6\n",
    )
    .unwrap();
    let out = rocking(
        d,
        &[
            "risk",
            "--hazard",
            "h.csv",
            "--inventory",
            "blocks.csv",
            "--out",
            "risk.parquet",
            "--plot",
            "ranking.svg",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let rows: Vec<RiskRow> = read(&d.join("risk.parquet")).unwrap();
    assert_eq!(rows.len(), 3);
    assert_eq!(rows[0].block, "statue, marble");
    assert!(rows[0].eps_housner && !rows[1].eps_housner);
    // The squat slab (p ≈ 2.9 1/s but ε = 0.6, α = 1.1 rad) is flagged:
    // the linearised regression does not describe it.
    assert!(rows[2].warnings.contains("use --direct"), "{:?}", rows[2]);
    // Each row's probability in 50 years follows from its rate.
    for r in &rows {
        assert!((r.p_overturn_in_years - (1.0 - (-r.annual_rate * r.years).exp())).abs() < 1e-15);
    }
    let svg = fs::read_to_string(d.join("ranking.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("statue, marble") && svg.contains("rack"));
    assert!(stdout(&out).contains("wrote risk.parquet (3 rows)"));
    // A bad inventory line is named.
    fs::write(
        d.join("bad.csv"),
        "name,b,h,eps\nok,0.2,1,0.8\nbad,0.2,1,1.5\n",
    )
    .unwrap();
    let out = rocking(
        d,
        &[
            "risk",
            "--hazard",
            "h.csv",
            "--inventory",
            "bad.csv",
            "--out",
            "x.parquet",
        ],
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("block `bad`") && stderr(&out).contains("1.5"),
        "{}",
        stderr(&out)
    );
    fs::write(d.join("bad2.csv"), "name,b,h\nok,0.2,1\nbad,x,1\n").unwrap();
    let out = rocking(
        d,
        &[
            "risk",
            "--hazard",
            "h.csv",
            "--inventory",
            "bad2.csv",
            "--out",
            "x.parquet",
        ],
    );
    assert!(stderr(&out).contains("bad2.csv:3"), "{}", stderr(&out));
    // A row with a field too many, in a file with CRLF endings: its line
    // (3, counted by hand), once (the csv crate's own count said 2).
    fs::write(
        d.join("bad3.csv"),
        "name,b,h\r\nok,0.2,1\r\nbad,0.2,1,7\r\n",
    )
    .unwrap();
    let args = ["risk", "--hazard", "h.csv", "--inventory", "bad3.csv"];
    let out = rocking(d, &[&args[..], &["--out", "x.parquet"]].concat());
    assert!(
        stderr(&out).contains("bad3.csv:3: 4 fields where the header has 3\n"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn bad_hazard_files_are_refused_naming_file_and_line() {
    let dir = tempdir();
    let d = dir.path();
    let head = "#,,,,,\"generated_by='OpenQuake engine 3.16.0', kind='mean', investigation_time=50.0, imt='PGA'\"\nlon,lat,depth,poe-0.1,poe-0.2,poe-0.4\n";
    let cases = [
        (
            head.replace("imt='PGA'", "imt='MMI'") + "1,2,0,0.5,0.2,0.1\n",
            1,
            "imt = 'MMI'",
        ),
        (
            head.replace("investigation_time=50.0, ", "") + "1,2,0,0.5,0.2,0.1\n",
            1,
            "investigation_time",
        ),
        (
            head.to_string() + "1,2,0,0.5,1.2,0.1\n",
            3,
            "outside [0, 1]",
        ),
        (
            head.to_string() + "1,2,0,0.5,0.2,0.1\n1,2,0,0.5,0.6,0.1\n",
            4,
            "rises",
        ),
        (head.to_string() + "1,2,0,0.5,nan?,0.1\n", 3, "not a number"),
    ];
    for (i, (text, line, what)) in cases.iter().enumerate() {
        let name = format!("h{i}.csv");
        fs::write(d.join(&name), text).unwrap();
        let out = rocking(d, &["risk", "--hazard", &name, "--b", "0.2", "--h", "1"]);
        let err = stderr(&out);
        assert!(!out.status.success(), "{what}");
        assert!(
            err.contains(&format!("{name}:{line}:")) && err.contains(what),
            "{what}: {err}"
        );
    }
    // A site the file does not have, and a curve with a single usable point.
    fs::write(d.join("one.csv"), "pga_g,annual_rate\n0.1,0.01\n").unwrap();
    let out = rocking(
        d,
        &["risk", "--hazard", "one.csv", "--b", "0.2", "--h", "1"],
    );
    assert!(stderr(&out).contains("needs two"), "{}", stderr(&out));
    fs::write(
        d.join("two.csv"),
        "pga_g,annual_rate\n0.1,0.01\n0.2,0.001\n",
    )
    .unwrap();
    let out = rocking(
        d,
        &[
            "risk", "--hazard", "two.csv", "--site", "3", "--b", "0.2", "--h", "1",
        ],
    );
    assert!(stderr(&out).contains("1 site(s)"), "{}", stderr(&out));
    // A tolerance that is not a relative error: once silently hid (NaN,
    // inf) or garbled (−1) the linearisation warning.
    for bad in ["nan", "inf", "-1", "0"] {
        let out = rocking(
            d,
            &[
                "risk",
                "--hazard",
                "two.csv",
                "--b",
                "0.2",
                "--h",
                "1",
                "--auto-tol",
                bad,
            ],
        );
        assert!(!out.status.success(), "--auto-tol {bad}");
        assert!(
            stderr(&out).contains("--auto-tol: auto tolerance") && stderr(&out).contains("(0, 1)"),
            "--auto-tol {bad}: {}",
            stderr(&out)
        );
    }
}

/// A flat hazard curve has no events within it: with `--beyond stop` the
/// rate is 0 exactly and no bin is negative (once 1.5e-18 with bins of
/// −14 % and 113 %, and −0 with --direct); extrapolated, its rate exceeds
/// every level and all of it overturns the block (once 0). A flat last
/// segment likewise carries λ(last IML) beyond the curve (once 2.8e-5/yr
/// and "0 % beyond" where 1e-3/yr exceed 0.6 g).
#[test]
fn a_flat_hazard_tail_is_carried_beyond_the_curve() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("flat.csv"),
        "pga_g,annual_rate\n0.1,0.01\n0.2,0.01\n0.3,0.01\n",
    )
    .unwrap();
    let risk = |file: &str, beyond: &str| {
        json(&rocking(
            d,
            &[
                "risk", "--hazard", file, "--b", "0.2", "--h", "0.9", "--beyond", beyond, "--json",
            ],
        ))
    };
    let v = risk("flat.csv", "stop");
    let site = &v["sites"][0];
    assert_eq!(site["annual_rate"].as_f64(), Some(0.0), "{site}");
    for bin in site["deaggregation"].as_array().unwrap() {
        for key in ["annual_rate", "share"] {
            let x = bin[key].as_f64().unwrap();
            assert_eq!(x.to_bits(), 0, "{key} = {x:e} (+0 exactly): {bin}");
        }
    }
    let v = risk("flat.csv", "extrapolate");
    assert_eq!(v["sites"][0]["annual_rate"].as_f64(), Some(0.01), "{v}");
    assert_eq!(v["sites"][0]["share_beyond_last_iml"].as_f64(), Some(1.0));
    fs::write(
        d.join("tail.csv"),
        "pga_g,annual_rate\n0.1,0.01\n0.3,0.001\n0.6,0.001\n",
    )
    .unwrap();
    let v = risk("tail.csv", "extrapolate");
    let site = &v["sites"][0];
    let (m, beta) = (
        v["fragility"]["median"].as_f64().unwrap(),
        v["fragility"]["beta"].as_f64().unwrap(),
    );
    // 1e-3/yr beyond 0.6 g, all of which overturns it, and the segments
    // inside by quadrature (cut at the uplift PGA, 0.2/0.9 g).
    let inside = quadrature(&[0.1, 0.3, 0.6], &[0.01, 0.001, 0.001], m, beta, 0.2 / 0.9);
    let got = site["annual_rate"].as_f64().unwrap();
    assert!(
        (got / (inside + 1e-3) - 1.0).abs() < 1e-8,
        "{got} vs {inside} + 1e-3"
    );
    let beyond = site["share_beyond_last_iml"].as_f64().unwrap();
    assert!((beyond - 1e-3 / got).abs() < 1e-12, "{site}");
}

/// What the guide concludes from its worked example (its printed outputs
/// are checked by `docs::the_guides_recipes_print_what_it_shows`): the
/// same 44 capacities of the statue scatter less in PGV than in PGA.
#[test]
fn the_guides_statue_scatters_less_in_pgv_than_in_pga() {
    let guide = fs::read_to_string(crate::util::root().join("docs/guide.md")).unwrap();
    let pga = "cargo run --release -- risk --hazard records/hazard/synthetic-site.csv --b 0.2 --h 0.9 --direct";
    let pgv = "cargo run --release -- risk --hazard records/hazard/synthetic-site-pgv.csv --b 0.2 --h 0.9 --direct";
    for command in [pga, pgv] {
        assert!(
            guide.contains(&format!("{command}\n")),
            "the guide shows `{command}`"
        );
    }
    let beta = |command: &str| {
        let mut args: Vec<&str> = command
            .trim_start_matches("cargo run --release -- ")
            .split_whitespace()
            .collect();
        args.push("--json");
        json(&rocking(&root(), &args))["fragility"]["beta"]
            .as_f64()
            .unwrap()
    };
    assert!(beta(pgv) < beta(pga) - 0.05);
}

/// What users write that the tool once misread: a quoted CSV header, spaces
/// around `=` in OpenQuake's metadata, `Housner` capitalised; and an
/// inventory's bad row named by its file, line and column, not by flags
/// the user never gave.
#[test]
fn inputs_as_users_write_them_and_rows_named_by_line() {
    let dir = tempdir();
    let d = dir.path();
    let rate = |args: &[&str]| -> f64 {
        let v = json(&rocking(d, args));
        v["sites"][0]["annual_rate"].as_f64().unwrap()
    };
    fs::write(
        d.join("plain.csv"),
        "pga_g,annual_rate\n0.1,0.01\n0.2,0.001\n0.4,0.0001\n",
    )
    .unwrap();
    fs::write(
        d.join("quoted.csv"),
        "\"pga_g\",\"annual_rate\"\n0.1,0.01\n0.2,0.001\n0.4,0.0001\n",
    )
    .unwrap();
    let one = ["--b", "0.2", "--h", "1", "--json"];
    let plain = rate(&[&["risk", "--hazard", "plain.csv"][..], &one].concat());
    assert_eq!(
        rate(&[&["risk", "--hazard", "quoted.csv"][..], &one].concat()),
        plain
    );
    let oq = fs::read_to_string(root().join("records/hazard/synthetic-openquake.csv")).unwrap();
    fs::write(d.join("oq.csv"), &oq).unwrap();
    fs::write(
        d.join("oq-spaced.csv"),
        oq.replace("imt='PGA'", "imt = 'PGA'"),
    )
    .unwrap();
    assert_eq!(
        rate(&[&["risk", "--hazard", "oq-spaced.csv"][..], &one].concat()),
        rate(&[&["risk", "--hazard", "oq.csv"][..], &one].concat())
    );
    let inventory = |rows: &str| {
        fs::write(
            d.join("inv.csv"),
            format!("name,b,h,eps\nfine,0.2,1.0,0.9\n{rows}"),
        )
        .unwrap();
        rocking(
            d,
            &[
                "risk",
                "--hazard",
                "plain.csv",
                "--inventory",
                "inv.csv",
                "--out",
                "r.parquet",
            ],
        )
    };
    assert!(inventory("vase,0.1,0.5,Housner\n").status.success());
    for (row, expected) in [
        (
            "neg,-0.2,1.0,0.9\n",
            "inv.csv:3: block `neg`: `b`, `h`: b = -0.2 m",
        ),
        (
            "hot,0.2,1.0,1.5\n",
            "inv.csv:3: block `hot`: `eps`: ε = 1.5",
        ),
        (
            "squat,1.0,0.5,housner\n",
            "inv.csv:3: block `squat`: `eps`: Housner's ε",
        ),
    ] {
        let out = inventory(row);
        let err = stderr(&out);
        assert!(
            !out.status.success() && err.contains(expected),
            "{row}: {err}"
        );
        assert!(!err.contains("--b") && !err.contains("--eps"), "{err}");
    }
}

/// `fragility` warns exactly where `risk` does (it once printed a curve
/// without a word for a stocky block, p or ε outside the regression's
/// range), and `risk` says when its rate is mostly an extrapolation
/// beyond the hazard curve's last IML.
#[test]
fn fragility_and_risk_warn_alike_and_risk_flags_extrapolation() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("h.csv"),
        "pga_g,annual_rate\n0.01,0.1\n0.02,0.02\n0.05,0.002\n",
    )
    .unwrap();
    for (b, h, expected) in [
        ("0.25", "1", vec!["α = 0.245 rad"]),
        ("1", "0.5", vec!["α = 1.107 rad"]),
        (
            "0.01",
            "0.05",
            vec!["p = ", "1/s is outside the regression's 0.33–10 1/s"],
        ),
        (
            "0.05",
            "1",
            vec!["ε = 0.996 is outside the regression's 0.5–0.95"],
        ),
        ("0.15", "1", vec![]),
    ] {
        let eps: &[&str] = match b {
            "1" => &["--eps", "0.5"],
            "0.15" => &["--eps", "0.8"],
            _ => &[],
        };
        let f = json(&rocking(
            d,
            &[
                &["fragility", "--b", b, "--h", h, "--pga", "0.3", "--json"][..],
                eps,
            ]
            .concat(),
        ));
        let r = json(&rocking(
            d,
            &[
                &[
                    "risk", "--hazard", "h.csv", "--b", b, "--h", h, "--beyond", "stop", "--json",
                ][..],
                eps,
            ]
            .concat(),
        ));
        assert_eq!(f["warnings"], r["warnings"], "b = {b}, h = {h}");
        let text = f["warnings"].to_string();
        for e in &expected {
            assert!(text.contains(e), "b = {b}, h = {h}: {text}");
        }
        if expected.is_empty() {
            assert_eq!(f["warnings"].as_array().unwrap().len(), 0, "{text}");
        }
    }
    // The curve ends at 0.05 g, far below this block's median (about
    // 0.45 g): extrapolated, nearly all of the rate lies beyond it.
    let r = json(&rocking(
        d,
        &[
            "risk", "--hazard", "h.csv", "--b", "0.1", "--h", "1", "--json",
        ],
    ));
    let share = r["sites"][0]["share_beyond_last_iml"].as_f64().unwrap();
    assert!(share > 0.5, "{share}");
    assert!(
        r["warnings"]
            .to_string()
            .contains("beyond the hazard curve's last IML"),
        "{r}"
    );
}

/// A PGV hazard λ(v) = k0 v^(−k) (cm/s) and the block's lognormal PGV
/// fragility from a study's IM table give Cornell's k0 m^(−k) e^{k²β²/2};
/// for a block on a node of the study's grid, m and β are that node's
/// (m = the dimensionless median p·PGV/(αg) turned back into cm/s), and
/// `fragility --im pgv` says the same. A hazard in PGV with a fragility
/// asked in PGA is refused.
#[test]
fn pgv_hazard_gives_cornells_closed_form() {
    let dir = tempdir();
    let d = dir.path();
    let (b, h) = (0.2f64, 0.9f64);
    let p = (3.0 * 9.80665 / (4.0 * (b * b + h * h).sqrt())).sqrt();
    let alpha = (b / h).atan();
    let pipeline = crate::util::write_pipeline(
        d,
        "pgvgrid",
        &format!(
            "sets = [\"far-field\"]\n[model]\nkind = \"linearized\"\n[blocks]\np = [1.0, {p:?}, 5.0]\neps = [0.6, 0.7, 0.8]\n"
        ),
    );
    let outputs = d.join("out");
    let (pipe, outs) = (pipeline.to_str().unwrap(), outputs.to_str().unwrap());
    let run = rocking(d, &["run", pipe, "--outputs", outs]);
    assert!(run.status.success(), "{}", stderr(&run));
    let (k0, k) = (5e-3, 2.2);
    let mut s = String::from("pgv_cm_s,annual_rate\n");
    for i in 0..30 {
        let v = 0.5 * (2000.0f64 / 0.5).powf(i as f64 / 29.0);
        s.push_str(&format!("{v:?},{:?}\n", k0 * v.powf(-k)));
    }
    fs::write(d.join("pgv.csv"), s).unwrap();
    let common = [
        "--b",
        "0.2",
        "--h",
        "0.9",
        "--eps",
        "0.7",
        "--from",
        pipe,
        "--outputs",
        outs,
        "--json",
    ];
    let v = json(&rocking(
        d,
        &[&["risk", "--hazard", "pgv.csv"][..], &common].concat(),
    ));
    assert_eq!(v["fragility"]["im"], "pgv");
    assert_eq!(v["fragility"]["unit"], "cm/s");
    let m = v["fragility"]["median"].as_f64().unwrap();
    let beta = v["fragility"]["beta"].as_f64().unwrap();
    let got = v["sites"][0]["annual_rate"].as_f64().unwrap();
    let expected = k0 * m.powf(-k) * (k * k * beta * beta / 2.0).exp();
    assert!((got / expected - 1.0).abs() < 1e-9, "{got} vs {expected}");
    // The node's values, by hand from the study's damage table (the
    // overturned state's fractile fit in PGV).
    let states: Vec<rocking::tables::damage::DamageStateRow> =
        read(&outputs.join("pgvgrid/damage_states.parquet")).unwrap();
    let node = states
        .iter()
        .find(|e| {
            e.im == "pgv"
                && e.state == "overturned"
                && e.method == rocking::damage::FitMethod::Fractile
                && (e.p - p).abs() < 1e-12
                && e.eps == 0.7
        })
        .unwrap();
    let by_hand = node.median_dimensionless.unwrap() * alpha * 9.80665 * 100.0 / p;
    assert!((m / by_hand - 1.0).abs() < 1e-9, "{m} vs {by_hand}");
    assert!((beta - node.beta.unwrap()).abs() < 1e-9);
    let f = json(&rocking(
        d,
        &[&["fragility", "--im", "pgv", "--at", "30,60"][..], &common].concat(),
    ));
    assert_eq!(f["median"].as_f64(), Some(m));
    assert_eq!(f["points"][1]["iml"].as_f64(), Some(60.0));
    // A PGV hazard and a PGA fragility do not mix.
    let out = rocking(
        d,
        &[&["risk", "--hazard", "pgv.csv", "--im", "pga"][..], &common].concat(),
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("a hazard in pgv (cm/s), and the fragility asked for is in pga"),
        "{}",
        stderr(&out)
    );
    // The paper's regression has no PGV.
    let out = rocking(
        d,
        &["risk", "--hazard", "pgv.csv", "--b", "0.2", "--h", "0.9"],
    );
    assert!(
        stderr(&out).contains("the paper's regression is in PGA"),
        "{}",
        stderr(&out)
    );
}

/// One block, one fragility: `fragility --direct`, `risk --direct` (plain
/// and `--states overturned=overturned`) and `export --direct` (its JSON and
/// the pelicun file it writes) give one median, one β and one fit name,
/// the same records folder, and `risk`'s two paths one rate. Once
/// `fragility --direct` printed the paper's regression, `--im pgv --direct`
/// the moments, `risk --direct` integrated the step curve while printing
/// the fractile fit, and `--states` the lognormal: four answers. (Python's
/// `fragility` and `risk` are held to these commands in python/tests.)
#[test]
fn one_block_one_fragility_in_every_command() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("h.csv"),
        "pga_g,annual_rate\n0.05,0.05\n0.1,0.01\n0.2,0.002\n0.4,0.0003\n0.8,0.00003\n",
    )
    .unwrap();
    let block = ["--b", "0.2", "--h", "0.9", "--direct"];
    let run = |args: &[&str]| {
        let mut a = args.to_vec();
        a.extend(block);
        json(&rocking(d, &a))
    };
    for (im, at) in [("pga", "0.3"), ("pgv", "30")] {
        let f = run(&["fragility", "--im", im, "--at", at, "--json"]);
        let (median, beta) = (f["median"].as_f64().unwrap(), f["beta"].as_f64().unwrap());
        assert_eq!(f["source"], "direct");
        assert_eq!(f["fit"], "fractile", "{im}");
        let folder = f["records_folder"].as_str().unwrap();
        assert!(folder.ends_with("records/fema-p695/far-field"), "{folder}");
        let out = d.join(format!("pelicun-{im}"));
        let e = run(&[
            "export",
            "--format",
            "pelicun",
            "--im",
            im,
            "--states",
            "overturned=overturned",
            "--out",
            out.to_str().unwrap(),
            "--json",
        ]);
        let state = &e[0]["fragility"]["states"][0];
        assert_eq!(state["fractile"]["median"].as_f64(), Some(median), "{im}");
        assert_eq!(state["fractile"]["beta"].as_f64(), Some(beta), "{im}");
        assert_eq!(state["fractile_kind"], "fractile");
        assert_eq!(e[0]["taxonomy"], "b0.2_h0.9");
        assert_eq!(e[0]["fragility"]["records_folder"], f["records_folder"]);
        // The file the engine reads: Theta_0 the median, Theta_1 β, to the bit.
        let csv = fs::read_to_string(out.join("fragility.csv")).unwrap();
        let row: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
        assert_eq!(row[7].parse::<f64>().unwrap(), median);
        assert_eq!(row[8].parse::<f64>().unwrap(), beta);
        if im == "pga" {
            let r = run(&["risk", "--hazard", "h.csv", "--json"]);
            assert_eq!(r["fragility"]["median"].as_f64(), Some(median));
            assert_eq!(r["fragility"]["beta"].as_f64(), Some(beta));
            assert_eq!(r["fragility"]["fit"], "fractile");
            assert_eq!(r["fragility"]["records_folder"], f["records_folder"]);
            let s = run(&[
                "risk",
                "--hazard",
                "h.csv",
                "--states",
                "overturned=overturned",
                "--json",
            ]);
            let st = &s["sites"][0]["states"][0];
            assert_eq!(st["median"].as_f64(), Some(median));
            assert_eq!(st["beta"].as_f64(), Some(beta));
            assert_eq!(st["fit"], "fractile");
            assert_eq!(st["annual_rate"], r["sites"][0]["annual_rate"]);
            // The rate is the lognormal's, cut at the uplift PGA (quadrature).
            let (a, l) = (
                [0.05, 0.1, 0.2, 0.4, 0.8],
                [0.05, 0.01, 0.002, 0.0003, 0.00003],
            );
            let inside = quadrature(&a, &l, median, beta, 0.2 / 0.9);
            let got = r["sites"][0]["annual_rate"].as_f64().unwrap();
            let beyond = r["sites"][0]["share_beyond_last_iml"].as_f64().unwrap() * got;
            assert!(
                ((got - beyond) / inside - 1.0).abs() < 1e-8,
                "{got} vs {inside}"
            );
        }
    }
}

/// `risk --inventory … --bootstrap N` gave each block's band in JSON alone:
/// the printed table and `risk.parquet` dropped it. Both now carry it, and
/// each block's band is the one it has alone (the same resamples).
#[test]
fn an_inventorys_bootstrap_bands_reach_the_table() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("inv.csv"),
        "name,b,h,eps\nstatue,0.2,1,\nvase,0.1,0.4,0.8\n",
    )
    .unwrap();
    let hazard = root().join("records/hazard/synthetic-site.csv");
    let far = bundled_records().join("far-field");
    let common = [
        "risk",
        "--hazard",
        hazard.to_str().unwrap(),
        "--direct",
        "--records",
        far.to_str().unwrap(),
        "--bootstrap",
        "50",
    ];
    let out = rocking(
        d,
        &[
            &common[..],
            &["--inventory", "inv.csv", "--out", "r.parquet"],
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("90 % band (1/yr)"), "{text}");
    let rows: Vec<rocking::tables::risk::RiskRow> =
        rocking::tables::read(&d.join("r.parquet")).unwrap();
    for (row, block) in rows
        .iter()
        .zip([["--b", "0.2", "--h", "1"], ["--b", "0.1", "--h", "0.4"]])
    {
        let eps: &[&str] = if row.block == "vase" {
            &["--eps", "0.8"]
        } else {
            &[]
        };
        let alone = json(&rocking(
            d,
            &[&common[..], &block, eps, &["--json"]].concat(),
        ));
        let band = &alone["sites"][0]["annual_rate_band"];
        assert_eq!(row.annual_rate_lo, band[0].as_f64(), "{}", row.block);
        assert_eq!(row.annual_rate_hi, band[1].as_f64(), "{}", row.block);
        assert!(
            row.annual_rate_lo.unwrap() < row.annual_rate
                && row.annual_rate < row.annual_rate_hi.unwrap()
        );
        assert!(
            text.contains(&format!("{:.3e}", row.annual_rate_lo.unwrap())),
            "{text}"
        );
    }
}
