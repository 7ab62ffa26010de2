//! The Taylor stepper of the nonlinear equation against independent truths:
//! its free motion conserves the nonlinear energy; its runs equal DP5's at
//! rtol 1e-13 (another engine) on bundled records; as α → 0 it tends to
//! the exact linearised stepper's closed form; an interval holding two
//! turning points keeps its impact; a lift settled within the rounding of
//! time rests on, as DP5's does; the hard cases certify to DP5's tight
//! search or are flagged chaotic where DP5's certification is; the
//! command line and pipelines choose it and refuse bad settings.

use rocking::ida::HARD_CASES;
use rocking::ida::{capacity_certified, capacity_traced, Certification, Trace};
use rocking::physics::taylor::Taylor;
use rocking::physics::{
    simulate, Model, Rocking, RunSpec, Stepper, Stretch, StretchEnd, DEFAULT_RTOL,
    DEFAULT_TAYLOR_TOL,
};

use crate::util::{bundled, rocking, root, stderr, tempdir, write_pipeline};

fn far(stem: &str) -> rocking::physics::Excitation {
    bundled(&format!("far-field/{stem}"))
}

/// The free motion on one pivot (`ÿ = −(p²/α) sin(α(1 − y))`) conserves
/// `E = ẏ²/2 + (p²/α²) cos(α(1 − y))`. Stepped in record-like intervals of
/// 0.01 s from y = 0.5 upward until it falls back to the pivot, E at every
/// step's end and at the impact equals its start to 1e-13 (relative): the
/// default tail (1e-10) bounds the last two terms kept, and the terms
/// omitted after them are smaller by the series' fall (about 0.03 an order).
#[test]
fn free_rocking_conserves_the_nonlinear_energy() {
    let (p, alpha) = (2.0, 0.3);
    let energy = |y: f64, w: f64| 0.5 * w * w + p * p / (alpha * alpha) * (alpha * (1.0 - y)).cos();
    for s in [1.0, -1.0] {
        let mut stepper = Taylor::new(p, 1.0, alpha, DEFAULT_TAYLOR_TOL, 10.0);
        let mut st = Rocking {
            x: 0.5 * s,
            v: 0.4 * s,
            s,
        };
        let e0 = energy(0.5, 0.4);
        let mut max = 0.0;
        let mut steps = 0;
        loop {
            let stretch = Stretch {
                tau0: 0.0,
                len: 0.01,
                g_a: 0.0,
                g1: 0.0,
            };
            let end = stepper.rock(stretch, &mut st, &mut max);
            let e = energy(s * st.x, s * st.v);
            assert!(
                ((e - e0) / e0).abs() < 1e-13,
                "step {steps}: {e} against {e0}"
            );
            steps += 1;
            match end {
                StretchEnd::End => assert!(steps < 10_000, "never came back"),
                StretchEnd::Impact { v, .. } => {
                    assert!((s * st.x).abs() < 1e-12, "impact at x = {}", st.x);
                    let e = energy(0.0, s * v);
                    assert!(((e - e0) / e0).abs() < 1e-13, "at impact: {e} against {e0}");
                    break;
                }
                other => panic!("{other:?}"),
            }
        }
        // Its highest point, where ẏ = 0: cos(α(1 − y)) = E α²/p².
        let apex = 1.0 - (e0 * alpha * alpha / (p * p)).acos() / alpha;
        assert!((max - apex).abs() < 1e-12, "θmax/α {max} against {apex}");
    }
}

