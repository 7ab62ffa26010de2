//! Two runs of the Taylor stepper in step, one lane each of an SSE2
//! register ([`F2`]): the two runs of a chaos probe follow nearly the same
//! motion, and two neighbouring grid levels of a search rock alike for
//! stretches, so their steps can share the series' chain of orders, which
//! bounds a step's time (docs/MODEL.md §3.5). Each lane does the
//! operations [`Taylor::series`] does, in its order, so each run's outcome
//! is the one it has alone, to the bit.

use super::series::{convolutions, ends};
use super::{quiet, Ends, Step, Taylor, INV, LEN, MAX_ORDER, MIN_ORDER};
use crate::physics::driver::CruisePair;
use crate::physics::lanes::F2;
use crate::physics::step::Rocking;
use crate::physics::Excitation;

/// The series of two steps at once: each lane's coefficients (in τ), its
/// degree (`None` while, or if, its tail is above the tolerance) and its
/// ends.
struct PairSeries {
    y: [F2; LEN],
    v: [F2; LEN],
    e: [F2; LEN],
    d: [F2; LEN],
    n: [Option<usize>; 2],
    ends: [Ends; 2],
}

impl PairSeries {
    fn new() -> Self {
        let zero = [F2::splat(0.0); LEN];
        PairSeries {
            y: zero,
            v: zero,
            e: zero,
            d: zero,
            n: [None; 2],
            ends: [Ends::default(); 2],
        }
    }

    /// [`Taylor::series`] for two steppers of the same `p`, α and
    /// tolerance (two values of η, each on its own pivot `s`) over the same
    /// step, lane by lane, until both lanes' tails are below the tolerance
    /// (or [`MAX_ORDER`]).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn build(
        &mut self,
        steppers: [&Taylor; 2],
        s: F2,
        y0: F2,
        w0: F2,
        e0: F2,
        d0: F2,
        h: f64,
        g_a: f64,
        g1: f64,
    ) {
        let [ta, tb] = steppers;
        let zero = F2::splat(0.0);
        let h2 = h * h;
        let k_sin = F2::splat(h2 * ta.p2_over_alpha);
        let f = (s * F2::splat(h2)) * F2::new(ta.p2_over_eta, tb.p2_over_eta);
        let (f0, f1) = (f * F2::splat(g_a), (f * F2::splat(g1)) * F2::splat(h));
        let a = ta.alpha;
        let (tol, tol_e) = (F2::splat(ta.tol), F2::splat(ta.tol_sin_cos()));
        let (y, v, e, d) = (&mut self.y, &mut self.v, &mut self.e, &mut self.d);
        let v0 = F2::splat(h) * w0;
        y[0] = y0;
        v[0] = v0;
        e[0] = e0;
        d[0] = d0;
        let fa = F2::splat(a);
        let (a_v0, a_e0, a_d0) = (fa * v0, fa * e0, fa * d0);
        let (mut vk, mut ek, mut dk, mut d_prev) = (v0, e0, d0, zero);
        let (mut scale_v, mut tol_v) = (v0.abs(), zero);
        self.n = [None; 2];
        // Order by order as [`Taylor::series`] grows them: the orders nearly
        // every step needs each its own straight code, the rest in a loop.
        macro_rules! order {
            ($k:expr) => {{
                let k: usize = $k;
                let m = k + 1;
                let inv = F2::splat(INV[m]);
                let (c0, cs, t1) = (f0 * inv, k_sin * inv, (f1 * inv) * d_prev);
                let (se, sd) = convolutions(&d[..], &e[..], &v[..], k, zero);
                let ai = F2::splat(a * INV[m]);
                let (se, sd) = (ai * se, ai * sd);
                let (cv, cd, ce) = (a_v0 * inv, a_d0 * inv, a_e0 * inv);
                let vm = (c0 * dk + t1) - cs * ek;
                let ym = vk * inv;
                let (em, dm) = if k > 0 {
                    (-(se + cv * dk) - cd * vk, (sd + cv * ek) + ce * vk)
                } else {
                    (-(cd * vk), ce * vk)
                };
                (y[m], v[m], e[m], d[m]) = (ym, vm, em, dm);
                if m <= 2 {
                    scale_v = scale_v.max(vm.abs());
                    tol_v = tol * scale_v;
                } else if m >= MIN_ORDER {
                    let done = (vm.abs() + vk.abs()).le(tol_v)
                        & (em.abs() + ek.abs()).le(tol_e)
                        & (dm.abs() + dk.abs()).le(tol_e);
                    let bits = done.bits();
                    if bits != 0 {
                        // Y's last term, as the next order's `ym` would be.
                        y[m + 1] = vm * F2::splat(INV[m + 1]);
                        let sums = ends(&y[..], &v[..], &e[..], &d[..], m, zero, F2::abs);
                        let [ye, ve, ee, de, ae] = sums.map(F2::lanes);
                        for lane in 0..2 {
                            if bits & (1 << lane) != 0 && self.n[lane].is_none() {
                                self.n[lane] = Some(m);
                                self.ends[lane] = Ends {
                                    y: ye[lane],
                                    v: ve[lane],
                                    e: ee[lane],
                                    d: de[lane],
                                    abs_v_tail: ae[lane],
                                };
                            }
                        }
                        if self.n[0].is_some() && self.n[1].is_some() {
                            // A lane done an order or more before has its own
                            // last term of Y already: this order's `ym`.
                            return;
                        }
                    }
                }
                (vk, ek, d_prev, dk) = (vm, em, dk, dm);
            }};
        }
        order!(0);
        order!(1);
        order!(2);
        order!(3);
        order!(4);
        order!(5);
        order!(6);
        order!(7);
        order!(8);
        for k in 9..MAX_ORDER {
            order!(k);
        }
    }

    /// Hands lane `lane`'s step (built from `from`) to `stepper`, as if it
    /// had built it: [`Taylor::rock`] or [`Taylor::cruise`] asked for it take
    /// it as it is.
    fn hand(&self, lane: usize, from: Step, stepper: &mut Taylor) {
        let Some(n) = self.n[lane] else { return };
        for i in 0..n + 2 {
            stepper.y[i] = self.y[i].lanes()[lane];
        }
        for i in 0..n + 1 {
            stepper.v[i] = self.v[i].lanes()[lane];
            stepper.e[i] = self.e[i].lanes()[lane];
            stepper.d[i] = self.d[i].lanes()[lane];
        }
        stepper.ends = self.ends[lane];
        stepper.built = Some((from.key(), n));
    }
}

