//! The solvers against independent truths: closed-form pulse criteria
//! (Housner 1963; the paper's Eq. 5; the full-cycle mode-0 bound), free
//! rocking in closed form, energy conservation, sign symmetry, and the
//! model's hard cases.

use rocking::ida::{capacity, ImGrid, Spacing};
use rocking::physics::{
    simulate, simulate_from, EventKind, Excitation, Model, Outcome, Overturn, Recorder, Rocking,
    RunSpec, Stop,
};

use crate::util::bundled;

const LIN: Model = Model::LINEARIZED;

fn run(exc: &Excitation, p: f64, eps: f64, eta: f64, model: Model) -> Outcome {
    simulate(exc, &RunSpec::new(p, eps, eta, model)).unwrap()
}

/// η_c by the IDA search refined to `tol`.
fn eta_c(exc: &Excitation, spec: RunSpec, tol: f64) -> f64 {
    let grid = ImGrid {
        eta_max: 1.0,
        eta_min: 1e-4,
        count: 400,
        spacing: Spacing::Log,
    };
    capacity(exc, &spec, &grid, tol).unwrap().eta_c.unwrap()
}

/// A rectangular pulse ψ̈ = 1 on [0, t_d] that is the whole record: the
/// forcing is exactly rectangular (no ramp), and what follows is free
/// rocking, decided from energy. No sampling error at all.
fn rectangle(t_d: f64, n: usize) -> Excitation {
    Excitation::new(&vec![1.0; n], t_d / (n - 1) as f64).unwrap()
}

#[test]
fn housner_rectangle_criterion_is_exact() {
    // Housner (1963): a half-cycle rectangular pulse of duration t_d
    // overturns the linearised block iff η < 1 − e^{−p t_d}.
    for f in [0.25f64, 0.5, 1.0, 2.0, 4.0, 8.0] {
        let exc = rectangle(1.0, 101);
        let exact = 1.0 - (-f).exp();
        let spec = RunSpec::new(f, 0.8, 1.0, LIN);
        // The whole record is one closed-form solution per interval; the
        // only error is rounding (~1e-15 per step, 100 steps).
        let c = eta_c(&exc, spec, 1e-13);
        assert!(
            (c - exact).abs() < 1e-12,
            "f = {f}: η_c = {c}, exact {exact}"
        );
        // Within 1e-9 of the critical value, the verdict on each side is right.
        assert!(
            run(&exc, f, 0.8, exact * (1.0 - 1e-9), LIN).overturned(),
            "f = {f} below"
        );
        assert!(
            !run(&exc, f, 0.8, exact * (1.0 + 1e-9), LIN).overturned(),
            "f = {f} above"
        );
    }
}

/// The paper's Eq. 5: safety wall of the symmetric exponential pulse
/// ψ̈(t) = (1 − e^{β(1 − |2t/t_d − 1|)}) / (1 − e^β), with the removable
/// singularity at f = 2β replaced by its limit.
fn eta_w_exponential(beta: f64, f: f64) -> f64 {
    let prefactor = 1.0 / (1.0 - beta.exp());
    if (f - 2.0 * beta).abs() < 1e-7 * f {
        // B = 1 + c (f − 2β) + …, B^{2β/(f−2β)} → e^{2βc}, with
        // c = d ln B / df at f = 2β = 1/2 − 1/(4β) + 1/(4β e^{2β}).
        let c = 0.5 - 1.0 / (4.0 * beta) + 1.0 / (4.0 * beta * (2.0 * beta).exp());
        return prefactor * (1.0 - (2.0 * beta * c).exp());
    }
    let base = f.exp() * (f + 2.0 * beta) / (2.0 * f * (f / 2.0 + beta).exp() - (f - 2.0 * beta));
    prefactor * (1.0 - base.powf(2.0 * beta / (f - 2.0 * beta)))
}

