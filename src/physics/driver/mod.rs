//! The event loop shared by every integrator (docs/MODEL.md §3): uplift from
//! rest, impacts (`ẋ⁺ = ε ẋ⁻`, pivot switch), rest, overturning, the record's
//! end and the fate after it. An integrator only advances on one pivot
//! ([`super::Stepper::rock`]); everything an event changes is done here,
//! once: for one run (`event_loop`), and for runs kept in step (`in_step`).

mod base;
mod coupled;
mod event_loop;
mod in_step;

pub use base::Mode;
pub(super) use event_loop::drive;
pub use event_loop::{Outcome, Stop};
pub(super) use in_step::{drive_lanes, drive_pair, CruiseLanes, CruisePair, Lane};
