//! The block that slides (`Equation::SlideRock`) against independent
//! truths: the rocking model where friction never binds, Newmark's sliding
//! block under rectangular and half-sine pulses, the work of friction,
//! Shenton's initiation criteria by a contact solve written here, the
//! instant a rocking block's friction gives way by an RK4 of the rocking
//! equation written here, and the energy of the free motion.

use rocking::ida::HARD_CASES;
use rocking::label::Label;
use rocking::physics::friction::{Friction, G};
use rocking::physics::{
    simulate, simulate_observed, EventKind, Excitation, HistoryPoint, Mode, Model, Outcome,
    Recorder, RunSpec, Solver, Stop,
};

use crate::util::bundled;

fn slide_rock(alpha: f64, mu: f64) -> Model {
    Model::slide_rock(alpha, Friction::new(mu), Solver::default())
}

fn history(exc: &Excitation, spec: &RunSpec) -> (Outcome, Vec<HistoryPoint>) {
    let mut rec = Recorder::new(1);
    let out = simulate_observed(exc, spec, &mut rec).unwrap();
    (out, rec.points)
}

/// Far-field records of the bundled set the checks run on.
const RECORDS: [&str; 6] = [
    "RSN1633_MANJIL_ABBAR--L",
    "RSN169_IMPVALL_H-DLT262",
    "RSN829_CAPEMEND_RIO360",
    "RSN848_LANDERS_CLW-LN",
    "RSN1111_KOBE_NIS000",
    "RSN1158_KOCAELI_DZC180",
];

fn far(stem: &str) -> Excitation {
    bundled(&format!("far-field/{stem}"))
}

#[test]
fn where_friction_never_binds_the_block_rocks_as_the_rocking_model_to_the_bit() {
    let (mut compared, mut slipped) = (0, 0);
    let mut cases: Vec<(&str, f64, f64, f64)> = HARD_CASES
        .iter()
        .map(|c| (c.record, c.p, c.eps, c.alpha))
        .collect();
    for stem in RECORDS {
        cases.push((stem, 2.0, 0.9, 0.2));
        cases.push((stem, 1.0, 0.7, 0.1));
    }
    for (stem, p, eps, alpha) in cases {
        let exc = far(stem);
        for eta in [0.05, 0.1, 0.2, 0.4, 0.7, 1.0] {
            let rocking = RunSpec::new(p, eps, eta, Model::nonlinear(alpha, Solver::default()));
            let sliding = RunSpec {
                model: slide_rock(alpha, 1.3),
                ..rocking
            };
            let a = simulate(&exc, &rocking).unwrap();
            let b = simulate(&exc, &sliding).unwrap();
            if b.slips > 0 {
                slipped += 1;
                continue;
            }
            compared += 1;
            assert_eq!(a.stop, b.stop, "{stem} p {p} η {eta}");
            assert_eq!(a.impacts, b.impacts, "{stem} p {p} η {eta}");
            // The same steps in the same order: equal to the bit (the
            // issue asks 1e-12).
            assert_eq!(
                a.max_abs_x.to_bits(),
                b.max_abs_x.to_bits(),
                "{stem} p {p} η {eta}: {} vs {}",
                a.max_abs_x,
                b.max_abs_x
            );
            assert_eq!(a.overturn_time_s, b.overturn_time_s);
            assert_eq!(b.slide_max_m, 0.0);
        }
    }
    eprintln!("compared {compared}, slipped {slipped}");
    assert!(compared > 60, "{compared}");
}

/// A block of slenderness α (b/h = tan α) with μ below b/h under a
/// rectangular pulse ψ̈ = 1 for `t_d` seconds that is the whole record.
fn rectangle(t_d: f64, n: usize) -> Excitation {
    Excitation::new(&vec![1.0; n], t_d / (n - 1) as f64).unwrap()
}

#[test]
fn a_stocky_block_under_a_rectangular_pulse_slides_as_newmark() {
    for (alpha, mu, ratio, t_d) in [
        (0.6f64, 0.3, 2.0, 0.5),
        (0.8, 0.5, 1.3, 0.2),
        (0.7, 0.2, 4.0, 1.0),
    ] {
        // A = αg/η at ψ̈ = 1: η for A = ratio·μg.
        let eta = alpha / (ratio * mu);
        let a = ratio * mu * G;
        let exc = rectangle(t_d, 201);
        let spec = RunSpec::new(2.0, 0.9, eta, slide_rock(alpha, mu));
        let (out, points) = history(&exc, &spec);
        let newmark = 0.5 * (a - mu * G) * t_d * t_d * a / (mu * G);
        let rel = (out.slide_residual_m - newmark).abs() / newmark;
        assert!(
            rel < 1e-9,
            "α {alpha} μ {mu}: {} vs {newmark}",
            out.slide_residual_m
        );
        assert_eq!(out.slide_max_m, out.slide_residual_m);
        assert_eq!(out.stop, Stop::Survived);
        assert_eq!(out.max_abs_x, 0.0, "it never rocks");
        assert_eq!(out.mode_s[Mode::Slide as usize], t_d);
        // Work: the inertial force A over the slide during the pulse equals
        // the friction μg over the whole slide (the block starts and ends
        // at rest relative to the ground).
        let at_end = points
            .iter()
            .find(|p| p.kind == EventKind::RecordEnd)
            .unwrap();
        let work_in = a * at_end.u_m;
        let work_out = mu * G * out.slide_residual_m;
        assert!((work_in - work_out).abs() < 1e-9 * work_in);
    }
}

#[test]
fn a_stocky_block_under_a_half_sine_slides_as_its_closed_form() {
    // ψ̈ = sin(πt/t_d) on [0, t_d]; the block slides from t₁ where
    // A sin(πt₁/t_d) = μg; w(t) = (A t_d/π)(cos πt₁/t_d − cos πt/t_d) − μg(t − t₁)
    // while positive; after the pulse it runs out at μg.
    let (alpha, mu, ratio, t_d) = (0.6f64, 0.3, 2.5, 0.4);
    let eta = alpha / (ratio * mu);
    let a = ratio * mu * G;
    let n = 200_001;
    let dt = t_d / (n - 1) as f64;
    let samples: Vec<f64> = (0..n)
        .map(|i| (std::f64::consts::PI * i as f64 * dt / t_d).sin())
        .collect();
    let exc = Excitation::new(&samples, dt).unwrap();
    let spec = RunSpec::new(2.0, 0.9, eta, slide_rock(alpha, mu));
    let out = simulate(&exc, &spec).unwrap();
    let om = std::f64::consts::PI / t_d;
    let s1 = mu * G / a;
    let t1 = s1.asin() / om;
    let c1 = (om * t1).cos();
    let w_td = (a / om) * (c1 + 1.0) - mu * G * (t_d - t1);
    assert!(w_td > 0.0, "the slide outlasts the pulse");
    let u_td = (a / om) * (c1 * (t_d - t1) + s1 / om) - 0.5 * mu * G * (t_d - t1).powi(2);
    let exact = u_td + w_td * w_td / (2.0 * mu * G);
    let rel = (out.slide_residual_m - exact).abs() / exact;
    // The record is the half sine sampled: its interpolation errs by
    // (πΔt/t_d)²/8 ≈ 3e-11 relative.
    assert!(rel < 1e-9, "{} vs {exact}: {rel:e}", out.slide_residual_m);
}

/// Gaussian elimination with partial pivoting for a 3×3 system.
fn solve3(mut m: [[f64; 3]; 3], mut r: [f64; 3]) -> [f64; 3] {
    for col in 0..3 {
        let piv = (col..3)
            .max_by(|&i, &j| m[i][col].abs().total_cmp(&m[j][col].abs()))
            .unwrap();
        m.swap(col, piv);
        r.swap(col, piv);
        let top = m[col];
        for row in col + 1..3 {
            let f = m[row][col] / top[col];
            for (v, t) in m[row].iter_mut().zip(top).skip(col) {
                *v -= f * t;
            }
            r[row] -= f * r[col];
        }
    }
    let mut x = [0.0; 3];
    for row in (0..3).rev() {
        let mut acc = r[row];
        for k in row + 1..3 {
            acc -= m[row][k] * x[k];
        }
        x[row] = acc / m[row][row];
    }
    x
}

