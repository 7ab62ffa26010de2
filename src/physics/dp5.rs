//! The DP5 integrator: Dormand–Prince 5(4) for either equation's
//! right-hand side ([`Rhs`]); the tool uses it for the nonlinear equation
//! (paper Eq. 7).
//!
//! Explicit Runge–Kutta of order 5 with an embedded order-4 error estimate,
//! first-same-as-last, and Shampine's continuous extension ("dense output")
//! as in Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations
//! I*, 2nd ed., §II.5 and §II.6 (code DOPRI5). Steps never cross a sample of
//! the record, so the kinks of the linearly interpolated forcing fall on step
//! boundaries and the method keeps its order.
//!
//! Error control: mixed per component, `atol + rtol·|y|`, with
//! `atol = 10⁻³·rtol` for x (which is O(1) near overturning) and `p` times
//! that for ẋ. Events are found from the signs at step ends and at the
//! interior turning points (from the dense output of ẋ), located on the
//! dense output by the Illinois method, and the state at the event is then
//! recomputed by one exact-length step from the step's start.

use super::equation::Rhs;
use super::step::{Rocking, Stepper, Stretch, StretchEnd};

// Dormand–Prince 5(4) tableau (Hairer–Nørsett–Wanner, Table II.5.2).
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
// Error coefficients b − b̂.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
// Dense output (DOPRI5's CONTD5).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

type Y = [f64; 2];

#[inline]
fn axpy(y: Y, h: f64, terms: &[(f64, Y)]) -> Y {
    let mut out = y;
    for &(a, k) in terms {
        out[0] += h * a * k[0];
        out[1] += h * a * k[1];
    }
    out
}

/// An equation's right-hand side on pivot `s` over a stretch with `ψ̈ = g_a + g1 σ`.
#[derive(Debug, Clone, Copy)]
pub struct Pivoted<R> {
    pub rhs: R,
    pub s: f64,
    pub g_a: f64,
    pub g1: f64,
}

impl<R: Rhs> Pivoted<R> {
    #[inline]
    pub fn eval(&self, sigma: f64, y: Y) -> Y {
        [
            y[1],
            self.rhs.accel(self.s, y[0], self.g_a + self.g1 * sigma),
        ]
    }
}

/// One accepted step with what is needed to interpolate inside it.
struct Step {
    sigma0: f64,
    h: f64,
    y0: Y,
    y1: Y,
    k1: Y,
    /// Dense-output coefficients r2..r5 (r1 = y0).
    r: [Y; 4],
}

impl Step {
    #[inline]
    #[allow(clippy::needless_range_loop)] // two components, indexed alike
    fn at(&self, sigma: f64) -> Y {
        let th = (sigma - self.sigma0) / self.h;
        let th1 = 1.0 - th;
        let mut out = [0.0; 2];
        for i in 0..2 {
            out[i] = self.y0[i]
                + th * (self.r[0][i]
                    + th1 * (self.r[1][i] + th * (self.r[2][i] + th1 * self.r[3][i])));
        }
        out
    }
}

/// Takes one DP5 step of size `h` from `(sigma, y)` with `k1 = f(sigma, y)`.
/// Returns the new state, `k7 = f(sigma + h, y_new)`, the error estimate
/// vector and the stages needed for dense output.
#[inline]
fn dp5_step<R: Rhs>(f: &Pivoted<R>, sigma: f64, y: Y, k1: Y, h: f64) -> (Y, Y, Y, [Y; 5]) {
    let k2 = f.eval(sigma + C2 * h, axpy(y, h, &[(A21, k1)]));
    let k3 = f.eval(sigma + C3 * h, axpy(y, h, &[(A31, k1), (A32, k2)]));
    let k4 = f.eval(
        sigma + C4 * h,
        axpy(y, h, &[(A41, k1), (A42, k2), (A43, k3)]),
    );
    let k5 = f.eval(
        sigma + C5 * h,
        axpy(y, h, &[(A51, k1), (A52, k2), (A53, k3), (A54, k4)]),
    );
    let k6 = f.eval(
        sigma + h,
        axpy(
            y,
            h,
            &[(A61, k1), (A62, k2), (A63, k3), (A64, k4), (A65, k5)],
        ),
    );
    let y1 = axpy(
        y,
        h,
        &[(A71, k1), (A73, k3), (A74, k4), (A75, k5), (A76, k6)],
    );
    let k7 = f.eval(sigma + h, y1);
    let err = axpy(
        [0.0; 2],
        h,
        &[(E1, k1), (E3, k3), (E4, k4), (E5, k5), (E6, k6), (E7, k7)],
    );
    (y1, k7, err, [k3, k4, k5, k6, k7])
}

