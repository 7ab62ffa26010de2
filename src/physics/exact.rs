//! The exact integrator: closed-form stepping of the linearised rocking equation.
//!
//! On pivot `s`, with `ψ̈(τ0 + σ) = g_a + g1·σ` over a stretch of a sample
//! interval, `ẍ = p²(x − s) + (p²/η)ψ̈` is linear with a linear forcing. With
//! `u = x_a − s + g_a/η` (the distance from the moving equilibrium) and
//! `z = pσ`, its solution written as increments from the state `(x_a, v_a)`
//! at the stretch start is
//!
//! ```text
//! x(σ) = x_a + u·C(z) + v_a·σ·S(z) + (g1/η)·σ·(S(z) − 1)
//! v(σ) = v_a + p·u·sinh z + (v_a + g1/η)·C(z)
//! C(z) = cosh z − 1 = 2 sinh²(z/2),   S(z) = sinh(z)/z
//! ```
//!
//! The textbook form `x = A cosh + B sinh + particular` subtracts numbers of
//! size 1 to get motions of size 1e-12; this form never does: each term is
//! as small as the motion it describes. `u` is formed as
//! `x_a + (g_a − sη)/η`, where `g_a − sη` is exact near the threshold
//! (Sterbenz), and `S − 1` uses its Taylor series for small z.
//!
//! Extrema: `v(σ) = 0` is a quadratic in `δ = e^z − 1`,
//! `A δ² + 2(pu + v_a) δ + 2 v_a = 0` with `A = pu + v_a + g1/η`, so the (at
//! most two) turning points inside a stretch are found in closed form. Between
//! them `x` is monotone, so every event (a return to `x = 0`, a crossing of
//! the overturning limit) is bracketed, never missed, and located to a few
//! ulps by safeguarded Newton iteration. The true maxima of |x| between
//! samples are the turning points, so θmax is exact too.

use super::{Rocking, Stepper, Stretch, StretchEnd};

/// `cosh z − 1`, without cancellation: `z²/2 · (1 + z²/12 + …)`, its
/// Taylor series to z¹⁴ for |z| < 0.5 (to z⁶ below |z| = 0.01, where the
/// first dropped term is below 2⁻⁵³ of the sum), `2 sinh²(z/2)` above.
/// The bracket is a polynomial in z² with reciprocal constants: no division
/// on the events' path.
#[inline(always)]
pub fn cosh_m1(z: f64) -> f64 {
    let z2 = z * z;
    if z2 < 1e-4 {
        0.5 * z2 * (1.0 + z2 * (1.0 / 12.0 + z2 * (1.0 / 360.0)))
    } else if z2 < 0.25 {
        0.5 * z2
            * (1.0
                + z2 * (1.0 / 12.0
                    + z2 * (1.0 / 360.0
                        + z2 * (1.0 / 20_160.0
                            + z2 * (1.0 / 1_814_400.0
                                + z2 * (1.0 / 239_500_800.0 + z2 * (1.0 / 43_589_145_600.0)))))))
    } else {
        let h = (0.5 * z).sinh();
        2.0 * h * h
    }
}

/// `sinh(z)/z − 1`: `z²/6 · (1 + z²/20 + …)`, its Taylor series to z¹⁴ for
/// |z| < 0.5 (to z⁶ below |z| = 0.01; the first dropped term is below 2⁻⁵³
/// of the sum), directly above. One division (z²/6, exactly rounded), off
/// the polynomial's dependency chain.
#[inline(always)]
pub fn sinhc_m1(z: f64) -> f64 {
    let z2 = z * z;
    if z2 < 1e-4 {
        z2 / 6.0 * (1.0 + z2 * (1.0 / 20.0 + z2 * (1.0 / 840.0)))
    } else if z2 < 0.25 {
        z2 / 6.0
            * (1.0
                + z2 * (1.0 / 20.0
                    + z2 * (1.0 / 840.0
                        + z2 * (1.0 / 60_480.0
                            + z2 * (1.0 / 6_652_800.0
                                + z2 * (1.0 / 1_037_836_800.0 + z2 * (1.0 / 217_945_728_000.0)))))))
    } else {
        z.sinh() / z - 1.0
    }
}

/// The functions of `z = pσ` the step needs.
#[derive(Debug, Clone, Copy)]
struct Coeffs {
    sigma: f64,
    sinh: f64,
    /// cosh z − 1
    c: f64,
    /// σ·sinh(z)/z = sinh(z)/p
    s_sigma: f64,
    /// σ·(sinh(z)/z − 1)
    s1_sigma: f64,
}

impl Coeffs {
    #[inline(always)]
    fn new(p: f64, sigma: f64) -> Self {
        // Below |z| = 0.5 (every sample interval up to p·dt = 0.5) these are
        // polynomials: no transcendental call in the hot loop.
        let z = p * sigma;
        let s1 = sinhc_m1(z);
        Coeffs {
            sigma,
            sinh: z + z * s1,
            c: cosh_m1(z),
            s_sigma: sigma + sigma * s1,
            s1_sigma: sigma * s1,
        }
    }
}

/// The exact stepper of the linearised equation; one per (p, η, dt).
#[derive(Clone)]
pub struct Exact {
    p: f64,
    eta: f64,
    inv_eta: f64,
    limit: f64,
    /// Coefficients of a whole sample interval, computed once.
    full: Coeffs,
    /// e^{p·dt} − 1
    full_expm1: f64,
}

/// The motion on one stretch, evaluable at any σ.
#[derive(Debug, Clone, Copy)]
struct Motion {
    p: f64,
    x_a: f64,
    v_a: f64,
    /// u = x_a − s + g_a/η
    u: f64,
    /// g1/η
    g1e: f64,
}

impl Motion {
    #[inline(always)]
    fn at(&self, c: &Coeffs) -> (f64, f64) {
        let x = self.x_a + self.u * c.c + self.v_a * c.s_sigma + self.g1e * c.s1_sigma;
        let v = self.v_a + self.p * self.u * c.sinh + (self.v_a + self.g1e) * c.c;
        (x, v)
    }

    /// The size of the largest term of x(σ): the scale of its rounding error.
    #[inline(always)]
    fn scale(&self, c: &Coeffs) -> f64 {
        self.x_a.abs()
            + (self.u * c.c).abs()
            + (self.v_a * c.s_sigma).abs()
            + (self.g1e * c.s1_sigma).abs()
    }

