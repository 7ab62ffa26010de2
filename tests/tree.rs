//! How sure the answer is: a logic tree over ε and the model (`--tree`)
//! against plain runs at each branch's values, its quantiles against a
//! weighted quantile written here, a one-branch tree against today's
//! answer to the bit; the rate's bootstrap band against a bootstrap written
//! here over the same resamples.

use std::fs;
use std::path::Path;

use serde_json::Value;

use crate::util::{bundled_records, cornell_above, rocking, root, stderr, stdout, tempdir};

fn json(out: &std::process::Output) -> Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

fn risk(d: &Path, extra: &[&str]) -> Value {
    let hazard = root().join("records/hazard/synthetic-openquake.csv");
    let mut args = vec!["risk", "--hazard", hazard.to_str().unwrap(), "--json"];
    args.extend_from_slice(extra);
    json(&rocking(d, &args))
}

/// OpenQuake's weighted quantile, written out: values sorted with their
/// weights, the weights accumulated, q interpolated linearly between the
/// points (cumulative weight, value), the end values outside.
fn quantile_by_hand(values: &[f64], weights: &[f64], q: f64) -> f64 {
    let mut idx: Vec<usize> = (0..values.len()).collect();
    idx.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut cum = Vec::new();
    let mut c = 0.0;
    for &i in &idx {
        c += weights[i];
        cum.push(c);
    }
    if q <= cum[0] {
        return values[idx[0]];
    }
    for k in 1..idx.len() {
        if q <= cum[k] {
            let t = (q - cum[k - 1]) / (cum[k] - cum[k - 1]);
            return values[idx[k - 1]] + t * (values[idx[k]] - values[idx[k - 1]]);
        }
    }
    values[*idx.last().unwrap()]
}

const TREE: &str = "[[eps]]\nratio = 1.0\nweight = 0.35\n[[eps]]\nratio = 0.95\nweight = 0.45\n\
                    [[eps]]\nvalue = 0.7\nweight = 0.2\n";

/// The mean rate of a tree equals the weighted mean of plain `risk` runs
/// at each branch's ε (1e-12), at every site; its quantiles equal the
/// weighted quantile written here; the mean fragility's median is where
/// the mixture of the branches' lognormals (Φ written here) reaches 1/2.
#[test]
fn the_mean_rate_is_the_weighted_mean_of_plain_runs() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(d.join("tree.toml"), TREE).unwrap();
    let (b, h) = (0.2f64, 0.9f64);
    let tree = risk(d, &["--b", "0.2", "--h", "0.9", "--tree", "tree.toml"]);
    let alpha = (b / h).atan();
    let housner = 1.0 - 1.5 * alpha.sin().powi(2);
    let branches = [(housner, 0.35), (0.95 * housner, 0.45), (0.7, 0.2)];
    let plain: Vec<Value> = branches
        .iter()
        .map(|(eps, _)| {
            risk(
                d,
                &["--b", "0.2", "--h", "0.9", "--eps", &format!("{eps:?}")],
            )
        })
        .collect();
    let weights: Vec<f64> = branches.iter().map(|b| b.1).collect();
    let sites = tree["sites"].as_array().unwrap();
    assert!(sites.len() >= 2);
    for (s, site) in sites.iter().enumerate() {
        let rates: Vec<f64> = plain
            .iter()
            .map(|p| p["sites"][s]["annual_rate"].as_f64().unwrap())
            .collect();
        let mean: f64 = rates.iter().zip(&weights).map(|(r, w)| r * w).sum();
        for key in ["mean_annual_rate", "annual_rate"] {
            let got = site[key].as_f64().unwrap();
            assert!(
                (got / mean - 1.0).abs() < 1e-12,
                "site {s} {key}: {got} vs {mean}"
            );
        }
        let q = site["quantile_annual_rates"].as_array().unwrap();
        for (k, qq) in [0.05, 0.16, 0.5, 0.84, 0.95].iter().enumerate() {
            let want = quantile_by_hand(&rates, &weights, *qq);
            let got = q[k].as_f64().unwrap();
            assert!(
                (got - want).abs() <= 1e-12 * want,
                "site {s} q{qq}: {got} vs {want}"
            );
        }
        for (k, br) in site["branches"].as_array().unwrap().iter().enumerate() {
            assert_eq!(
                br["annual_rate"].as_f64().unwrap().to_bits(),
                rates[k].to_bits()
            );
        }
    }
    // The mixture's median: Σ wᵢ Φ(ln(x/mᵢ)/βᵢ) = 1/2 at the stated median.
    let f = &tree["fragility"];
    assert_eq!(f["fit"], "mixture");
    let x = f["median"].as_f64().unwrap();
    let mix: f64 = plain
        .iter()
        .zip(&weights)
        .map(|(p, w)| {
            let (m, beta) = (
                p["fragility"]["median"].as_f64().unwrap(),
                p["fragility"]["beta"].as_f64().unwrap(),
            );
            w * crate::util::phi((x / m).ln() / beta)
        })
        .sum();
    assert!((mix - 0.5).abs() < 1e-10, "{mix}");
    // FEMA P-58's split, by hand: β_m the weighted sd of ln mᵢ.
    let ln_m: Vec<f64> = plain
        .iter()
        .map(|p| p["fragility"]["median"].as_f64().unwrap().ln())
        .collect();
    let mean_ln: f64 = ln_m.iter().zip(&weights).map(|(l, w)| l * w).sum();
    let var: f64 = ln_m
        .iter()
        .zip(&weights)
        .map(|(l, w)| w * (l - mean_ln).powi(2))
        .sum();
    let split = &f["tree"]["split"];
    assert!((split["beta_m"].as_f64().unwrap() - var.sqrt()).abs() < 1e-12);
}

