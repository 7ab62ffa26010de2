//! `rocking reduce`, `fit` and `fragility`: the Lilliefors calibration by
//! Monte Carlo, the resurrection rule and the fractile definitions end to
//! end, the regression on synthetic data, the fragility curve, stage
//! reruns, and (slow, `ROCKING_SLOW=1`, run by CI) the paper's median
//! capacity against its Eq. 10.

use std::fs;
use std::path::Path;

use rocking::fit::{curve, fit_curve};
use rocking::fragility::paper;
use rocking::stages::sweep::read_capacities;
use rocking::stages::{Context, Silent, Stage, Study};
use rocking::stats::FractileDef;
use rocking::stats::{fractile, lilliefors, lilliefors_critical_value, lilliefors_p_value};
use rocking::tables::fit::{FitBandRow, FitComparisonRow, FitStep1Row};
use rocking::tables::read;
use rocking::tables::reduce::{CapacityFractileRow, LognormalRow, OverturnFractionRow};

use crate::util::{bundled_records, rocking, root, stderr, stdout, tempdir};

/// The library's SplitMix64 and Box–Muller: a reproducible normal sample.
struct Normal(rocking::stats::SplitMix64);

impl Normal {
    fn new(seed: u64) -> Self {
        Normal(rocking::stats::SplitMix64::new(seed))
    }
    fn uniform(&mut self) -> f64 {
        ((self.0.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn next(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

#[test]
fn lilliefors_critical_value_agrees_with_monte_carlo() {
    // 20,000 normal samples of n = 44 (the far-field set): the 95th
    // percentile of D. Its Monte Carlo standard error is about 0.0006
    // (binomial error of the 5 % tail over the density of D there), so the
    // two must agree to 0.003; the p-value there must be 0.05 ± 0.01.
    let mut rng = Normal::new(20261122);
    let n = 44;
    let mut ds: Vec<f64> = (0..20_000)
        .map(|_| {
            let x: Vec<f64> = (0..n).map(|_| 3.0 + 0.5 * rng.next()).collect();
            lilliefors(&x).unwrap().d
        })
        .collect();
    ds.sort_by(|a, b| a.total_cmp(b));
    let mc95 = fractile(&ds, 0.95, FractileDef::Type7).unwrap();
    let ours = lilliefors_critical_value(n, 0.05);
    assert!((mc95 - ours).abs() < 0.003, "Monte Carlo {mc95} vs {ours}");
    assert!((lilliefors_p_value(mc95, n) - 0.05).abs() < 0.01);
    // Under the null, rejections at 5 % happen about 5 % of the time.
    let rejected = ds
        .iter()
        .filter(|&&d| lilliefors_p_value(d, n) < 0.05)
        .count() as f64
        / ds.len() as f64;
    assert!((rejected - 0.05).abs() < 0.01, "{rejected}");
}

#[test]
fn regression_recovers_known_coefficients_and_admits_defeat() {
    // The paper's median law at ε = 0.7 on the paper's 12 values of p, with
    // ±1 % multiplicative noise (deterministic).
    let (a, b, c) = (
        0.44 + 0.43 * 0.7,
        0.56 - 1.14 * 0.7 + 1.25 * 0.49,
        1.66 - 0.38 * 0.7 + 1.4 * 0.49,
    );
    let p: Vec<f64> = (0..12)
        .map(|k| 0.33 * (10.0f64 / 0.33).powf(k as f64 / 11.0))
        .collect();
    let mut rng = Normal::new(7);
    let y: Vec<f64> = p
        .iter()
        .map(|&p| curve(a, b, c, p) * (1.0 + 0.01 * rng.next()))
        .collect();
    let fit = fit_curve(&p, &y);
    assert!(fit.stop.converged(), "{fit:?}");
    // a is pinned by the plateau; b and c trade off against each other, so
    // with 1 % noise they are known to ~10 %.
    assert!((fit.a / a - 1.0).abs() < 0.03, "{fit:?}");
    assert!((fit.b / b - 1.0).abs() < 0.15, "{fit:?}");
    assert!((fit.c / c - 1.0).abs() < 0.15, "{fit:?}");
    // The residual is the noise, not more.
    let noise_rms = (y
        .iter()
        .zip(&p)
        .map(|(y, &p)| (y - curve(a, b, c, p)).powi(2))
        .sum::<f64>()
        / 12.0)
        .sqrt();
    assert!(fit.rms <= noise_rms * 1.01, "{} vs {noise_rms}", fit.rms);
    // Exact data: exact answer.
    let exact: Vec<f64> = p.iter().map(|&p| curve(a, b, c, p)).collect();
    let fit = fit_curve(&p, &exact);
    assert!(
        (fit.a - a).abs() < 1e-6 && (fit.b - b).abs() < 1e-6 && (fit.c - c).abs() < 1e-5,
        "{fit:?}"
    );
    // Capacity that falls with p cannot be a(1 − e^{−bp})^c with a, b, c > 0:
    // the fit must say it did not converge.
    let falling: Vec<f64> = p.iter().map(|&p| 0.8 / (1.0 + p)).collect();
    let fit = fit_curve(&p, &falling);
    assert!(!fit.stop.converged(), "{fit:?}");
}

const STUDY: &str = r#"ids = ["RSN1111_KOBE_NIS000", "RSN953_NORTHR_MUL009", "RSN1633_MANJIL_ABBAR--L",
       "RSN848_LANDERS_CLW-LN", "RSN1148_KOCAELI_ARC000", "RSN960_NORTHR_LOS000",
       "RSN1602_DUZCE_BOL000", "RSN1787_HECTOR_HEC000", "RSN169_IMPVALL_H-DLT262"]
[blocks]
p = [0.5, 1.0, 2.0, 4.0]
eps = [0.6, 0.75, 0.9]
[im]
count = 80
eta_min = 0.005
"#;

fn write_study(dir: &Path) -> std::path::PathBuf {
    let rec = bundled_records();
    let text = format!(
        "name = \"study\"\n[records]\nat2 = [\"{}\"]\nmanifest = \"{}\"\n{STUDY}",
        rec.display(),
        rec.join("manifest.csv").display()
    );
    let path = dir.join("study.toml");
    fs::write(&path, text).unwrap();
    path
}

#[test]
fn reduce_and_fit_follow_the_definitions_and_rerun_only_on_change() {
    let dir = tempdir();
    let pipe = write_study(dir.path());
    let out = dir.path().join("out");
    let (p, o) = (pipe.to_str().unwrap(), out.to_str().unwrap());
    let ok = |args: &[&str]| {
        let r = rocking(dir.path(), args);
        assert!(r.status.success(), "{args:?}: {}", stderr(&r));
        stdout(&r)
    };
    ok(&["sweep", p, "--outputs", o]);
    let text = ok(&["reduce", p, "--outputs", o]);
    assert!(text.contains("reduced 9 records × 12 blocks"), "{text}");
    assert!(ok(&["reduce", p, "--outputs", o]).contains("up to date"));

    let folder = out.join("study");
    let caps = read_capacities(&folder).unwrap();
    let fractiles: Vec<CapacityFractileRow> =
        read(&folder.join("capacity_fractiles.parquet")).unwrap();
    let fraction: Vec<OverturnFractionRow> =
        read(&folder.join("overturn_fraction.parquet")).unwrap();
    for row in &fractiles {
        let (bp, be, q) = (row.p, row.eps, row.quantile);
        // η_c fractile by hand (type 7 over the 9 records: h = 1 + 8q).
        let mut etas: Vec<f64> = caps
            .iter()
            .filter(|c| c.p == bp && c.eps == be)
            .map(|c| c.eta_c.unwrap_or(0.0))
            .collect();
        etas.sort_by(|a, b| a.total_cmp(b));
        let h = 1.0 + 8.0 * q;
        let (lo, w) = (h.floor() as usize - 1, h - h.floor());
        let by_hand = if w == 0.0 {
            etas[lo]
        } else {
            etas[lo] + w * (etas[lo + 1] - etas[lo])
        };
        assert!((row.eta_c - by_hand).abs() < 1e-15);
        // The horizontal counterpart: the q-fractile of EDP is +∞ at a level
        // once the interpolation at h touches an overturned record, i.e. once
        // at least 9 − ⌊h⌋ (+1 if h is whole) records have overturned there
        // under the resurrection rule.
        let need = if w == 0.0 { 9 - lo } else { 9 - lo - 1 };
        let first = fraction
            .iter()
            .filter(|r| r.p == bp && r.eps == be)
            .find(|r| (r.fraction_resurrection * 9.0).round() as usize >= need)
            .map(|r| r.eta);
        assert_eq!(row.eta_c_horizontal, first, "p = {bp}, ε = {be}, q = {q}");
    }
    // Lognormal table: β from the fractiles is (ln q84 − ln q16)/2 of the same rows.
    let logn: Vec<LognormalRow> = read(&folder.join("lognormal.parquet")).unwrap();
    assert_eq!(logn.len(), 12);

    let text = ok(&["fit", p, "--outputs", o]);
    assert!(text.contains("step 1:"), "{text}");
    assert!(ok(&["fit", p, "--outputs", o]).contains("up to date"));
    let step1: Vec<FitStep1Row> = read(&folder.join("fit_step1.parquet")).unwrap();
    assert_eq!(step1.len(), 9, "3 ε × 3 fractiles");
    // The reduce stage refuses sweep tables made with other settings (tables
    // copied by hand, say), rather than relabel them.
    let other = fs::read_to_string(&pipe)
        .unwrap()
        .replace("eta_min = 0.005", "eta_min = 0.004");
    let other_pipe = dir.path().join("other.toml");
    fs::write(&other_pipe, other).unwrap();
    let other_study = Study::load(&other_pipe, &out).unwrap();
    let cx = Context {
        study: &other_study,
        shard: None,
        reporter: &Silent,
        stage_seconds: Vec::new(),
        forced: false,
    };
    let e = rocking::stages::reduce::Reduce.run(&cx).unwrap_err();
    assert!(e.to_string().contains("other settings"), "{e}");
    // Through the command, an edited pipeline reruns the sweep first: no
    // stale sweep is ever reduced.
    let r = rocking(
        dir.path(),
        &["reduce", other_pipe.to_str().unwrap(), "--outputs", o],
    );
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(
        stderr(&r).contains("sweep        running: settings changed"),
        "{}",
        stderr(&r)
    );

    // Rerun with --force redoes the work.
    assert!(!ok(&["reduce", p, "--outputs", o, "--force"]).contains("up to date"));
    // A changed fractile definition reruns reduce.
    let text = fs::read_to_string(&pipe).unwrap() + "[reduce]\nfractile = \"type5\"\n";
    fs::write(&pipe, text).unwrap();
    assert!(!ok(&["reduce", p, "--outputs", o]).contains("up to date"));

    // Fragility from this pipeline's fit: rises with PGA.
    let fragility = || {
        rocking(
            dir.path(),
            &[
                "fragility",
                "--b",
                "0.2",
                "--h",
                "1.0",
                "--eps",
                "0.75",
                "--pga",
                "0.05,0.1,0.2,0.4",
                "--from",
                p,
                "--outputs",
                o,
                "--json",
            ],
        )
    };
    // The fit on disk was made from the type-7 fractiles, which reduce has
    // just replaced: it is refused (once used without a word), and is
    // taken again once fit has rerun.
    let r = fragility();
    assert!(!r.status.success());
    assert!(
        stderr(&r).contains("is not") && stderr(&r).contains(&format!("rocking run {p}")),
        "{}",
        stderr(&r)
    );
    ok(&["fit", p, "--outputs", o]);
    let r = fragility();
    assert!(r.status.success(), "{}", stderr(&r));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    let probs: Vec<f64> = v["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["probability"].as_f64().unwrap())
        .collect();
    assert!(probs.windows(2).all(|w| w[1] >= w[0]), "{probs:?}");
    // The study's regression is stretched beyond the study's own blocks
    // (p 0.5–4 1/s, ε 0.6–0.9), not the paper's (0.33–10 1/s): p = 7.05 was
    // extrapolated without a word. A block inside both is not warned of.
    for (block, want) in [
        (
            ["0.03", "0.145", "0.7"],
            Some("p = 7.048 1/s is outside the study's 0.5–4 1/s"),
        ),
        (["0.2", "0.9", "0.75"], None),
    ] {
        let [b, h, eps] = block;
        let args = [
            "fragility",
            "--b",
            b,
            "--h",
            h,
            "--eps",
            eps,
            "--pga",
            "0.5",
            "--from",
            p,
            "--outputs",
            o,
        ];
        let r = rocking(dir.path(), &args);
        assert!(r.status.success(), "{}", stderr(&r));
        match want {
            Some(want) => assert!(stderr(&r).contains(want), "{}", stderr(&r)),
            None => assert!(!stderr(&r).contains("outside"), "{}", stderr(&r)),
        }
        assert!(!stderr(&r).contains("regression's"), "{}", stderr(&r));
    }
}

#[test]
fn fragility_is_one_half_at_the_median_capacity() {
    // From the paper's coefficients: b = 0.25 m, h = 1 m, Housner's ε.
    let alpha = 0.25f64.atan();
    let p = (3.0 * 9.80665 / (4.0 * 1.0625f64.sqrt())).sqrt();
    let eps = 1.0 - 1.5 * alpha.sin().powi(2);
    let median = paper()[1].eta_c(p, eps);
    let pga_median = alpha / median;
    let pgas = format!("{},{},{}", pga_median * 0.5, pga_median, pga_median * 2.0);
    let r = rocking(
        &root(),
        &[
            "fragility",
            "--b",
            "0.25",
            "--h",
            "1",
            "--pga",
            &pgas,
            "--json",
        ],
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    let probs: Vec<f64> = v["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["probability"].as_f64().unwrap())
        .collect();
    assert!((probs[1] - 0.5).abs() < 1e-9, "{probs:?}");
    assert!(probs[0] < 0.5 && probs[2] > 0.5);
    assert!((v["eps"].as_f64().unwrap() - eps).abs() < 1e-12);

    // --direct: the share of the 44 far-field records whose capacity the
    // block exceeds; it can only grow with PGA, and it brackets the fitted
    // curve's 0.5 around the median PGA (the paper's fit describes these records).
    let pgas = format!(
        "{},{},{},{}",
        pga_median * 0.25,
        pga_median * 0.7,
        pga_median * 1.4,
        pga_median * 4.0
    );
    let r = rocking(
        &root(),
        &[
            "fragility",
            "--b",
            "0.25",
            "--h",
            "1",
            "--pga",
            &pgas,
            "--direct",
            "--json",
        ],
    );
    assert!(r.status.success(), "{}", stderr(&r));
    let v: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(v["records"], 44);
    let emp: Vec<f64> = v["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| q["empirical"].as_f64().unwrap())
        .collect();
    assert!(emp.windows(2).all(|w| w[1] >= w[0]), "{emp:?}");
    assert!(emp[1] < 0.5 && emp[2] > 0.5, "{emp:?}");
    assert_eq!((emp[0], emp[3]), (0.0, 1.0), "{emp:?}");
}

/// The paper's grid end to end (about a minute): the median capacity within
/// 10 % of the paper's Eq. 10 on average over p ≥ 0.5. Opt-in locally with
/// ROCKING_SLOW=1; CI sets it.
#[test]
fn paper_median_capacity_within_ten_percent_of_eq10() {
    if std::env::var("ROCKING_SLOW").is_err() {
        eprintln!("skipped: set ROCKING_SLOW=1 to run the paper's grid");
        return;
    }
    let dir = tempdir();
    let out = dir.path().join("out");
    let pipe = root().join("pipelines/paper.toml");
    for stage in ["sweep", "reduce", "example"] {
        let r = rocking(
            &root(),
            &[
                stage,
                pipe.to_str().unwrap(),
                "--outputs",
                out.to_str().unwrap(),
            ],
        );
        assert!(r.status.success(), "{stage}: {}", stderr(&r));
    }
    let rows: Vec<CapacityFractileRow> =
        read(&out.join("paper/capacity_fractiles.parquet")).unwrap();
    let law = &paper()[1];
    let errors: Vec<f64> = rows
        .iter()
        .filter(|r| r.quantile == 0.5 && r.p >= 0.5)
        .map(|r| (r.eta_c / law.eta_c(r.p, r.eps) - 1.0).abs())
        .collect();
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    eprintln!(
        "mean |η_c,50 / Eq. 10 − 1| over p ≥ 0.5: {mean:.4} ({} blocks)",
        errors.len()
    );
    assert!(mean < 0.10, "{mean}");

    // The paper's Fig. 5 block (p = 2 1/s, ε = 0.70, `[example]`,
    // off the grid) over the 44 records: its median capacity against Eq. 10
    // there, by the same 10 % (measured: 0.1952 against 0.1956).
    let example: Vec<rocking::tables::sweep::CapacityRow> =
        read(&out.join("paper/example_capacities.parquet")).unwrap();
    assert_eq!(example.len(), 44);
    assert!(example.iter().all(|c| (c.p, c.eps) == (2.0, 0.7)));
    let mut etas: Vec<f64> = example.iter().map(|c| c.eta_c.unwrap_or(0.0)).collect();
    etas.sort_by(f64::total_cmp);
    let median = (etas[21] + etas[22]) / 2.0;
    let eq10 = law.eta_c(2.0, 0.7);
    eprintln!("example block: median η_c {median:.4}, Eq. 10 {eq10:.4}");
    assert!((median / eq10 - 1.0).abs() < 0.10, "{median} vs {eq10}");

    // The bootstrap bands (paper.toml: 1,000 resamples of pairs,
    // 90 %) against the paper's laws. docs/MODEL.md §12 gives a numpy
    // reference of the same procedure: Eq. 10 inside the median's band at
    // about 97 % of the blocks with p ≥ 0.5, Eq. 11 (16 %) about 83 %,
    // Eq. 12 (84 %) about 91 %. Another generator moves band edges by Monte
    // Carlo noise, and with it the few blocks whose paper value lies near an
    // edge: ±6 points (6 of 100 blocks).
    let bands: Vec<rocking::tables::reduce::CapacityBandRow> =
        read(&out.join("paper/capacity_bands.parquet")).unwrap();
    assert_eq!(bands.len(), 360);
    for (qi, (q, reference)) in [(0.16, 0.83), (0.5, 0.97), (0.84, 0.91)]
        .into_iter()
        .enumerate()
    {
        let law = &paper()[qi];
        let rows: Vec<_> = bands
            .iter()
            .filter(|b| b.quantile == q && b.p >= 0.5)
            .collect();
        let inside = rows
            .iter()
            .filter(|b| (b.lo..=b.hi).contains(&law.eta_c(b.p, b.eps)))
            .count() as f64
            / rows.len() as f64;
        eprintln!(
            "q = {q}: paper inside the band at {inside:.2} of {} blocks",
            rows.len()
        );
        assert!(
            (inside - reference).abs() <= 0.06,
            "q = {q}: {inside} vs {reference}"
        );
    }
    assert!(bands.iter().all(|b| b.lo <= b.eta_c && b.eta_c <= b.hi));
}

/// Bootstrap bands of the capacity fractiles on the far-field
/// set (two blocks, a coarse grid). Every band contains its point estimate
/// (the estimate is the statistic of the full sample, which the resamples
/// scatter around); the same seed gives the same bytes at 1 and 2 threads;
/// another seed moves the bands; pairs need the manifest's pairs.
#[test]
fn capacity_bands_contain_their_estimates_and_repeat_to_the_byte() {
    use rocking::stats::ResampleUnit;
    use rocking::tables::reduce::{CapacityBandRow, CapacityResampleRow};
    let dir = tempdir();
    let body = |seed: u64| {
        format!(
            "sets = [\"far-field\"]\n[blocks]\np = [1.0, 2.0, 4.0]\neps = [0.6, 0.75, 0.9]\n\
             [im]\ncount = 40\n[uncertainty]\nresamples = 300\nseed = {seed}\n"
        )
    };
    let pipe = crate::util::write_pipeline(dir.path(), "bands", &body(5));
    let run = |out: &str, threads: &str| {
        let o = rocking(
            dir.path(),
            &[
                "run",
                pipe.to_str().unwrap(),
                "--outputs",
                out,
                "--threads",
                threads,
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        ["capacity_bands", "capacity_resamples", "fit_bands"]
            .map(|t| fs::read(dir.path().join(out).join(format!("bands/{t}.parquet"))).unwrap())
    };
    let (one, two) = (run("one", "1"), run("two", "2"));
    for (k, t) in ["capacity_bands", "capacity_resamples", "fit_bands"]
        .iter()
        .enumerate()
    {
        assert!(
            one[k] == two[k],
            "{t}.parquet differs between 1 and 2 threads"
        );
    }
    let rows: Vec<CapacityBandRow> =
        read(&dir.path().join("one/bands/capacity_bands.parquet")).unwrap();
    let fractiles: Vec<CapacityFractileRow> =
        read(&dir.path().join("one/bands/capacity_fractiles.parquet")).unwrap();
    assert_eq!(rows.len(), 27);
    for (b, f) in rows.iter().zip(&fractiles) {
        assert_eq!((b.p, b.quantile, b.eta_c), (f.p, f.quantile, f.eta_c));
        assert!(b.lo <= b.eta_c && b.eta_c <= b.hi, "{b:?}");
        assert!(b.lo < b.hi, "a band of 44 records has width: {b:?}");
        assert_eq!(
            (b.level, b.resamples, b.unit),
            (0.9, 300, ResampleUnit::Pair)
        );
    }
    // The resamples: 300 per block and fractile; each band is their 5 and
    // 95 % type-7 fractiles (recomputed here from the table).
    let resamples: Vec<CapacityResampleRow> =
        read(&dir.path().join("one/bands/capacity_resamples.parquet")).unwrap();
    assert_eq!(resamples.len(), 300 * 27);
    for b in &rows {
        let mut v: Vec<f64> = resamples
            .iter()
            .filter(|r| (r.p, r.eps, r.quantile) == (b.p, b.eps, b.quantile))
            .map(|r| r.eta_c)
            .collect();
        v.sort_by(f64::total_cmp);
        let at = |q: f64| {
            let h = 299.0 * q;
            let i = h.floor() as usize;
            v[i] + (h - i as f64) * (v[i + 1] - v[i])
        };
        assert!((b.lo - at(0.05)).abs() < 1e-15 && (b.hi - at(0.95)).abs() < 1e-15);
    }
    // The fit's bands: every resample refitted. Each ε's η_c curve at 61 p
    // and the example fragility at 120 PGAs; at the grid's ends the point
    // value is the fitted law of fit_comparison; every band holds its point.
    let fit_bands: Vec<FitBandRow> = read(&dir.path().join("one/bands/fit_bands.parquet")).unwrap();
    assert_eq!(fit_bands.len(), 3 * 3 * 61 + 120);
    let comparison: Vec<FitComparisonRow> =
        read(&dir.path().join("one/bands/fit_comparison.parquet")).unwrap();
    for c in comparison.iter().filter(|c| c.p == 1.0 || c.p == 4.0) {
        let band = fit_bands
            .iter()
            .find(|f| f.quantile == Some(c.quantile) && f.eps == c.eps && f.p == c.p)
            .expect("a band row at the grid's ends");
        assert!((band.value.unwrap() - c.eta_c_fit.unwrap()).abs() < 1e-12);
    }
    for f in &fit_bands {
        assert!(f.used > 0 && f.used <= 300 && f.resamples == 300, "{f:?}");
        let (lo, v, hi) = (f.lo.unwrap(), f.value.unwrap(), f.hi.unwrap());
        assert!(lo <= v && v <= hi, "{f:?}");
    }
    // The example fragility (b = 0.25 m, h = 1 m, Housner's ε) is the one
    // `fragility --from` gives at every PGA: 0 below the uplift PGA b/h =
    // 0.25 g, where the table had P > 0 (0.0125 at 0.24 g in the quick
    // study), and the command's probability above it.
    let example: Vec<&FitBandRow> = fit_bands.iter().filter(|f| f.pga_g.is_some()).collect();
    let pgas: Vec<String> = example
        .iter()
        .map(|f| f.pga_g.unwrap().to_string())
        .collect();
    let command = rocking(
        dir.path(),
        &[
            "fragility",
            "--b",
            "0.25",
            "--h",
            "1.0",
            "--from",
            pipe.to_str().unwrap(),
            "--outputs",
            "one",
            "--pga",
            &pgas.join(","),
            "--json",
        ],
    );
    assert!(command.status.success(), "{}", stderr(&command));
    let command: serde_json::Value = serde_json::from_slice(&command.stdout).unwrap();
    for (k, f) in example.iter().enumerate() {
        let pga = f.pga_g.unwrap();
        let p = command["points"][k]["probability"].as_f64().unwrap();
        assert_eq!(f.value, Some(p), "at {pga} g");
        if pga < 0.25 {
            assert_eq!((f.lo, f.hi), (Some(0.0), Some(0.0)), "at {pga} g");
        }
    }

    // Another seed: other draws, other bands.
    fs::write(
        &pipe,
        fs::read_to_string(&pipe)
            .unwrap()
            .replace("seed = 5", "seed = 6"),
    )
    .unwrap();
    assert!(run("one", "2")[0] != one[0], "the seed moves the bands");

    // Without a manifest there are no pairs: refused with the pipeline,
    // before any run; by record it works.
    let far = crate::util::bundled_records().join("far-field");
    let bare = dir.path().join("bare.toml");
    let text = |unit: &str| {
        format!(
            "name = \"bare\"\n[records]\nat2 = [\"{}\"]\n[blocks]\np = [2.0]\neps = [0.8]\n\
             [im]\ncount = 20\n[uncertainty]\nresamples = 50\nunit = \"{unit}\"\n",
            far.display()
        )
    };
    fs::write(&bare, text("pair")).unwrap();
    let o = rocking(
        dir.path(),
        &["run", bare.to_str().unwrap(), "--outputs", "bare"],
    );
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("unit` = \"pair\"")
            && e.contains("no manifest")
            && e.contains("unit = \"record\""),
        "{e}"
    );
    assert!(
        !dir.path().join("bare/bare/capacities.parquet").exists(),
        "no sweep ran"
    );
    fs::write(&bare, text("record")).unwrap();
    let o = rocking(
        dir.path(),
        &["run", bare.to_str().unwrap(), "--outputs", "bare"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
}