/// A hop: the block leaves the pivot with a small speed `w0` against a
/// forcing that pulls it back, and lands within the stretch (most impacts
/// of a run are such hops). Under a constant forcing `g_a` the motion on
/// pivot `s` conserves `E = ẏ²/2 + (p²/α²) cos u + (c/α) sin u` (`c = s
/// p² g_a / η`, `u = α(1 − y)`), equal at both ends on the pivot: it lands
/// at the speed it left with, to 1e-12. So low, the hop follows `ÿ = a0 +
/// k y` (the equation's value and slope at the pivot), whose landing is
/// `t = 2 atanh(w0 √k / |a0|) / √k`: the terms left out (`y²` and up, y ≤
/// 1e-8) move it by less than 1e-15 (relative). The stepper lands there
/// to 1e-13 whether it takes the hop in closed form (the largest `|x|` met
/// before above the hop) or steps it and locates its turning point
/// (nothing met before).
#[test]
fn a_hop_lands_as_it_left() {
    let (p, eta, alpha): (f64, f64, f64) = (2.0, 0.3, 0.25);
    let uplift = eta * alpha.tan() / alpha;
    for s in [1.0, -1.0] {
        for g in [-1.0, 0.0, 0.5, 0.9] {
            for w0 in [1e-7, 1e-5, 1e-4] {
                let g_a = s * g * uplift;
                let c = p * p * (s * g_a) / eta;
                let a0 = -(p * p / alpha) * alpha.sin() + c * alpha.cos();
                let k = p * p * alpha.cos() + c * alpha * alpha.sin();
                let landing = 2.0 * (w0 * k.sqrt() / a0.abs()).atanh() / k.sqrt();
                let stretch = Stretch {
                    tau0: 0.0,
                    len: 0.01,
                    g_a,
                    g1: 0.0,
                };
                let land = |top: f64| {
                    let mut stepper = Taylor::new(p, eta, alpha, DEFAULT_TAYLOR_TOL, 1.0);
                    let (mut st, mut max) = (
                        Rocking {
                            x: 0.0,
                            v: s * w0,
                            s,
                        },
                        top,
                    );
                    match stepper.rock(stretch, &mut st, &mut max) {
                        StretchEnd::Impact { sigma, v } => (sigma, v, max),
                        other => panic!("s {s}, g {g}, w0 {w0}: {other:?}"),
                    }
                };
                let case = format!("s {s}, g {g}, w0 {w0}");
                let (t_hop, v_hop, max_hop) = land(1.0);
                let (t_turn, v_turn, max_turn) = land(0.0);
                for (t, v) in [(t_hop, v_hop), (t_turn, v_turn)] {
                    assert!((v + s * w0).abs() <= 1e-12 * w0, "{case}: lands at {v}");
                    assert!(
                        (t - landing).abs() <= 1e-13 * landing,
                        "{case}: {t} against {landing}"
                    );
                }
                // The closed form leaves the largest |x| as it was; the
                // turning point raises it to the hop's height, w0²/(2|a0|)
                // nearly.
                assert_eq!(max_hop, 1.0, "{case}");
                let height = w0 * w0 / (2.0 * a0.abs());
                assert!(
                    (max_turn - height).abs() < 1e-3 * height,
                    "{case}: {max_turn}"
                );
            }
        }
    }
}

/// Every run's outcome equals DP5's at rtol 1e-13, an independent engine:
/// the same stop, impacts and overturning, θmax/α within 1e-9 (DP5's
/// global error at 1e-13 over a record is about 1e-10), and the overturning
/// time within 1e-9 s.
#[test]
fn runs_equal_dp5_at_its_tightest() {
    let cases = [
        ("RSN1111_KOBE_NIS000", 2.0, 0.25),
        ("RSN848_LANDERS_CLW-LN", 1.0, 0.15),
        ("RSN1633_MANJIL_ABBAR--L", 4.0, 0.4),
    ];
    for (stem, p, alpha) in cases {
        let exc = far(stem);
        for eta in [0.6, 0.4, 0.3, 0.2, 0.15, 0.1] {
            let run = |m| simulate(&exc, &RunSpec::new(p, 0.8, eta, m)).unwrap();
            let (t, d) = (
                run(Model::taylor(alpha, DEFAULT_TAYLOR_TOL)),
                run(Model::dp5(alpha, 1e-13)),
            );
            let what = format!("{stem} p = {p} α = {alpha} η = {eta}: {t:?} against {d:?}");
            assert_eq!((t.stop, t.impacts), (d.stop, d.impacts), "{what}");
            assert!(
                (t.max_abs_x - d.max_abs_x).abs() <= 1e-9 * d.max_abs_x.max(1.0),
                "{what}"
            );
            match (t.overturn_time_s, d.overturn_time_s) {
                (Some(a), Some(b)) => assert!((a - b).abs() < 1e-9, "{what}"),
                (a, b) => assert_eq!(a, b, "{what}"),
            }
        }
    }
}