/// A tree of one branch of weight 1 is today's answer to the bit: the
/// rates, return periods, deaggregation and fragility of a plain run.
#[test]
fn a_one_branch_tree_is_the_plain_answer() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(d.join("one.toml"), "[[eps]]\nvalue = 0.85\nweight = 1.0\n").unwrap();
    let plain = risk(d, &["--b", "0.2", "--h", "0.9", "--eps", "0.85"]);
    let tree = risk(d, &["--b", "0.2", "--h", "0.9", "--tree", "one.toml"]);
    for key in ["median", "beta", "fit", "source"] {
        assert_eq!(plain["fragility"][key], tree["fragility"][key], "{key}");
    }
    let (p, t) = (
        plain["sites"].as_array().unwrap(),
        tree["sites"].as_array().unwrap(),
    );
    for (a, b) in p.iter().zip(t) {
        for key in [
            "annual_rate",
            "return_period_years",
            "p_overturn_in_years",
            "share_beyond_last_iml",
            "deaggregation",
        ] {
            assert_eq!(a[key], b[key], "{key}");
        }
        assert_eq!(b["mean_annual_rate"], a["annual_rate"]);
    }
    // And `fragility` alike, at its levels.
    let levels = ["--b", "0.2", "--h", "0.9", "--pga", "0.3,0.5,0.8", "--json"];
    let mut with = vec!["fragility", "--tree", "one.toml"];
    with.extend_from_slice(&levels);
    let mut without = vec!["fragility", "--eps", "0.85"];
    without.extend_from_slice(&levels);
    let (a, b) = (json(&rocking(d, &without)), json(&rocking(d, &with)));
    assert_eq!(a["points"], b["points"]);
    assert_eq!(a["median"], b["median"]);
}

/// A [[model]] branch runs the records with that model: on a slender block
/// `auto` chooses the linearised one, so the linearised branch's rate is
/// the plain `--direct` rate; refused without `--direct`.
#[test]
fn model_branches_run_the_records() {
    let dir = tempdir();
    let d = dir.path();
    let recs = d.join("recs");
    fs::create_dir_all(&recs).unwrap();
    for id in [
        "RSN1111_KOBE_NIS000",
        "RSN953_NORTHR_MUL009",
        "RSN1633_MANJIL_ABBAR--L",
    ] {
        fs::copy(
            bundled_records().join(format!("far-field/{id}.AT2")),
            recs.join(format!("{id}.AT2")),
        )
        .unwrap();
    }
    fs::write(
        d.join("m.toml"),
        "[[model]]\nname = \"linearized\"\nweight = 0.5\n[[model]]\nname = \"nonlinear\"\nweight = 0.5\n",
    )
    .unwrap();
    let common = [
        "--b",
        "0.1",
        "--h",
        "1.0",
        "--eps",
        "0.8",
        "--direct",
        "--records",
        "recs",
        "--method",
        "empirical",
    ];
    let mut args = common.to_vec();
    args.extend_from_slice(&["--tree", "m.toml"]);
    let tree = risk(d, &args);
    let plain = risk(d, &common);
    let br = &tree["sites"][0]["branches"];
    assert_eq!(br[0]["annual_rate"], plain["sites"][0]["annual_rate"]);
    assert_ne!(br[1]["annual_rate"], br[0]["annual_rate"]);
    let refused = rocking(
        d,
        &[
            "risk",
            "--hazard",
            root()
                .join("records/hazard/synthetic-openquake.csv")
                .to_str()
                .unwrap(),
            "--b",
            "0.1",
            "--h",
            "1.0",
            "--tree",
            "m.toml",
        ],
    );
    assert!(!refused.status.success());
    assert!(
        stderr(&refused).contains(
            "--tree m.toml: a [[model]] branch (linearized) runs the records: add --direct"
        ),
        "{}",
        stderr(&refused)
    );
    // A tree's keys are checked, naming the file.
    fs::write(d.join("bad.toml"), "[[eps]]\nvalue = 0.8\nweight = 0.6\n").unwrap();
    let bad = rocking(
        d,
        &[
            "risk",
            "--hazard",
            root()
                .join("records/hazard/synthetic-openquake.csv")
                .to_str()
                .unwrap(),
            "--b",
            "0.1",
            "--h",
            "1.0",
            "--tree",
            "bad.toml",
        ],
    );
    assert!(
        stderr(&bad).contains("bad.toml: [[eps]]: the weights sum to 0.6, not 1"),
        "{}",
        stderr(&bad)
    );
}