/// The modes consistent with a block at rest under a suddenly applied
/// horizontal inertial acceleration `a` (per mass, +X tips it onto the +X
/// corner), half-width `b`, half-height `h`, friction `mu` (Shenton 1996's
/// cases): each mode's Newton–Euler equations (unit mass, I = (b² + h²)/3
/// about the centre) solved for its unknowns, then its inequalities.
fn consistent_modes(a: f64, b: f64, h: f64, mu: f64) -> Vec<&'static str> {
    let g = G;
    let i_c = (b * b + h * h) / 3.0;
    let mut modes = Vec::new();
    if a.abs() <= mu * g && a.abs() <= g * b / h {
        modes.push("rest");
    }
    for dir in [1.0, -1.0] {
        // Flat slide: friction −μ·dir·g at the base; the resultant stays
        // within the base while μh ≤ b.
        let u_dd = a - mu * dir * g;
        if dir * u_dd > 0.0 && mu * h <= b {
            modes.push("slide");
        }
    }
    let s = a.signum();
    // Rock on pivot s: unknowns (θ̈, F, N); the centre's acceleration with
    // the pivot held is (h θ̈, s b θ̈) at θ = 0; the torque about the centre
    // of the pivot's force (F, N) at (s b, −h) is s b N + h F = −I θ̈ (θ
    // tips towards +X, clockwise).
    let [th, f, n] = solve3(
        [[h, -1.0, 0.0], [s * b, 0.0, -1.0], [i_c, h, s * b]],
        [a, -g, 0.0],
    );
    if s * th > 0.0 && n >= 0.0 && f.abs() <= mu * n {
        modes.push("rock");
    }
    for dir in [1.0, -1.0] {
        // Slide-rock: unknowns (θ̈, ü_p, N) with F = −μ dir N.
        let [th, u_dd, n] = solve3(
            [
                [h, 1.0, mu * dir],
                [s * b, 0.0, -1.0],
                [i_c, 0.0, s * b - h * mu * dir],
            ],
            [a, -g, 0.0],
        );
        if s * th > 0.0 && n >= 0.0 && dir * u_dd > 0.0 {
            modes.push("slide-rock");
        }
    }
    modes
}

/// The mode the tool starts in from rest under a step of ψ̈ = 1.
fn first_mode(points: &[HistoryPoint]) -> &'static str {
    match points.get(1) {
        Some(p) if p.t_s == 0.0 && p.kind == EventKind::Uplift => "rock",
        Some(p) if p.t_s == 0.0 && p.kind == EventKind::Slip && p.pivot == 0 => "slide",
        Some(p) if p.t_s == 0.0 && p.kind == EventKind::Slip => "slide-rock",
        _ => "rest",
    }
}

#[test]
fn from_rest_the_block_starts_in_the_mode_shentons_criteria_give() {
    let exc = Excitation::new(&[1.0, 1.0, 1.0], 0.001).unwrap();
    let (mut checked, mut every_mode, mut several) = (0, Vec::new(), 0);
    for b_over_h in [0.1f64, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0] {
        let alpha = b_over_h.atan();
        let h = 1.0;
        let b = b_over_h * h;
        let p = (0.75 * G / (b * b + h * h).sqrt()).sqrt();
        for mu in [0.05, 0.15, 0.25, 0.35, 0.5, 0.7, 0.9, 1.2] {
            for a_over_g in [0.03, 0.085, 0.155, 0.235, 0.32, 0.52, 0.83, 1.23, 2.1, 4.1] {
                let a = a_over_g * G;
                let eta = alpha * G / a;
                let spec = RunSpec::new(p, 0.9, eta, slide_rock(alpha, mu));
                let (_, points) = history(&exc, &spec);
                let tool = first_mode(&points);
                let modes = consistent_modes(a, b, h, mu);
                assert!(
                    modes.contains(&tool),
                    "b/h {b_over_h} μ {mu} a/g {a_over_g}: the tool {tool}, consistent {modes:?}"
                );
                several += usize::from(modes.len() > 1);
                if !every_mode.contains(&tool) {
                    every_mode.push(tool);
                }
                checked += 1;
            }
        }
    }
    every_mode.sort();
    assert_eq!(every_mode, ["rest", "rock", "slide", "slide-rock"]);
    eprintln!("{checked} grid points, {several} with more than one consistent mode");
}

/// F/N at the pivot of a block rocking about `s` (half-width b, height h
/// from the rigid-body equations with the pivot held), at angle θ, rate θ̇,
/// under the inertial acceleration `a`: written here from the centre's
/// acceleration about a fixed pivot.
fn demand(b: f64, h: f64, s: f64, th: f64, th_d: f64, a: f64) -> (f64, f64) {
    let r = (b * b + h * h).sqrt();
    let alpha = (b / h).atan();
    let phi = alpha - s * th;
    let p2 = 0.75 * G / r;
    let th_dd = p2 * (-s * phi.sin() + (a / G) * phi.cos());
    // The centre at (−s r sin φ, r cos φ) from the pivot.
    let xc_dd = r * (s * phi.sin() * th_d * th_d + phi.cos() * th_dd);
    let yc_dd = -r * phi.cos() * th_d * th_d + s * r * phi.sin() * th_dd;
    (xc_dd - a, yc_dd + G)
}

#[test]
fn a_rocking_block_starts_to_slip_when_its_friction_demand_reaches_mu() {
    // Blocks a little less stocky than μ: they rock, and strong shaking
    // asks the pivot for more than μN.
    let mut found = 0;
    for (stem, b_over_h, mu, eta) in [
        ("RSN1111_KOBE_NIS000", 0.2f64, 0.25, 0.08),
        ("RSN848_LANDERS_CLW-LN", 0.3, 0.36, 0.1),
        ("RSN169_IMPVALL_H-DLT262", 0.15, 0.2, 0.05),
    ] {
        let exc = far(stem);
        let alpha = b_over_h.atan();
        let (h, b) = (1.0, b_over_h);
        let p = (0.75 * G / (b * b + h * h).sqrt()).sqrt();
        let spec = RunSpec::new(p, 0.9, eta, slide_rock(alpha, mu));
        let (_, points) = history(&exc, &spec);
        // The first slip while rocking (not at an impact, where the check
        // is the demand just after it, below).
        let at_impact = |i: usize| {
            i > 0 && points[i - 1].kind == EventKind::Impact && points[i - 1].t_s == points[i].t_s
        };
        for (i, q) in points.iter().enumerate() {
            if q.kind == EventKind::Slip && at_impact(i) {
                let (f, n) = demand(b, h, f64::from(q.pivot), alpha * q.x, alpha * q.v, {
                    let k = (q.t_s / exc.dt_s) as usize;
                    let frac = q.t_s / exc.dt_s - k as f64;
                    alpha * G / eta * (exc.psi[k] + frac * (exc.psi[k + 1] - exc.psi[k]))
                });
                assert!(
                    f.abs() > mu * n,
                    "{stem} t {}: slipped after an impact",
                    q.t_s
                );
            }
        }
        let Some(slip) =
            (0..points.len()).find(|&i| points[i].kind == EventKind::Slip && !at_impact(i))
        else {
            panic!("{stem}: no slip while rocking");
        };
        let t_slip = points[slip].t_s;
        // The rocking trajectory up to it: the last point before it (a
        // sample, or the last event), then RK4 of the rocking equation
        // written here, steps of 1e-7 s, with the demand interpolated
        // linearly between steps.
        let start = points[..slip]
            .iter()
            .rev()
            .find(|q| q.pivot != 0 && q.t_s < t_slip)
            .unwrap();
        let s = f64::from(start.pivot);
        let a_at = |t: f64| {
            let k = ((t / exc.dt_s).floor() as usize).min(exc.psi.len() - 2);
            let frac = t / exc.dt_s - k as f64;
            alpha * G / eta * (exc.psi[k] + frac * (exc.psi[k + 1] - exc.psi[k]))
        };
        let accel = |t: f64, th: f64| {
            let phi = alpha - s * th;
            0.75 * G / (b * b + h * h).sqrt() * (-s * phi.sin() + a_at(t) / G * phi.cos())
        };
        let margin = |t: f64, th: f64, th_d: f64| {
            let (f, n) = demand(b, h, s, th, th_d, a_at(t));
            mu * n - f.abs()
        };
        let (mut t, mut th, mut th_d) = (start.t_s, alpha * start.x, alpha * start.v);
        let step = 1e-7;
        let mut m_prev = margin(t, th, th_d);
        assert!(m_prev >= 0.0);
        let crossing = loop {
            let k1 = (th_d, accel(t, th));
            let k2 = (
                th_d + 0.5 * step * k1.1,
                accel(t + 0.5 * step, th + 0.5 * step * k1.0),
            );
            let k3 = (
                th_d + 0.5 * step * k2.1,
                accel(t + 0.5 * step, th + 0.5 * step * k2.0),
            );
            let k4 = (th_d + step * k3.1, accel(t + step, th + step * k3.0));
            th += step / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            th_d += step / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            t += step;
            let m = margin(t, th, th_d);
            if m < 0.0 {
                break t - step * m / (m - m_prev);
            }
            m_prev = m;
            assert!(t < t_slip + 1e-3, "{stem}: no crossing near {t_slip}");
        };
        assert!(
            (crossing - t_slip).abs() < 1e-9,
            "{stem}: the tool slips at {t_slip}, the demand reaches μ at {crossing}"
        );
        eprintln!("{stem}: slip at {t_slip} s, demand at μ {crossing} s");
        found += 1;
    }
    assert_eq!(found, 3);
}

