//! The one event loop ([`drive`]): uplift from rest, impacts (`ẋ⁺ = ε ẋ⁻`,
//! pivot switch), rest, overturning, the record's end and the fate after
//! it, for one run ([`Driver`], which `in_step` walks several of).

use super::base::{Arm, Coupled, Mode};
use crate::label::Label;
use crate::physics::friction::Contact;
use crate::physics::history::{EventKind, HistoryPoint, Observer};
use crate::physics::step::{Rocking, Stepper, Stretch, StretchEnd};
use crate::physics::{Excitation, RunSpec, MAX_EVENTS};

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The record ended with the block rocking or at rest, and energy says it stays up.
    Survived,
    /// Reached the overturning limit.
    Overturned,
    /// At rest, and the rest of the record stays below the uplift threshold.
    RestForGood,
    /// Hit [`MAX_EVENTS`], or a sliding run stalled at one instant (bug guards).
    EventLimit,
    /// A block that slides: the normal force at its pivot reached 0, so it
    /// would leave the base, which the model does not follow.
    Flight,
}

impl Label for Stop {
    const ALL: &'static [Self] = &[
        Stop::Survived,
        Stop::Overturned,
        Stop::RestForGood,
        Stop::EventLimit,
        Stop::Flight,
    ];
    fn label(self) -> &'static str {
        match self {
            Stop::Survived => "survived",
            Stop::Overturned => "overturned",
            Stop::RestForGood => "rest_for_good",
            Stop::EventLimit => "event_limit",
            Stop::Flight => "flight",
        }
    }
}

/// Summary of one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// max |x| = θmax/α over the run, including the free rocking after the
    /// record (for an overturned block, the overturning limit).
    pub max_abs_x: f64,
    pub stop: Stop,
    /// Time of overturning (s, from the first sample), if it overturned.
    pub overturn_time_s: Option<f64>,
    /// Whether the overturning happens after the record ends.
    pub overturn_after_record: bool,
    pub impacts: u64,
    pub first_uplift_s: Option<f64>,
    /// Sample intervals the run went through before it stopped (work done).
    pub intervals: u64,
    /// A block that slides: the largest |u| of its base relative to the
    /// ground (m), over the run and the slip's end after the record.
    pub slide_max_m: f64,
    /// Where its base ends, relative to where it stood (m, signed; for an
    /// overturned block, where it was when it went over).
    pub slide_residual_m: f64,
    /// How many times the base or the pivot started to slip.
    pub slips: u64,
    /// Seconds of the record spent at rest, sliding, rocking and
    /// slide-rocking (`Mode`'s order); all at rest for a block that cannot
    /// slide is not kept: zeros there.
    pub mode_s: [f64; 4],
}

impl Outcome {
    pub fn overturned(&self) -> bool {
        self.stop == Stop::Overturned
    }
}

/// The state of one run as the driver walks the record.
pub(super) struct Driver<'a, S, O> {
    pub(super) exc: &'a Excitation,
    pub(super) spec: &'a RunSpec,
    limit: f64,
    pub(super) stepper: &'a mut S,
    obs: &'a mut O,
    /// Under `escape` with the linearised model: `limit` is only where the
    /// next proof of escape is tried ([`crate::physics::escape_proven`]).
    escape: bool,
    /// Uplift threshold on |ψ̈| (the equation's factor times η).
    threshold: f64,
    /// Speed after an impact below which the block is at rest.
    pub(super) v_rest: f64,
    /// A block that may slide: its base and the slide-rock stepper.
    pub(super) coupled: Option<Coupled>,
    /// `None`: at rest on the base.
    pub(super) state: Option<Rocking>,
    events: u64,
    pub(super) out: Outcome,
}

/// The event loop, generic over the integrator (monomorphised per stepper).
#[inline(always)]
pub(in crate::physics) fn drive<S: Stepper, O: Observer>(
    exc: &Excitation,
    spec: &RunSpec,
    start: Option<Rocking>,
    limit: f64,
    stepper: &mut S,
    obs: &mut O,
) -> Outcome {
    let mut d = Driver::new(exc, spec, start, limit, stepper, obs);
    let n = exc.psi.len().saturating_sub(1);
    d.emit(0.0, exc.psi[0], EventKind::Start);
    let mut k = 0;
    while k < n {
        if d.advance(&mut k, n, n) == Flow::Stopped {
            d.stopped();
            return d.out;
        }
    }
    d.finish();
    d.out
}

