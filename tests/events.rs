//! `risk --gmf`: risk from OpenQuake's event-based ground-motion fields.
//! The rates against OpenQuake's own `event_based_damage` on the same
//! fields with the tool's exported fragility, and against `rocking risk` on
//! the same run's hazard curves; the count distribution against a Monte
//! Carlo written here on a hand-made field set; bad folders refused naming
//! file, line and column.

use std::fs;
use std::path::Path;
use std::process::Command;

use serde_json::Value;

use crate::util::{rocking, root, stderr, tempdir};

fn json(out: &std::process::Output) -> Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

/// A hand-made field set: `events` events at two sites, PGA of event e at
/// site s given by `pga(e, s)` (every event written at every site).
fn fields(dir: &Path, events: usize, pga: impl Fn(usize, usize) -> f64) {
    fs::create_dir_all(dir).unwrap();
    let meta = "#,,,\"generated_by='OpenQuake engine 3.26.2'\"\n";
    fs::write(
        dir.join("sitemesh_1.csv"),
        format!("{meta}custom_site_id,lon,lat\naaa,0.0,0.0\nbbb,0.1,0.0\n"),
    )
    .unwrap();
    let mut ev = format!("{meta}event_id,rup_id,rlz_id,year,ses_id\n");
    let mut gmf = format!("{meta}event_id,gmv_PGA,custom_site_id\n");
    for e in 0..events {
        ev.push_str(&format!("{e},{e},0,1,1\n"));
        for (s, id) in ["aaa", "bbb"].iter().enumerate() {
            gmf.push_str(&format!("{e},{:.6E},{id}\n", pga(e, s)));
        }
    }
    fs::write(dir.join("events_1.csv"), ev).unwrap();
    fs::write(dir.join("gmf-data_1.csv"), gmf).unwrap();
}

/// Three blocks, one event at two sites: each block's probability at each
/// site is its fragility's (read back from the answer), and the count
/// distribution of the three is exact: under `independent` a
/// Poisson-binomial, checked against a Monte Carlo of 400,000 draws written
/// here (3σ), and under `same-record` the k-th largest probability.
#[test]
fn the_count_distribution_is_a_monte_carlo_by_hand() {
    let dir = tempdir();
    let d = dir.path();
    fields(&d.join("g"), 1, |_, s| [0.45, 0.6][s]);
    fs::write(
        d.join("inv.csv"),
        "name,b,h,eps\nstatue,0.2,0.9,\ncabinet,0.25,1.0,\nvase,0.1,0.5,\n",
    )
    .unwrap();
    for (together, mc) in [("independent", true), ("same-record", false)] {
        let v = json(&rocking(
            d,
            &[
                "risk",
                "--gmf",
                "g",
                "--eff-years",
                "100",
                "--inventory",
                "inv.csv",
                "--together",
                together,
                "--json",
            ],
        ));
        assert_eq!(v["eff_years_from"], "--eff-years");
        // Each block's P at each site: its rate × 100 years (one event).
        let p: Vec<[f64; 2]> = v["blocks"]
            .as_array()
            .unwrap()
            .iter()
            .map(|b| {
                let s = b["sites"].as_array().unwrap();
                [0, 1].map(|k| s[k]["annual_rate"].as_f64().unwrap() * 100.0)
            })
            .collect();
        for site in 0..2 {
            let ps: Vec<f64> = p.iter().map(|q| q[site]).collect();
            let rates: Vec<f64> = v["counts"][site]["rate_at_least"]
                .as_array()
                .unwrap()
                .iter()
                .map(|r| r.as_f64().unwrap() * 100.0)
                .collect();
            assert_eq!(rates.len(), 4);
            if mc {
                // A Monte Carlo: each item falls on its own uniform draw.
                let mut state = 0x2545F4914F6CDD1Du64;
                let mut uniform = || {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    (state >> 11) as f64 / (1u64 << 53) as f64
                };
                let n = 400_000;
                let mut at_least = [0usize; 4];
                for _ in 0..n {
                    let k = ps.iter().filter(|&&q| uniform() < q).count();
                    for c in at_least.iter_mut().take(k + 1) {
                        *c += 1;
                    }
                }
                for k in 0..4 {
                    let f = at_least[k] as f64 / n as f64;
                    let sd = (f * (1.0 - f) / n as f64).sqrt().max(1e-6);
                    assert!(
                        (f - rates[k]).abs() < 3.0 * sd + 1e-12,
                        "site {site} k {k}: {f} vs {}",
                        rates[k]
                    );
                }
            } else {
                let mut sorted = ps.clone();
                sorted.sort_by(|a, b| b.total_cmp(a));
                for k in 1..4 {
                    assert!(
                        (rates[k] - sorted[k - 1]).abs() < 1e-12,
                        "site {site} k {k}"
                    );
                }
            }
            let expected = v["counts"][site]["expected_per_event"].as_f64().unwrap();
            assert!((expected - ps.iter().sum::<f64>()).abs() < 1e-12);
        }
    }
}