/// The rate's bootstrap band (`--bootstrap`) equals a bootstrap written
/// here over the same resamples (the far-field pairs by the manifest, drawn
/// by the library's generator from the seed): each resample's lognormal by
/// the type-7 fractiles of its capacities (from `rocking capacity`), its
/// rate by the library's integral (held to Cornell's closed form in
/// `risk.rs`), the band their type-7 5 and 95 % fractiles; to 1e-12. The
/// records' curve's β band is the same resamples' fractile β.
#[test]
fn the_rates_band_is_a_bootstrap_by_hand() {
    let dir = tempdir();
    let d = dir.path();
    let (k0, k) = (1e-4, 2.2);
    let mut text = String::from("pga_g,annual_rate\n");
    for i in 0..40 {
        let a = 0.001 * (5000.0f64).powf(i as f64 / 39.0);
        text.push_str(&format!("{a:?},{:?}\n", k0 * a.powf(-k)));
    }
    fs::write(d.join("h.csv"), &text).unwrap();
    let far = bundled_records().join("far-field");
    let (resamples, seed) = (200usize, 17u64);
    let ask: Vec<String> = [
        "risk",
        "--hazard",
        "h.csv",
        "--b",
        "0.1",
        "--h",
        "1.0",
        "--eps",
        "0.8",
        "--direct",
        "--records",
        far.to_str().unwrap(),
        "--if-not-lognormal",
        "lognormal",
        "--bootstrap",
        &resamples.to_string(),
        "--seed",
        &seed.to_string(),
        "--json",
    ]
    .map(String::from)
    .into();
    let v = json(&rocking(
        d,
        &ask.iter().map(String::as_str).collect::<Vec<_>>(),
    ));
    let boot = &v["fragility"]["bootstrap"];
    assert_eq!(boot["unit"], "pair");
    assert_eq!(boot["fitted"], resamples);
    // The records in the tool's order (file names sorted), their pairs
    // from the manifest (set and pair number), numbered as they appear.
    let mut files: Vec<String> = fs::read_dir(&far)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.to_ascii_uppercase().ends_with(".AT2"))
        .collect();
    files.sort();
    let manifest = fs::read_to_string(bundled_records().join("manifest.csv")).unwrap();
    let pair_of = |file: &str| -> String {
        manifest
            .lines()
            .find(|l| l.ends_with(&format!("/{file}")))
            .map(|l| {
                let c: Vec<&str> = l.split(',').collect();
                format!("{}/{}", c[0], c[1])
            })
            .unwrap()
    };
    let mut seen: Vec<String> = Vec::new();
    let units: Vec<usize> = files
        .iter()
        .map(|f| {
            let p = pair_of(f);
            seen.iter().position(|s| *s == p).unwrap_or_else(|| {
                seen.push(p);
                seen.len() - 1
            })
        })
        .collect();
    assert_eq!(seen.len(), 22);
    // Each record's capacity in PGA, α/η_c (the linearised model at α = 0.1).
    let alpha = 0.1f64.atan();
    let p = (3.0 * 9.80665 / (4.0 * (0.01f64 + 1.0).sqrt())).sqrt();
    let caps: Vec<f64> = files
        .iter()
        .map(|f| {
            let c = json(&rocking(
                d,
                &[
                    "capacity",
                    "--record",
                    far.join(f).to_str().unwrap(),
                    "--p",
                    &p.to_string(),
                    "--eps",
                    "0.8",
                    "--json",
                ],
            ));
            c["eta_c"].as_f64().map_or(f64::INFINITY, |e| alpha / e)
        })
        .collect();
    let type7 = |sorted: &[f64], q: f64| {
        let h = (sorted.len() - 1) as f64 * q;
        let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
        sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
    };
    let curve = rocking::hazard::parse(&text).unwrap().remove(0);
    let units_of = rocking::stats::Units::new(&units);
    let mut rng = rocking::stats::SplitMix64::new(seed);
    let (mut rates, mut medians, mut betas) = (Vec::new(), Vec::new(), Vec::new());
    let mut draw = Vec::new();
    for _ in 0..resamples {
        units_of.draw(&mut rng, &mut draw);
        let mut x: Vec<f64> = draw.iter().map(|&i| caps[i]).collect();
        x.sort_by(f64::total_cmp);
        let (q16, q50, q84) = (type7(&x, 0.16), type7(&x, 0.5), type7(&x, 0.84));
        let beta = 0.5 * (q84 / q16).ln();
        let f = rocking::risk::Fragility::Lognormal { median: q50, beta };
        let r = rocking::risk::assess_above(&curve, &f, rocking::risk::Beyond::Extrapolate, 0.1);
        // The integral itself against Cornell's closed form.
        let c = cornell_above(k0, k, q50, beta, 0.1);
        assert!(
            (r.annual_rate / c - 1.0).abs() < 1e-8,
            "{} vs {c}",
            r.annual_rate
        );
        rates.push(r.annual_rate);
        medians.push(q50);
        betas.push(beta);
    }
    let band = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        [type7(v, 0.05), type7(v, 0.95)]
    };
    let want = band(&mut rates);
    let got = &v["sites"][0]["annual_rate_band"];
    for k in 0..2 {
        let g = got[k].as_f64().unwrap();
        assert!(
            (g / want[k] - 1.0).abs() < 1e-12,
            "band {k}: {g} vs {}",
            want[k]
        );
    }
    let m = band(&mut medians);
    for k in 0..2 {
        let g = boot["median_band"][k].as_f64().unwrap();
        assert!(
            (g / m[k] - 1.0).abs() < 1e-12,
            "median band {k}: {g} vs {}",
            m[k]
        );
    }
    let b = band(&mut betas);
    for k in 0..2 {
        let g = boot["beta_band"][k].as_f64().unwrap();
        assert!(
            (g / b[k] - 1.0).abs() < 1e-12,
            "β band {k}: {g} vs {}",
            b[k]
        );
    }
    let rate = v["sites"][0]["annual_rate"].as_f64().unwrap();
    assert!(want[0] < rate && rate < want[1], "{want:?} {rate}");
    // The records' own curve (`--method empirical`) has no β: none in the
    // answer, none in the resamples, so no β band; its median band is the
    // resamples' curves' medians.
    let mut args: Vec<&str> = ask.iter().map(String::as_str).collect();
    args.extend(["--method", "empirical"]);
    let e = json(&rocking(d, &args));
    assert!(e["fragility"]["beta"].is_null(), "{e}");
    assert!(e["fragility"]["bootstrap"]["beta_band"].is_null(), "{e}");
    assert!(e["fragility"]["bootstrap"]["median_band"].is_array(), "{e}");
}