/// Whether a run goes on after [`Driver::advance`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Flow {
    Going,
    /// Overturned, at rest for good or out of events: the outcome is final.
    Stopped,
}

impl<'a, S: Stepper, O: Observer> Driver<'a, S, O> {
    pub(super) fn new(
        exc: &'a Excitation,
        spec: &'a RunSpec,
        start: Option<Rocking>,
        limit: f64,
        stepper: &'a mut S,
        obs: &'a mut O,
    ) -> Self {
        Driver {
            exc,
            spec,
            limit,
            escape: spec
                .overturn
                .needs_escape_proof(spec.model.equation.alpha()),
            stepper,
            obs,
            threshold: spec.eta * spec.model.equation.uplift_factor(),
            v_rest: spec.rest_tol * spec.p,
            coupled: coupled(spec, limit, start.is_some()),
            state: start,
            events: 0,
            out: Outcome {
                max_abs_x: start.map_or(0.0, |st| st.x.abs()),
                stop: Stop::Survived,
                overturn_time_s: None,
                overturn_after_record: false,
                impacts: 0,
                first_uplift_s: None,
                intervals: 0,
                slide_max_m: 0.0,
                slide_residual_m: 0.0,
                slips: 0,
                mode_s: [0.0; 4],
            },
        }
    }

    /// Whether the base slips now (never for a block that cannot slide).
    #[inline(always)]
    fn slipping(&self) -> bool {
        self.coupled.as_ref().is_some_and(|c| c.slipping)
    }

    /// Books a change of mode at `t_s` (a block that may slide only).
    #[inline(always)]
    fn enter(&mut self, mode: Mode, t_s: f64) {
        if let Some(c) = self.coupled.as_mut() {
            c.enter(mode, t_s);
        }
    }

    /// One pass of the event loop from sample `*k` (below `n`, the number of
    /// intervals): a stretch of quiet at rest, or eventless intervals in the
    /// stepper's tight loop up to `cap` (above `*k`, at most `n`), or one
    /// interval walked event by event. Moves `*k` past what it did.
    #[inline(always)]
    pub(super) fn advance(&mut self, k: &mut usize, n: usize, cap: usize) -> Flow {
        let exc = self.exc;
        let plain = self.coupled.is_none();
        let slipping = self.slipping();
        // A block that may slide on a held pivot: one eventless interval at
        // a time, its friction checked at the end as a walked interval's is.
        let held = !plain && !slipping && self.state.is_some();
        if held && !O::SAMPLES && self.cruise_held(*k) {
            self.out.intervals += 1;
            *k += 1;
            return Flow::Going;
        }
        match self.state.as_mut() {
            None if !slipping && exc.suffix_max[*k] <= self.threshold => {
                self.out.stop = Stop::RestForGood;
                return Flow::Stopped;
            }
            None if !O::SAMPLES && !slipping => {
                // At rest: whole intervals with both ends within the
                // threshold lift nothing (the forcing is linear between), as
                // `interval` would find one by one; stop where the record
                // stays below it for good, as the arm above would.
                let (thr, start) = (self.threshold, *k);
                if exc.psi[start].abs() <= thr {
                    *k = exc.quiet_until(start, thr);
                }
                self.out.intervals += (*k - start) as u64;
                if *k == n || *k > start {
                    return Flow::Going;
                }
            }
            Some(st) if !O::SAMPLES && plain => {
                // Eventless whole intervals in the stepper's tight loop.
                let next = self
                    .stepper
                    .cruise(exc, *k, cap, st, &mut self.out.max_abs_x);
                self.out.intervals += (next - *k) as u64;
                *k = next;
                if next == n || next == cap {
                    return Flow::Going;
                }
            }
            _ => {}
        }
        self.out.intervals += 1;
        // The walk of a block that may slide, or of one that cannot, each
        // compiled on its own (the rocking walk carries none of the checks).
        let stopped = if plain {
            self.interval::<false>(*k)
        } else {
            self.interval::<true>(*k)
        };
        if stopped.is_some() {
            return Flow::Stopped;
        }
        self.emit(
            (*k + 1) as f64 * exc.dt_s,
            exc.psi[*k + 1],
            EventKind::Sample,
        );
        *k += 1;
        Flow::Going
    }

