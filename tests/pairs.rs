//! Record pairs through the binary: the rotated component and its
//! capacities at the axes (the components themselves, bit for bit) and at
//! θ and θ + 180°; RotD50 and RotD100 against an independent computation
//! (another oscillator integrator, the responses rotated every 1°);
//! refusals.

use serde_json::Value;

use crate::util::{bundled_records, rocking, root, stderr, tempdir, write_at2};

fn json(out: &std::process::Output) -> Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout).unwrap()
}

fn far(stem: &str) -> String {
    bundled_records()
        .join(format!("far-field/{stem}.AT2"))
        .to_string_lossy()
        .into_owned()
}

/// The relative displacement of a 5 %-damped oscillator of period `t`
/// under `a` (g), by Newmark's average-acceleration rule on `k` equal
/// sub-steps a sample (the record linear between samples): a method other
/// than the tool's exact stepping, whose period error (ωh)²/12 is below
/// 1e-5 here.
fn newmark(a: &[f64], dt: f64, t: f64, k: usize) -> Vec<f64> {
    let (w, z) = (std::f64::consts::TAU / t, 0.05);
    let h = dt / k as f64;
    let (mut u, mut v) = (0.0f64, 0.0f64);
    let mut acc = -a[0];
    let mut out = vec![0.0];
    let kk = w * w + 2.0 * z * w * 2.0 / h + 4.0 / (h * h);
    for win in a.windows(2) {
        for j in 1..=k {
            let g = win[0] + (win[1] - win[0]) * j as f64 / k as f64;
            // ü + 2ζωu̇ + ω²u = −a_g, average acceleration.
            let rhs =
                -g + (4.0 / (h * h)) * u + (4.0 / h) * v + acc + 2.0 * z * w * ((2.0 / h) * u + v);
            let un = rhs / kk;
            let vn = 2.0 / h * (un - u) - v;
            acc = 4.0 / (h * h) * (un - u) - 4.0 / h * v - acc;
            u = un;
            v = vn;
            out.push(u);
        }
    }
    out
}

/// RotD50 (mean of the 90th and 91st of 180) and RotD100 of peaks at 0–179°.
fn rotd(peaks: &mut [f64]) -> (f64, f64) {
    peaks.sort_by(f64::total_cmp);
    (0.5 * (peaks[89] + peaks[90]), peaks[179])
}

