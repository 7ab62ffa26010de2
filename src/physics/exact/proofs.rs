//! The cruise proofs: sign tests that prove a whole sample interval
//! eventless (the motion monotone, or its one turning point a maximum below
//! θmax so far or a minimum above the pivot), and the stepper's floor for
//! `rocking-bench` ([`Exact::bare_pass`]).

use super::closed_form::Motion;
use super::stepper::Exact;
use crate::physics::lanes::{Lane, Lanes, Mask};
use crate::physics::Excitation;

impl<T: Lane> Motion<T> {
    /// Whether the velocity provably keeps its sign on the stretch, given
    /// its value `v_end` at the end and `delta_max = e^{p·len} − 1`: then x
    /// is monotone and has no turning point inside. `2e^z·v(σ)` is the
    /// quadratic `Q(δ) = A δ² + 2B δ + 2v_a` in `δ = e^z − 1` (see
    /// [`Motion::turning_points`]); with `Q` of one sign at both ends, it has
    /// a root inside only if its vertex `−B/A` lies in `(0, δ_max)`,
    /// `Q(0) = 2v_a` has the sign of `A` (otherwise the ends lie on the
    /// vertex's side and the roots, if any, straddle the stretch) and the
    /// discriminant is not negative. Only sign tests and products: no division, root or
    /// logarithm.
    /// Lane by lane for runs in step.
    #[inline(always)]
    pub(super) fn monotone(&self, v_end: T, delta_max: T) -> T::Mask {
        // Same strict sign at both ends (NaN: no claim). The tests are
        // combined without short circuits: one branch for the caller.
        let zero = T::splat(0.0);
        let same_sign = (self.v_a * v_end).gt(zero);
        let b = self.p * self.u + self.v_a;
        let a = b + self.g1e;
        let vertex_inside =
            (a * b).lt(zero) & b.abs().lt(a.abs() * delta_max) & (a * self.v_a).gt(zero);
        same_sign & (!vertex_inside | (b * b - a * (T::splat(2.0) * self.v_a)).lt(zero))
    }
}

impl Exact {
    /// The floor of the stepper, for `rocking-bench`: every whole interval
    /// of `exc` advanced by the closed form with the sign tests of
    /// [`crate::physics::Stepper::cruise`] (monotone, the pivot, the limit) but no event
    /// ever handled, from `x = s/2` at rest. Returns the final state and
    /// how many intervals the tests flagged (so that nothing is optimised
    /// away). The motion is unbounded, as the linearised equation is
    /// without impacts: the time is what matters.
    pub fn bare_pass(&self, exc: &Excitation, s: f64) -> (f64, f64, u64) {
        let (psi, slope) = (&exc.psi[..], &exc.slope[..]);
        let (mut x, mut v, mut flagged) = (0.5 * s, 0.0, 0u64);
        for (k, &g1) in slope.iter().enumerate() {
            let m = self.motion(x, v, s, psi[k], g1);
            let (x_hi, v_hi) = m.at(&self.full);
            let y_hi = s * x_hi;
            flagged +=
                u64::from(!(m.monotone(v_hi, self.full_expm1) && y_hi < self.limit && y_hi > 0.0));
            (x, v) = (x_hi, v_hi);
        }
        (x, v, flagged)
    }
}

impl Exact {
    /// The floor of runs in step, for `rocking-bench`: [`Exact::bare_pass`]
    /// of four runs at `etas` (the same block and record) advanced together,
    /// four lanes of one AVX register on a CPU with x86-64-v3 (else one by
    /// one). Returns each run's final x and how many intervals some lane's
    /// tests flagged (so that nothing is optimised away).
    pub fn bare_pass_four(&self, exc: &Excitation, s: f64, etas: [f64; 4]) -> ([f64; 4], u64) {
        #[cfg(target_arch = "x86_64")]
        match crate::physics::Isa::detected() {
            // SAFETY (both arms): the CPU has the features of the isa detected.
            crate::physics::Isa::V4 => return unsafe { bare_pass_four_v4(self, exc, s, etas) },
            crate::physics::Isa::V3 => return unsafe { bare_pass_four_v3(self, exc, s, etas) },
            crate::physics::Isa::Baseline => {}
        }
        let mut x = [0.0; 4];
        let mut flagged = 0;
        for (xi, &eta) in x.iter_mut().zip(&etas) {
            let one = Exact::new(self.p, eta, exc.dt_s, self.limit);
            let (x_end, _, f) = one.bare_pass(exc, s);
            (*xi, flagged) = (x_end, flagged + f);
        }
        (x, flagged)
    }

