//! Runs of the Taylor stepper in step, one lane each of a vector: two in
//! an SSE2 register ([`F2`]), four in an AVX one ([`F4`]). The two runs of
//! a chaos probe follow nearly the same motion, as do a run and its probes
//! at a tighter tolerance (each lane has its own); the probes of
//! neighbouring decisive runs and neighbouring grid levels of a search rock
//! alike for stretches, so their steps can share the series' chain of
//! orders, which bounds a step's time (docs/MODEL.md §3.5): four lanes cost
//! about what two do. The series is [`build`]'s, the one the lone run's
//! [`Taylor::series`] is the one-lane case of, so each run's outcome is the
//! one it has alone, to the bit.

use super::series::{build, Coefficients, Shared};
use super::{quiet, Ends, Step, Taylor, LEN};
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

    /// The series of the lanes' steps ([`build`]), kept here until
    /// [`LaneSeries::hand`] gives each to its stepper.
    #[inline(always)]
    fn build(&mut self, c: &Shared<T>, start: [T; 5], h: f64, g_a: f64, g1: f64) {
        let coeffs = Coefficients {
            y: &mut self.y,
            v: &mut self.v,
            e: &mut self.e,
            d: &mut self.d,
        };
        (self.n, self.ends) = build(coeffs, c, start, h, g_a, g1);
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

impl CruisePair for Taylor {
    #[inline(always)]
    fn cruise_pair(
        steppers: [&mut Taylor; 2],
        exc: &Excitation,
        k: usize,
        states: [&mut Rocking; 2],
        tops: [&mut f64; 2],
    ) -> [usize; 2] {
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
        [cruise_lanes::<F2, 2>(runs, exc, k); 2]
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
        let from = [
            lanes_s,
            T::from_lanes(y0),
            T::from_lanes(w0),
            T::from_lanes(e0),
            T::from_lanes(d0),
        ];
        series.build(&c, from, dt, g_a, g1);
        // No `array::map` here nor in `lane_ends`: its closures are not
        // compiled with the vector features, and would call the lanes'
        // instructions.
        let ys = [
            series.y[0].to_lanes(),
            series.y[1].to_lanes(),
            series.y[2].to_lanes(),
        ];
        let vs = [series.v[0].to_lanes(), series.v[1].to_lanes()];
        // Nor `Iterator::all`: outlined, it was compiled for the baseline
        // and called on every interval (9 % of a Taylor sweep).
        let mut all_quiet = true;
        for i in 0..N {
            all_quiet &= !live[i]
                || (series.n[i].is_some()
                    && quiet(
                        [ys[0][i], ys[1][i], ys[2][i]],
                        [vs[0][i], vs[1][i]],
                        &series.ends[i],
                        top[i],
                        limit[i],
                    ));
        }
        if !all_quiet {
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
