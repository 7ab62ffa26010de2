//! A block on a building's floor, and a block that slides before it rocks,
//! through the binary: the floor motion is what runs (the same capacity as
//! the floor motion written as a record), its PFA/PGA against the samples,
//! the ground's PGA through the building's linearity; the sliding check in
//! every command that assesses a block; refusals.

use std::path::Path;

use serde_json::Value;

use crate::util::{
    bundled_records, peak_velocity, plain_at2_values, rocking, root, stderr, stdout, tempdir,
    write_at2,
};

fn kobe() -> std::path::PathBuf {
    bundled_records().join("far-field/RSN1111_KOBE_NIS000.AT2")
}

/// Far-field records some tests run through, fewer for speed.
const FEW: [&str; 4] = [
    "RSN1111_KOBE_NIS000",
    "RSN1116_KOBE_SHI000",
    "RSN1148_KOCAELI_ARC000",
    "RSN1148_KOCAELI_ARC090",
];

/// A folder `dir/few` holding copies of the far-field records `ids`.
fn few_far_field(dir: &Path, ids: &[&str]) -> std::path::PathBuf {
    let few = dir.join("few");
    std::fs::create_dir(&few).unwrap();
    for id in ids {
        let name = format!("{id}.AT2");
        std::fs::copy(
            bundled_records().join("far-field").join(&name),
            few.join(&name),
        )
        .unwrap();
    }
    few
}

fn json(out: &std::process::Output) -> Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!("{e}: {}", String::from_utf8_lossy(&out.stdout));
    })
}

/// The capacity on a floor is the capacity of the floor motion: written as
/// an AT2 file and run without --floor, it gives the same η_c to the bit.
/// PFA/PGA is the floor motion's largest sample over the record's (read by
/// the test's own AT2 reader), and the ground's PGA at the capacity is the
/// floor's over it (the building is linear).
#[test]
fn a_capacity_on_a_floor_is_that_of_the_floor_motion_as_a_record() {
    let dir = tempdir();
    let record = kobe();
    let modes = ["1.5,0.05,1.3", "0.5,0.05,-0.4"];
    let ground = plain_at2_values(&record);
    let building =
        rocking::floor::Building::new(modes.iter().map(|m| m.parse().unwrap()).collect()).unwrap();
    let floor = building.floor_motion(&ground, 0.01).unwrap();
    assert_eq!(floor.substeps, 1);
    let file = dir.path().join("floor.AT2");
    write_at2(&file, &floor.accel_g, floor.dt_s);

    let block = ["--b", "0.2", "--h", "1", "--eps", "0.9", "--json"];
    let mut on_floor = vec!["capacity", "--record", record.to_str().unwrap()];
    on_floor.extend(block);
    for m in modes {
        on_floor.extend(["--floor", m]);
    }
    let a = json(&rocking(&root(), &on_floor));
    let mut as_record = vec!["capacity", "--record", file.to_str().unwrap()];
    as_record.extend(block);
    let b = json(&rocking(&root(), &as_record));
    assert!(a["eta_c"].as_f64().is_some());
    assert_eq!(a["eta_c"], b["eta_c"]);
    assert_eq!(a["runs"], b["runs"]);
    assert!(b["floor"].is_null() && b["pfa_over_pga"].is_null());
    assert_eq!(a["floor"], "1.5,0.05,1.3; 0.5,0.05,-0.4");

    let peak = |v: &[f64]| v.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    let ratio = peak(&floor.accel_g) / peak(&ground);
    assert_eq!(a["pfa_over_pga"].as_f64().unwrap(), ratio);
    let pfa_c = a["pfa_c_g"].as_f64().unwrap();
    let alpha = a["alpha_rad"].as_f64().unwrap();
    assert_eq!(pfa_c, alpha / a["eta_c"].as_f64().unwrap());
    assert_eq!(a["pga_c_g"].as_f64().unwrap(), pfa_c / ratio);
}

/// `simulate --floor --pga` scales the ground: η is the floor's, α over the
/// ground PGA times the building's amplification; and a floor through a
/// building with Γφ = 0 is the ground itself (the same response).
#[test]
fn simulate_on_a_floor_scales_the_ground() {
    let record = kobe();
    let rec = record.to_str().unwrap();
    let base = [
        "simulate", "--record", rec, "--b", "0.2", "--h", "1", "--eps", "0.9", "--json",
    ];
    let mut args = base.to_vec();
    args.extend(["--pga", "0.1", "--floor", "0.5,0.05,1.3"]);
    let s = json(&rocking(&root(), &args));
    let ratio = s["pfa_over_pga"].as_f64().unwrap();
    assert!(ratio > 1.0, "{ratio}");
    let alpha = s["alpha_rad"].as_f64().unwrap();
    assert_eq!(s["eta"].as_f64().unwrap(), alpha / (0.1 * ratio));

    let mut node = base.to_vec();
    node.extend(["--eta", "0.4", "--floor", "0.5,0.05,0"]);
    let mut ground = base.to_vec();
    ground.extend(["--eta", "0.4"]);
    let (n, g) = (
        json(&rocking(&root(), &node)),
        json(&rocking(&root(), &ground)),
    );
    assert_eq!(n["pfa_over_pga"].as_f64(), Some(1.0));
    for key in [
        "theta_max_over_alpha",
        "impacts",
        "overturned",
        "first_uplift_s",
    ] {
        assert_eq!(n[key], g[key], "{key}");
    }
}

/// `capacity --json`'s `pga_c_g` on a floor is the ground's PGA, the one
/// `simulate --pga` takes: run there, the block overturns, and at the PGA
/// of the bracket's surviving end it survives (it was the floor's peak,
/// 5.3 times the ground's, under the same name).
#[test]
fn a_floor_capacity_s_pga_is_the_one_simulate_takes() {
    let record = kobe();
    let rec = record.to_str().unwrap();
    let block = [
        "--b",
        "0.2",
        "--h",
        "0.9",
        "--eps",
        "0.9",
        "--floor",
        "0.5,0.05,1.3",
    ];
    let mut args = vec!["capacity", "--record", rec, "--json"];
    args.extend(block);
    let c = json(&rocking(&root(), &args));
    let (pga_c, pfa_c) = (
        c["pga_c_g"].as_f64().unwrap(),
        c["pfa_c_g"].as_f64().unwrap(),
    );
    let ratio = c["pfa_over_pga"].as_f64().unwrap();
    assert!(ratio > 2.0, "{ratio}");
    assert!(
        (pfa_c / pga_c / ratio - 1.0).abs() < 1e-15,
        "{pfa_c} {pga_c} {ratio}"
    );
    let alpha = c["alpha_rad"].as_f64().unwrap();
    let survived_pga = alpha / c["eta_survived"].as_f64().unwrap() / ratio;
    for (pga, overturns) in [(pga_c, true), (survived_pga, false)] {
        let level = format!("{pga}");
        let mut args = vec!["simulate", "--record", rec, "--json", "--pga", &level];
        args.extend(block);
        let s = json(&rocking(&root(), &args));
        assert_eq!(s["overturned"].as_bool(), Some(overturns), "PGA {pga} g");
    }
}