    /// [`Exact::bare_pass`] in the lanes of `L`, one run of `etas` each.
    #[inline(always)]
    fn bare_pass_lanes<L: Lanes<N>, const N: usize>(
        &self,
        exc: &Excitation,
        s: f64,
        etas: [f64; N],
    ) -> ([f64; N], u64) {
        let (psi, slope) = (&exc.psi[..], &exc.slope[..]);
        let full = self.full.splat::<L>();
        let (p, delta_max) = (L::splat(self.p), L::splat(self.full_expm1));
        let (s_lane, zero, limit) = (L::splat(s), L::splat(0.0), L::splat(self.limit));
        let s_eta = L::from_lanes(etas.map(|e| s * e));
        let inv_eta = L::from_lanes(etas.map(|e| 1.0 / e));
        let (mut x, mut v, mut flagged) = (L::splat(0.5 * s), zero, 0u64);
        for (k, &g1) in slope.iter().enumerate() {
            let m = Motion::new(p, s_eta, inv_eta, x, v, L::splat(psi[k]), L::splat(g1));
            let (x_hi, v_hi) = m.at(&full);
            let y_hi = s_lane * x_hi;
            let fine = m.monotone(v_hi, delta_max) & y_hi.lt(limit) & y_hi.gt(zero);
            flagged += u64::from(!fine.all());
            (x, v) = (x_hi, v_hi);
        }
        (x.to_lanes(), flagged)
    }
}

/// [`Exact::bare_pass_four`] in one AVX register.
///
/// # Safety
/// The CPU must have the features enabled here.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,bmi1,bmi2,fma,lzcnt,movbe,popcnt")]
unsafe fn bare_pass_four_v3(
    stepper: &Exact,
    exc: &Excitation,
    s: f64,
    etas: [f64; 4],
) -> ([f64; 4], u64) {
    stepper.bare_pass_lanes::<crate::physics::lanes::F4, 4>(exc, s, etas)
}

/// [`Exact::bare_pass_four`] in one AVX register, compiled for x86-64-v4.
///
/// # Safety
/// The CPU must have the features enabled here.
#[cfg(target_arch = "x86_64")]
#[target_feature(
    enable = "avx,avx2,bmi1,bmi2,fma,lzcnt,movbe,popcnt,avx512f,avx512bw,avx512cd,avx512dq,avx512vl"
)]
unsafe fn bare_pass_four_v4(
    stepper: &Exact,
    exc: &Excitation,
    s: f64,
    etas: [f64; 4],
) -> ([f64; 4], u64) {
    stepper.bare_pass_lanes::<crate::physics::lanes::F4, 4>(exc, s, etas)
}

impl Exact {
    /// Whether the one turning point of an interval is a maximum that
    /// provably stays below `top` (θmax so far): then `rock` would find the
    /// interval eventless and leave θmax as it is, and `cruise` may cross
    /// it. With `y = s·x` rising at the start and falling at the end, `ẏ`
    /// has one root inside (at most two, an odd number): a maximum, above
    /// both ends, so the pivot is not reached. While `y ≤ top`,
    /// `ÿ = p²(y − 1 + sψ̈/η) ≤ p²(top − 1 + max sψ̈/η) = −D`. Two bounds
    /// follow, and either proves the maximum below `top` (with a margin of
    /// 1e-9 for rounding):
    /// - if `D > 0`, `y` stays below `y_a + ẏ_a²/(2D)` (the parabola's apex;
    ///   sharp for a swing whose apex is near);
    /// - in any case `ẏ(σ) ≤ ẏ_a + max(0, −D)·σ`, so `y` stays below
    ///   `y_a + ẏ_a·dt + max(0, −D)·dt²/2` over the interval (sharp for a
    ///   swing that turns far below `top`, where the forcing may push out).
    ///
    /// Only products and sign tests.
    #[inline(always)]
    pub(super) fn apex_below(
        &self,
        m: &Motion,
        s: f64,
        v_end: f64,
        g0: f64,
        g_end: f64,
        top: f64,
    ) -> bool {
        let (w_a, y_a) = (s * m.v_a, s * m.x_a);
        if !(w_a > 0.0 && s * v_end < 0.0) {
            return false;
        }
        let d = self.p * self.p * (1.0 - top - (s * g0).max(s * g_end) * self.inv_eta);
        let room = top * (1.0 - 1e-9) - y_a;
        let dt = self.full.sigma;
        let parabola = d > 0.0 && w_a * w_a < 2.0 * d * room;
        let chord = w_a * dt + 0.5 * (-d).max(0.0) * dt * dt < room;
        parabola | chord
    }

