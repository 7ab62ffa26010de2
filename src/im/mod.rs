//! Intensity measures: what they are ([`Im`], every fact about each in
//! [`measure`]), a record's measures from its samples ([`RecordIms`], in
//! [`record`]), a capacity in η as a capacity in any IM ([`scale`]), and
//! how well each predicts a block's overturning ([`efficiency`]) (pure;
//! docs/MODEL.md §1, §7 and §14).
//!
//! The IDA runs, stores and searches in η, whatever the IM: an IM is a view
//! of it. Adding an intensity measure: a variant of [`Im`] with its arms in
//! `measure.rs` (its names, unit, scaling power, dimensionless form and the
//! doors it may pass) and its computation from a record's samples in
//! `record.rs` (`Im::of_record`); the compiler lists every arm. Every list
//! of IMs (the command line's, the tables', the hazard reader's, the
//! exports', Python's) is derived from the enum.

pub mod efficiency;
pub mod measure;
pub mod record;
pub mod rotd;
pub mod scale;

pub use measure::{
    level_text, period_text, pgv_pga_s, Im, Rotated, AVGSA_PERIODS_S, G_M_S2, PERIODS_S,
    SPECTRAL_DAMPING,
};
pub use record::{RecordIms, RecordImsError};
pub use scale::{eta_of_pga, of_eta, pga_of_eta};