/// The blocks: b/h = 0.4 with μ = 0.2 slides first and is warned
/// of in `simulate` and `capacity` (and flagged in their JSON); μ = 0.6 is
/// not. --mu needs the block's α; a negative μ is refused.
#[test]
fn a_block_that_slides_first_is_warned_of() {
    let rec = kobe();
    let rec = rec.to_str().unwrap();
    for command in ["simulate", "capacity"] {
        for (mu, slides) in [("0.2", true), ("0.6", false)] {
            let mut args = vec![
                command, "--record", rec, "--b", "0.4", "--h", "1", "--eps", "0.9", "--mu", mu,
                "--json",
            ];
            if command == "simulate" {
                args.extend(["--eta", "0.5"]);
            }
            let out = rocking(&root(), &args);
            let report = json(&out);
            assert_eq!(report["slides_first"], slides, "{command} μ {mu}");
            assert_eq!(report["mu"].as_f64(), mu.parse().ok());
            assert_eq!(
                stderr(&out).contains("slides before it rocks"),
                slides,
                "{command} μ {mu}: {}",
                stderr(&out)
            );
        }
    }
    let out = rocking(
        &root(),
        &[
            "capacity", "--record", rec, "--p", "2", "--eps", "0.9", "--mu", "0.3",
        ],
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("--mu is compared with the block's b/h"),
        "{}",
        stderr(&out)
    );
    let out = rocking(
        &root(),
        &[
            "capacity",
            "--record",
            rec,
            "--b",
            "0.4",
            "--h",
            "1",
            "--eps",
            "0.9",
            "--mu=-0.3",
        ],
    );
    assert!(
        stderr(&out).contains("--mu: friction coefficient μ = -0.3"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn bad_floors_are_refused_by_name() {
    let rec = kobe();
    let rec = rec.to_str().unwrap();
    let base = ["capacity", "--record", rec, "--p", "2", "--eps", "0.9"];
    for (floor, says) in [
        ("0.5,0.05", "a mode is T,ZETA,GAMMA_PHI"),
        ("0,0.05,1", "--floor: mode 1: period T = 0 s"),
        ("0.5,1.5,1", "--floor: mode 1: damping ratio ζ = 1.5"),
        // A mode given twice was summed twice, without a word.
        ("0.5,0.05,1.3 0.5,0.05,1.3", "mode 2 repeats mode 1"),
    ] {
        let mut args = base.to_vec();
        for mode in floor.split(' ') {
            args.extend(["--floor", mode]);
        }
        let out = rocking(&root(), &args);
        assert!(!out.status.success(), "{floor}");
        assert!(stderr(&out).contains(says), "{floor}: {}", stderr(&out));
    }
    let out = rocking(
        &root(),
        &[
            "simulate",
            "--pulse",
            "rect",
            "--p",
            "2",
            "--eps",
            "0.9",
            "--eta",
            "0.5",
            "--floor",
            "0.5,0.05,1",
        ],
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("a pulse is given as the block's own excitation"),
        "{}",
        stderr(&out)
    );
}

/// `fragility --direct --floor`: the share of records overturning the block
/// at each ground PGA is the share whose ground PGA at capacity, from
/// `capacity --floor` over the same records, is at most that level (the two
/// commands reach the floor by their own paths); a building whose floor is
/// a node of its mode (Γφ = 0) gives the ground's shares.
#[test]
fn fragility_on_a_floor_counts_the_records_by_their_ground_capacity() {
    let far = bundled_records().join("far-field");
    let far = far.to_str().unwrap();
    // α = atan 0.1: the linearised model at the default --auto-tol.
    let block = ["--b", "0.1", "--h", "1", "--eps", "0.9"];
    let levels = [0.03, 0.06, 0.1, 0.2];
    let levels_arg = "0.03,0.06,0.1,0.2";
    let fragility = |floor: &str| {
        let mut args = vec![
            "fragility",
            "--records",
            far,
            "--direct",
            "--json",
            "--pga",
            levels_arg,
        ];
        args.extend(block);
        args.extend(["--floor", floor]);
        json(&rocking(&root(), &args))
    };
    let f = fragility("0.5,0.05,1.3");
    assert_eq!(f["floor"], "0.5,0.05,1.3");
    assert_eq!(f["source"], "direct");
    let mut args = vec![
        "capacity",
        "--record",
        far,
        "--json",
        "--floor",
        "0.5,0.05,1.3",
    ];
    args.extend(block);
    let out = rocking(&root(), &args);
    assert!(out.status.success(), "{}", stderr(&out));
    let caps: Vec<f64> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| {
            let v: Value = serde_json::from_str(l).unwrap();
            v["pga_c_g"].as_f64().unwrap_or(f64::INFINITY)
        })
        .collect();
    assert_eq!(caps.len(), 44);
    let points = f["points"].as_array().unwrap();
    for (pt, x) in points.iter().zip(levels) {
        let share = caps.iter().filter(|&&c| c <= x).count() as f64 / caps.len() as f64;
        assert_eq!(pt["empirical"].as_f64().unwrap(), share, "PGA {x}");
    }
    // The floor overturns the block under more records than the ground does.
    let g = {
        let mut args = vec![
            "fragility",
            "--records",
            far,
            "--direct",
            "--json",
            "--pga",
            levels_arg,
        ];
        args.extend(block);
        json(&rocking(&root(), &args))
    };
    let node = fragility("0.5,0.05,0");
    let share = |v: &Value, i: usize| v["points"][i]["empirical"].as_f64().unwrap();
    for i in 0..levels.len() {
        assert_eq!(share(&node, i), share(&g, i), "level {i}");
        assert!(share(&f, i) >= share(&g, i), "level {i}");
    }
    assert!(share(&f, 1) > share(&g, 1));
}

/// The block (b/h = 0.4) with μ = 0.2 is warned of by `fragility`
/// (and its `--states`) and `risk` (one block and an inventory's `mu`
/// column, flagged in risk.parquet) from the regression; with μ = 0.6 it
/// is not. With `--direct` it runs sliding and never rocks: `fragility`
/// says why, `export` refuses its rotation states. A floor without
/// --direct is refused: the regressions are of blocks on the ground.
#[test]
fn fragility_risk_and_export_warn_of_a_block_that_slides_first() {
    let hazard = root().join("records/hazard/synthetic-site.csv");
    let hazard = hazard.to_str().unwrap();
    let block = ["--b", "0.4", "--h", "1", "--eps", "0.8"];
    for (mu, slides) in [("0.2", true), ("0.6", false)] {
        let mut args = vec!["fragility", "--pga", "0.3", "--json", "--mu", mu];
        args.extend(block);
        let out = rocking(&root(), &args);
        let f = json(&out);
        assert_eq!(f["slides_first"], slides, "μ {mu}");
        let warned = |v: &Value| {
            v["warnings"]
                .as_array()
                .unwrap()
                .iter()
                .any(|w| w.as_str().unwrap().contains("slides before it rocks"))
        };
        assert_eq!(warned(&f), slides, "fragility μ {mu}");

        let mut args = vec!["risk", "--hazard", hazard, "--json", "--mu", mu];
        args.extend(block);
        let out = rocking(&root(), &args);
        let r = json(&out);
        let r = if r.is_array() { r[0].clone() } else { r };
        assert_eq!(r["block"]["slides_first"], slides, "risk μ {mu}");
        assert_eq!(warned(&r), slides, "risk μ {mu}");
        assert_eq!(stderr(&out).contains("slides before it rocks"), slides);
    }
    let dir = tempdir();
    let inventory = dir.path().join("blocks.csv");
    std::fs::write(
        &inventory,
        "name,b,h,eps,mu\nslides,0.4,1,0.8,0.2\nrocks,0.4,1,0.8,0.6\nunknown,0.4,1,0.8,\n",
    )
    .unwrap();
    let table = dir.path().join("risk.parquet");
    let out = rocking(
        &root(),
        &[
            "risk",
            "--hazard",
            hazard,
            "--inventory",
            inventory.to_str().unwrap(),
            "--out",
            table.to_str().unwrap(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stderr(&out).contains("warning: block slides: the block slides before it rocks"));
    assert!(!stderr(&out).contains("block rocks: the block slides"));
    let rows = rocking::tables::read::<rocking::tables::risk::RiskRow>(&table).unwrap();
    let flags: Vec<(&str, Option<f64>, bool)> = rows
        .iter()
        .map(|r| (r.block.as_str(), r.mu, r.slides_first))
        .collect();
    assert_eq!(
        flags,
        [
            ("slides", Some(0.2), true),
            ("rocks", Some(0.6), false),
            ("unknown", None, false)
        ]
    );
    std::fs::write(&inventory, "name,b,h,mu\nbad,0.4,1,-1\n").unwrap();
    let out = rocking(
        &root(),
        &[
            "risk",
            "--hazard",
            hazard,
            "--inventory",
            inventory.to_str().unwrap(),
            "--out",
            table.to_str().unwrap(),
        ],
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains(":2: block `bad`: `mu`: friction coefficient μ = -1"),
        "{}",
        stderr(&out)
    );

    let mut args = vec![
        "fragility",
        "--pga",
        "0.3",
        "--json",
        "--mu",
        "0.2",
        "--direct",
        "--states",
        "rocking=0.5,overturned=overturned",
        "--records",
    ];
    let few = few_far_field(dir.path(), &FEW[..3]);
    args.push(few.to_str().unwrap());
    args.extend(block);
    let out = rocking(&root(), &args);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("slides before it rocks"),
        "{}",
        stderr(&out)
    );

    let out = rocking(
        &root(),
        &[
            "export",
            "--format",
            "pelicun",
            "--b",
            "0.4",
            "--h",
            "1",
            "--eps",
            "0.8",
            "--mu",
            "0.2",
            "--direct",
            "--records",
            few.to_str().unwrap(),
            "--states",
            "rocking=0.5,overturned=overturned",
            "--out",
            dir.path().join("pelicun").to_str().unwrap(),
        ],
    );
    // With --direct the block runs sliding (the slide-rock model): it never
    // rocks, which no engine's function can state, so the export refuses
    // those states and names the states it can write.
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("slides before it rocks, so under horizontal shaking it neither rocks"),
        "{e}"
    );
    assert!(e.contains("--states NAME=Xm"), "{e}");
    assert!(!dir.path().join("pelicun/fragility.csv").exists());

    for command in ["fragility", "risk"] {
        let mut args = vec![command, "--floor", "0.5,0.05,1.3"];
        if command == "fragility" {
            args.extend(["--pga", "0.3"]);
        } else {
            args.extend(["--hazard", hazard]);
        }
        args.extend(block);
        let out = rocking(&root(), &args);
        assert!(!out.status.success(), "{command}");
        assert!(
            stderr(&out).contains("are of blocks on the ground")
                && stderr(&out).contains("add --direct"),
            "{command}: {}",
            stderr(&out)
        );
    }
}

/// A `[floor]` pipeline: the sweep's capacities are `capacity --floor`'s
/// for each record (the stage and the command reach the floor by their own
/// paths), with each record's PFA/PGA and the sliding flag; a floor at a
/// node of its mode (Γφ = 0) gives the ground study's capacities to the bit;
/// `fragility --from` the study needs --direct, and then runs its records
/// through its building.
#[test]
fn a_floor_study_runs_the_floor_motion_in_every_stage() {
    use crate::util::write_pipeline;
    let dir = tempdir();
    let ids =
        "ids = [\"RSN1111_KOBE_NIS000\", \"RSN1116_KOBE_SHI000\", \"RSN1148_KOCAELI_ARC000\"]\n";
    let blocks = "[model]\nkind = \"auto\"\n\
        [[block]]\nname = \"rack\"\nb = 0.3\nh = 1.0\neps = 0.75\nmu = 0.4\n\
        [[block]]\nname = \"cabinet\"\nb = 0.1\nh = 1.0\neps = 0.85\nmu = 0.05\n";
    let floor = write_pipeline(
        dir.path(),
        "on-floor",
        &format!("{ids}{blocks}[floor]\nmodes = [[0.5, 0.05, 1.3], [0.2, 0.05, -0.3]]\n"),
    );
    let node = write_pipeline(
        dir.path(),
        "on-node",
        &format!("{ids}{blocks}[floor]\nmodes = [[0.5, 0.05, 0.0]]\n"),
    );
    let ground = write_pipeline(dir.path(), "on-ground", &format!("{ids}{blocks}"));
    let outputs = dir.path().join("out");
    let out_s = outputs.to_str().unwrap();
    for p in [&floor, &node, &ground] {
        let out = rocking(
            dir.path(),
            &["run", p.to_str().unwrap(), "--outputs", out_s],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        // `auto` runs the cabinet (μ = 0.05 < b/h = 0.1) sliding and says
        // why, instead of warning that the rocking results assume it does
        // not slide; the rack (μ = 0.4 > 0.3) rocks first.
        let e = stderr(&out);
        assert!(
            e.contains("slide-rock model: the block slides before it rocks (μ = 0.05 ≤ b/h"),
            "{e}"
        );
        assert!(e.contains("μ = 0.4 > b/h = 0.3000: it rocks first"), "{e}");
        assert!(!e.contains("warning: block"), "{e}");
        // Three records: too few for the lognormal check of either block,
        // and the reduce stage's count says so rather than "0 of 0".
        let all = format!("{}{e}", crate::util::stdout(&out));
        assert!(
            all.contains("lognormality of η_c untested in every block (fewer than five"),
            "{all}"
        );
    }
    let caps = |name: &str| rocking::stages::sweep::read_capacities(&outputs.join(name)).unwrap();
    let on_floor = caps("on-floor");
    assert_eq!(on_floor.len(), 6);
    for c in &on_floor {
        let record = bundled_records().join(format!("far-field/{}.AT2", c.record_id));
        let (b, h, eps, mu) = if c.block == "rack" {
            ("0.3", "1.0", "0.75", "0.4")
        } else {
            ("0.1", "1.0", "0.85", "0.05")
        };
        let one = json(&rocking(
            &root(),
            &[
                "capacity",
                "--record",
                record.to_str().unwrap(),
                "--b",
                b,
                "--h",
                h,
                "--eps",
                eps,
                "--model",
                "auto",
                "--mu",
                mu,
                "--floor",
                "0.5,0.05,1.3",
                "--floor",
                "0.2,0.05,-0.3",
                "--json",
            ],
        ));
        assert_eq!(
            c.eta_c,
            one["eta_c"].as_f64(),
            "{} {}",
            c.record_id,
            c.block
        );
        assert_eq!(c.pfa_over_pga, one["pfa_over_pga"].as_f64());
        assert_eq!(c.slides_first, one["slides_first"] == true);
        assert_eq!(c.slides_first, c.block == "cabinet");
    }
    let (on_node, on_ground) = (caps("on-node"), caps("on-ground"));
    for (n, g) in on_node.iter().zip(&on_ground) {
        assert_eq!((n.eta_c, n.runs), (g.eta_c, g.runs), "{}", n.record_id);
        assert_eq!(n.pfa_over_pga, Some(1.0));
        assert_eq!(g.pfa_over_pga, None);
    }
    let report = std::fs::read_to_string(outputs.join("on-floor/report.md")).unwrap();
    assert!(report.contains("## On a building's floor"), "{report}");
    // `auto` runs the cabinet sliding: the report's table of the blocks that
    // slide has it (never overturning: it slides first) beside the rack.
    assert!(report.contains("## Blocks that slide"), "{report}");
    assert!(
        report.contains("| cabinet | 0.05 | 0.100 | 0 of 3 |"),
        "{report}"
    );
    assert!(outputs.join("on-floor/figures/floor_capacity.svg").exists());
    // What the building does to the records' peaks, counted from the
    // capacities: "amplifies" was said of records whose peak it reduced.
    let ratios: Vec<f64> = on_floor
        .iter()
        .filter(|c| c.block == "rack")
        .map(|c| c.pfa_over_pga.unwrap())
        .collect();
    let below = ratios.iter().filter(|&&r| r < 1.0).count();
    let said = match below {
        0 => ": it amplifies every one.".to_string(),
        n => format!(
            " (it reduces the peak of {n} of the {} records).",
            ratios.len()
        ),
    };
    assert!(report.contains(&said), "{said}\n{report}");
    // Named blocks of their own ε: the IM table lists each, with its ε;
    // the cabinet, which never overturns, "survives" in the fractiles.
    assert!(report.contains("Each block at its own ε:"), "{report}");
    assert!(report.contains("| rack, "), "{report}");
    assert!(
        report.contains("| survives | survives | survives |"),
        "{report}"
    );

    // The study states each block's fragility in the floor's demands beside
    // the ground's IMs. record_ims holds each record's floor motion's PFA,
    // which is its PGA times the sweep's PFA/PGA (two paths to the floor).
    let study = outputs.join("on-floor");
    let ims: Vec<rocking::tables::ims::RecordImRow> =
        rocking::tables::read(&study.join("record_ims.parquet")).unwrap();
    let value = |id: &str, im: &str| {
        ims.iter()
            .find(|r| r.record_id == id && r.im == im)
            .unwrap_or_else(|| panic!("{id} {im}"))
            .value
    };
    for c in on_floor.iter().filter(|c| c.block == "rack") {
        let (pga, pfa) = (value(&c.record_id, "pga"), value(&c.record_id, "pfa"));
        let ratio = c.pfa_over_pga.unwrap();
        assert!(
            (pfa / (pga * ratio) - 1.0).abs() < 1e-12,
            "{}: {pfa} {pga} {ratio}",
            c.record_id
        );
        assert!(value(&c.record_id, "pfv") > 0.0 && value(&c.record_id, "fsa(1.0)") > 0.0);
    }
    // Its PFV fragility is `fragility --im pfv --direct --method mle`'s over
    // the same records, on the study's μ (both run it sliding): every record overturns the rack, so the censored maximum
    // likelihood's median is the logs' mean, as the table's is, and its β
    // (n in the denominator) is the table's (n − 1) times √((n − 1)/n).
    let eff: Vec<rocking::tables::ims::EfficiencyRow> =
        rocking::tables::read(&study.join("im_efficiency.parquet")).unwrap();
    assert!(on_floor
        .iter()
        .filter(|c| c.block == "rack")
        .all(|c| c.eta_c.is_some()));
    let row = |im: &str| {
        eff.iter()
            .find(|r| r.block == "rack" && r.im == im)
            .unwrap_or_else(|| panic!("rack {im}"))
    };
    let direct = json(&rocking(
        dir.path(),
        &[
            "fragility",
            "--b",
            "0.3",
            "--h",
            "1",
            "--eps",
            "0.75",
            "--mu",
            "0.4",
            "--im",
            "pfv",
            "--at",
            "40",
            "--from",
            floor.to_str().unwrap(),
            "--outputs",
            out_s,
            "--direct",
            "--method",
            "mle",
            "--json",
        ],
    ));
    let pfv = row("pfv");
    let (median, beta) = (
        direct["median"].as_f64().unwrap(),
        direct["beta"].as_f64().unwrap(),
    );
    assert_eq!((pfv.n, pfv.unit.as_str(), pfv.rank), (3, "cm/s", None));
    assert!(
        (pfv.median.unwrap() / median - 1.0).abs() < 1e-9,
        "{pfv:?} {direct}"
    );
    assert!(
        (pfv.beta * (2.0f64 / 3.0).sqrt() / beta - 1.0).abs() < 1e-6,
        "{pfv:?} {direct}"
    );
    // The ground's PGV is another number (the building amplifies), ranked.
    assert!(row("pgv").rank.is_some() && row("pgv").median != pfv.median);
    assert!(report.contains("PFV (cm/s): median, β"), "{report}");
    assert!(
        report.contains(&format!("| rack | {:.3} |", row("pfv").p)),
        "{report}"
    );

    let from = floor.to_str().unwrap();
    let base = [
        "fragility",
        "--b",
        "0.3",
        "--h",
        "1",
        "--eps",
        "0.75",
        "--pga",
        "0.1,0.3",
        "--json",
    ];
    let mut args = base.to_vec();
    args.extend(["--from", from, "--outputs", out_s]);
    let out = rocking(dir.path(), &args);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("add --direct"), "{}", stderr(&out));
    args.push("--direct");
    let by_study = json(&rocking(dir.path(), &args));
    assert_eq!(by_study["floor"], "0.5,0.05,1.3; 0.2,0.05,-0.3");
    assert_eq!(by_study["source"], "direct");
    let mut args = base.to_vec();
    args.extend([
        "--from",
        from,
        "--outputs",
        out_s,
        "--direct",
        "--floor",
        "1,0.05,1",
    ]);
    let out = rocking(dir.path(), &args);
    assert!(
        stderr(&out).contains("has its own building"),
        "{}",
        stderr(&out)
    );
    // The rack's share at each PGA: its study capacities restated in the ground's η.
    let alpha = (0.3f64).atan();
    for (i, x) in [0.1, 0.3].iter().enumerate() {
        let rack: Vec<&rocking::tables::sweep::CapacityRow> =
            on_floor.iter().filter(|c| c.block == "rack").collect();
        let over = rack
            .iter()
            .filter(|c| {
                c.eta_c
                    .is_some_and(|e| alpha / (e * c.pfa_over_pga.unwrap()) <= *x)
            })
            .count();
        let share = by_study["points"][i]["empirical"].as_f64().unwrap();
        assert_eq!(share, over as f64 / 3.0, "PGA {x}");
    }

    let pulses = dir.path().join("pulse-floor.toml");
    std::fs::write(
        &pulses,
        "[pulses]\nshape = \"rect\"\nf = [1.0]\neta = [0.5]\neps = [0.9]\n\
         [floor]\nmodes = [[0.5, 0.05, 1.3]]\n",
    )
    .unwrap();
    let out = rocking(
        dir.path(),
        &["run", pulses.to_str().unwrap(), "--outputs", out_s],
    );
    assert!(
        stderr(&out).contains("runs no records: remove [floor]"),
        "{}",
        stderr(&out)
    );
    for (body, says) in [
        (
            "[floor]\nmodes = [[0.5, 0.05]]\n",
            "`floor.modes[0]` has 2 numbers",
        ),
        (
            "[floor]\nmodes = [[0.5, 1.2, 1.0]]\n",
            "`floor.modes`: mode 1: damping ratio ζ = 1.2",
        ),
        (
            "[floor]\nmodes = []\n",
            "`floor.modes`: a floor needs at least one mode",
        ),
        (
            "[[block]]\nb = 0.3\nh = 1.0\neps = 0.75\nmu = -0.4\n",
            "`block[0].mu`: friction coefficient μ = -0.4",
        ),
    ] {
        let body = if body.starts_with("[floor]") {
            format!("{ids}{blocks}{body}")
        } else {
            format!("{ids}{body}")
        };
        let bad = write_pipeline(dir.path(), "bad", &body);
        let out = rocking(
            dir.path(),
            &["run", bad.to_str().unwrap(), "--outputs", out_s],
        );
        assert!(!out.status.success(), "{body}");
        assert!(stderr(&out).contains(says), "{body}: {}", stderr(&out));
    }
}

/// Through a building whose floor is a node of its mode (Γφ = 0), the
/// records' capacities are the ground's: `fragility --direct --im pgv`
/// gives the ground's lognormal to the bit, and `export --direct` the
/// ground's fragility file but for its description, which names the floor.
#[test]
fn a_node_floor_gives_the_grounds_fragility_in_any_im_and_export() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW);
    let few_s = few.to_str().unwrap();
    let block = ["--b", "0.1", "--h", "1", "--eps", "0.85"];
    let pgv = |floor: Option<&str>| {
        let mut args = vec![
            "fragility",
            "--direct",
            "--records",
            few_s,
            "--im",
            "pgv",
            "--at",
            "20,60",
            "--json",
        ];
        args.extend(block);
        if let Some(f) = floor {
            args.extend(["--floor", f]);
        }
        json(&rocking(&root(), &args))
    };
    let (g, n, f) = (
        pgv(None),
        pgv(Some("0.5,0.05,0")),
        pgv(Some("0.5,0.05,1.3")),
    );
    assert_eq!((&n["median"], &n["beta"]), (&g["median"], &g["beta"]));
    assert_ne!(f["median"], g["median"]);
    let export = |floor: Option<&str>, out: &str| {
        let out = dir.path().join(out);
        let mut args = vec![
            "export",
            "--format",
            "nrml",
            "--direct",
            "--records",
            few_s,
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(block);
        if let Some(f) = floor {
            args.extend(["--floor", f]);
        }
        let run = rocking(&root(), &args);
        assert!(run.status.success(), "{}", stderr(&run));
        std::fs::read_to_string(out.join(rocking::export::nrml::FRAGILITY_FILE)).unwrap()
    };
    let (g, n) = (export(None, "ground"), export(Some("0.5,0.05,0"), "node"));
    assert!(n.contains("on the floor of a building of modes T,zeta,Gamma-phi = 0.5,0.05,0"));
    let body = |x: &str| {
        x.lines()
            .filter(|l| !l.contains("<description>"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(body(&g), body(&n));
}

/// Fragilities in floor demands (FEMA P-58's PFA and PFV): the floor
/// motions written as AT2 files and run as records on the ground give the
/// same PFA and PFV fragilities as the block on that floor, to the bit
/// (the demand is the floor motion's own, not restated in the ground's);
/// each floor motion's PFV equals the test's own integration of it (exact
/// for a piecewise-linear acceleration: trapezoids at the samples, the
/// parabola's vertex where the acceleration changes sign inside an
/// interval). On the ground, PFA and PFV are PGA and PGV. Without
/// `--direct` they are refused: a study's tables are the ground's.
#[test]
fn floor_demands_are_the_floor_motions_own() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW[..3]);
    let mode = "0.5,0.05,1.3";
    let building = rocking::floor::Building::new(vec![mode.parse().unwrap()]).unwrap();
    let floors = dir.path().join("floors");
    std::fs::create_dir(&floors).unwrap();
    let mut pfv_by_hand = Vec::new();
    for id in &FEW[..3] {
        let record = few.join(format!("{id}.AT2"));
        let (_, dt) = rocking::records::read_samples(&record).unwrap();
        let f = building
            .floor_motion(&plain_at2_values(&record), dt)
            .unwrap();
        write_at2(&floors.join(format!("{id}.AT2")), &f.accel_g, f.dt_s);
        pfv_by_hand.push(peak_velocity(&f.accel_g, f.dt_s) * 980.665);
    }
    for (k, id) in FEW[..3].iter().enumerate() {
        let path = floors.join(format!("{id}.AT2"));
        let ims = json(&rocking(
            &root(),
            &["ims", "--record", path.to_str().unwrap(), "--json"],
        ));
        let pfv = ims["pgv_cm_s"].as_f64().unwrap();
        assert!(
            (pfv / pfv_by_hand[k] - 1.0).abs() < 1e-12,
            "{id}: {pfv} against {}",
            pfv_by_hand[k]
        );
    }
    let fragility = |records: &Path, im: &str, at: &str, floor: Option<&str>| {
        let mut args = vec![
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--im",
            im,
            "--at",
            at,
            "--records",
            records.to_str().unwrap(),
            "--json",
        ];
        if let Some(m) = floor {
            args.extend(["--floor", m]);
        }
        json(&rocking(&root(), &args))
    };
    for (im, at) in [("pfa", "0.3,0.6"), ("pfv", "30,60")] {
        let on = fragility(&few, im, at, Some(mode));
        let as_records = fragility(&floors, im, at, None);
        assert_eq!(on["im"], im);
        for key in ["median", "beta", "points"] {
            assert_eq!(on[key], as_records[key], "{im}: {key}");
        }
        // Not the ground's: the same block's PGA or PGV fragility on that
        // floor is another curve.
        let ground_im = if im == "pfa" { "pga" } else { "pgv" };
        let ground = fragility(&few, ground_im, at, Some(mode));
        assert_ne!(on["median"], ground["median"], "{im}");
        // On the ground the demand is the ground's own motion.
        let (a, b) = (
            fragility(&few, im, at, None),
            fragility(&few, ground_im, at, None),
        );
        assert_eq!(
            (&a["median"], &a["beta"]),
            (&b["median"], &b["beta"]),
            "{im}"
        );
    }
    let out = rocking(
        &root(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--im",
            "pfv",
            "--at",
            "40",
        ],
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("PFV is a demand of the motion the block stands on"),
        "{}",
        stderr(&out)
    );
}

/// A structural model's floor motions as text: each record's floor motion
/// (the modal building's, so that an independent truth exists) written as
/// an OpenSees `Node` recorder with `-time` would write it (time from one
/// step, three columns: another node, the floor's acceleration in m/s²,
/// another dof) and as a two-column CSV in g with a header line. Read with
/// `--records-unit` (and `--records-column 2`), both give the capacities
/// the same block has with `--floor` on the ground records: the CSV in g
/// to 1e-9 (its times' mean step differs from the filter's by ulps), the
/// recorder's m/s² to 1e-9 (one rounding per sample). Bad files and
/// requests are refused naming the file and line, or the options.
#[test]
fn a_structural_models_floor_motions_are_read_as_text() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW[..3]);
    let mode = "0.5,0.05,1.3";
    let building = rocking::floor::Building::new(vec![mode.parse().unwrap()]).unwrap();
    let (recorder, csv) = (dir.path().join("recorder"), dir.path().join("csv"));
    std::fs::create_dir(&recorder).unwrap();
    std::fs::create_dir(&csv).unwrap();
    for id in &FEW[..3] {
        let record = few.join(format!("{id}.AT2"));
        let (_, dt) = rocking::records::read_samples(&record).unwrap();
        let f = building
            .floor_motion(&plain_at2_values(&record), dt)
            .unwrap();
        let (mut out, mut two) = (String::new(), String::from("time_s,accel_g\n"));
        for (i, a) in f.accel_g.iter().enumerate() {
            let t = (i + 1) as f64 * f.dt_s;
            out.push_str(&format!("{t} {} {} 7\n", 0.5 * a, a * 9.80665));
            two.push_str(&format!("{t},{a}\n"));
        }
        std::fs::write(recorder.join(format!("{id}.out")), out).unwrap();
        std::fs::write(csv.join(format!("{id}.csv")), two).unwrap();
    }
    let fragility = |extra: &[&str]| {
        let mut args = vec![
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--im",
            "pfv",
            "--at",
            "30,60",
            "--json",
        ];
        args.extend(extra);
        let out = rocking(&root(), &args);
        assert!(out.status.success(), "{}", stderr(&out));
        (json(&out), stderr(&out))
    };
    let few_s = few.to_str().unwrap();
    let (on, _) = fragility(&["--records", few_s, "--floor", mode]);
    let close = |a: &Value, b: &Value, what: &str| {
        let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
        assert!(
            (a - b).abs() <= 1e-9 * b.abs().max(1e-300),
            "{what}: {a} against {b}"
        );
    };
    for (folder, unit, column) in [(&csv, "g", "1"), (&recorder, "m/s2", "2")] {
        let (text, err) = fragility(&[
            "--records",
            folder.to_str().unwrap(),
            "--records-unit",
            unit,
            "--records-column",
            column,
        ]);
        close(&text["median"], &on["median"], unit);
        close(&text["beta"], &on["beta"], unit);
        for k in 0..2 {
            close(
                &text["points"][k]["probability"],
                &on["points"][k]["probability"],
                unit,
            );
        }
        assert!(
            text["records_folder"]
                .as_str()
                .unwrap()
                .contains(&format!("text columns in {unit}, value column {column}")),
            "{text}"
        );
        assert!(err.contains("each scaled itself"), "{err}");
    }
    // Refusals: a column without a unit; a bad line, named.
    let out = rocking(
        &root(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--pga",
            "0.3",
            "--records",
            few_s,
            "--records-column",
            "2",
        ],
    );
    assert!(!out.status.success());
    assert!(stderr(&out).contains("--records-unit"), "{}", stderr(&out));
    let bad = dir.path().join("bad");
    std::fs::create_dir(&bad).unwrap();
    std::fs::write(bad.join("floor3.txt"), "0.01 0.1\n0.02 x\n").unwrap();
    let out = rocking(
        &root(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--pga",
            "0.3",
            "--records",
            bad.to_str().unwrap(),
            "--records-unit",
            "g",
        ],
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("floor3.txt:2: `x` is not a finite number"),
        "{}",
        stderr(&out)
    );
    // A recorder's time in milliseconds, a column of zeros (a support's
    // node) and values in gal read as g each ran as a record: 1000 times
    // too slow, never lifting the block, or hundreds of g.
    for (body, says) in [
        (
            "5 0.1\n10 0.2\n15 0.1\n",
            "floor3.txt:2: a time step of 5e0 s",
        ),
        (
            "0.01 0\n0.02 0\n0.03 0\n",
            "floor3.txt: every acceleration is 0",
        ),
        ("0.01 12\n0.02 -245.2\n", "floor3.txt:1: 1.2e1 g, past 10 g"),
    ] {
        std::fs::write(bad.join("floor3.txt"), body).unwrap();
        let out = rocking(
            &root(),
            &[
                "fragility",
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--direct",
                "--pga",
                "0.3",
                "--records",
                bad.to_str().unwrap(),
                "--records-unit",
                "g",
            ],
        );
        assert!(!out.status.success(), "{body}");
        assert!(stderr(&out).contains(says), "{}", stderr(&out));
    }
}