/// A study's `[tree]`: the tree stage runs the example block on every
/// branch over every record, each capacity the one `rocking capacity`
/// finds at the branch's ε; the report states each branch's lognormal by
/// the type-7 fractiles of those capacities in PGA (α/η_c, α = 0.1) and
/// the mixture's median where Σ wᵢ Φ(ln(x/mᵢ)/βᵢ) = 1/2 (Φ written here).
#[test]
fn a_studys_tree_runs_the_example_on_every_branch() {
    use crate::util::{direct_capacity, phi, write_pipeline};
    use rocking::tables::read;
    use rocking::tables::sweep::CapacityRow;
    let dir = tempdir();
    let d = dir.path();
    let records = [
        "RSN953_NORTHR_MUL009",
        "RSN960_NORTHR_LOS000",
        "RSN1602_DUZCE_BOL000",
        "RSN1787_HECTOR_HEC000",
        "RSN1111_KOBE_NIS000",
        "RSN1158_KOCAELI_DZC180",
    ];
    let pipe = write_pipeline(
        d,
        "t",
        &format!(
            "ids = {records:?}\n[model]\nkind = \"linearized\"\nalpha = 0.1\n[blocks]\np = [2.0]\n\
             eps = [0.7]\n[im]\ncount = 60\neta_min = 0.01\n[example]\np = 2.0\neps = 0.7\n\
             [[tree.eps]]\nvalue = 0.7\nweight = 0.6\n[[tree.eps]]\nvalue = 0.55\nweight = 0.4\n"
        ),
    );
    let out = d.join("out");
    let run = || {
        let r = rocking(
            &root(),
            &[
                "run",
                pipe.to_str().unwrap(),
                "--outputs",
                out.to_str().unwrap(),
            ],
        );
        assert!(r.status.success(), "{}", stderr(&r));
    };
    run();
    let caps: Vec<CapacityRow> = read(&out.join("t/tree_capacities.parquet")).unwrap();
    assert_eq!(caps.len(), 2 * records.len());
    let (eps, weights) = ([0.7, 0.55], [0.6, 0.4]);
    let mut fits = Vec::new();
    // Each branch's capacities in PGA, ascending (+∞ where it survives).
    let mut sorted = Vec::new();
    for (b, &e) in eps.iter().enumerate() {
        let mut pga: Vec<f64> = caps
            .iter()
            .skip(b)
            .step_by(2)
            .map(|c| {
                assert_eq!(c.eps, e);
                let record = format!("records/fema-p695/far-field/{}.AT2", c.record_id);
                let v = direct_capacity(&root(), &record, 2.0, e, 60);
                assert_eq!(c.eta_c, v["eta_c"].as_f64(), "{} at ε = {e}", c.record_id);
                c.eta_c.map_or(f64::INFINITY, |x| 0.1 / x)
            })
            .collect();
        pga.sort_by(f64::total_cmp);
        let q = |q: f64| {
            let h = (pga.len() - 1) as f64 * q;
            let lo = h.floor() as usize;
            pga[lo] + (h - lo as f64) * (pga[(lo + 1).min(pga.len() - 1)] - pga[lo])
        };
        fits.push((q(0.5), 0.5 * (q(0.84) / q(0.16)).ln()));
        sorted.push(pga);
    }
    let report = std::fs::read_to_string(out.join("t/report.md")).unwrap();
    assert!(
        report.contains("## How sure: the example block over the logic tree"),
        "{report}"
    );
    for &(m, beta) in &fits {
        assert!(
            report.contains(&format!("| {m:.4} | {beta:.3} |")),
            "{m} {beta}\n{report}"
        );
    }
    // The mixture's median by bisection here.
    let mix = |x: f64| -> f64 {
        fits.iter()
            .zip(weights)
            .map(|(&(m, b), w)| w * phi((x / m).ln() / b))
            .sum()
    };
    let (mut lo, mut hi) = (1e-3f64, 10.0f64);
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if mix(mid) < 0.5 {
            lo = mid
        } else {
            hi = mid
        }
    }
    assert!(
        report.contains(&format!("| **mean (the mixture)** | 1 | | | {hi:.4} |")),
        "{hi}\n{report}"
    );
    assert!(out.join("t/figures/tree_tornado.svg").is_file());

    // A study of other fractiles fits its branches by them, as its damage
    // states (the report gave type 7 beside the damage section's type 5):
    // Hyndman–Fan type 5, h = nq + 1/2 (1-based), written here.
    let text = std::fs::read_to_string(&pipe).unwrap();
    std::fs::write(&pipe, format!("{text}[reduce]\nfractile = \"type5\"\n")).unwrap();
    run();
    let report = std::fs::read_to_string(out.join("t/report.md")).unwrap();
    assert!(report.contains("(the study's fractiles, type5"), "{report}");
    for pga in &sorted {
        let n = pga.len();
        let q = |q: f64| {
            let h = n as f64 * q + 0.5;
            if h <= 1.0 {
                return pga[0];
            }
            if h >= n as f64 {
                return pga[n - 1];
            }
            let lo = h.floor() as usize;
            pga[lo - 1] + (h - lo as f64) * (pga[lo] - pga[lo - 1])
        };
        let (m, beta) = (q(0.5), 0.5 * (q(0.84) / q(0.16)).ln());
        assert!(
            report.contains(&format!("| {m:.4} | {beta:.3} |")),
            "type 5: {m} {beta}\n{report}"
        );
    }
}

