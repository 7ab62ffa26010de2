//! Hops, the impacts most of a run is made of: the block leaves the pivot
//! and lands again within a step (docs/MODEL.md §3.5). A step holding one
//! is proven simple from its coefficients and landed without its turning
//! point ([`super::poly::hop`]); a hop low enough is not stepped at all,
//! but solved in closed form as the linearised equation's are
//! ([`Taylor::low_hop`]).

use super::Taylor;
use crate::physics::hop::{hop_return, HOP_Z};
use crate::physics::step::{Rocking, Stretch, StretchEnd};

/// The share of a low hop's deceleration the closed form may leave out
/// ([`Taylor::low_hop`]), as a fraction of the tail tolerance: the return
/// it gives is then within a hundredth of the tolerance of the equation's
/// (relative), far inside what a step's series is held to.
const HOP_LEFT_OUT: f64 = 1e-2;

impl Taylor {
    /// A hop low enough to be solved in closed form, as the exact stepper
    /// solves its own: from the pivot at speed `w0` out under the forcing
    /// `g + g1·σ`, the equation about the pivot is `ÿ = a + bσ + (k0 +
    /// k1σ)·y + f2·y² + …` (`a`, `b` the forcing and its rate there, `k0`,
    /// `k1`, `f2` the derivatives in y; docs/MODEL.md §3.5), and without
    /// `k1σy` and `f2y²` it is the exact stepper's `ÿ = p²y + a + bσ` with
    /// `p² = k0`, whose return [`hop_return`] gives. What they add is at
    /// most `|k1|·σ·apex + |f2|·apex²` against `|a|` over the hop (apex its
    /// bound on the height), and moves the return by that share of it: the
    /// hop is taken so where that share is below [`HOP_LEFT_OUT`] times the
    /// tolerance. Above it their first-order effect is added (the drift
    /// `δ = ∬ (k1σy + f2y²)` over the motion to leading order moves the
    /// return by `−δ/ẏ`, its speed by `ÿ` times that plus `δ̇`), and the hop
    /// is taken where what that misses, the share times `2(|β| + z²)` (the
    /// motion's next terms) plus its square, is below the same. Returns
    /// the return's σ and speed (`ẏ`, < 0).
    #[inline(always)]
    fn low_hop(&self, s: f64, w0: f64, g: f64, g1: f64, len: f64, top: f64) -> Option<(f64, f64)> {
        if w0.is_nan() || w0 <= 0.0 {
            return None;
        }
        let (e0, d0, alpha) = (self.sin_alpha, self.cos_alpha, self.alpha);
        let (p2, c) = (self.p * self.p, s * self.p2_over_eta);
        let a = -self.p2_over_alpha * e0 + c * g * d0;
        let b = c * g1 * d0;
        let k0 = p2 * d0 + c * g * alpha * e0;
        if k0.is_nan() || k0 <= 0.0 {
            return None;
        }
        let hop = hop_return(k0.sqrt(), w0, a, b, len, top)?;
        let t = hop.sigma;
        let k1 = c * g1 * alpha * e0;
        let f2 = 0.5 * alpha * (p2 * e0 - c * g * alpha * d0);
        let apex = w0 * w0 * (1.0 + 4.0 * HOP_Z) / (-2.0 * a);
        let left_out = (k1.abs() * t * apex + f2.abs() * apex * apex) / -a;
        let speed = -w0 * hop.v_ratio;
        if left_out <= HOP_LEFT_OUT * self.tol {
            return Some((t, speed));
        }
        // The two terms' first-order effect on the return, from the motion
        // to leading order, `y ≈ w0·σ + a·σ²/2` (docs/MODEL.md §3.5).
        let (t3, t4) = (t * t * t, t * t * t * t);
        let ww = w0 * w0;
        let drift = k1 * t4 * (w0 / 12.0 + a * t / 40.0)
            + f2 * t4 * (ww / 12.0 + a * w0 * t / 20.0 + a * a * t * t / 120.0);
        let drift_rate = k1 * t3 * (w0 / 3.0 + a * t / 8.0)
            + f2 * t3 * (ww / 3.0 + a * w0 * t / 4.0 + a * a * t * t / 20.0);
        let later = -drift / speed;
        let (sigma, speed) = (t + later, speed + (a + b * t) * later + drift_rate);
        // What the correction misses: its own share of the motion left out
        // of `y` (the next terms, β and z² of it) and the second order.
        let missed = left_out * (2.0 * (hop.beta.abs() + hop.q) + left_out);
        (missed <= HOP_LEFT_OUT * self.tol && sigma > 0.0 && sigma < len).then_some((sigma, speed))
    }