#[test]
fn exponential_pulse_family_matches_paper_eq5() {
    // Sampling the curved pulse at dt and interpolating linearly is the only
    // error; it is second order in dt. Measured at dt = 1e-4 s: at most 2e-8
    // over these cases (and 4× that at 2e-4), so 2e-7 is a 10× margin.
    let cases = [
        (-5.0, 1.0),
        (-5.0, 8.0),
        (-1.0, 3.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (3.0, 3.0),
        (3.0, 6.0),
        (3.0, 8.0),
    ];
    for (beta, f) in cases {
        let lobe = rocking::pulse::Pulse {
            shape: rocking::pulse::Shape::Exp { beta },
            cycle: rocking::pulse::Cycle::Half,
            t_d_s: 1.0,
        };
        let exc = lobe.excitation(10_000).unwrap(); // dt = 1e-4 s
        let c = eta_c(&exc, RunSpec::new(f, 0.7, 1.0, LIN), 1e-11);
        let w = eta_w_exponential(beta, f);
        assert!(
            (c - w).abs() < 2e-7,
            "β = {beta}, f = {f}: η_c = {c}, Eq. 5 gives {w}"
        );
    }
    // β → −∞ recovers Housner's rectangle (the gap closes like f/|β|).
    let housner = 1.0 - (-2.0f64).exp();
    assert!((eta_w_exponential(-1e3, 2.0) - housner).abs() < 1e-2);
    assert!((eta_w_exponential(-1e7, 2.0) - housner).abs() < 1e-6);
}

#[test]
fn full_cycle_pulse_mode_zero_bound_under_escape_criterion() {
    // ψ̈ = +1 for one lobe, −1 for the next, each of length t1 (f = p t1).
    // Without impact the block escapes after the pulse iff η < (1 − e^{−f})²
    // (MODEL.md §9). "Escape" = the static limit is not checked during the
    // pulse (a cap far away) and the record ends with the pulse.
    let k = 20_000;
    let dt = 1.0 / (k as f64 + 0.5); // lobe switch centred between two samples
    let mut samples = vec![1.0; k + 1];
    samples.extend(vec![-1.0; k + 1]);
    let exc = Excitation::new(&samples, dt).unwrap();
    for f in [0.5f64, 1.0, 2.0, 4.0] {
        let w = (1.0 - (-f).exp()).powi(2);
        let at = |eta: f64| {
            let spec = RunSpec {
                overturn: Overturn::Cap(1e12),
                ..RunSpec::new(f, 0.9, eta, LIN)
            };
            simulate(&exc, &spec).unwrap()
        };
        // The one-interval ramp at the switch is antisymmetric about it:
        // second-order error, below 1e-8 here; test at ±1e-7.
        let below = at(w * (1.0 - 1e-7));
        assert!(
            below.overturned() && below.impacts == 0 && below.overturn_after_record,
            "f = {f}"
        );
        let above = at(w * (1.0 + 1e-7));
        assert!(
            !(above.overturned() && above.impacts == 0),
            "f = {f}: {above:?}"
        );
    }
}

/// Free rocking from rest at x0 (ground still): impact speeds and the time
/// to rest in closed form. First impact after t1 = acosh(1/(1 − x0))/p at
/// speed v1 = p sqrt(1 − (1 − x0)²); a swing leaving the pivot at speed w
/// returns after (2/p) atanh(w/p).
#[test]
fn free_rocking_comes_to_rest_when_the_closed_form_says() {
    let (p, x0) = (2.0f64, 0.5f64);
    let quiet = Excitation::new(&vec![0.0; 40_001], 0.01).unwrap(); // 400 s of nothing
    let t1 = (1.0 / (1.0 - x0)).acosh() / p;
    let v1 = p * (1.0 - (1.0 - x0).powi(2)).sqrt();
    for eps in [0.3f64, 0.7, 0.95, 0.99] {
        let spec = RunSpec::new(p, eps, 0.5, LIN);
        let mut rec = Recorder::new(usize::MAX);
        let start = Rocking {
            x: x0,
            v: 0.0,
            s: 1.0,
        };
        let out = simulate_from(&quiet, &spec, Some(start), &mut rec).unwrap();
        assert!(!out.overturned());
        assert_eq!(out.stop, Stop::RestForGood);
        // Impacts until the speed after one falls below the rest tolerance.
        let n = (1..)
            .find(|&k| eps.powi(k) * v1 < spec.rest_tol * p)
            .unwrap();
        assert_eq!(out.impacts, n as u64, "ε = {eps}");
        let t_rest = rec
            .points
            .iter()
            .find(|q| q.kind == EventKind::Rest)
            .unwrap()
            .t_s;
        let t_closed: f64 = t1
            + (1..n)
                .map(|k| 2.0 / p * (eps.powi(k) * v1 / p).atanh())
                .sum::<f64>();
        // Each located impact carries a few ulps of time; n ≤ 2100 of them.
        assert!(
            (t_rest - t_closed).abs() < 1e-12 * n as f64,
            "ε = {eps}: {t_rest} vs {t_closed}"
        );
        // The same sum to infinity (the true rest time) differs by less than
        // the ignored tail, (2/p) Σ_{k≥n} ε^k v1/p ≲ 2·tol/(p(1 − ε)).
        let tail_bound = 2.0 * spec.rest_tol / (p * (1.0 - eps)) * 1.01;
        let t_infinite: f64 = t1
            + (1..20_000)
                .map(|k| 2.0 / p * (eps.powi(k) * v1 / p).atanh())
                .sum::<f64>();
        assert!((t_infinite - t_rest).abs() < tail_bound);
        // Impact speeds fall by ε each time (the n-th settles the block:
        // its row is the state after it, at rest).
        let speeds: Vec<f64> = rec
            .points
            .iter()
            .filter(|q| q.kind == EventKind::Impact)
            .map(|q| q.v.abs())
            .collect();
        let n = n as usize;
        assert_eq!(speeds.len(), n, "ε = {eps}");
        assert_eq!(speeds[n - 1], 0.0);
        for (k, v) in speeds.iter().enumerate().take(20.min(n - 1)) {
            let expected = eps.powi(k as i32 + 1) * v1;
            assert!(
                (v - expected).abs() < 1e-12 * v1,
                "impact {k}: {v} vs {expected}"
            );
        }
    }
}

#[test]
fn elastic_impacts_conserve_energy_and_never_rest() {
    let (p, x0) = (3.0f64, 0.5f64);
    let quiet = Excitation::new(&vec![0.0; 6001], 0.005).unwrap(); // 30 s
    let v1 = p * (1.0 - (1.0 - x0).powi(2)).sqrt();
    let spec = RunSpec::new(p, 1.0, 0.5, LIN);
    let mut rec = Recorder::new(usize::MAX);
    let out = simulate_from(
        &quiet,
        &spec,
        Some(Rocking {
            x: x0,
            v: 0.0,
            s: 1.0,
        }),
        &mut rec,
    )
    .unwrap();
    assert_eq!(out.stop, Stop::Survived);
    assert!(rec.points.iter().all(|q| q.kind != EventKind::Rest));
    // Half-period between impacts: (2/p) atanh(v1/p); the first at t1.
    let t1 = (1.0 / (1.0 - x0)).acosh() / p;
    let half = 2.0 / p * (v1 / p).atanh();
    let expected_impacts = ((30.0 - t1) / half).floor() as u64 + 1;
    assert_eq!(out.impacts, expected_impacts);
    for q in rec.points.iter().filter(|q| q.kind == EventKind::Impact) {
        assert!(
            (q.v.abs() - v1).abs() < 1e-11 * v1,
            "speed {} vs {v1}",
            q.v.abs()
        );
    }
    assert!((out.max_abs_x - x0).abs() < 1e-12);
}

#[test]
fn amplitude_between_samples_is_the_exact_turning_point() {
    // Leaving the pivot at speed w on still ground, the swing peaks at
    // 1 − sqrt(1 − (w/p)²) (MODEL.md §9), between samples in general.
    let quiet = Excitation::new(&vec![0.0; 101], 0.02).unwrap();
    for (p, w) in [(1.0, 0.3), (4.0, 2.0), (10.0, 9.9)] {
        let spec = RunSpec::new(p, 0.5, 0.5, LIN);
        let out = simulate_from(
            &quiet,
            &spec,
            Some(Rocking {
                x: 0.0,
                v: -w,
                s: -1.0,
            }),
            &mut (),
        )
        .unwrap();
        let expected = 1.0 - (1.0 - (w / p) * (w / p)).sqrt();
        assert!(
            (out.max_abs_x - expected).abs() < 1e-14,
            "p = {p}: {} vs {expected}",
            out.max_abs_x
        );
    }
}

#[test]
fn peak_a_hair_above_threshold_lifts_imperceptibly_and_settles() {
    // A triangular record peaking at 1, run at η just below 1: the block lifts
    // for ~2δ/|slope| s. Its motion scales as δ³ (force ∝ δ over a time ∝ δ,
    // displacement ∝ force·time²), so doubling δ must multiply θmax by 8:
    // only a solver that keeps relative precision at 1e-30 gets that right.
    let mut samples: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    samples.extend((0..100).rev().map(|i| i as f64 / 100.0));
    samples.extend(vec![0.0; 200]);
    let exc = Excitation::new(&samples, 0.01).unwrap();
    let mut peaks = Vec::new();
    for delta in [1e-12, 2e-12, 4e-12] {
        let out = run(&exc, 2.0, 0.7, 1.0 - delta, LIN);
        assert!(!out.overturned());
        assert!(out.first_uplift_s.is_some(), "it does lift");
        assert_eq!(out.stop, Stop::RestForGood, "and it settles for good");
        assert!(
            out.max_abs_x > 0.0 && out.max_abs_x < 1e-30,
            "{}",
            out.max_abs_x
        );
        peaks.push(out.max_abs_x);
    }
    for w in peaks.windows(2) {
        assert!(
            (w[1] / w[0] - 8.0).abs() < 8.0 * 1e-3,
            "ratio {} (peaks {peaks:?})",
            w[1] / w[0]
        );
    }
    // At exactly the threshold nothing moves.
    let out = run(&exc, 2.0, 0.7, 1.0, LIN);
    assert_eq!((out.first_uplift_s, out.max_abs_x), (None, 0.0));
}

#[test]
fn a_sample_exactly_at_the_threshold_does_not_lift_the_block() {
    // 0.2 → 0.9 over one interval: 0.2 + ((0.9 − 0.2)/dt)·dt rounds to
    // 0.9000000000000001, past a threshold of exactly 0.9 that the record only
    // touches. Only the later peak of 1 may lift the block.
    let mut samples = vec![0.0, 0.2, 0.9, 0.2, 0.0];
    samples.extend(vec![0.0; 45]);
    samples.extend([0.5, 1.0, 0.5, 0.0]);
    samples.extend(vec![0.0; 20]);
    for dt in [0.01, 0.02, 0.005] {
        let exc = Excitation::new(&samples, dt).unwrap();
        // The uplift threshold is η·tan α / α for the nonlinear equation (MODEL.md §3).
        for (model, alpha_factor) in [(LIN, 1.0), (Model::dp5(0.1, 1e-9), 0.1f64.tan() / 0.1)] {
            let out = run(&exc, 2.0, 0.8, 0.9 / alpha_factor, model);
            let t = out.first_uplift_s.expect("the later peak lifts it");
            assert!(
                t > 50.0 * dt,
                "dt = {dt}: lifted at {t} s by the touch at {} s",
                2.0 * dt
            );
        }
    }
}

#[test]
fn flipping_the_record_gives_the_same_response() {
    for stem in [
        "far-field/RSN1111_KOBE_NIS000",
        "far-field/RSN848_LANDERS_CLW-LN",
    ] {
        let exc = bundled(stem);
        let neg = exc.negated();
        for (p, eps, eta) in [(1.0, 0.8, 0.3), (3.0, 0.6, 0.2), (8.0, 0.95, 0.5)] {
            for model in [LIN, Model::dp5(0.2, 1e-8)] {
                let a = run(&exc, p, eps, eta, model);
                let b = run(&neg, p, eps, eta, model);
                assert_eq!(a.overturned(), b.overturned(), "{stem} {p} {eps} {eta}");
                assert_eq!(a.impacts, b.impacts);
                assert!((a.max_abs_x - b.max_abs_x).abs() <= 1e-12 * a.max_abs_x.max(1e-300));
            }
        }
    }
}

#[test]
fn results_do_not_depend_on_the_rest_tolerance() {
    // θmax/α and the fate, over a spread of blocks on two records, at the
    // default rest tolerance and 100× either side.
    for stem in [
        "far-field/RSN953_NORTHR_MUL009",
        "far-field/RSN1633_MANJIL_ABBAR--L",
    ] {
        let exc = bundled(stem);
        for (p, eps, eta) in [
            (0.5, 0.6, 0.05),
            (2.0, 0.9, 0.2),
            (6.0, 0.7, 0.4),
            (12.0, 0.95, 0.6),
        ] {
            let base = RunSpec::new(p, eps, eta, LIN);
            let a = simulate(&exc, &base).unwrap();
            for tol in [base.rest_tol * 100.0, base.rest_tol / 100.0] {
                let b = simulate(
                    &exc,
                    &RunSpec {
                        rest_tol: tol,
                        ..base
                    },
                )
                .unwrap();
                assert_eq!(a.overturned(), b.overturned(), "{stem} p = {p}");
                assert!(
                    (a.max_abs_x - b.max_abs_x).abs() <= 1e-9 * a.max_abs_x,
                    "{stem} p = {p}: {} vs {}",
                    a.max_abs_x,
                    b.max_abs_x
                );
            }
        }
    }
}

#[test]
fn extremes_run_to_a_verdict() {
    // p from 0.1 to 20 1/s, ε from 0.3 to 1, dt from 0.0025 to 0.02 s, the
    // longest bundled record (18,000 samples): every capacity search ends
    // with a verdict, never at the event limit, and η_c is in (0, 1).
    let records = [
        "far-field/RSN848_LANDERS_CLW-LN",            // dt = 0.0025
        "far-field/RSN1633_MANJIL_ABBAR--L",          // dt = 0.02
        "near-field-pulse/RSN1529_CHICHI_TCU102_278", // 18,000 samples
    ];
    for stem in records {
        let exc = bundled(stem);
        for p in [0.1, 1.0, 20.0] {
            for eps in [0.3, 1.0] {
                let grid = ImGrid {
                    count: 60,
                    ..ImGrid::default()
                };
                let cap = capacity(&exc, &RunSpec::new(p, eps, 1.0, LIN), &grid, 1e-4).unwrap();
                assert!(
                    cap.points
                        .iter()
                        .all(|q| q.outcome.stop != Stop::EventLimit),
                    "{stem} {p} {eps}"
                );
                if let Some(c) = cap.eta_c {
                    assert!(c > 0.0 && c < 1.0);
                    assert!(cap.eta_survived - c <= 1e-4 && cap.eta_survived > c);
                }
            }
        }
    }
    // A record of zeros never lifts the block.
    let zeros = Excitation::new(&vec![0.0; 1000], 0.01).unwrap();
    let out = run(&zeros, 5.0, 0.8, 1e-6, LIN);
    assert_eq!(
        (out.first_uplift_s, out.max_abs_x, out.stop),
        (None, 0.0, Stop::RestForGood)
    );
}

#[test]
fn nonlinear_capacity_tends_to_linearised_as_alpha_vanishes() {
    // On Housner's rectangle (exact forcing) the nonlinear capacity differs
    // from 1 − e^{−f} by O(α²): quartering α must cut the gap ~16×.
    let exc = rectangle(1.0, 201);
    let f = 2.0f64;
    let exact = 1.0 - (-f).exp();
    let gaps: Vec<f64> = [0.2, 0.1, 0.05, 0.025]
        .iter()
        .map(|&alpha| {
            let spec = RunSpec::new(f, 0.8, 1.0, Model::dp5(alpha, 1e-10));
            (eta_c(&exc, spec, 1e-10) - exact).abs()
        })
        .collect();
    for w in gaps.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            ratio > 3.5 && ratio < 4.5,
            "halving α divides the gap by {ratio} ({gaps:?})"
        );
    }
    assert!(gaps[3] < 1e-3);
}

