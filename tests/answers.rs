//! Answers that once contradicted each other or physics, each found by a
//! hostile probe of the newer commands and each named after its fault:
//! hazard files that meant something else, exports an engine could not
//! read or that mixed two runs, records and periods that never finished,
//! and messages that named the wrong thing. (The agreement of the commands
//! is in `risk` and `damage`, the engines' in `engines`.)

use std::fs;
use std::path::Path;

use serde_json::Value;

use crate::util::{at2_text, bundled_records, rocking, root, stderr, stdout, tempdir};

fn json(out: &std::process::Output) -> Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout).unwrap()
}

fn fails(dir: &Path, args: &[&str], what: &str) -> String {
    let out = rocking(dir, args);
    assert!(!out.status.success(), "{args:?} succeeded");
    let e = stderr(&out);
    assert!(e.contains(what), "{args:?}: {e}");
    e
}

const KOBE: &str = "far-field/RSN1111_KOBE_NIS000.AT2";

/// An OpenQuake hazard CSV in PGA with `imls` and one row per site
/// (lon, lat, poes).
fn openquake(path: &Path, imt: &str, imls: &[&str], rows: &[(&str, &str, &[&str])]) {
    let mut text = format!(
        "#,,,,\"generated_by='test', start_date='2026-01-01', checksum=0, kind='mean', \
         investigation_time=50.0, imt='{imt}'\"\nlon,lat,depth"
    );
    for a in imls {
        text.push_str(&format!(",poe-{a}"));
    }
    text.push('\n');
    for (lon, lat, poes) in rows {
        text.push_str(&format!("{lon},{lat},0.0,{}\n", poes.join(",")));
    }
    fs::write(path, text).unwrap();
}

/// `ims --period 1e-9` never ended (time grows as 1/T) and the keys of
/// `sa_g` were Rust's debug text (`"1000000000.0"`, `"1e-6"`): a period
/// below Δt/250 is refused at once, and keys are plain decimals.
#[test]
fn a_tiny_period_is_refused_and_sa_keys_are_plain_decimals() {
    let dir = tempdir();
    let kobe = bundled_records().join(KOBE);
    let kobe = kobe.to_str().unwrap();
    let e = fails(
        dir.path(),
        &["ims", "--record", kobe, "--period", "1e-9"],
        "period T = 0.000000001 s is below Δt/250",
    );
    assert!(e.contains("ask for T ≥ 0.00004 s, or for PGA"), "{e}");
    // Through --direct, where SA is computed at any period, too.
    fails(
        dir.path(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--im",
            "sa(1e-9)",
            "--at",
            "0.3",
            "--direct",
        ],
        "below Δt/250",
    );
    let v = json(&rocking(
        dir.path(),
        &[
            "ims", "--record", kobe, "--period", "1e9", "--period", "1e-4", "--period", "5e-5",
            "--json",
        ],
    ));
    let keys: Vec<&String> = v["sa_g"].as_object().unwrap().keys().collect();
    for key in ["1000000000.0", "0.0001", "0.00005", "1.0", "0.05"] {
        assert!(keys.iter().any(|k| *k == key), "{key} in {keys:?}");
    }
    // SA at 0.1 ms is the record's PGA (a rigid oscillator): it lags the
    // ground by its damping force, a relative 2ζ|ȧ|/(ω|a|), below 1e-3
    // for a slope |ȧ| of up to 6|a|/Δt at ω = 62,832 rad/s, ζ = 0.05.
    let (sa, pga) = (
        v["sa_g"]["0.0001"].as_f64().unwrap(),
        v["pga_g"].as_f64().unwrap(),
    );
    assert!((sa / pga - 1.0).abs() < 1e-3, "{sa} against {pga}");
}

/// A record sampled every 1e4 s never finished its spectrum; it is refused
/// when read, naming DT.
#[test]
fn a_record_sampled_every_ten_thousand_seconds_is_refused() {
    let dir = tempdir();
    let path = dir.path().join("slow.AT2");
    fs::write(
        &path,
        at2_text(
            "ACCELERATION TIME SERIES IN UNITS OF G",
            "NPTS=    5, DT= 10000.0 SEC",
            &["0.0", "0.1", "-0.2", "0.1", "0.0"],
        ),
    )
    .unwrap();
    fails(
        dir.path(),
        &["ims", "--record", path.to_str().unwrap()],
        "DT = 10000 s: an accelerogram is sampled every 0.001–0.05 s",
    );
}

/// D5–95 of a record scaled by 1e300 was 0 (∫a² overflowed); a duration
/// does not change with scaling. Arias and CAV of one sample were −0.
#[test]
fn durations_do_not_change_with_scaling_and_nothing_is_minus_zero() {
    use rocking::im::record::{arias_m_s, cav_g_s, significant_duration_s};
    let (acc, dt) = rocking::records::read_samples(&bundled_records().join(KOBE)).unwrap();
    let d = significant_duration_s(&acc, dt, 0.05, 0.95);
    for k in [1e300, 1e-300, -3.0] {
        let scaled: Vec<f64> = acc.iter().map(|a| a * k).collect();
        let ds = significant_duration_s(&scaled, dt, 0.05, 0.95);
        assert!((ds - d).abs() < 1e-9 * d, "×{k}: {ds} against {d}");
    }
    assert!(d > 1.0);
    for one in [[0.3], [-0.3]] {
        assert_eq!(arias_m_s(&one, dt).to_bits(), 0);
        assert_eq!(cav_g_s(&one, dt).to_bits(), 0);
    }
}