    /// Acceleration at σ given x(σ): p²(x − s + ψ̈(σ)/η).
    #[inline(always)]
    fn acc(&self, x: f64, sigma: f64) -> f64 {
        self.p * self.p * (x - self.x_a + self.u + self.g1e * sigma)
    }

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
    #[inline(always)]
    fn monotone(&self, v_end: f64, delta_max: f64) -> bool {
        // Same strict sign at both ends (NaN: no claim). The tests are
        // combined without short circuits: one branch for the caller.
        let same_sign = self.v_a * v_end > 0.0;
        let b = self.p * self.u + self.v_a;
        let a = b + self.g1e;
        let vertex_inside = (a * b < 0.0) & (b.abs() < a.abs() * delta_max) & (a * self.v_a > 0.0);
        same_sign & (!vertex_inside | (b * b - a * (2.0 * self.v_a) < 0.0))
    }

    /// Turning points (v = 0) with 0 < σ < len, ascending.
    /// `delta_max = e^{p·len} − 1` bounds δ, so roots outside the stretch
    /// cost no logarithm.
    #[inline(always)]
    fn turning_points(&self, len: f64, delta_max: f64) -> ([f64; 2], usize) {
        let b = self.p * self.u + self.v_a;
        let a = b + self.g1e;
        let c = 2.0 * self.v_a;
        let mut roots = [f64::NAN; 2];
        let mut n = 0;
        let mut push = |delta: f64| {
            if delta > 0.0 && delta < delta_max {
                let sigma = delta.ln_1p() / self.p;
                if sigma > 0.0 && sigma < len {
                    roots[n] = sigma;
                    n += 1;
                }
            }
        };
        if a == 0.0 {
            if b != 0.0 {
                push(-c / (2.0 * b));
            }
        } else {
            let disc = b * b - a * c;
            if disc >= 0.0 {
                // a δ² + 2b δ + c = 0, the stable pair of formulas.
                let q = -(b + b.signum() * disc.sqrt());
                if q != 0.0 {
                    push(q / a);
                    push(c / q);
                } else {
                    // b = 0 and disc = 0: c = 0 too, a double root at δ = 0.
                }
            }
        }
        if n == 2 && roots[0] > roots[1] {
            roots.swap(0, 1);
        }
        (roots, n)
    }
}

/// The smallest positive root of `a τ² + b τ + c = 0` (NaN if none).
#[inline(always)]
fn first_positive_root(a: f64, b: f64, c: f64) -> f64 {
    if a == 0.0 {
        let t = -c / b;
        return if t > 0.0 { t } else { f64::NAN };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return f64::NAN;
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let (r1, r2) = (q / a, if q != 0.0 { c / q } else { f64::NAN });
    match (r1 > 0.0, r2 > 0.0) {
        (true, true) => r1.min(r2),
        (true, false) => r1,
        (false, true) => r2,
        _ => f64::NAN,
    }
}

/// [`super::driver::drive`] with the exact stepper, compiled for `isa`
/// (see [`Isa`]).
#[inline]
pub(super) fn drive<O: super::Observer>(
    exc: &super::Excitation,
    spec: &super::RunSpec,
    start: Option<Rocking>,
    limit: f64,
    stepper: &mut Exact,
    obs: &mut O,
    isa: Isa,
) -> super::Outcome {
    match isa {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: this function's callers pass `Isa::V3` only where the CPU
        // has its features: `Isa::detected()` (`simulate_from`), or an isa
        // `simulate_on` checked with `Isa::available`.
        Isa::V3 => unsafe { drive_v3(exc, spec, start, limit, stepper, obs) },
        _ => super::driver::drive(exc, spec, start, limit, stepper, obs),
    }
}

/// [`drive`] compiled for x86-64-v3: the event loop and the stepper's
/// methods are `#[inline(always)]`, so they are compiled into this
/// function, with its features.
///
/// # Safety
/// The CPU must have the features enabled here.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,bmi1,bmi2,fma,lzcnt,movbe,popcnt")]
unsafe fn drive_v3<O: super::Observer>(
    exc: &super::Excitation,
    spec: &super::RunSpec,
    start: Option<Rocking>,
    limit: f64,
    stepper: &mut Exact,
    obs: &mut O,
) -> super::Outcome {
    super::driver::drive(exc, spec, start, limit, stepper, obs)
}

/// [`super::driver::drive_pair`] compiled for x86-64-v3, the one
/// compilation with a paired path ([`super::simulate_pair`]).
///
/// # Safety
/// The CPU must have the features enabled here.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,bmi1,bmi2,fma,lzcnt,movbe,popcnt")]
pub(super) unsafe fn drive_pair_v3(
    exc: &super::Excitation,
    specs: [&super::RunSpec; 2],
    limits: [f64; 2],
    steppers: [&mut Exact; 2],
) -> [super::Outcome; 2] {
    super::driver::drive_pair(exc, specs, limits, steppers)
}

/// Which compilation of the exact stepper's event loop runs. The loop and
/// the stepper are compiled twice, for the x86-64 baseline and for
/// x86-64-v3 (AVX2, FMA, BMI: VEX-encoded three-operand arithmetic),
/// chosen at run time by the CPU's features, so one binary runs on any
/// x86-64 CPU and at its best on those of the last decade. Both do the
/// same IEEE operations in the same order (Rust never fuses a product and
/// a sum unless asked to, and the stepper never asks), so their results
/// are identical to the bit; `tests/physics.rs` holds them equal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// The x86-64 baseline (SSE2), or any other architecture's default.
    Baseline,
    /// x86-64-v3: AVX2, FMA, BMI1/2, LZCNT, MOVBE.
    V3,
}

impl Isa {
    /// The best compilation this CPU runs: [`Isa::V3`] where it has the
    /// features, unless the environment variable `ROCKING_ISA` is
    /// `baseline` (to compare the two, or to rule the faster one out; any
    /// other value changes nothing). Decided once per process.
    pub fn detected() -> Isa {
        static DETECTED: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *DETECTED.get_or_init(|| {
            let forced = std::env::var_os("ROCKING_ISA").is_some_and(|v| v == "baseline");
            if !forced && Isa::V3.available() {
                Isa::V3
            } else {
                Isa::Baseline
            }
        })
    }

    /// Whether this CPU can run this compilation.
    pub fn available(self) -> bool {
        match self {
            Isa::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            Isa::V3 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
                    && std::arch::is_x86_feature_detected!("bmi1")
                    && std::arch::is_x86_feature_detected!("bmi2")
                    && std::arch::is_x86_feature_detected!("lzcnt")
                    && std::arch::is_x86_feature_detected!("movbe")
                    && std::arch::is_x86_feature_detected!("popcnt")
            }
            #[cfg(not(target_arch = "x86_64"))]
            Isa::V3 => false,
        }
    }
}