#[test]
fn nonlinear_solver_converges_with_its_tolerance() {
    // θmax/α on a real record: tightening rtol converges; rtol 1e-6 is within
    // 1e-4 relative of rtol 1e-11.
    let exc = bundled("far-field/RSN1111_KOBE_NIS000");
    let at = |rtol| run(&exc, 2.0, 0.8, 0.3, Model::dp5(0.15, rtol)).max_abs_x;
    let reference = at(1e-11);
    assert!(
        reference > 0.05 && reference < 1.0,
        "a rocking but surviving case: {reference}"
    );
    assert!((at(1e-6) - reference).abs() < 1e-4 * reference);
    assert!((at(1e-9) - reference).abs() < 1e-6 * reference);
}

#[test]
fn nonlinear_free_rocking_conserves_energy_with_elastic_impacts() {
    // ε = 1, ground still: every impact at the same speed, fixed by the
    // release height: ½w² = (p²/α²)(cos α − cos(α(1 − x0))).
    let (p, alpha, x0) = (2.0f64, 0.25f64, 0.6f64);
    let quiet = Excitation::new(&vec![0.0; 2001], 0.01).unwrap();
    let w = (2.0 * p * p / (alpha * alpha) * ((alpha * (1.0 - x0)).cos() - alpha.cos())).sqrt();
    let spec = RunSpec::new(p, 1.0, 0.5, Model::dp5(alpha, 1e-10));
    let mut rec = Recorder::new(usize::MAX);
    simulate_from(
        &quiet,
        &spec,
        Some(Rocking {
            x: x0,
            v: 0.0,
            s: 1.0,
        }),
        &mut rec,
    )
    .unwrap();
    let speeds: Vec<f64> = rec
        .points
        .iter()
        .filter(|q| q.kind == EventKind::Impact)
        .map(|q| q.v.abs())
        .collect();
    assert!(speeds.len() > 5);
    for v in speeds {
        assert!((v - w).abs() < 1e-7 * w, "{v} vs {w}");
    }
}

