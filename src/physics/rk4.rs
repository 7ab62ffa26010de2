//! Baseline: classical fixed-step RK4, events by linear interpolation.
//!
//! What a user would write first: `substeps` equal RK4 steps per sample
//! interval, an impact or overturning detected when `x` changes side at a
//! step's end and placed by linear interpolation between the two step ends,
//! |x|max from the step ends. It exists to be measured against in the
//! benchmarks, not to be used for results.

use super::equation::Rhs;
use super::step::{Rocking, Stepper, Stretch, StretchEnd};

/// The RK4 stepper of one equation; one per run.
pub struct Rk4<R> {
    rhs: R,
    h: f64,
    limit: f64,
}

impl<R: Rhs> Rk4<R> {
    pub fn new(rhs: R, dt: f64, substeps: u32, limit: f64) -> Self {
        Rk4 {
            rhs,
            h: dt / substeps as f64,
            limit,
        }
    }
}

impl<R: Rhs> Stepper for Rk4<R> {
    fn set_limit(&mut self, limit: f64) {
        self.limit = limit;
    }

    fn rock(&mut self, st: Stretch, state: &mut Rocking, max_abs_x: &mut f64) -> StretchEnd {
        let s = state.s;
        let rhs = self.rhs;
        let f = |sigma: f64, x: f64| rhs.accel(s, x, st.g_a + st.g1 * sigma);
        let (mut x, mut v) = (state.x, state.v);
        let mut sigma = 0.0;
        while sigma < st.len {
            let h = self.h.min(st.len - sigma);
            let (k1x, k1v) = (v, f(sigma, x));
            let (k2x, k2v) = (v + 0.5 * h * k1v, f(sigma + 0.5 * h, x + 0.5 * h * k1x));
            let (k3x, k3v) = (v + 0.5 * h * k2v, f(sigma + 0.5 * h, x + 0.5 * h * k2x));
            let (k4x, k4v) = (v + h * k3v, f(sigma + h, x + h * k3x));
            let xn = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            let vn = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            let (ya, yb) = (s * x, s * xn);
            let cross = |target: f64| {
                let frac = ((target - ya) / (yb - ya)).clamp(0.0, 1.0);
                (sigma + frac * h, v + frac * (vn - v))
            };
            if yb >= self.limit {
                let (sig, ve) = cross(self.limit);
                *max_abs_x = max_abs_x.max(self.limit);
                *state = Rocking {
                    x: s * self.limit,
                    v: ve,
                    s,
                };
                return StretchEnd::Overturn { sigma: sig };
            }
            if yb <= 0.0 {
                let (sig, ve) = cross(0.0);
                // Keep time moving even if the crossing interpolates to the step start.
                let sig = if sig > 0.0 { sig } else { sigma + h };
                return StretchEnd::Impact { sigma: sig, v: ve };
            }
            *max_abs_x = max_abs_x.max(yb);
            x = xn;
            v = vn;
            sigma += h;
        }
        *state = Rocking { x, v, s };
        StretchEnd::End
    }
}