impl Exact {
    pub fn new(p: f64, eta: f64, dt: f64, limit: f64) -> Self {
        Exact {
            p,
            eta,
            inv_eta: 1.0 / eta,
            limit,
            full: Coeffs::new(p, dt),
            full_expm1: (p * dt).exp_m1(),
        }
    }

    /// The motion on pivot `s` from `(x, v)` under the forcing `g_a + g1·σ`.
    #[inline(always)]
    fn motion(&self, x: f64, v: f64, s: f64, g_a: f64, g1: f64) -> Motion {
        Motion {
            p: self.p,
            x_a: x,
            v_a: v,
            u: x + (g_a - s * self.eta) * self.inv_eta,
            g1e: g1 * self.inv_eta,
        }
    }

    /// The first σ in (lo, hi] where `y(σ) = s·x(σ)` reaches `target`, given
    /// `y(lo)` short of it, `y(hi)` on or past it and `y` monotone between.
    /// Returns σ on the far side, within a few ulps of the crossing (so the
    /// event condition holds there), and the velocity there.
    /// `(lo, (x, v) at lo)` and `(hi, (x, v) at hi)` bracket the crossing.
    #[inline(always)]
    fn locate(
        &self,
        m: &Motion,
        s: f64,
        target: f64,
        (mut lo, (x_lo, v_lo)): (f64, (f64, f64)),
        (mut hi, (x_hi, mut v_hi)): (f64, (f64, f64)),
        rising: bool,
    ) -> (f64, f64) {
        let reached = |y: f64| if rising { y >= target } else { y <= target };
        let mut g_hi = s * x_hi - target;
        let mut g_lo = s * x_lo - target;
        // First guess from the Taylor parabola at `lo`: a piece that starts at a
        // turning point (a Zeno swing of 1e-9 s inside a 0.01 s interval, say)
        // is found at once instead of by ~30 halvings.
        // One Newton step on the cubic Taylor polynomial then takes the jerk
        // into account, so that Newton on the motion itself starts within
        // O(τ⁴) and usually needs one step.
        let (y1, y2) = (s * v_lo, s * m.acc(x_lo, lo));
        let mut tau = first_positive_root(0.5 * y2, y1, g_lo);
        let y3 = s * self.p * self.p * (v_lo + m.g1e);
        let slope = y1 + tau * (y2 + 0.5 * y3 * tau);
        let cubic = tau - (g_lo + tau * (y1 + tau * (0.5 * y2 + tau * y3 / 6.0))) / slope;
        if cubic > 0.0 && cubic < hi - lo {
            tau = cubic;
        }
        let guess = lo + tau;
        let mut at = if guess > lo && guess < hi {
            guess
        } else {
            0.5 * (lo + hi)
        };
        let mut c_at = Coeffs::new(self.p, at);
        let (mut x_at, mut v_at) = m.at(&c_at);
        // Safeguarded Newton: quadratic convergence; when a step leaves the
        // bracket, regula falsi between its ends, then bisection.
        for _ in 0..100 {
            let g_at = s * x_at - target;
            if reached(s * x_at) {
                (hi, v_hi, g_hi) = (at, v_at, g_at);
            } else {
                (lo, g_lo) = (at, g_at);
            }
            if hi - lo <= 4.0 * f64::EPSILON * hi {
                break;
            }
            let dy = s * v_at;
            let newton = at - g_at / dy;
            // Converged when the step is within the time equivalent of the
            // rounding in x (a few ulps of its largest term): beyond that,
            // Newton only chases noise.
            let resolution =
                4.0 * f64::EPSILON * (at + m.scale(&c_at) / dy.abs().max(f64::MIN_POSITIVE));
            if (newton - at).abs() <= resolution {
                break;
            }
            let mut next = newton;
            if !(next > lo && next < hi) {
                next = lo + (hi - lo) * (g_lo / (g_lo - g_hi));
                if !(next > lo && next < hi) {
                    next = 0.5 * (lo + hi);
                }
                if !(next > lo && next < hi) {
                    break;
                }
            }
            at = next;
            c_at = Coeffs::new(self.p, at);
            (x_at, v_at) = m.at(&c_at);
        }
        if hi - lo <= 4.0 * f64::EPSILON * hi || at == hi {
            // Closed, or Newton converged on the far side: within its
            // resolution of the crossing, and the event condition holds.
            return (hi, v_hi);
        }
        // Newton converged from one side only: close the bracket by walking
        // away from the last iterate in steps doubling from one ulp, so that
        // the returned point is within a few ulps of the crossing.
        let mut step = f64::EPSILON * at.max(f64::MIN_POSITIVE);
        if at == hi {
            loop {
                let probe = hi - step;
                if probe <= lo {
                    return (hi, v_hi);
                }
                let (x, v) = m.at(&Coeffs::new(self.p, probe));
                if !reached(s * x) {
                    return (hi, v_hi);
                }
                (hi, v_hi) = (probe, v);
                step *= 2.0;
            }
        }
        loop {
            let probe = lo + step;
            if probe >= hi {
                return (hi, v_hi);
            }
            let (x, v) = m.at(&Coeffs::new(self.p, probe));
            if reached(s * x) {
                return (probe, v);
            }
            lo = probe;
            step *= 2.0;
        }
    }
}

/// The largest expansion parameter of a hop solved by its Taylor series:
/// `z = pσ` and the relative change of the forcing over the hop. At 1e-2,
/// the series through y⁽⁸⁾ leaves a remainder below 1e-18 of the motion
/// (its last term kept is 5e-17 of it).
const HOP_Z: f64 = 1e-2;

/// Up to this size of a hop's expansion parameters (`max(z², |bσ/|a||)`),
/// its return time and speed are their series to fifth order in them;
/// above it, two Newton steps from the second-order guess (see
/// [`Exact::hop`]).
const HOP_SERIES: f64 = 2e-3;