#[test]
fn the_fast_path_and_the_event_by_event_walk_agree_to_the_bit() {
    // Without an observer the driver crosses eventless intervals in the
    // exact stepper's tight loop (`Stepper::cruise`); with a recorder it
    // walks every interval through `rock`. Two code paths, one answer: the
    // same outcome, bit for bit, over strong and weak shaking.
    use rocking::physics::simulate_observed;
    let (mut rocked, mut overturned) = (0, 0);
    for stem in [
        "far-field/RSN1111_KOBE_NIS000",
        "far-field/RSN169_IMPVALL_H-DLT352",
    ] {
        let exc = bundled(stem);
        for (p, eps) in [(1.0, 0.9), (3.0, 0.7), (8.0, 0.95)] {
            for eta in [0.02, 0.05, 0.1, 0.2, 0.4] {
                let spec = RunSpec::new(p, eps, eta, LIN);
                let fast = simulate(&exc, &spec).unwrap();
                let walked = simulate_observed(&exc, &spec, &mut Recorder::new(1)).unwrap();
                assert_eq!(fast, walked, "{stem} p = {p} ε = {eps} η = {eta}");
                assert_eq!(fast.max_abs_x.to_bits(), walked.max_abs_x.to_bits());
                rocked += usize::from(fast.impacts > 10 && !fast.overturned());
                overturned += usize::from(fast.overturned());
            }
        }
    }
    // Both kinds of run were compared.
    assert!(
        rocked >= 5 && overturned >= 5,
        "{rocked} rocked, {overturned} overturned"
    );
}