    /// Whether the one turning point of an interval is a minimum that
    /// provably stays above the pivot (`y > 0`, with a margin of 1e-12):
    /// then `rock` would find the interval eventless, and `cruise` may
    /// cross it. With `y` falling at the start and rising at the end, the
    /// turning point is a minimum below both ends, so the limit is not
    /// reached. While `y ≥ 0`, `ÿ ≥ p²(min sψ̈/η − 1) = −E`, so
    /// `ẏ(σ) ≥ ẏ_a − max(0, E)·σ` and `y` stays above
    /// `y_a + ẏ_a·dt − max(0, E)·dt²/2` over the interval. Only products and
    /// sign tests.
    #[inline(always)]
    pub(super) fn valley_above(&self, m: &Motion, s: f64, v_end: f64, g0: f64, g_end: f64) -> bool {
        let (w_a, y_a) = (s * m.v_a, s * m.x_a);
        if !(w_a < 0.0 && s * v_end > 0.0) {
            return false;
        }
        let e = self.p * self.p * (1.0 - (s * g0).min(s * g_end) * self.inv_eta);
        let dt = self.full.sigma;
        y_a + w_a * dt - 0.5 * e.max(0.0) * dt * dt > 1e-12
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::exact::closed_form::Coeffs;

    /// Four chains in step are four lone chains, to the bit (the same IEEE
    /// operations in each lane), and flag as often as the lone ones do.
    #[test]
    fn four_chains_in_step_are_four_lone_passes() {
        let mut draw = uniform_from(7);
        let samples: Vec<f64> = (0..3000).map(|_| draw(-1.0, 1.0)).collect();
        let exc = Excitation::new(&samples, 0.01).unwrap();
        let etas = [0.5, 0.55, 0.6, 0.65];
        let (x4, flagged) = Exact::new(2.0, 0.5, 0.01, 1.0).bare_pass_four(&exc, 1.0, etas);
        let mut lone_flagged = 0;
        for (x, eta) in x4.iter().zip(etas) {
            let (x1, _, f) = Exact::new(2.0, eta, 0.01, 1.0).bare_pass(&exc, 1.0);
            assert_eq!(x.to_bits(), x1.to_bits(), "η = {eta}");
            lone_flagged = lone_flagged.max(f);
        }
        // An interval is flagged where any lane's is: at least as often as
        // the chain flagged most.
        assert!(flagged >= lone_flagged && flagged > 0);
    }

    /// Uniform draws in `[lo, hi)` from a fixed seed (a 64-bit LCG): the
    /// random tests are the same on every run.
    fn uniform_from(seed: u64) -> impl FnMut(f64, f64) -> f64 {
        let mut state = seed;
        move |lo, hi| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            lo + (hi - lo) * ((state >> 11) as f64 / (1u64 << 53) as f64)
        }
    }

    /// `monotone` against the velocity itself, sampled on a fine grid over
    /// motions of every shape: it never claims a sign change away (sound),
    /// and it claims every stretch whose velocity keeps its sign with a
    /// margin (sharp), including those whose quadratic in δ has its vertex
    /// inside but both roots outside (a parabola that turns short of zero).
    #[test]
    fn monotone_claims_exactly_the_stretches_of_one_velocity_sign() {
        let mut uniform = uniform_from(0x9e37_79b9_7f4a_7c15u64);
        let (mut claimed, mut turning_short) = (0, 0);
        for _ in 0..20_000 {
            let p = [0.5, 2.0, 8.0][(uniform(0.0, 3.0) as usize).min(2)];
            let len = uniform(0.005, 0.05);
            let m = Motion {
                p,
                x_a: uniform(0.0, 0.5),
                v_a: uniform(-1.0, 1.0) * 10f64.powf(uniform(-4.0, 0.0)),
                u: uniform(-2.0, 2.0),
                g1e: uniform(-1.0, 1.0) * 10f64.powf(uniform(-1.0, 3.0)),
            };
            let delta_max = (p * len).exp_m1();
            let v = |sigma: f64| m.at(&Coeffs::new(p, sigma)).1;
            let samples: Vec<f64> = (0..=2000).map(|i| v(len * i as f64 / 2000.0)).collect();
            let scale = samples.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let one_sign = samples.iter().all(|w| w * m.v_a > 0.0);
            let margin = samples.iter().all(|w| w * m.v_a > 1e-6 * scale);
            let says = m.monotone(v(len), delta_max);
            assert!(
                !says || one_sign,
                "claimed monotone with a sign change: {m:?}, len {len}"
            );
            assert!(
                says || !margin,
                "missed a monotone stretch: {m:?}, len {len}"
            );
            claimed += usize::from(says);
            let b = p * m.u + m.v_a;
            let a = b + m.g1e;
            let vertex_inside = a * b < 0.0 && b.abs() < a.abs() * delta_max;
            turning_short += usize::from(says && vertex_inside && b * b >= a * 2.0 * m.v_a);
        }
        assert!(
            claimed > 5_000 && turning_short > 500,
            "{claimed}, {turning_short}"
        );
    }

