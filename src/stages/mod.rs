//! Pipeline stages: glue between the domain modules and the tables.
//!
//! A stage takes a typed configuration, reads its input tables or files,
//! calls pure domain code and writes its output tables through
//! [`crate::tables`]. Stages print nothing: they return a report that the CLI
//! presents.
//!
//! Stages so far: [`ingest`] (AT2 files → records table) and [`sweep`] (IDA
//! of every record × block → IDA points and capacities). Reduce and fit
//! follow the same shape.

pub mod convergence;
pub mod fit;
pub mod ingest;
pub mod reduce;
pub mod report;
pub mod run;
pub mod sweep;
