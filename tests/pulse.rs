//! Pulses and the `escape` criterion against independent truths: the
//! paper's Eqs. 3, 5 and 6 by the wall search, the full-cycle rectangle's
//! overturning modes against a hand-derived piecewise closed form, and the
//! escape proof against a long run.

use rocking::physics::{simulate, Model, Overturn, RunSpec};
use rocking::pulse::{self, Cycle, Pulse, Shape, WallSearch};

const LIN: Model = Model::LINEARIZED;

fn pulse(shape: Shape, cycle: Cycle) -> Pulse {
    Pulse {
        shape,
        cycle,
        t_d_s: 1.0,
    }
}

/// The walls of a pulse at f (t_d = 1 s, so p = f).
fn walls(pl: Pulse, f: f64, eps: f64, overturn: Overturn) -> pulse::Wall {
    let exc = pl.excitation_for(f).unwrap();
    let base = RunSpec {
        overturn,
        ..RunSpec::new(f, eps, 1.0, LIN)
    };
    pulse::wall(&exc, &base, WallSearch::default()).unwrap()
}

#[test]
fn half_cycle_rectangle_wall_is_housner_eq3() {
    // The rectangle is integrated exactly; only rounding and the 1e-10
    // bisection remain. Both criteria agree for a pulse that never pushes back.
    for f in [0.05, 0.5, 1.0, 2.0, 4.0, 8.0] {
        for overturn in [Overturn::Static, Overturn::Escape] {
            let w = walls(pulse(Shape::Rect, Cycle::Half), f, 0.7, overturn);
            let exact = pulse::housner_eq3(f);
            let got = w.eta_w.unwrap();
            assert!(
                (got - exact).abs() < 1e-6 * exact,
                "f = {f}, {overturn}: {got} vs {exact}"
            );
            assert_eq!(w.eta_w, w.eta_w_mode0, "f = {f}: Housner's is Mode 0");
            assert_eq!(w.mode, Some(0));
        }
    }
}

#[test]
fn half_cycle_exponential_wall_is_eq5() {
    // Including f = 2β (β = 1, f = 2; β = 3, f = 6), β = 0 (the triangle)
    // and |β| = 50 toward both limits (β → −∞ the rectangle, β → +∞ the
    // spike). The lobe is interpolated linearly between samples: an error
    // of second order in the step, measured below 1e-8 here.
    let cases = [
        (-50.0, 2.0),
        (-5.0, 1.0),
        (-5.0, 8.0),
        (-1.0, 3.0),
        (0.0, 1.0),
        (1.0, 2.0),
        (3.0, 6.0),
        (3.0, 3.0),
        (5.0, 10.0),
        (50.0, 2.0),
    ];
    for (beta, f) in cases {
        let pl = pulse(Shape::Exp { beta }, Cycle::Half);
        let w = walls(pl, f, 0.7, Overturn::Escape);
        let cf = pl.closed_form(f, Overturn::Escape).unwrap();
        assert_eq!(cf.equation, "Eq. 5");
        let got = w.eta_w.unwrap();
        assert!(
            (got - cf.eta).abs() < 1e-6 * cf.eta,
            "β = {beta}, f = {f}: wall {got}, Eq. 5 {}",
            cf.eta
        );
    }
    // β → −∞: the wall tends to Housner's (the gap closes like f/|β|).
    let w = walls(
        pulse(Shape::Exp { beta: -50.0 }, Cycle::Half),
        2.0,
        0.7,
        Overturn::Escape,
    );
    let gap = pulse::housner_eq3(2.0) - w.eta_w.unwrap();
    assert!(gap > 0.0 && gap < 2.0 * 2.0 / 50.0, "gap {gap}");
}

#[test]
fn full_cycle_rectangle_mode0_wall_is_eq6_under_escape_only() {
    for f in [0.5, 1.0, 2.0, 4.0] {
        let w = walls(pulse(Shape::Rect, Cycle::Full), f, 0.9, Overturn::Escape);
        let exact = pulse::full_cycle_eq6(f);
        let got = w.eta_w_mode0.unwrap();
        assert!(
            (got - exact).abs() < 1e-6 * exact,
            "f = {f}: {got} vs {exact}"
        );
    }
    // Under the static criterion the same pulse "overturns" blocks up to
    // η = 0.189 at f = 0.5 (MODEL.md §10): |x| reaches 1 in the second lobe
    // and the block would have come back.
    let w = walls(pulse(Shape::Rect, Cycle::Full), 0.5, 0.9, Overturn::Static);
    let st = w.eta_w_mode0.unwrap();
    assert!((st - 0.189).abs() < 5e-4, "static mode-0 wall {st}");
    assert!(st > pulse::full_cycle_eq6(0.5) * 1.2);
}