impl Exact {
    /// A small hop after an impact, in closed form: from `x = 0` with the
    /// block moving out on pivot `s` against a restoring forcing, the return
    /// to `x = 0` (σ, and the velocity there), when it lies inside the
    /// stretch and its apex provably stays below `max_abs_x` (so nothing
    /// else can happen on the way). `None` leaves the stretch to the
    /// general walk.
    ///
    /// The tail of impacts that brings a block to rest (about 60 at
    /// ε = 0.8) is made of such hops. With `y = s·x`, `w = ẏ(0) > 0`,
    /// `ÿ = p²y + a + bσ` (`a = p²·s·u < 0`, `b = p²·s·g1/η`), the Taylor
    /// coefficients of `y` are `w, a, p²w + b, p²a, p²(p²w + b), p⁴a, …`;
    /// over a hop (σ ≈ σ₀ = 2w/|a|) term n of `y` is of relative size
    /// `2z^(n−2)/n!` (n even) or `(z^(n−1) + 2z^(n−3)·bσ/|a|)/n!` (n odd), so
    /// with both below [`HOP_Z`] the terms through y⁽⁸⁾ are exact to rounding.
    ///
    /// In the time `t = σ/σ₀`, with `q = (pσ₀)²`, `β = bσ₀/|a|` and
    /// `Y = y/(wσ₀)`, the hop is `Y'' = qY − 2 + 2βt`, `Y(0) = 0`,
    /// `Y'(0) = 1`: its return time `T = σ/σ₀` and speed ratio
    /// `V = −Y'(T)` are functions of `(q, β)` alone, 1 at `(0, 0)`.
    ///
    /// - For `e = max(q, |β|)` up to [`HOP_SERIES`] (nine hops in ten of a
    ///   sweep, spread evenly over the decades from 1e-8; `q` is at most
    ///   `HOP_Z²` = 1e-4, so `e` is mostly `|β|`), `T` and `V` are
    ///   their double series in `q` and `β` to total degree 5, found by
    ///   perturbation of `Y(T) = 0` (exact rationals; along `q = 0` they
    ///   are Catalan's numbers over 3ⁿ, the roots of `βT²/3 − T + 1 = 0`,
    ///   and at `β = 0` the hop is symmetric, `V = 1`). The first term left
    ///   out is below 0.2·e⁶ = 1.2e-17, and against the closed form (mpmath,
    ///   40 digits) the evaluation's worst relative error over
    ///   `q ≤ 1e-4, |β| ≤ 2e-3` is 1.7e-16: rounding. No division but the one reciprocal of `a`,
    ///   and no Newton iteration: the chain from one hop to the next is
    ///   short.
    /// - Above it, up to [`HOP_Z`], the Taylor terms through y⁽⁸⁾, with
    ///   `c = q/6 + β/3` and `u = q t²`,
    ///
    ///   ```text
    ///   Y/t = 1 − t + t²·(c·(1 + u/20 + u²/840) − (q/12)·t·(1 + u/30 + u²/1680))
    ///   Y'  = 1 − 2t + 3c·t²·(1 + u/12 + u²/360) − (q/3)·t³·(1 + u/20 + u²/840)
    ///   ```
    ///
    ///   are solved by two Newton steps from the expansion of the root to
    ///   second order, `t ≈ 1 + δ + δ(2c − q/4) + cq/20 − q²/360` with
    ///   `δ = c − q/12`, whose error is about 0.2·e³: each step squares the
    ///   error and multiplies it by about e, leaving ~e¹⁵.
    ///
    /// About two thirds of the impacts of a sweep are such hops; the general
    /// walk costs several closed-form evaluations, a square root and a
    /// logarithm each.
    #[inline(always)]
    fn hop(&self, m: &Motion, s: f64, len: f64, max_abs_x: f64) -> Option<(f64, f64)> {
        let w = s * m.v_a;
        if !(m.x_a == 0.0 && w > 0.0) {
            return None;
        }
        let p2 = self.p * self.p;
        let a = p2 * s * m.u;
        let b = p2 * s * m.g1e;
        if a.is_nan() || a >= 0.0 {
            return None;
        }
        let r = 1.0 / a;
        let sigma0 = -2.0 * w * r;
        let beta = -(b * r) * sigma0;
        let z0 = self.p * sigma0;
        // On the hop ÿ ≤ a(1 − HOP_Z) + p²·y_max, so the apex is below
        // w²/(2|a|)·(1 + 4·HOP_Z) (the p²y part is z²/8 of a): it must stay
        // below max_abs_x.
        if !(z0 <= HOP_Z
            && beta.abs() <= HOP_Z
            && w * w * (1.0 + 4.0 * HOP_Z) < max_abs_x * (-2.0 * a))
        {
            return None;
        }
        let q = z0 * z0;
        let (t, v_ratio) = if q.max(beta.abs()) <= HOP_SERIES {
            hop_series(q, beta)
        } else {
            hop_newton(q, beta)
        };
        let sigma = sigma0 * t;
        if !(sigma > 0.0 && sigma < len) {
            return None;
        }
        Some((sigma, -s * w * v_ratio))
    }
}

/// A hop's return time `T = σ/σ₀` and speed ratio `V` to fifth order in
/// `q` and `β` (see [`Exact::hop`]): `Σ βʲ·Pⱼ(q)`, the `Pⱼ` independent of
/// each other and `β`'s powers paired, so that few operations depend on
/// one another. As `q = z² ≤ HOP_Z² = 1e-4` on a hop, the terms of `q⁴`
/// and `q³β²` and beyond (below 1e-19) are left out.
#[inline(always)]
fn hop_series(q: f64, beta: f64) -> (f64, f64) {
    let t0 = 1.0 + q * (1.0 / 12.0 + q * (1.0 / 80.0 + q * (1.0 / 448.0)));
    let t1 = 1.0 / 3.0 + q * (1.0 / 10.0 + q * (3.0 / 112.0 + q * (1.0 / 144.0)));
    let t2 = 2.0 / 9.0 + q * (7.0 / 60.0 + q * (47.0 / 1050.0));
    let t3 = 5.0 / 27.0 + q * (56.0 / 405.0 + q * (173.0 / 2520.0));
    let t4 = 14.0 / 81.0 + q * (1.0 / 6.0);
    let t5 = 14.0 / 81.0;
    let v1 = -1.0 / 3.0 - q * (1.0 / 20.0 + q * (1.0 / 112.0 + q * (1.0 / 576.0)));
    let v2 = -2.0 / 9.0 - q * (7.0 / 90.0 + q * (47.0 / 2100.0));
    let v3 = -5.0 / 27.0 - q * (14.0 / 135.0 + q * (173.0 / 4200.0));
    let v4 = -14.0 / 81.0 - q * (2.0 / 15.0);
    let v5 = -14.0 / 81.0;
    let b2 = beta * beta;
    let t = t0 + beta * ((t1 + beta * t2) + b2 * ((t3 + beta * t4) + b2 * t5));
    let v = 1.0 + beta * ((v1 + beta * v2) + b2 * ((v3 + beta * v4) + b2 * v5));
    (t, v)
}