/// `rocking contents` states each FEMA P-58 item's fragility as the block's
/// one fragility: a row equals `fragility --im pfv --direct
/// --if-not-lognormal lognormal` for the item's sizes (from the
/// description: 12-5/8 in deep × 56 in tall for E.20.22.104a), on the
/// ground and on the roof of the modal building, to the bit; FEMA's median
/// and β are the library's (0.361 m/s, 0.5).
#[test]
fn fema_contents_rows_are_the_blocks_own_fragility() {
    let far = bundled_records().join("far-field");
    let set = format!("far={}", far.display());
    let out = rocking(
        &root(),
        &["contents", "--set", &set, "--periods", "0.8", "--json"],
    );
    assert!(!stderr(&out).contains("warning"), "{}", stderr(&out));
    let rows = json(&out);
    let rows = rows.as_array().unwrap();
    assert_eq!(rows.len(), 2 * 9);
    let (b, h) = (0.5 * 12.625 * 0.0254, 0.5 * 56.0 * 0.0254);
    for (scene, floor) in [("ground", None), ("roof", Some("0.8,0.05,1.3"))] {
        let row = rows
            .iter()
            .find(|r| r["id"] == "E.20.22.104a" && r["scene"] == scene)
            .unwrap();
        assert_eq!(row["fema_median_mps"].as_f64(), Some(0.361));
        assert_eq!(row["fema_beta"].as_f64(), Some(0.5));
        let (b_s, h_s) = (b.to_string(), h.to_string());
        let mut args = vec![
            "fragility",
            "--b",
            &b_s,
            "--h",
            &h_s,
            "--direct",
            "--records",
            far.to_str().unwrap(),
            "--im",
            "pfv",
            "--at",
            "50",
            "--if-not-lognormal",
            "lognormal",
            "--json",
        ];
        if let Some(f) = floor {
            args.extend(["--floor", f]);
        }
        let f = json(&rocking(&root(), &args));
        assert_eq!(
            row["median_mps"].as_f64().unwrap(),
            f["median"].as_f64().unwrap() / 100.0,
            "{scene}"
        );
        assert_eq!(row["beta"], f["beta"], "{scene}");
        assert_eq!(row["b_m"].as_f64(), Some(b));
        assert_eq!(row["h_m"].as_f64(), Some(h));
    }
}

