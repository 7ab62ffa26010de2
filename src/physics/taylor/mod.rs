//! The Taylor stepper of the nonlinear equation (paper Eq. 7): one step per
//! sample interval, its Taylor series built by recurrences, its truncation
//! bounded by the series' tail, events located on the polynomial.
//!
//! With `y = s·x` on pivot `s` and `u = α(1 − y)`, the equation is
//!
//! ```text
//! ÿ = −(p²/α) sin u + s (p²/η) (g_a + g1 σ) cos u,    u̇ = −α ẏ
//! ```
//!
//! In the step's own time `τ = σ/h ∈ [0, 1]` write `Y(τ) = Σ Y_k τ^k` and
//! `V = dY/dτ`, `E = sin u`, `D = cos u` likewise. Because the forcing is
//! linear in time and `E' = −α D V`, `D' = α E V`, every coefficient follows
//! from lower ones (the automatic differentiation of Moore, *Interval
//! Analysis*, 1966; Jorba & Zou, *Exp. Math.* 14, 2005):
//!
//! ```text
//! (k+1) V_{k+1} = −h²(p²/α) E_k + s h²(p²/η) (g_a D_k + g1 h D_{k−1})
//! (k+1) Y_{k+1} = V_k
//! (k+1) E_{k+1} = −α Σ_{j≤k} D_j V_{k−j}
//! (k+1) D_{k+1} =  α Σ_{j≤k} E_j V_{k−j}
//! ```
//!
//! The series is grown until the last two coefficients of `V` are below
//! `tol` times its largest (and those of `E`, `D` below a tenth of `tol·α`,
//! [`SIN_COS_TAIL`]; `Y`, kept to degree n + 1, has an omitted tail that is
//! the integral of `V`'s, so no larger, docs/MODEL.md §3.5): the solution
//! is analytic with a radius of convergence far beyond a sample interval
//! (`p·Δt ≤ 0.2` on the bundled records), so its coefficients fall
//! geometrically and the omitted tail is smaller than the last terms kept
//! (Jorba & Zou's criterion). A series that has not converged by
//! [`MAX_ORDER`] is thrown away and the step halved: the step is then
//! shorter than the sample interval (long free-rocking stretches after the
//! record; extreme forcing), never longer, so the forcing's kinks fall on
//! step boundaries. `Y' = V` holds exactly for the polynomials, so the
//! turning points, impacts and overturning are the roots of polynomials,
//! found by safeguarded Newton (impacts and overturning to a few ulps,
//! turning points as finely as their use needs); the state at an event is
//! the series evaluated there, as accurate as at the step's end. A hop (a
//! step from the pivot back to it, most of a run's impacts) is proven
//! simple from its coefficients and its landing found without its turning
//! point ([`hop`]); a hop low enough is not stepped at all, but solved in
//! closed form as the linearised equation's are ([`Taylor::low_hop`],
//! docs/MODEL.md §3.5).
//!
//! `sin u` and `cos u` at the next step's start are the series' values at
//! its end (no `sin_cos` per step), recomputed exactly after an impact or an
//! uplift (`y = 0`: `sin α`, `cos α`) and whenever the driver hands over a
//! state this stepper did not leave.
//!
//! Whole intervals a step proves eventless are crossed by
//! [`Stepper::cruise`] without returning to the driver, and those of runs
//! in step (`pair`, one lane each: a chaos probe's two runs, the four
//! probes of two decisive runs, a refinement run with its two probes at a
//! tighter tolerance, two grid levels).

mod hops;
#[cfg(target_arch = "x86_64")]
mod pair;
mod poly;
mod series;

use super::step::{Rocking, Stepper, Stretch, StretchEnd};
use super::Excitation;
use poly::{hop, poly, root, turning_points, Turns};

/// The highest order of a step's series; a series not converged by then is
/// thrown away and the step halved.
pub const MAX_ORDER: usize = 24;

/// The lowest order accepted, so that coefficients small by symmetry (a
/// step from rest under a forcing at the threshold) cannot end a series.
const MIN_ORDER: usize = 4;

/// The fraction of `tol·α` the last two coefficients of `sin u` and `cos
/// u` must fall below (V's fall below `tol` times V's scale). Their
/// truncation errors are carried from step to step as a drift of `sin u`
/// and `cos u` from the angle (they are set from it again only at impacts
/// and uplifts), and in slow rocking at a small `p·Δt` their series fall
/// more slowly than V's: at the full `tol·α` a run of 521 impacts at p·Δt
/// = 0.0045 (tests/taylor.rs, RSN900) misses DP5's at rtol 1e-13 by 1e-12,
/// at a tenth of it by 5e-15.
const SIN_COS_TAIL: f64 = 0.1;