/// The block's mechanical energy per unit mass relative to the ground
/// (J/kg): kinetic (the centre's and the rotation's) and potential.
fn energy(q: &HistoryPoint, alpha: f64, r: f64) -> f64 {
    let (th, th_d) = (alpha * q.x, alpha * q.v);
    let (xc_d, yc_d, yc) = if q.pivot == 0 {
        (q.w_mps, 0.0, r * alpha.cos())
    } else {
        let s = f64::from(q.pivot);
        let phi = alpha - s * th;
        (
            q.w_mps + r * phi.cos() * th_d,
            s * r * phi.sin() * th_d,
            r * phi.cos(),
        )
    };
    0.5 * (xc_d * xc_d + yc_d * yc_d) + 0.5 * r * r / 3.0 * th_d * th_d + G * yc
}

#[test]
fn energy_never_rises_in_the_free_motion_through_every_mode_and_impact() {
    // Each record's first seconds, then 20 s of quiet: from the quiet's
    // start on, friction and impacts can only take energy away.
    let mut modes_seen = [0.0f64; 4];
    let mut impacts = 0;
    for stem in RECORDS {
        let full = far(stem);
        let cut = (8.0 / full.dt_s) as usize;
        let mut samples: Vec<f64> = full.psi[..cut.min(full.psi.len())].to_vec();
        let quiet_from = samples.len();
        samples.extend(std::iter::repeat_n(0.0, (20.0 / full.dt_s) as usize));
        let exc = Excitation::new(&samples, full.dt_s).unwrap();
        for (b_over_h, mu, eta) in [(0.25f64, 0.3, 0.12), (0.5, 0.3, 0.15), (0.3, 0.35, 0.08)] {
            let alpha = b_over_h.atan();
            let r = (1.0 + b_over_h * b_over_h).sqrt();
            let p = (0.75 * G / r).sqrt();
            let spec = RunSpec::new(p, 0.85, eta, slide_rock(alpha, mu));
            let (out, points) = history(&exc, &spec);
            if out.overturned() {
                continue;
            }
            for (m, t) in modes_seen.iter_mut().zip(out.mode_s) {
                *m += t;
            }
            let t_quiet = quiet_from as f64 * exc.dt_s;
            let free: Vec<&HistoryPoint> = points.iter().filter(|q| q.t_s > t_quiet).collect();
            impacts += free.iter().filter(|q| q.kind == EventKind::Impact).count();
            for pair in free.windows(2) {
                let (e0, e1) = (energy(pair[0], alpha, r), energy(pair[1], alpha, r));
                // The potential energy is about g·h = 10 J/kg; the
                // integrators' error is far below 1e-9 of it.
                assert!(
                    e1 <= e0 + 1e-8,
                    "{stem} b/h {b_over_h}: energy rises from {e0} to {e1} at {:?} t = {}",
                    pair[1].kind,
                    pair[1].t_s
                );
            }
        }
    }
    assert!(impacts > 0);
    assert!(modes_seen.iter().all(|&t| t > 0.0), "{modes_seen:?}");
}

/// Newmark's sliding block over a record, written here: the base's
/// velocity w relative to the ground under ẇ = a(t) − μg·sgn(w) while it
/// slips, held while |a| ≤ μg; a(t) linear between samples, so each piece
/// of an interval is a quadratic in w, integrated exactly (its stops by the
/// quadratic's root). Returns (max |u|, u at the end, the slide run out
/// after the record).
fn newmark(samples: &[f64], dt: f64, a_scale: f64, mu: f64) -> (f64, f64) {
    let f = mu * G;
    let (mut u, mut w, mut top) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..samples.len() - 1 {
        let (a0, a1) = (a_scale * samples[k], a_scale * samples[k + 1]);
        let slope = (a1 - a0) / dt;
        let mut t = 0.0;
        while t < dt {
            let a = a0 + slope * t;
            if w == 0.0 {
                // Held until |a| passes μg within the interval.
                let dir = if a.abs() > f {
                    a.signum()
                } else {
                    let next = [f, -f]
                        .iter()
                        .filter(|_| slope != 0.0)
                        .map(|&level| (level - a0) / slope)
                        .filter(|&s| s > t && s < dt)
                        .fold(f64::INFINITY, f64::min);
                    if !next.is_finite() {
                        break;
                    }
                    t = next;
                    (a0 + slope * t).signum()
                };
                // Slipping towards dir from w = 0: ẇ = a − dir·f.
                let (c0, c1) = (a0 + slope * t - dir * f, slope);
                let len = dt - t;
                // dir·w(s) = dir·(c0 s + c1 s²/2): its first root after 0.
                let root = if dir * c1 < 0.0 {
                    -2.0 * c0 / c1
                } else {
                    f64::INFINITY
                };
                let s = if root > 1e-15 { root.min(len) } else { len };
                u += c0 * s * s / 2.0 + c1 * s * s * s / 6.0;
                w = if s < len {
                    0.0
                } else {
                    c0 * s + c1 * s * s / 2.0
                };
                t += s;
            } else {
                let dir = w.signum();
                let (c0, c1) = (a0 + slope * t - dir * f, slope);
                let len = dt - t;
                // w + c0 s + c1 s²/2 = 0: the first root in (0, len].
                let disc = c0 * c0 - 2.0 * c1 * w;
                let mut s = len;
                if c1 == 0.0 {
                    if c0 * dir < 0.0 {
                        s = s.min(-w / c0);
                    }
                } else if disc >= 0.0 {
                    for r in [(-c0 + disc.sqrt()) / c1, (-c0 - disc.sqrt()) / c1] {
                        if r > 0.0 && r < s {
                            s = r;
                        }
                    }
                }
                u += w * s + c0 * s * s / 2.0 + c1 * s * s * s / 6.0;
                w = if s < len {
                    0.0
                } else {
                    w + c0 * s + c1 * s * s / 2.0
                };
                t += s;
            }
            top = top.max(u.abs());
        }
    }
    // After the record the slip runs out at μg.
    u += w * w.abs() / (2.0 * f);
    (top.max(u.abs()), u)
}

#[test]
fn a_block_that_slides_first_slides_as_newmarks_block_over_real_records() {
    // b/h = 0.6, μ = 0.3: it slides before it rocks and, a flat slide
    // never lifting it, only slides. So does a block at the tie μ = b/h
    // (MODEL.md §17): b/h = 0.2/0.9 given as μ, and an ulp above it.
    let tie = 0.2f64 / 0.9;
    // The levels: the record's peak 1.6 to 4 times μg.
    for (alpha, mu, etas) in [
        (0.6f64.atan(), 0.3, [0.5, 0.8, 1.2]),
        (tie.atan(), tie, [0.25, 0.4, 0.6]),
        (tie.atan(), tie.next_up(), [0.25, 0.4, 0.6]),
    ] {
        slides_as_newmark(alpha, mu, etas);
    }
}

fn slides_as_newmark(alpha: f64, mu: f64, etas: [f64; 3]) {
    for stem in [
        "RSN1111_KOBE_NIS000",
        "RSN848_LANDERS_CLW-LN",
        "RSN169_IMPVALL_H-DLT262",
    ] {
        let exc = far(stem);
        for eta in etas {
            let spec = RunSpec::new(2.0, 0.9, eta, slide_rock(alpha, mu));
            let out = simulate(&exc, &spec).unwrap();
            let (top, end) = newmark(&exc.psi, exc.dt_s, alpha * G / eta, mu);
            assert!(top > 0.001, "{stem} η {eta}: it slides ({top} m)");
            assert_eq!(out.max_abs_x, 0.0, "{stem} μ {mu}: it never rocks");
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * b.abs().max(1e-3);
            assert!(
                close(out.slide_max_m, top),
                "{stem} η {eta}: {} vs {top}",
                out.slide_max_m
            );
            assert!(
                close(out.slide_residual_m, end),
                "{stem} η {eta}: {} vs {end}",
                out.slide_residual_m
            );
        }
    }
}