/// One record's capacities have no dispersion: `fragility` warns that its
/// β = 0 is a step, not a certainty, and `contents` printed the same β = 0
/// for every item without it. It now gives the fragility's warning once per
/// scene, naming the items (here all nine); with the records a set should
/// have it says nothing (the far-field set, above).
#[test]
fn contents_warns_as_fragility_does() {
    let dir = tempdir();
    let one = few_far_field(dir.path(), &FEW[..1]);
    let set = format!("one={}", one.display());
    let out = rocking(
        &root(),
        &["contents", "--set", &set, "--periods", "0.8", "--json"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let rows = json(&out);
    assert!(rows.as_array().unwrap().iter().all(|r| r["beta"] == 0.0));
    let err = stderr(&out);
    let fitted = "`overturned` is fitted to the capacity of one record";
    for place in [
        "on the ground under one",
        "on the roof of T = 0.8 s under one",
    ] {
        let line = format!("warning: {place} (every item): {fitted}");
        assert_eq!(err.matches(&line).count(), 1, "{err}");
    }
    let (b, h) = ("0.2032", "0.4572");
    let f = rocking(
        &root(),
        &[
            "fragility",
            "--b",
            b,
            "--h",
            h,
            "--direct",
            "--records",
            one.to_str().unwrap(),
            "--im",
            "pfv",
            "--at",
            "50",
        ],
    );
    assert!(stderr(&f).contains(fitted), "{}", stderr(&f));
}

/// A building with its floors: `--building T,ζ,Γ,φ1,…,φn --level k` is the
/// one-floor case with Γφ = Γ·φ_k for each mode, so every floor's
/// fragility comes from one description: floor 2 of a two-mode building
/// (Γ 1.25 and −0.35, shapes 0.45,0.8,1 and 1,−0.5,−1) equals `--floor
/// 0.5,0.05,1.0 --floor 0.18,0.05,0.175` to the bit, in PFV; the roof (Γφ
/// 1.25, −0.35) differs; Python takes the same keywords (tests/python).
/// Wrong levels and mixtures are refused naming the options.
#[test]
fn a_building_gives_each_floors_modes() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW[..3]);
    let few_s = few.to_str().unwrap();
    let base = [
        "fragility",
        "--b",
        "0.2",
        "--h",
        "0.9",
        "--direct",
        "--records",
        few_s,
        "--im",
        "pfv",
        "--at",
        "40,80",
        "--json",
    ];
    let modes = [
        "--building",
        "0.5,0.05,1.25,0.45,0.8,1",
        "--building",
        "0.18,0.05,-0.35,1,-0.5,-1",
    ];
    let level = |k: &str| {
        json(&rocking(
            &root(),
            &[&base[..], &modes, &["--level", k]].concat(),
        ))
    };
    let floor = json(&rocking(
        &root(),
        &[
            &base[..],
            &["--floor", "0.5,0.05,1", "--floor", "0.18,0.05,0.175"],
        ]
        .concat(),
    ));
    let two = level("2");
    for key in ["median", "beta", "points", "floor"] {
        assert_eq!(two[key], floor[key], "{key}");
    }
    assert_ne!(level("3")["median"], two["median"]);
    for (extra, says) in [
        (
            &["--level", "4"][..],
            "--level 4: the building has floors 1–3",
        ),
        (
            &[][..],
            "--building has floors 1–3: give the block's with --level",
        ),
        (
            &["--level", "2", "--floor", "0.5,0.05,1"][..],
            "--floor and --building both place the block",
        ),
    ] {
        let out = rocking(&root(), &[&base[..], &modes, extra].concat());
        assert!(!out.status.success());
        assert!(stderr(&out).contains(says), "{}", stderr(&out));
    }
    let out = rocking(
        &root(),
        &[
            &base[..],
            &[
                "--building",
                "0.5,0.05,1.25,0.45,0.8,1",
                "--building",
                "0.2,0.05,1,1",
                "--level",
                "1",
            ],
        ]
        .concat(),
    );
    assert!(
        stderr(&out).contains("mode 2 has its shape at 1 floors"),
        "{}",
        stderr(&out)
    );
}