const LEN: usize = MAX_ORDER + 2;

/// 1/k for k < LEN (1/0 unused).
const INV: [f64; LEN] = {
    let mut t = [0.0; LEN];
    let mut k = 1;
    while k < LEN {
        t[k] = 1.0 / k as f64;
        k += 1;
    }
    t
};

/// The Taylor stepper of the nonlinear equation; one per run.
pub struct Taylor {
    p: f64,
    p2_over_alpha: f64,
    p2_over_eta: f64,
    alpha: f64,
    sin_alpha: f64,
    cos_alpha: f64,
    tol: f64,
    limit: f64,
    /// The longest step tried (s): halved when a series does not converge,
    /// grown again after steps it cut short.
    h: f64,
    /// The state this stepper last returned, with `sin u` and `cos u` there.
    left: Option<(Rocking, f64, f64)>,
    /// The current step's coefficients (in τ): Y to degree n + 1, V, E, D to n.
    y: [f64; LEN],
    v: [f64; LEN],
    e: [f64; LEN],
    d: [f64; LEN],
    /// The current step's sums.
    ends: Ends,
    /// What the current step's series was built from ([`Step::key`]) and
    /// its degree, when [`Stepper::cruise`] built it and left the step to
    /// [`Stepper::rock`]: `rock` asked for the same series takes it as it is.
    built: Option<([u64; 8], usize)>,
    /// Steps taken and series thrown away (for benchmarks).
    pub steps: u64,
    pub rejected: u64,
}

impl Taylor {
    /// The stepper for a block of frequency parameter `p`, at `eta`, of
    /// slenderness `alpha` (rad), with tail tolerance `tol`, stopping at `|x|
    /// = limit`.
    pub fn new(p: f64, eta: f64, alpha: f64, tol: f64, limit: f64) -> Self {
        let (sin_alpha, cos_alpha) = alpha.sin_cos();
        Taylor {
            p,
            p2_over_alpha: p * p / alpha,
            p2_over_eta: p * p / eta,
            alpha,
            sin_alpha,
            cos_alpha,
            tol,
            limit,
            h: f64::INFINITY,
            left: None,
            y: [0.0; LEN],
            v: [0.0; LEN],
            e: [0.0; LEN],
            d: [0.0; LEN],
            ends: Ends::default(),
            built: None,
            steps: 0,
            rejected: 0,
        }
    }

    /// What the last two coefficients of `sin u` and `cos u` must fall
    /// below for a series to be done: [`SIN_COS_TAIL`] of `tol·α`.
    #[inline(always)]
    fn tol_sin_cos(&self) -> f64 {
        self.tol * self.alpha * SIN_COS_TAIL
    }

    /// `sin u`, `cos u` at `state`.
    #[inline]
    fn sin_cos_at(&self, state: &Rocking) -> (f64, f64) {
        if state.x == 0.0 {
            return (self.sin_alpha, self.cos_alpha);
        }
        match self.left {
            Some((left, e, d)) if left == *state => (e, d),
            _ => (self.alpha * (1.0 - state.s * state.x)).sin_cos(),
        }
    }

    /// The series of a step from these inputs (as [`Taylor::series`]):
    /// the one [`Taylor::built`] holds if it was built from them, else
    /// built now.
    #[inline(always)]
    fn build(&mut self, from: Step) -> Option<usize> {
        if let Some((key, n)) = self.built.take() {
            if key == from.key() {
                return Some(n);
            }
        }
        self.series(from)
    }

    /// Whether a stretch of `len` left is cut into steps of [`Taylor::h`]
    /// (a last piece under 1 % of a step is taken with the one before).
    #[inline(always)]
    fn cuts(&self, len: f64) -> bool {
        self.h < len && len - self.h > 0.01 * self.h
    }

    /// [`quiet`] for the step just built.
    #[inline(always)]
    fn quiet(&self, top: f64) -> bool {
        let (y, v) = ([self.y[0], self.y[1], self.y[2]], [self.v[0], self.v[1]]);
        quiet(y, v, &self.ends, top, self.limit)
    }