/// A block lifted by a forcing past the threshold only by rounding, and
/// falling back within the rounding of the interval's time (RSN900 at the
/// α = 0.3 paper grid's second p, ε = 0.5, η = 0.0653): it rests on until
/// the forcing lifts it anew, instead of lifting and settling at the same
/// instant until the event cap. The run then equals DP5's at rtol 1e-13
/// (another engine): the same stop and 521 impacts, and θmax/α at least as
/// close to it as DP5's at its default rtol 1e-10 (what the Taylor stepper's
/// default must match; here DP5 errs by about 6e-12, the Taylor stepper by
/// about 5e-15: 521 impacts of slow rocking at p·Δt = 0.0045, where the
/// series of sin u and cos u set the order).
#[test]
fn a_lift_settled_within_the_rounding_of_time_rests_on() {
    let exc = far("RSN900_LANDERS_YER360");
    let p = 0.33 * (10.0f64 / 0.33).powf(1.0 / 11.0);
    let spec = |m| RunSpec {
        eta: 0.06531305526474723,
        ..RunSpec::new(p, 0.5, 1.0, m)
    };
    let t = simulate(&exc, &spec(Model::taylor(0.3, DEFAULT_TAYLOR_TOL))).unwrap();
    let d = simulate(&exc, &spec(Model::dp5(0.3, 1e-13))).unwrap();
    let d_default = simulate(&exc, &spec(Model::dp5(0.3, DEFAULT_RTOL))).unwrap();
    assert_eq!(
        (t.stop, t.impacts),
        (d.stop, d.impacts),
        "{t:?} against {d:?}"
    );
    assert_eq!(t.impacts, 521);
    let (err, err_dp5) = (
        (t.max_abs_x - d.max_abs_x).abs(),
        (d_default.max_abs_x - d.max_abs_x).abs(),
    );
    assert!(
        err <= err_dp5 && err_dp5 < 1e-10,
        "θmax/α off by {err:e} against DP5 at its default's {err_dp5:e}: {t:?} against {d:?}"
    );
}

/// As α → 0 the nonlinear equation tends to the linearised one, their
/// difference in the motion of order α² (MODEL.md §2): θmax/α by the Taylor
/// stepper approaches the exact stepper's closed form, the difference
/// falling fourfold each time α halves (4 ± 5 %, from 4e-3 to 1e-3 rad).
#[test]
fn a_slender_block_tends_to_the_linearised_closed_form_at_second_order() {
    let exc = far("RSN1111_KOBE_NIS000");
    for eta in [0.6, 0.4] {
        let run = |m| simulate(&exc, &RunSpec::new(2.0, 0.8, eta, m)).unwrap();
        let lin = run(Model::LINEARIZED);
        assert!(!lin.overturned() && lin.max_abs_x > 0.01, "{lin:?}");
        let diff =
            |alpha| (run(Model::taylor(alpha, DEFAULT_TAYLOR_TOL)).max_abs_x - lin.max_abs_x).abs();
        let d = [diff(4e-3), diff(2e-3), diff(1e-3)];
        for w in d.windows(2) {
            let ratio = w[0] / w[1];
            assert!((ratio - 4.0).abs() < 0.2, "η = {eta}: differences {d:?}");
        }
    }
}

/// One sample interval of Cape Mendocino (Δt = 0.02 s) holds two turning
/// points of a small rocking swing with ẋ of one sign at both ends: a
/// stepper that looked for one turning point only let the block settle
/// there and survive, where DP5 at 1e-13 (small steps) finds the impact
/// and the overturning 3 s later.
#[test]
fn an_interval_with_two_turning_points_keeps_its_impact() {
    let exc = far("RSN829_CAPEMEND_RIO360");
    let run = |m| simulate(&exc, &RunSpec::new(1.0, 0.7, 0.021077, m)).unwrap();
    let (t, d) = (
        run(Model::taylor(0.3, DEFAULT_TAYLOR_TOL)),
        run(Model::dp5(0.3, 1e-13)),
    );
    assert!(d.overturned() && t.overturned(), "{t:?} against {d:?}");
    assert_eq!(t.impacts, d.impacts);
    let (a, b) = (t.overturn_time_s.unwrap(), d.overturn_time_s.unwrap());
    assert!((a - b).abs() < 1e-9, "{a} against {b}");
}