fn dense(sigma0: f64, h: f64, y0: Y, y1: Y, k1: Y, ks: [Y; 5]) -> Step {
    let [k3, k4, k5, k6, k7] = ks;
    let mut r = [[0.0; 2]; 4];
    for i in 0..2 {
        let ydiff = y1[i] - y0[i];
        let bspl = h * k1[i] - ydiff;
        r[0][i] = ydiff;
        r[1][i] = bspl;
        r[2][i] = ydiff - h * k7[i] - bspl;
        r[3][i] = h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
    }
    Step {
        sigma0,
        h,
        y0,
        y1,
        k1,
        r,
    }
}

/// Root of `g` in (lo, hi] with `g(lo)` and `g(hi)` of opposite signs (or
/// `g(hi) = 0`), by the Illinois variant of regula falsi; returns the end
/// where `g` has the sign of `g(hi)` (or is zero).
fn illinois(g: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let (mut glo, mut ghi) = (g(lo), g(hi));
    if ghi == 0.0 {
        return hi;
    }
    let mut side = 0;
    for _ in 0..200 {
        if hi - lo <= 4.0 * f64::EPSILON * hi.abs().max(f64::MIN_POSITIVE) {
            break;
        }
        let mut m = (lo * ghi - hi * glo) / (ghi - glo);
        if !(m > lo && m < hi) {
            m = 0.5 * (lo + hi);
        }
        let gm = g(m);
        if gm == 0.0 {
            return m;
        }
        if (gm > 0.0) == (ghi > 0.0) {
            hi = m;
            ghi = gm;
            if side == 1 {
                glo *= 0.5;
            }
            side = 1;
        } else {
            lo = m;
            glo = gm;
            if side == -1 {
                ghi *= 0.5;
            }
            side = -1;
        }
    }
    hi
}

/// The DP5 stepper of one equation; one per run.
pub struct Dp5<R> {
    rhs: R,
    p: f64,
    rtol: f64,
    atol: f64,
    limit: f64,
    /// Step size carried from one stretch to the next.
    h: f64,
    /// Accepted and rejected steps so far (for benchmarks).
    pub steps: u64,
}

impl<R: Rhs> Dp5<R> {
    pub fn new(rhs: R, p: f64, rtol: f64, limit: f64) -> Self {
        Dp5 {
            rhs,
            p,
            rtol,
            atol: 1e-3 * rtol,
            limit,
            h: 0.0,
            steps: 0,
        }
    }

    fn pivoted(&self, s: f64, g_a: f64, g1: f64) -> Pivoted<R> {
        Pivoted {
            rhs: self.rhs,
            s,
            g_a,
            g1,
        }
    }

    #[inline]
    fn error_norm(&self, y0: Y, y1: Y, err: Y) -> f64 {
        let sx = self.atol + self.rtol * y0[0].abs().max(y1[0].abs());
        let sv = self.p * self.atol + self.rtol * y0[1].abs().max(y1[1].abs());
        let (ex, ev) = (err[0] / sx, err[1] / sv);
        (0.5 * (ex * ex + ev * ev)).sqrt()
    }

    /// Checks an accepted step for events; `None` if there is none.
    ///
    /// The step is cut at its interior turning point (if the dense output of
    /// ẋ changes sign) into pieces on which `y = s·x` is monotone; the first
    /// piece whose end reaches the limit or the pivot holds the event.
    fn event_in(&self, f: &Pivoted<R>, st: &Step, max_abs_x: &mut f64) -> Option<(StretchEnd, Y)> {
        let s = f.s;
        let (sa, sb) = (st.sigma0, st.sigma0 + st.h);
        let y_of = |sig: f64| s * st.at(sig)[0];
        let w_of = |sig: f64| s * st.at(sig)[1];
        let (wa, wb) = (s * st.y0[1], s * st.y1[1]);
        let mut pieces = [(sa, s * st.y0[0], sb, s * st.y1[0]); 2];
        let mut n = 1;
        if (wa > 0.0 && wb < 0.0) || (wa < 0.0 && wb > 0.0) {
            let t = illinois(w_of, sa, sb);
            if t > sa && t < sb {
                let yt = y_of(t);
                pieces = [(sa, s * st.y0[0], t, yt), (t, yt, sb, s * st.y1[0])];
                n = 2;
            }
        }
        let mut event = None;
        for &(lo, y_lo, hi, y_hi) in &pieces[..n] {
            if y_hi >= self.limit {
                event = Some((illinois(|q| y_of(q) - self.limit, lo, hi), true));
                break;
            }
            if y_hi <= 0.0 {
                if y_lo <= 0.0 {
                    // A departure swamped by rounding: it never left the pivot.
                    return Some((StretchEnd::Settled { sigma: hi }, [0.0, 0.0]));
                }
                event = Some((illinois(y_of, lo, hi), false));
                break;
            }
            *max_abs_x = max_abs_x.max(y_hi);
        }
        let (sig, overturn) = event?;
        // Recompute the state at the event by one exact-length step.
        let h = sig - sa;
        let y = if h > 0.0 {
            dp5_step(f, sa, st.y0, st.k1, h).0
        } else {
            st.y0
        };
        Some(if overturn {
            *max_abs_x = max_abs_x.max(self.limit);
            (StretchEnd::Overturn { sigma: sig }, [s * self.limit, y[1]])
        } else {
            (
                StretchEnd::Impact {
                    sigma: sig,
                    v: y[1],
                },
                y,
            )
        })
    }
}