/// pelicun takes one function per state: the export writes the tree's mean
/// as a multilinear_CDF whose every point is the mixture of the branches'
/// lognormals (Φ written here; the ends set to 0 and 1 at the mixture's 0.1
/// and 99.9 % levels), each 0 below the uplift PGA g·tan α = b/h g, where
/// `risk --tree` and `fragility --tree` count 0 (the mixture of uncut
/// lognormals gave 1.05 % just below it), as it reproduces the mean better
/// than β_total's lognormal (both errors stated).
#[test]
fn pelicun_gets_the_mean_of_a_tree() {
    let dir = tempdir();
    let d = dir.path();
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
            "--tree",
            "restitution-tests",
            "--out",
            "p",
            "--json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let mean = &v[0]["tree"]["mean"];
    assert_eq!(mean["written_as"], "curve");
    assert!(mean["curve_error"].as_f64().unwrap() < mean["lognormal_error"].as_f64().unwrap());
    let tree = risk(
        d,
        &["--b", "0.2", "--h", "0.9", "--tree", "restitution-tests"],
    );
    let branches: Vec<(f64, f64, f64)> = tree["fragility"]["tree"]["branches"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| {
            (
                b["weight"].as_f64().unwrap(),
                b["median"].as_f64().unwrap(),
                b["beta"].as_f64().unwrap(),
            )
        })
        .collect();
    let csv = fs::read_to_string(d.join("p/fragility.csv")).unwrap();
    let row = csv.lines().nth(1).unwrap();
    let quoted = row.split('"').nth(1).unwrap();
    let (xs, ps) = quoted.split_once('|').unwrap();
    let xs: Vec<f64> = xs.split(',').map(|x| x.parse().unwrap()).collect();
    let ps: Vec<f64> = ps.split(',').map(|x| x.parse().unwrap()).collect();
    let uplift = 0.2 / 0.9;
    // The range starts at the uplift PGA, a step there (from 0 to the
    // mixture one part in 10⁶ above it).
    assert!((xs[0] / uplift - 1.0).abs() < 1e-12, "{}", xs[0]);
    assert_eq!(ps[0], 0.0);
    assert_eq!(xs.len(), 61);
    for (k, (&x, &p)) in xs.iter().zip(&ps).enumerate().skip(1) {
        let mix: f64 = branches
            .iter()
            .map(|&(w, m, b)| w * crate::util::phi((x / m).ln() / b))
            .sum();
        // Two implementations of Φ (statrs' erfc, the test's series) agree to ~1e-12.
        let tol = if k == 0 || k == xs.len() - 1 {
            1.01e-3
        } else {
            1e-10
        };
        assert!((mix - p).abs() <= tol, "point {k}: {p} vs {mix}");
    }
}