/// A hop's `T` and `V` by two Newton steps on its Taylor terms through
/// y⁽⁸⁾ (see [`Exact::hop`]), for `max(q, |β|)` up to [`HOP_Z`].
#[inline(always)]
fn hop_newton(q: f64, beta: f64) -> (f64, f64) {
    let c = q * (1.0 / 6.0) + beta * (1.0 / 3.0);
    let q12 = q * (1.0 / 12.0);
    let d1 = c - q12;
    let mut t =
        1.0 + (d1 + d1 * (2.0 * c - 0.25 * q) + c * q * (1.0 / 20.0) - q * q * (1.0 / 360.0));
    for _ in 0..2 {
        let t2 = t * t;
        let u = q * t2;
        let f = (1.0 - t)
            + t2 * (c * (1.0 + u * (1.0 / 20.0 + u * (1.0 / 840.0)))
                - q12 * t * (1.0 + u * (1.0 / 30.0 + u * (1.0 / 1680.0))));
        let df = -1.0 + 2.0 * c * t * (1.0 + u * (1.0 / 10.0 + u * (1.0 / 280.0)))
            - q12 * t2 * (3.0 + u * (1.0 / 6.0 + u * (1.0 / 240.0)));
        t -= f / df;
    }
    let t2 = t * t;
    let u = q * t2;
    let ydot_w = (1.0 - 2.0 * t)
        + (3.0 * c * t2 * (1.0 + u * (1.0 / 12.0 + u * (1.0 / 360.0)))
            - 4.0 * q12 * t2 * t * (1.0 + u * (1.0 / 20.0 + u * (1.0 / 840.0))));
    (t, -ydot_w)
}

impl Exact {
    /// The floor of the stepper, for `rocking bench`: every whole interval
    /// of `exc` advanced by the closed form with the sign tests of
    /// [`Stepper::cruise`] (monotone, the pivot, the limit) but no event
    /// ever handled, from `x = s/2` at rest. Returns the final state and
    /// how many intervals the tests flagged (so that nothing is optimised
    /// away). The motion is unbounded, as the linearised equation is
    /// without impacts: the time is what matters.
    pub fn bare_pass(&self, exc: &super::Excitation, s: f64) -> (f64, f64, u64) {
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
    fn apex_below(&self, m: &Motion, s: f64, v_end: f64, g0: f64, g_end: f64, top: f64) -> bool {
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
    fn valley_above(&self, m: &Motion, s: f64, v_end: f64, g0: f64, g_end: f64) -> bool {
        let (w_a, y_a) = (s * m.v_a, s * m.x_a);
        if !(w_a < 0.0 && s * v_end > 0.0) {
            return false;
        }
        let e = self.p * self.p * (1.0 - (s * g0).min(s * g_end) * self.inv_eta);
        let dt = self.full.sigma;
        y_a + w_a * dt - 0.5 * e.max(0.0) * dt * dt > 1e-12
    }
}

/// Two `f64` lanes of one SSE2 register: the arithmetic of two runs at once,
/// each lane's operations the IEEE operations the scalar code does (no
/// fused multiply-add, nothing reassociated), so each lane's results are the
/// scalar ones to the bit.
#[cfg(target_arch = "x86_64")]
#[allow(unused_unsafe)] // the SSE2 intrinsics are safe to call from Rust 1.87 on
mod lanes {
    use std::arch::x86_64::*;
    use std::ops::{Add, BitAnd, BitOr, Mul, Not, Sub};

    #[derive(Clone, Copy)]
    pub struct F2(__m128d);

    /// A lane-wise comparison: all ones where it holds.
    #[derive(Clone, Copy)]
    pub struct M2(__m128d);

    impl F2 {
        #[inline(always)]
        pub fn new(a: f64, b: f64) -> F2 {
            F2(unsafe { _mm_setr_pd(a, b) })
        }
        #[inline(always)]
        pub fn splat(x: f64) -> F2 {
            F2(unsafe { _mm_set1_pd(x) })
        }
        #[inline(always)]
        pub fn lanes(self) -> [f64; 2] {
            let mut out = [0.0; 2];
            unsafe { _mm_storeu_pd(out.as_mut_ptr(), self.0) };
            out
        }
        #[inline(always)]
        pub fn abs(self) -> F2 {
            F2(unsafe { _mm_andnot_pd(_mm_set1_pd(-0.0), self.0) })
        }
        #[inline(always)]
        pub fn lt(self, o: F2) -> M2 {
            M2(unsafe { _mm_cmplt_pd(self.0, o.0) })
        }
        #[inline(always)]
        pub fn gt(self, o: F2) -> M2 {
            M2(unsafe { _mm_cmpgt_pd(self.0, o.0) })
        }
        /// `self.max(o)` lane by lane, for operands that are not NaN and
        /// not both zero (where `f64::max` and `maxpd` may differ).
        #[inline(always)]
        pub fn max(self, o: F2) -> F2 {
            F2(unsafe { _mm_max_pd(self.0, o.0) })
        }
    }

    impl M2 {
        /// Bit i set where lane i holds.
        #[inline(always)]
        pub fn bits(self) -> i32 {
            unsafe { _mm_movemask_pd(self.0) }
        }
    }

    /// `impl $trait for $ty` by the lane-wise intrinsic `$op`.
    macro_rules! lane_wise {
        ($($trait:ident, $method:ident, $ty:ident, $op:ident;)*) => {$(
            impl $trait for $ty {
                type Output = $ty;
                #[inline(always)]
                fn $method(self, o: $ty) -> $ty {
                    $ty(unsafe { $op(self.0, o.0) })
                }
            }
        )*};
    }
    lane_wise! {
        Add, add, F2, _mm_add_pd;
        Sub, sub, F2, _mm_sub_pd;
        Mul, mul, F2, _mm_mul_pd;
        BitAnd, bitand, M2, _mm_and_pd;
        BitOr, bitor, M2, _mm_or_pd;
    }
    impl Not for M2 {
        type Output = M2;
        #[inline(always)]
        fn not(self) -> M2 {
            M2(unsafe { _mm_xor_pd(self.0, _mm_castsi128_pd(_mm_set1_epi32(-1))) })
        }
    }
}

/// [`Stepper::cruise`] for two runs at once, steppers of the same `p` and
/// `dt` (two values of η), both rocking at sample `k`: their whole
/// intervals, one lane each, for as long as both are proved eventless by
/// sign tests alone (x monotone, between the pivot and the limit). Stops
/// at the first interval either must leave to `cruise`'s other bounds or
/// to `rock` (the other is left there too, and crosses it on its own) and
/// returns it. Each lane does what [`Exact::cruise`] does, operation for
/// operation.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn cruise_pair(
    steppers: [&Exact; 2],
    exc: &super::Excitation,
    mut k: usize,
    states: [&mut Rocking; 2],
    tops: [&mut f64; 2],
) -> usize {
    use lanes::F2;
    let [sa, sb] = steppers;
    if exc.dt_s != sa.full.sigma || sa.p != sb.p || sa.full.sigma != sb.full.sigma {
        return k;
    }
    let [st_a, st_b] = states;
    let [top_a, top_b] = tops;
    let (psi, slope) = (&exc.psi[..], &exc.slope[..]);
    let n = slope.len().min(psi.len()).min(exc.psi_end().len());
    let full = &sa.full;
    let (p, c, s_sigma, s1_sigma, sinh, delta_max) = (
        F2::splat(sa.p),
        F2::splat(full.c),
        F2::splat(full.s_sigma),
        F2::splat(full.s1_sigma),
        F2::splat(full.sinh),
        F2::splat(sa.full_expm1),
    );
    let (zero, two) = (F2::splat(0.0), F2::splat(2.0));
    let s = F2::new(st_a.s, st_b.s);
    let s_eta = s * F2::new(sa.eta, sb.eta);
    let inv_eta = F2::new(sa.inv_eta, sb.inv_eta);
    let limit = F2::new(sa.limit, sb.limit);
    let (mut x, mut v) = (F2::new(st_a.x, st_b.x), F2::new(st_a.v, st_b.v));
    let mut top = F2::new(*top_a, *top_b);
    while k < n {
        let (g0, g1) = (psi[k], slope[k]);
        // `Exact::motion`, `Motion::at` and `Motion::monotone`, lane-wise.
        let u = x + (F2::splat(g0) - s_eta) * inv_eta;
        let g1e = F2::splat(g1) * inv_eta;
        let x_hi = x + u * c + v * s_sigma + g1e * s1_sigma;
        let pu = p * u;
        let v_hi = v + pu * sinh + (v + g1e) * c;
        let y_hi = s * x_hi;
        let inside = y_hi.lt(limit) & y_hi.gt(zero);
        let b = pu + v;
        let a = b + g1e;
        let vertex_inside = (a * b).lt(zero) & b.abs().lt(a.abs() * delta_max) & (a * v).gt(zero);
        let turn_free = !vertex_inside | (b * b - a * (two * v)).lt(zero);
        // A lane with a turning point inside (or an event) leaves the pair
        // to cross that interval on its own, by `cruise`'s other bounds or
        // `rock`: kept out of this loop, they would crowd its registers.
        if (inside & (v * v_hi).gt(zero) & turn_free).bits() != 0b11 {
            break;
        }
        // y_hi lies in (0, limit) on both lanes: `max` is `f64::max` there.
        top = top.max(y_hi);
        (x, v) = (x_hi, v_hi);
        k += 1;
    }
    let ([xa, xb], [va, vb], [ta, tb]) = (x.lanes(), v.lanes(), top.lanes());
    (st_a.x, st_a.v, st_b.x, st_b.v) = (xa, va, xb, vb);
    (*top_a, *top_b) = (ta, tb);
    k
}

impl Stepper for Exact {
    fn set_limit(&mut self, limit: f64) {
        self.limit = limit;
    }