    /// `apex_below` against the apex itself (turning point in closed form):
    /// whenever it says the maximum stays below `top`, it does, for `top`
    /// on both sides of the apex; and it does say so where `top` is well
    /// above it.
    #[test]
    fn apex_bound_holds_and_is_used() {
        let (mut accepted, mut cases) = (0, 0);
        for p in [0.5, 2.0, 6.0] {
            for eta in [0.1, 0.4] {
                for s in [1.0, -1.0] {
                    for (y_a, w_rel) in [(0.3, 0.2), (0.05, 0.1), (0.6, 0.02)] {
                        for (g0, g_end) in [(0.0, 0.05), (-0.08, 0.02), (0.03, -0.09)] {
                            let dt = 0.02;
                            let lin = Exact::new(p, eta, dt, 1.0);
                            let (x_a, v_a) = (s * y_a, s * w_rel * p);
                            let m = Motion {
                                p,
                                x_a,
                                v_a,
                                u: x_a + (s * g0 - s * eta) / eta,
                                g1e: s * (g_end - g0) / dt / eta,
                            };
                            let (_, v_end) = m.at(&lin.full);
                            if s * v_end >= 0.0 {
                                continue;
                            }
                            let (t, n) = m.turning_points(dt, lin.full_expm1);
                            assert_eq!(n, 1, "one maximum inside");
                            let apex = s * m.at(&Coeffs::new(p, t[0])).0;
                            for f in [0.9, 0.999, 1.001, 1.05, 1.5, 3.0] {
                                let top = apex * f;
                                cases += 1;
                                if lin.apex_below(&m, s, v_end, s * g0, s * g_end, top) {
                                    accepted += 1;
                                    assert!(
                                        apex < top,
                                        "p {p} η {eta} y {y_a} w {w_rel}: {apex} vs {top}"
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
        assert!(accepted * 4 > cases, "{accepted} of {cases} accepted");
    }

    /// `apex_below` and `valley_above` against the turning point itself
    /// (closed form), over random swings of every strength of forcing: a
    /// maximum they pass stays below `top` and a minimum stays above the
    /// pivot; and each bound (the apex parabola, the chord where the forcing
    /// pushes out, the valley) passes swings that turn well inside.
    #[test]
    fn turn_bounds_hold_against_the_closed_form() {
        let mut uniform = uniform_from(0x2545_f491_4f6c_dd1du64);
        let (mut parabola, mut chord, mut valley, mut maxima, mut minima) = (0, 0, 0, 0, 0);
        for _ in 0..200_000 {
            let p = [0.5, 2.0, 8.0][(uniform(0.0, 3.0) as usize).min(2)];
            let eta = uniform(0.05, 1.0);
            let dt = [0.005, 0.01, 0.02][(uniform(0.0, 3.0) as usize).min(2)];
            let s = if uniform(0.0, 1.0) < 0.5 { 1.0 } else { -1.0 };
            let (g0, g_end) = (uniform(-1.0, 1.0), uniform(-1.0, 1.0));
            // Down to swings of 1e-5 just off the pivot, where a minimum
            // comes near it.
            let y_a = 0.9 * 10f64.powf(uniform(-5.0, 0.0));
            let w_a = uniform(-1.0, 1.0) * p * 10f64.powf(uniform(-5.0, 0.0));
            let lin = Exact::new(p, eta, dt, 1.0);
            let (x_a, v_a) = (s * y_a, s * w_a);
            let m = lin.motion(x_a, v_a, s, g0, (g_end - g0) / dt);
            let (x_end, v_end) = m.at(&lin.full);
            let (t, n) = m.turning_points(dt, lin.full_expm1);
            if n != 1 || s * x_end <= 0.0 || x_end.is_nan() {
                continue;
            }
            let turn = s * m.at(&Coeffs::new(p, t[0])).0;
            if w_a > 0.0 {
                maxima += 1;
                let d = p * p * (1.0 - 1.0 - (s * g0).max(s * g_end) / eta);
                for f in [0.5, 0.9, 0.999, 1.001, 1.05, 1.5, 3.0] {
                    let top = turn * f;
                    if lin.apex_below(&m, s, v_end, g0, g_end, top) {
                        assert!(turn < top, "{m:?}: apex {turn} vs top {top}");
                        if f >= 1.5 {
                            // Which bound passed it (D at top = 1 is a lower bound of D).
                            if d + p * p * (1.0 - top) > 0.0 {
                                parabola += 1;
                            } else {
                                chord += 1;
                            }
                        }
                    }
                }
            } else {
                minima += 1;
                if lin.valley_above(&m, s, v_end, g0, g_end) {
                    assert!(turn > 0.0, "{m:?}: valley {turn}");
                    valley += 1;
                }
            }
        }
        assert!(
            maxima > 1000 && minima > 1000,
            "{maxima} maxima, {minima} minima"
        );
        assert!(
            parabola > 100 && chord > 100 && valley > 100,
            "{parabola}, {chord}, {valley}"
        );
    }
}