/// Hazard IMLs ≤ 0 printed NaN, and lon 200 / lat 95 went into the
/// exposure: refused, naming the line and the column.
#[test]
fn impossible_hazard_levels_and_coordinates_are_refused() {
    let dir = tempdir();
    let d = dir.path();
    let block = ["--b", "0.2", "--h", "0.9"];
    let case = |imls: &[&str], lon: &str, lat: &str, what: &str| {
        openquake(
            &d.join("h.csv"),
            "PGA",
            imls,
            &[(lon, lat, &["0.5", "0.1", "0.01"])],
        );
        let mut args = vec!["risk", "--hazard", "h.csv"];
        args.extend(block);
        fails(d, &args, what);
    };
    case(
        &["0", "0.2", "0.5"],
        "20",
        "38",
        "h.csv:2: column `poe-0`: the IML 0 must be positive",
    );
    case(
        &["-0.1", "0.2", "0.5"],
        "20",
        "38",
        "the IML -0.1 must be positive",
    );
    case(
        &["0.1", "0.2", "0.5"],
        "200",
        "38",
        "h.csv:3: column `lon`: 200° is not a lon",
    );
    case(
        &["0.1", "0.2", "0.5"],
        "20",
        "95",
        "h.csv:3: column `lat`: 95° is not a lat",
    );
}

/// PGA given in gal (49–981 "g") or PGV in m/s (0.05–1 "cm/s") went
/// through without a word; AvgSA was taken whatever its periods. Each is
/// warned of, naming the likely unit.
#[test]
fn likely_unit_slips_are_warned_of() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("gal.csv"),
        "pga_g,annual_rate\n49,0.01\n196,0.001\n490,0.0001\n981,0.00001\n",
    )
    .unwrap();
    fs::write(
        d.join("ms.csv"),
        "pgv_cm_s,annual_rate\n0.05,0.01\n0.2,0.001\n0.5,0.0001\n1,0.00001\n",
    )
    .unwrap();
    fs::write(
        d.join("avgsa.csv"),
        "avgsa_g,annual_rate\n0.05,0.01\n0.2,0.001\n0.5,0.0001\n1,0.00001\n",
    )
    .unwrap();
    let warned = |file: &str, direct: bool, what: &str| {
        let mut args = vec![
            "risk", "--hazard", file, "--b", "0.2", "--h", "0.9", "--json",
        ];
        if direct {
            args.push("--direct");
        }
        let out = rocking(d, &args);
        let v = json(&out);
        let all: Vec<&str> = v["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|w| w.as_str().unwrap())
            .collect();
        assert!(all.iter().any(|w| w.contains(what)), "{file}: {all:?}");
        assert!(stderr(&out).contains(what));
    };
    warned(
        "gal.csv",
        false,
        "are they in cm/s² (gal)? Divide them by 980.665",
    );
    warned("ms.csv", true, "are they in m/s? Multiply them by 100");
    // PGA in m/s² on a usual grid (0.005–5 g × 9.81): it starts at
    // plausible g, but its tail reaches 49 "g", past any grid in g.
    let mut ms2 = String::from("pga_g,annual_rate\n");
    for k in 0..20 {
        let g = 0.005 * (1000f64).powf(k as f64 / 19.0);
        ms2.push_str(&format!(
            "{},{:e}\n",
            g * 9.80665,
            1e-2 * g.powf(-2.0) / 200.0
        ));
    }
    fs::write(d.join("ms2.csv"), ms2).unwrap();
    warned(
        "ms2.csv",
        false,
        "are they in m/s² (divide by 9.80665 for g)",
    );
    warned(
        "avgsa.csv",
        true,
        "the hazard must be computed over the same periods",
    );
}

/// Two blocks whose names make one taxonomy (`marble statue`, and
/// `marble_statue`) were refused as "taxonomy given twice", naming neither
/// block nor line; they are refused before any run with both lines. Names
/// that differ as taxonomies export.
#[test]
fn an_export_names_the_lines_of_two_blocks_of_one_taxonomy() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("inv.csv"),
        "name,b,h,eps\nmarble statue,0.2,0.9,\nkouros,0.15,1.0,0.8\nmarble_statue,0.15,1.0,0.8\n",
    )
    .unwrap();
    let args = [
        "export",
        "--format",
        "pelicun",
        "--inventory",
        "inv.csv",
        "--out",
        "x",
    ];
    fails(
        d,
        &args,
        "inv.csv:4: block `marble_statue` is keyed `marble_statue` in the engines' files, as \
         block `marble statue` (line 2) is",
    );
    assert!(!d.join("x").exists());
    fs::write(
        d.join("inv.csv"),
        "name,b,h,eps\nmarble statue,0.2,0.9,\nmarble-statue,0.15,1.0,0.8\n",
    )
    .unwrap();
    let out = rocking(d, &args);
    assert!(out.status.success(), "{}", stderr(&out));
}