    /// The first event of the step just built (degree `n`), if any: the
    /// step cut at its turning points (every root of V, [`turning_points`])
    /// into pieces on which Y is monotone; the first piece whose end reaches
    /// the limit or the pivot holds it. Returns the event's τ and the event;
    /// raises `max_abs_x` to the turning points passed.
    #[inline]
    fn event(&self, n: usize, y_end: f64, max_abs_x: &mut f64) -> Option<(f64, Event)> {
        let (yc, vc) = (&self.y[..n + 2], &self.v[..n + 1]);
        if let Some(t) = hop(yc, y_end, *max_abs_x, self.limit) {
            return Some((t, Event::Impact));
        }
        let mut turns = Turns::default();
        turning_points(vc, &mut turns);
        let (mut lo, mut y_lo) = (0.0, yc[0]);
        let ends = turns.as_slice().iter().copied().chain([1.0]);
        for hi in ends {
            let y_hi = if hi == 1.0 { y_end } else { poly(yc, hi) };
            if y_hi >= self.limit {
                let mut shifted = [0.0; LEN];
                shifted[..yc.len()].copy_from_slice(yc);
                shifted[0] -= self.limit;
                let over = y_hi - self.limit;
                return Some((root(&shifted[..yc.len()], lo, hi, over), Event::Overturn));
            }
            if y_hi <= 0.0 {
                if y_lo <= 0.0 {
                    // A departure swamped by rounding: it never left the pivot.
                    return Some((hi, Event::Settled));
                }
                return Some((root(yc, lo, hi, y_hi), Event::Impact));
            }
            *max_abs_x = max_abs_x.max(y_hi);
            (lo, y_lo) = (hi, y_hi);
        }
        None
    }
}

/// Whether a step (its first coefficients `[Y_0, Y_1, Y_2]`, `[V_0, V_1]`
/// and its sums) holds no event and raises the largest `y` met before
/// (`top`) to its end at most: either it has no turning point inside (|V| >
/// 0 on the step, its first term above the sum of the others') and its end
/// is inside (0, limit), for Y is monotone; or [`calm`] proves it.
#[inline(always)]
fn quiet([y0, y1, y2]: [f64; 3], [v0, v1]: [f64; 2], ends: &Ends, top: f64, limit: f64) -> bool {
    (v0.abs() > ends.abs_v_tail && ends.y > 0.0 && ends.y < limit)
        || calm([y0, y1, y2, v1], ends, top, limit)
}

/// Whether a step (its first coefficients `[Y_0, Y_1, Y_2, V_1]` and its
/// sums) is proven to hold no event and to reach no higher than `top` (the
/// largest `y` met before, its end included after it) though its velocity
/// may change sign: then the turning points [`Taylor::event`] would locate
/// change nothing (neither an event nor the largest `|x|`), and the step is
/// taken as a quiet one, with the same result to the bit.
///
/// On τ ∈ [0, 1], `Y = Y_0 + Q(τ) + T(τ)` with `Q = Y_1 τ + Y_2 τ²`, whose
/// extremes are at the ends or its vertex, and `|T| ≤ Σ_{k≥3} |Y_k| ≤
/// Σ_{j≥2} |V_j| / 3` (`Y_{j+1} = V_j/(j+1)`). The bounds are widened by
/// far more than the rounding of these sums and of [`poly`]'s evaluations
/// of Y (a few ulps of `Σ |Y_k|` each), so a value `event` would compute
/// lies within them.
#[inline(always)]
fn calm([y0, y1, y2, v1]: [f64; 4], ends: &Ends, top: f64, limit: f64) -> bool {
    let tail = (ends.abs_v_tail - v1.abs()) * (1.0 / 3.0);
    let q1 = y1 + y2;
    let (mut q_lo, mut q_hi) = (q1.min(0.0), q1.max(0.0));
    let vertex = -y1 / (2.0 * y2);
    if vertex > 0.0 && vertex < 1.0 {
        let q = y1 * vertex + y2 * vertex * vertex;
        (q_lo, q_hi) = (q_lo.min(q), q_hi.max(q));
    }
    let slack = tail + 64.0 * f64::EPSILON * (y0.abs() + y1.abs() + y2.abs() + tail);
    let (lo, hi) = (y0 + q_lo - slack, y0 + q_hi + slack);
    lo > 0.0 && hi <= top.max(ends.y) && hi < limit
}

/// What a step's series is built from: the pivot `s`, `y0`, `ẏ0 = w0`,
/// `sin u0 = e0`, `cos u0 = d0`, the step `h` and the forcing `g_a + g1·σ`.
#[derive(Clone, Copy)]
struct Step {
    s: f64,
    y0: f64,
    w0: f64,
    e0: f64,
    d0: f64,
    h: f64,
    g_a: f64,
    g1: f64,
}

impl Step {
    /// Every number, as bits: two steps with one key build one series.
    fn key(&self) -> [u64; 8] {
        [
            self.s, self.y0, self.w0, self.e0, self.d0, self.h, self.g_a, self.g1,
        ]
        .map(f64::to_bits)
    }
}