/// `--vector` on a floor cut at the ground's uplift PGA, where the scalar
/// rate beside it cuts nothing (the floor amplifies: the block feels more
/// than the ground's peak): every event below g·tan α dropped from the one
/// rate and counted in the other. Fields whose every PGA lies below the
/// statue's uplift PGA (0.2/0.9 g): on the ground both rates are 0 (the
/// block cannot lift); on a 0.5 s floor with Γφ = 1.3 both count them.
#[test]
fn the_vector_rate_on_a_floor_cuts_where_the_scalar_rate_does() {
    let dir = tempdir();
    let d = dir.path();
    let meta = "#,,,\"generated_by='OpenQuake engine 3.26.2'\"\n";
    let g = d.join("g");
    fs::create_dir_all(&g).unwrap();
    fs::write(
        g.join("sitemesh_1.csv"),
        format!("{meta}custom_site_id,lon,lat\naaa,0.0,0.0\nbbb,0.1,0.0\n"),
    )
    .unwrap();
    let (mut ev, mut gmf) = (
        format!("{meta}event_id,rup_id,rlz_id,year,ses_id\n"),
        format!("{meta}event_id,gmv_PGA,gmv_PGV,custom_site_id\n"),
    );
    for e in 0..30 {
        ev.push_str(&format!("{e},{e},0,1,1\n"));
        for (s, id) in ["aaa", "bbb"].iter().enumerate() {
            let pga = 0.10 + 0.0035 * e as f64 + 0.002 * s as f64;
            assert!(pga < 0.2 / 0.9);
            let pgv = pga * (40.0 + 3.0 * e as f64);
            gmf.push_str(&format!("{e},{pga:.6E},{pgv:.6E},{id}\n"));
        }
    }
    fs::write(g.join("events_1.csv"), ev).unwrap();
    fs::write(g.join("gmf-data_1.csv"), gmf).unwrap();
    let records = crate::util::bundled_records();
    let rates = |floor: Option<&str>| -> Vec<(f64, f64)> {
        let mut a = vec![
            "risk",
            "--gmf",
            "g",
            "--eff-years",
            "100",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--vector",
            "--json",
            "--records",
        ];
        a.push(records.to_str().unwrap());
        if let Some(f) = floor {
            a.extend(["--floor", f]);
        }
        let v = json(&rocking(d, &a));
        v["blocks"][0]["sites"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| {
                let rate = |k: &str| s[k].as_f64().unwrap();
                (rate("annual_rate"), rate("annual_rate_vector"))
            })
            .collect()
    };
    for (scalar, vector) in rates(None) {
        assert_eq!((scalar, vector), (0.0, 0.0));
    }
    for (scalar, vector) in rates(Some("0.5,0.05,1.3")) {
        assert!(scalar > 1e-3, "the floor lifts the block: {scalar}");
        // Two fits of one block's runs (PGA alone, PGA with PGV/PGA): the
        // same order, not the same number.
        assert!(
            vector > 0.2 * scalar && vector < 5.0 * scalar,
            "vector {vector} against scalar {scalar}"
        );
    }
}