/// Two runs that differ in η alone, run in step (`simulate_pair`: their
/// eventless intervals two lanes of one vector), must each give the outcome
/// it gives alone, to the bit: verdict, θmax, impacts, times and intervals.
/// Over the chaos probe's pairs (η moved by ±1e-9, runs that stay in step
/// for most of the record) and pairs 2 % and 30 % apart (runs that part at
/// the first uplift, one catching up to the other at each event), either
/// order, records of every time step, slender to squat blocks and the
/// overturning criteria that stop the stepper differently; for the exact
/// stepper of the linearised equation and the Taylor stepper of the
/// nonlinear one. Three and four runs in step (`simulate_lanes`, the Taylor
/// stepper's four lanes, three with their tolerances apart; refused for the
/// exact stepper) likewise.
#[test]
fn runs_in_step_agree_with_runs_alone_to_the_bit() {
    use rocking::physics::Isa;
    if !Isa::detected().has_lanes() {
        eprintln!("skipped: runs are kept in step only by the x86-64-v3 compilation");
        return;
    }
    runs_in_step_agree(
        LIN,
        &[Overturn::Static, Overturn::Escape, Overturn::Cap(2.0)],
        16,
    );
    // The Taylor stepper: a squat block (α = 0.25), far from the
    // linearised model, at its default tail and at the checking one.
    let tail = rocking::physics::DEFAULT_TAYLOR_TOL;
    for tol in [tail, tail / rocking::ida::TIGHTEN] {
        runs_in_step_agree(
            Model::taylor(0.25, tol),
            &[Overturn::Static, Overturn::Escape],
            8,
        );
    }
}