    /// At the record's end: the free rocking after it.
    pub(super) fn finish(&mut self) {
        self.emit(self.exc.duration_s(), 0.0, EventKind::RecordEnd);
        if let Some(c) = self.coupled.as_mut() {
            c.close(self.exc.duration_s());
        }
        self.after_record();
        self.stopped();
    }

    /// The run is over (at the record's end or before it): a block that
    /// may slide reports its base and its time in each mode, up to when it
    /// went over or flew, or to the record's end.
    pub(super) fn stopped(&mut self) {
        let end_s = self.exc.duration_s();
        if let Some(c) = self.coupled.as_mut() {
            c.close(self.out.overturn_time_s.unwrap_or(end_s).min(end_s));
            self.out.mode_s = c.mode_s;
            self.out.slide_residual_m = c.u;
        }
    }
}

impl<S: Stepper, O: Observer> Driver<'_, S, O> {
    /// Reports the current state as a history point.
    #[inline(always)]
    pub(super) fn emit(&mut self, t_s: f64, psi: f64, kind: EventKind) {
        let (x, v, pivot) = self.state.map_or((0.0, 0.0, 0), |r| (r.x, r.v, r.s as i8));
        let (u_m, w_mps) = self.coupled.as_ref().map_or((0.0, 0.0), |c| (c.u, c.w));
        self.obs.point(HistoryPoint {
            t_s,
            x,
            v,
            pivot,
            psi,
            u_m,
            w_mps,
            kind,
        });
    }

    /// Walks sample interval `k` event by event. `Some(stop)` ends the run.
    #[inline(always)]
    fn interval<const SLIDES: bool>(&mut self, k: usize) -> Option<Stop> {
        let dt = self.exc.dt_s;
        let (g0, g_end, g1) = (self.exc.psi[k], self.exc.psi_end()[k], self.exc.slope[k]);
        let t_k = k as f64 * dt;
        let mut tau = 0.0;
        // Forcing at `tau`; exactly ±threshold at an uplift instant.
        let mut g_a = g0;
        // At rest after a settling within τ's rounding, on the side of `g_a`.
        let mut held = false;
        while tau < dt {
            self.events += 1;
            if self.events > MAX_EVENTS {
                self.out.stop = Stop::EventLimit;
                return Some(Stop::EventLimit);
            }
            if SLIDES && self.slipping() {
                match self.slipping_arm(t_k, tau, g_a, g1, dt) {
                    Arm::End => return None,
                    Arm::Stopped => return Some(self.out.stop),
                    Arm::At(at) => {
                        tau = at;
                        g_a = g0 + g1 * tau;
                        continue;
                    }
                }
            }
            let Some(mut st) = self.state else {
                // At rest: find where |ψ̈| first exceeds the threshold in [tau, dt].
                let (at, side) = uplift_in(g_a, g_end, g1, dt - tau, self.threshold, held)?;
                held = false;
                tau += at;
                // The forcing at the crossing is exactly ±threshold (or beyond it
                // when the block was already pushed past it at rest).
                g_a = if at > 0.0 { side * self.threshold } else { g_a };
                if SLIDES {
                    self.leave_rest(t_k + tau, g_a, side);
                    continue;
                }
                self.state = Some(Rocking {
                    x: 0.0,
                    v: 0.0,
                    s: side,
                });
                self.out.first_uplift_s.get_or_insert(t_k + tau);
                self.emit(t_k + tau, g_a, EventKind::Uplift);
                continue;
            };
            let stretch = Stretch {
                tau0: tau,
                len: dt - tau,
                g_a,
                g1,
            };
            let (before, max_before) = (st, self.out.max_abs_x);
            let end = self.stepper.rock(stretch, &mut st, &mut self.out.max_abs_x);
            self.state = Some(st);
            if SLIDES {
                let checked = self.slip_check(t_k, tau, stretch, g_end, before, max_before, end);
                if let Some(at) = checked {
                    tau = at;
                    g_a = g0 + g1 * tau;
                    continue;
                }
            }
            match end {
                StretchEnd::End => return None,
                StretchEnd::Overturn { sigma } if self.escape => {
                    tau += sigma;
                    g_a = g0 + g1 * tau;
                    if self.escaped(k, t_k + tau, g_a, st) {
                        return Some(Stop::Overturned);
                    }
                }
                StretchEnd::Overturn { sigma } => {
                    let t = t_k + tau + sigma;
                    self.out.stop = Stop::Overturned;
                    self.out.overturn_time_s = Some(t);
                    self.emit(t, g_a + g1 * sigma, EventKind::Overturn);
                    return Some(Stop::Overturned);
                }
                StretchEnd::Settled { sigma } => {
                    // Settled within τ's rounding (a lift the forcing cannot
                    // sustain): time moves on by an ulp (MODEL.md §3, uplift).
                    let moved = tau + sigma > tau;
                    held = !moved && g1 * g_a <= 0.0;
                    tau = if moved { tau + sigma } else { tau.next_up() };
                    g_a = g0 + g1 * tau;
                    self.state = None;
                    self.enter(Mode::Rest, t_k + tau);
                    self.emit(t_k + tau, g_a, EventKind::Rest);
                }
                StretchEnd::Impact { sigma, v } => {
                    tau += sigma;
                    g_a = g0 + g1 * tau;
                    self.impact(t_k + tau, g_a, st.s, v);
                }
            }
        }
        None
    }

    /// Past the watch level under `escape` at `t_s` in interval `k`, at
    /// `st`: overturned once the bound proves the escape (`true`); else it
    /// watches twice as far out and goes on.
    #[inline(always)]
    fn escaped(&mut self, k: usize, t_s: f64, psi: f64, st: Rocking) -> bool {
        let m_over_eta = self.exc.suffix_max[k] / self.spec.eta;
        if crate::physics::escape_proven(self.spec.p, st, m_over_eta) {
            self.out.max_abs_x = f64::INFINITY;
            self.out.stop = Stop::Overturned;
            self.out.overturn_time_s = Some(t_s);
            self.emit(t_s, psi, EventKind::Overturn);
            return true;
        }
        self.limit *= 2.0;
        self.stepper.set_limit(self.limit);
        false
    }

    /// An impact on a held pivot `s` at `t_s` with velocity `v`: Housner's
    /// map `ẋ⁺ = ε ẋ⁻` onto the other pivot, or rest below the rest speed.
    #[inline(always)]
    fn impact(&mut self, t_s: f64, psi: f64, s: f64, v: f64) {
        self.out.impacts += 1;
        let v_plus = self.spec.eps * v;
        let kind = if v_plus.abs() < self.v_rest {
            self.state = None;
            self.enter(Mode::Rest, t_s);
            EventKind::Rest
        } else {
            self.state = Some(Rocking {
                x: 0.0,
                v: v_plus,
                s: -s,
            });
            EventKind::Impact
        };
        self.emit_impact(t_s, psi, kind);
    }

    /// After the record: free rocking, settled by energy; an overturning
    /// still to come is followed (no forcing) to time it. It starts where
    /// the record ends, or on a base with friction where the slip after it
    /// runs out.
    fn after_record(&mut self) {
        let start = match self.coupled {
            Some(_) => self.after_record_coupled(),
            None => Some(self.exc.duration_s()),
        };
        let Some(start) = start else { return };
        let Some(mut st) = self.state else { return };
        let fate = self
            .spec
            .model
            .equation
            .free_fate(self.spec.p, st, self.spec.eps);
        if !fate.passes_crest {
            self.out.max_abs_x = self.out.max_abs_x.max(fate.max_abs_x);
            return;
        }
        self.out.stop = Stop::Overturned;
        self.out.overturn_after_record = true;
        if self.escape {
            // Decided at the excitation's end: the free motion escapes.
            self.out.max_abs_x = f64::INFINITY;
            self.out.impacts += fate.impacts;
            self.out.overturn_time_s = Some(start);
            self.emit(start, 0.0, EventKind::Overturn);
            return;
        }
        let at_start = st;
        self.out.max_abs_x = self.out.max_abs_x.max(self.limit);
        // At most one impact lies on the way to the limit.
        let mut t = start;
        let horizon = 60.0 / self.spec.p;
        for _ in 0..8 {
            let stretch = Stretch {
                tau0: 0.0,
                len: horizon,
                g_a: 0.0,
                g1: 0.0,
            };
            let mut scratch = 0.0;
            match self.stepper.rock(stretch, &mut st, &mut scratch) {
                StretchEnd::Overturn { sigma } => {
                    self.out.overturn_time_s = Some(t + sigma);
                    break;
                }
                StretchEnd::Settled { .. } => break,
                StretchEnd::Impact { sigma, v } => {
                    t += sigma;
                    self.out.impacts += 1;
                    st = Rocking {
                        x: 0.0,
                        v: self.spec.eps * v,
                        s: -st.s,
                    };
                }
                StretchEnd::End => t += horizon,
            }
        }
        if O::SAMPLES {
            self.replay_after_record(start, at_start);
        }
    }

    /// The free motion after the record as history points, so that a
    /// history shows the overturning its run reports: a point every record
    /// step, the impacts, and the overturning at the time the run found
    /// (stepping over the longer stretches above, whose last bits the
    /// replay's may not share). Only for an observer that takes samples.
    fn replay_after_record(&mut self, mut t: f64, mut st: Rocking) {
        let Some(t_over) = self.out.overturn_time_s else {
            return;
        };
        while t < t_over {
            let len = self.exc.dt_s.min(t_over - t);
            let stretch = Stretch {
                tau0: 0.0,
                len,
                g_a: 0.0,
                g1: 0.0,
            };
            let mut scratch = 0.0;
            match self.stepper.rock(stretch, &mut st, &mut scratch) {
                StretchEnd::End => {
                    t += len;
                    self.state = Some(st);
                    if t < t_over {
                        self.emit(t, 0.0, EventKind::Sample);
                    }
                }
                StretchEnd::Impact { sigma, v } => {
                    t += sigma;
                    st = Rocking {
                        x: 0.0,
                        v: self.spec.eps * v,
                        s: -st.s,
                    };
                    self.state = Some(st);
                    self.emit(t, 0.0, EventKind::Impact);
                }
                StretchEnd::Overturn { .. } | StretchEnd::Settled { .. } => {
                    self.state = Some(st);
                    break;
                }
            }
        }
        self.emit(t_over, 0.0, EventKind::Overturn);
    }
}