impl<R: Rhs> Stepper for Dp5<R> {
    fn set_limit(&mut self, limit: f64) {
        self.limit = limit;
    }

    fn rock(&mut self, stretch: Stretch, state: &mut Rocking, max_abs_x: &mut f64) -> StretchEnd {
        let f = self.pivoted(state.s, stretch.g_a, stretch.g1);
        let len = stretch.len;
        let mut sigma = 0.0;
        let mut y: Y = [state.x, state.v];
        let mut k1 = f.eval(0.0, y);
        if self.h <= 0.0 {
            self.h = (0.01 / self.p).min(len);
        }
        let h_min = 1e-14 * (1.0 / self.p);
        while sigma < len {
            let remaining = len - sigma;
            let wanted = self.h;
            let mut h = wanted.min(remaining);
            // Avoid a sliver of a last step.
            if remaining - h < 0.01 * h {
                h = remaining;
            }
            let (y1, k7, err, ks) = dp5_step(&f, sigma, y, k1, h);
            self.steps += 1;
            let e = self.error_norm(y, y1, err);
            let factor = if e == 0.0 {
                5.0
            } else {
                (0.9 * e.powf(-0.2)).clamp(0.2, 5.0)
            };
            if e > 1.0 && h > h_min {
                self.h = h * factor;
                continue;
            }
            let step = dense(sigma, h, y, y1, k1, ks);
            if let Some((end, ye)) = self.event_in(&f, &step, max_abs_x) {
                state.x = ye[0];
                state.v = ye[1];
                return end;
            }
            *max_abs_x = max_abs_x.max(state.s * y1[0]);
            sigma = if h == remaining { len } else { sigma + h };
            y = y1;
            k1 = k7;
            // A step cut short by the stretch's end says nothing about the next one.
            self.h = if h < wanted && factor >= 1.0 {
                wanted
            } else {
                h * factor
            };
        }
        state.x = y[0];
        state.v = y[1];
        StretchEnd::End
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dense output is a 4th-order interpolant: its error in mid-step on
    /// a smooth problem falls as h⁵ (a wrong coefficient would break this).
    #[test]
    fn dense_output_converges_at_fifth_order_locally() {
        // Linear rocking ODE as α → 0 has exact solution; use the nonlinear
        // RHS with no forcing: ÿ = −(p²/α) sin(α(1 − y)). Compare with a
        // reference from tiny RK steps.
        let f = Pivoted {
            rhs: crate::physics::equation::NonlinearRhs {
                p2_over_alpha: 4.0 / 0.2,
                p2_over_eta: 0.0,
                alpha: 0.2,
            },
            s: 1.0,
            g_a: 0.0,
            g1: 0.0,
        };
        let y0 = [0.3, 0.5];
        let reference = |t: f64| {
            let n = 2000;
            let h = t / n as f64;
            let (mut y, mut s) = (y0, 0.0);
            let mut k1 = f.eval(0.0, y);
            for _ in 0..n {
                let (y1, k7, _, _) = dp5_step(&f, s, y, k1, h);
                y = y1;
                k1 = k7;
                s += h;
            }
            y
        };
        let mut errs = Vec::new();
        for h in [0.2, 0.1, 0.05] {
            let k1 = f.eval(0.0, y0);
            let (y1, _, _, ks) = dp5_step(&f, 0.0, y0, k1, h);
            let st = dense(0.0, h, y0, y1, k1, ks);
            let mid = st.at(0.37 * h);
            errs.push((mid[0] - reference(0.37 * h)[0]).abs());
        }
        for w in errs.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!(order > 4.5, "local order {order} ({errs:?})");
        }
    }

    #[test]
    fn illinois_finds_roots_to_ulps() {
        let r = illinois(|x| x * x - 2.0, 0.0, 2.0);
        assert!((r - std::f64::consts::SQRT_2).abs() <= 4.0 * f64::EPSILON * 2.0);
        assert!(r * r - 2.0 >= 0.0, "returns the side of g(hi)");
    }
}