fn runs_in_step_agree(model: Model, overturns: &[Overturn], levels: usize) {
    use rocking::physics::{simulate_lanes, simulate_pair, Integrator};
    let (mut pairs, mut overturned, mut split) = (0, 0, 0);
    let (mut fours, mut mixed) = (0, 0);
    // Four lanes are the Taylor stepper's; the exact stepper runs two.
    let four_lanes = matches!(model.integrator, Integrator::Taylor { .. });
    for stem in [
        "far-field/RSN848_LANDERS_CLW-LN",
        "far-field/RSN1111_KOBE_NIS000",
        "far-field/RSN1633_MANJIL_ABBAR--L",
    ] {
        let exc = bundled(stem);
        for p in [0.5, 2.0, 8.0] {
            for eps in [0.5, 0.9] {
                for &overturn in overturns {
                    for j in 0..levels {
                        let eta = 10f64.powf(-1.6 * j as f64 / (levels - 1) as f64);
                        for moved in [
                            eta * (1.0 + 1e-9),
                            eta * (1.0 - 1e-9),
                            eta * 1.02,
                            eta / 1.3,
                        ] {
                            let spec = |eta| RunSpec {
                                overturn,
                                ..RunSpec::new(p, eps, eta, model)
                            };
                            let (a, b) = (spec(eta), spec(moved));
                            let alone = [simulate(&exc, &a).unwrap(), simulate(&exc, &b).unwrap()];
                            let in_step =
                                simulate_pair(&exc, [&a, &b]).expect("v3 runs a pair in step");
                            assert_eq!(
                                format!("{alone:?}"),
                                format!("{in_step:?}"),
                                "{model:?}: {stem} p = {p}, ε = {eps}, η = {eta} and {moved}, \
                                 {overturn:?}"
                            );
                            let [qb, qa] =
                                simulate_pair(&exc, [&b, &a]).expect("v3 runs a pair in step");
                            assert_eq!(
                                format!("{:?}", [qa, qb]),
                                format!("{alone:?}"),
                                "the other order: {stem} p = {p}, ε = {eps}, η = {eta} and {moved}"
                            );
                            pairs += 1;
                            overturned += usize::from(alone[0].overturned());
                            split += usize::from(alone[0].overturned() != alone[1].overturned());
                        }
                        // Four at once (two probes' pairs, and levels that
                        // part), in two orders: lanes end at different
                        // times, and the others go on without them. Three
                        // (a run with its probes at the checking tail, a
                        // lane left empty).
                        let spec = |eta| RunSpec {
                            overturn,
                            ..RunSpec::new(p, eps, eta, model)
                        };
                        let tighter = |eta| RunSpec {
                            model: tightened(model),
                            ..spec(eta)
                        };
                        let etas = [
                            eta * (1.0 + 1e-9),
                            eta * 1.02,
                            eta * (1.0 - 1e-9),
                            eta / 1.3,
                        ];
                        let sets = [
                            [0, 1, 2, 3].map(|i| spec(etas[i])).to_vec(),
                            [3, 2, 1, 0].map(|i| spec(etas[i])).to_vec(),
                            vec![spec(eta), tighter(etas[0]), tighter(etas[2])],
                        ];
                        for set in &sets {
                            let alone: Vec<_> =
                                set.iter().map(|s| simulate(&exc, s).unwrap()).collect();
                            match simulate_lanes(&exc, set) {
                                Some(in_step) => assert_eq!(
                                    format!("{alone:?}"),
                                    format!("{in_step:?}"),
                                    "{model:?}: {stem} p = {p}, ε = {eps}, {set:?}"
                                ),
                                None => assert!(!four_lanes, "{model:?}: runs in step refused"),
                            }
                            fours += 1;
                            let over = alone.iter().filter(|o| o.overturned()).count();
                            mixed += usize::from(over > 0 && over < set.len());
                        }
                    }
                }
            }
        }
    }
    // Both verdicts, and pairs whose runs end differently, were compared.
    assert!(
        overturned > pairs / 5 && overturned < pairs * 4 / 5 && split > 20,
        "{model:?}: {overturned} overturned, {split} split, of {pairs}"
    );
    assert!(
        mixed > 10,
        "{model:?}: {mixed} of {fours} sets end both ways"
    );
}