/// Bad folders and files are refused, naming the file, line and column.
#[test]
fn bad_fields_are_refused_naming_file_line_and_column() {
    let dir = tempdir();
    let d = dir.path();
    fields(&d.join("g"), 3, |e, _| 0.1 * (e + 1) as f64);
    let run = |args: &[&str]| {
        let mut a = vec!["risk", "--gmf", "g", "--b", "0.2", "--h", "0.9"];
        a.extend_from_slice(args);
        rocking(d, &a)
    };
    let no_time = run(&[]);
    assert!(
        stderr(&no_time).contains("give --eff-years"),
        "{}",
        stderr(&no_time)
    );
    let gmf = d.join("g/gmf-data_1.csv");
    let text = fs::read_to_string(&gmf).unwrap();
    fs::write(&gmf, text.replacen("2.000000E-1", "abc", 1)).unwrap();
    let bad = run(&["--eff-years", "10"]);
    assert!(
        stderr(&bad).contains("gmf-data_1.csv:5, column `gmv_PGA`: `abc` is not a number"),
        "{}",
        stderr(&bad)
    );
    fs::write(&gmf, text.replace(",bbb", ",zzz")).unwrap();
    let site = run(&["--eff-years", "10"]);
    assert!(
        stderr(&site).contains("site `zzz` is not in the site mesh"),
        "{}",
        stderr(&site)
    );
    fs::write(&gmf, &text).unwrap();
    let tree = run(&["--eff-years", "10", "--tree", "restitution-tests"]);
    assert!(
        stderr(&tree).contains("--tree and --bootstrap are for hazard curves"),
        "{}",
        stderr(&tree)
    );
    fs::write(&gmf, text.replacen(",aaa\n", ",bbb\n", 1)).unwrap();
    let twice = run(&["--eff-years", "10"]);
    assert!(
        stderr(&twice).contains("event 0 at site `bbb` is written twice (lines 3 and 4)"),
        "{}",
        stderr(&twice)
    );
    // A file cut short mid-line named the last site `` as unknown.
    fs::write(&gmf, &text[..text.len() - 8]).unwrap();
    let cut = run(&["--eff-years", "10"]);
    assert!(
        stderr(&cut).contains("gmf-data_1.csv:8: 2 cells where the header has 3 columns"),
        "{}",
        stderr(&cut)
    );
    fs::write(&gmf, &text).unwrap();
    let im = run(&["--eff-years", "10", "--im", "pgv"]);
    assert!(
        stderr(&im).contains("the fields have no PGV"),
        "{}",
        stderr(&im)
    );
}

/// OpenQuake's event-based source model for the engine test: a point source
/// of M 5.0 and 5.1 (2.5 events a year), BooreAtkinson2008 for PGA and PGV.
const SOURCE: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<nrml xmlns="http://openquake.org/xmlns/nrml/0.4" xmlns:gml="http://www.opengis.net/gml">
<sourceModel name="point">
<pointSource id="1" name="point" tectonicRegion="active shallow crust">
<pointGeometry><gml:Point><gml:pos>0.0 0.0</gml:pos></gml:Point>
<upperSeismoDepth>0.0</upperSeismoDepth><lowerSeismoDepth>10.0</lowerSeismoDepth></pointGeometry>
<magScaleRel>PeerMSR</magScaleRel><ruptAspectRatio>1.0</ruptAspectRatio>
<incrementalMFD minMag="5.0" binWidth="0.1"><occurRates>1.0 1.5</occurRates></incrementalMFD>
<nodalPlaneDist><nodalPlane probability="1.0" strike="0.0" dip="90.0" rake="0.0"/></nodalPlaneDist>
<hypoDepthDist><hypoDepth probability="0.6" depth="4.0"/><hypoDepth probability="0.4" depth="5.0"/></hypoDepthDist>
</pointSource>
</sourceModel>
</nrml>
"#;

