//! The damage stage and the damage states of `fragility`, `risk` and
//! `export --from PIPELINE.toml`: each record's state capacities against its
//! runs, the fits against the paper's fractiles by hand and the likelihood's
//! maximum, the example block against the same block of the grid, the
//! table carried to another block, refusals and staleness.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::util::{rocking, stderr, stdout, tempdir, write_pipeline, TempDir};
use rocking::damage::FitMethod;
use rocking::tables::damage::{DamageStateRow, StateCapacityRow};
use rocking::tables::ims::RecordImRow;
use rocking::tables::sweep::{CapacityRow, IdaRow};

const STATES: &str = "light=0.2,heavy=0.6,overturned=overturned";

/// Two blocks of the grid (p = 1 and 4 1/s, ε = 0.7) and the example
/// block p = 1, ε = 0.7 (the grid's first, run again by the example stage).
fn study() -> (TempDir, PathBuf, PathBuf) {
    let dir = tempdir();
    let body = format!(
        "sets = [\"far-field\"]\n[model]\nkind = \"linearized\"\n[blocks]\np = [1.0, 4.0]\n\
         eps = [0.7]\n[example]\np = 1.0\neps = 0.7\n[damage]\nstates = \"{STATES}\"\n"
    );
    let pipeline = write_pipeline(dir.path(), "dmg", &body);
    let outputs = dir.path().join("out");
    let out = rocking(dir.path(), &["run", s(&pipeline), "--outputs", s(&outputs)]);
    assert!(out.status.success(), "{}", stderr(&out));
    (dir, pipeline, outputs)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn read<T: rocking::tables::Table>(dir: &Path, name: &str) -> Vec<T> {
    rocking::tables::read(&dir.join(name)).unwrap()
}

/// Type 7 fractile of sorted values, written out (numpy's default).
fn type7(sorted: &[f64], q: f64) -> f64 {
    let h = (sorted.len() - 1) as f64 * q;
    let (lo, t) = (h.floor() as usize, h - h.floor());
    if t == 0.0 {
        sorted[lo]
    } else {
        sorted[lo] + t * (sorted[lo + 1] - sorted[lo])
    }
}

/// The censored normal log-likelihood of ln capacities.
fn log_likelihood(reached: &[f64], censored: &[f64], mu: f64, sigma: f64) -> f64 {
    let n = statrs::distribution::Normal::new(0.0, 1.0).unwrap();
    use statrs::distribution::{Continuous, ContinuousCDF};
    let a: f64 = reached
        .iter()
        .map(|y| n.ln_pdf((y.ln() - mu) / sigma) - sigma.ln())
        .sum();
    let b: f64 = censored
        .iter()
        .map(|c| n.sf((c.ln() - mu) / sigma).ln())
        .sum();
    a + b
}

#[test]
fn damage_tables_against_the_runs_and_the_fits_by_hand() {
    let (_dir, _pipeline, outputs) = study();
    let dir = outputs.join("dmg");
    let caps: Vec<CapacityRow> = read(&dir, "capacities.parquet");
    let ida: Vec<IdaRow> = read(&dir, "ida_points.parquet");
    let state_caps: Vec<StateCapacityRow> = read(&dir, "state_capacities.parquet");
    let fits: Vec<DamageStateRow> = read(&dir, "damage_states.parquet");
    let ims: Vec<RecordImRow> = read(&dir, "record_ims.parquet");
    assert_eq!(state_caps.len(), caps.len() * 3);
    let thresholds = [
        ("light", Some(0.2)),
        ("heavy", Some(0.6)),
        ("overturned", None),
    ];
    let n_blocks = 2;
    for c in &caps {
        let block = c.case_id as usize % n_blocks;
        let mut runs: Vec<&IdaRow> = ida.iter().filter(|r| r.case_id == c.case_id).collect();
        runs.sort_by(|a, b| b.eta.total_cmp(&a.eta));
        for (name, x) in thresholds {
            let row = state_caps
                .iter()
                .find(|r| {
                    r.block_index as usize == block && r.record_id == c.record_id && r.state == name
                })
                .unwrap();
            let Some(x) = x else {
                // Overturning is η_c itself, or censored at the strongest run.
                match c.eta_c {
                    Some(eta) => assert!(row.reached && row.eta == eta),
                    None => assert!(!row.reached && row.eta == runs.last().unwrap().eta),
                }
                continue;
            };
            // The first run, as intensity rises, at or past the threshold.
            let first = runs.iter().position(|r| r.overturned || r.edp >= x);
            match first {
                None => assert!(!row.reached && row.eta == runs.last().unwrap().eta),
                Some(k) => {
                    assert!(row.reached, "{} {name}", c.record_id);
                    let at = runs[k];
                    let want = if at.overturned || k == 0 || runs[k - 1].edp >= at.edp {
                        at.eta
                    } else {
                        // Linear in 1/η between the run before and this one.
                        let b = runs[k - 1];
                        let t = (x - b.edp) / (at.edp - b.edp);
                        1.0 / (1.0 / b.eta + t * (1.0 / at.eta - 1.0 / b.eta))
                    };
                    assert!(
                        (row.eta / want - 1.0).abs() < 1e-12,
                        "{} {name}: {} against {want}",
                        c.record_id,
                        row.eta
                    );
                }
            }
        }
    }
    // The fits in PGA/(αg) and p·PGV/(αg), by the paper's fractiles by hand.
    // The long table: one row per record × measure.
    let value: BTreeMap<(&str, &str), f64> = ims
        .iter()
        .map(|r| ((r.record_id.as_str(), r.im.as_str()), r.value))
        .collect();
    for (block, p) in [(0, 1.0), (1, 4.0)] {
        for (name, _) in thresholds {
            let of_state: Vec<&StateCapacityRow> = state_caps
                .iter()
                .filter(|r| r.block_index == block && r.state == name)
                .collect();
            for (im, to_im) in [
                (
                    "pga",
                    Box::new(|_: &str, eta: f64| 1.0 / eta) as Box<dyn Fn(&str, f64) -> f64>,
                ),
                (
                    "pgv",
                    Box::new(|id: &str, eta: f64| {
                        let (pgv, pga) = (value[&(id, "pgv")], value[&(id, "pga")]);
                        p / 100.0 / 9.80665 * pgv * (1.0 / eta) / pga
                    }),
                ),
            ] {
                let mut all: Vec<f64> = of_state
                    .iter()
                    .map(|r| {
                        if r.reached {
                            to_im(&r.record_id, r.eta)
                        } else {
                            f64::INFINITY
                        }
                    })
                    .collect();
                all.sort_by(f64::total_cmp);
                let fit = |m: FitMethod| {
                    fits.iter()
                        .find(|f| {
                            f.block_index == block && f.state == name && f.im == im && f.method == m
                        })
                        .unwrap()
                };
                let fr = fit(FitMethod::Fractile);
                assert_eq!(fr.n_records, 44);
                assert_eq!(
                    fr.n_reached as usize,
                    of_state.iter().filter(|r| r.reached).count()
                );
                let (q16, q50, q84) = (type7(&all, 0.16), type7(&all, 0.5), type7(&all, 0.84));
                if q84.is_finite() {
                    let m = fr.median_dimensionless.unwrap();
                    assert!(
                        (m / q50 - 1.0).abs() < 1e-12,
                        "{name} {im}: {m} against {q50}"
                    );
                    let beta = 0.5 * (q84 / q16).ln();
                    assert!((fr.beta.unwrap() - beta).abs() < 1e-12);
                } else {
                    assert!(fr.median_dimensionless.is_none());
                }
                // Maximum likelihood: no step in μ or σ raises the likelihood.
                let ml = fit(FitMethod::MaxLikelihood);
                let (Some(m), Some(beta)) = (ml.median_dimensionless, ml.beta) else {
                    continue;
                };
                let reached: Vec<f64> = all.iter().copied().filter(|v| v.is_finite()).collect();
                let censored: Vec<f64> = of_state
                    .iter()
                    .filter(|r| !r.reached)
                    .map(|r| to_im(&r.record_id, r.eta))
                    .collect();
                let best = log_likelihood(&reached, &censored, m.ln(), beta);
                for (dm, ds) in [(1e-4, 0.0), (-1e-4, 0.0), (0.0, 1e-4), (0.0, -1e-4)] {
                    let other = log_likelihood(&reached, &censored, m.ln() + dm, beta + ds);
                    assert!(other <= best + 1e-9, "{name} {im}: {other} > {best}");
                }
            }
        }
    }
    // The example block is the grid's first: the same rows, by another run.
    let example: Vec<DamageStateRow> = read(&dir, "example_damage_states.parquet");
    let grid_first: Vec<&DamageStateRow> = fits.iter().filter(|f| f.block_index == 0).collect();
    assert_eq!(example.len(), grid_first.len());
    for (a, b) in example.iter().zip(grid_first) {
        assert_eq!(
            (a.median_dimensionless, a.beta, &a.state, &a.im),
            (b.median_dimensionless, b.beta, &b.state, &b.im)
        );
    }
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("## Damage states"), "{report}");
    assert!(report.contains("| light | θmax/α ≥ 0.2 |"), "{report}");
    assert!(dir.join("figures/damage_states.svg").exists());
}