/// Kobe Nishi-Akashi (equal lengths) and Manjil Abbar (2,676 against
/// 2,300 samples: b is 0 after its end): RotD of PGA, PGV and SA at 0.2, 1
/// and 3 s from `rocking ims --pair` against the components read here,
/// padded, rotated every 1° and (for SA) each stepped by Newmark's rule at
/// 20 sub-steps a sample (PGV by the trapezoid rule on the same sub-steps),
/// within 0.1 % (SA; measured ≤ 3e-4, the sampled peaks of Newmark's
/// responses at 400 steps a period at 0.2 s) and 1e-4 (PGV; measured
/// ≤ 7e-6); PGA, whose peaks are samples, to 1e-12 (the issue asks 0.5 %).
#[test]
fn rotd_equals_an_independent_rotation_of_the_responses() {
    for (a, b) in [
        ("RSN1111_KOBE_NIS000", "RSN1111_KOBE_NIS090"),
        ("RSN1633_MANJIL_ABBAR--L", "RSN1633_MANJIL_ABBAR--T"),
    ] {
        let (a_path, b_path) = (far(a), far(b));
        let out = json(&rocking(
            &root(),
            &["ims", "--record", &a_path, "--pair", &b_path, "--json"],
        ));
        let (mut xa, dt) = rocking::records::read_samples(a_path.as_ref()).unwrap();
        let (mut xb, dt_b) = rocking::records::read_samples(b_path.as_ref()).unwrap();
        assert_eq!(dt, dt_b);
        let n = xa.len().max(xb.len());
        xa.resize(n, 0.0);
        xb.resize(n, 0.0);
        let dirs: Vec<(f64, f64)> = (0..180)
            .map(|k| {
                let r = (k as f64).to_radians();
                (r.cos(), r.sin())
            })
            .collect();
        let close = |what: &str, got: &Value, want: f64, tol: f64| {
            let got = got.as_f64().unwrap();
            eprintln!("{a} {what}: {:+.2e}", got / want - 1.0);
            assert!(
                (got / want - 1.0).abs() < tol,
                "{a} {what}: {got} against {want}"
            );
        };
        // PGA.
        let mut peaks: Vec<f64> = dirs
            .iter()
            .map(|&(c, s)| {
                xa.iter()
                    .zip(&xb)
                    .fold(0.0f64, |m, (x, y)| m.max((c * x + s * y).abs()))
            })
            .collect();
        let (d50, d100) = rotd(&mut peaks);
        close("RotD50 PGA", &out["rotd50"]["pga_g"], d50, 1e-12);
        close("RotD100 PGA", &out["rotd100"]["pga_g"], d100, 1e-12);
        // PGV, cm/s.
        let k = 20;
        let velocity = |x: &[f64]| -> Vec<f64> {
            let h = dt / k as f64;
            let mut v = 0.0;
            let mut out = vec![0.0];
            for w in x.windows(2) {
                for j in 0..k {
                    let g0 = w[0] + (w[1] - w[0]) * j as f64 / k as f64;
                    let g1 = w[0] + (w[1] - w[0]) * (j + 1) as f64 / k as f64;
                    v += 0.5 * (g0 + g1) * h * 980.665;
                    out.push(v);
                }
            }
            out
        };
        let (va, vb) = (velocity(&xa), velocity(&xb));
        let mut peaks: Vec<f64> = dirs
            .iter()
            .map(|&(c, s)| {
                va.iter()
                    .zip(&vb)
                    .fold(0.0f64, |m, (x, y)| m.max((c * x + s * y).abs()))
            })
            .collect();
        let (d50, d100) = rotd(&mut peaks);
        close("RotD50 PGV", &out["rotd50"]["pgv_cm_s"], d50, 1e-4);
        close("RotD100 PGV", &out["rotd100"]["pgv_cm_s"], d100, 1e-4);
        // SA.
        for (t, key) in [(0.2, "0.2"), (1.0, "1.0"), (3.0, "3.0")] {
            let (ua, ub) = (newmark(&xa, dt, t, k), newmark(&xb, dt, t, k));
            let w2 = (std::f64::consts::TAU / t).powi(2);
            let mut peaks: Vec<f64> = dirs
                .iter()
                .map(|&(c, s)| {
                    w2 * ua
                        .iter()
                        .zip(&ub)
                        .fold(0.0f64, |m, (x, y)| m.max((c * x + s * y).abs()))
                })
                .collect();
            let (d50, d100) = rotd(&mut peaks);
            close(
                &format!("RotD50 SA({key})"),
                &out["rotd50"]["sa_g"][key],
                d50,
                1e-3,
            );
            close(
                &format!("RotD100 SA({key})"),
                &out["rotd100"]["sa_g"][key],
                d100,
                1e-3,
            );
        }
        // RotD100 bounds each component's own peak; RotD50 lies below it.
        let one = json(&rocking(&root(), &["ims", "--record", &a_path, "--json"]));
        for key in ["pga_g", "pgv_cm_s"] {
            let (r50, r100) = (
                out["rotd50"][key].as_f64().unwrap(),
                out["rotd100"][key].as_f64().unwrap(),
            );
            assert!(
                r100 >= one[key].as_f64().unwrap() && r50 <= r100,
                "{a} {key}"
            );
        }
        // The record's own measures are still there, unchanged.
        assert_eq!(out["pga_g"], one["pga_g"]);
        assert_eq!(out["sa_g"], one["sa_g"]);
    }
}