const SOURCE_LT: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<nrml xmlns:gml="http://www.opengis.net/gml" xmlns="http://openquake.org/xmlns/nrml/0.4">
<logicTree logicTreeID="lt1"><logicTreeBranchingLevel branchingLevelID="bl1">
<logicTreeBranchSet uncertaintyType="sourceModel" branchSetID="bs1">
<logicTreeBranch branchID="b1"><uncertaintyModel>source_model.xml</uncertaintyModel><uncertaintyWeight>1.0</uncertaintyWeight></logicTreeBranch>
</logicTreeBranchSet></logicTreeBranchingLevel></logicTree>
</nrml>
"#;

const GSIM_LT: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<nrml xmlns:gml="http://www.opengis.net/gml" xmlns="http://openquake.org/xmlns/nrml/0.4">
<logicTree logicTreeID="lt1"><logicTreeBranchingLevel branchingLevelID="bl1">
<logicTreeBranchSet uncertaintyType="gmpeModel" branchSetID="bs1" applyToTectonicRegionType="active shallow crust">
<logicTreeBranch branchID="b1"><uncertaintyModel>BooreAtkinson2008</uncertaintyModel><uncertaintyWeight>1.0</uncertaintyWeight></logicTreeBranch>
</logicTreeBranchSet></logicTreeBranchingLevel></logicTree>
</nrml>
"#;

/// Three sites (lon, lat) of the engine test.
const SITES: [(f64, f64); 3] = [(0.0, -0.2), (0.0, 0.05), (0.1, 0.0)];