/// `fragility --states --from`: the study's fits carried to a block between
/// its two p (linear in ln p, the median on a log scale), at the study's ε;
/// the probabilities are the lognormals'; `risk --states` gives the same
/// overturning rate as `risk`; a state the study lacks, an edited [damage]
/// and the paper's regression are refused by name.
#[test]
fn states_from_a_study_carried_to_a_block() {
    let (dir, pipeline, outputs) = study();
    let table: Vec<DamageStateRow> = read(&outputs.join("dmg"), "damage_states.parquet");
    let (b, h) = ("0.1", "1.0");
    let common = |extra: &[&str]| {
        let mut a = vec![
            "--b",
            b,
            "--h",
            h,
            "--eps",
            "0.7",
            "--from",
            s(&pipeline),
            "--outputs",
            s(&outputs),
            "--states",
            STATES,
        ];
        a.extend(extra);
        a.iter().map(|x| x.to_string()).collect::<Vec<_>>()
    };
    let run = |args: Vec<String>| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        rocking(dir.path(), &args)
    };
    let fragility = |dispersion: &str| {
        let mut args = vec!["fragility".to_string()];
        args.extend(common(&[
            "--pga",
            "0.05,0.1",
            "--dispersion",
            dispersion,
            "--json",
        ]));
        let out = run(args);
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_str::<serde_json::Value>(&stdout(&out)).unwrap()
    };
    let v = fragility("each");
    let (alpha, p) = (v["alpha_rad"].as_f64().unwrap(), v["p"].as_f64().unwrap());
    assert!(p > 1.0 && p < 4.0, "{p}");
    let t = (p.ln() - 1f64.ln()) / (4f64.ln() - 1f64.ln());
    for (j, name) in ["light", "heavy", "overturned"].iter().enumerate() {
        let node = |block: i64| {
            let r = table
                .iter()
                .find(|r| {
                    r.block_index == block
                        && r.state == *name
                        && r.im == "pga"
                        && r.method == FitMethod::Fractile
                })
                .unwrap();
            (r.median_dimensionless.unwrap().ln(), r.beta.unwrap())
        };
        let ((m0, b0), (m1, b1)) = (node(0), node(1));
        let median = alpha * (m0 + t * (m1 - m0)).exp();
        let beta = b0 + t * (b1 - b0);
        let state = &v["fragility"]["states"][j];
        let got = state["fractile"]["median"].as_f64().unwrap();
        assert!(
            (got / median - 1.0).abs() < 1e-12,
            "{name}: {got} against {median}"
        );
        assert!((state["fractile"]["beta"].as_f64().unwrap() - beta).abs() < 1e-12);
        let prob = v["points"][1]["probabilities"][j].as_f64().unwrap();
        let want = rocking::stats::normal_cdf((0.1f64 / median).ln() / beta);
        assert!((prob - want).abs() < 1e-14, "{name}: {prob} against {want}");
    }
    // By default the states share the heaviest's β, medians in order
    // (docs/MODEL.md §15): the same fits, made sequential.
    let each = &v["fragility"]["states"];
    let v = fragility("common");
    assert_eq!(v["fragility"]["dispersion"], "common");
    let heaviest = each[2]["fractile"]["beta"].as_f64().unwrap();
    // Lowered to the next heavier state's where above it; the heaviest
    // (overturning) as its own fit.
    let mut ceiling = f64::INFINITY;
    let names = ["light", "heavy", "overturned"];
    let warned = v["fragility"]["warnings"].to_string();
    for j in (0..3).rev() {
        let state = &v["fragility"]["states"][j];
        let own = each[j]["fractile"]["median"].as_f64().unwrap();
        ceiling = ceiling.min(own);
        assert_eq!(state["fractile"]["median"].as_f64(), Some(ceiling));
        assert_eq!(state["fractile"]["beta"].as_f64(), Some(heaviest));
        // A median lowered is said, one kept is not.
        let said = warned.contains(&format!("the median of `{}`", names[j]));
        assert_eq!(said, ceiling < own, "{}: {warned}", names[j]);
    }
    // risk --states on a power-law hazard λ(a) = k0 a^−k: each state's rate
    // is Cornell's closed form k0 m^−k exp(k²β²/2) of its lognormal.
    let (k0, k) = (2e-4, 2.6);
    let mut text = String::from("pga_g,annual_rate\n");
    for i in 0..30 {
        let a = 0.001 * (10.0f64 / 0.001).powf(i as f64 / 29.0);
        text.push_str(&format!("{a:?},{:?}\n", k0 * a.powf(-k)));
    }
    let hazard = dir.path().join("h.csv");
    std::fs::write(&hazard, text).unwrap();
    let mut args = vec![
        "risk".to_string(),
        "--hazard".into(),
        s(&hazard).into(),
        "--json".into(),
    ];
    args.extend(common(&[]));
    let out = run(args);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    let rows = v["sites"][0]["states"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    for r in rows {
        let (m, beta) = (r["median"].as_f64().unwrap(), r["beta"].as_f64().unwrap());
        // Cut at the block's uplift PGA, b/h g (MODEL.md §13).
        let want = crate::util::cornell_above(k0, k, m, beta, 0.1);
        let got = r["annual_rate"].as_f64().unwrap();
        assert!(
            (got / want - 1.0).abs() < 1e-9,
            "{}: {got} against {want}",
            r["state"]
        );
        let p50 = 1.0 - (-50.0 * got).exp();
        assert!((r["p_in_years"].as_f64().unwrap() - p50).abs() < 1e-15);
    }
    // Refusals. SA at a period the study's records do not carry: the
    // periods they do, and --direct (once "periods 0.05–4 s", which holds
    // 0.6, or "no full grid of p × ε").
    let mut args = vec!["fragility".to_string()];
    args.extend(common(&["--im", "sa(0.6)", "--at", "0.1"]));
    let out = run(args);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("has no sa(0.6): a study's records carry SA at 0.05, 0.075")
            && e.contains("(--direct), which computes SA at any period"),
        "{e}"
    );
    let mut args = vec!["fragility".to_string()];
    args.extend(common(&["--pga", "0.1"]));
    let k = args.iter().position(|a| a == STATES).unwrap();
    args[k] = "moved=0.3,overturned=overturned".into();
    let out = run(args.clone());
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("damage state `moved`"),
        "{}",
        stderr(&out)
    );
    let paper: Vec<String> = vec![
        "fragility",
        "--b",
        b,
        "--h",
        h,
        "--pga",
        "0.1",
        "--states",
        STATES,
    ]
    .into_iter()
    .map(String::from)
    .collect();
    let out = run(paper);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(e.contains("`light`") && e.contains("--direct"), "{e}");
    // An edited [damage]: the table on disk is not the pipeline's.
    let text = std::fs::read_to_string(&pipeline).unwrap();
    std::fs::write(&pipeline, text.replace("heavy=0.6", "heavy=0.7")).unwrap();
    args[k] = STATES.into();
    let out = run(args);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("damage table"), "{}", stderr(&out));
}

