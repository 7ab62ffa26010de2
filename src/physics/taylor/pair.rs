//! Runs of the Taylor stepper in step, one lane each of a vector: two in
//! an SSE2 register ([`F2`]), four in an AVX one ([`F4`]). The two runs of
//! a chaos probe follow nearly the same motion, as do a run and its probes
//! at a tighter tolerance (each lane has its own); the probes of
//! neighbouring decisive runs and neighbouring grid levels of a search rock
//! alike for stretches, so their steps can share the series' chain of
//! orders, which bounds a step's time (docs/MODEL.md §3.5): four lanes cost
//! about what two do. Each lane does the operations [`Taylor::series`] does, in its
//! order, so each run's outcome is the one it has alone, to the bit.

use super::series::{convolutions, ends};
use super::{quiet, Ends, Step, Taylor, INV, LEN, MAX_ORDER, MIN_ORDER};
use crate::physics::driver::{CruiseLanes, CruisePair, Lane};
use crate::physics::lanes::{Lanes, F2, F4};
use crate::physics::step::Rocking;
use crate::physics::Excitation;

/// The series of `N` steps at once: each lane's coefficients (in τ), its
/// degree (`None` while, or if, its tail is above the tolerance) and its
/// ends.
struct LaneSeries<T, const N: usize> {
    y: [T; LEN],
    v: [T; LEN],
    e: [T; LEN],
    d: [T; LEN],
    n: [Option<usize>; N],
    ends: [Ends; N],
}

/// What the lanes' steppers share (the same `p` and α), as
/// [`Taylor::series`] uses it, and what each has of its own (η, the
/// tolerance: a run and its chaos probes at a tighter one go together).
struct Shared<T> {
    p2_over_alpha: f64,
    alpha: f64,
    p2_over_eta: T,
    tol: T,
    tol_e: T,
}

impl<T: Lanes<N>, const N: usize> LaneSeries<T, N> {
    #[inline(always)]
    fn new() -> Self {
        let zero = [T::splat(0.0); LEN];
        LaneSeries {
            y: zero,
            v: zero,
            e: zero,
            d: zero,
            n: [None; N],
            ends: [Ends::default(); N],
        }
    }

