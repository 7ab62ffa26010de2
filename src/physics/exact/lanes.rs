//! [`crate::physics::Stepper::cruise`] of the exact stepper for two or
//! four runs at once, one lane each ([`F2`], [`F4`]): the lone run's
//! motion ([`Motion::new`], [`Motion::at`]) and proofs
//! ([`Motion::monotone`], [`Motion::apex_below`], [`Motion::valley_above`]),
//! written once, in lanes, and the event loop's rest test.

use super::closed_form::Motion;
use super::proofs::Bounds;
use super::stepper::Exact;
use crate::physics::driver::{CruiseLanes, Lane};
use crate::physics::lanes::{Lanes, Mask, F2, F4};
use crate::physics::step::Rocking;
use crate::physics::Excitation;

/// The levels of an IDA in lanes ([`crate::physics::driver::drive_lanes`]):
/// up to four runs of one block and record at several values of η, each
/// rocking or at rest, crossed interval by interval in one AVX register.
impl CruiseLanes<4> for Exact {
    const RESTS_IN_LANES: bool = true;

    #[inline(always)]
    fn cruise_lanes(runs: [Option<Lane<'_, Exact>>; 4], exc: &Excitation, k: usize) -> [usize; 4] {
        cruise_levels::<F4, 4>(runs, exc, k)
    }
}

/// Two runs (a chaos probe's pair) in the two lanes of an SSE2 register.
impl CruiseLanes<2> for Exact {
    const RESTS_IN_LANES: bool = true;

    #[inline(always)]
    fn cruise_lanes(runs: [Option<Lane<'_, Exact>>; 2], exc: &Excitation, k: usize) -> [usize; 2] {
        cruise_levels::<F2, 2>(runs, exc, k)
    }
}

/// [`CruiseLanes::cruise_lanes`] of the exact stepper in the lanes of `T`:
/// from sample `k`, whole intervals while every lane crosses them without
/// an event: a rocking lane where [`Exact::cruise`] would (its motion
/// monotone, or its one turning point proved harmless, between the pivot
/// and the limit), a lane at rest where the forcing stays within its
/// threshold at both ends and the record does not stay below it for good
/// (as the event loop's rest arms decide). At the first interval some lane
/// cannot cross, the lanes that can cross it (their state at the next
/// sample) and the others are left at its start, to walk it on their own.
/// Each lane does what `cruise` does alone, operation for operation.
#[inline(always)]
fn cruise_levels<T: Lanes<N>, const N: usize>(
    mut runs: [Option<Lane<'_, Exact>>; N],
    exc: &Excitation,
    k0: usize,
) -> [usize; N] {
    let Some(first) = runs.iter().flatten().next() else {
        return [k0; N];
    };
    let e0 = &*first.stepper;
    let (p, sigma) = (e0.p, e0.full.sigma);
    let differs = |e: &Exact| e.p != p || e.full.sigma != sigma;
    if exc.dt_s != sigma || runs.iter().flatten().any(|r| differs(r.stepper)) {
        return [k0; N];
    }
    let (full, bounds) = (e0.full.splat::<T>(), e0.bounds());
    let bounds = Bounds {
        p2: T::splat(bounds.p2),
        inv_eta: T::splat(0.0),
        dt: T::splat(bounds.dt),
    };
    let (mut s, mut s_eta, mut inv_eta, mut limit) = ([1.0; N], [0.0; N], [1.0; N], [1.0; N]);
    let (mut x, mut v, mut top, mut threshold) = ([0.0; N], [0.0; N], [0.0; N], [0.0; N]);
    let (mut rocking, mut dead) = ([0.0; N], [1.0; N]);
    for (i, run) in runs.iter().enumerate() {
        let Some(r) = run else { continue };
        let e = &*r.stepper;
        (inv_eta[i], limit[i], top[i], threshold[i], dead[i]) =
            (e.inv_eta, e.limit, *r.top, r.threshold, 0.0);
        s_eta[i] = s[i] * e.eta;
        if let Some(st) = *r.state {
            (s[i], x[i], v[i], rocking[i]) = (st.s, st.x, st.v, 1.0);
            s_eta[i] = st.s * e.eta;
        }
    }
    let zero = T::splat(0.0);
    let (rocking, dead) = (
        T::from_lanes(rocking).gt(zero),
        T::from_lanes(dead).gt(zero),
    );
    let (s, s_eta, inv_eta) = (
        T::from_lanes(s),
        T::from_lanes(s_eta),
        T::from_lanes(inv_eta),
    );
    let (limit, threshold) = (T::from_lanes(limit), T::from_lanes(threshold));
    let bounds = Bounds { inv_eta, ..bounds };
    let (p_lanes, delta_max) = (T::splat(p), T::splat(e0.full_expm1));
    let (mut x, mut v, mut top) = (T::from_lanes(x), T::from_lanes(v), T::from_lanes(top));
    let (psi, psi_end, slope, suffix) = (
        &exc.psi[..],
        exc.psi_end(),
        &exc.slope[..],
        &exc.suffix_max[..],
    );
    let n = slope
        .len()
        .min(psi.len())
        .min(psi_end.len())
        .min(suffix.len());
    // No lane at rest (a lane without a run crosses every interval).
    let all_rocking = (rocking | dead).all();
    let mut k = k0;
    let mut at = [k0; N];
    while k < n {
        let (g0, g_end) = (T::splat(psi[k]), T::splat(psi_end[k]));
        let m = Motion::new(p_lanes, s_eta, inv_eta, x, v, g0, T::splat(slope[k]));
        let (x_hi, v_hi) = m.at(&full);
        let y_hi = s * x_hi;
        let inside = y_hi.lt(limit) & y_hi.gt(zero);
        let monotone = m.monotone(v_hi, delta_max);
        if all_rocking {
            if (inside & monotone | dead).all() {
                // The common case, every lane rocking monotone: y_hi lies in
                // (0, limit), where `max` is `f64::max` (a lane without a run
                // computes what it may: nothing of it is kept).
                (x, v, top) = (x_hi, v_hi, top.max(y_hi));
                k += 1;
                continue;
            }
        }
        let quiet = !rocking
            & g0.abs().le(threshold)
            & g_end.abs().le(threshold)
            & T::splat(suffix[k]).gt(threshold);
        let mut moves = rocking & inside & monotone;
        let mut crossed = dead | moves | quiet;
        if !crossed.all() {
            // Turning points proved harmless.
            let proved = m.apex_below(&bounds, s, v_hi, g0, g_end, top)
                | m.valley_above(&bounds, s, v_hi, g0, g_end);
            moves = moves | (rocking & inside & proved);
            crossed = dead | moves | quiet;
        }
        (x, v, top) = (
            T::select(moves, x_hi, x),
            T::select(moves, v_hi, v),
            T::select(moves, top.max(y_hi), top),
        );
        if crossed.all() {
            k += 1;
            continue;
        }
        // The lanes that cross this interval did; the others stay at it.
        let bits = crossed.bits();
        for (i, a) in at.iter_mut().enumerate() {
            *a = k + usize::from(bits & (1 << i) != 0);
        }
        break;
    }
    if k == n {
        at = [n; N];
    }
    let (x, v, top) = (x.to_lanes(), v.to_lanes(), top.to_lanes());
    for (i, run) in runs.iter_mut().enumerate() {
        let Some(r) = run else { continue };
        if let Some(st) = *r.state {
            // Whole, as the walk reads it (not field by field).
            *r.state = Some(Rocking {
                x: x[i],
                v: v[i],
                s: st.s,
            });
            *r.top = top[i];
        }
    }
    at
}