#[test]
fn unordered_damage_states_in_a_pipeline_are_refused_by_key() {
    let dir = tempdir();
    let pipeline = write_pipeline(
        dir.path(),
        "bad",
        "sets = [\"far-field\"]\n[blocks]\np = [1.0]\neps = [0.7]\n[damage]\nstates = \"a=0.5,b=0.2\"\n",
    );
    let out = rocking(
        dir.path(),
        &["run", s(&pipeline), "--outputs", s(&dir.path().join("o"))],
    );
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(e.contains("damage.states") && e.contains("`b`"), "{e}");
}

/// The rates of `risk --states` (JSON of one block or an inventory), per
/// block and site, lightest state first.
fn state_rates(v: &serde_json::Value) -> Vec<(String, Vec<f64>)> {
    let blocks = v.as_array().cloned().unwrap_or_else(|| vec![v.clone()]);
    let mut out = Vec::new();
    for b in &blocks {
        for site in b["sites"].as_array().unwrap() {
            let rates = site["states"]
                .as_array()
                .unwrap()
                .iter()
                .map(|s| s["annual_rate"].as_f64().unwrap())
                .collect();
            out.push((
                format!("{} at site {}", b["block"]["name"], site["site"]),
                rates,
            ));
        }
    }
    out
}

/// A heavier state is never reached more often than a lighter one: every
/// record passes θmax/α = 0.1 before it overturns. Fitted each on its own,
/// the states' lognormals cross, and on a steep hazard the block of the
/// fault (b = 0.2, h = 0.9) overturned 10⁵ times more often than it
/// rocked (1.31e-6 against 1.10e-11/yr); the server rack of the bundled
/// inventory had large_rocking below overturned at two sites. By default
/// the states share one β, and the rates are ordered at every site.
#[test]
fn damage_state_rates_never_invert() {
    let dir = tempdir();
    let d = dir.path();
    std::fs::write(
        d.join("steep.csv"),
        "pga_g,annual_rate\n0.01,1\n0.05,0.1\n0.1,1e-2\n0.15,1e-4\n0.2,1e-7\n0.25,1e-12\n",
    )
    .unwrap();
    let hazard = crate::util::root().join("records/hazard");
    let (oq, museum) = (
        hazard.join("synthetic-openquake.csv"),
        hazard.join("museum-inventory.csv"),
    );
    let states = "rocking=0.1,large_rocking=0.5,overturned=overturned";
    // The lognormals alone (--if-not-lognormal lognormal): where a state's
    // capacities fail the lognormal check the block's fragility is
    // otherwise the records' curves, which are ordered by construction
    // (each record reaches a lighter state first), checked last.
    let risk = |hazard: &str, blocks: &[&str], dispersion: &str, shape: &str| {
        let mut args = vec![
            "risk",
            "--hazard",
            hazard,
            "--direct",
            "--states",
            states,
            "--dispersion",
            dispersion,
            "--if-not-lognormal",
            shape,
            "--json",
        ];
        args.extend(blocks);
        let out = rocking(d, &args);
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_str::<serde_json::Value>(&stdout(&out)).unwrap()
    };
    let ordered = |rates: &[f64]| rates.windows(2).all(|w| w[1] <= w[0]);
    let statue = ["--b", "0.2", "--h", "0.9"];
    let inventory = ["--inventory", s(&museum)];
    let cases = [
        ("steep.csv", &statue[..]),
        (s(&oq), &inventory[..]),
        ("steep.csv", &inventory[..]),
    ];
    for (hazard, blocks) in cases {
        for shape in ["lognormal", "curve"] {
            for (name, rates) in state_rates(&risk(hazard, blocks, "common", shape)) {
                assert_eq!(rates.len(), 3);
                assert!(ordered(&rates), "{hazard}, {shape}, {name}: {rates:?}");
            }
        }
    }
    // Each its own fit: the fault, which the default removes.
    let each = state_rates(&risk("steep.csv", &statue, "each", "lognormal"));
    assert!(!ordered(&each[0].1), "{each:?}");
    // The records' curves are ordered whatever the dispersion (the statue
    // with ε = 0.85, whose overturning capacities are not lognormal).
    let not_lognormal = ["--b", "0.2", "--h", "0.9", "--eps", "0.85"];
    let curves = risk("steep.csv", &not_lognormal, "each", "curve");
    assert_eq!(curves["method"], "empirical", "{curves}");
    let fits: Vec<&str> = curves["sites"][0]["states"]
        .as_array()
        .map(|s| s.iter().filter_map(|x| x["fit"].as_str()).collect())
        .unwrap_or_default();
    assert!(fits.iter().all(|f| *f == "empirical"), "{curves}");
    assert!(ordered(&state_rates(&curves)[0].1));
}