    /// The end of the stretch `st` at the landing of a low hop from its
    /// offset `sigma` (the block on the pivot there, `ẏ = w0`), as
    /// [`Taylor::rock`] reports an impact, if [`Taylor::low_hop`] takes it.
    #[inline(always)]
    pub(super) fn low_hop_end(
        &mut self,
        st: Stretch,
        sigma: f64,
        w0: f64,
        top: f64,
        state: &mut Rocking,
    ) -> Option<StretchEnd> {
        let s = state.s;
        let g_a = st.g_a + st.g1 * sigma;
        let (at, w_land) = self.low_hop(s, w0, g_a, st.g1, st.len - sigma, top)?;
        let v = s * w_land;
        self.steps += 1;
        self.left = None;
        *state = Rocking { x: 0.0, v, s };
        Some(StretchEnd::Impact {
            sigma: sigma + at,
            v,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::poly::{hop, poly};
    use super::super::Step;
    use super::*;
    use crate::physics::step::Stepper;

    /// A low hop in closed form ([`Taylor::low_hop`]) against the same hop
    /// taken by the step's series, both by its hop path ([`hop`]) and by
    /// locating its turning point ([`Taylor::rock`] with nothing met
    /// before, which the closed form refuses): the returns agree to 1e-12
    /// (relative), the closed form's bound (a hundredth of the tolerance
    /// 1e-10; the series' own error is far smaller), over blocks, forcings
    /// pushing either way and changing fast, and hops from the closed
    /// form's limit down to the rest tolerance. Each part matters: without
    /// the first-order correction for `k1σy` the returns miss by 1e-11,
    /// without the one for `f2y²` by 5e-12 (the slender block's fastest
    /// hops), and with `p` for `√k0` by 5e-9; the largest miss here is
    /// 1.3e-13.
    #[test]
    fn low_hops_agree_with_the_series() {
        let (mut solved, mut refused_by_bound, mut series_too) = (0, 0, 0);
        for p in [0.5, 2.0, 8.0] {
            for (eta, alpha) in [(0.2, 0.1), (0.6, 0.25), (0.3, 0.4)] {
                let uplift = eta * f64::tan(alpha) / alpha;
                for s in [1.0, -1.0] {
                    for g_rel in [-0.9, 0.0, 0.7] {
                        for g1 in [0.0, 0.3, -2.0, 40.0] {
                            for w_rel in [4.5e-3, 2e-3, 4e-4, 1e-5, 1e-9] {
                                let (g, w) = (s * g_rel * uplift, w_rel * p);
                                let len = 0.015;
                                let t = Taylor::new(p, eta, alpha, 1e-10, 1.0);
                                let Some((sigma, v)) = t.low_hop(s, w, g, g1, len, 1.0) else {
                                    let loose = Taylor::new(p, eta, alpha, 1.0, 1.0);
                                    if loose.low_hop(s, w, g, g1, len, 1.0).is_some() {
                                        refused_by_bound += 1;
                                    }
                                    continue;
                                };
                                solved += 1;
                                let case = format!("p {p} α {alpha} s {s} g {g} g1 {g1} w {w}");
                                // The series' hop path, over the whole stretch.
                                let mut t = Taylor::new(p, eta, alpha, 1e-10, 1.0);
                                let from = Step {
                                    s,
                                    y0: 0.0,
                                    w0: w,
                                    e0: t.sin_alpha,
                                    d0: t.cos_alpha,
                                    h: len,
                                    g_a: g,
                                    g1,
                                };
                                let n = t.series(from).expect("converges");
                                // (Where it proves the hop simple over the stretch.)
                                let by_series = hop(&t.y[..n + 2], t.ends.y, 1.0, 1.0)
                                    .map(|tau| (tau * len, poly(&t.v[..n + 1], tau) / len));
                                series_too += usize::from(by_series.is_some());
                                // The turning point's walk.
                                let mut st = Rocking {
                                    x: 0.0,
                                    v: s * w,
                                    s,
                                };
                                let stretch = Stretch {
                                    tau0: 0.0,
                                    len,
                                    g_a: g,
                                    g1,
                                };
                                let mut t = Taylor::new(p, eta, alpha, 1e-10, 1.0);
                                let StretchEnd::Impact {
                                    sigma: s_walk,
                                    v: v_walk,
                                } = t.rock(stretch, &mut st, &mut 0.0)
                                else {
                                    panic!("{case}: no impact");
                                };
                                let refs = by_series.into_iter().chain([(s_walk, s * v_walk)]);
                                for (s_ref, v_ref) in refs {
                                    assert!(
                                        (sigma / s_ref - 1.0).abs() < 1e-12,
                                        "{case}: σ {sigma} vs {s_ref}"
                                    );
                                    assert!(
                                        (v / v_ref - 1.0).abs() < 1e-12,
                                        "{case}: v {v} vs {v_ref}"
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
        assert!(
            solved > 200 && series_too > 100 && refused_by_bound > 10,
            "{solved} solved ({series_too} by the series hop path too), {refused_by_bound} refused"
        );
    }
}