/// `risk --inventory` with the museum's μ column and `--direct` runs the
/// blocks that can slide sliding and says so per block: the rack and the
/// transformer slide first, so never overturn (rate 0, and a warning that
/// says why); the statue rocks first and its friction never gives way on
/// these records, so its rate is the nonlinear model's to the bit; the
/// slender kouros runs sliding too (without μ, the linearised model).
/// Without μ every block rocks.
#[test]
fn the_museum_with_its_mu_runs_the_blocks_that_can_slide_sliding() {
    use crate::util::{rocking, root, stderr, stdout, tempdir};
    let dir = tempdir();
    let museum = root().join("records/hazard/museum-inventory.csv");
    let text = std::fs::read_to_string(&museum).unwrap();
    let held: String = text
        .lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
        .collect();
    let held_path = dir.path().join("held.csv");
    std::fs::write(&held_path, held).unwrap();
    let hazard = root().join("records/hazard/synthetic-openquake.csv");
    let run = |inventory: &std::path::Path, out: &str| {
        let out = rocking(
            dir.path(),
            &[
                "risk",
                "--hazard",
                hazard.to_str().unwrap(),
                "--inventory",
                inventory.to_str().unwrap(),
                "--direct",
                "--site",
                "1",
                "--json",
                "--out",
                out,
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        let v: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
        v.as_array().unwrap().clone()
    };
    let (with_mu, without) = (run(&museum, "mu.parquet"), run(&held_path, "held.parquet"));
    let rate = |b: &serde_json::Value| b["sites"][0]["annual_rate"].as_f64().unwrap();
    let model = |b: &serde_json::Value| b["fragility"]["equation"].as_str().unwrap().to_string();
    for (a, b) in with_mu.iter().zip(&without) {
        let name = a["block"]["name"].as_str().unwrap();
        let slides_first = a["block"]["slides_first"] == true;
        match name {
            "server rack" | "transformer" => {
                assert!(slides_first, "{name}");
                assert_eq!(model(a), "slide-rock");
                assert_eq!(rate(a), 0.0, "{name}");
                assert!(rate(b) > 0.0, "{name}: held against sliding it overturns");
                let w = a["warnings"].to_string();
                assert!(w.contains("slides before it rocks (μ ≤ b/h)"), "{w}");
                assert!(!w.contains("the rocking results assume"), "{w}");
            }
            "marble statue" => {
                assert_eq!(
                    (model(a), model(b)),
                    ("slide-rock".into(), "nonlinear".into())
                );
                assert_eq!(rate(a).to_bits(), rate(b).to_bits(), "{name}");
            }
            "bronze kouros" => {
                assert_eq!(
                    (model(a), model(b)),
                    ("slide-rock".into(), "linearized".into())
                );
            }
            _ => assert_eq!(model(a), "slide-rock", "{name}"),
        }
    }
    // The table says it per row.
    let rows: Vec<rocking::tables::risk::RiskRow> =
        rocking::tables::read(&dir.path().join("mu.parquet")).unwrap();
    let models: Vec<Option<&str>> = rows.iter().map(|r| r.model.as_deref()).collect();
    assert_eq!(
        models,
        [
            Some("slide-rock"),
            Some("slide-rock"),
            Some("slide-rock"),
            Some("slide-rock"),
            Some("slide-rock"),
            Some("slide-rock")
        ]
    );
}

/// `simulate --model slide-rock` reports the slide; the model's refusals
/// name what is missing.
#[test]
fn simulate_reports_the_slide_and_refusals_name_what_is_missing() {
    use crate::util::{bundled_records, rocking, root, stderr, stdout};
    let kobe = bundled_records().join("far-field/RSN1111_KOBE_NIS000.AT2");
    let kobe = kobe.to_str().unwrap();
    let base = [
        "simulate", "--record", kobe, "--b", "0.3", "--h", "0.5", "--eps", "0.8",
    ];
    let with = |more: &[&str]| {
        let mut args = base.to_vec();
        args.extend(more);
        rocking(&root(), &args)
    };
    let out = with(&[
        "--model",
        "slide-rock",
        "--mu",
        "0.3",
        "--pga",
        "0.6",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(v["model"], "slide-rock");
    // The library's run of the same block and record, by hand.
    let (alpha, eta) = (0.6f64.atan(), 0.6f64.atan() / 0.6);
    let p = (0.75 * G / (0.3f64.hypot(0.5))).sqrt();
    let spec = RunSpec::new(p, 0.8, eta, slide_rock(alpha, 0.3));
    let exc = far("RSN1111_KOBE_NIS000");
    let ours = simulate(&exc, &spec).unwrap();
    let s = &v["sliding"];
    assert!(ours.slide_max_m > 0.01);
    assert!((s["slide_max_m"].as_f64().unwrap() - ours.slide_max_m).abs() < 1e-12);
    assert!((s["slide_residual_m"].as_f64().unwrap() - ours.slide_residual_m).abs() < 1e-12);
    let modes: f64 = ["rest_s", "slide_s", "rock_s", "slide_rock_s"]
        .iter()
        .map(|k| s[k].as_f64().unwrap())
        .sum();
    // The modes' seconds add up to the record's duration.
    assert!((modes - exc.duration_s()).abs() < 1e-9, "{modes}");
    assert!(v["sliding"].is_object());
    for (more, says) in [
        (
            &["--model", "slide-rock", "--pga", "0.6"][..],
            "needs the base's friction coefficient μ",
        ),
        (
            &[
                "--model",
                "slide-rock",
                "--mu",
                "0.3",
                "--mu-k",
                "0.4",
                "--pga",
                "0.6",
            ][..],
            "must be in (0, μₛ = 0.3]",
        ),
        (
            &["--model", "slide-rock", "--mu", "2", "--pga", "0.6"][..],
            "must be in (0, 1.3]",
        ),
        (&["--mu-k", "0.2", "--pga", "0.6"][..], "give both"),
    ] {
        let out = with(more);
        assert!(!out.status.success(), "{more:?}");
        assert!(stderr(&out).contains(says), "{more:?}: {}", stderr(&out));
    }
    // A rocking model with μ still says it would slide, and has no `sliding`.
    let out = with(&[
        "--model",
        "nonlinear",
        "--mu",
        "0.3",
        "--pga",
        "0.6",
        "--json",
    ]);
    assert!(stderr(&out).contains("the rocking results assume it does not slide"));
    let v: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert!(v.get("sliding").is_none());
}

/// Moreau–Jean's time-stepping of a rigid block with two corner contacts,
/// Newton's impact law (e = 0) and Coulomb friction (Jean 1999, "The
/// non-smooth contact dynamics method", Comput. Methods Appl. Mech. Eng.
/// 177), written here from the rigid body's kinematics: no code of the
/// tool's. The block's centre (X, Y) and its rotation θ (towards +X),
/// unit mass, I = R²/3; at each step the contacts whose gap closes within
/// the step solve a linear complementarity problem of impulses, found by
/// enumerating each contact's status (open, stuck, slipping either way).
struct MoreauJean {
    b: f64,
    h: f64,
    mu: f64,
    i_c: f64,
}

/// The block's configuration and velocity.
#[derive(Clone, Copy)]
struct Body {
    q: [f64; 3],
    v: [f64; 3],
}

impl MoreauJean {
    /// The rows of the normal and tangential velocities of corner `cx`
    /// (±b) at rotation θ: u = H·v.
    fn rows(&self, cx: f64, th: f64) -> ([f64; 3], [f64; 3]) {
        let (s, c) = th.sin_cos();
        (
            [0.0, 1.0, -cx * c + self.h * s],
            [1.0, 0.0, -cx * s - self.h * c],
        )
    }

    fn gap(&self, cx: f64, q: &[f64; 3]) -> f64 {
        let (s, c) = q[2].sin_cos();
        q[1] - cx * s - self.h * c
    }

    /// One step of length `dt` under the inertial acceleration `a` (at the
    /// step's middle).
    fn step(&self, body: &mut Body, a: f64, dt: f64) {
        let inv_m = [1.0, 1.0, 1.0 / self.i_c];
        let mid = [
            body.q[0] + 0.5 * dt * body.v[0],
            body.q[1] + 0.5 * dt * body.v[1],
            body.q[2] + 0.5 * dt * body.v[2],
        ];
        // The free velocity: gravity and the ground's inertial force.
        let free = [body.v[0] + dt * a, body.v[1] - dt * G, body.v[2]];
        let active: Vec<f64> = [self.b, -self.b]
            .into_iter()
            .filter(|&cx| self.gap(cx, &mid) <= 0.0)
            .collect();
        let rows: Vec<([f64; 3], [f64; 3])> =
            active.iter().map(|&cx| self.rows(cx, mid[2])).collect();
        let v = self.impulses(&free, &rows, &inv_m);
        for ((q, before), after) in body.q.iter_mut().zip(body.v).zip(v) {
            *q += 0.5 * dt * (before + after);
        }
        body.v = v;
    }

    /// The velocity after the contacts' impulses: each active contact
    /// open (no impulse, u_N ≥ 0), stuck (u_N = 0, u_T = 0, |P_T| ≤ μP_N)
    /// or slipping (u_N = 0, P_T = ∓μP_N against u_T); the first
    /// combination that satisfies every inequality.
    fn impulses(
        &self,
        free: &[f64; 3],
        rows: &[([f64; 3], [f64; 3])],
        inv_m: &[f64; 3],
    ) -> [f64; 3] {
        let n = rows.len();
        let dot = |r: &[f64; 3], v: &[f64; 3]| r[0] * v[0] + r[1] * v[1] + r[2] * v[2];
        let statuses = 4usize.pow(n as u32);
        for code in 0..statuses {
            let status: Vec<usize> = (0..n).map(|i| (code / 4usize.pow(i as u32)) % 4).collect();
            // Unknowns: P_N of each closed contact, and P_T of each stuck one.
            let mut dirs: Vec<[f64; 3]> = Vec::new();
            let mut eqs: Vec<[f64; 3]> = Vec::new();
            for (i, &st) in status.iter().enumerate() {
                let (hn, ht) = rows[i];
                match st {
                    0 => {}
                    1 => {
                        dirs.push(hn);
                        eqs.push(hn);
                        dirs.push(ht);
                        eqs.push(ht);
                    }
                    _ => {
                        let sign = if st == 2 { -1.0 } else { 1.0 };
                        let d = [
                            hn[0] + sign * self.mu * ht[0],
                            hn[1] + sign * self.mu * ht[1],
                            hn[2] + sign * self.mu * ht[2],
                        ];
                        dirs.push(d);
                        eqs.push(hn);
                    }
                }
            }
            let m = dirs.len();
            // eqs[j] · (free + M⁻¹ Σ dirs[k] P_k) = 0.
            let mut a = vec![vec![0.0; m]; m];
            let mut rhs = vec![0.0; m];
            for j in 0..m {
                rhs[j] = -dot(&eqs[j], free);
                for k in 0..m {
                    let w = [
                        inv_m[0] * dirs[k][0],
                        inv_m[1] * dirs[k][1],
                        inv_m[2] * dirs[k][2],
                    ];
                    a[j][k] = dot(&eqs[j], &w);
                }
            }
            let Some(p) = solve(a, rhs) else { continue };
            let mut v = *free;
            for (k, d) in dirs.iter().enumerate() {
                for c in 0..3 {
                    v[c] += inv_m[c] * d[c] * p[k];
                }
            }
            let tol = 1e-12;
            let mut ok = true;
            let mut k = 0;
            for (i, &st) in status.iter().enumerate() {
                let (hn, ht) = rows[i];
                match st {
                    0 => ok &= dot(&hn, &v) >= -tol,
                    1 => {
                        let (pn, pt) = (p[k], p[k + 1]);
                        ok &= pn >= -tol && pt.abs() <= self.mu * pn + tol;
                        k += 2;
                    }
                    _ => {
                        let pn = p[k];
                        let ut = dot(&ht, &v);
                        // Slipping towards +X (st 2) takes friction −μP_N.
                        let sign = if st == 2 { 1.0 } else { -1.0 };
                        ok &= pn >= -tol && sign * ut >= -tol;
                        k += 1;
                    }
                }
            }
            if ok {
                return v;
            }
        }
        panic!("no consistent contact status");
    }
}

/// Gaussian elimination with partial pivoting; `None` if singular.
fn solve(mut a: Vec<Vec<f64>>, mut r: Vec<f64>) -> Option<Vec<f64>> {
    let n = r.len();
    for col in 0..n {
        let piv = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() < 1e-14 {
            return None;
        }
        a.swap(col, piv);
        r.swap(col, piv);
        let top = a[col].clone();
        for row in col + 1..n {
            let f = a[row][col] / top[col];
            for (x, t) in a[row].iter_mut().zip(&top).skip(col) {
                *x -= f * t;
            }
            r[row] -= f * r[col];
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let mut acc = r[row];
        for k in row + 1..n {
            acc -= a[row][k] * x[k];
        }
        x[row] = acc / a[row][row];
    }
    Some(x)
}

/// A half-sine pulse A sin(πt/t_d) of `t_d` seconds, then quiet to
/// `total`, at step `dt`: ψ̈ with unit peak.
fn half_sine(t_d: f64, total: f64, dt: f64) -> Excitation {
    let n = (total / dt).round() as usize + 1;
    let samples: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 * dt;
            if t <= t_d {
                (std::f64::consts::PI * t / t_d).sin()
            } else {
                0.0
            }
        })
        .collect();
    Excitation::new(&samples, dt).unwrap()
}

/// Moreau–Jean's rotation θ/α and base position u (the pivot's position
/// less s·b on a pivot, the centre's when flat) at every sample of `exc`,
/// with `sub` steps per sample interval.
fn moreau_jean(
    b: f64,
    h: f64,
    mu: f64,
    a_scale: f64,
    exc: &Excitation,
    sub: usize,
    until_s: f64,
) -> Vec<(f64, f64)> {
    let mj = MoreauJean {
        b,
        h,
        mu,
        i_c: (b * b + h * h) / 3.0,
    };
    let alpha = (b / h).atan();
    let mut body = Body {
        q: [0.0, h, 0.0],
        v: [0.0; 3],
    };
    let dt = exc.dt_s / sub as f64;
    let mut out = vec![(0.0, 0.0)];
    for k in 0..exc.psi.len() - 1 {
        if k as f64 * exc.dt_s >= until_s {
            break;
        }
        for j in 0..sub {
            let frac = (j as f64 + 0.5) / sub as f64;
            let a = a_scale * (exc.psi[k] + frac * (exc.psi[k + 1] - exc.psi[k]));
            mj.step(&mut body, a, dt);
        }
        let th = body.q[2];
        let u = if th.abs() < 1e-12 {
            body.q[0]
        } else {
            let s = th.signum();
            body.q[0] + s * b * th.cos() - h * th.sin() - s * b
        };
        out.push((th / alpha, u));
    }
    out
}

/// An independent integrator of non-smooth contact dynamics converges to
/// the tool's rotation and slide histories as its step shrinks, on a block
/// that slides, one that rocks (Newton's e = 0 at the corners, which gives
/// Housner's ε = 1 − 1.5 sin²α when the corner sticks; the tool runs that
/// ε) and one that rocks, then slide-rocks (compared up to its first impact
/// on a slipping pivot, where the tool's impact law, which scales the whole
/// velocity by ε, and Newton's at two corners part).
#[test]
fn moreau_jean_converges_to_the_tools_histories_as_its_step_shrinks() {
    let dt = 0.002;
    for (case, b, h, mu, a_g, t_d, total) in [
        ("slide", 0.3f64, 0.5f64, 0.3, 0.8, 0.5, 2.0),
        ("rock", 0.25, 1.0, 0.8, 0.4, 0.4, 3.0),
        ("slide-rock", 0.25, 1.0, 0.3, 0.8, 0.2, 3.0),
    ] {
        let exc = half_sine(t_d, total, dt);
        let alpha = (b / h).atan();
        let p = (0.75 * G / (b * b + h * h).sqrt()).sqrt();
        let eta = alpha / a_g;
        let eps = 1.0 - 1.5 * alpha.sin().powi(2);
        let spec = RunSpec::new(p, eps, eta, slide_rock(alpha, mu));
        let (out, points) = history(&exc, &spec);
        assert!(!out.overturned(), "{case}");
        let mode_s = out.mode_s;
        match case {
            "slide" => assert!(mode_s[Mode::Slide as usize] > 0.1 && out.max_abs_x == 0.0),
            "rock" => {
                assert!(mode_s[Mode::Rock as usize] > 0.5 && out.slips == 0 && out.impacts > 3)
            }
            _ => assert!(mode_s[Mode::SlideRock as usize] > 0.01, "{mode_s:?}"),
        }
        // Up to the first impact on a slipping pivot.
        let until = points
            .iter()
            .find(|q| q.kind == EventKind::Impact && q.w_mps != 0.0)
            .map_or(total, |q| q.t_s);
        let tool: Vec<(f64, f64, f64)> = points
            .iter()
            .filter(|q| q.kind == EventKind::Sample && q.t_s < until)
            .map(|q| (q.t_s, q.x, q.u_m))
            .collect();
        let (x_top, u_top) = tool.iter().fold((0.0f64, 0.0f64), |(a, b), t| {
            (a.max(t.1.abs()), b.max(t.2.abs()))
        });
        let errors: Vec<f64> = [4, 16, 64]
            .iter()
            .map(|&sub| {
                let mj = moreau_jean(b, h, mu, alpha * G / eta, &exc, sub, until);
                tool.iter()
                    .map(|&(t, x, u)| {
                        let k = (t / dt).round() as usize;
                        let (xm, um) = mj[k];
                        let ex = if x_top > 0.0 {
                            (xm - x).abs() / x_top
                        } else {
                            0.0
                        };
                        let eu = if u_top > 0.0 {
                            (um - u).abs() / u_top
                        } else {
                            0.0
                        };
                        ex.max(eu)
                    })
                    .fold(0.0, f64::max)
            })
            .collect();
        eprintln!(
            "{case}: up to {until:.3} s, errors {errors:?} (x top {x_top:.3}, u top {u_top:.4} m)"
        );
        assert!(errors[2] < 0.02, "{case}: {errors:?}");
        assert!(errors[2] < errors[0] / 4.0, "{case}: {errors:?}");
    }
}

/// A study whose blocks run sliding (`kind = "slide-rock"`): every run's
/// slide in `ida_points` is the library's run at that η; each record's
/// capacity for a slide state is the first run by rising intensity whose
/// slide reaches it (or that overturns), interpolated in 1/η from the run
/// before, as written here; the report has its "Blocks that slide"; and a
/// slide state with a block run rocking is refused naming the block.
#[test]
fn a_study_of_blocks_that_slide_states_their_slides() {
    use crate::util::{rocking, stderr, tempdir, write_pipeline};
    use rocking::tables::damage::StateCapacityRow;
    use rocking::tables::sweep::IdaRow;
    let dir = tempdir();
    let blocks =
        "[[block]]\nname = \"rack\"\nb = 0.3\nh = 1.0\neps = 0.75\nmu = 0.2\nmu_k = 0.15\n\
                  [[block]]\nname = \"statue\"\nb = 0.2\nh = 0.9\neps = 0.9\nmu = 0.5\n";
    let body = format!(
        "ids = [\"RSN1111_KOBE_NIS000\", \"RSN848_LANDERS_CLW-LN\", \"RSN169_IMPVALL_H-DLT262\"]\n\
         [model]\nkind = \"slide-rock\"\n{blocks}[im]\ncount = 60\n\
         [damage]\nstates = \"walks=0.05m,off=0.3m\"\n"
    );
    let pipeline = write_pipeline(dir.path(), "sl", &body);
    let outputs = dir.path().join("out");
    let out = rocking(
        dir.path(),
        &[
            "run",
            pipeline.to_str().unwrap(),
            "--outputs",
            outputs.to_str().unwrap(),
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let study = outputs.join("sl");
    let ida: Vec<IdaRow> = rocking::tables::read(&study.join("ida_points.parquet")).unwrap();
    let states: Vec<StateCapacityRow> =
        rocking::tables::read(&study.join("state_capacities.parquet")).unwrap();
    let mut checked = 0;
    // The rack's kinetic friction below its static one.
    let rack = Friction {
        mu_s: 0.2,
        mu_k: 0.15,
    };
    for (name, b, h, eps, friction) in [
        ("rack", 0.3f64, 1.0f64, 0.75, rack),
        ("statue", 0.2, 0.9, 0.9, Friction::new(0.5)),
    ] {
        let alpha = (b / h).atan();
        let p = (0.75 * G / b.hypot(h)).sqrt();
        for stem in [
            "RSN1111_KOBE_NIS000",
            "RSN848_LANDERS_CLW-LN",
            "RSN169_IMPVALL_H-DLT262",
        ] {
            let exc = far(stem);
            let mut runs: Vec<&IdaRow> = ida
                .iter()
                .filter(|r| r.block == name && r.record_id == stem)
                .collect();
            for r in &runs {
                let model = Model::slide_rock(alpha, friction, Solver::default());
                let o = simulate(&exc, &RunSpec::new(p, eps, r.eta, model)).unwrap();
                assert_eq!(
                    r.slide_max_m,
                    Some(o.slide_max_m),
                    "{name} {stem} η {}",
                    r.eta
                );
                assert_eq!(r.model.label(), "slide-rock");
            }
            runs.sort_by(|a, b| b.eta.total_cmp(&a.eta));
            for (state, d) in [("walks", 0.05), ("off", 0.3)] {
                let row = states
                    .iter()
                    .find(|s| s.block == name && s.record_id == stem && s.state == state)
                    .unwrap();
                let i = runs
                    .iter()
                    .position(|r| r.overturned || r.slide_max_m.unwrap() >= d);
                match i {
                    None => assert!(!row.reached, "{name} {stem} {state}"),
                    Some(i) => {
                        assert!(row.reached);
                        let r1 = runs[i];
                        let want = match (i, r1.overturned) {
                            (0, _) | (_, true) => r1.eta,
                            _ => {
                                let r0 = runs[i - 1];
                                let (s0, s1) = (r0.slide_max_m.unwrap(), r1.slide_max_m.unwrap());
                                if s1 > s0 {
                                    let inv = 1.0 / r0.eta
                                        + (d - s0) / (s1 - s0) * (1.0 / r1.eta - 1.0 / r0.eta);
                                    1.0 / inv
                                } else {
                                    r1.eta
                                }
                            }
                        };
                        assert!(
                            (row.eta - want).abs() <= 1e-12 * want,
                            "{name} {stem} {state}"
                        );
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked >= 6, "{checked}");
    let report = std::fs::read_to_string(study.join("report.md")).unwrap();
    assert!(report.contains("## Blocks that slide"), "{report}");
    assert!(
        report.contains("| rack | 0.2 | 0.300 | 0 of 3 |"),
        "{report}"
    );
    // A slide state with a block run rocking.
    let refused = |body: &str| {
        let bad = write_pipeline(dir.path(), "bad", body);
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
        stderr(&out)
    };
    let rocking_blocks = body.replace("kind = \"slide-rock\"", "kind = \"nonlinear\"");
    let e = refused(&rocking_blocks);
    assert!(
        e.contains("`walks` is on the slide, but block `rack` runs the nonlinear"),
        "{e}"
    );
    let e = refused(&body.replace("mu = 0.2\n", ""));
    assert!(
        e.contains(".mu_k` is the kinetic friction beside `mu`"),
        "{e}"
    );
}

/// The tolerance study's 528 cases (44 far-field records × p ∈ {1, 2, 4} ×
/// ε ∈ {0.7, 0.9} × α ∈ {0.15, 0.3}) on a base of μ = 1.3, their certified
/// capacities: wherever no run of a case slips, its capacity and every run
/// of its search (θmax/α, the outcome, the impacts) are the nonlinear
/// model's to the bit. ROCKING_SLOW=1 (CI sets it).
#[test]
fn where_friction_never_binds_the_tolerance_studys_capacities_are_the_rocking_models() {
    if std::env::var_os("ROCKING_SLOW").is_none() {
        return;
    }
    use rocking::ida::{capacity_certified, ImGrid, Trace};
    let dir = crate::util::bundled_records().join("far-field");
    let mut stems: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "AT2"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    stems.sort();
    assert_eq!(stems.len(), 44);
    let grid = ImGrid::default();
    let (mut compared, mut slipped) = (0, 0);
    for stem in &stems {
        let exc = far(stem);
        for p in [1.0, 2.0, 4.0] {
            for eps in [0.7, 0.9] {
                for alpha in [0.15, 0.3] {
                    let rocking =
                        RunSpec::new(p, eps, 1.0, Model::nonlinear(alpha, Solver::default()));
                    let sliding = RunSpec {
                        model: slide_rock(alpha, 1.3),
                        ..rocking
                    };
                    let a = capacity_certified(&exc, &rocking, &grid, 1e-4, Trace::StopAtFirst)
                        .unwrap();
                    let b = capacity_certified(&exc, &sliding, &grid, 1e-4, Trace::StopAtFirst)
                        .unwrap();
                    if b.capacity.points.iter().any(|q| q.outcome.slips > 0) {
                        slipped += 1;
                        continue;
                    }
                    let case = format!("{stem} p {p} ε {eps} α {alpha}");
                    assert_eq!(a.capacity.eta_c, b.capacity.eta_c, "{case}");
                    assert_eq!(a.capacity.points.len(), b.capacity.points.len(), "{case}");
                    for (x, y) in a.capacity.points.iter().zip(&b.capacity.points) {
                        assert_eq!(x.eta, y.eta, "{case}");
                        assert_eq!(
                            x.outcome.max_abs_x.to_bits(),
                            y.outcome.max_abs_x.to_bits(),
                            "{case}"
                        );
                        assert_eq!(
                            (x.outcome.stop, x.outcome.impacts),
                            (y.outcome.stop, y.outcome.impacts),
                            "{case}"
                        );
                    }
                    compared += 1;
                }
            }
        }
    }
    eprintln!("{compared} cases compared, {slipped} slipped");
    assert_eq!(compared + slipped, 528);
    assert!(compared > 400, "{compared}");
}

/// `[example]` took no `mu`: a study of blocks that slide could not draw
/// its example as one of them, and under `kind = "slide-rock"` a block
/// without `mu` was refused naming the command line's `--mu`. The example
/// now takes a `[[block]]`'s friction, and the example stage's capacities
/// of a block equal the sweep's of the same block (one search, run twice);
/// the refusal names the file's key. `--from` such a study does not hand
/// its sliding block's fits to a block asked without that friction.
#[test]
fn the_example_block_may_slide() {
    use crate::util::{rocking, stderr, tempdir, write_pipeline};
    use rocking::tables::sweep::CapacityRow;
    let dir = tempdir();
    let rack = "name = \"rack\"\nb = 0.3\nh = 1.0\neps = 0.75\nmu = 0.2\nmu_k = 0.15\n";
    let body = format!(
        "ids = [\"RSN1111_KOBE_NIS000\", \"RSN848_LANDERS_CLW-LN\"]\n\
         [model]\nkind = \"slide-rock\"\n[[block]]\n{rack}[example]\n{rack}[im]\ncount = 40\n"
    );
    let pipeline = write_pipeline(dir.path(), "ex", &body);
    let outputs = dir.path().join("out");
    let run = |pipeline: &std::path::Path| {
        rocking(
            dir.path(),
            &[
                "run",
                pipeline.to_str().unwrap(),
                "--outputs",
                outputs.to_str().unwrap(),
            ],
        )
    };
    let out = run(&pipeline);
    assert!(out.status.success(), "{}", stderr(&out));
    let study = outputs.join("ex");
    let read =
        |name: &str| -> Vec<CapacityRow> { rocking::tables::read(&study.join(name)).unwrap() };
    let (sweep, example) = (
        read("capacities.parquet"),
        read("example_capacities.parquet"),
    );
    assert_eq!(sweep.len(), 2);
    assert_eq!(example.len(), 2);
    for (s, e) in sweep.iter().zip(&example) {
        assert_eq!(s.record_id, e.record_id);
        assert_eq!(
            (s.eta_c, s.eta_survived),
            (e.eta_c, e.eta_survived),
            "{}",
            s.record_id
        );
    }
    // `--from` the study: its rack's fits are of its friction, not of a
    // block asked without it (nor of another μ).
    for mu in [&[][..], &["--mu", "0.6"][..]] {
        let mut args = vec![
            "fragility",
            "--from",
            pipeline.to_str().unwrap(),
            "--outputs",
            outputs.to_str().unwrap(),
            "--b",
            "0.3",
            "--h",
            "1.0",
            "--eps",
            "0.75",
            "--pga",
            "0.3",
        ];
        args.extend(mu);
        let out = rocking(dir.path(), &args);
        assert!(!out.status.success());
        let e = stderr(&out);
        assert!(
            e.contains("the study's block `rack` ran sliding on its base (mu = 0.2)"),
            "{e}"
        );
    }
    // Without the block's `mu`, the file's key is named.
    let bare = write_pipeline(
        dir.path(),
        "bare",
        "ids = [\"RSN1111_KOBE_NIS000\"]\n[model]\nkind = \"slide-rock\"\n[[block]]\n\
         name = \"rack\"\nb = 0.3\nh = 1.0\neps = 0.75\n",
    );
    let out = run(&bare);
    assert!(!out.status.success());
    let e = stderr(&out);
    assert!(e.contains("block `rack`: `model.kind` = \"slide-rock\" needs the base's friction coefficient: give the block's `mu`"), "{e}");
    assert!(!e.contains("--mu"), "{e}");
}

/// A record that ends at rest, alone and padded with zeros: the padding
/// changes nothing physical, so a block that overturns after the record
/// overturns at the same instant either way. On a base with friction the
/// block may still be slipping when the record ends: its free motion
/// starts where that slip runs out, not at the record's end (the slip's
/// time was lost: overturning at 9.2763 s against 9.3824 s, by an RK4 of
/// the free rocking from the stick written by a reviewer, on Kobe cut to
/// 900 samples, b/h = 0.25, μ = 0.3, η = 0.2). The padded run steps the
/// zeros as a record; the other follows the free motion in one stretch:
/// the same equation by two paths, within the Taylor stepper's tolerance.
#[test]
fn a_block_overturning_after_the_record_overturns_when_the_padded_record_says() {
    let (b, h) = (0.25f64, 1.0f64);
    let alpha = (b / h).atan();
    let p = (3.0 * G / (4.0 * b.hypot(h))).sqrt();
    let eps = 1.0 - 1.5 * alpha.sin().powi(2);
    let (mut after, mut slipping_after) = (0, 0);
    for (stem, cut) in [
        ("RSN1111_KOBE_NIS000", 800),
        ("RSN1111_KOBE_NIS000", 900),
        ("RSN1111_KOBE_NIS000", 1000),
        ("RSN752_LOMAP_CAP090", 1300),
    ] {
        let whole = far(stem);
        let mut samples = whole.psi[..cut].to_vec();
        samples.push(0.0);
        let alone = Excitation::new(&samples, whole.dt_s).unwrap();
        samples.extend(std::iter::repeat_n(0.0, 3000));
        let padded = Excitation::new(&samples, whole.dt_s).unwrap();
        for mu in [0.3, 0.4] {
            for eta in (0..16).map(|i| 0.05 + 0.025 * i as f64) {
                let spec = RunSpec::new(p, eps, eta, slide_rock(alpha, mu));
                let (a, points) = history(&alone, &spec);
                if !a.overturn_after_record {
                    continue;
                }
                after += 1;
                let end = alone.duration_s();
                slipping_after += usize::from(
                    points
                        .iter()
                        .any(|q| q.t_s > end && q.kind == EventKind::Stick),
                );
                let z = simulate(&padded, &spec).unwrap();
                assert_eq!(z.stop, Stop::Overturned, "{stem} {cut} μ {mu} η {eta}");
                let (ta, tz) = (a.overturn_time_s.unwrap(), z.overturn_time_s.unwrap());
                assert!(
                    (ta - tz).abs() < 1e-6,
                    "{stem} cut at {cut}, μ {mu}, η {eta}: {ta} s alone, {tz} s padded"
                );
            }
        }
    }
    eprintln!("{after} overturned after the record, {slipping_after} slipping at its end");
    assert!(
        after >= 8 && slipping_after >= 4,
        "{after} {slipping_after}"
    );
}

/// A history has an `impact` row for each impact its run counts: the
/// impact that settles the block was written as a `rest` row alone (336
/// impacts counted, 332 `impact` rows and 4 `rest` ones, on Kobe at p = 2,
/// ε = 0.8, η = 0.3), so the history's impacts fell short of the summary's.
#[test]
fn a_history_has_a_row_for_every_impact_counted() {
    let exc = far("RSN1111_KOBE_NIS000");
    let mut settled = 0;
    for (model, eps, eta) in [
        (Model::LINEARIZED, 0.8, 0.3),
        (Model::LINEARIZED, 0.5, 0.2),
        (Model::nonlinear(0.2, Solver::default()), 0.9, 0.25),
        (slide_rock(0.25, 0.3), 0.9, 0.2),
        (slide_rock(0.2, 0.15), 0.8, 0.3),
    ] {
        let spec = RunSpec::new(2.0, eps, eta, model);
        let (out, points) = history(&exc, &spec);
        let rows = |kind| points.iter().filter(|q| q.kind == kind).count();
        assert_eq!(
            rows(EventKind::Impact) as u64,
            out.impacts,
            "{model:?} ε {eps} η {eta}"
        );
        settled += points
            .windows(2)
            .filter(|w| w[0].kind == EventKind::Impact && w[1].kind == EventKind::Rest)
            .count();
    }
    assert!(settled > 4, "{settled}");
}

/// A slender block's friction demand while it rocks is not bounded by
/// tan α: Kobe at PGA 0.2 g rocks a 0.2 m × 2 m block (b/h = 0.1) hard
/// enough that |F|/N, worked here from its nonlinear history by
/// Newton–Euler (the centre of mass about the pivot, the ground's
/// acceleration, θ̈ from the equation of motion), first passes μ = 0.12
/// between two samples. `auto` with that μ runs the slide-rock model, whose
/// first slip falls in that interval. (It kept the linearised model for
/// such a block, which never slips: 16 % on its capacity at μ = 0.105.)
#[test]
fn auto_with_mu_lets_a_slender_rocking_block_slip_where_its_demand_passes_mu() {
    use crate::util::{bundled_records, rocking, stderr, stdout, tempdir};
    let dir = tempdir();
    let kobe = bundled_records().join("far-field/RSN1111_KOBE_NIS000.AT2");
    let (mu, pga) = (0.12, 0.2);
    let run = |model: &[&str], history: &str| {
        let mut args = vec![
            "simulate",
            "--record",
            kobe.to_str().unwrap(),
            "--b",
            "0.1",
            "--h",
            "1",
            "--eps",
            "0.9",
            "--pga",
            "0.2",
            "--json",
            "--history",
            history,
        ];
        args.extend(model);
        let out = rocking(dir.path(), &args);
        assert!(out.status.success(), "{}", stderr(&out));
        let v: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
        let text = std::fs::read_to_string(dir.path().join(history)).unwrap();
        // t, x = θ/α, θ̇/α, the pivot, ψ (the record over its peak), the event.
        let rows: Vec<(f64, f64, f64, f64, f64, String)> = text
            .lines()
            .skip(1)
            .map(|l| {
                let c: Vec<&str> = l.split(',').collect();
                let n = |i: usize| c[i].parse::<f64>().unwrap();
                (n(0), n(1), n(2), n(3), n(4), c[7].to_string())
            })
            .collect();
        (v, rows)
    };
    let (_, rocking_rows) = run(&["--model", "nonlinear"], "nonlinear.csv");
    let (half_b, half_h) = (0.1_f64, 1.0_f64);
    let (alpha, r) = (half_b.atan2(half_h), half_b.hypot(half_h));
    let p2 = 3.0 * G / (4.0 * r);
    // The block mirrored onto pivot +1: θ ≥ 0, the forcing f (in g) that
    // lifts it positive; the pivot at the origin, the centre of mass at
    // (−R sin φ, R cos φ) with φ = α − θ, the ground accelerating at −f·g.
    let demand = |s: f64, x: f64, v: f64, psi: f64| {
        let (th, thd, f) = (alpha * x * s, alpha * v * s, s * psi * pga);
        let phi = alpha - th;
        let thdd = -p2 * (phi.sin() - f * phi.cos());
        let horizontal = -f * G + r * (phi.sin() * thd * thd + phi.cos() * thdd);
        let vertical = G + r * (-phi.cos() * thd * thd + phi.sin() * thdd);
        horizontal.abs() / vertical
    };
    let mut before = f64::NAN;
    let mut window = None;
    for &(t, x, v, s, psi, _) in &rocking_rows {
        if s != 0.0 && demand(s, x, v, psi) > mu {
            window = Some((before, t));
            break;
        }
        before = t;
    }
    let (from, to) = window.expect("the rocking block's demand passes μ");
    assert!(to - from <= 0.01 + 1e-12, "{from}..{to}");

    let mu_text = mu.to_string();
    let (auto, rows) = run(&["--model", "auto", "--mu", &mu_text], "auto.csv");
    assert_eq!(auto["model"], "slide-rock", "{auto}");
    assert!(auto["sliding"]["slips"].as_u64().unwrap() >= 1, "{auto}");
    let slip = rows
        .iter()
        .find(|row| row.5 == "slip")
        .map(|row| row.0)
        .expect("a slip in the history");
    assert!(
        slip > from && slip <= to,
        "first slip at {slip} s, the demand passes μ in ({from}, {to}] s"
    );
}

/// A slip that stopped with the block at its impact (x within rounding of
/// 0, on the wrong side, moving into it) started again there, and its stop
/// was located before the impact: stop and slip alternated at one instant
/// without end (the first 116 samples of Superstition Hills' POE270 at η =
/// 0.3661; the whole record's capacity search never ended). The impact now
/// comes first, and the run reaches its verdict: it survives, as the
/// record's 0.045 g cannot overturn this block, with a handful of slips.
/// The bug guard (events at one instant) would stop it as `EventLimit`.
#[test]
fn a_slip_that_stops_on_the_impact_does_not_stall() {
    let path = crate::util::bundled_records().join("far-field/RSN725_SUPERST_B-POE270.AT2");
    let samples = crate::util::plain_at2_values(&path);
    let spec = RunSpec::new(1.0, 0.85, 0.3661, slide_rock(0.2, 0.25));
    let head = Excitation::new(&samples[..116], 0.01).unwrap();
    let out = simulate(&head, &spec).unwrap();
    assert_eq!(out.stop, Stop::Survived, "{out:?}");
    assert!(out.slips < 20 && out.impacts > 0, "{out:?}");
    // The whole record at the level where a capacity search stalled.
    let whole = Excitation::new(&samples, 0.01).unwrap();
    let spec = RunSpec {
        eta: 0.036866027018437636,
        ..spec
    };
    let out = simulate(&whole, &spec).unwrap();
    assert_ne!(out.stop, Stop::EventLimit, "{out:?}");
}

/// A friction given to an answer that does not model it is said: below b/h
/// the block slides before it rocks (statics: it slips at |a| = μg before
/// it lifts at g·tan α), above it the friction is simply unused by the
/// regression and the study's tables; the records' runs (`--direct`) run
/// the slide-rock model and say neither.
#[test]
fn a_friction_the_answer_does_not_model_is_said() {
    let dir = crate::util::tempdir();
    let said = |extra: &[&str]| {
        let args = [
            &["fragility", "--b", "0.2", "--h", "0.9", "--pga", "0.3"][..],
            extra,
        ]
        .concat();
        let out = crate::util::rocking(dir.path(), &args);
        assert!(out.status.success(), "{}", crate::util::stderr(&out));
        let e = crate::util::stderr(&out);
        (
            e.contains("is not used"),
            e.contains("slides before it rocks"),
        )
    };
    // b/h = 0.222.
    assert_eq!(said(&["--mu", "0.4"]), (true, false));
    assert_eq!(said(&["--mu", "0.1"]), (false, true));
    assert_eq!(said(&[]), (false, false));
    assert_eq!(said(&["--mu", "0.4", "--direct"]), (false, false));
}

/// The slide's sign: along the inertial force of a positive record value,
/// against the record's axis (docs/MODEL.md §21). Under a rectangular
/// pulse of A = 0.3 g for 0.5 s a squat block on μ = 0.1 slides, never
/// rocking (tan α = 1 > μ), and is left behind by Coulomb's law: relative
/// deceleration (A − μg) during the pulse, μg after it until it stops,
/// d = (A − μg)t²/2 + ((A − μg)t)²/(2μg) = 0.734 m, which the tool reports
/// as +d (the ground moved towards the record's +, the block lagged).
#[test]
fn a_pulse_leaves_a_sliding_block_behind_by_coulombs_law() {
    let dir = crate::util::tempdir();
    let record = dir.path().join("pulse.AT2");
    let dt = 0.001;
    let mut accel = vec![0.3; 500];
    accel.extend(vec![0.0; 3000]);
    crate::util::write_at2(&record, &accel, dt);
    let out = crate::util::rocking(
        dir.path(),
        &[
            "simulate",
            "--record",
            record.to_str().unwrap(),
            "--b",
            "0.5",
            "--h",
            "0.5",
            "--eps",
            "0.8",
            "--model",
            "slide-rock",
            "--mu",
            "0.1",
            "--pga",
            "0.3",
            "--json",
        ],
    );
    assert!(out.status.success(), "{}", crate::util::stderr(&out));
    let v: serde_json::Value = serde_json::from_str(&crate::util::stdout(&out)).unwrap();
    let residual = v["sliding"]["slide_residual_m"].as_f64().unwrap();
    // The pulse ends on the ramp from its last sample (t = 0.499 s) to 0 at
    // 0.5 s: its impulse is that of 0.4995 s at A.
    let (g, t) = (rocking::block::G, 0.4995);
    let a = 0.2 * g;
    let d = a * t * t / 2.0 + (a * t).powi(2) / (2.0 * 0.1 * g);
    assert!(residual > 0.0, "{residual}");
    assert!((residual / d - 1.0).abs() < 2e-3, "{residual} against {d}");
}