/// The same, for any fits and any hazard: a property over 2,000 sets of
/// three states' lognormals (random medians and β, pseudo-random but
/// fixed) made sequential, each probability ordered at 400 levels, and
/// each rate ordered on steep, power-law, flat-tailed and ending curves,
/// with and without a lower cut.
#[test]
fn sequential_states_are_ordered_at_every_level_and_on_every_curve() {
    use rocking::damage::{common_dispersion, Lognormal};
    use rocking::hazard::HazardCurve;
    use rocking::risk::{assess_above, Beyond, Fragility};
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut uniform = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let curve = |iml: &[f64], rate: &[f64], ends_at: Option<f64>| HazardCurve {
        im: rocking::im::Im::Pga,
        lon: None,
        lat: None,
        iml: iml.to_vec(),
        annual_rate: rate.to_vec(),
        ends_at,
        infinite: Vec::new(),
        kind: None,
    };
    let curves = [
        curve(
            &[0.01, 0.05, 0.1, 0.15, 0.2, 0.25],
            &[1.0, 0.1, 1e-2, 1e-4, 1e-7, 1e-12],
            None,
        ),
        curve(&[0.005, 0.1, 1.0, 3.0], &[2.0, 2e-2, 2e-4, 1e-5], None),
        curve(&[0.1, 0.3, 0.6], &[0.01, 1e-3, 1e-3], None),
        curve(&[0.05, 0.2, 0.5], &[0.05, 2e-3, 1e-4], Some(0.8)),
    ];
    for _ in 0..2000 {
        let mut fits: Vec<Option<Lognormal>> = (0..3)
            .map(|_| {
                Some(Lognormal {
                    median: 0.02 * 10f64.powf(2.0 * uniform()),
                    beta: 0.05 + 0.8 * uniform(),
                })
            })
            .collect();
        common_dispersion(&mut fits);
        let fits: Vec<Lognormal> = fits.into_iter().flatten().collect();
        for i in 0..400 {
            let x = 1e-3 * 1e4f64.powf(i as f64 / 399.0);
            let p: Vec<f64> = fits.iter().map(|l| l.cdf(x)).collect();
            assert!(p[1] <= p[0] && p[2] <= p[1], "{fits:?} at {x}: {p:?}");
        }
        let cut = 0.2 * uniform();
        for c in &curves {
            for beyond in [Beyond::Stop, Beyond::Extrapolate] {
                let r: Vec<f64> = fits
                    .iter()
                    .map(|l| {
                        let f = Fragility::Lognormal {
                            median: l.median,
                            beta: l.beta,
                        };
                        assess_above(c, &f, beyond, cut).annual_rate
                    })
                    .collect();
                assert!(r[1] <= r[0] && r[2] <= r[1], "{fits:?}, {c:?}: {r:?}");
            }
        }
    }
}