/// A duplicated inventory column silently took the first.
#[test]
fn a_duplicated_inventory_column_is_refused() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(d.join("h.csv"), "pga_g,annual_rate\n0.1,0.01\n0.3,0.001\n").unwrap();
    fs::write(d.join("inv.csv"), "name,b,h,b\nstatue,0.2,0.9,0.4\n").unwrap();
    fails(
        d,
        &["risk", "--hazard", "h.csv", "--inventory", "inv.csv"],
        "inv.csv:1: column `b` is given twice (columns 2 and 4)",
    );
}

/// An inventory column misspelt or renamed (`epsilon`, `friction`, `Mu`)
/// was passed over: every block took Housner's ε, or no friction, and the
/// rates changed without a word (the kouros 4.63e-3/yr against 2.58e-3).
/// So were `e`, `ε`, `restitution_coefficient`, `mu_static` and `fric`:
/// a column is read as restitution or friction by its stem too. The
/// user's own columns are still passed over.
#[test]
fn a_misnamed_inventory_column_is_refused() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(d.join("h.csv"), "pga_g,annual_rate\n0.1,0.01\n0.3,0.001\n").unwrap();
    for (header, column, known) in [
        ("name,b,h,epsilon", "epsilon", "eps"),
        ("name,b,h,eps,friction", "friction", "mu"),
        ("name,b,h,eps,Mu", "Mu", "mu"),
        ("name,b,h,EPS", "EPS", "eps"),
        ("name,b,h,eps.", "eps.", "eps"),
        ("name,b,h,epss", "epss", "eps"),
        ("id,b,h", "id", "name"),
        ("name,b,h,e", "e", "eps"),
        ("name,b,h,E", "E", "eps"),
        ("name,b,h,ε", "ε", "eps"),
        (
            "name,b,h,restitution_coefficient",
            "restitution_coefficient",
            "eps",
        ),
        ("name,b,h,coeff_restitution", "coeff_restitution", "eps"),
        ("name,b,h,rest", "rest", "eps"),
        ("name,b,h,eps,mu_static", "mu_static", "mu"),
        ("name,b,h,eps,fric", "fric", "mu"),
    ] {
        fs::write(
            d.join("inv.csv"),
            format!("{header}\nstatue,0.2,0.9,0.7,0.5\n"),
        )
        .unwrap();
        for command in ["risk", "export"] {
            let args = match command {
                "risk" => vec![command, "--hazard", "h.csv", "--inventory", "inv.csv"],
                _ => vec![
                    command,
                    "--format",
                    "pelicun",
                    "--inventory",
                    "inv.csv",
                    "--out",
                    "x",
                ],
            };
            fails(
                d,
                &args,
                &format!("inv.csv:1: column `{column}`: is it `{known}`?"),
            );
        }
    }
    // A kinetic coefficient beside `mu` was passed over, the block run
    // with μk = μ: it is refused, pointing to where one is run.
    for column in [
        "mu_k",
        "Mu-kinetic",
        "dynamic friction",
        "kinetic_friction_coefficient",
        "friction_kinetic",
        "μ_k",
    ] {
        fs::write(
            d.join("inv.csv"),
            format!("name,b,h,eps,mu,{column}\nrack,0.3,1.0,0.75,0.5,0.3\n"),
        )
        .unwrap();
        fails(
            d,
            &["risk", "--hazard", "h.csv", "--inventory", "inv.csv"],
            &format!("inv.csv:1: column `{column}`: an inventory's friction is one coefficient"),
        );
    }
    // A comment line before the header: said why the header is not found.
    fs::write(d.join("inv.csv"), "# museum\nname,b,h\nstatue,0.2,0.9\n").unwrap();
    fails(
        d,
        &["risk", "--hazard", "h.csv", "--inventory", "inv.csv"],
        "a `#` comment line is not skipped",
    );
    // Columns of the user's own, or a near name beside the known one.
    for header in [
        "name,b,h,eps,room",
        "name,b,h,eps,epsilon",
        "name,b,h,eps,museum",
        "name,b,h,eps,era",
        "name,b,h,eps,african_provenance",
        "name,b,h,eps,friction_angle_deg",
        "name,b,h,eps,african_dynasty",
        "name,b,h,eps,mural_sliding_panel",
    ] {
        fs::write(
            d.join("inv.csv"),
            format!("{header}\nstatue,0.2,0.9,0.7,x\n"),
        )
        .unwrap();
        let out = rocking(
            d,
            &[
                "risk",
                "--hazard",
                "h.csv",
                "--inventory",
                "inv.csv",
                "--json",
            ],
        );
        assert!(out.status.success(), "{header}: {}", stderr(&out));
    }
}

