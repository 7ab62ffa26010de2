//! The event loop's arms for a block that may slide (docs/MODEL.md §21):
//! the mode a block leaves rest in, the flat slide, the slide-rock mode,
//! the check that a rocking block's friction holds, and the free motion
//! after the record. [`super::event_loop`]'s interval walk calls them where
//! a run has a [`Coupled`] part; a rocking run has none and never enters
//! them.

use super::base::{Arm, Coupled, Mode, MAX_STILL};
use super::event_loop::{Driver, Stop};
use crate::physics::friction::Onset;
use crate::physics::history::{EventKind, Observer};
use crate::physics::slide_rock::{first_negative, SlideRockEnd, Slipping};
use crate::physics::step::{Rocking, Stepper, Stretch, StretchEnd};

impl<S: Stepper, O: Observer> Driver<'_, S, O> {
    /// The coupled part (only called where there is one).
    fn c(&mut self) -> &mut Coupled {
        self.coupled.as_mut().expect("a coupled run")
    }

    /// Interval `k` of a block on a held pivot by the stepper's fast path,
    /// if it proves the interval eventless and the friction holds at its
    /// end (`true`); else the state is left as it was, for the interval to
    /// be walked (the fast path's arithmetic is the walk's, so either way
    /// the run is the same to the bit).
    pub(super) fn cruise_held(&mut self, k: usize) -> bool {
        let Some(mut st) = self.state else {
            return false;
        };
        let (exc, max_before) = (self.exc, self.out.max_abs_x);
        if self
            .stepper
            .cruise(exc, k, k + 1, &mut st, &mut self.out.max_abs_x)
            == k
        {
            return false;
        }
        let mu = self.c().contact.friction.mu_s;
        let forces = self
            .c()
            .contact
            .rock_forces(st.s, st.x, st.v, exc.psi_end()[k]);
        if forces.margin(mu) < 0.0 {
            self.out.max_abs_x = max_before;
            return false;
        }
        self.state = Some(st);
        true
    }

    /// A block at rest leaves it at `t_s` towards `side` under forcing
    /// `psi` (past rest's threshold) in the mode the contact gives.
    pub(super) fn leave_rest(&mut self, t_s: f64, psi: f64, side: f64) {
        let onset = self.c().contact.onset(psi, side);
        let (mode, kind) = match onset {
            Onset::Slide { dir } => {
                let c = self.c();
                (c.slipping, c.dir, c.w) = (true, dir, 0.0);
                (Mode::Slide, EventKind::Slip)
            }
            Onset::Rock { s } => {
                self.state = Some(Rocking { x: 0.0, v: 0.0, s });
                (Mode::Rock, EventKind::Uplift)
            }
            Onset::SlideRock { s, dir } => {
                self.state = Some(Rocking { x: 0.0, v: 0.0, s });
                let c = self.c();
                (c.slipping, c.dir, c.w) = (true, dir, 0.0);
                (Mode::SlideRock, EventKind::Slip)
            }
        };
        if mode != Mode::Slide {
            self.out.first_uplift_s.get_or_insert(t_s);
        }
        if mode != Mode::Rock {
            self.out.slips += 1;
        }
        self.c().enter(mode, t_s);
        self.emit(t_s, psi, kind);
    }

    /// A slipping block from offset `tau` of the interval starting at
    /// `t_k` (forcing `g_a + g1 σ`, length `dt`): flat or on its pivot.
    /// A run whose events stop moving time on ([`MAX_STILL`] of them in a
    /// row) is stopped as [`Stop::EventLimit`].
    pub(super) fn slipping_arm(&mut self, t_k: f64, tau: f64, g_a: f64, g1: f64, dt: f64) -> Arm {
        let arm = match self.state {
            None => self.slide_arm(t_k, tau, g_a, g1, dt),
            Some(_) => {
                let stretch = Stretch {
                    tau0: tau,
                    len: dt - tau,
                    g_a,
                    g1,
                };
                self.slide_rock_arm(t_k, tau, stretch)
            }
        };
        // Counted where an arm ends at the instant the one before it ended
        // (whatever moved time on between them resets it).
        let c = self.c();
        (c.still, c.still_at) = match arm {
            Arm::At(at) if t_k + at == c.still_at => (c.still + 1, c.still_at),
            Arm::At(at) => (0, t_k + at),
            _ => (0, f64::NAN),
        };
        if c.still > MAX_STILL {
            self.out.stop = Stop::EventLimit;
            return Arm::Stopped;
        }
        arm
    }

    /// The flat slide from offset `tau` to the interval's end or the
    /// slip's stop.
    fn slide_arm(&mut self, t_k: f64, tau: f64, g_a: f64, g1: f64, dt: f64) -> Arm {
        let c = self.c();
        let flat = c.contact.slide(c.w, c.dir, g_a, g1, dt - tau);
        c.u += flat.du;
        c.w = flat.w;
        self.out.slide_max_m = self.out.slide_max_m.max(self.c().u.abs());
        let Some(sigma) = flat.stop else {
            return Arm::End;
        };
        // Held: where the forcing still exceeds rest's threshold the rest
        // arm starts the next slip, by the one test that started this one.
        // A slip that could not start (stopped where it began, the forcing
        // on the threshold within rounding) moves time on by an ulp, as a
        // settling within τ's rounding does.
        let at = if tau + sigma > tau {
            tau + sigma
        } else {
            tau.next_up()
        };
        let psi = g_a + g1 * (at - tau);
        let c = self.c();
        c.slipping = false;
        c.enter(Mode::Rest, t_k + at);
        self.emit(t_k + at, psi, EventKind::Stick);
        Arm::At(at)
    }

    /// The slide-rock mode from offset `tau` to the interval's end or its
    /// first event.
    pub(super) fn slide_rock_arm(&mut self, t_k: f64, tau: f64, stretch: Stretch) -> Arm {
        let Some(st) = self.state else {
            unreachable!("slide-rock is on a pivot")
        };
        let c = self.coupled.as_mut().expect("a coupled run");
        let mut slipping = Slipping {
            st,
            u: c.u,
            w: c.w,
            dir: c.dir,
        };
        let end = c
            .stepper
            .advance(stretch, &mut slipping, &mut self.out.max_abs_x);
        (c.u, c.w) = (slipping.u, slipping.w);
        self.state = Some(slipping.st);
        self.out.slide_max_m = self.out.slide_max_m.max(c.u.abs());
        let (sigma, kind) = match end {
            SlideRockEnd::End => return Arm::End,
            SlideRockEnd::Overturn { sigma } => {
                let t = t_k + tau + sigma;
                self.out.stop = Stop::Overturned;
                self.out.overturn_time_s = Some(t);
                self.emit(t, stretch.g_a + stretch.g1 * sigma, EventKind::Overturn);
                return Arm::Stopped;
            }
            SlideRockEnd::Flight { sigma } => {
                let t = t_k + tau + sigma;
                self.out.stop = Stop::Flight;
                self.c().close(t);
                self.emit(t, stretch.g_a + stretch.g1 * sigma, EventKind::Flight);
                return Arm::Stopped;
            }
            SlideRockEnd::Impact { sigma } => {
                let psi = stretch.g_a + stretch.g1 * sigma;
                self.impact_slipping(t_k + tau + sigma, psi, slipping.st);
                return Arm::At(tau + sigma);
            }
            SlideRockEnd::Stick { sigma } => (sigma, EventKind::Stick),
        };
        let psi = stretch.g_a + stretch.g1 * sigma;
        let st = slipping.st;
        let c = self.c();
        match c.contact.after_stick(st.s, st.x, st.v, psi) {
            Some(dir) => {
                c.dir = dir;
                self.out.slips += 1;
            }
            None => {
                c.slipping = false;
                c.enter(Mode::Rock, t_k + tau + sigma);
            }
        }
        self.emit(t_k + tau + sigma, psi, kind);
        Arm::At(tau + sigma)
    }

    /// An impact while the pivot slips, `st` at it: the whole velocity is
    /// scaled by ε (the rotation's as Housner's, the base's alike), so the
    /// impact keeps ε² of the kinetic energy; the block goes on to the
    /// other pivot, or lands flat below the rest speed.
    fn impact_slipping(&mut self, t_s: f64, psi: f64, st: Rocking) {
        self.out.impacts += 1;
        let (eps, v_rest) = (self.spec.eps, self.v_rest);
        let v_plus = eps * st.v;
        let c = self.c();
        c.w *= eps;
        let slips = c.w != 0.0;
        c.slipping = slips;
        let kind = if v_plus.abs() < v_rest {
            if !slips {
                self.state = None;
                self.c().enter(Mode::Rest, t_s);
            } else if self.c().contact.slides_flat() {
                self.state = None;
                self.c().enter(Mode::Slide, t_s);
            } else {
                // Too rough to slide flat: the slip tips it onto the corner
                // it slides towards.
                let dir = self.c().dir;
                self.state = Some(Rocking {
                    x: 0.0,
                    v: 0.0,
                    s: dir,
                });
                self.emit(t_s, psi, EventKind::Impact);
                return;
            }
            EventKind::Rest
        } else {
            self.state = Some(Rocking {
                x: 0.0,
                v: v_plus,
                s: -st.s,
            });
            if !slips {
                self.c().enter(Mode::Rock, t_s);
            }
            EventKind::Impact
        };
        self.emit_impact(t_s, psi, kind);
    }

    /// An impact's row, and where it settles the block the `rest` row
    /// after it: the history has an `impact` row for each impact the run
    /// counts (the settling one was written as `rest` alone).
    pub(super) fn emit_impact(&mut self, t_s: f64, psi: f64, kind: EventKind) {
        if kind == EventKind::Rest {
            self.emit(t_s, psi, EventKind::Impact);
        }
        self.emit(t_s, psi, kind);
    }

    /// After a rocking stretch from `before` that ended in `end` (its state
    /// now in `self.state`): whether the friction held throughout, checked
    /// at the stretch's end; if it did not, the instant it gave way (by
    /// bisection on the stretch, each trial the stepper from `before`), the
    /// state there, and the slip begun. `max_before` is the run's max |x|
    /// before the stretch.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn slip_check(
        &mut self,
        t_k: f64,
        tau: f64,
        stretch: Stretch,
        g_end: f64,
        before: Rocking,
        max_before: f64,
        end: StretchEnd,
    ) -> Option<f64> {
        let sigma_end = match end {
            StretchEnd::End => stretch.len,
            StretchEnd::Impact { sigma, .. }
            | StretchEnd::Overturn { sigma }
            | StretchEnd::Settled { sigma } => sigma,
        };
        let mu = self.c().contact.friction.mu_s;
        let margin = |d: &Self, st: Rocking, sigma: f64| {
            let c = d.coupled.as_ref().expect("a coupled run");
            let psi = stretch.g_a + stretch.g1 * sigma;
            c.contact.rock_forces(st.s, st.x, st.v, psi).margin(mu)
        };
        let st_end = self.state?;
        // At the interval's end, its forcing as the fast path reads it.
        let m_end = match end {
            StretchEnd::End => {
                let c = self.c();
                let forces = c.contact.rock_forces(st_end.s, st_end.x, st_end.v, g_end);
                forces.margin(mu)
            }
            _ => margin(self, st_end, sigma_end),
        };
        if matches!(end, StretchEnd::Settled { .. }) || m_end >= 0.0 {
            return None;
        }
        let m_start = margin(self, before, 0.0);
        let (hi, (st_hi, top_hi)) = if m_start < 0.0 {
            // It gives way at once (just after an impact or an uplift).
            (0.0, (before, max_before))
        } else {
            // To a few ulps of the record's time: far below any reported
            // digit, and above the lengths where a stepper's series lose theirs.
            let floor = 1e-14 * (self.exc.duration_s() + 1.0);
            first_negative(
                (0.0, m_start),
                (sigma_end, m_end),
                (st_end, self.out.max_abs_x),
                floor,
                |len| {
                    let (mut st, mut top) = (before, max_before);
                    let part = Stretch { len, ..stretch };
                    self.stepper.rock(part, &mut st, &mut top);
                    (margin(self, st, len), (st, top))
                },
            )
        };
        self.out.max_abs_x = top_hi;
        self.state = Some(st_hi);
        let psi = stretch.g_a + stretch.g1 * hi;
        let forces = self.c().contact.rock_forces(st_hi.s, st_hi.x, st_hi.v, psi);
        let c = self.c();
        (c.slipping, c.dir, c.w) = (true, -forces.f.signum(), 0.0);
        c.enter(Mode::SlideRock, t_k + tau + hi);
        self.out.slips += 1;
        self.emit(t_k + tau + hi, psi, EventKind::Slip);
        Some(tau + hi)
    }

    /// The record is over: the slip runs out with no forcing (a flat slide
    /// in closed form, a slipping pivot stepped until it holds, lands or
    /// overturns), then the rocking block's fate as the rocking model's.
    /// `None` where the block overturned on the way; else the time the
    /// slip ran out, from which the rocking block's fate is followed.
    pub(super) fn after_record_coupled(&mut self) -> Option<f64> {
        let mut t = self.exc.duration_s();
        let horizon = 60.0 / self.spec.p;
        let free = Stretch {
            tau0: 0.0,
            len: horizon,
            g_a: 0.0,
            g1: 0.0,
        };
        for _ in 0..10_000 {
            if !self.c().slipping {
                break;
            }
            if self.state.is_none() {
                let c = self.c();
                let flat = c.contact.slide(c.w, c.dir, 0.0, 0.0, f64::INFINITY);
                c.u += flat.du;
                (c.w, c.slipping) = (0.0, false);
                self.out.slide_max_m = self.out.slide_max_m.max(self.c().u.abs());
                break;
            }
            match self.slide_rock_arm(t, 0.0, free) {
                Arm::Stopped => {
                    self.out.overturn_after_record = self.out.stop == Stop::Overturned;
                    return None;
                }
                Arm::End => t += horizon,
                Arm::At(sigma) => t += sigma,
            }
        }
        Some(t)
    }
}