/// Relative floor accelerations (an OpenSees `Node` recorder without
/// `-timeSeries`): each modal floor motion minus its ground record, the
/// ground linear between its samples (written here), at the floor's
/// times from 0; with `--records-ground` the ground (the AT2 records) is
/// added back at those times, and the capacities are `--floor`'s to 1e-9.
/// Without it the same files give other capacities (the relative motion),
/// and a ground folder missing a record is refused naming the file.
#[test]
fn relative_floor_motions_take_their_ground_back() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW[..3]);
    let mode = "0.5,0.05,1.3";
    let building = rocking::floor::Building::new(vec![mode.parse().unwrap()]).unwrap();
    let rel = dir.path().join("relative");
    std::fs::create_dir(&rel).unwrap();
    for id in &FEW[..3] {
        let record = few.join(format!("{id}.AT2"));
        let ground = plain_at2_values(&record);
        let (_, dt) = rocking::records::read_samples(&record).unwrap();
        let f = building.floor_motion(&ground, dt).unwrap();
        let mut out = String::new();
        for (i, a) in f.accel_g.iter().enumerate() {
            let t = i as f64 * f.dt_s;
            let x = t / dt;
            let k = x.floor() as usize;
            let frac = x - k as f64;
            let g = match (ground.get(k), ground.get(k + 1)) {
                (Some(&a0), Some(&a1)) => a0 + (a1 - a0) * frac,
                (Some(&a0), None) if frac < 1e-9 => a0,
                _ => 0.0,
            };
            out.push_str(&format!("{t} {}\n", (a - g) * 9.80665));
        }
        std::fs::write(rel.join(format!("{id}.out")), out).unwrap();
    }
    let fragility = |extra: &[&str]| {
        let mut args = vec![
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--im",
            "pfv",
            "--at",
            "30,60",
            "--json",
        ];
        args.extend(extra);
        rocking(&root(), &args)
    };
    let on = json(&fragility(&[
        "--records",
        few.to_str().unwrap(),
        "--floor",
        mode,
    ]));
    let rel_s = rel.to_str().unwrap();
    let text = ["--records", rel_s, "--records-unit", "m/s2"];
    let back = json(&fragility(
        &[&text[..], &["--records-ground", few.to_str().unwrap()]].concat(),
    ));
    for key in ["median", "beta"] {
        let (a, b) = (back[key].as_f64().unwrap(), on[key].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * b, "{key}: {a} against {b}");
    }
    let alone = json(&fragility(&text));
    assert!(
        (alone["median"].as_f64().unwrap() / on["median"].as_f64().unwrap() - 1.0).abs() > 1e-3
    );
    // Without the ground the answer warns that the files were read as
    // absolute accelerations; with it, it does not.
    let warned = |v: &serde_json::Value| {
        v["warnings"].as_array().unwrap().iter().any(|w| {
            w.as_str()
                .unwrap()
                .contains("read as absolute accelerations")
        })
    };
    assert!(warned(&alone), "{alone}");
    assert!(!warned(&back), "{back}");
    let partial = dir.path().join("partial");
    std::fs::create_dir(&partial).unwrap();
    std::fs::copy(
        few.join(format!("{}.AT2", FEW[0])),
        partial.join(format!("{}.AT2", FEW[0])),
    )
    .unwrap();
    let out = fragility(&[&text[..], &["--records-ground", partial.to_str().unwrap()]].concat());
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains(&format!(
            "{}.out: no ground motion of the same name",
            FEW[1]
        )),
        "{}",
        stderr(&out)
    );
    // A ground of its name twice (AT2 and text) is ambiguous, and one whose
    // times start after the record's would be 0 before them: both refused
    // (the doubled text was passed over; the offset halved a capacity).
    let twice = dir.path().join("twice");
    std::fs::create_dir(&twice).unwrap();
    for id in &FEW[..3] {
        let name = format!("{id}.AT2");
        std::fs::copy(few.join(&name), twice.join(&name)).unwrap();
    }
    let record = few.join(format!("{}.AT2", FEW[0]));
    let (_, dt) = rocking::records::read_samples(&record).unwrap();
    let as_text = |t0: f64| -> String {
        let values = plain_at2_values(&record);
        let rows = values.iter().enumerate();
        rows.map(|(i, a)| format!("{} {}\n", t0 + i as f64 * dt, a * 9.80665))
            .collect()
    };
    std::fs::write(twice.join(format!("{}.txt", FEW[0])), as_text(0.0)).unwrap();
    let out = fragility(&[&text[..], &["--records-ground", twice.to_str().unwrap()]].concat());
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("two ground motions of its name in"),
        "{}",
        stderr(&out)
    );
    let late = dir.path().join("late");
    std::fs::create_dir(&late).unwrap();
    for id in &FEW[1..3] {
        let name = format!("{id}.AT2");
        std::fs::copy(few.join(&name), late.join(&name)).unwrap();
    }
    std::fs::write(late.join(format!("{}.txt", FEW[0])), as_text(5.0)).unwrap();
    let out = fragility(&[&text[..], &["--records-ground", late.to_str().unwrap()]].concat());
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("its ground starts at 5"),
        "{}",
        stderr(&out)
    );
    // The same ground as text from time 0 is the AT2's.
    std::fs::write(late.join(format!("{}.txt", FEW[0])), as_text(0.0)).unwrap();
    let out = fragility(&[&text[..], &["--records-ground", late.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    let (a, b) = (
        json(&out)["median"].as_f64().unwrap(),
        on["median"].as_f64().unwrap(),
    );
    assert!((a - b).abs() <= 1e-9 * b, "median: {a} against {b}");
    // Relative floor motions with their ground, and a building besides:
    // they went through it twice (a PFA median three times the floor's),
    // refused; absolute text through a building is its ground, warned.
    let ground = ["--records-ground", few.to_str().unwrap()];
    let out = fragility(&[&text[..], &ground, &["--floor", mode]].concat());
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("they would go through it twice"),
        "{}",
        stderr(&out)
    );
    let as_ground = json(&fragility(&[&text[..], &["--floor", mode]].concat()));
    let warned = as_ground["warnings"].as_array().unwrap().iter().any(|w| {
        w.as_str()
            .unwrap()
            .contains("run through the building (--floor or --building) as its ground motions")
    });
    assert!(warned, "{as_ground}");
}

/// The floor's spectral acceleration, FSA(T): on a floor it is the SA of
/// the floor motion, so the block's fragility in fsa(T) with `--floor`
/// equals its fragility in sa(T) under the floor motions written as AT2
/// files and run as records, to the bit, at a standard period (1.0 s) and
/// at one the records' tables lack (0.7 s, computed when asked).
#[test]
fn floor_spectral_acceleration_is_the_floor_motions_sa() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW[..3]);
    let mode = "0.5,0.05,1.3";
    let building = rocking::floor::Building::new(vec![mode.parse().unwrap()]).unwrap();
    let floors = dir.path().join("floors");
    std::fs::create_dir(&floors).unwrap();
    for id in &FEW[..3] {
        let record = few.join(format!("{id}.AT2"));
        let (_, dt) = rocking::records::read_samples(&record).unwrap();
        let f = building
            .floor_motion(&plain_at2_values(&record), dt)
            .unwrap();
        write_at2(&floors.join(format!("{id}.AT2")), &f.accel_g, f.dt_s);
    }
    let fragility = |records: &Path, im: &str, floor: Option<&str>| {
        let mut args = vec![
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--im",
            im,
            "--at",
            "0.4,0.8",
            "--records",
            records.to_str().unwrap(),
            "--json",
        ];
        if let Some(m) = floor {
            args.extend(["--floor", m]);
        }
        json(&rocking(&root(), &args))
    };
    for t in ["1.0", "0.7"] {
        let on = fragility(&few, &format!("fsa({t})"), Some(mode));
        let as_records = fragility(&floors, &format!("sa({t})"), None);
        for key in ["median", "beta", "points"] {
            assert_eq!(on[key], as_records[key], "fsa({t}): {key}");
        }
        // The ground's SA of the same block on that floor is another curve.
        let ground = fragility(&few, &format!("sa({t})"), Some(mode));
        assert_ne!(on["median"], ground["median"], "{t}");
    }
}