/// OpenQuake's job counts nothing beyond the hazard's last IML, where
/// `risk` by default continues the curve: the export said nothing of the
/// difference (2.7 % of the statue's rate at site 1 of the bundled hazard).
/// It now warns with the share `risk` itself reports there.
#[test]
fn an_export_warns_of_the_rate_beyond_the_last_iml_that_risk_counts() {
    let dir = tempdir();
    let d = dir.path();
    let hazard = root().join("records/hazard/synthetic-openquake.csv");
    let hazard = hazard.to_str().unwrap();
    // With a tree the share is its mean's, as `risk --tree` states it (the
    // export took its first branch's: 2.7 % at site 1 against 3.4 %).
    for tree in [&[][..], &["--tree", "restitution-tests"][..]] {
        let mut block = vec!["--b", "0.2", "--h", "0.9", "--direct"];
        block.extend(tree);
        let mut args = vec![
            "export", "--format", "nrml", "--hazard", hazard, "--out", "job",
        ];
        args.extend(&block);
        let out = rocking(d, &args);
        assert!(out.status.success(), "{}", stderr(&out));
        let e = stderr(&out);
        let warning = e
            .lines()
            .find(|l| l.contains("counts nothing beyond the hazard's last IML (2 g)"))
            .unwrap_or_else(|| panic!("no warning: {e}"));
        let (site, share): (u64, f64) = {
            let after = warning.split("at site ").nth(1).unwrap();
            let (site, rest) = after.split_once(", ").unwrap();
            let share = rest.split(" %").next().unwrap();
            (site.parse().unwrap(), share.parse().unwrap())
        };
        // `risk`'s share at each of the three sites: the one named is the largest.
        let shares: Vec<f64> = (0..3)
            .map(|k| {
                let k_text = k.to_string();
                let mut args = vec!["risk", "--hazard", hazard, "--json", "--site", &k_text];
                args.extend(&block);
                let v: Value = serde_json::from_str(&stdout(&rocking(d, &args))).unwrap();
                100.0 * v["sites"][0]["share_beyond_last_iml"].as_f64().unwrap()
            })
            .collect();
        let risk_share = shares[site as usize];
        assert!(
            (share - risk_share).abs() <= 0.05,
            "{tree:?}: export {share} % against risk {risk_share} %"
        );
        for (k, s) in shares.iter().enumerate() {
            assert!(
                *s <= risk_share,
                "{tree:?}: site {k}: {s} % above the one named"
            );
        }
        // The other sites where it is 1 % or more are counted, not named.
        let others = shares.iter().filter(|&&s| s >= 1.0).count() - 1;
        let counted = match others {
            0 => !warning.contains("other site"),
            1 => warning.contains("and 1 % or more at 1 other site of 3"),
            n => warning.contains(&format!("and 1 % or more at {n} other sites of 3")),
        };
        assert!(counted, "{tree:?}: {shares:?}: {warning}");
        std::fs::remove_dir_all(d.join("job")).unwrap();
    }
}

/// `fragility --pga 0.2` gave the statue (uplift PGA g·tan α = 0.2222 g)
/// P(overturn) = 0.0011, and `--states` P(rocking) = 0.148, at a level
/// where no record lifts it and `risk` and the OpenQuake export count 0.
/// Below the cut every state is 0; above it P is the printed lognormal's;
/// on a floor, which may lift the block below the ground's uplift PGA,
/// nothing is cut.
#[test]
fn fragility_is_zero_below_the_uplift_pga_as_risk_counts_it() {
    let dir = tempdir();
    let d = dir.path();
    let levels = "0.1,0.2,0.222,0.223,0.3,0.5";
    let fragility = |extra: &[&str]| -> Value {
        let mut args = vec![
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--json",
            "--pga",
            levels,
        ];
        args.extend(extra);
        let out = rocking(d, &args);
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_str(&stdout(&out)).unwrap()
    };
    let cut = (0.2f64 / 0.9).atan().tan();
    for extra in [&[][..], &["--direct"][..]] {
        let v = fragility(extra);
        let (m, b) = (v["median"].as_f64().unwrap(), v["beta"].as_f64().unwrap());
        for p in v["points"].as_array().unwrap() {
            let (a, got) = (
                p["iml"].as_f64().unwrap(),
                p["probability"].as_f64().unwrap(),
            );
            let lognormal = rocking::stats::normal_cdf((a / m).ln() / b);
            let want = if a < cut { 0.0 } else { lognormal };
            assert!(
                (got - want).abs() < 1e-14,
                "{extra:?} at {a} g: {got} against {want}"
            );
            if let Some(share) = p["empirical"].as_f64() {
                // No record lifts the block below the cut.
                assert!(a >= cut || share == 0.0, "{a} g: {share}");
            }
        }
    }
    let v = fragility(&["--direct", "--states", "rocking=0.1,overturned=overturned"]);
    for p in v["points"].as_array().unwrap() {
        let a = p["iml"].as_f64().unwrap();
        for q in p["probabilities"].as_array().unwrap() {
            let q = q.as_f64().unwrap();
            assert!(a >= cut || q == 0.0, "{a} g: {q}");
            assert!(a < cut || q > 0.0, "{a} g: {q}");
        }
    }
    let on_floor = fragility(&["--direct", "--floor", "0.5,0.05,1.3"]);
    let below = on_floor["points"][1]["probability"].as_f64().unwrap();
    assert!(below > 0.0, "on a floor at 0.2 g: {below}");
}