/// The hard cases (`ida::HARD_CASES`): certified from the
/// Taylor stepper's default, a capacity equals the plain search by DP5 at
/// 1e-13 within the search's resolution, or is flagged chaotic where
/// DP5's certification from its default flags it too; no new flags.
#[test]
fn hard_cases_certify_to_dp5s_tight_search_or_are_chaotic_where_it_says() {
    for c in &HARD_CASES {
        let exc = far(c.record);
        let spec = |m| RunSpec::new(c.p, c.eps, 1.0, m);
        let by_taylor = capacity_certified(
            &exc,
            &spec(Model::taylor(c.alpha, DEFAULT_TAYLOR_TOL)),
            &c.grid,
            c.tol,
            Trace::StopAtFirst,
        )
        .unwrap();
        let by_dp5 = capacity_certified(
            &exc,
            &spec(Model::dp5(c.alpha, DEFAULT_RTOL)),
            &c.grid,
            c.tol,
            Trace::StopAtFirst,
        )
        .unwrap();
        let what = format!(
            "{c:?}: {} / {}",
            by_taylor.certification, by_dp5.certification
        );
        assert_eq!(
            by_taylor.certification.kind(),
            by_dp5.certification.kind(),
            "{what}"
        );
        if by_taylor.certification.certified() {
            let tight = capacity_traced(
                &exc,
                &spec(Model::dp5(c.alpha, 1e-13)),
                &c.grid,
                c.tol,
                Trace::StopAtFirst,
            )
            .unwrap();
            let (got, want) = (by_taylor.capacity.eta_c.unwrap(), tight.eta_c.unwrap());
            assert!(
                (got - want).abs() <= 2.0 * c.tol,
                "{what}: {got} against {want}"
            );
            assert!(
                matches!(by_taylor.certification, Certification::Tolerance { rtol, checked_rtol, .. }
                    if rtol == DEFAULT_TAYLOR_TOL && checked_rtol == DEFAULT_TAYLOR_TOL / 100.0),
                "{what}"
            );
        }
    }
}

/// `capacity` runs the Taylor stepper unless told otherwise, says so, and
/// gives DP5's capacity; a tolerance outside the integrator's range and an
/// unknown integrator in a pipeline are refused, naming the flag or key.
#[test]
fn the_command_line_and_pipelines_choose_the_integrator() {
    let dir = tempdir();
    let d = dir.path();
    let record = root().join("records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2");
    let capacity = |extra: &[&str]| {
        let mut args = vec![
            "capacity",
            "--record",
            record.to_str().unwrap(),
            "--p",
            "2",
            "--eps",
            "0.8",
            "--model",
            "nonlinear",
            "--alpha",
            "0.25",
            "--levels",
            "40",
            "--json",
        ];
        args.extend_from_slice(extra);
        rocking(d, &args)
    };
    let json = |out: std::process::Output| -> serde_json::Value {
        assert!(out.status.success(), "{}", stderr(&out));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let taylor = json(capacity(&[]));
    let dp5 = json(capacity(&["--integrator", "dp5"]));
    assert_eq!(taylor["integrator"], "taylor");
    assert_eq!(taylor["rtol"], DEFAULT_TAYLOR_TOL);
    assert_eq!(dp5["integrator"], "dp5");
    assert_eq!(dp5["rtol"], DEFAULT_RTOL);
    assert_eq!(taylor["eta_c"], dp5["eta_c"]);
    let out = capacity(&["--rtol", "1e-17"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("--rtol") && stderr(&out).contains("1e-15"),
        "{}",
        stderr(&out)
    );
    let body = "[model]\nkind = \"nonlinear\"\nalpha = 0.2\nintegrator = \"rk4\"\n\
                [blocks]\np = [1.0]\neps = [0.8]\n";
    let pipe = write_pipeline(d, "bad", body);
    let out = rocking(d, &["run", pipe.to_str().unwrap(), "--outputs", "out"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stderr(&out).contains("`model.integrator`") && stderr(&out).contains("taylor, dp5"),
        "{}",
        stderr(&out)
    );
}