/// A pipeline over a structural model's floor motions: `[records] text =
/// [...]` with `unit` (and `column`) runs the same study as the floor
/// motions written as AT2 files (`at2 = [...]`): every capacity and η equal
/// to the bit (the text in g, read back exactly); the records table says
/// how each was read; `unit` is required and refused with the valid ones.
/// The text study's tables name its measures the floor's: `record_ims`,
/// `im_efficiency` and `damage_states` hold `pfa`, `pfv` and `fsa(T)` only,
/// each equal to the AT2 study's `pga`, `pgv` and `sa(T)` of the same
/// motions (to 1e-12), and its report says PFA where the AT2 one says PGA.
#[test]
fn a_pipeline_reads_a_structural_models_floor_motions() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW[..3]);
    let building = rocking::floor::Building::new(vec!["0.5,0.05,1.3".parse().unwrap()]).unwrap();
    let (at2, text) = (dir.path().join("at2"), dir.path().join("text"));
    std::fs::create_dir(&at2).unwrap();
    std::fs::create_dir(&text).unwrap();
    for id in &FEW[..3] {
        let record = few.join(format!("{id}.AT2"));
        let (_, dt) = rocking::records::read_samples(&record).unwrap();
        let f = building
            .floor_motion(&plain_at2_values(&record), dt)
            .unwrap();
        write_at2(&at2.join(format!("{id}.AT2")), &f.accel_g, f.dt_s);
        let mut out = String::from("# node 3, absolute acceleration (g)\n");
        for (i, a) in f.accel_g.iter().enumerate() {
            out.push_str(&format!("{} 0 {a}\n", i as f64 * f.dt_s));
        }
        std::fs::write(text.join(format!("{id}.out")), out).unwrap();
    }
    let blocks =
        "[model]\nkind = \"auto\"\n[[block]]\nname = \"rack\"\nb = 0.3\nh = 1.0\neps = 0.75\n";
    let write = |name: &str, records: String| {
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(
            &path,
            format!("name = \"{name}\"\n[records]\n{records}{blocks}"),
        )
        .unwrap();
        path
    };
    let a = write("as-at2", format!("at2 = [\"{}\"]\n", at2.display()));
    let a_path = a.clone();
    let t = write(
        "as-text",
        format!(
            "text = [\"{}\"]\nunit = \"g\"\ncolumn = 2\n",
            text.display()
        ),
    );
    let outputs = dir.path().join("out");
    for p in [&a, &t] {
        let out = rocking(
            dir.path(),
            &[
                "run",
                p.to_str().unwrap(),
                "--outputs",
                outputs.to_str().unwrap(),
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
    }
    floor_names_of_text_studies(&outputs.join("as-at2"), &outputs.join("as-text"));
    let caps = |name: &str| rocking::stages::sweep::read_capacities(&outputs.join(name)).unwrap();
    let (from_at2, from_text) = (caps("as-at2"), caps("as-text"));
    assert_eq!(from_at2.len(), 3);
    for (x, y) in from_at2.iter().zip(&from_text) {
        assert_eq!(x.record_id, y.record_id);
        assert_eq!(
            x.eta_c.map(f64::to_bits),
            y.eta_c.map(f64::to_bits),
            "{}",
            x.record_id
        );
    }
    // The pipeline's text records are floor motions as `--records` text
    // is: a ground IM of them is refused through the study (its runs or its
    // tables) as through the folder, and its PFA fragility is the folder's.
    let block = ["--b", "0.3", "--h", "1.0", "--eps", "0.75"];
    let out_s = outputs.to_str().unwrap();
    let ask = |source: &[&str], rest: &[&str]| {
        let mut args = vec!["fragility"];
        args.extend(source);
        args.extend(block);
        args.extend(rest);
        rocking(dir.path(), &args)
    };
    let (t_s, text_s) = (t.to_str().unwrap(), text.to_str().unwrap());
    let study = ["--from", t_s, "--outputs", out_s];
    let folder = [
        "--records",
        text_s,
        "--records-unit",
        "g",
        "--records-column",
        "2",
    ];
    for rest in [
        &["--direct", "--pga", "0.5"][..],
        &["--im", "pgv", "--at", "20"][..],
    ] {
        let out = ask(&study, rest);
        assert!(!out.status.success(), "{rest:?}");
        assert!(
            stderr(&out).contains("text records are the motions the block stands on"),
            "{rest:?}: {}",
            stderr(&out)
        );
    }
    // Run through a building they are its ground motions, PGA theirs, as
    // through the folder.
    let through = [
        "--direct",
        "--pga",
        "0.5",
        "--floor",
        "0.5,0.05,1.3",
        "--json",
    ];
    let (s_floor, f_floor) = (ask(&study, &through), ask(&folder, &through));
    assert!(s_floor.status.success(), "{}", stderr(&s_floor));
    assert_eq!(json(&s_floor)["median"], json(&f_floor)["median"]);
    let pfa = ["--direct", "--im", "pfa", "--at", "0.3,0.6", "--json"];
    let (through_study, through_folder) = (ask(&study, &pfa), ask(&folder, &pfa));
    assert!(through_study.status.success(), "{}", stderr(&through_study));
    let (a, b) = (json(&through_study), json(&through_folder));
    for key in ["median", "beta", "points"] {
        assert_eq!(a[key], b[key], "{key}");
    }
    // A pipeline over the text study's records table has the same records.
    let table = outputs.join("as-text/records.parquet");
    let via = write("via-table", format!("table = \"{}\"\n", table.display()));
    let via_study = ["--from", via.to_str().unwrap(), "--outputs", out_s];
    let out = ask(&via_study, &["--direct", "--pga", "0.5"]);
    assert!(
        stderr(&out).contains("text records are the motions the block stands on"),
        "{}",
        stderr(&out)
    );
    // The same motions as AT2 files are ground motions: PGA is theirs.
    let a_s = a_path.to_str().unwrap();
    let at2_study = ask(
        &["--from", a_s, "--outputs", out_s],
        &["--direct", "--pga", "0.5"],
    );
    assert!(at2_study.status.success(), "{}", stderr(&at2_study));
    let bad = write("no-unit", format!("text = [\"{}\"]\n", text.display()));
    let out = rocking(
        dir.path(),
        &[
            "run",
            bad.to_str().unwrap(),
            "--outputs",
            outputs.to_str().unwrap(),
        ],
    );
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("`records.text` needs `unit`"),
        "{}",
        stderr(&out)
    );
}