/// The full-cycle rectangle (lobes of 1 s, ψ̈ = +1 then −1) in closed form,
/// piece by piece, written independently of the stepper: on pivot s with
/// `y = s·x`, `ÿ = p²(y − 1) + (p²/η) s ψ̈`, so over a constant-forcing
/// piece `y − y* = (y₀ − y*) cosh pτ + (w₀/p) sinh pτ` with
/// `y* = 1 − sψ̈/η`; an impact is the first root `z = e^{pτ} > 1` of a
/// quadratic. After the pulse the free motion escapes iff `y − 1 + w/p > 0`;
/// heading back, it hits the pivot with speed² = p²(1 − 2D),
/// `D = ½((1 − y)² − (w/p)²)`, then escapes iff ε·speed > p. Returns the
/// impacts before escaping, or None if the block survives.
fn full_rect_mode(f: f64, eps: f64, eta: f64) -> Option<u32> {
    let p = f;
    let (mut y, mut w, mut s) = (0.0f64, 0.0f64, 1.0f64); // uplift at t = 0 on s = +1
    let mut impacts = 0;
    for psi in [1.0f64, -1.0] {
        let mut left = 1.0f64; // time left in this lobe
        loop {
            let ystar = 1.0 - s * psi / eta;
            let (a, b) = (y - ystar, w / p);
            // y(τ) = y* + a cosh + b sinh = 0 ⇔ (a+b)/2 z² + y* z + (a−b)/2 = 0.
            let (qa, qb, qc) = ((a + b) / 2.0, ystar, (a - b) / 2.0);
            let disc = qb * qb - 4.0 * qa * qc;
            let mut hit = None;
            if disc >= 0.0 && qa != 0.0 {
                for z in [
                    (-qb - disc.sqrt()) / (2.0 * qa),
                    (-qb + disc.sqrt()) / (2.0 * qa),
                ] {
                    if z > 1.0 + 1e-12 && z.ln() / p <= left {
                        hit = Some(hit.map_or(z, |h: f64| h.min(z)));
                    }
                }
            }
            match hit {
                Some(z) => {
                    let tau = z.ln() / p;
                    let (c, sh) = (tau * p).cosh_sinh();
                    let w_hit = p * (a * sh) + w * c;
                    impacts += 1;
                    (y, w, s, left) = (0.0, -eps * w_hit, -s, left - tau);
                }
                None => {
                    let (c, sh) = (left * p).cosh_sinh();
                    (y, w) = (ystar + a * c + b * sh, p * a * sh + w * c);
                    break;
                }
            }
        }
    }
    // Free motion after the pulse.
    loop {
        if y - 1.0 + w / p > 0.0 {
            return Some(impacts);
        }
        let d = 0.5 * ((1.0 - y).powi(2) - (w / p).powi(2));
        let speed = p * (1.0 - 2.0 * d).max(0.0).sqrt();
        impacts += 1;
        if eps * speed <= p {
            return None;
        }
        (y, w) = (0.0, eps * speed);
    }
}

trait CoshSinh {
    fn cosh_sinh(self) -> (f64, f64);
}
impl CoshSinh for f64 {
    fn cosh_sinh(self) -> (f64, f64) {
        (self.cosh(), self.sinh())
    }
}

#[test]
fn full_cycle_rectangle_modes_match_the_piecewise_closed_form() {
    // Fig. 4's areas: on a grid of (f, η) for three ε, the simulation's
    // verdict and impact count equal the closed form's at every point not
    // within 1e-6 (relative, in η) of a boundary of the closed form's map.
    let pl = pulse(Shape::Rect, Cycle::Full);
    let mut seen = [0usize; 4]; // safe, mode 0, mode 1, mode 2+
    for eps in [0.5, 0.7, 0.9] {
        for i in 0..24 {
            let f = 0.2 * (50.0f64).powf(i as f64 / 23.0); // 0.2 … 10
            let exc = pl.excitation_for(f).unwrap();
            for j in 0..40 {
                let eta = 10f64.powf(-2.0 * j as f64 / 39.0); // 1 … 0.01
                let want = full_rect_mode(f, eps, eta);
                let near = [1.0 - 1e-6, 1.0 + 1e-6]
                    .iter()
                    .any(|r| full_rect_mode(f, eps, eta * r) != want);
                if near || eta >= 1.0 {
                    continue;
                }
                let spec = RunSpec {
                    overturn: Overturn::Escape,
                    ..RunSpec::new(f, eps, eta, LIN)
                };
                let out = simulate(&exc, &spec).unwrap();
                let got = out.overturned().then_some(out.impacts as u32);
                assert_eq!(got, want, "ε = {eps}, f = {f}, η = {eta}: {out:?}");
                seen[want.map_or(0, |m| 1 + m.min(2) as usize)] += 1;
            }
        }
    }
    // Every area of Fig. 4 was visited (safe, Mode 0, Mode 1; this grid
    // has no Mode 2).
    assert!(
        seen[..3].iter().all(|&n| n >= 50),
        "points per area {seen:?}"
    );
}