/// A step's series at its end (τ = 1), and how far its velocity can be
/// from its first term: `Σ_{j≥1} |V_j|`.
#[derive(Default, Clone, Copy)]
struct Ends {
    y: f64,
    v: f64,
    e: f64,
    d: f64,
    abs_v_tail: f64,
}

enum Event {
    Impact,
    Overturn,
    Settled,
}

impl Stepper for Taylor {
    fn set_limit(&mut self, limit: f64) {
        self.limit = limit;
    }

    /// Whole intervals while each is one step (the step not cut) whose
    /// series converges and proves it eventless, as [`Taylor::rock`] would
    /// take them, without leaving the loop. The first interval it cannot
    /// prove is left to `rock` with its series built ([`Taylor::built`]).
    #[inline(always)]
    fn cruise(
        &mut self,
        exc: &Excitation,
        mut k: usize,
        end: usize,
        state: &mut Rocking,
        max_abs_x: &mut f64,
    ) -> usize {
        let dt = exc.dt_s;
        if self.cuts(dt) {
            return k;
        }
        let (psi, slope) = (&exc.psi[..], &exc.slope[..]);
        let n = slope.len().min(psi.len()).min(end);
        let s = state.s;
        let (mut y0, mut w0) = (s * state.x, s * state.v);
        let (mut e0, mut d0) = self.sin_cos_at(state);
        let mut top = *max_abs_x;
        let start = k;
        while k < n {
            // `rock`'s forcing at the stretch's start, to the bit.
            let from = Step {
                s,
                y0,
                w0,
                e0,
                d0,
                h: dt,
                g_a: psi[k] + slope[k] * 0.0,
                g1: slope[k],
            };
            let Some(order) = self.build(from) else {
                break;
            };
            let e = self.ends;
            if !self.quiet(top) {
                self.built = Some((from.key(), order));
                break;
            }
            self.steps += 1;
            top = top.max(e.y);
            (y0, w0, e0, d0) = (e.y, e.v / dt, e.e, e.d);
            k += 1;
        }
        if k > start {
            *state = Rocking {
                x: s * y0,
                v: s * w0,
                s,
            };
            self.left = Some((*state, e0, d0));
            *max_abs_x = top;
        }
        k
    }