    /// Whole intervals while the motion is provably monotone and stays
    /// strictly between the pivot and the limit: the arithmetic of `rock`'s
    /// first branch, without leaving the loop.
    #[inline(always)]
    fn cruise(
        &mut self,
        exc: &super::Excitation,
        mut k: usize,
        end: usize,
        state: &mut Rocking,
        max_abs_x: &mut f64,
    ) -> usize {
        if exc.dt_s != self.full.sigma {
            return k;
        }
        let (psi, psi_end, slope, s) = (&exc.psi[..], exc.psi_end(), &exc.slope[..], state.s);
        let (mut x, mut v, mut top) = (state.x, state.v, *max_abs_x);
        let n = slope.len().min(psi.len()).min(psi_end.len()).min(end);
        while k < n {
            let (g0, g_end, g1) = (psi[k], psi_end[k], slope[k]);
            let m = self.motion(x, v, s, g0, g1);
            let (x_hi, v_hi) = m.at(&self.full);
            let y_hi = s * x_hi;
            let inside = (y_hi < self.limit) & (y_hi > 0.0);
            let monotone = inside & m.monotone(v_hi, self.full_expm1);
            if !(monotone
                || inside
                    && (self.apex_below(&m, s, v_hi, g0, g_end, top)
                        || self.valley_above(&m, s, v_hi, g0, g_end)))
            {
                break;
            }
            top = top.max(y_hi);
            (x, v) = (x_hi, v_hi);
            k += 1;
        }
        *state = Rocking { x, v, s };
        *max_abs_x = top;
        k
    }