#[test]
fn escape_proof_stops_runs_early_with_the_verdict_of_a_long_run() {
    // Under `escape` a block that passes |x| = 1 during the excitation
    // either comes back or is proven to escape. A proof must never be
    // wrong: the same record with the static limit moved far away (a cap
    // of 1e30, nothing decided before) must end overturned whenever the
    // proof said so, and the verdicts agree at every level.
    let exc = crate::util::bundled("far-field/RSN1111_KOBE_NIS000");
    let mut proven_early = 0;
    for p in [1.0, 3.0] {
        for j in 0..60 {
            let eta = 0.6 * 0.95f64.powi(j);
            let escape = RunSpec {
                overturn: Overturn::Escape,
                ..RunSpec::new(p, 0.8, eta, LIN)
            };
            let far = RunSpec {
                overturn: Overturn::Cap(1e30),
                ..escape
            };
            let (a, b) = (
                simulate(&exc, &escape).unwrap(),
                simulate(&exc, &far).unwrap(),
            );
            // With the cap this far the motion only grows (e^{pt} < 1e30 for
            // the rest of this record) once the growing mode wins: the far
            // run says overturned after the record when it escaped.
            assert_eq!(a.overturned(), b.overturned(), "p = {p}, η = {eta}");
            if a.overturned() && !a.overturn_after_record {
                proven_early += 1;
                assert!(a.intervals < b.intervals, "p = {p}, η = {eta}");
            }
            if !a.overturned() {
                assert_eq!(a.max_abs_x, b.max_abs_x, "p = {p}, η = {eta}");
            }
        }
    }
    assert!(
        proven_early >= 10,
        "only {proven_early} runs proven during the record"
    );
}

fn wall_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["wall", "--json"];
    all.extend_from_slice(args);
    let out = crate::util::rocking(&crate::util::root(), &all);
    assert!(out.status.success(), "{}", crate::util::stderr(&out));
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn wall_command_reports_the_walls_beside_the_closed_forms() {
    // One object with the issue's fields; the closed form is the paper's
    // equation, evaluated here by hand from its formula.
    let v = wall_json(&[
        "--pulse", "rect", "--cycle", "full", "--f", "1.5", "--eps", "0.9",
    ]);
    for key in [
        "f",
        "pulse",
        "beta",
        "cycle",
        "eps",
        "overturn",
        "eta_w",
        "eta_w_mode0",
        "closed_form",
        "mode",
    ] {
        assert!(v.get(key).is_some(), "missing {key}: {v}");
    }
    assert_eq!(v["overturn"], "escape");
    assert_eq!(v["pulse"], "rect");
    assert_eq!(v["cycle"], "full");
    assert!(v["beta"].is_null());
    let eq6 = (1.0 - (-1.5f64).exp()).powi(2);
    assert!((v["closed_form"].as_f64().unwrap() - eq6).abs() < 1e-14);
    assert!((v["eta_w_mode0"].as_f64().unwrap() - eq6).abs() < 1e-6 * eq6);
    assert_eq!(v["closed_form_of"], "eta_w_mode0");
    // The exponential half cycle on the line f = 2β: Eq. 5's removable
    // singularity, against mpmath's 0.44471611825027558 (β = 1, f = 2).
    let v = wall_json(&["--pulse", "exp", "--beta", "1", "--f", "2"]);
    assert!((v["closed_form"].as_f64().unwrap() - 0.444_716_118_250_275_6).abs() < 1e-9);
    assert!((v["eta_w"].as_f64().unwrap() - 0.444_716_118_250_275_6).abs() < 1e-6);
    assert_eq!(v["mode"], 0);
    // No closed form for the full-cycle exponential pulse, nor for the
    // full rectangle under the static criterion.
    assert!(
        wall_json(&["--pulse", "exp", "--beta", "2", "--cycle", "full", "--f", "2"])["closed_form"]
            .is_null()
    );
    assert!(wall_json(&[
        "--pulse",
        "rect",
        "--cycle",
        "full",
        "--f",
        "2",
        "--overturn",
        "static"
    ])["closed_form"]
        .is_null());
    // Bad input names the flag.
    for (args, says) in [
        (vec!["wall", "--pulse", "exp", "--f", "1"], "--beta"),
        (
            vec!["wall", "--pulse", "rect", "--beta", "1", "--f", "1"],
            "--beta",
        ),
        (vec!["wall", "--pulse", "rect", "--f", "-1"], "--f"),
        // Required, and marked so in the usage line of the help.
        (
            vec!["wall", "--f", "1"],
            "required arguments were not provided:\n  --pulse <PULSE>",
        ),
        (
            vec!["wall", "--pulse", "rect", "--f", "1", "--overturn", "escap"],
            "escape",
        ),
        // The wall is of one model: its options name what it offers (the
        // refusals sent users to `--mu` and `--model auto`, which it does
        // not take), and α beside the linearised model was dropped unsaid.
        (
            vec![
                "wall",
                "--pulse",
                "rect",
                "--f",
                "1",
                "--model",
                "slide-rock",
            ],
            "[possible values: linearized, nonlinear]",
        ),
        (
            vec!["wall", "--pulse", "rect", "--f", "1", "--integrator", "dp5"],
            "(give --model nonlinear)",
        ),
        (
            vec!["wall", "--pulse", "rect", "--f", "1", "--alpha", "0.3"],
            "--alpha, --integrator and --rtol are the nonlinear model's",
        ),
    ] {
        let out = crate::util::rocking(&crate::util::root(), &args);
        assert!(!out.status.success(), "{args:?}");
        let err = crate::util::stderr(&out);
        assert!(err.contains(says), "{args:?}: {err}");
    }
}