    #[inline(always)]
    fn rock(&mut self, st: Stretch, state: &mut Rocking, max_abs_x: &mut f64) -> StretchEnd {
        let s = state.s;
        let (mut y0, mut w0) = (s * state.x, s * state.v);
        let (mut e0, mut d0) = self.sin_cos_at(state);
        let mut sigma = 0.0;
        while sigma < st.len {
            let remaining = st.len - sigma;
            if y0 == 0.0 {
                if let Some(end) = self.low_hop_end(st, sigma, w0, *max_abs_x, state) {
                    return end;
                }
            }
            let cut = self.cuts(remaining);
            let h = if cut { self.h } else { remaining };
            let from = Step {
                s,
                y0,
                w0,
                e0,
                d0,
                h,
                g_a: st.g_a + st.g1 * sigma,
                g1: st.g1,
            };
            let n = match self.build(from) {
                Some(n) => n,
                // Only a state that is not finite fails at steps this short
                // (p·h = 1e-9): take the series as it is, so time goes on.
                None if h * self.p <= 1e-9 => self.as_it_is(),
                None => {
                    self.rejected += 1;
                    self.h = 0.5 * h;
                    continue;
                }
            };
            self.steps += 1;
            let Ends {
                y: y_end,
                v: v_end,
                e: e_end,
                d: d_end,
                ..
            } = self.ends;
            let event = if self.quiet(*max_abs_x) {
                None
            } else {
                self.event(n, y_end, max_abs_x)
            };
            if let Some((t, event)) = event {
                let at = sigma + t * h;
                let w = poly(&self.v[..n + 1], t) / h;
                self.left = None;
                return match event {
                    Event::Impact => {
                        // At the root of Y: x = 0 (the driver starts the
                        // next pivot there), not Y evaluated again.
                        *state = Rocking {
                            x: 0.0,
                            v: s * w,
                            s,
                        };
                        StretchEnd::Impact {
                            sigma: at,
                            v: s * w,
                        }
                    }
                    Event::Overturn => {
                        *max_abs_x = max_abs_x.max(self.limit);
                        *state = Rocking {
                            x: s * self.limit,
                            v: s * w,
                            s,
                        };
                        StretchEnd::Overturn { sigma: at }
                    }
                    Event::Settled => {
                        *state = Rocking { x: 0.0, v: 0.0, s };
                        StretchEnd::Settled { sigma: at }
                    }
                };
            }
            *max_abs_x = max_abs_x.max(y_end);
            (y0, w0, e0, d0) = (y_end, v_end / h, e_end, d_end);
            if cut {
                sigma += h;
                if n <= MAX_ORDER * 2 / 3 {
                    self.h *= 1.5;
                }
            } else {
                sigma = st.len;
            }
        }
        *state = Rocking {
            x: s * y0,
            v: s * w0,
            s,
        };
        self.left = Some((*state, e0, d0));
        StretchEnd::End
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Wherever [`calm`] lets a step pass as quiet, the step's polynomial,
    /// evaluated densely, stays above the pivot, below the limit and no
    /// higher than `top`; and it does let steps pass whose velocity changes
    /// sign (turning points it saves locating). Random swings: states,
    /// forcing and `top` drawn by a fixed generator.
    #[test]
    fn calm_steps_stay_within_their_bounds() {
        let (alpha, limit) = (0.25, 1.0);
        let mut t = Taylor::new(2.0, 0.3, alpha, 1e-12, limit);
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut draw = |lo: f64, hi: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            lo + (hi - lo) * (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut passed, mut turning) = (0, 0);
        for _ in 0..20_000 {
            let y0 = draw(1e-4, 0.95);
            let (e0, d0) = (alpha * (1.0 - y0)).sin_cos();
            let from = Step {
                s: 1.0,
                y0,
                w0: draw(-3.0, 3.0),
                e0,
                d0,
                h: 0.02,
                g_a: draw(-2.0, 2.0),
                g1: draw(-60.0, 60.0),
            };
            let Some(n) = t.series(from) else { continue };
            let top = draw(y0, 1.0);
            let first = [t.y[0], t.y[1], t.y[2], t.v[1]];
            if !calm(first, &t.ends, top, limit) {
                continue;
            }
            passed += 1;
            let y = &t.y[..n + 2];
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for i in 0..=4000 {
                let at = poly(y, i as f64 / 4000.0);
                (lo, hi) = (lo.min(at), hi.max(at));
            }
            assert!(lo > 0.0, "{lo} below the pivot");
            assert!(hi <= top.max(t.ends.y) && hi < limit, "{hi} above {top}");
            let v_end = poly(&t.v[..n + 1], 1.0);
            turning += usize::from(t.v[0].signum() != v_end.signum());
        }
        assert!(
            passed > 1000 && turning > 100,
            "{passed} calm, {turning} turning"
        );
    }

    /// A state that is not finite has no converging series: the stepper
    /// halves its step down to p·h = 1e-9, then goes on, and the stretch
    /// ends instead of looping.
    #[test]
    fn a_state_that_is_not_finite_still_ends_the_stretch() {
        let mut t = Taylor::new(2.0, 0.5, 0.2, 1e-12, 1.0);
        let mut st = Rocking {
            x: f64::NAN,
            v: 0.1,
            s: 1.0,
        };
        let mut max = 0.0;
        let stretch = Stretch {
            tau0: 0.0,
            len: 1e-8,
            g_a: 0.0,
            g1: 0.0,
        };
        assert_eq!(t.rock(stretch, &mut st, &mut max), StretchEnd::End);
        assert!(t.rejected > 0);
    }

    /// A stretch longer than the series converges over (the free motion
    /// after a record) is cut into halved steps and ends where one series
    /// over it would: energy, conserved, says where the swing turns.
    #[test]
    fn a_long_stretch_is_cut_into_steps_that_converge() {
        let (p, alpha) = (2.0, 0.3);
        let mut t = Taylor::new(p, 1.0, alpha, 1e-12, 10.0);
        let mut st = Rocking {
            x: 0.5,
            v: 0.4,
            s: 1.0,
        };
        let mut max = 0.0;
        let stretch = Stretch {
            tau0: 0.0,
            len: 30.0 / p,
            g_a: 0.0,
            g1: 0.0,
        };
        let end = t.rock(stretch, &mut st, &mut max);
        assert!(matches!(end, StretchEnd::Impact { .. }), "{end:?}");
        assert!(t.rejected > 0 && t.steps > 1);
        let e0 = 0.5 * 0.4 * 0.4 + p * p / (alpha * alpha) * (alpha * 0.5).cos();
        let apex = 1.0 - (e0 * alpha * alpha / (p * p)).acos() / alpha;
        assert!((max - apex).abs() < 1e-12, "{max} against {apex}");
    }
}