/// A pelicun row's limit states as functions of the IM: a lognormal's Φ
/// (the test's own), a multilinear_CDF linear between its points (0 below
/// the first, its last P beyond).
fn pelicun_states(csv: &str) -> Vec<Box<dyn Fn(f64) -> f64>> {
    let row = csv.lines().nth(1).unwrap();
    // Cells, with the quoted ones (commas inside) whole.
    let (mut cells, mut cell, mut quoted) = (Vec::new(), String::new(), false);
    for c in row.chars() {
        match c {
            '"' => quoted = !quoted,
            ',' if !quoted => cells.push(std::mem::take(&mut cell)),
            c => cell.push(c),
        }
    }
    cells.push(cell);
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let cell = |name: String| cells[header.iter().position(|h| *h == name).unwrap()].clone();
    (1..)
        .take_while(|k| header.contains(&format!("LS{k}-Family").as_str()))
        .map(|k| -> Box<dyn Fn(f64) -> f64> {
            let theta = cell(format!("LS{k}-Theta_0"));
            match cell(format!("LS{k}-Family")).as_str() {
                "lognormal" => {
                    let m: f64 = theta.parse().unwrap();
                    let b: f64 = cell(format!("LS{k}-Theta_1")).parse().unwrap();
                    Box::new(move |x: f64| crate::util::phi((x / m).ln() / b))
                }
                "multilinear_CDF" => {
                    let (xs, ps) = theta.split_once('|').unwrap();
                    let xs: Vec<f64> = xs.split(',').map(|v| v.parse().unwrap()).collect();
                    let ps: Vec<f64> = ps.split(',').map(|v| v.parse().unwrap()).collect();
                    Box::new(move |x: f64| {
                        let i = xs.partition_point(|&v| v <= x);
                        match i {
                            0 => 0.0,
                            i if i == xs.len() => ps[i - 1],
                            i => {
                                let t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
                                ps[i - 1] + t * (ps[i] - ps[i - 1])
                            }
                        }
                    })
                }
                other => panic!("family {other}"),
            }
        })
        .collect()
}