impl CruisePair for Taylor {
    /// Whole intervals while each is one step for both runs and both
    /// series prove it eventless, as [`Taylor::cruise`] takes them one run
    /// at a time. At the first interval one run cannot cross so, each run's
    /// series of it is handed to its stepper ([`PairSeries::hand`]): the
    /// runs then cross it on their own without building it again.
    #[inline(always)]
    fn cruise_pair(
        steppers: [&mut Taylor; 2],
        exc: &Excitation,
        mut k: usize,
        states: [&mut Rocking; 2],
        tops: [&mut f64; 2],
    ) -> usize {
        let [ta, tb] = steppers;
        let dt = exc.dt_s;
        if ta.cuts(dt) || tb.cuts(dt) || ta.p != tb.p || ta.alpha != tb.alpha || ta.tol != tb.tol {
            return k;
        }
        let (psi, slope) = (&exc.psi[..], &exc.slope[..]);
        let n = slope.len().min(psi.len());
        let [st_a, st_b] = states;
        let [top_a, top_b] = tops;
        let s = [st_a.s, st_b.s];
        let mut y0 = [s[0] * st_a.x, s[1] * st_b.x];
        let mut w0 = [s[0] * st_a.v, s[1] * st_b.v];
        let ((ea, da), (eb, db)) = (ta.sin_cos_at(st_a), tb.sin_cos_at(st_b));
        let (mut e0, mut d0) = ([ea, eb], [da, db]);
        let mut top = [*top_a, *top_b];
        let limit = [ta.limit, tb.limit];
        let start = k;
        let mut pair = PairSeries::new();
        let lanes = |x: [f64; 2]| F2::new(x[0], x[1]);
        while k < n {
            // `rock`'s forcing at the stretch's start, to the bit.
            let (g_a, g1) = (psi[k] + slope[k] * 0.0, slope[k]);
            pair.build(
                [&*ta, &*tb],
                lanes(s),
                lanes(y0),
                lanes(w0),
                lanes(e0),
                lanes(d0),
                dt,
                g_a,
                g1,
            );
            let quiet = |lane: usize| {
                let at = |c: &F2| c.lanes()[lane];
                let (y, v) = (
                    [&pair.y[0], &pair.y[1], &pair.y[2]].map(at),
                    [&pair.v[0], &pair.v[1]].map(at),
                );
                pair.n[lane].is_some() && quiet(y, v, &pair.ends[lane], top[lane], limit[lane])
            };
            if !(quiet(0) && quiet(1)) {
                let from = |l: usize| Step {
                    s: s[l],
                    y0: y0[l],
                    w0: w0[l],
                    e0: e0[l],
                    d0: d0[l],
                    h: dt,
                    g_a,
                    g1,
                };
                pair.hand(0, from(0), ta);
                pair.hand(1, from(1), tb);
                break;
            }
            for (lane, t) in [(0, &mut *ta), (1, &mut *tb)] {
                let e = pair.ends[lane];
                t.steps += 1;
                top[lane] = top[lane].max(e.y);
                (y0[lane], w0[lane], e0[lane], d0[lane]) = (e.y, e.v / dt, e.e, e.d);
            }
            k += 1;
        }
        if k > start {
            for (lane, t, st) in [(0, &mut *ta, &mut *st_a), (1, &mut *tb, &mut *st_b)] {
                *st = Rocking {
                    x: s[lane] * y0[lane],
                    v: s[lane] * w0[lane],
                    s: s[lane],
                };
                t.left = Some((*st, e0[lane], d0[lane]));
            }
            (*top_a, *top_b) = (top[0], top[1]);
        }
        k
    }
}
