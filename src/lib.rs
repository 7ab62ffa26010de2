//! `rocking`: overturning capacity and fragility of free-standing rigid blocks.
//!
//! The tool follows Voyagaki, Psycharis, Mylonakis & Vamvatsikos,
//! "Probabilistic characterization of overturning capacity for
//! simply-supported rigid blocks", as a pipeline of stages over Parquet tables:
//!
//! 1. **ingest**: PEER AT2 files (+ manifest) → `records.parquet`;
//! 2. **sweep**: rocking simulations over an IDA grid → IDA points, capacities;
//! 3. **reduce**: fractile statistics with the resurrection rule;
//! 4. **fit**: the two-step regression of the capacity against p and ε.
//!
//! Module map (see `ARCHITECTURE.md` for the invariants):
//!
//! - [`at2`], [`manifest`], [`motion`]: parsing and record summaries, no I/O;
//! - [`physics`]: the rocking equations, integrators and events, no I/O;
//! - [`ida`]: capacity of one record by incremental dynamic analysis, no I/O;
//! - [`pipeline`]: pipeline files (TOML text) → a typed plan, no I/O;
//! - [`stats`]: fractiles (+∞ allowed), Lilliefors, normal distribution, no I/O;
//! - [`fit`]: the two-step regression (Levenberg–Marquardt, polynomials), no I/O;
//! - [`fragility`]: P(overturn | PGA) of a real block from the regression, no I/O;
//! - [`figures`]: the paper's figures as chart specifications from the tables, no I/O;
//! - [`bench`]: speed-against-error measurements of the solvers (timing only);
//! - [`plot`]: figures as SVG text;
//! - [`tables`]: the only module that touches Parquet;
//! - [`stages`]: glue, one module per stage;
//! - [`cli`]: the only module that knows clap.

pub mod at2;
pub mod bench;
pub mod cli;
pub mod figures;
pub mod fit;
pub mod fragility;
pub mod ida;
pub mod manifest;
pub mod motion;
pub mod physics;
pub mod pipeline;
pub mod plot;
pub mod stages;
pub mod stats;
pub mod tables;