/// The text study `text`'s tables against the AT2 study `at2` of the same
/// motions: every measure renamed to the floor's, each value and fit equal.
fn floor_names_of_text_studies(at2: &std::path::Path, text: &std::path::Path) {
    use rocking::im::Im;
    use rocking::tables::{damage::DamageStateRow, ims::EfficiencyRow, ims::RecordImRow};
    let close = |a: f64, b: f64, what: &str| {
        assert!((a - b).abs() <= 1e-12 * b.abs(), "{what}: {a} against {b}")
    };
    let floor_of = |name: &str| -> String {
        let im: Im = name.parse().unwrap();
        im.felt().map_or(String::new(), |f| f.name())
    };
    let ims: [Vec<RecordImRow>; 2] =
        [at2, text].map(|d| rocking::tables::read(&d.join("record_ims.parquet")).unwrap());
    // The floor's demands, and the measures that name no ground (Arias,
    // CAV, D5–95, Tm) as they are.
    let renamed = |name: &str| -> String {
        let im: Im = name.parse().unwrap();
        match im.of_any_motion() {
            true => name.to_string(),
            false => floor_of(name),
        }
    };
    assert!(ims[1].iter().all(|r| {
        let im = r.im.parse::<Im>().unwrap();
        im.floor() || im.of_any_motion()
    }));
    assert!(ims[1].iter().any(|r| r.im == "arias"));
    let mut wanted: Vec<(String, &RecordImRow)> = ims[0]
        .iter()
        .map(|r| (renamed(&r.im), r))
        .filter(|(name, _)| !name.is_empty())
        .collect();
    assert_eq!(wanted.len(), ims[1].len());
    let key = |id: &str, im: &str| (id.to_string(), im.to_string());
    wanted.sort_by_key(|(name, r)| key(&r.record_id, name));
    let mut got: Vec<&RecordImRow> = ims[1].iter().collect();
    got.sort_by_key(|r| key(&r.record_id, &r.im));
    for ((name, g), f) in wanted.iter().zip(&got) {
        assert_eq!(
            (name, &g.record_id, &g.unit),
            (&f.im, &f.record_id, &f.unit)
        );
        close(f.value, g.value, &f.im);
    }
    let eff: [Vec<EfficiencyRow>; 2] =
        [at2, text].map(|d| rocking::tables::read(&d.join("im_efficiency.parquet")).unwrap());
    assert!(!eff[1].is_empty());
    for f in &eff[1] {
        let g = eff[0]
            .iter()
            .find(|g| g.block == f.block && floor_of(&g.im) == f.im)
            .unwrap_or_else(|| panic!("{} {}", f.block, f.im));
        close(f.beta, g.beta, &f.im);
        close(f.median.unwrap(), g.median.unwrap(), &f.im);
    }
    // Ranked among the floor's measures: rank 1 is the smallest β.
    for f in eff[1].iter().filter(|f| f.rank == Some(1)) {
        let least = eff[1].iter().filter(|o| o.block == f.block).map(|o| o.beta);
        assert_eq!(least.fold(f64::INFINITY, f64::min), f.beta);
    }
    let states: [Vec<DamageStateRow>; 2] =
        [at2, text].map(|d| rocking::tables::read(&d.join("damage_states.parquet")).unwrap());
    assert!(!states[1].is_empty());
    assert!(states[1]
        .iter()
        .all(|r| r.im.parse::<Im>().unwrap().floor()));
    for f in &states[1] {
        let g = states[0]
            .iter()
            .find(|g| g.state == f.state && g.method == f.method && floor_of(&g.im) == f.im)
            .unwrap();
        match (f.median, g.median) {
            (Some(a), Some(b)) => close(a, b, &f.im),
            (a, b) => assert_eq!(a, b, "{} {}", f.state, f.im),
        }
    }
    let report = |d: &std::path::Path| std::fs::read_to_string(d.join("report.md")).unwrap();
    let (g, f) = (report(at2), report(text));
    assert!(g.contains("β of PGA") && !g.contains("β of PFA"));
    assert!(f.contains("β of PFA") && !f.contains("β of PGA"), "{f}");
    assert!(
        f.contains("in PFA/(αg)") && !f.contains("in PGA/(αg)"),
        "{f}"
    );
    // Its IM section ends in a blank line, as the AT2 one does (Markdown
    // read the next heading as text).
    assert!(f.contains("\n\n## Damage states"), "{f}");
    // Each block's PFA and PFV median and β, as a floor study's report
    // gives them, without the ground's columns (there is no ground).
    assert!(
        f.contains("## In the floor's demands")
            && f.contains("| PFA (g): median, β | PFV (cm/s): median, β |")
            && !f.contains("ground PGA"),
        "{f}"
    );
    assert!(!g.contains("## In the floor's demands"));
}

/// A pipeline's `[floor]` given as a building and the blocks' level is the
/// one-floor form with Γφ = Γ·φ_level of each mode: a building of two
/// floors whose floor 2 takes Γφ = 1.5 × 0.5 = 0.75 and −0.5 × 0.25 =
/// −0.125 (exact in binary) gives the capacities of `modes = [[0.5, 0.05,
/// 0.75], [0.2, 0.05, -0.125]]` to the bit; a wrong level, a building
/// without one, and both forms at once are refused by key.
#[test]
fn a_pipeline_places_its_blocks_on_a_buildings_floor() {
    use crate::util::write_pipeline;
    let dir = tempdir();
    let head = "ids = [\"RSN1111_KOBE_NIS000\", \"RSN1148_KOCAELI_ARC000\"]\n\
        [[block]]\nname = \"rack\"\nb = 0.3\nh = 1.0\neps = 0.75\n";
    let building = "building = [[0.5, 0.05, 1.5, 0.25, 0.5], [0.2, 0.05, -0.5, 0.5, 0.25]]\n";
    let by_level = write_pipeline(
        dir.path(),
        "by-level",
        &format!("{head}[floor]\n{building}level = 2\n"),
    );
    let by_modes = write_pipeline(
        dir.path(),
        "by-modes",
        &format!("{head}[floor]\nmodes = [[0.5, 0.05, 0.75], [0.2, 0.05, -0.125]]\n"),
    );
    let outputs = dir.path().join("out");
    let out_s = outputs.to_str().unwrap();
    for p in [&by_level, &by_modes] {
        let out = rocking(
            dir.path(),
            &["run", p.to_str().unwrap(), "--outputs", out_s],
        );
        assert!(out.status.success(), "{}", stderr(&out));
    }
    let caps = |name: &str| rocking::stages::sweep::read_capacities(&outputs.join(name)).unwrap();
    let (a, b) = (caps("by-level"), caps("by-modes"));
    assert_eq!(a.len(), 2);
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(
            (x.eta_c, x.pfa_over_pga, x.runs),
            (y.eta_c, y.pfa_over_pga, y.runs)
        );
        assert!(x.pfa_over_pga.is_some_and(|r| r != 1.0));
    }
    for (body, says) in [
        (
            format!("{building}level = 3\n"),
            "`floor.level` = 3: the building has floors 1–2",
        ),
        (building.to_string(), "give the blocks' `floor.level`"),
        (
            format!("{building}level = 1\nmodes = [[0.5, 0.05, 1.3]]\n"),
            "`floor.modes` and `floor.building` both place the blocks",
        ),
        (
            "building = [[0.5, 0.05, 1.5, 0.25, 0.5], [0.2, 0.05, -0.5, 0.5]]\nlevel = 1\n"
                .to_string(),
            "mode 2 has its shape at 1 floors, mode 1 at 2",
        ),
    ] {
        let bad = write_pipeline(dir.path(), "bad", &format!("{head}[floor]\n{body}"));
        let out = rocking(
            dir.path(),
            &["run", bad.to_str().unwrap(), "--outputs", out_s],
        );
        assert!(!out.status.success(), "{body}");
        assert!(stderr(&out).contains(says), "{body}: {}", stderr(&out));
    }
}

