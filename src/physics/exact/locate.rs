//! Event location on a monotone piece of a stretch: the first instant the
//! closed form reaches a target (the pivot or the overturning limit), by
//! safeguarded Newton from a Taylor guess, to a few ulps.

use super::closed_form::{Coeffs, Motion};
use super::stepper::Exact;

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

impl Exact {
    /// The first σ in (lo, hi] where `y(σ) = s·x(σ)` reaches `target`, given
    /// `y(lo)` short of it, `y(hi)` on or past it and `y` monotone between.
    /// Returns σ on the far side, within a few ulps of the crossing (so the
    /// event condition holds there), and the velocity there.
    /// `(lo, (x, v) at lo)` and `(hi, (x, v) at hi)` bracket the crossing.
    #[inline(always)]
    pub(super) fn locate(
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
        let mut at = self.first_guess(m, s, (lo, (x_lo, v_lo)), hi, g_lo);
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
        // Newton converged from one side only.
        self.close_bracket(m, s, target, rising, lo, (hi, v_hi), at)
    }

    /// The first guess of [`Exact::locate`] in `(lo, hi)`, from the Taylor
    /// parabola at `lo`: a piece that starts at a turning point (a Zeno swing
    /// of 1e-9 s inside a 0.01 s interval, say) is found at once instead of
    /// by ~30 halvings. One Newton step on the cubic Taylor polynomial then
    /// takes the jerk into account, so that Newton on the motion itself
    /// starts within O(τ⁴) and usually needs one step. `g_lo` is
    /// `s·x(lo) − target`.
    #[inline(always)]
    fn first_guess(
        &self,
        m: &Motion,
        s: f64,
        (lo, (x_lo, v_lo)): (f64, (f64, f64)),
        hi: f64,
        g_lo: f64,
    ) -> f64 {
        let (y1, y2) = (s * v_lo, s * m.acc(x_lo, lo));
        let mut tau = first_positive_root(0.5 * y2, y1, g_lo);
        let y3 = s * self.p * self.p * (v_lo + m.g1e);
        let slope = y1 + tau * (y2 + 0.5 * y3 * tau);
        let cubic = tau - (g_lo + tau * (y1 + tau * (0.5 * y2 + tau * y3 / 6.0))) / slope;
        if cubic > 0.0 && cubic < hi - lo {
            tau = cubic;
        }
        let guess = lo + tau;
        if guess > lo && guess < hi {
            guess
        } else {
            0.5 * (lo + hi)
        }
    }

    /// The end of [`Exact::locate`] when Newton converged from one side
    /// only (at `at`, with the crossing in `(lo, hi]`): closes the bracket by
    /// walking away from the last iterate in steps doubling from one ulp,
    /// so that the returned point is within a few ulps of the crossing.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn close_bracket(
        &self,
        m: &Motion,
        s: f64,
        target: f64,
        rising: bool,
        mut lo: f64,
        (mut hi, mut v_hi): (f64, f64),
        at: f64,
    ) -> (f64, f64) {
        let reached = |y: f64| if rising { y >= target } else { y <= target };
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
