//! The exact stepper as a [`Stepper`]: [`Stepper::rock`] walks a stretch
//! piece by piece between its turning points and locates its first event;
//! [`Stepper::cruise`] crosses whole intervals the sign tests prove eventless.

use super::closed_form::Coeffs;
use super::stepper::Exact;
use crate::physics::step::{Rocking, Stepper, Stretch, StretchEnd};
use crate::physics::Excitation;

impl Stepper for Exact {
    #[inline]
    fn set_limit(&mut self, limit: f64) {
        self.limit = limit;
    }

    /// Whole intervals while the motion is provably monotone and stays
    /// strictly between the pivot and the limit: the arithmetic of `rock`'s
    /// first branch, without leaving the loop.
    #[inline(always)]
    fn cruise(
        &mut self,
        exc: &Excitation,
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
