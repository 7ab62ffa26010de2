//! Pipeline stages: glue between the domain modules and the tables.
//!
//! Each stage is one file implementing [`Stage`] and one line of
//! [`STAGES`]; the engine ([`engine`]) runs them in that order, each only
//! when its fingerprint ([`fingerprint`]) says it is stale, under the study
//! folder's lock ([`lock`]). Stages print nothing: they report through a
//! [`Reporter`] and return a [`Summary`].
//!
//! To add a stage: write `stages/<name>.rs` with a unit struct implementing
//! [`Stage`] (name, help, settings, inputs, outputs, run), declare the module
//! below, and put it in [`STAGES`] after the stages whose outputs it reads.
//! `rocking run`, `rocking status`, `--from`, `--to` and a `rocking <name>`
//! command follow from that line.

pub mod convergence;
pub mod damage;
pub mod engine;
pub mod example;
pub mod fingerprint;
pub mod fit;
pub mod ims;
pub mod ingest;
mod load;
pub mod lock;
pub mod pulses;
pub mod reason;
pub mod reduce;
pub mod report;
pub mod stage;
pub mod sweep;
pub mod tree;

pub use reason::{Reason, Skip, Stale};
pub use stage::{
    BoxError, Context, LoadError, Progress, Reporter, Shard, Silent, Stage, StageEvent, Study,
    Summary,
};

/// Every stage, in run order (a stage reads only what earlier ones write).
pub static STAGES: &[&dyn Stage] = &[
    &ingest::Ingest,
    &sweep::Sweep,
    &convergence::Convergence,
    &reduce::Reduce,
    &ims::Ims,
    &example::Example,
    &tree::Tree,
    &damage::Damage,
    &fit::Fit,
    &pulses::Pulses,
    &report::Report,
];