/// A pipeline's `[floor]` reached the OpenQuake export through `--from
/// PIPELINE --direct` without its cut: the export wrote the ground's
/// noDamageLimit (g·tan α) for a block on the floor, where `risk` and
/// `fragility` count below it (2–2.7× the rate apart). The study's floor and
/// records, and the same given as `--floor` and `--records`, write the same
/// fragility model, with no noDamageLimit (the floor moves otherwise than
/// the ground).
#[test]
fn a_pipelines_floor_exports_as_the_same_floor_given_by_hand() {
    let dir = tempdir();
    let d = dir.path();
    let hazard = root().join("records/hazard/synthetic-openquake.csv");
    let hazard = hazard.to_str().unwrap();
    let pipeline = root().join("pipelines/floor.toml");
    let far = bundled_records().join("far-field");
    let by_hand = [
        "--floor",
        "0.5,0.05,1.3",
        "--records",
        far.to_str().unwrap(),
    ];
    let from = ["--from", pipeline.to_str().unwrap(), "--outputs", "o"];
    for (out, floor) in [("study", &from[..]), ("by-hand", &by_hand[..])] {
        let mut args = vec![
            "export", "--format", "nrml", "--b", "0.2", "--h", "0.9", "--direct", "--hazard",
            hazard, "--out", out,
        ];
        args.extend(floor);
        let o = rocking(d, &args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let study = std::fs::read_to_string(d.join("study/fragility_model.xml")).unwrap();
    let by_hand = std::fs::read_to_string(d.join("by-hand/fragility_model.xml")).unwrap();
    assert!(!study.contains("noDamageLimit"), "{study}");
    assert_eq!(study, by_hand);
}

/// On a floor, `fragility` states η_c as α/PGA of the ground (its levels
/// are the ground's) where `capacity --floor` states the floor's α/PFA; the
/// shared name read as one quantity. The text says whose it is, and the
/// value is α over the median PGA it prints (η = αg/PGA by hand).
#[test]
fn a_floors_eta_c_says_whose_it_is() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW[..3]);
    let out = rocking(
        &root(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
            few.to_str().unwrap(),
            "--floor",
            "0.5,0.05,1.3",
            "--pga",
            "0.3",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let number = |after: &str| -> f64 {
        let rest = text
            .split(after)
            .nth(1)
            .unwrap_or_else(|| panic!("{after}: {text}"));
        rest.split([' ', ',']).next().unwrap().parse().unwrap()
    };
    let eta = number("median η_c = ");
    assert!(
        text.contains("median η_c = ") && text.contains(" (α/PGA of the ground), median "),
        "{text}"
    );
    let pga = number("(α/PGA of the ground), median ");
    let alpha = (0.2f64 / 0.9).atan();
    assert!(
        (eta - alpha / pga).abs() <= 1e-3 * eta,
        "{eta} against {alpha}/{pga}"
    );
    let cap = rocking(
        &root(),
        &[
            "capacity",
            "--record",
            few.join("RSN1111_KOBE_NIS000.AT2").to_str().unwrap(),
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--eps",
            "0.8",
            "--floor",
            "0.5,0.05,1.3",
        ],
    );
    assert!(
        stdout(&cap).contains("η is the floor's"),
        "{}",
        stdout(&cap)
    );
    // On the ground there is one η_c, and nothing to say.
    let ground = rocking(
        &root(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
            few.to_str().unwrap(),
            "--pga",
            "0.3",
        ],
    );
    assert!(
        !stdout(&ground).contains("of the ground"),
        "{}",
        stdout(&ground)
    );
}

/// Text records are the motions the block stands on, each scaled to its own
/// peak: a fragility of them in PGA was the floor's PFA labelled the
/// ground's (a floor at twice its ground gave the ground's answer, and
/// `risk` against a ground-PGA hazard a rate 14× off a modal building's).
/// A ground IM of text records is refused in `fragility`, `risk` and
/// `export`; in PFA they are the motions' own peaks: the same records
/// written as text give in PFA what their AT2 files give in PGA, to 1e-9.
#[test]
fn text_records_are_not_stated_in_a_ground_im() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW[..3]);
    let text = dir.path().join("text");
    std::fs::create_dir(&text).unwrap();
    for id in &FEW[..3] {
        let record = few.join(format!("{id}.AT2"));
        let (_, dt) = rocking::records::read_samples(&record).unwrap();
        let body: String = plain_at2_values(&record)
            .iter()
            .enumerate()
            .map(|(i, a)| format!("{} {a}\n", i as f64 * dt))
            .collect();
        std::fs::write(text.join(format!("{id}.txt")), body).unwrap();
    }
    let (few_s, text_s) = (few.to_str().unwrap(), text.to_str().unwrap());
    let block = ["--b", "0.2", "--h", "0.9", "--direct"];
    let as_text = ["--records", text_s, "--records-unit", "g"];
    let hazard = root().join("records/hazard/synthetic-site.csv");
    let out_dir = dir.path().join("x");
    for command in [
        &["fragility", "--pga", "0.3"][..],
        &["risk", "--hazard", hazard.to_str().unwrap()],
        &[
            "export",
            "--format",
            "pelicun",
            "--out",
            out_dir.to_str().unwrap(),
        ],
    ] {
        let out = rocking(&root(), &[command, &block, &as_text].concat());
        assert!(!out.status.success(), "{command:?}");
        assert!(
            stderr(&out).contains("PGA is a measure of the ground's motion, and text records"),
            "{command:?}: {}",
            stderr(&out)
        );
    }
    assert!(!out_dir.exists());
    let fragility = |extra: &[&str]| {
        json(&rocking(
            &root(),
            &[&["fragility", "--json"][..], &block, extra].concat(),
        ))
    };
    let pfa = fragility(&[&as_text[..], &["--im", "pfa", "--at", "0.3"]].concat());
    let pga = fragility(&["--records", few_s, "--pga", "0.3"]);
    // The folder without its unit: no AT2 files, and the text ones named.
    let out = rocking(
        &root(),
        &[
            &["fragility", "--pga", "0.3"][..],
            &block,
            &["--records", text_s],
        ]
        .concat(),
    );
    assert!(
        stderr(&out).contains("but 3 text motion file(s)")
            && stderr(&out).contains("--records-unit"),
        "{}",
        stderr(&out)
    );
    // One of them given to `capacity`, which reads AT2 files: said so.
    let one = text.join(format!("{}.txt", FEW[0]));
    let out = rocking(
        &root(),
        &[
            &[
                "capacity",
                "--record",
                one.to_str().unwrap(),
                "--eps",
                "0.8",
            ][..],
            &block[..4],
        ]
        .concat(),
    );
    assert!(
        stderr(&out).contains("a text motion file? this command reads AT2 files"),
        "{}",
        stderr(&out)
    );
    for key in ["median", "beta"] {
        let (a, b) = (pfa[key].as_f64().unwrap(), pga[key].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * b, "{key}: {a} against {b}");
    }
}

/// A pelicun export of a block on a floor says whose motion its IM is of:
/// the floor's for PFA and PFV (it said "IMs of the ground" whatever the
/// IM), the ground's for PGA.
#[test]
fn a_floor_export_names_whose_motion_its_im_is_of() {
    let dir = tempdir();
    let few = few_far_field(dir.path(), &FEW[..3]);
    for (im, whose) in [
        ("pfv", "(IMs of the floor's motion)"),
        ("pfa", "(IMs of the floor's motion)"),
        ("pga", "(IMs of the ground)"),
    ] {
        let out_dir = dir.path().join(im);
        let out = rocking(
            &root(),
            &[
                "export",
                "--format",
                "pelicun",
                "--b",
                "0.16",
                "--h",
                "0.71",
                "--direct",
                "--records",
                few.to_str().unwrap(),
                "--floor",
                "0.8,0.05,1.0",
                "--im",
                im,
                "--out",
                out_dir.to_str().unwrap(),
            ],
        );
        assert!(out.status.success(), "{im}: {}", stderr(&out));
        let meta = std::fs::read_to_string(out_dir.join("fragility.json")).unwrap();
        assert!(meta.contains(whose), "{im}: {meta}");
    }
}

/// A relative text record whose times start well after its ground's, the
/// ground already moving before them: a model's recorder starts with its
/// analysis, so the two clocks are likely offset, and the floor motion
/// (record plus ground at the same times) shifted by it. Said, with the
/// file, by `--direct` and by a pipeline's ingest; the same files with one
/// clock say nothing.
#[test]
fn a_relative_record_whose_clock_looks_offset_is_said() {
    use crate::util::{write_at2, write_pipeline};
    let dir = tempdir();
    let d = dir.path();
    let dt = 0.01;
    let (ground, late, same) = (d.join("ground"), d.join("late"), d.join("same"));
    for f in [&ground, &late, &same] {
        std::fs::create_dir_all(f).unwrap();
    }
    for k in 1..=5 {
        let g: Vec<f64> = (0..1000)
            .map(|i| 0.3 * (2.0 * std::f64::consts::PI * k as f64 * i as f64 * dt).sin())
            .collect();
        write_at2(&ground.join(format!("R{k}.AT2")), &g, dt);
        for (folder, t0) in [(&late, 1.0), (&same, 0.0)] {
            let text: String = g
                .iter()
                .enumerate()
                .map(|(i, a)| format!("{:?} {:?}\n", t0 + i as f64 * dt, 0.5 * a))
                .collect();
            std::fs::write(folder.join(format!("R{k}.txt")), text).unwrap();
        }
    }
    let says = "are the two files' times of one clock";
    for (folder, offset) in [(&late, true), (&same, false)] {
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
                folder.to_str().unwrap(),
                "--records-unit",
                "g",
                "--records-ground",
                ground.to_str().unwrap(),
                "--im",
                "pfa",
                "--at",
                "0.3",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        let e = stderr(&out);
        assert_eq!(e.contains(says), offset, "{e}");
        if offset {
            assert!(e.contains("R1.txt: its first time 1 s is 1 s after"), "{e}");
        }
    }
    // A pipeline's ingest says it too.
    let pipe = write_pipeline(d, "late", "");
    let body = format!(
        "name = \"late\"\n[records]\ntext = [\"{}\"]\nunit = \"g\"\nground = \"{}\"\n[[block]]\nname = \"s\"\nb = 0.2\nh = 0.9\neps = 0.8\n",
        late.display(),
        ground.display()
    );
    std::fs::write(&pipe, body).unwrap();
    let out = rocking(
        d,
        &[
            "run",
            pipe.to_str().unwrap(),
            "--outputs",
            "out",
            "--to",
            "ingest",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains(says) || stdout(&out).contains(says),
        "{}",
        stderr(&out)
    );
}