/// The mean over a tree of the records' runs (`--direct`, three states;
/// one branch's capacities fail the lognormal check, so the mixture has a
/// records' curve with a kink at each capacity): pelicun's curve of each
/// state goes through the same levels, at each of which it is the mixture
/// of the branches as each branch's own export writes it (the weights from
/// the tree's answer, the mixture summed here), to 1e-10 inside its
/// 0.1–99.9 % ends; so the states keep their order at every level (a
/// heavier state never the likelier), and between them.
#[test]
fn pelicun_gets_a_trees_states_in_order_through_every_branchs_kink() {
    let dir = tempdir();
    let d = dir.path();
    let block = ["--b", "0.2", "--h", "0.9", "--direct", "--json"];
    let export = |out: &str, more: &[&str]| -> Value {
        let mut args = vec!["export", "--format", "pelicun", "--out", out];
        args.extend(block);
        args.extend(more);
        let o = rocking(d, &args);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let tree = export("mean", &["--tree", "restitution-tests"]);
    assert_eq!(tree[0]["tree"]["mean"]["written_as"], "curve");
    let csv = fs::read_to_string(d.join("mean/fragility.csv")).unwrap();
    let mean = pelicun_states(&csv);
    let row = csv.lines().nth(1).unwrap();
    let theta: Vec<&str> = row.split('"').skip(1).step_by(2).collect();
    let levels: Vec<Vec<f64>> = theta
        .iter()
        .filter_map(|t| t.split_once('|'))
        .map(|(xs, _)| xs.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(levels.len(), 3);
    assert!(levels.windows(2).all(|w| w[0] == w[1]), "one set of levels");
    let mut branches = Vec::new();
    let mut curves = 0;
    for (k, b) in tree[0]["tree"]["branches"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
    {
        let eps = b["eps"].as_f64().unwrap().to_string();
        let out = format!("b{k}");
        let one = export(&out, &["--eps", &eps]);
        curves += usize::from(one[0]["written_as"] == "curve");
        let text = fs::read_to_string(d.join(&out).join("fragility.csv")).unwrap();
        branches.push((b["weight"].as_f64().unwrap(), pelicun_states(&text)));
    }
    assert!(curves >= 1, "a branch with a kinked curve");
    // Every kink of a branch's curve inside the mean's ends is one of its
    // levels: there the mean is the mixture, as everywhere between.
    let xs = &levels[0];
    let kinks: Vec<f64> = (0..branches.len())
        .flat_map(|k| {
            let text = fs::read_to_string(d.join(format!("b{k}/fragility.csv"))).unwrap();
            let row = text.lines().nth(1).unwrap().to_string();
            row.split('"')
                .skip(1)
                .step_by(2)
                .filter_map(|t| t.split_once('|'))
                .flat_map(|(x, _)| x.split(',').map(|v| v.parse::<f64>().unwrap()))
                .collect::<Vec<_>>()
        })
        .filter(|&x| x > xs[0] && x < xs[xs.len() - 1])
        .collect();
    assert!(kinks.len() > 40, "{}", kinks.len());
    // Each branch counts 0 below the uplift PGA (b/h g), as `risk --tree`
    // does; the mean's step there is its first two levels.
    let uplift = 0.2 / 0.9;
    let cut = |x: f64, p: f64| if x < uplift { 0.0 } else { p };
    assert!((xs[0] / uplift - 1.0).abs() < 1e-12 && (xs[1] / xs[0] - 1.0 - 1e-6).abs() < 1e-9);
    for &x in &kinks {
        for j in 0..3 {
            let mix: f64 = branches.iter().map(|(w, s)| w * cut(x, s[j](x))).sum();
            assert!(
                (mean[j](x) - mix).abs() <= 1e-10,
                "state {j} at the kink {x}"
            );
        }
    }
    for (i, &x) in xs.iter().enumerate().skip(1) {
        let p: Vec<f64> = (0..3).map(|j| mean[j](x)).collect();
        for j in 0..3 {
            let mix: f64 = branches.iter().map(|(w, s)| w * cut(x, s[j](x))).sum();
            // Two Φ (statrs' erfc, the test's series) agree to ~1e-12.
            let tol = if i == 0 || i == xs.len() - 1 {
                1.01e-3
            } else {
                1e-10
            };
            assert!(
                (p[j] - mix).abs() <= tol,
                "state {j} at {x}: {} vs {mix}",
                p[j]
            );
        }
        assert!(p[0] >= p[1] && p[1] >= p[2], "at {x}: {p:?}");
    }
}

/// An inventory's own ε is not silently replaced by a tree's [[eps]]; an
/// OpenQuake export of a tree writes its taxonomy mapping with or without
/// a job.
#[test]
fn a_trees_eps_and_an_inventorys_and_the_mapping_without_a_job() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(d.join("inv.csv"), "name,b,h,eps\nstatue,0.2,0.9,0.8\n").unwrap();
    let hazard = root().join("records/hazard/synthetic-openquake.csv");
    let out = rocking(
        d,
        &[
            "risk",
            "--hazard",
            hazard.to_str().unwrap(),
            "--inventory",
            "inv.csv",
            "--tree",
            "restitution-tests",
        ],
    );
    assert!(
        stderr(&out).contains("the block has its own ε = 0.8"),
        "{}",
        stderr(&out)
    );
    let out = rocking(
        d,
        &[
            "export",
            "--format",
            "nrml",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--tree",
            "restitution-tests",
            "--out",
            "x",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let mapping = fs::read_to_string(d.join("x/taxonomy_mapping.csv")).unwrap();
    assert_eq!(mapping.lines().count(), 4, "{mapping}");
    // A ratio that takes a slender block's ε above 1 is refused, naming the branch.
    fs::write(d.join("up.toml"), "[[eps]]\nratio = 1.2\nweight = 1.0\n").unwrap();
    let out = rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.05",
            "--h",
            "1.0",
            "--pga",
            "0.3",
            "--tree",
            "up.toml",
        ],
    );
    assert!(
        stderr(&out).contains("the tree's branch `ε = 1.2 × Housner's` gives this block ε = 1.19"),
        "{}",
        stderr(&out)
    );
}

/// `fragility --tree` mixed the branches' fragilities uncut: P > 0 below
/// the PGA at which the block first lifts off (g·tan α = 0.25 g for
/// b/h = 0.25), where each branch alone, `risk --tree` and the OpenQuake
/// export count 0. Each level's probability is the weighted mean of the
/// branches' own answers (each run alone with its ε), 0 at and below the
/// uplift PGA.
#[test]
fn a_trees_fragility_is_its_branches_each_cut_below_uplift() {
    let dir = tempdir();
    let d = dir.path();
    let levels = [0.1, 0.2, 0.24, 0.3, 0.5];
    let at = "0.1,0.2,0.24,0.3,0.5";
    let ask = |more: &[&str]| -> Value {
        let mut args = vec![
            "fragility",
            "--b",
            "0.25",
            "--h",
            "1.0",
            "--pga",
            at,
            "--json",
        ];
        args.extend(more);
        json(&rocking(d, &args))
    };
    let tree = ask(&["--tree", "restitution-tests"]);
    let branches = tree["tree"]["branches"].as_array().unwrap();
    assert_eq!(branches.len(), 3);
    let mut mean = [0.0; 5];
    for b in branches {
        let eps = b["eps"].as_f64().unwrap().to_string();
        let one = ask(&["--eps", &eps]);
        let w = b["weight"].as_f64().unwrap();
        for (k, m) in mean.iter_mut().enumerate() {
            *m += w * one["points"][k]["probability"].as_f64().unwrap();
        }
    }
    // With damage states the tree was dropped without a word: refused, as
    // `risk` refuses it.
    let both = rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.25",
            "--h",
            "1.0",
            "--pga",
            at,
            "--tree",
            "restitution-tests",
            "--states",
            "rocking=0.1,overturned=overturned",
        ],
    );
    assert!(!both.status.success());
    assert!(
        stderr(&both).contains("give it or --states, not both"),
        "{}",
        stderr(&both)
    );
    for (k, &x) in levels.iter().enumerate() {
        let p = tree["points"][k]["probability"].as_f64().unwrap();
        assert!(
            (p - mean[k]).abs() <= 1e-15,
            "at {x} g: {p} against the branches' {}",
            mean[k]
        );
        if x <= 0.25 {
            assert_eq!(p, 0.0, "at {x} g, below the uplift PGA");
        } else {
            assert!(p > 0.0, "at {x} g");
        }
    }
}

