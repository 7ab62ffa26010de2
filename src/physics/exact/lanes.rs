//! [`crate::physics::Stepper::cruise`] of the exact stepper for two runs at
//! once, one lane each ([`super::super::lanes::F2`]): the lone run's
//! motion ([`Motion::new`], [`Motion::at`]) and sign tests
//! ([`Motion::monotone`]), written once, in two lanes.

use super::closed_form::Motion;
use super::stepper::Exact;
use crate::physics::driver::CruisePair;
use crate::physics::lanes::{Mask, F2};
use crate::physics::step::Rocking;
use crate::physics::Excitation;

/// [`crate::physics::Stepper::cruise`] for two runs at once, steppers of the same `p` and
/// `dt` (two values of η), both rocking at sample `k`: their whole
/// intervals, one lane each, for as long as both are proved eventless by
/// sign tests alone (x monotone, between the pivot and the limit). At the
/// first interval one must leave to `cruise`'s other bounds or to `rock`,
/// the other crosses it where the sign tests prove it eventless (so that
/// the one left behind walks it alone and they go on together, without
/// the other crossing it alone after), and returns where each is. Each
/// lane does what [`Exact::cruise`] does, operation for operation.
impl CruisePair for Exact {
    #[inline(always)]
    fn cruise_pair(
        steppers: [&mut Exact; 2],
        exc: &Excitation,
        k: usize,
        states: [&mut Rocking; 2],
        tops: [&mut f64; 2],
    ) -> [usize; 2] {
        cruise_pair([&*steppers[0], &*steppers[1]], exc, k, states, tops)
    }
}

#[inline(always)]
fn cruise_pair(
    steppers: [&Exact; 2],
    exc: &Excitation,
    mut k: usize,
    states: [&mut Rocking; 2],
    tops: [&mut f64; 2],
) -> [usize; 2] {
    let [sa, sb] = steppers;
    if exc.dt_s != sa.full.sigma || sa.p != sb.p || sa.full.sigma != sb.full.sigma {
        return [k; 2];
    }
    let [st_a, st_b] = states;
    let [top_a, top_b] = tops;
    let (psi, slope) = (&exc.psi[..], &exc.slope[..]);
    let n = slope.len().min(psi.len()).min(exc.psi_end().len());
    let full = sa.full.splat::<F2>();
    let (p, delta_max) = (F2::splat(sa.p), F2::splat(sa.full_expm1));
    let zero = F2::splat(0.0);
    let s = F2::new(st_a.s, st_b.s);
    let s_eta = s * F2::new(sa.eta, sb.eta);
    let inv_eta = F2::new(sa.inv_eta, sb.inv_eta);
    let limit = F2::new(sa.limit, sb.limit);
    let (mut x, mut v) = (F2::new(st_a.x, st_b.x), F2::new(st_a.v, st_b.v));
    let mut top = F2::new(*top_a, *top_b);
    // Where each lane ends: both at `k` unless one crossed the interval
    // the other could not.
    let mut ends = None;
    while k < n {
        // The lone run's motion and sign tests, in two lanes.
        let m = Motion::new(
            p,
            s_eta,
            inv_eta,
            x,
            v,
            F2::splat(psi[k]),
            F2::splat(slope[k]),
        );
        let (x_hi, v_hi) = m.at(&full);
        let y_hi = s * x_hi;
        let inside = y_hi.lt(limit) & y_hi.gt(zero);
        let crossed = inside & m.monotone(v_hi, delta_max);
        // A lane with a turning point inside (or an event) leaves the pair
        // to cross that interval on its own, by `cruise`'s other bounds or
        // `rock`: kept out of this loop, they would crowd its registers.
        // The other crosses it here, as `cruise` would, and waits.
        if !crossed.all() {
            let (one, [xh_a, xh_b], [vh_a, vh_b]) = (crossed.bits(), x_hi.lanes(), v_hi.lanes());
            let ([x_a, x_b], [v_a, v_b]) = (x.lanes(), v.lanes());
            let ([t_a, t_b], [y_a, y_b]) = (top.lanes(), y_hi.lanes());
            // y_hi lies in (0, limit) where a lane crossed: `max` is `f64::max`.
            let (a, b) = (one & 1 != 0, one & 2 != 0);
            x = F2::new(if a { xh_a } else { x_a }, if b { xh_b } else { x_b });
            v = F2::new(if a { vh_a } else { v_a }, if b { vh_b } else { v_b });
            top = F2::new(
                if a { t_a.max(y_a) } else { t_a },
                if b { t_b.max(y_b) } else { t_b },
            );
            ends = Some([k + usize::from(a), k + usize::from(b)]);
            break;
        }
        // y_hi lies in (0, limit) on both lanes: `max` is `f64::max` there.
        top = top.max(y_hi);
        (x, v) = (x_hi, v_hi);
        k += 1;
    }
    let ([xa, xb], [va, vb], [ta, tb]) = (x.lanes(), v.lanes(), top.lanes());
    (st_a.x, st_a.v, st_b.x, st_b.v) = (xa, va, xb, vb);
    (*top_a, *top_b) = (ta, tb);
    ends.unwrap_or([k, k])
}
