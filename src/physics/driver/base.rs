//! The sliding base of a run whose equation has friction: its modes
//! ([`Mode`]), its state and stepper ([`Coupled`]), and what an arm of the
//! interval walk did ([`Arm`]). The arms themselves are `coupled`'s.

use crate::label::Label;
use crate::physics::friction::Contact;
use crate::physics::slide_rock::SlideRock;

/// What a block on a frictional base is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Flat and held.
    Rest,
    /// Flat, its base slipping.
    Slide,
    /// On a pivot held by friction.
    Rock,
    /// On a pivot that slips.
    SlideRock,
}

impl Label for Mode {
    const ALL: &'static [Self] = &[Mode::Rest, Mode::Slide, Mode::Rock, Mode::SlideRock];
    fn label(self) -> &'static str {
        match self {
            Mode::Rest => "rest",
            Mode::Slide => "slide",
            Mode::Rock => "rock",
            Mode::SlideRock => "slide-rock",
        }
    }
}

/// The sliding part of a run: the contact's mechanics, the slide-rock
/// stepper, the base's position and velocity, and the time in each mode.
pub(in crate::physics) struct Coupled {
    pub(super) contact: Contact,
    pub(super) stepper: SlideRock,
    /// The base's position (m) and velocity (m/s) relative to the ground.
    pub(super) u: f64,
    pub(super) w: f64,
    /// Whether the base (flat) or the pivot slips, and towards which side.
    pub(super) slipping: bool,
    pub(super) dir: f64,
    /// Seconds spent in each mode ([`Mode`]'s order) up to `since_s`.
    pub(super) mode_s: [f64; 4],
    since_s: f64,
    mode: Mode,
    /// The record is over: the time in modes is booked.
    closed: bool,
    /// Slipping arms in a row that ended at one instant, `still_at` (s)
    /// ([`MAX_STILL`]).
    pub(super) still: u32,
    pub(super) still_at: f64,
}

/// Events in a row at one instant of a sliding run that stop it as
/// [`super::Stop::EventLimit`] (a bug guard, as [`crate::physics::MAX_EVENTS`]
/// is): a slip's stop and start, or an impact and a stop, come at one
/// instant a few times, never thousands.
pub(super) const MAX_STILL: u32 = 10_000;

impl Coupled {
    pub(in crate::physics) fn new(contact: Contact, p: f64, limit: f64, rtol: f64) -> Self {
        Coupled {
            stepper: SlideRock::new(contact, p, limit, rtol),
            contact,
            u: 0.0,
            w: 0.0,
            slipping: false,
            dir: 0.0,
            mode_s: [0.0; 4],
            since_s: 0.0,
            mode: Mode::Rest,
            closed: false,
            still: 0,
            still_at: f64::NAN,
        }
    }

    /// Books the time since the last change to the mode it was in, and
    /// enters `mode` at `t_s` (during the record; after it, nothing).
    pub(super) fn enter(&mut self, mode: Mode, t_s: f64) {
        if self.closed {
            return;
        }
        self.mode_s[self.mode as usize] += t_s - self.since_s;
        self.since_s = t_s;
        self.mode = mode;
    }

    /// Books the time up to the record's end, `t_s`.
    pub(super) fn close(&mut self, t_s: f64) {
        self.enter(self.mode, t_s);
        self.closed = true;
    }
}

/// What a coupled arm did to the interval walk.
#[derive(Debug, Clone, Copy)]
pub(super) enum Arm {
    /// The interval is done.
    End,
    /// An event at the new offset `tau`: walk on from there.
    At(f64),
    /// The run is over (its stop in the outcome).
    Stopped,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_are_labelled_in_order() {
        let labels: Vec<_> = Mode::ALL.iter().map(|m| m.label()).collect();
        assert_eq!(labels, ["rest", "slide", "rock", "slide-rock"]);
        assert_eq!(Mode::SlideRock as usize, 3);
    }
}
