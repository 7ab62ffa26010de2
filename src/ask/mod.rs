//! What a user asks, in one vocabulary for every front end (pure; no I/O).
//!
//! The command line parses its options into these types, and Python's
//! keyword arguments land in them (deserialised, unknown keys refused);
//! each type's `resolve` does every check of what was asked and builds the
//! library's typed request, so both front ends refuse the same input with
//! the same message, each naming the option in its own spelling
//! ([`Spelling`]). Closed sets inside them are [`crate::label::Label`]s,
//! parsed in one place.
//!
//! - [`block`]: a block (or a grid of blocks) and how to run it: its size
//!   or p and α, ε, μ, the floor it stands on, the model, the integrator
//!   and its tolerance, the overturning criterion;
//! - [`excitation`]: a pulse instead of a record, and the capacity search;
//! - [`assess`]: the blocks of `fragility`, `risk` and `export` (one by its
//!   sizes, or an inventory), where their capacities come from, the levels,
//!   the hazard, the damage states;
//! - `gmf`: risk's hazard as asked, curves or event-based fields;
//! - `tree`: a logic tree named by a request, checked against it;
//! - [`export`]: what `export` is asked, and its keyword arguments, flat,
//!   for Python.

pub mod assess;
pub mod block;
pub mod excitation;
pub mod export;
mod gmf;
mod law;
mod spelling;
mod tree;

pub use assess::{BlocksAsk, FragilityAsk, RiskAsk, StatesAsk};
pub use block::{AskedBlock, BlockAsk};
pub use excitation::{check_angle_step, check_angles, PulseAsk, SearchAsk};
pub use export::{ExportAsk, ExportKw};
pub use gmf::HazardAsk;
pub use law::LawAsk;
pub use spelling::{AskError, Spelling};