/// OpenQuake's `event_based_damage` on a point source (2000 years, 4,900
/// events, spatially correlated fields by JB2009) with the statue's
/// exported NRML fragility, one statue at each of three sites: its rate of
/// overturning per asset (`aggrisk-id`, float32 with 6 digits) equals `risk
/// --gmf` on the fields it wrote, to its printed rounding (1e-5 relative).
/// And against `rocking risk` on the same run's hazard curves (PGA, 40
/// IMLs): both integrate the same catalogue, the curve interpolating its
/// empirical exceedance between IMLs, so they differ by less than the
/// catalogue's sampling error 1/√(λT) where λT, the expected number of
/// overturning events in the catalogue, is 5 or more.
#[test]
fn openquake_event_based_damage_agrees_with_risk_from_its_fields() {
    let Some(venv) = crate::engines::engines() else {
        return;
    };
    let dir = tempdir();
    let d = dir.path();
    let job = d.join("job");
    let out = rocking(
        d,
        &[
            "export", "--format", "nrml", "--b", "0.2", "--h", "0.9", "--out", "job",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    fs::write(job.join("source_model.xml"), SOURCE).unwrap();
    fs::write(job.join("source_model_logic_tree.xml"), SOURCE_LT).unwrap();
    fs::write(job.join("gsim_logic_tree.xml"), GSIM_LT).unwrap();
    let assets: String = SITES
        .iter()
        .enumerate()
        .map(|(k, (lon, lat))| {
            format!(
                "    <asset id=\"a{k}\" number=\"1\" taxonomy=\"b0.2_h0.9\"><location lon=\"{lon}\" lat=\"{lat}\"/><costs><cost type=\"contents\" value=\"1\"/></costs></asset>\n"
            )
        })
        .collect();
    fs::write(
        job.join("exposure_model.xml"),
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<nrml xmlns=\"http://openquake.org/xmlns/nrml/0.5\">\n<exposureModel id=\"museum\" category=\"buildings\" taxonomySource=\"rocking\">\n  <description>statues</description>\n  <conversions><costTypes><costType name=\"contents\" type=\"per_asset\" unit=\"block\"/></costTypes></conversions>\n  <tagNames/>\n  <assets>\n{assets}  </assets>\n</exposureModel>\n</nrml>\n"
        ),
    )
    .unwrap();
    fs::write(
        job.join("job.ini"),
        "[general]\ndescription = rocking: event-based damage\ncalculation_mode = event_based_damage\n\
         ses_seed = 1066\n\n[exposure]\nexposure_file = exposure_model.xml\naggregate_by = id\n\n\
         [fragility]\ncontents_fragility_file = fragility_model.xml\n\n[logic_tree]\n\
         number_of_logic_tree_samples = 0\n\n[erf]\nwidth_of_mfd_bin = 1.0\n\n[site_params]\n\
         reference_vs30_type = measured\nreference_vs30_value = 400.0\n\
         reference_depth_to_2pt5km_per_sec = 2.5\nreference_depth_to_1pt0km_per_sec = 50.0\n\n\
         [calculation]\nsource_model_logic_tree_file = source_model_logic_tree.xml\n\
         gsim_logic_tree_file = gsim_logic_tree.xml\ninvestigation_time = 1.0\n\
         intensity_measure_types_and_levels = {\"PGA\": logscale(0.005, 3.0, 40), \"PGV\": logscale(0.5, 300, 40)}\n\
         truncation_level = 3.0\nmaximum_distance = 200.0\nminimum_intensity = {\"PGA\": 0.001, \"PGV\": 0.01}\n\n\
         [event_based_params]\nses_per_logic_tree_path = 2000\nground_motion_correlation_model = JB2009\n\
         ground_motion_correlation_params = {\"vs30_clustering\": False}\n\n[output]\n\
         hazard_curves_from_gmfs = true\nmean = true\nground_motion_fields = true\n",
    )
    .unwrap();
    let data = d.join("oqdata");
    fs::create_dir_all(&data).unwrap();
    let oq = Command::new(venv.join("bin/oq"))
        .args(["run", "job.ini", "--exports", "csv"])
        .current_dir(&job)
        .env("CI", "true")
        .env("OQ_DISTRIBUTE", "no")
        .env("NUMBA_DISABLE_JIT", "1")
        .env("OQ_DATADIR", &data)
        .output()
        .unwrap();
    assert!(
        oq.status.success(),
        "oq run failed:\n{}\n{}",
        String::from_utf8_lossy(&oq.stdout),
        String::from_utf8_lossy(&oq.stderr)
    );
    let file = |prefix: &str| {
        fs::read_dir(&job)
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|p| p.file_name().unwrap().to_string_lossy().starts_with(prefix))
            .unwrap_or_else(|| panic!("oq wrote no {prefix}"))
    };
    // OpenQuake's rate of overturning per asset.
    let agg = fs::read_to_string(file("aggrisk-id")).unwrap();
    let oq_rate = |asset: &str| -> f64 {
        let line = agg
            .lines()
            .find(|l| l.split(',').nth(1) == Some(asset))
            .unwrap();
        line.split(',').nth(3).unwrap().parse().unwrap()
    };
    let v = json(&rocking(
        d,
        &["risk", "--gmf", "job", "--b", "0.2", "--h", "0.9", "--json"],
    ));
    assert_eq!(v["eff_years"].as_f64(), Some(2000.0));
    assert!(v["events"].as_u64().unwrap() > 4000);
    let sites = v["blocks"][0]["sites"].as_array().unwrap();
    let curves = json(&rocking(
        d,
        &[
            "risk",
            "--hazard",
            file("hazard_curve-mean-PGA").to_str().unwrap(),
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--json",
        ],
    ));
    for (k, (lon, lat)) in SITES.iter().enumerate() {
        let s = sites
            .iter()
            .find(|s| {
                (s["lon"].as_f64().unwrap() - lon).abs() < 1e-9
                    && (s["lat"].as_f64().unwrap() - lat).abs() < 1e-9
            })
            .unwrap();
        let ours = s["annual_rate"].as_f64().unwrap();
        let theirs = oq_rate(&format!("a{k}"));
        assert!(
            (ours / theirs - 1.0).abs() < 1e-5,
            "site {k}: {ours} vs OpenQuake's {theirs}"
        );
        let c = curves["sites"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| {
                (c["lon"].as_f64().unwrap() - lon).abs() < 1e-9
                    && (c["lat"].as_f64().unwrap() - lat).abs() < 1e-9
            })
            .unwrap()["annual_rate"]
            .as_f64()
            .unwrap();
        let expected_events = ours * 2000.0;
        eprintln!("site {k}: from the fields {ours:.4e}, OpenQuake {theirs:.4e}, from the curves {c:.4e} (λT = {expected_events:.1})");
        if expected_events >= 5.0 {
            let tol = 1.0 / expected_events.sqrt();
            assert!(
                (c / ours - 1.0).abs() < tol,
                "site {k}: curves {c} vs fields {ours} (tolerance {tol})"
            );
        }
    }
}