/// `export --years -5` wrote `risk_investigation_time = -5` into the job,
/// where `risk --years -5` refuses: one check for both.
#[test]
fn export_refuses_the_years_risk_refuses() {
    let dir = tempdir();
    let d = dir.path();
    let hazard = root().join("records/hazard/synthetic-openquake.csv");
    let hazard = hazard.to_str().unwrap();
    for years in ["0", "-5", "inf"] {
        let message = format!("--years {years}: give a positive number of years");
        let block = [
            "--b", "0.2", "--h", "0.9", "--years", years, "--hazard", hazard,
        ];
        let mut risk = vec!["risk"];
        risk.extend(block);
        fails(d, &risk, &message);
        let mut export = vec!["export", "--format", "nrml", "--out", "job"];
        export.extend(block);
        fails(d, &export, &message);
        assert!(!d.join("job").exists(), "--years {years}: nothing written");
    }
}

/// `--plot` with every rate 0 wrote the table, then failed (now it ranks
/// them at 0), as did a `--plot` whose folder could not be made (a file
/// stands in its path): nothing is written then;
/// `--out` with `--states` (or for one block) exited 0 and wrote nothing.
#[test]
fn risk_writes_nothing_it_cannot_finish_and_refuses_what_it_would_ignore() {
    let dir = tempdir();
    let d = dir.path();
    // Every level below the statues' uplift PGA (0.2/0.9 g): no rate.
    fs::write(
        d.join("low.csv"),
        "pga_g,annual_rate\n0.01,0.01\n0.05,0.001\n0.1,0.0001\n",
    )
    .unwrap();
    fs::write(
        d.join("inv.csv"),
        "name,b,h\nstatue,0.2,0.9\nwide,0.5,0.9\n",
    )
    .unwrap();
    let args = [
        "risk",
        "--hazard",
        "low.csv",
        "--inventory",
        "inv.csv",
        "--beyond",
        "stop",
        "--out",
        "r.parquet",
        "--plot",
        "r.svg",
    ];
    // It now ranks them at 0 on a linear axis (a log axis shows no 0).
    let out = rocking(d, &args);
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = fs::read_to_string(d.join("r.svg")).unwrap();
    assert!(svg.contains("statue") && svg.contains("wide"), "{svg}");
    fs::remove_file(d.join("r.parquet")).unwrap();
    fs::write(
        d.join("h.csv"),
        "pga_g,annual_rate\n0.1,0.01\n0.3,0.001\n0.6,1e-4\n",
    )
    .unwrap();
    fs::write(d.join("a-file"), "not a folder").unwrap();
    let mut args = args;
    (args[2], args[10]) = ("h.csv", "a-file/chart.svg");
    let out = rocking(d, &args);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("a-file/chart.svg"),
        "{}",
        stderr(&out)
    );
    assert!(!d.join("r.parquet").exists(), "the table was written");
    for extra in [
        &[
            "--inventory",
            "inv.csv",
            "--states",
            "a=0.5,overturned=overturned",
            "--out",
            "x.parquet",
        ][..],
        &["--b", "0.2", "--h", "0.9", "--out", "x.parquet"][..],
    ] {
        let mut args = vec!["risk", "--hazard", "low.csv"];
        args.extend(extra);
        let out = rocking(d, &args);
        assert!(!out.status.success(), "{args:?}");
        assert!(stderr(&out).contains("--out"), "{}", stderr(&out));
        assert!(!d.join("x.parquet").exists());
    }
}

/// Most of P(OT) below the hazard curve's first IML was not said (the upper
/// tail warned; the lower did not): the rate is then a lower bound. And the
/// PGV extrapolation warning spoke of "60 g".
#[test]
fn both_ends_of_a_short_hazard_curve_are_warned_of_in_its_unit() {
    let dir = tempdir();
    let d = dir.path();
    // From 0.6 g, above the statue's median (0.45 g): P(OT) there is 0.8.
    fs::write(
        d.join("high.csv"),
        "pga_g,annual_rate\n0.6,0.001\n0.8,0.0003\n1.0,0.0001\n",
    )
    .unwrap();
    let v = json(&rocking(
        d,
        &[
            "risk", "--hazard", "high.csv", "--b", "0.2", "--h", "0.9", "--json",
        ],
    ));
    let w = v["warnings"].to_string();
    assert!(
        w.contains("already at the hazard curve's first IML (0.6 g)"),
        "{w}"
    );
    assert!(w.contains("the rate is a lower bound"), "{w}");
    // A PGV curve that stops short: the extrapolation named in cm/s.
    fs::write(
        d.join("pgv.csv"),
        "pgv_cm_s,annual_rate\n2,0.1\n10,0.01\n20,0.003\n",
    )
    .unwrap();
    let v = json(&rocking(
        d,
        &[
            "risk", "--hazard", "pgv.csv", "--b", "0.2", "--h", "0.9", "--direct", "--json",
        ],
    ));
    let w = v["warnings"].to_string();
    assert!(w.contains("last IML (20 cm/s)"), "{w}");
    assert!(!w.contains(" g)"), "{w}");
}