/// A pair at two sample steps is refused, naming both files; a pair alone
/// (without --record) is not a command.
#[test]
fn a_pair_at_two_steps_is_refused() {
    let dir = tempdir();
    let (a, b) = (dir.path().join("a.AT2"), dir.path().join("b.AT2"));
    write_at2(&a, &[0.0, 0.1, -0.2, 0.0], 0.01);
    write_at2(&b, &[0.0, 0.1, -0.2, 0.0], 0.005);
    let out = rocking(
        dir.path(),
        &[
            "ims",
            "--record",
            a.to_str().unwrap(),
            "--pair",
            b.to_str().unwrap(),
        ],
    );
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(
        e.contains("a.AT2") && e.contains("b.AT2") && e.contains("sample steps differ"),
        "{e}"
    );
}

/// `capacity --pair --angle`: at 0° and 90° the capacities of the
/// components run alone (`capacity --record`), bit for bit, runs included;
/// θ + 180° (the mirror image: the component negated exactly) gives θ's
/// capacity to the bit; the angles of --angle-step 45 are 0, 45, 90, 135;
/// bad requests are refused by option.
#[test]
fn a_pair_at_the_axes_is_its_components_and_mirrors_agree() {
    let (a, b) = (far("RSN1111_KOBE_NIS000"), far("RSN1111_KOBE_NIS090"));
    let block = ["--b", "0.2", "--h", "0.9", "--eps", "housner", "--json"];
    let lines = |extra: &[&str]| -> Vec<Value> {
        let mut args = vec!["capacity", "--record", &a];
        args.extend(extra);
        args.extend(block);
        let out = rocking(&root(), &args);
        assert!(out.status.success(), "{}", stderr(&out));
        String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect()
    };
    let alone = |path: &str| {
        let mut args = vec!["capacity", "--record", path];
        args.extend(block);
        json(&rocking(&root(), &args))
    };
    let rotated = lines(&["--pair", &b, "--angle", "0,90,30,210,100,280"]);
    let angles: Vec<f64> = rotated
        .iter()
        .map(|r| r["angle_deg"].as_f64().unwrap())
        .collect();
    assert_eq!(angles, [0.0, 90.0, 30.0, 210.0, 100.0, 280.0]);
    assert_eq!(rotated[0]["record_id"], "RSN1111_KOBE_NIS000@0");
    for (r, path) in [(&rotated[0], &a), (&rotated[1], &b)] {
        let one = alone(path);
        for key in ["eta_c", "runs", "eta_survived", "pga_c_g"] {
            assert_eq!(r[key], one[key], "{path} {key}");
        }
    }
    for pair in rotated[2..].chunks(2) {
        assert_eq!(pair[0]["eta_c"], pair[1]["eta_c"]);
        assert_eq!(pair[0]["runs"], pair[1]["runs"]);
    }
    // The orientation matters: 30° is not the components' capacity.
    assert_ne!(rotated[2]["eta_c"], rotated[0]["eta_c"]);
    let stepped = lines(&["--pair", &b, "--angle-step", "45"]);
    let angles: Vec<f64> = stepped
        .iter()
        .map(|r| r["angle_deg"].as_f64().unwrap())
        .collect();
    assert_eq!(angles, [0.0, 45.0, 90.0, 135.0]);
    assert_eq!(stepped[2]["eta_c"], rotated[1]["eta_c"]);
    for (extra, says) in [
        (
            vec!["--pair", b.as_str()],
            "give the rocking plane's --angle",
        ),
        (
            vec!["--pair", b.as_str(), "--angle-step", "0"],
            "--angle-step 0",
        ),
        (vec!["--angle", "30"], "--pair"),
    ] {
        let mut args = vec!["capacity", "--record", a.as_str()];
        args.extend(extra.iter().copied());
        args.extend(block);
        let out = rocking(&root(), &args);
        assert!(!out.status.success(), "{extra:?}");
        assert!(stderr(&out).contains(says), "{extra:?}: {}", stderr(&out));
    }
}