/// `--states` over the fields: each state's rate at each site is Σ over
/// events of Φ(ln(PGA/m)/β) ÷ the effective time, m and β the state's
/// lognormal as `fragility --states` states it (Φ written here), 0 below
/// the uplift PGA; and the heaviest state's rate is overturning's.
#[test]
fn damage_states_over_the_fields_are_their_lognormals_summed() {
    let dir = tempdir();
    let d = dir.path();
    let pgas = |e: usize, s: usize| 0.05 + 0.9 * ((e * 7 + s * 3) % 10) as f64 / 10.0;
    fields(&d.join("g"), 20, pgas);
    let states = "rocking=0.1,large_rocking=0.5,overturned=overturned";
    let block = ["--b", "0.2", "--h", "0.9", "--direct", "--states", states];
    let mut args = vec!["risk", "--gmf", "g", "--eff-years", "50", "--json"];
    args.extend_from_slice(&block);
    let v = json(&rocking(d, &args));
    let mut fargs = vec!["fragility", "--pga", "0.3", "--json"];
    fargs.extend_from_slice(&block);
    let f = json(&rocking(d, &fargs));
    let uplift = 0.2 / 0.9;
    let b = &v["blocks"][0];
    for (j, st) in f["fragility"]["states"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
    {
        let (m, beta) = (
            st["fractile"]["median"].as_f64().unwrap(),
            st["fractile"]["beta"].as_f64().unwrap(),
        );
        for s in 0..2 {
            let want: f64 = (0..20)
                .map(|e| {
                    // The field file's PGA as printed (6 significant digits).
                    let x: f64 = format!("{:.6E}", pgas(e, s)).parse().unwrap();
                    if x < uplift {
                        0.0
                    } else {
                        crate::util::phi((x / m).ln() / beta)
                    }
                })
                .sum::<f64>()
                / 50.0;
            let got = b["states"][j]["annual_rates"][s].as_f64().unwrap();
            assert!(
                (got - want).abs() <= 1e-10 * want.max(1e-12),
                "state {j} site {s}: {got} vs {want}"
            );
        }
    }
    for s in 0..2 {
        assert_eq!(
            b["states"][2]["annual_rates"][s],
            b["sites"][s]["annual_rate"]
        );
    }
}

/// The effective time from the job (its `ses_per_logic_tree_path`
/// defaulting to 1, as OpenQuake's), realisations of unequal weights
/// refused (their events cannot be pooled), and a hazard file's options
/// refused with the fields.
#[test]
fn the_effective_time_and_realisations() {
    let dir = tempdir();
    let d = dir.path();
    fields(&d.join("g"), 4, |e, _| 0.3 + 0.1 * e as f64);
    let run = |extra: &[&str]| {
        let mut a = vec!["risk", "--gmf", "g", "--b", "0.2", "--h", "0.9", "--json"];
        a.extend_from_slice(extra);
        rocking(d, &a)
    };
    fs::write(
        d.join("g/job.ini"),
        "[calculation]\ninvestigation_time = 25.0\n",
    )
    .unwrap();
    let v = json(&run(&[]));
    assert_eq!(v["eff_years"].as_f64(), Some(25.0));
    fs::write(
        d.join("g/job.ini"),
        "investigation_time = 25.0\nses_per_logic_tree_path = 4 # sets\n",
    )
    .unwrap();
    assert_eq!(json(&run(&[]))["eff_years"].as_f64(), Some(100.0));
    let clash = run(&["--eff-years", "50"]);
    assert!(
        stderr(&clash).contains("--eff-years 50, but"),
        "{}",
        stderr(&clash)
    );
    fs::write(d.join("g/job.ini"), "investigation_time = x\n").unwrap();
    assert!(stderr(&run(&[])).contains("job.ini: `investigation_time = x` is not a number"));
    fs::write(d.join("g/job.ini"), "investigation_time = 1\n").unwrap();
    fs::write(
        d.join("g/realizations_1.csv"),
        "#,,\"x\"\nrlz_id,branch_path,weight\n0,A,0.6\n1,B,0.4\n",
    )
    .unwrap();
    let unequal = run(&[]);
    assert!(
        stderr(&unequal).contains("the realisations have unequal weights (0.6, 0.4)"),
        "{}",
        stderr(&unequal)
    );
    fs::write(
        d.join("g/realizations_1.csv"),
        "rlz_id,branch_path,weight\n0,A,0.5\n1,B,0.5\n",
    )
    .unwrap();
    assert_eq!(json(&run(&[]))["eff_years"].as_f64(), Some(2.0));
    let site = run(&["--site", "0"]);
    assert!(
        stderr(&site).contains("--site and --component are a hazard file's"),
        "{}",
        stderr(&site)
    );
    let together = rocking(
        d,
        &[
            "risk",
            "--hazard",
            "x.csv",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--together",
            "independent",
        ],
    );
    assert!(
        stderr(&together).contains("are for --gmf"),
        "{}",
        stderr(&together)
    );
}

/// A job.ini that is not the fields' calculation's set every rate by its
/// samples without a cross-check: 10 samples over a calculation listing 2
/// realisations gave rates a fifth of the job's own. That is warned of
/// (the rates still the job's, as OpenQuake's effective time is), events
/// naming a realisation past the job's samples or past those listed are
/// refused, and a job that agrees says nothing.
#[test]
fn a_job_ini_of_another_calculation_is_caught() {
    let dir = tempdir();
    let d = dir.path();
    fields(&d.join("g"), 4, |e, _| 0.3 + 0.1 * e as f64);
    let run = || {
        rocking(
            d,
            &["risk", "--gmf", "g", "--b", "0.2", "--h", "0.9", "--json"],
        )
    };
    fs::write(
        d.join("g/realizations_1.csv"),
        "rlz_id,branch_path,weight\n0,A,0.5\n1,B,0.5\n",
    )
    .unwrap();
    let job = |samples: u32| {
        let text = format!("investigation_time = 1\nnumber_of_logic_tree_samples = {samples}\n");
        fs::write(d.join("g/job.ini"), text).unwrap();
    };
    job(2);
    let agrees = run();
    assert_eq!(json(&agrees)["eff_years"].as_f64(), Some(2.0));
    assert!(
        !stderr(&agrees).contains("realisations"),
        "{}",
        stderr(&agrees)
    );
    job(10);
    let stale = run();
    assert_eq!(json(&stale)["eff_years"].as_f64(), Some(10.0));
    assert!(
        stderr(&stale).contains("samples 10 realisations (`number_of_logic_tree_samples`), but")
            && stderr(&stale).contains("realizations_1.csv lists 2"),
        "{}",
        stderr(&stale)
    );
    // The events of realisation 2: past the 2 listed, and past 2 samples.
    let events = fs::read_to_string(d.join("g/events_1.csv")).unwrap();
    fs::write(
        d.join("g/events_1.csv"),
        events.replace("3,3,0,1,1", "3,3,2,1,1"),
    )
    .unwrap();
    let past = run();
    assert!(
        stderr(&past).contains("the events name realisation 2, but it lists 2 (0 to 1)"),
        "{}",
        stderr(&past)
    );
    // A job of fewer event sets than the events are in: its time, and
    // every rate, would be off by as much (the bundled fields' 2000 sets
    // under a job of 20 gave 8.26 a year for 0.0826).
    let g = root().join("records/gmf");
    let stale = d.join("stale");
    fs::create_dir(&stale).unwrap();
    for f in [
        "gmf-data_239.csv",
        "events_239.csv",
        "sitemesh_239.csv",
        "realizations_239.csv",
    ] {
        fs::copy(g.join(f), stale.join(f)).unwrap();
    }
    let ini = fs::read_to_string(g.join("job.ini")).unwrap();
    assert!(ini.contains("ses_per_logic_tree_path = 2000"));
    for (sets, refused) in [("20", true), ("2000", false)] {
        let text = ini.replace("= 2000", &format!("= {sets}"));
        fs::write(stale.join("job.ini"), text).unwrap();
        let out = rocking(
            d,
            &[
                "risk", "--gmf", "stale", "--b", "0.2", "--h", "0.9", "--json",
            ],
        );
        assert_eq!(!out.status.success(), refused, "{sets}: {}", stderr(&out));
        if refused {
            let e = stderr(&out);
            assert!(
                e.contains("the events are in event sets up to 2000, but")
                    && e.contains("`ses_per_logic_tree_path = 20`")
                    && e.contains("100× too high"),
                "{e}"
            );
        }
    }
    fs::remove_file(d.join("g/realizations_1.csv")).unwrap();
    job(2);
    let past = run();
    assert!(
        stderr(&past).contains("the events name realisation 2, but")
            && stderr(&past)
                .contains("samples 2 (`number_of_logic_tree_samples`, realisations 0 to 1)"),
        "{}",
        stderr(&past)
    );
}

/// Fields of PGA in cm/s² read as g gave every site 2.45 overturnings a
/// year without a word, where the hazard's IMLs in cm/s² are warned of.
/// The fields are held to the same rule: fields of 0.1–0.5 g are not
/// warned of, the same in gal are, with their median and largest.
#[test]
fn fields_in_gal_are_warned_of_as_a_hazards_are() {
    let dir = tempdir();
    let d = dir.path();
    let pga = |e: usize, s: usize| 0.1 + 0.1 * ((e + s) % 5) as f64;
    fields(&d.join("g"), 20, pga);
    fields(&d.join("gal"), 20, |e, s| 981.0 * pga(e, s));
    for (folder, warned) in [("g", false), ("gal", true)] {
        let v = json(&rocking(
            d,
            &[
                "risk",
                "--gmf",
                folder,
                "--eff-years",
                "1000",
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--json",
            ],
        ));
        let w = v["warnings"].to_string();
        assert_eq!(
            w.contains("are they in cm/s² (gal)?"),
            warned,
            "{folder}: {w}"
        );
        if warned {
            assert!(
                w.contains("a median of 294.3 g where written, and reaches 490.5 g"),
                "{w}"
            );
        }
    }
}

/// Without a job.ini, `--eff-years` is held to the events' own years (each
/// event's year lies within its realisation's investigation_time ×
/// ses_per_logic_tree_path, so the effective time is at least the largest):
/// a time of 20 years over events up to year 395 made every rate 20× too
/// high, silently. Events of several realisations without their weights
/// are pooled equally, and said so.
#[test]
fn an_effective_time_shorter_than_the_events_years_is_refused() {
    let dir = tempdir();
    let d = dir.path();
    fields(&d.join("g"), 4, |e, _| 0.1 * (e + 1) as f64);
    let events = d.join("g/events_1.csv");
    let text = fs::read_to_string(&events).unwrap();
    // Years 1, 101, 201, 395; realisations 0 and 1.
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    for (k, year) in [1, 101, 201, 395].iter().enumerate() {
        lines[2 + k] = format!("{k},{k},{},{year},1", k % 2);
    }
    fs::write(&events, lines.join("\n") + "\n").unwrap();
    let run = |t: &str| {
        rocking(
            d,
            &[
                "risk",
                "--gmf",
                "g",
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--eff-years",
                t,
                "--json",
            ],
        )
    };
    let short = run("20");
    assert!(!short.status.success());
    let e = stderr(&short);
    assert!(
        e.contains("has events in year 395") && e.contains("2 realisation(s)"),
        "{e}"
    );
    let enough = run("800");
    assert!(enough.status.success(), "{}", stderr(&enough));
    let v = json(&enough);
    let said = v["warnings"].to_string();
    assert!(
        said.contains("of 2 realisations and no realizations_*.csv"),
        "{said}"
    );
}