#[test]
fn simulate_and_capacity_take_a_pulse() {
    // Housner's rectangle through `capacity`: η_c = 1 − e^{−p t_d} with
    // t_d = 0.5 s and p = 4 (f = 2), to the search's tolerance.
    let out = crate::util::rocking(
        &crate::util::root(),
        &[
            "capacity", "--pulse", "rect", "--td", "0.5", "--p", "4", "--eps", "0.7", "--tol",
            "1e-9", "--json",
        ],
    );
    assert!(out.status.success(), "{}", crate::util::stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let c = v["eta_c"].as_f64().unwrap();
    assert!((c - pulse::housner_eq3(2.0)).abs() < 1e-9, "{c}");
    assert_eq!(v["record_id"], "rect-half t_d=0.5s");
    let out = crate::util::rocking(
        &crate::util::root(),
        &[
            "simulate",
            "--pulse",
            "rect",
            "--cycle",
            "full",
            "--p",
            "0.5",
            "--eps",
            "0.9",
            "--eta",
            "0.15",
            "--overturn",
            "escape",
            "--json",
        ],
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // Below Eq. 6's 0.1548 at f = 0.5: Mode 0, decided at the pulse's end.
    assert_eq!(v["overturned"], true);
    assert_eq!(v["impacts"], 0);
    assert_eq!(v["overturn_after_record"], true);
}

/// A pipeline file as given (no records added).
fn write(dir: &std::path::Path, name: &str, body: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, body).unwrap();
    path
}

#[test]
fn pulse_map_pipeline_writes_walls_map_and_figures() {
    use rocking::tables::pulse::{PulseCellRow, PulseWallRow};
    // The bundled Fig. 4 pipeline, coarser: every Mode 0 wall is Eq. 6,
    // every map point has the piecewise closed form's mode, the same bytes
    // come out at 1 and 2 threads, and the report lists Figs. 2–4.
    let dir = crate::util::tempdir();
    let pipe = write(
        dir.path(),
        "map.toml",
        r#"
name = "map"
[pulses]
shape = "rect"
cycle = "full"
f = { from = 0.2, to = 8.0, count = 12, spacing = "log" }
eta = { from = 1.0, to = 0.02, count = 30, spacing = "log" }
eps = [0.6, 0.9]
"#,
    );
    let mut bytes = Vec::new();
    for threads in ["1", "2"] {
        let out_dir = dir.path().join(format!("out{threads}"));
        let out = crate::util::rocking(
            dir.path(),
            &[
                "run",
                pipe.to_str().unwrap(),
                "--outputs",
                out_dir.to_str().unwrap(),
                "--threads",
                threads,
            ],
        );
        assert!(out.status.success(), "{}", crate::util::stderr(&out));
        let study = out_dir.join("map");
        bytes.push(
            ["pulse_walls.parquet", "pulse_map.parquet"]
                .map(|t| std::fs::read(study.join(t)).unwrap()),
        );
        if threads == "2" {
            let walls: Vec<PulseWallRow> =
                rocking::tables::read(&study.join("pulse_walls.parquet")).unwrap();
            assert_eq!(walls.len(), 24);
            for w in &walls {
                // Default criterion of a pulse map: escape.
                assert_eq!(w.overturn, "escape");
                let eq6 = (1.0 - (-w.f).exp()).powi(2);
                let got = w.eta_w_mode0.unwrap();
                assert!((got - eq6).abs() < 1e-6 * eq6, "{w:?}");
                assert!(w.eta_w.unwrap() >= got);
            }
            let cells: Vec<PulseCellRow> =
                rocking::tables::read(&study.join("pulse_map.parquet")).unwrap();
            assert_eq!(cells.len(), 24 * 30);
            for c in &cells {
                let want = full_rect_mode(c.f, c.eps, c.eta);
                let near = [1.0 - 1e-6, 1.0 + 1e-6]
                    .iter()
                    .any(|r| full_rect_mode(c.f, c.eps, c.eta * r) != want);
                if !near && c.eta < 1.0 {
                    let got = c.overturned.then_some(c.impacts as u32);
                    assert_eq!(got, want, "{c:?}");
                }
            }
            let report = std::fs::read_to_string(study.join("report.md")).unwrap();
            for fig in [
                "fig02_pulse_waveforms.svg",
                "fig03_pulse_walls.svg",
                "fig04_modes_eps0.60.svg",
                "fig04_modes_eps0.90.svg",
            ] {
                assert!(report.contains(fig), "{fig} not in the report");
                assert!(study.join("figures").join(fig).exists(), "{fig}");
            }
            assert!(
                report.contains("| ε = 0.90 | Eq. 6 | η_w,0 (Mode 0) | 12 |"),
                "{report}"
            );
        }
    }
    assert!(
        bytes[0] == bytes[1],
        "tables differ between 1 and 2 threads"
    );
}

#[test]
fn pulse_map_pipelines_refuse_what_they_cannot_use() {
    let dir = crate::util::tempdir();
    let base = "[pulses]\nshape = \"rect\"\nf = [1.0]\neta = [0.5]\neps = [0.7]\n";
    for (extra, says) in [
        ("[records]\nat2 = [\"x\"]\n", "remove [records]"),
        ("[blocks]\np = [1.0]\n", "remove [blocks]"),
        ("[uncertainty]\n", "remove [uncertainty]"),
        (
            "[damage]\nstates = \"rocking=0.1,overturned=overturned\"\n",
            "remove [damage]",
        ),
        (
            "[tree]\n[[tree.eps]]\nvalue = 0.8\nweight = 1\n",
            "remove [tree]",
        ),
    ] {
        let pipe = write(dir.path(), "bad.toml", &format!("{base}{extra}"));
        let out = crate::util::rocking(dir.path(), &["run", pipe.to_str().unwrap()]);
        assert!(!out.status.success());
        let err = crate::util::stderr(&out);
        assert!(err.contains(says) && err.contains("bad.toml"), "{err}");
    }
    for (body, says) in [
        (base.replace("rect", "exp"), "pulses.beta"),
        (
            base.replace("rect\"", "rect\"\nbeta = [1.0]"),
            "pulses.beta",
        ),
        (
            base.replace("shape = \"rect\"", "shape = \"sine\""),
            "pulses.shape",
        ),
        (base.replace("f = [1.0]", "f = [-1.0]"), "pulses.f"),
        (base.replace("eps = [0.7]", "eps = [1.5]"), "pulses.eps"),
        (format!("{base}intervals = 3\n"), "pulses.intervals"),
        ("name = \"x\"\n".to_string(), "[records]"),
    ] {
        let pipe = write(dir.path(), "bad.toml", &body);
        let out = crate::util::rocking(dir.path(), &["run", pipe.to_str().unwrap()]);
        assert!(!out.status.success(), "{body}");
        let err = crate::util::stderr(&out);
        assert!(err.contains(says), "{body}: {err}");
    }
    // Nothing to shard on a cluster, and no records stage to run by hand.
    let pipe = write(dir.path(), "map.toml", base);
    let p = pipe.to_str().unwrap();
    for (args, says) in [
        (vec!["submit", p, "--shards", "2"], "runs no records"),
        (vec!["sweep", p], "does not need `sweep`"),
    ] {
        let out = crate::util::rocking(dir.path(), &args);
        assert!(!out.status.success(), "{args:?}");
        let err = crate::util::stderr(&out);
        assert!(err.contains(says), "{args:?}: {err}");
    }
}