/// Exports an engine cannot read or that mixed two runs: one record gave
/// β = 0 (OpenQuake's lognormal returns NaN); a second export into the same
/// folder left the first's job, exposure and assets beside it; a folder
/// holding a user's own file was written over; two exports at once mixed
/// blocks.
#[test]
fn an_export_folder_is_one_consistent_set() {
    let dir = tempdir();
    let d = dir.path();
    fs::create_dir_all(d.join("one")).unwrap();
    fs::copy(bundled_records().join(KOBE), d.join("one/kobe.AT2")).unwrap();
    let hazard = root().join("records/hazard/synthetic-openquake.csv");
    let hazard = hazard.to_str().unwrap();
    let block = ["--b", "0.2", "--h", "0.9", "--direct"];
    let run = |extra: &[&str]| {
        let mut args = vec!["export"];
        args.extend(block);
        args.extend(extra);
        rocking(d, &args)
    };
    let out = run(&["--format", "pelicun", "--records", "one", "--out", "beta0"]);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(e.contains("β = 0 (one record reaches it)"), "{e}");
    assert!(e.contains("cannot evaluate"), "{e}");
    assert!(!d.join("beta0/fragility.csv").exists());
    // The commands that do take a step from one record say so (they printed
    // β = 0.000 without a word).
    for command in ["fragility", "risk"] {
        let mut args = vec![command, "--records", "one", "--json"];
        args.extend(block);
        match command {
            "risk" => args.extend(["--hazard", hazard, "--site", "0"]),
            _ => args.extend(["--pga", "0.3"]),
        }
        let out = rocking(d, &args);
        assert!(out.status.success(), "{command}: {}", stderr(&out));
        let warned = format!("{}{}", stderr(&out), stdout(&out));
        assert!(
            warned.contains("fitted to the capacity of one record: it has no dispersion"),
            "{command}: {warned}"
        );
    }
    // Ten records or fewer: warned of as rough.
    fs::create_dir_all(d.join("few")).unwrap();
    for e in fs::read_dir(bundled_records().join("far-field"))
        .unwrap()
        .take(8)
    {
        let e = e.unwrap();
        fs::copy(e.path(), d.join("few").join(e.file_name())).unwrap();
    }
    let out = run(&[
        "--format",
        "pelicun",
        "--records",
        "few",
        "--out",
        "few-out",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("capacities of 8 records (fewer than 10)"),
        "{}",
        stderr(&out)
    );
    // A job, then a pelicun model into the same folder: the job is gone.
    let out = run(&["--format", "nrml", "--hazard", hazard, "--out", "x"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(d.join("x/job.ini").exists() && d.join("x/assets.csv").exists());
    let out = run(&["--format", "pelicun", "--out", "x"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let mut left: Vec<String> = fs::read_dir(d.join("x"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    left.sort();
    assert_eq!(left, ["fragility.csv", "fragility.json"]);
    // A folder with a user's own job.ini is not written over.
    fs::create_dir_all(d.join("mine")).unwrap();
    fs::write(d.join("mine/job.ini"), "mine").unwrap();
    let out = run(&["--format", "nrml", "--hazard", hazard, "--out", "mine"]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("it holds job.ini, which no export wrote"),
        "{}",
        stderr(&out)
    );
    assert_eq!(fs::read_to_string(d.join("mine/job.ini")).unwrap(), "mine");
    // Nor is anything written beside it: every target is checked first (the
    // fragility model, exposure, assets and hazard were written, then the
    // job refused).
    let mut there: Vec<String> = fs::read_dir(d.join("mine"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    there.sort();
    assert_eq!(there, ["job.ini"]);
    // A folder another export holds (a live process's lock) is refused.
    let (mut holder, _) = crate::util::live_lock(&d.join("x/.lock"), "rocking export");
    let out = run(&["--format", "pelicun", "--out", "x"]);
    holder.kill().unwrap();
    holder.wait().unwrap();
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("is in use: `rocking export`"),
        "{}",
        stderr(&out)
    );
}

/// `export --json` for an inventory had no block name, sizes or taxonomy,
/// and the sliding-first flag never reached the exports.
#[test]
fn an_export_names_its_blocks_and_their_sliding() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("inv.csv"),
        "name,b,h,eps,mu\nmarble statue,0.2,0.9,0.85,0.1\nrack,0.3,1.0,0.75,\n",
    )
    .unwrap();
    let out = rocking(
        d,
        &[
            "export",
            "--format",
            "nrml",
            "--inventory",
            "inv.csv",
            "--out",
            "o",
            "--json",
        ],
    );
    let v = json(&out);
    assert_eq!(v[0]["block"]["name"], "marble statue");
    assert_eq!(v[0]["taxonomy"], "marble_statue");
    assert_eq!(v[0]["block"]["b_m"], 0.2);
    assert_eq!(v[0]["block"]["slides_first"], true);
    assert_eq!(v[1]["block"]["slides_first"], Value::Null);
    let xml = fs::read_to_string(d.join("o/fragility_model.xml")).unwrap();
    assert!(
        xml.contains("marble statue: half-width 0.2 m") && xml.contains("slides before it rocks")
    );
    assert!(stderr(&out).contains("warning: block marble statue: the block slides"));
}

/// Messages that named the wrong thing: `--im pgv` without `--at` asked
/// for `--pga`; `capacity --b --h` said "linearised model, as asked" when
/// nothing was asked (and not that it errs by 2 % at α = 0.22); a state at
/// θmax/α ≥ 1e-300 printed 300 zeros and, under MLE, "fewer than two
/// records reach the state" when 44 do.
#[test]
fn messages_name_what_is_meant() {
    let dir = tempdir();
    let d = dir.path();
    fails(
        d,
        &["fragility", "--b", "0.2", "--h", "0.9", "--im", "pgv"],
        "give the levels of pgv with --at (in cm/s)",
    );
    let kobe = bundled_records().join(KOBE);
    let out = rocking(
        d,
        &[
            "capacity",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--eps",
            "0.9",
            "--record",
            kobe.to_str().unwrap(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(!text.contains("as asked"), "{text}");
    assert!(
        text.contains(
            "linearised model, which errs by about 2.2e-2 in η_c at α = 0.2187 rad; --model auto"
        ),
        "{text}"
    );
    let states = "a=1e-300,overturned=overturned";
    let out = rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--pga",
            "0.3",
            "--direct",
            "--states",
            states,
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).contains("θmax/α ≥ 1e-300"), "{}", stdout(&out));
    assert!(!stdout(&out).contains("0.0000000000"));
    let e = fails(
        d,
        &[
            "export", "--format", "pelicun", "--b", "0.2", "--h", "0.9", "--direct", "--states",
            states, "--method", "mle", "--out", "o",
        ],
        "damage state `a` has no mle fit (the records that reach it all reach it at one level",
    );
    assert!(!e.contains("fewer than two"), "{e}");
}

/// `fragility --from PIPELINE --direct` searched each record with
/// `capacity`'s defaults (200 log levels, Δη = 1e-4, static overturning)
/// whatever the pipeline's `[im]` and `[model] overturn` said, so the
/// command and the study stated other capacities for one block (−5 % in
/// the median with a coarse linear grid). Each record's capacity is now
/// the one `rocking capacity` finds with the pipeline's grid, tolerance,
/// criterion and model given by hand, and the fit their type-7 16/50/84 %
/// fractiles in PGA (α/η_c).
#[test]
fn a_pipelines_search_is_the_one_its_records_run_with() {
    pipeline_and_capacity_agree("kind = \"auto\"\n", &["--model", "auto"]);
}

/// The same for the pipeline's `[model]` kind and solver: the command ran
/// `auto` (the statue, α = 0.219, nonlinear by the Taylor stepper) over a
/// pipeline that runs its blocks linearised, or nonlinear by DP5, and so
/// stated other capacities than the study's (the linearised statue's
/// median 1.8 % apart, its β 0.21 against 0.16). The model's note names
/// the pipeline's key, not `capacity`'s option.
#[test]
fn a_pipelines_model_is_the_one_its_records_run_with() {
    let f = pipeline_and_capacity_agree("kind = \"linearized\"\n", &["--model", "linearized"]);
    let note = f["model"].as_str().unwrap();
    assert!(
        note.starts_with("linearised model")
            && note.contains("kind = \"auto\" or \"nonlinear\" in the pipeline's [model]")
            && !note.contains("--model"),
        "{note}"
    );
    pipeline_and_capacity_agree(
        "kind = \"nonlinear\"\nintegrator = \"dp5\"\nrtol = 1e-7\n",
        &[
            "--model",
            "nonlinear",
            "--integrator",
            "dp5",
            "--rtol",
            "1e-7",
        ],
    );
}

/// `fragility --from PIPELINE --direct` over a pipeline of five records
/// whose `[model]` is `model` (TOML lines), against `rocking capacity` of
/// each record with the same grid, tolerance, criterion and `model_args`.
fn pipeline_and_capacity_agree(model: &str, model_args: &[&str]) -> serde_json::Value {
    let dir = tempdir();
    let d = dir.path();
    let far = bundled_records().join("far-field");
    let ids = [
        "RSN1111_KOBE_NIS000",
        "RSN953_NORTHR_MUL009",
        "RSN1633_MANJIL_ABBAR--L",
        "RSN848_LANDERS_CLW-LN",
        "RSN1148_KOCAELI_ARC000",
    ];
    let pipe = d.join("search.toml");
    fs::write(
        &pipe,
        format!(
            "name = \"search\"\n[records]\nat2 = [\"{}\"]\nids = [{}]\n[model]\n{model}\
             overturn = \"cap:1.5\"\n[[block]]\nname = \"statue\"\nb = 0.2\nh = 0.9\n\
             eps = \"housner\"\n[im]\nspacing = \"linear\"\ncount = 40\neta_max = 1.0\n\
             eta_min = 0.01\ntol = 1e-2\n",
            far.display(),
            ids.map(|i| format!("\"{i}\"")).join(", ")
        ),
    )
    .unwrap();
    let alpha = (0.2f64 / 0.9).atan();
    let mut caps: Vec<f64> = ids
        .iter()
        .map(|id| {
            let record = far.join(format!("{id}.AT2"));
            let mut args = vec![
                "capacity",
                "--record",
                record.to_str().unwrap(),
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--eps",
                "housner",
                "--levels",
                "40",
                "--spacing",
                "linear",
                "--eta-min",
                "0.01",
                "--tol",
                "1e-2",
                "--overturn",
                "cap:1.5",
                "--json",
            ];
            args.extend(model_args);
            let c = json(&rocking(d, &args));
            alpha / c["eta_c"].as_f64().unwrap()
        })
        .collect();
    caps.sort_by(f64::total_cmp);
    let type7 = |q: f64| {
        let h = (caps.len() - 1) as f64 * q;
        let i = h.floor() as usize;
        caps[i] + (h - i as f64) * (caps[(i + 1).min(caps.len() - 1)] - caps[i])
    };
    let f = json(&rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--from",
            pipe.to_str().unwrap(),
            "--outputs",
            "o",
            "--direct",
            "--if-not-lognormal",
            "lognormal",
            "--pga",
            "0.3",
            "--json",
        ],
    ));
    let (median, beta) = (f["median"].as_f64().unwrap(), f["beta"].as_f64().unwrap());
    let want = (type7(0.5), 0.5 * (type7(0.84) / type7(0.16)).ln());
    assert!(
        (median / want.0 - 1.0).abs() < 1e-12,
        "median {median} against {}",
        want.0
    );
    assert!(
        (beta / want.1 - 1.0).abs() < 1e-12,
        "β {beta} against {}",
        want.1
    );
    f
}

/// pelicun's lognormal has no lower limit where the block's states have one
/// (the uplift PGA b/h, OpenQuake's noDamageLimit): the pelicun export says
/// how much the lightest state already has there, P at the uplift PGA as
/// `fragility --states` gives it (to the warning's tenth of a per cent).
#[test]
fn the_pelicun_export_says_what_its_lognormal_counts_below_uplift() {
    let dir = tempdir();
    let d = dir.path();
    let out = rocking(
        d,
        &[
            "export", "--format", "pelicun", "--b", "0.2", "--h", "0.9", "--direct", "--out", "p",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let err = stderr(&out);
    let line = err
        .lines()
        .find(|l| l.contains("pelicun's lognormal has no lower limit"))
        .unwrap_or_else(|| panic!("no warning of the uncut lognormal:\n{err}"));
    let cut = format!("{:?}", 0.2f64 / 0.9);
    let at = json(&rocking(
        d,
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--states",
            "rocking=0.1,large_rocking=0.5,overturned=overturned",
            "--pga",
            &cut,
            "--json",
        ],
    ));
    let p = at["points"][0]["probabilities"][0].as_f64().unwrap();
    assert!(p > 0.01, "{p}");
    assert!(
        line.contains(&format!("P = {:.1} %", 100.0 * p)),
        "{line} against {p}"
    );
}

/// SA at 100 s gave a median of 0.0001 g without a word: no hazard model
/// states SA there (NGA-West2 stops at 10 s) and a record's spectrum there
/// is its filter's. `fragility` and `risk` warn of it; SA(10) is not.
#[test]
fn spectra_past_ten_seconds_are_warned_of_in_every_answer() {
    let dir = tempdir();
    let d = dir.path();
    fs::write(
        d.join("h.csv"),
        "sa(100)_g,annual_rate\n0.0001,0.1\n0.001,0.001\n",
    )
    .unwrap();
    for (im, warned) in [("sa(100)", true), ("sa(10)", false)] {
        let f = json(&rocking(
            d,
            &[
                "fragility",
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--direct",
                "--im",
                im,
                "--at",
                "0.001",
                "--json",
            ],
        ));
        let w = f["warnings"].to_string();
        assert_eq!(w.contains("past 10 s"), warned, "{im}: {w}");
    }
    let out = rocking(
        d,
        &[
            "risk", "--hazard", "h.csv", "--b", "0.2", "--h", "0.9", "--direct", "--json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("past 10 s") || stderr(&out).contains("past 10 s"),
        "{}",
        stderr(&out)
    );
}

/// An export whose block's capacities fail the lognormal check writes the
/// records' own curves (discrete, multilinear_CDF), and its description
/// said "fractile fit" all the same. It says what it wrote; a lognormal
/// written as asked still says its fit.
#[test]
fn an_exports_description_says_what_it_wrote() {
    let dir = tempdir();
    let d = dir.path();
    let eps = "0.85";
    for (format, keep, curves) in [
        ("nrml", "curve", true),
        ("pelicun", "curve", true),
        ("nrml", "lognormal", false),
    ] {
        let out = format!("{format}-{keep}");
        let run = rocking(
            d,
            &[
                "export",
                "--format",
                format,
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--eps",
                eps,
                "--direct",
                "--out",
                &out,
                "--json",
                "--if-not-lognormal",
                keep,
            ],
        );
        assert!(run.status.success(), "{}", stderr(&run));
        let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
        assert_eq!(
            v[0]["written_as"] == "curve",
            curves,
            "{format} ε {eps}: {v}"
        );
        let text: String = fs::read_dir(d.join(&out))
            .unwrap()
            .map(|f| fs::read_to_string(f.unwrap().path()).unwrap_or_default())
            .collect();
        let says_curves = text.contains("own curves (their capacities fail the lognormal check");
        assert_eq!(says_curves, curves, "{format} ε {eps}");
        assert_eq!(text.contains("fractile fit,"), !curves, "{format} ε {eps}");
    }
}
