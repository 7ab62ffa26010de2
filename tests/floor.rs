//! A block on a building's floor, and a block that slides before it rocks,
//! through the binary: the floor motion is what runs (the same capacity as
//! the floor motion written as a record), its PFA/PGA against the samples,
//! the ground's PGA through the building's linearity; the sliding check in
//! every command that assesses a block; refusals.

use std::path::Path;

use serde_json::Value;

use crate::util::{bundled_records, plain_at2_values, rocking, root, stderr, tempdir};

fn kobe() -> std::path::PathBuf {
    bundled_records().join("far-field/RSN1111_KOBE_NIS000.AT2")
}

fn json(out: &std::process::Output) -> Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!("{e}: {}", String::from_utf8_lossy(&out.stdout));
    })
}

/// An AT2 file in the NGA-West2 layout holding `accel` (g) exactly: every
/// value in Rust's shortest round-trip form, read back correctly rounded.
fn write_at2(path: &Path, accel: &[f64], dt: f64) {
    let mut s = format!(
        "FLOOR MOTION\nTEST\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= {}, DT= {dt} SEC\n",
        accel.len()
    );
    for chunk in accel.chunks(5) {
        let line: Vec<String> = chunk.iter().map(|a| format!("{a:e}")).collect();
        s.push_str(&line.join("  "));
        s.push('\n');
    }
    std::fs::write(path, s).unwrap();
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
    let pga_c = a["pga_c_g"].as_f64().unwrap();
    let alpha = a["alpha_rad"].as_f64().unwrap();
    assert_eq!(pga_c, alpha / a["eta_c"].as_f64().unwrap());
    assert_eq!(a["ground_pga_c_g"].as_f64().unwrap(), pga_c / ratio);
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
    ] {
        let mut args = base.to_vec();
        args.extend(["--floor", floor]);
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