    #[allow(clippy::needless_range_loop)] // pieces end at turns[i], or at len for the last
    #[inline(always)]
    fn rock(&mut self, st: Stretch, state: &mut Rocking, max_abs_x: &mut f64) -> StretchEnd {
        let s = state.s;
        let m = self.motion(state.x, state.v, s, st.g_a, st.g1);
        if let Some((sigma, v)) = self.hop(&m, s, st.len, *max_abs_x) {
            return StretchEnd::Impact { sigma, v };
        }
        let whole = st.tau0 == 0.0 && st.len == self.full.sigma;
        let c_end = if whole {
            self.full
        } else {
            Coeffs::new(self.p, st.len)
        };
        let end = m.at(&c_end);
        // δ = e^{pσ} − 1 on the stretch is below e^{p·dt} − 1 when the stretch
        // lies in one interval (the free rocking after the record is longer).
        let delta_max = if st.len <= self.full.sigma {
            self.full_expm1
        } else {
            (self.p * st.len).exp_m1()
        };
        // Turning points, unless sign tests exclude them: the common case, x
        // monotone.
        let (turns, n_turns) = if m.monotone(end.1, delta_max) {
            ([f64::NAN; 2], 0)
        } else {
            m.turning_points(st.len, delta_max)
        };
        // Walk the monotone pieces [0, t1], [t1, t2], [t2, len].
        let (mut lo, mut at_lo) = (0.0, (state.x, state.v));
        for i in 0..=n_turns {
            let (hi, at_hi) = if i < n_turns {
                (turns[i], m.at(&Coeffs::new(self.p, turns[i])))
            } else {
                (st.len, end)
            };
            let y_hi = s * at_hi.0;
            if y_hi >= self.limit {
                let (sigma, v) = self.locate(&m, s, self.limit, (lo, at_lo), (hi, at_hi), true);
                *max_abs_x = max_abs_x.max(self.limit);
                *state = Rocking {
                    x: s * self.limit,
                    v,
                    s,
                };
                return StretchEnd::Overturn { sigma };
            }
            if y_hi <= 0.0 {
                if s * at_lo.0 <= 0.0 {
                    // Never left the pivot (a departure swamped by rounding):
                    // it settles, with no impact and no speed to carry over.
                    return StretchEnd::Settled { sigma: hi };
                }
                let (sigma, v) = self.locate(&m, s, 0.0, (lo, at_lo), (hi, at_hi), false);
                return StretchEnd::Impact { sigma, v };
            }
            *max_abs_x = max_abs_x.max(y_hi);
            (lo, at_lo) = (hi, at_hi);
        }
        *state = Rocking {
            x: end.0,
            v: end.1,
            s,
        };
        StretchEnd::End
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_functions_keep_relative_precision() {
        // Against their Taylor series, truncated where the next term is below
        // 1e-17 relative for these z: cosh z − 1 = z²/2 (1 + z²/12 + z⁴/360 + z⁶/20160),
        // sinh z / z − 1 = z²/6 (1 + z²/20 + z⁴/840 + z⁶/60480).
        for z in [1e-12f64, 1e-8, 1e-4, 1e-2] {
            let z2 = z * z;
            let c_ref = z2 / 2.0 * (1.0 + z2 / 12.0 * (1.0 + z2 / 30.0 * (1.0 + z2 / 56.0)));
            let s_ref = z2 / 6.0 * (1.0 + z2 / 20.0 * (1.0 + z2 / 42.0 * (1.0 + z2 / 72.0)));
            assert!((cosh_m1(z) / c_ref - 1.0).abs() < 4e-16, "{z}");
            assert!((sinhc_m1(z) / s_ref - 1.0).abs() < 4e-16, "{z}");
        }
        // The series branch agrees with the direct formula where they meet
        // (the direct one is accurate there: it loses only 1 − 1/1.04 of a digit).
        for z in [0.49999f64, 0.3, 0.1] {
            let direct = z.sinh() / z - 1.0;
            assert!((sinhc_m1(z) - direct).abs() < 1e-14, "{z}");
        }
    }

    /// One step against a fine RK4 integration of the same ODE (an
    /// independent method): the closed form must agree to RK4's own error.
    #[test]
    fn step_matches_numerical_integration() {
        let (p, eta, s) = (2.5, 0.3, -1.0);
        let (x0, v0, g_a, g1) = (-0.2, 0.7, -0.25, 8.0);
        let len = 0.05;
        let lin = Exact::new(p, eta, len, 1.0);
        let m = Motion {
            p,
            x_a: x0,
            v_a: v0,
            u: x0 + (g_a - s * eta) / eta,
            g1e: g1 / eta,
        };
        let (x, v) = m.at(&lin.full);
        let f = |t: f64, x: f64| p * p * (x - s) + p * p / eta * (g_a + g1 * t);
        let (mut xr, mut vr) = (x0, v0);
        let n = 20000;
        let h = len / n as f64;
        for i in 0..n {
            let t = i as f64 * h;
            let (k1x, k1v) = (vr, f(t, xr));
            let (k2x, k2v) = (vr + 0.5 * h * k1v, f(t + 0.5 * h, xr + 0.5 * h * k1x));
            let (k3x, k3v) = (vr + 0.5 * h * k2v, f(t + 0.5 * h, xr + 0.5 * h * k2x));
            let (k4x, k4v) = (vr + h * k3v, f(t + h, xr + h * k3x));
            xr += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            vr += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
        // RK4 with h = 2.5e-6 s: truncation ~ (ph)⁴ ≈ 1e-21 per step; rounding dominates (~1e-13).
        assert!((x - xr).abs() < 1e-12, "{x} vs {xr}");
        assert!((v - vr).abs() < 1e-11, "{v} vs {vr}");
    }

    #[test]
    fn tiny_motions_keep_relative_precision() {
        // Just past uplift: x_a = v_a = 0, forcing exactly at the threshold
        // and rising. x(σ) ≈ (g1/η) p² σ³/6 to leading order.
        let (p, eta) = (3.0, 0.5);
        let g1 = 1e-12 / 0.01; // a 1e-12 excess over one 0.01 s interval
        let m = Motion {
            p,
            x_a: 0.0,
            v_a: 0.0,
            u: 0.0,
            g1e: g1 / eta,
        };
        let sigma = 0.01;
        let (x, v) = m.at(&Coeffs::new(p, sigma));
        let z: f64 = p * sigma;
        let x_ref = g1 / eta * sigma * (z.sinh() / z - 1.0); // exact; here z²/6 dominates
        let x_series = g1 / eta * sigma * z * z / 6.0
            * (1.0 + z * z / 20.0 + z.powi(4) / 840.0 + z.powi(6) / 60480.0);
        assert!(x > 0.0);
        assert!(
            (x / x_series - 1.0).abs() < 1e-14,
            "{x} vs {x_series} (naive {x_ref})"
        );
        let v_series =
            g1 / eta * z * z / 2.0 * (1.0 + z * z / 12.0 + z.powi(4) / 360.0 + z.powi(6) / 20160.0);
        assert!((v / v_series - 1.0).abs() < 1e-14, "{v} vs {v_series}");
    }

    #[test]
    fn turning_points_are_where_velocity_vanishes() {
        let (p, eta, s) = (4.0, 0.4, 1.0);
        // Moving out, decelerating: one maximum inside.
        let m = Motion {
            p,
            x_a: 0.1,
            v_a: 0.5,
            u: 0.1 + (0.1 - s * eta) / eta,
            g1e: -3.0 / eta,
        };
        let (t, n) = m.turning_points(1.0, 4.0f64.exp_m1());
        assert_eq!(n, 1);
        let (_, v) = m.at(&Coeffs::new(p, t[0]));
        assert!(v.abs() < 1e-14, "{v}");
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

    /// A hop solved by its series against the general walk (the closed form,
    /// turning point and safeguarded Newton), from hops near the series'
    /// limit (where a wrong low-order coefficient would show at z² ≈ 1e-6)
    /// down to the rest tolerance.
    #[test]
    fn hops_by_series_match_the_general_walk() {
        let mut solved = 0;
        for p in [0.5, 2.0, 8.0] {
            for eta in [0.2, 0.6] {
                for s in [1.0, -1.0] {
                    for g_rel in [-0.9, 0.0, 0.7] {
                        for g1 in [0.0, 0.3, -2.0] {
                            for w_rel in [2e-3, 4e-4, 1e-5, 1e-9] {
                                let (g_a, w) = (s * g_rel * eta, w_rel * p);
                                let lin = Exact::new(p, eta, 0.02, 1.0);
                                let m = Motion {
                                    p,
                                    x_a: 0.0,
                                    v_a: s * w,
                                    u: (g_a - s * eta) / eta,
                                    g1e: g1 / eta,
                                };
                                let Some((sigma, v)) = lin.hop(&m, s, 0.015, 1.0) else {
                                    continue;
                                };
                                solved += 1;
                                let mut st = Rocking {
                                    x: 0.0,
                                    v: s * w,
                                    s,
                                };
                                // max |x| = 0: the series refuses, the general walk runs.
                                let stretch = Stretch {
                                    tau0: 0.005,
                                    len: 0.015,
                                    g_a,
                                    g1,
                                };
                                let StretchEnd::Impact {
                                    sigma: s_ref,
                                    v: v_ref,
                                } = lin.clone().rock(stretch, &mut st, &mut 0.0)
                                else {
                                    panic!("no impact: p {p} η {eta} g {g_a} g1 {g1} w {w}");
                                };
                                let case = format!("p {p} η {eta} s {s} g {g_a} g1 {g1} w {w}");
                                assert!(
                                    (sigma / s_ref - 1.0).abs() < 1e-13,
                                    "{case}: σ {sigma} vs {s_ref}"
                                );
                                assert!(
                                    (v / v_ref - 1.0).abs() < 1e-13,
                                    "{case}: v {v} vs {v_ref}"
                                );
                            }
                        }
                    }
                }
            }
        }
        assert!(solved > 100, "only {solved} hops solved by series");
    }

    /// Hops against the closed-form solution of `ÿ = p²y + a + bσ` from
    /// `y = 0, ẏ = w`, `y = (w/p)·sinh pσ + (a/p²)(cosh pσ − 1) + (b/p³)(sinh pσ − pσ)`,
    /// whose return to `y = 0` and speed there were solved with mpmath at
    /// 40 digits (an independent method): to a few ulps, by the series
    /// (`e` up to [`HOP_SERIES`], near its edge with both `q` and `β` of
    /// either sign) and by Newton, on both pivots.
    #[test]
    #[allow(clippy::excessive_precision)] // mpmath's 20 digits, as printed
    fn hops_match_the_closed_form_to_rounding() {
        // p, s, v_a, u, g1e; then σ and v at the return (mpmath).
        let cases: [(f64, f64, f64, f64, f64, f64, f64); 5] = [
            (
                2.0,
                1.0,
                0.004,
                -0.75,
                0.5,
                0.002_668_255_123_772_262_9,
                -0.003_997_626_805_991_231_4,
            ),
            (
                2.0,
                -1.0,
                -0.007,
                0.75,
                -1.0,
                0.004_676_420_170_177_663_6,
                0.006_985_420_750_850_105_4,
            ),
            (
                0.5,
                1.0,
                1e-9,
                -0.9,
                -3.0,
                8.888_888_801_097_395_8e-9,
                -1.000_000_009_876_543_1e-9,
            ),
            (
                8.0,
                -1.0,
                -0.02,
                0.6,
                5.0,
                0.001_038_675_868_378_032,
                0.020_057_538_470_295_825,
            ),
            // q = 9.0e-5, β = −1.9e-3: the series' fifth-order terms count.
            (
                8.0,
                1.0,
                0.0228,
                -0.6,
                -0.96,
                0.001_186_757_778_592_257_873_6,
                -0.022_814_421_933_150_636_78,
            ),
        ];
        let mut newton = 0;
        for (p, s, v_a, u, g1e, sigma_ref, v_ref) in cases {
            let lin = Exact::new(p, 0.5, 0.02, 1.0);
            let m = Motion {
                p,
                x_a: 0.0,
                v_a,
                u,
                g1e,
            };
            let (sigma, v) = lin.hop(&m, s, 0.02, 1.0).expect("a hop");
            assert!(
                (sigma / sigma_ref - 1.0).abs() < 1e-15,
                "p {p}: σ {sigma} vs {sigma_ref}"
            );
            assert!((v / v_ref - 1.0).abs() < 2e-15, "p {p}: v {v} vs {v_ref}");
            let sigma0 = 2.0 * v_a.abs() / (p * p * u.abs());
            let e = (p * sigma0).powi(2).max((g1e / u * sigma0).abs());
            newton += usize::from(e > HOP_SERIES);
        }
        assert_eq!(newton, 2, "both branches are exercised");
    }

    /// The hop's two solutions, the double series and Newton on the Taylor
    /// terms (derived separately), agree to rounding wherever the series
    /// is used (`q ≤ HOP_Z²`, `|β| ≤ HOP_SERIES`): a fifth-order
    /// coefficient wrong by 10 % would show at its edges (0.17·β⁵ = 5e-15
    /// there).
    #[test]
    fn hop_series_agrees_with_newton_where_it_is_used() {
        let steps = [-1.0, -0.7, -0.3, -1e-2, 0.0, 1e-3, 0.2, 0.5, 0.9, 1.0];
        for fq in steps.iter().map(|f: &f64| f.abs()) {
            for fb in steps {
                let (q, beta) = (fq * HOP_Z * HOP_Z, fb * HOP_SERIES);
                let (t, v) = hop_series(q, beta);
                let (t_n, v_n) = hop_newton(q, beta);
                assert!((t - t_n).abs() <= 4e-16, "q {q} β {beta}: T {t} vs {t_n}");
                assert!((v - v_n).abs() <= 4e-16, "q {q} β {beta}: V {v} vs {v_n}");
            }
        }
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