/// `model` with the Taylor stepper's tail tightened as a certification
/// checks it; any other model as it is.
fn tightened(model: Model) -> Model {
    use rocking::physics::Integrator;
    match model.integrator {
        Integrator::Taylor { tol } => Model {
            integrator: Integrator::Taylor {
                tol: tol / rocking::ida::TIGHTEN,
            },
            ..model
        },
        _ => model,
    }
}

/// The compilations this CPU runs besides the baseline (`Isa`: x86-64-v3
/// and v4), each to be held equal to it.
fn other_compilations() -> Vec<rocking::physics::Isa> {
    use rocking::physics::Isa;
    let others: Vec<Isa> = [Isa::V3, Isa::V4]
        .into_iter()
        .filter(|isa| isa.available())
        .collect();
    if others.is_empty() {
        eprintln!("skipped: this CPU lacks x86-64-v3, so only the baseline compilation runs");
    }
    others
}

/// The exact stepper's compilations (`Isa`: the x86-64 baseline, x86-64-v3
/// and v4) do the same IEEE operations in the same order, so every outcome
/// must be identical to the bit: verdict, θmax, impacts, times and
/// intervals. Over records of every time step, slender to squat blocks,
/// three restitutions, levels from no uplift to overturning at once, and
/// both overturning criteria that stop the stepper differently.
#[test]
fn every_compilation_of_the_exact_stepper_agrees_to_the_bit() {
    use rocking::physics::{simulate_on, Isa};
    let others = other_compilations();
    let (mut runs, mut overturned) = (0, 0);
    for stem in [
        "far-field/RSN848_LANDERS_CLW-LN",
        "far-field/RSN1148_KOCAELI_ARC000",
        "far-field/RSN1111_KOBE_NIS000",
        "far-field/RSN1633_MANJIL_ABBAR--L",
    ] {
        let exc = bundled(stem);
        for p in [0.5, 2.0, 8.0] {
            for eps in [0.5, 0.9] {
                for overturn in [Overturn::Static, Overturn::Escape] {
                    for j in 0..30 {
                        let eta = 10f64.powf(-2.0 * j as f64 / 29.0);
                        let spec = RunSpec {
                            overturn,
                            ..RunSpec::new(p, eps, eta, LIN)
                        };
                        let base = simulate_on(&exc, &spec, Isa::Baseline).unwrap();
                        for &isa in &others {
                            let other = simulate_on(&exc, &spec, isa).unwrap();
                            assert_eq!(
                                format!("{base:?}"),
                                format!("{other:?}"),
                                "{isa:?}: {stem} p = {p}, ε = {eps}, η = {eta}, {overturn:?}"
                            );
                        }
                        runs += 1;
                        overturned += usize::from(base.overturned());
                    }
                }
            }
        }
    }
    // The set spans both verdicts (the comparison means little otherwise).
    assert!(
        overturned > runs / 5 && overturned < runs * 4 / 5,
        "{overturned} of {runs}"
    );
}