/// `export --tree` printed the first branch's fit as the block's while the
/// files held every branch (OpenQuake) or their mean (pelicun): each
/// branch's states are now in the answer and printed, each the fit
/// `fragility` gives that branch's ε alone.
#[test]
fn a_trees_export_states_every_branch() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("t2.toml"),
        "[[eps]]\nvalue = 0.5\nweight = 0.5\n[[eps]]\nvalue = 0.9\nweight = 0.5\n",
    )
    .unwrap();
    let args = |json: bool| {
        let mut a = vec![
            "export", "--format", "pelicun", "--b", "0.2", "--h", "0.9", "--tree", "t2.toml",
            "--out",
        ];
        a.push(if json { "j" } else { "t" });
        if json {
            a.push("--json");
        }
        a
    };
    let v = json(&rocking(d, &args(true)));
    let branches = v[0]["tree"]["branches"].as_array().unwrap();
    let text = stdout(&rocking(d, &args(false)));
    assert!(
        text.contains("over the logic tree t2.toml (2 branches)"),
        "{text}"
    );
    for (b, eps) in branches.iter().zip(["0.5", "0.9"]) {
        let alone = json(&rocking(
            d,
            &[
                "fragility",
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--eps",
                eps,
                "--pga",
                "0.3",
                "--json",
            ],
        ));
        let state = &b["fragility"]["states"][0]["fractile"];
        assert_eq!(state["median"], alone["median"], "ε = {eps}");
        assert_eq!(state["beta"], alone["beta"], "ε = {eps}");
        let shown = format!("{:.4} g", alone["median"].as_f64().unwrap());
        assert!(text.contains(&shown), "ε = {eps}: {shown} in\n{text}");
    }
}