/// First offset in `[0, len]` where `|g_a + g1 σ| > threshold`, and its side.
/// Strict: a record that only touches the threshold does not lift the block.
/// `g_b` is the forcing at the end of the stretch, the next sample itself
/// (not `g_a + g1·len`, which can round past a threshold the sample only touches).
/// `held`: the block has just settled within τ's rounding with `g_a` past the
/// threshold and growing no stronger on its side (`g1·g_a ≤ 0`): it lifts
/// off the other side only, where the forcing crosses it there.
#[inline(always)]
fn uplift_in(
    g_a: f64,
    g_b: f64,
    g1: f64,
    len: f64,
    threshold: f64,
    held: bool,
) -> Option<(f64, f64)> {
    if held {
        let side = -g_a.signum();
        let sigma = ((side * threshold - g_a) / g1).clamp(0.0, len);
        return (side * g_b > threshold).then_some((sigma, side));
    }
    if g_a.abs() > threshold {
        return Some((0.0, g_a.signum()));
    }
    if g_b.abs() <= threshold {
        // Linear in σ: if neither end exceeds it, no point between does.
        return None;
    }
    let side = g_b.signum();
    // g_a + g1 σ = side·threshold; the crossing lies in (0, len].
    let sigma = ((side * threshold - g_a) / g1).clamp(0.0, len);
    Some((sigma, side))
}

/// The sliding part of a run whose equation has friction (`on_pivot`: the
/// run starts rocking, its pivot held).
fn coupled(spec: &RunSpec, limit: f64, on_pivot: bool) -> Option<Coupled> {
    let friction = spec.model.equation.friction()?;
    let alpha = spec.model.equation.alpha()?;
    let contact = Contact::new(spec.p, spec.eta, alpha, friction);
    let rtol = spec.model.integrator.tol().unwrap_or(1e-10);
    let mut c = Coupled::new(contact, spec.p, limit, rtol);
    if on_pivot {
        c.enter(Mode::Rock, 0.0);
    }
    Some(c)
}