/// The Taylor stepper is compiled for each too (its step and series are
/// `#[inline(always)]` into the event loop): every outcome identical to the
/// bit, over records of every time step, slender and stocky blocks, and
/// levels from no uplift to overturning at once.
#[test]
fn every_compilation_of_the_taylor_stepper_agrees_to_the_bit() {
    use rocking::physics::{simulate_on, Isa, DEFAULT_TAYLOR_TOL};
    let others = other_compilations();
    let (mut runs, mut overturned) = (0, 0);
    for stem in [
        "far-field/RSN848_LANDERS_CLW-LN",
        "far-field/RSN1111_KOBE_NIS000",
        "far-field/RSN1633_MANJIL_ABBAR--L",
    ] {
        let exc = bundled(stem);
        for (p, alpha) in [(0.5, 0.1), (2.0, 0.25), (8.0, 0.4)] {
            for j in 0..12 {
                let eta = 10f64.powf(-1.5 * j as f64 / 11.0);
                let spec = RunSpec::new(p, 0.8, eta, Model::taylor(alpha, DEFAULT_TAYLOR_TOL));
                let base = simulate_on(&exc, &spec, Isa::Baseline).unwrap();
                for &isa in &others {
                    let other = simulate_on(&exc, &spec, isa).unwrap();
                    assert_eq!(
                        format!("{base:?}"),
                        format!("{other:?}"),
                        "{isa:?}: {stem} p = {p}, α = {alpha}, η = {eta}"
                    );
                }
                runs += 1;
                overturned += usize::from(base.overturned());
            }
        }
    }
    assert!(
        overturned > runs / 5 && overturned < runs * 4 / 5,
        "{overturned} of {runs}"
    );
}

/// A block whose rocking grows many e-folds within one sample interval:
/// under a constant forcing just past the uplift threshold (ψ̈ = 1, η just
/// below one) the linearised block leaves rest at once and
/// x = (1/η − 1)(cosh pt − 1), so it overturns (x = 1) at
/// t = acosh(1/(1 − η))/p, here p·t = 14.5 within
/// the first one-second interval, with p·Δt up to the stepper's bound
/// (`MAX_P_DT` = 100). Past the bound the run is refused, naming p·Δt: there
/// located events lost their digits (an overturning 0.02 s late at
/// p·Δt = 300) and past 709 e^{p·Δt} overflowed into a block that
/// "survived" though it overturns.
#[test]
fn the_exact_step_takes_long_intervals_up_to_its_bound_and_refuses_beyond() {
    let step = Excitation::new(&[1.0; 6], 1.0).unwrap();
    let eta = 1.0 - 1e-6;
    for p in [5.0, 20.0, 50.0, 100.0] {
        let out = run(&step, p, 0.9, eta, LIN);
        let t = out.overturn_time_s.expect("it overturns");
        let truth = (1.0 / (1.0 - eta)).acosh() / p;
        assert!(
            (t - truth).abs() <= 1e-12 * truth,
            "p = {p}: {t} against {truth}"
        );
    }
    for p in [100.5, 300.0, 1000.0] {
        let e = simulate(&step, &RunSpec::new(p, 0.9, eta, LIN)).unwrap_err();
        assert!(e.to_string().contains("is above 100"), "p = {p}: {e}");
        // The nonlinear model cuts its own steps, and takes it.
        let nonlinear = Model::nonlinear(0.01, rocking::physics::Solver::default());
        assert!(simulate(&step, &RunSpec::new(p, 0.9, eta, nonlinear)).is_ok());
    }
}
