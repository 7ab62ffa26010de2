//! Record pairs through the binary: the rotated component and its
//! capacities at the axes (the components themselves, bit for bit) and at
//! θ and θ + 180°; RotD50 and RotD100 against an independent computation
//! (another oscillator integrator, the responses rotated every 1°);
//! refusals.

use serde_json::Value;

use crate::util::{bundled_records, cornell_above, rocking, root, stderr, tempdir, write_at2};

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
        // Finer than a degree: 1e-9° held 1.8e11 motions at once, and the
        // process was killed.
        (
            vec!["--pair", b.as_str(), "--angle-step", "1e-9"],
            "--angle-step 0.000000001: the angle step is in degrees, in [1, 180]",
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

/// A folder of two pairs (Kobe Nishi-Akashi, Manjil Abbar: unequal
/// lengths) with their manifest lines, as `--direct` reads pairs.
fn two_pairs(dir: &std::path::Path) -> std::path::PathBuf {
    let folder = dir.join("pairs");
    std::fs::create_dir(&folder).unwrap();
    let manifest = std::fs::read_to_string(bundled_records().join("manifest.csv")).unwrap();
    let mut lines = manifest.lines();
    let mut out = format!("{}\n", lines.next().unwrap());
    for stem in STEMS {
        std::fs::copy(far(stem), folder.join(format!("{stem}.AT2"))).unwrap();
        let line = lines
            .clone()
            .find(|l| l.contains(&format!("/{stem}.AT2")))
            .unwrap();
        out.push_str(&line.replace("far-field/", ""));
        out.push('\n');
    }
    std::fs::write(folder.join("manifest.csv"), out).unwrap();
    folder
}

const STEMS: [&str; 4] = [
    "RSN1111_KOBE_NIS000",
    "RSN1111_KOBE_NIS090",
    "RSN1633_MANJIL_ABBAR--L",
    "RSN1633_MANJIL_ABBAR--T",
];

/// exp(mean ln) and the standard deviation (n in the denominator) of ln x:
/// the maximum-likelihood lognormal of capacities that all overturn.
fn mle(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().map(|v| v.ln()).sum::<f64>() / n;
    let s = (x.iter().map(|v| (v.ln() - m).powi(2)).sum::<f64>() / n).sqrt();
    (m.exp(), s)
}

/// The orientation rules from the capacities of `capacity --pair
/// --angle-step 45` (each pair at 0, 45, 90, 135°) and `rocking ims
/// --pair`: as recorded, each component's PGA at overturning; random,
/// every pair at every angle, equally weighted; worst, each pair's
/// smallest; in RotD50 PGA, each capacity's scale factor times its pair's
/// RotD50. `fragility --direct --method mle` (every capacity reached: the
/// likelihood's lognormal is the logs' mean and spread) states each to
/// 1e-9; `risk --im rotd50_pga` on a PGA hazard (declared RotD50) of a
/// power law equals Cornell's closed form with that fragility (1e-9; no
/// uplift cut in RotD50).
#[test]
fn orientation_rules_are_the_capacities_over_angles() {
    let dir = tempdir();
    let folder = two_pairs(dir.path());
    let folder_s = folder.to_str().unwrap();
    // The model --direct runs (auto: the nonlinear one for this α).
    let block = [
        "--b", "0.2", "--h", "0.9", "--eps", "housner", "--model", "auto", "--json",
    ];
    let capacity = |args: &[&str]| -> Vec<Value> {
        let mut all = vec!["capacity"];
        all.extend(args);
        all.extend(block);
        let out = rocking(&root(), &all);
        assert!(out.status.success(), "{}", stderr(&out));
        String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect()
    };
    let pga_c = |v: &Value| v["pga_c_g"].as_f64().unwrap();
    let mut as_recorded = Vec::new();
    let mut as_recorded_rotd = Vec::new();
    let mut random = Vec::new();
    let mut random_rotd = Vec::new();
    let mut worst = Vec::new();
    for pair in STEMS.chunks(2) {
        let (a, b) = (far(pair[0]), far(pair[1]));
        let ims = json(&rocking(
            &root(),
            &["ims", "--record", &a, "--pair", &b, "--json"],
        ));
        let rotd50 = ims["rotd50"]["pga_g"].as_f64().unwrap();
        for path in [&a, &b] {
            let one = &capacity(&["--record", path])[0];
            let pga = json(&rocking(&root(), &["ims", "--record", path, "--json"]))["pga_g"]
                .as_f64()
                .unwrap();
            as_recorded.push(pga_c(one));
            as_recorded_rotd.push(pga_c(one) / pga * rotd50);
        }
        let (xa, dt) = rocking::records::read_samples(a.as_ref()).unwrap();
        let (xb, _) = rocking::records::read_samples(b.as_ref()).unwrap();
        let p = rocking::pair::Pair::new(xa, dt, xb, dt).unwrap();
        let angled = capacity(&["--record", &a, "--pair", &b, "--angle-step", "45"]);
        assert_eq!(angled.len(), 4);
        let mut smallest = f64::INFINITY;
        for r in &angled {
            let theta = r["angle_deg"].as_f64().unwrap();
            let pga_theta = p.rotated(theta).iter().fold(0.0f64, |m, x| m.max(x.abs()));
            random.push(pga_c(r));
            random_rotd.push(pga_c(r) / pga_theta * rotd50);
            smallest = smallest.min(pga_c(r));
        }
        worst.push(smallest);
    }
    let fragility = |orientation: &str, im: &str| -> Value {
        let mut args = vec![
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
            folder_s,
            "--orientation",
            orientation,
            "--im",
            im,
            "--at",
            "0.4",
            "--method",
            "mle",
            "--json",
        ];
        // The step of the orientations (refused as recorded, where it does nothing).
        if orientation != "as-recorded" {
            args.extend(["--angle-step", "45"]);
        }
        json(&rocking(&root(), &args))
    };
    for (orientation, im, caps, n) in [
        ("as-recorded", "pga", &as_recorded, 4),
        ("as-recorded", "rotd50_pga", &as_recorded_rotd, 4),
        ("random", "pga", &random, 8),
        ("random", "rotd50_pga", &random_rotd, 8),
        ("worst", "pga", &worst, 2),
    ] {
        let f = fragility(orientation, im);
        let (m, s) = mle(caps);
        let (got_m, got_s) = (f["median"].as_f64().unwrap(), f["beta"].as_f64().unwrap());
        assert!(
            (got_m / m - 1.0).abs() < 1e-9,
            "{orientation} {im}: {got_m} vs {m}"
        );
        assert!(
            (got_s / s - 1.0).abs() < 1e-9,
            "{orientation} {im}: {got_s} vs {s}"
        );
        assert_eq!(f["records"], n, "{orientation} {im}");
        assert_eq!(f["orientation"].is_string(), orientation != "as-recorded");
    }
    // Risk in the hazard's component.
    let (k0, k) = (2e-4, 2.6);
    let mut h = String::from("pga_g,annual_rate\n");
    for i in 0..30 {
        let a = 0.005 * (600.0f64).powf(i as f64 / 29.0);
        h.push_str(&format!("{a:?},{:?}\n", k0 * a.powf(-k)));
    }
    std::fs::write(dir.path().join("h.csv"), h).unwrap();
    let risk = |im: &str, orientation: &str| {
        rocking(
            dir.path(),
            &[
                "risk",
                "--hazard",
                "h.csv",
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--direct",
                "--records",
                folder_s,
                "--orientation",
                orientation,
                "--angle-step",
                "45",
                "--im",
                im,
                "--method",
                "mle",
                "--json",
            ],
        )
    };
    let v = json(&risk("rotd50_pga", "random"));
    let (m, s) = mle(&random_rotd);
    assert!((v["fragility"]["median"].as_f64().unwrap() / m - 1.0).abs() < 1e-9);
    let expected = cornell_above(k0, k, m, s, 0.0);
    let got = v["sites"][0]["annual_rate"].as_f64().unwrap();
    assert!((got / expected - 1.0).abs() < 1e-9, "{got} vs {expected}");
    // `--component rotd50` says the same of the hazard: the same rate.
    let said = json(&rocking(
        dir.path(),
        &[
            "risk",
            "--hazard",
            "h.csv",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
            folder_s,
            "--orientation",
            "random",
            "--angle-step",
            "45",
            "--component",
            "rotd50",
            "--method",
            "mle",
            "--json",
        ],
    ));
    assert_eq!(
        said["sites"][0]["annual_rate"],
        v["sites"][0]["annual_rate"]
    );
    // Without the records' pairs the fragility is the recorded components':
    // the mismatch is warned of.
    let out = rocking(
        dir.path(),
        &[
            "risk",
            "--hazard",
            "h.csv",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--component",
            "rotd50",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("the hazard is RotD50 (--component rotd50)"),
        "{}",
        stderr(&out)
    );
    // Over orientations in the rotated component's own PGA: warned of.
    let out = risk("pga", "random");
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("give --im rotd50_pga"),
        "{}",
        stderr(&out)
    );
    // Into OpenQuake, a RotD50 fragility is named as its measure (the
    // component of the models behind its hazard), and says what it is.
    let out = rocking(
        dir.path(),
        &[
            "export",
            "--format",
            "nrml",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
            folder_s,
            "--orientation",
            "random",
            "--angle-step",
            "45",
            "--im",
            "rotd50_pga",
            "--out",
            "nrml",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let xml = std::fs::read_to_string(dir.path().join("nrml/fragility_model.xml")).unwrap();
    assert!(xml.contains("imt=\"PGA\""), "{xml}");
    assert!(
        xml.contains(
            "facing any direction of the records&apos; pairs (every 45 degrees) in RotD50 PGA"
        ),
        "{xml}"
    );
    // A pair's IM needs the pairs' runs; a folder without a manifest has no pairs.
    let out = rocking(
        &root(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--im",
            "rotd50_pga",
            "--at",
            "0.3",
        ],
    );
    assert!(
        stderr(&out).contains("measure of a record pair"),
        "{}",
        stderr(&out)
    );
    std::fs::remove_file(folder.join("manifest.csv")).unwrap();
    let out = fragility_refused(folder_s);
    assert!(
        out.contains("pairs come from the records' manifest"),
        "{out}"
    );
}

fn fragility_refused(folder: &str) -> String {
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
            folder,
            "--orientation",
            "worst",
            "--pga",
            "0.3",
        ],
    );
    assert!(!out.status.success());
    stderr(&out)
}

/// A study over orientations (`[records] orientation = "random"`): the
/// sweep's records are every pair at every angle of the step, named
/// `<a>@<θ>`, each capacity `capacity --pair --angle θ`'s to the bit; the
/// study's fragility (`--from`, `--direct`) is `fragility --orientation
/// random`'s over the same pairs; refusals by key.
#[test]
fn a_study_over_orientations_runs_every_pair_at_every_angle() {
    use crate::util::write_pipeline;
    let dir = tempdir();
    let folder = two_pairs(dir.path());
    let head = format!("ids = {STEMS:?}\n");
    let block = "[model]\nkind = \"auto\"\n[[block]]\nname = \"statue\"\nb = 0.2\nh = 0.9\neps = \"housner\"\n";
    let study = write_pipeline(
        dir.path(),
        "turned",
        &format!("{head}orientation = \"random\"\nangle_step = 45\n{block}"),
    );
    let outputs = dir.path().join("out");
    let out_s = outputs.to_str().unwrap();
    let out = rocking(
        dir.path(),
        &["run", study.to_str().unwrap(), "--outputs", out_s],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let report = std::fs::read_to_string(outputs.join("turned/report.md")).unwrap();
    assert!(report.contains("## Facing any direction"), "{report}");
    assert!(
        report.contains("Every one of the 2 record pairs"),
        "{report}"
    );
    // Along and across each pair's strongest velocity (its two pairs).
    assert!(
        report.contains("| statue | 2.824 | 0.929 | 2 |"),
        "{report}"
    );
    assert!(outputs
        .join("turned/figures/orientation_capacity.svg")
        .exists());
    // The study's RotD50 fragility (its ims stage) is `fragility
    // --orientation random --im rotd50_pga`'s: every motion overturns the
    // statue, so the likelihood's median is the logs' mean, as the table's.
    let eff: Vec<rocking::tables::ims::EfficiencyRow> =
        rocking::tables::read(&outputs.join("turned/im_efficiency.parquet")).unwrap();
    let row = eff.iter().find(|e| e.im == "rotd50_pga").unwrap();
    let direct = json(&rocking(
        &root(),
        &[
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--records",
            folder.to_str().unwrap(),
            "--orientation",
            "random",
            "--angle-step",
            "45",
            "--im",
            "rotd50_pga",
            "--at",
            "0.4",
            "--method",
            "mle",
            "--json",
        ],
    ));
    let m = direct["median"].as_f64().unwrap();
    assert_eq!(row.n, 8);
    assert!(
        (row.median.unwrap() / m - 1.0).abs() < 1e-9,
        "{row:?} {direct}"
    );
    assert!(
        report.contains("random, RotD50 PGA: median (g), β"),
        "{report}"
    );
    let caps = rocking::stages::sweep::read_capacities(&outputs.join("turned")).unwrap();
    let ids: Vec<&str> = caps.iter().map(|c| c.record_id.as_str()).collect();
    assert_eq!(
        ids,
        [
            "RSN1111_KOBE_NIS000@0",
            "RSN1111_KOBE_NIS000@45",
            "RSN1111_KOBE_NIS000@90",
            "RSN1111_KOBE_NIS000@135",
            "RSN1633_MANJIL_ABBAR--L@0",
            "RSN1633_MANJIL_ABBAR--L@45",
            "RSN1633_MANJIL_ABBAR--L@90",
            "RSN1633_MANJIL_ABBAR--L@135",
        ]
    );
    for pair in STEMS.chunks(2) {
        let (a, b) = (far(pair[0]), far(pair[1]));
        let out = rocking(
            &root(),
            &[
                "capacity",
                "--record",
                &a,
                "--pair",
                &b,
                "--angle-step",
                "45",
                "--b",
                "0.2",
                "--h",
                "0.9",
                "--eps",
                "housner",
                "--model",
                "auto",
                "--json",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        for line in String::from_utf8(out.stdout).unwrap().lines() {
            let v: Value = serde_json::from_str(line).unwrap();
            let c = caps
                .iter()
                .find(|c| c.record_id == v["record_id"].as_str().unwrap())
                .unwrap();
            assert_eq!(c.eta_c, v["eta_c"].as_f64(), "{}", c.record_id);
        }
    }
    let fragility = |extra: &[&str]| {
        let mut args = vec![
            "fragility",
            "--b",
            "0.2",
            "--h",
            "0.9",
            "--direct",
            "--at",
            "0.4",
            "--json",
        ];
        args.extend(extra);
        rocking(dir.path(), &args)
    };
    let by_study = json(&fragility(&[
        "--from",
        study.to_str().unwrap(),
        "--outputs",
        out_s,
    ]));
    let by_pairs = json(&fragility(&[
        "--records",
        folder.to_str().unwrap(),
        "--orientation",
        "random",
        "--angle-step",
        "45",
    ]));
    assert_eq!(by_study["median"], by_pairs["median"]);
    assert_eq!(by_study["beta"], by_pairs["beta"]);
    assert_eq!(by_study["records"], 8);
    let out = fragility(&[
        "--from",
        study.to_str().unwrap(),
        "--outputs",
        out_s,
        "--orientation",
        "worst",
    ]);
    assert!(
        stderr(&out).contains("already its pairs at every angle"),
        "{}",
        stderr(&out)
    );
    for (body, says) in [
        (
            "orientation = \"worst\"\n",
            "a study holds every motion's capacity",
        ),
        (
            "angle_step = 30\n",
            "`records.angle_step` is the random orientation's",
        ),
        (
            "orientation = \"random\"\nangle_step = 0\n",
            "`records.angle_step` = 0",
        ),
        // 1e-9° would hold 1.8e11 motions.
        (
            "orientation = \"random\"\nangle_step = 1e-9\n",
            "`records.angle_step` = 0.000000001: the angle step is in degrees, in [1, 180]",
        ),
        (
            "orientation = \"sideways\"\n",
            "`records.orientation`: unknown orientation",
        ),
    ] {
        let bad = write_pipeline(dir.path(), "bad", &format!("{head}{body}{block}"));
        let out = rocking(
            dir.path(),
            &["run", bad.to_str().unwrap(), "--outputs", out_s],
        );
        assert!(!out.status.success(), "{body}");
        assert!(stderr(&out).contains(says), "{body}: {}", stderr(&out));
    }
}