/// A state every record reaches as it lifts (θmax/α ≥ 1e-9): each
/// record's capacity is its first grid level above the uplift PGA, g·tan α
/// for every record (|ψ̈| ≤ 1 at PGA 1), so the 44 capacities are one
/// level, a step. The lognormal check found "p = 0.000" on their last
/// bits and warned that some records never reach `a`, while all 44 do.
/// Equal capacities are not tested, and nothing is warned.
#[test]
fn a_state_every_record_reaches_at_one_level_is_a_step_without_warning() {
    let dir = tempdir();
    let out = rocking(
        dir.path(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--states",
            "a=1e-9",
            "--pga",
            "0.3",
            "--json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let answer: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    let f = &answer["fragility"];
    let warnings = f["warnings"].to_string();
    assert!(!warnings.contains("never reach"), "{warnings}");
    assert!(!warnings.contains("lognormal check"), "{warnings}");
    let a = &f["states"][0];
    // g·tan α in g: b/h.
    let uplift = 0.2 / 0.9;
    let median = a["fractile"]["median"].as_f64().unwrap();
    // The first of the grid's levels (3.5 % apart in η) above the uplift.
    assert!(
        median >= uplift && median < uplift * 1.036,
        "median {median} g against the uplift PGA {uplift} g"
    );
    assert!(a["fractile"]["beta"].as_f64().unwrap() < 1e-6, "{a}");
    assert_eq!(a["reached"], 44);
    assert!(a["lognormal_p"].is_null(), "{a}");
}

/// With `--from PIPELINE`, overturning's maximum-likelihood fit is the
/// study's damage table's. It was read only where another state was asked:
/// `--states overturned=overturned --method mle` printed "—" where
/// `--states light=0.2,overturned=overturned` gave 0.80 g for the same
/// block. Both give the table's now, and the same P.
#[test]
fn overturnings_likelihood_fit_does_not_depend_on_the_other_states() {
    let (dir, pipeline, outputs) = study();
    let mle = |states: &str| -> (f64, f64) {
        let out = rocking(
            dir.path(),
            &[
                "fragility",
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--eps",
                "0.7",
                "--pga",
                "0.5",
                "--from",
                s(&pipeline),
                "--outputs",
                s(&outputs),
                "--states",
                states,
                "--method",
                "mle",
                "--dispersion",
                "each",
                "--json",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        let v: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
        let f = &v["fragility"];
        let over = f["states"].as_array().unwrap().last().unwrap().clone();
        let p = v["points"][0]["probabilities"]
            .as_array()
            .map(|p| p.last().unwrap().as_f64().unwrap())
            .unwrap_or(f64::NAN);
        (over["mle"]["median"].as_f64().expect("an mle fit"), p)
    };
    let (alone, p_alone) = mle("overturned=overturned");
    let (beside, p_beside) = mle("light=0.2,overturned=overturned");
    assert_eq!(alone, beside);
    assert_eq!(p_alone.to_bits(), p_beside.to_bits());
}

/// A study of named blocks (`[[block]]`, as `pipelines/any-direction.toml`)
/// is no grid of p × ε: `--from` it was refused for every block as though
/// "too few records reach the state", with `--method mle` suggested, which
/// failed alike. Its own block is now answered by its own fits, the
/// states' of `--direct` through the same records and model (the same
/// runs, fitted by the one fit); any other block is refused as not a grid,
/// the study's blocks named.
#[test]
fn a_study_of_named_blocks_answers_for_its_own_blocks() {
    let dir = tempdir();
    let pipeline = write_pipeline(
        dir.path(),
        "named",
        "ids = [\"RSN1111_KOBE_NIS000\", \"RSN953_NORTHR_MUL009\", \"RSN1633_MANJIL_ABBAR--L\", \
         \"RSN848_LANDERS_CLW-LN\", \"RSN1148_KOCAELI_ARC000\", \"RSN169_IMPVALL_H-DLT262\", \
         \"RSN725_SUPERST_B-POE270\", \"RSN829_CAPEMEND_RIO360\"]\n[model]\nkind = \"linearized\"\n\
         [[block]]\nname = \"statue\"\nb = 0.2\nh = 0.9\neps = 0.9\n\
         [[block]]\nname = \"cabinet\"\nb = 0.3\nh = 1.0\neps = 0.75\n",
    );
    let outputs = dir.path().join("out");
    let out = rocking(dir.path(), &["run", s(&pipeline), "--outputs", s(&outputs)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let ask = |block: [&str; 3], extra: &[&str]| {
        let mut a = vec![
            "fragility",
            "--b",
            block[0],
            "--h",
            block[1],
            "--eps",
            block[2],
            "--from",
            s(&pipeline),
            "--outputs",
            s(&outputs),
            "--pga",
            "0.15,0.3,0.6",
            "--states",
            "rocking=0.1,overturned=overturned",
            "--json",
        ];
        a.extend(extra);
        rocking(dir.path(), &a)
    };
    for block in [["0.2", "0.9", "0.9"], ["0.3", "1.0", "0.75"]] {
        let (from, direct) = (
            ask(block, &[]),
            ask(block, &["--direct", "--if-not-lognormal", "lognormal"]),
        );
        assert!(from.status.success(), "{}", stderr(&from));
        assert!(direct.status.success(), "{}", stderr(&direct));
        let v = |o: &std::process::Output| -> serde_json::Value {
            serde_json::from_str(&stdout(o)).unwrap()
        };
        let (f, d) = (v(&from), v(&direct));
        for k in 0..3 {
            for j in 0..2 {
                let (a, b) = (
                    f["points"][k]["probabilities"][j].as_f64().unwrap(),
                    d["points"][k]["probabilities"][j].as_f64().unwrap(),
                );
                // The table keeps the median as its dimensionless form and
                // its logarithm is taken again: rounding alone.
                assert!(
                    (a - b).abs() < 1e-12,
                    "{block:?} level {k} state {j}: {a} against {b}"
                );
            }
        }
    }
    let other = ask(["0.25", "0.9", "0.9"], &[]);
    assert!(!other.status.success());
    let e = stderr(&other);
    assert!(
        e.contains("are not a grid of p × ε")
            && e.contains("statue at p = 2.824 1/s, ε = 0.900; cabinet at p = 2.654 1/s")
            && !e.contains("too few records"),
        "{e}"
    );
}

/// The records' own curve has no β: `fragility --json`, `risk`'s
/// fragility and its bootstrap band stated the fractile lognormal's β
/// beside it (the text said "no β"); they now state none. The median is
/// the curve's own: it passes 1/2 there. Asked for the lognormal anyway,
/// the same records give a β.
#[test]
fn the_records_curve_states_no_beta() {
    let dir = tempdir();
    let d = dir.path();
    let block = ["--b", "0.2", "--h", "0.9", "--eps", "0.85", "--direct"];
    let json = |args: &[&str]| -> serde_json::Value {
        let out = rocking(d, &[args, &block[..], &["--json"]].concat());
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_str(&stdout(&out)).unwrap()
    };
    let f = json(&["fragility", "--pga", "0.3"]);
    assert_eq!(f["fit"], "empirical", "{f}");
    assert!(f["beta"].is_null(), "{f}");
    // The curve passes 1/2 at the median it states.
    let median = f["median"].as_f64().unwrap().to_string();
    let at = json(&["fragility", "--pga", &median]);
    let half = at["points"][0]["probability"].as_f64().unwrap();
    assert!((half - 0.5).abs() < 1e-9, "{at}");
    let hazard = crate::util::root().join("records/hazard/synthetic-site.csv");
    let r = json(&["risk", "--hazard", s(&hazard), "--bootstrap", "200"]);
    assert_eq!(r["fragility"]["fit"], "empirical", "{r}");
    assert!(r["fragility"]["beta"].is_null(), "{r}");
    assert!(r["fragility"]["bootstrap"]["beta_band"].is_null(), "{r}");
    assert!(r["fragility"]["bootstrap"]["median_band"].is_array(), "{r}");
    let l = json(&[
        "fragility",
        "--pga",
        "0.3",
        "--if-not-lognormal",
        "lognormal",
    ]);
    assert_eq!(l["fit"], "fractile", "{l}");
    assert!(l["beta"].as_f64().is_some_and(|b| b > 0.0), "{l}");
    // The states' table says which fragility it is, above the lognormal
    // fits it shows for comparison; not where the lognormal is kept.
    let curve_line = "the fragility: the records' own curve";
    let text = |extra: &[&str]| {
        let args = [
            &[
                "fragility",
                "--pga",
                "0.3",
                "--states",
                "rocking=0.1,overturned=overturned",
            ][..],
            &block[..],
            extra,
        ]
        .concat();
        let out = rocking(d, &args);
        assert!(out.status.success(), "{}", stderr(&out));
        stdout(&out)
    };
    let curve = text(&[]);
    assert!(curve.contains(curve_line), "{curve}");
    let kept = text(&["--if-not-lognormal", "lognormal"]);
    assert!(!kept.contains(curve_line), "{kept}");
}

/// One block, one kind of fragility through both doors of a study: the
/// statue (ε = 0.85) whose capacities over the far-field records fail the
/// lognormal check is the records' own curve with `--direct`, and through
/// the study's tables (which carry its lognormal) the answer says so.
#[test]
fn a_study_says_when_its_lognormal_is_not_the_records_curve() {
    let dir = tempdir();
    let d = dir.path();
    let pipe = crate::util::write_pipeline(
        d,
        "statue",
        "sets = [\"far-field\"]\n[model]\nkind = \"auto\"\n[[block]]\nname = \"statue\"\n\
         b = 0.2\nh = 0.9\neps = 0.85\n",
    );
    let (pipe_s, out) = (pipe.to_str().unwrap(), d.join("out"));
    let out_s = out.to_str().unwrap();
    let run = rocking(d, &["run", pipe_s, "--outputs", out_s]);
    assert!(run.status.success(), "{}", stderr(&run));
    let rows: Vec<rocking::tables::reduce::LognormalRow> =
        rocking::tables::read(&out.join("statue/lognormal.parquet")).unwrap();
    assert!(rows[0].rejected_5pct, "{:?}", rows[0]);
    let ask = |extra: &[&str]| {
        let base = [
            "fragility",
            "--from",
            pipe_s,
            "--outputs",
            out_s,
            "--b",
            "0.2",
            "--h",
        ];
        let level: &[&str] = if extra.contains(&"--im") {
            &[]
        } else {
            &["--pga", "0.3"]
        };
        let args = [&base[..], &["0.9", "--eps", "0.85", "--json"], level, extra].concat();
        let o = rocking(d, &args);
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_str::<serde_json::Value>(&stdout(&o)).unwrap()
    };
    let said = |v: &serde_json::Value| {
        v["warnings"].as_array().unwrap().iter().any(|w| {
            w.as_str()
                .unwrap()
                .contains("the study's capacities of this block in ")
        })
    };
    let carried = ask(&[]);
    assert_eq!(carried["fit"], "fractile", "{carried}");
    assert!(said(&carried), "{carried}");
    // Its p as the study's table has it.
    let p = format!("{:.2e}", rows[0].p_value.unwrap());
    let text = carried["warnings"].to_string();
    // In another IM, the study's damage table checks the capacities in that
    // IM, as `--direct` does from its own runs: the two doors say the same,
    // with the same p (the statue's SA(0.2) capacities fail, its PGV pass).
    let mut failed = 0;
    for (im, at) in [("pgv", "30"), ("sa(0.2)", "0.4"), ("pgd", "5")] {
        let study = ask(&["--im", im, "--at", at]);
        let direct = ask(&["--im", im, "--at", at, "--direct"]);
        let rejected = direct["fit"] == "empirical";
        assert_eq!(said(&study), rejected, "{im}: {study} {direct}");
        if rejected {
            failed += 1;
            let p = format!("{:.2e}", direct["lognormal_p"].as_f64().unwrap());
            let text = study["warnings"].to_string();
            assert!(
                text.contains(&format!(
                    "in {im} fail the lognormal check (Lilliefors p = {p} "
                )),
                "{im} {p}: {text}"
            );
        }
    }
    assert!(failed >= 1, "an IM whose capacities fail the check");
    assert!(
        text.contains(&format!("Lilliefors p = {p} < 0.05")),
        "{p}: {text}"
    );
    let direct = ask(&["--direct"]);
    assert_eq!(direct["fit"], "empirical", "{direct}");
    assert!(!said(&direct), "{direct}");
    // Kept lognormal through the records, the doors agree on the kind.
    let kept = ask(&["--direct", "--if-not-lognormal", "lognormal"]);
    assert_eq!(kept["fit"], "fractile", "{kept}");
}

/// The heaviest state decides the kind of every state's fragility
/// (docs/MODEL.md §15): a lighter state whose capacities fail the
/// lognormal check was kept lognormal without a word, while asked alone it
/// is the records' curve. It is now said, with its p; asked alone, it is
/// its own curve (the block 0.2 m × 1 m, whose `rocking=0.1` capacities
/// over the far-field records fail the check at p ≈ 0.01 and whose
/// overturning capacities pass it).
#[test]
fn a_lighter_state_kept_lognormal_is_said() {
    let dir = tempdir();
    let d = dir.path();
    let hazard = crate::util::root().join("records/hazard/synthetic-site.csv");
    let ask = |states: &str| {
        let out = rocking(
            d,
            &[
                "risk",
                "--hazard",
                s(&hazard),
                "--b",
                "0.2",
                "--h",
                "1",
                "--direct",
                "--states",
                states,
                "--dispersion",
                "each",
                "--json",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        (
            serde_json::from_str::<serde_json::Value>(&stdout(&out)).unwrap(),
            stderr(&out),
        )
    };
    let (both, said) = ask("rocking=0.1,overturned=overturned");
    assert_ne!(both["method"], "empirical", "{both}");
    assert!(
        said.contains("the capacities of `rocking` (Lilliefors p = 0.0")
            && said.contains("but the heaviest state, `overturned`, decides"),
        "{said}"
    );
    let (alone, said) = ask("rocking=0.1");
    assert_eq!(alone["method"], "empirical", "{alone}");
    assert!(!said.contains("decides the kind"), "{said}");
}

/// A study whose grid has blocks without a fit in one method only: with a
/// strong cut (η ≥ 0.3) no record overturns the p = 1, ε = 0.7 block, so
/// it has no likelihood fit, and at p = 2 and 3 too few overturn for the
/// fractile fit. `--method mle` for a block in the cell p = 2–3,
/// ε = 0.7–0.9, whose four corners all have their likelihood fits, is the
/// bilinear value of those four in (ln p, ε), worked here from the table
/// (it was refused for the fractile fit's holes, with "try --method
/// mle"); the fractile fit is refused naming the corners without one.
#[test]
fn a_fit_is_carried_where_its_own_corners_have_one() {
    let dir = tempdir();
    let body = "sets = [\"far-field\"]\n[model]\nkind = \"linearized\"\n[blocks]\n\
                p = [1.0, 2.0, 3.0]\neps = [0.7, 0.9]\n[im]\ncount = 60\neta_min = 0.3\n";
    let pipeline = write_pipeline(dir.path(), "holes", body);
    let outputs = dir.path().join("out");
    let out = rocking(dir.path(), &["run", s(&pipeline), "--outputs", s(&outputs)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let table: Vec<DamageStateRow> = read(&outputs.join("holes"), "damage_states.parquet");
    // (ln of the dimensionless median, β) of the grid block (p, ε).
    let node = |p: f64, eps: f64, im: &str, method: FitMethod| {
        table
            .iter()
            .find(|r| {
                r.p == p
                    && r.eps == eps
                    && r.state == "overturned"
                    && r.im == im
                    && r.method == method
            })
            .and_then(|r| Some((r.median_dimensionless?.ln(), r.beta?)))
    };
    // The holes this test is about.
    assert!(node(1.0, 0.7, "pga", FitMethod::MaxLikelihood).is_none());
    assert!(node(2.0, 0.7, "pga", FitMethod::Fractile).is_none());
    let (alpha, p, eps) = (0.15_f64, 2.5_f64, 0.8);
    let (b, h) = (
        (9.80665 * alpha.sin() * 3.0 / (4.0 * p * p)).to_string(),
        (9.80665 * alpha.cos() * 3.0 / (4.0 * p * p)).to_string(),
    );
    let fragility = |method: &str, levels: &[&str]| {
        let mut args = vec![
            "fragility",
            "--b",
            &b,
            "--h",
            &h,
            "--eps",
            "0.8",
            "--from",
            s(&pipeline),
            "--outputs",
            s(&outputs),
            "--method",
            method,
            "--json",
        ];
        args.extend(levels);
        rocking(dir.path(), &args)
    };
    let answer = |out: std::process::Output| -> serde_json::Value {
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_str(&stdout(&out)).unwrap()
    };
    let v = answer(fragility("mle", &["--pga", "0.3"]));
    let (got_alpha, got_p) = (v["alpha_rad"].as_f64().unwrap(), v["p"].as_f64().unwrap());
    let tp = (got_p.ln() - 2f64.ln()) / (3f64.ln() - 2f64.ln());
    let te = (eps - 0.7) / (0.9 - 0.7);
    // The likelihood fit in `im` at the block, bilinear between the four
    // corners of its cell: (ln of the dimensionless median, β).
    let carried = |im: &str| {
        let at = |p, e| node(p, e, im, FitMethod::MaxLikelihood).unwrap();
        let (a, b, c, d) = (at(2.0, 0.7), at(2.0, 0.9), at(3.0, 0.7), at(3.0, 0.9));
        let mix = |f: fn((f64, f64)) -> f64| {
            let low = f(a) * (1.0 - te) + f(b) * te;
            let high = f(c) * (1.0 - te) + f(d) * te;
            low * (1.0 - tp) + high * tp
        };
        (mix(|x| x.0), mix(|x| x.1))
    };
    let (ln_median, beta) = carried("pga");
    let median = got_alpha * ln_median.exp();
    let got = v["median"].as_f64().unwrap();
    assert!((got / median - 1.0).abs() < 1e-12, "{got} against {median}");
    assert!((v["beta"].as_f64().unwrap() - beta).abs() < 1e-12);
    assert!((got_p - p).abs() < 1e-9 && (got_alpha - alpha).abs() < 1e-9);

    let refused = fragility("fractile", &["--pga", "0.3"]);
    assert!(!refused.status.success());
    let e = stderr(&refused);
    assert!(
        e.contains(
            "(p = 2.000 1/s, ε = 0.700; p = 2.000 1/s, ε = 0.900; p = 3.000 1/s, ε = 0.700)"
        ) && e.contains("try --method mle"),
        "{e}"
    );

    // In PGV the fractile fit comes from the IM table, whose holes refused
    // the likelihood fit too: p·PGV/(αg) carried as in PGA, in cm/s.
    let v = answer(fragility("mle", &["--im", "pgv", "--at", "30"]));
    let (ln_median, beta) = carried("pgv");
    let median = ln_median.exp() * 100.0 * got_alpha * 9.80665 / got_p;
    let got = v["median"].as_f64().unwrap();
    assert!(
        (got / median - 1.0).abs() < 1e-12,
        "{got} against {median} cm/s"
    );
    assert!((v["beta"].as_f64().unwrap() - beta).abs() < 1e-12);
}

/// A study's fragility in PGV (`fragility --im pgv --from`) of a grid block
/// some of whose records never overturn it: the paper's fractiles by hand,
/// those records beyond every level (+∞), not left out. It was the
/// moments of the records that overturn the block alone (the IM table's),
/// which put a block 16 of whose 44 records never overturn it at P = 0.85
/// at a PGV 55 % of the records overturn it at. A block with more than 16 %
/// of its records never overturning it has no fractile fit: refused, as
/// the regression refuses it in PGA, with the likelihood fit and --direct
/// named.
#[test]
fn a_study_s_pgv_fragility_counts_the_records_that_never_overturn() {
    let dir = tempdir();
    let body = "sets = [\"far-field\"]\n[model]\nkind = \"linearized\"\n[blocks]\n\
                p = [0.5, 1.0]\neps = [0.7]\n[im]\nspacing = \"log\"\ncount = 100\n\
                eta_max = 1.0\neta_min = 0.02\ntol = 1e-4\n";
    let pipeline = write_pipeline(dir.path(), "cens", body);
    let outputs = dir.path().join("out");
    let (pipe, outs) = (s(&pipeline), s(&outputs));
    let out = rocking(dir.path(), &["run", pipe, "--outputs", outs]);
    assert!(out.status.success(), "{}", stderr(&out));
    let caps: Vec<CapacityRow> = read(&outputs.join("cens"), "capacities.parquet");
    let ims: Vec<RecordImRow> = read(&outputs.join("cens"), "record_ims.parquet");
    let of = |id: &str, im: &str| {
        ims.iter()
            .find(|r| r.record_id == id && r.im == im)
            .unwrap()
            .value
    };
    // The grid's block of frequency `p` (1/s) at α = atan(1/4), its
    // fragility in PGV from the study (R = 3g/(4p²), b = h/4).
    let alpha = (0.25f64).atan();
    let fragility = |p: f64, json: bool| {
        let r = 3.0 * 9.80665 / (4.0 * p * p);
        let h = r / (1.0f64 + 1.0 / 16.0).sqrt();
        let (bs, hs) = (format!("{}", h / 4.0), format!("{h}"));
        let mut args = vec![
            "fragility",
            "--b",
            &bs,
            "--h",
            &hs,
            "--eps",
            "0.7",
            "--im",
            "pgv",
            "--at",
            "50",
            "--from",
            pipe,
            "--outputs",
            outs,
        ];
        if json {
            args.push("--json");
        }
        rocking(dir.path(), &args)
    };
    // The block p = 1 1/s: its records' PGV at capacity (cm/s), the
    // records that never overturn it at +∞.
    let mut pgv_c: Vec<f64> = caps
        .iter()
        .filter(|c| c.p == 1.0)
        .map(|c| match c.eta_c {
            Some(eta) => of(&c.record_id, "pgv") * (alpha / eta) / of(&c.record_id, "pga"),
            None => f64::INFINITY,
        })
        .collect();
    pgv_c.sort_by(f64::total_cmp);
    let never = pgv_c.iter().filter(|x| x.is_infinite()).count();
    assert!(
        never > 0 && never * 100 <= 16 * pgv_c.len(),
        "the test needs a block some, not too many, of whose records never overturn it: {never}"
    );
    let median = type7(&pgv_c, 0.5);
    let beta = 0.5 * (type7(&pgv_c, 0.84) / type7(&pgv_c, 0.16)).ln();
    let f = fragility(1.0, true);
    assert!(f.status.success(), "{}", stderr(&f));
    let v: serde_json::Value = serde_json::from_str(&stdout(&f)).unwrap();
    assert_eq!(v["fit"], "fractile");
    let (m, bt) = (v["median"].as_f64().unwrap(), v["beta"].as_f64().unwrap());
    assert!(
        (m / median - 1.0).abs() < 1e-9,
        "median {m} against {median} by hand"
    );
    assert!(
        (bt / beta - 1.0).abs() < 1e-9,
        "β {bt} against {beta} by hand"
    );
    // p = 0.5 1/s: more than 16 % of the records never overturn it.
    let never_half = caps
        .iter()
        .filter(|c| c.p == 0.5 && c.eta_c.is_none())
        .count();
    assert!(never_half * 100 > 16 * 44, "{never_half}");
    let f = fragility(0.5, false);
    assert!(!f.status.success());
    let e = stderr(&f);
    assert!(e.contains("--method mle") && e.contains("--direct"), "{e}");
}

/// Two states' fitted curves that cross below the PGA the block lifts at
/// (g·tan α), the heavier the less likely above it, cross where every
/// command counts P = 0: no warning (the statue's `large_rocking` and
/// `overturned` by the fractiles, at 0.205 g against 0.222 g). A crossing
/// above it, or one below it with the heavier state likelier above, is
/// still said. By hand from the fits printed: ln x* = (β_h ln θ_l − β_l ln
/// θ_h)/(β_h − β_l).
#[test]
fn curves_that_cross_where_nothing_moves_are_not_warned_of() {
    let dir = tempdir();
    let states = "rocking=0.1,large_rocking=0.5,overturned=overturned";
    let out = rocking(
        dir.path(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--eps",
            "housner",
            "--states",
            states,
            "--dispersion",
            "each",
            "--direct",
            "--pga",
            "0.3",
            "--json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    let f = &v["fragility"];
    let cut = (0.2f64 / 0.9).atan().tan();
    let fit = |i: usize| {
        let s = &f["states"][i]["fractile"];
        (s["median"].as_f64().unwrap(), s["beta"].as_f64().unwrap())
    };
    let phi = |x: f64, (m, b): (f64, f64)| crate::util::phi((x / m).ln() / b);
    let warned: Vec<&str> = f["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w.as_str())
        .filter(|w| w.contains("cross at"))
        .collect();
    let names = ["rocking", "large_rocking", "overturned"];
    let (mut below, mut said_all) = (0, 0);
    // Every pair, not only neighbours: `rocking` and `overturned` cross
    // where no neighbours do.
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let ((ml, bl), (mh, bh)) = (fit(i), fit(j));
        let x = ((bh * ml.ln() - bl * mh.ln()) / (bh - bl)).exp();
        let p = phi(x, (ml, bl));
        let inverted_above = phi(cut, (mh, bh)) > phi(cut, (ml, bl));
        let said = warned
            .iter()
            .any(|w| w.contains(&format!("`{}` and `{}` cross", names[i], names[j])));
        let expected = (x >= cut || inverted_above) && (1e-3..=1.0 - 1e-3).contains(&p);
        assert_eq!(
            said, expected,
            "{} and {} at {x} g: {warned:?}",
            names[i], names[j]
        );
        below += usize::from(x < cut && !inverted_above);
        said_all += usize::from(said);
    }
    assert_eq!(below, 1, "the statue has one pair crossing below the cut");
    assert_eq!(warned.len(), said_all, "{warned:?}");
}

/// Overturning from a study's regression and the lighter states from its
/// damage table: beyond the study's p the regression's law is extrapolated
/// while the table holds at its edge, and a lighter state's median can lie
/// above overturning's. Kept in order, it is lowered to it, and said, where
/// and only where `--dispersion each` (each state's own fit) shows it above.
#[test]
fn a_lighter_median_lowered_to_keep_the_states_in_order_is_said() {
    let dir = tempdir();
    let body = format!(
        "sets = [\"far-field\"]\n[model]\nkind = \"linearized\"\n[blocks]\n\
         p = [0.5, 1.0, 2.0, 5.0]\neps = [0.5, 0.7, 0.9]\n[damage]\nstates = \"{STATES}\"\n"
    );
    let pipeline = write_pipeline(dir.path(), "fitted", &body);
    let outputs = dir.path().join("out");
    let out = rocking(dir.path(), &["run", s(&pipeline), "--outputs", s(&outputs)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let run = |args: Vec<String>| {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        rocking(dir.path(), &args)
    };
    let names = ["light", "heavy", "overturned"];
    let mut lowered = 0;
    for (b, h) in [("0.02", "0.2"), ("0.03", "0.15"), ("0.5", "8.0")] {
        let mut args: Vec<String> = ["fragility", "--b", b, "--h", h, "--eps", "0.7", "--from"]
            .iter()
            .map(|x| x.to_string())
            .collect();
        args.extend(
            [s(&pipeline), "--outputs", s(&outputs), "--states", STATES]
                .iter()
                .map(|x| x.to_string()),
        );
        let (e, c) = (
            run([
                args.clone(),
                vec![
                    "--pga".into(),
                    "0.1".into(),
                    "--dispersion".into(),
                    "each".into(),
                    "--json".into(),
                ],
            ]
            .concat()),
            run([args, vec!["--pga".into(), "0.1".into(), "--json".into()]].concat()),
        );
        assert!(e.status.success() && c.status.success(), "{}", stderr(&c));
        let (e, c): (serde_json::Value, serde_json::Value) = (
            serde_json::from_str(&stdout(&e)).unwrap(),
            serde_json::from_str(&stdout(&c)).unwrap(),
        );
        let warned = c["fragility"]["warnings"].to_string();
        for (j, name) in names.iter().enumerate() {
            let median =
                |v: &serde_json::Value| v["fragility"]["states"][j]["fractile"]["median"].as_f64();
            let (own, kept) = (median(&e), median(&c));
            let said = warned.contains(&format!("the median of `{name}`"));
            assert_eq!(
                said,
                kept < own,
                "{b}×{h} {name}: {own:?} {kept:?} {warned}"
            );
            lowered += usize::from(said);
        }
    }
    assert!(lowered > 0, "a lighter median lowered");
}