    /// [`Taylor::series`] for `N` steppers sharing `c` (each lane its own
    /// η and tolerance, on its own pivot `s`) over the same step, lane by
    /// lane, until every lane's tail is below its tolerance (or
    /// [`MAX_ORDER`]).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn build(
        &mut self,
        c: &Shared<T>,
        s: T,
        y0: T,
        w0: T,
        e0: T,
        d0: T,
        h: f64,
        g_a: f64,
        g1: f64,
    ) {
        let zero = T::splat(0.0);
        let h2 = h * h;
        let k_sin = T::splat(h2 * c.p2_over_alpha);
        let f = (s * T::splat(h2)) * c.p2_over_eta;
        let (f0, f1) = (f * T::splat(g_a), (f * T::splat(g1)) * T::splat(h));
        let a = c.alpha;
        let (tol, tol_e) = (c.tol, c.tol_e);
        let (y, v, e, d) = (&mut self.y, &mut self.v, &mut self.e, &mut self.d);
        let v0 = T::splat(h) * w0;
        y[0] = y0;
        v[0] = v0;
        e[0] = e0;
        d[0] = d0;
        let fa = T::splat(a);
        let (a_v0, a_e0, a_d0) = (fa * v0, fa * e0, fa * d0);
        let (mut vk, mut ek, mut dk, mut d_prev) = (v0, e0, d0, zero);
        let (mut scale_v, mut tol_v) = (v0.abs(), zero);
        self.n = [None; N];
        // Order by order as [`Taylor::series`] grows them: the orders nearly
        // every step needs each its own straight code, the rest in a loop.
        macro_rules! order {
            ($k:expr) => {{
                let k: usize = $k;
                let m = k + 1;
                let inv = T::splat(INV[m]);
                let (c0, cs, t1) = (f0 * inv, k_sin * inv, (f1 * inv) * d_prev);
                let (se, sd) = convolutions(&d[..], &e[..], &v[..], k, zero);
                let ai = T::splat(a * INV[m]);
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
                    let tails = (
                        vm.abs() + vk.abs(),
                        em.abs() + ek.abs(),
                        dm.abs() + dk.abs(),
                    );
                    let bits = tails.0.le3(tol_v, tails.1, tol_e, tails.2, tol_e);
                    if bits != 0 {
                        // Y's last term, as the next order's `ym` would be.
                        y[m + 1] = vm * T::splat(INV[m + 1]);
                        let [ye, ve, ee, de, ae] = lane_ends(&y[..], &v[..], &e[..], &d[..], m);
                        for lane in 0..N {
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
                        if self.n.iter().all(Option::is_some) {
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
    #[inline(always)]
    fn hand(&self, lane: usize, from: Step, stepper: &mut Taylor) {
        let Some(n) = self.n[lane] else { return };
        for i in 0..n + 2 {
            stepper.y[i] = self.y[i].to_lanes()[lane];
        }
        for i in 0..n + 1 {
            stepper.v[i] = self.v[i].to_lanes()[lane];
            stepper.e[i] = self.e[i].to_lanes()[lane];
            stepper.d[i] = self.d[i].to_lanes()[lane];
        }
        stepper.ends = self.ends[lane];
        stepper.built = Some((from.key(), n));
    }
}

/// [`ends`] of the lanes' series, lane by lane.
#[inline(always)]
fn lane_ends<T: Lanes<N>, const N: usize>(
    y: &[T],
    v: &[T],
    e: &[T],
    d: &[T],
    m: usize,
) -> [[f64; N]; 5] {
    let [ye, ve, ee, de, ae] = ends(y, v, e, d, m, T::splat(0.0), T::abs);
    [
        ye.to_lanes(),
        ve.to_lanes(),
        ee.to_lanes(),
        de.to_lanes(),
        ae.to_lanes(),
    ]
}

impl CruisePair for Taylor {
    #[inline(always)]
    fn cruise_pair(
        steppers: [&mut Taylor; 2],
        exc: &Excitation,
        k: usize,
        states: [&mut Rocking; 2],
        tops: [&mut f64; 2],
    ) -> usize {
        let [ta, tb] = steppers;
        let ([st_a, st_b], [top_a, top_b]) = (states, tops);
        let lane = |stepper, state, top| {
            Some(Lane {
                stepper,
                state,
                top,
            })
        };
        let runs = [lane(ta, st_a, top_a), lane(tb, st_b, top_b)];
        cruise_lanes::<F2, 2>(runs, exc, k)
    }
}

impl CruiseLanes<4> for Taylor {
    #[inline(always)]
    fn cruise_lanes(runs: [Option<Lane<'_, Taylor>>; 4], exc: &Excitation, k: usize) -> usize {
        cruise_lanes::<F4, 4>(runs, exc, k)
    }
}

/// Whole intervals while each is one step for every run given and every
/// series proves it eventless, as [`Taylor::cruise`] takes them one run at
/// a time. At the first interval one run cannot cross so, each run's series
/// of it is handed to its stepper ([`LaneSeries::hand`]): the runs then
/// cross it on their own without building it again. A lane without a run
/// (fewer runs than lanes) repeats the first run's, and nothing of it is
/// kept.
#[inline(always)]
fn cruise_lanes<T: Lanes<N>, const N: usize>(
    mut runs: [Option<Lane<'_, Taylor>>; N],
    exc: &Excitation,
    mut k: usize,
) -> usize {
    let Some(first) = runs.iter().flatten().next() else {
        return k;
    };
    let dt = exc.dt_s;
    let t0 = &*first.stepper;
    let (p2_over_alpha, alpha) = (t0.p2_over_alpha, t0.alpha);
    let differs = |t: &Taylor| t.cuts(dt) || t.p != t0.p || t.alpha != t0.alpha;
    if runs.iter().flatten().any(|r| differs(r.stepper)) {
        return k;
    }
    let live = runs.each_ref().map(Option::is_some);
    let (mut s, mut y0, mut w0, mut e0, mut d0) =
        ([0.0; N], [0.0; N], [0.0; N], [0.0; N], [0.0; N]);
    let (mut top, mut limit, mut p2_over_eta) = ([0.0; N], [0.0; N], [0.0; N]);
    let (mut tol, mut tol_e) = ([0.0; N], [0.0; N]);
    for i in 0..N {
        let r = runs[i].as_ref().unwrap_or(first);
        let (t, st) = (&*r.stepper, &*r.state);
        (s[i], y0[i], w0[i]) = (st.s, st.s * st.x, st.s * st.v);
        (e0[i], d0[i]) = t.sin_cos_at(st);
        (top[i], limit[i], p2_over_eta[i]) = (*r.top, t.limit, t.p2_over_eta);
        (tol[i], tol_e[i]) = (t.tol, t.tol_sin_cos());
    }
    let (psi, slope) = (&exc.psi[..], &exc.slope[..]);
    let n = slope.len().min(psi.len());
    let c = Shared {
        p2_over_alpha,
        alpha,
        p2_over_eta: T::from_lanes(p2_over_eta),
        tol: T::from_lanes(tol),
        tol_e: T::from_lanes(tol_e),
    };
    let lanes_s = T::from_lanes(s);
    let start = k;
    let mut series = LaneSeries::<T, N>::new();
    while k < n {
        // `rock`'s forcing at the stretch's start, to the bit.
        let (g_a, g1) = (psi[k] + slope[k] * 0.0, slope[k]);
        series.build(
            &c,
            lanes_s,
            T::from_lanes(y0),
            T::from_lanes(w0),
            T::from_lanes(e0),
            T::from_lanes(d0),
            dt,
            g_a,
            g1,
        );
        // No `array::map` here nor in `lane_ends`: its closures are not
        // compiled with the vector features, and would call the lanes'
        // instructions.
        let ys = [
            series.y[0].to_lanes(),
            series.y[1].to_lanes(),
            series.y[2].to_lanes(),
        ];
        let vs = [series.v[0].to_lanes(), series.v[1].to_lanes()];
        let quiet_lane = |i: usize| {
            !live[i]
                || (series.n[i].is_some()
                    && quiet(
                        [ys[0][i], ys[1][i], ys[2][i]],
                        [vs[0][i], vs[1][i]],
                        &series.ends[i],
                        top[i],
                        limit[i],
                    ))
        };
        if !(0..N).all(quiet_lane) {
            for (i, r) in runs.iter_mut().enumerate() {
                if let Some(r) = r {
                    let from = Step {
                        s: s[i],
                        y0: y0[i],
                        w0: w0[i],
                        e0: e0[i],
                        d0: d0[i],
                        h: dt,
                        g_a,
                        g1,
                    };
                    series.hand(i, from, r.stepper);
                }
            }
            break;
        }
        for i in 0..N {
            let e = series.ends[i];
            top[i] = top[i].max(e.y);
            (y0[i], w0[i], e0[i], d0[i]) = (e.y, e.v / dt, e.e, e.d);
        }
        for r in runs.iter_mut().flatten() {
            r.stepper.steps += 1;
        }
        k += 1;
    }
    if k > start {
        for (i, r) in runs.iter_mut().enumerate() {
            if let Some(r) = r {
                *r.state = Rocking {
                    x: s[i] * y0[i],
                    v: s[i] * w0[i],
                    s: s[i],
                };
                r.stepper.left = Some((*r.state, e0[i], d0[i]));
                *r.top = top[i];
            }
        }
    }
    k
}
