//! `rocking`: overturning capacity and fragility of free-standing rigid blocks.
//!
//! The tool follows Voyagaki, Psycharis, Mylonakis & Vamvatsikos,
//! "Probabilistic characterization of overturning capacity for
//! simply-supported rigid blocks", as a pipeline of stages over Parquet
//! tables ([`stages::STAGES`], in run order):
//!
//! 1. **ingest**: PEER AT2 files (+ manifest) → `records.parquet`;
//! 2. **sweep**: rocking simulations over an IDA grid → IDA points, capacities;
//! 3. **convergence**: the capacity search at several grid resolutions;
//! 4. **reduce**: fractile statistics with the resurrection rule, bands;
//! 5. **ims**: the records' intensity measures, the capacity's dispersion in each;
//! 6. **example**: the report's example block over every record;
//! 7. **tree**: the example block on each branch of a logic tree;
//! 8. **damage**: damage states' capacities and lognormals in every IM;
//! 9. **fit**: the two-step regression of the capacity against p and ε;
//! 10. **pulses**: the pulse map (safety walls, overturning modes);
//! 11. **report**: the paper's figures, `report.md` and `report.html`.
//!
//! Module map (`ARCHITECTURE.md` has the invariants):
//!
//! - [`ask`]: what a user asks (a block, a search, a fragility, a risk, an
//!   export), one vocabulary for the command line and Python, checked once;
//! - [`at2`], [`manifest`], [`motion`], [`decimal`]: parsing and record
//!   summaries, no I/O;
//! - [`block`]: a block's geometry (α, R, p) and restitution, defined once,
//!   and whether it slides before it rocks, no I/O;
//! - [`sdof`], [`floor`]: a linear oscillator stepped exactly; a building's
//!   floor motion under a record, no I/O;
//! - [`im`]: the intensity measures, every fact about each, a record's
//!   measures, a capacity in any IM, no I/O;
//! - [`physics`]: the equations, integrators and events, no I/O;
//! - [`ida`]: capacity of one record by incremental dynamic analysis, no I/O;
//! - [`damage`]: limit states on the IDA curve, their capacities and lognormal fits, no I/O;
//! - [`export`]: damage-state fragilities as OpenQuake NRML and pelicun CSV text, no I/O;
//! - [`pulse`]: rectangular and exponential pulses, their closed-form walls
//!   (paper Eqs. 3, 5, 6) and walls by simulation, no I/O;
//! - [`pipeline`]: pipeline files (TOML text) → a typed plan, no I/O;
//! - [`stats`], [`fit`]: fractiles (+∞ allowed), Lilliefors, the bootstrap;
//!   the two-step regression, no I/O;
//! - [`fragility`], [`hazard`], [`risk`], [`cut`]: P(overturn | PGA) from the
//!   regression; hazard curves; the annual rate of overturning; the level
//!   below which a block cannot move, no I/O;
//! - [`study`], [`figures`], [`report`], [`plot`]: a study's results, its
//!   figures as chart specifications, its report, SVG, no I/O;
//! - [`label`], [`hash`], [`cluster`], [`outpath`]: closed sets' labels;
//!   SHA-256; Slurm as text; output paths checked;
//! - [`records`]: the records runs shake blocks with: AT2 files found, read,
//!   checked and loaded, a pipeline's selection (reads files);
//! - [`tables`]: the only module that touches Parquet;
//! - [`stages`]: glue, one file per stage, the engine that runs them;
//! - [`ops`]: what the other commands do (capacity batches, fragility,
//!   damage states, risk, export, Slurm submission).
//!
//! The command line is the `rocking` binary (`src/bin/rocking/`); the library
//! does not know clap.

/// The tool's version, raised with any change of a table's schema
/// (ARCHITECTURE.md, "How to add a table").
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// A hash of the library's sources, its lock file and the compiler's version
/// (`build.rs`): the physics can change
/// within a version, and a study's notes name the build that made them.
pub const SOURCES: &str = env!("ROCKING_SOURCE_HASH");

/// The build as a study's notes and `rocking --version` name it:
/// `0.7.0 (sources 0123456789abcdef)`.
pub const BUILD: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (sources ",
    env!("ROCKING_SOURCE_HASH"),
    ")"
);

pub mod ask;
pub mod at2;
pub mod block;
pub mod building;
pub mod cluster;
pub mod columns;
pub mod contents;
pub mod csv_rows;
pub mod cut;
pub mod damage;
pub mod decimal;
pub mod events;
pub mod export;
pub mod figures;
pub mod fit;
pub mod floor;
pub mod fragility;
pub mod gmf;
pub mod hash;
pub mod hazard;
pub mod ida;
pub mod im;
pub mod label;
pub mod manifest;
pub mod motion;
pub mod ops;
pub mod outpath;
pub mod pair;
pub mod physics;
pub mod pipeline;
pub mod plot;
pub mod pulse;
pub mod records;
pub mod report;
pub mod risk;
pub mod sdof;
pub mod stages;
pub mod stats;
pub mod study;
pub mod tables;
pub mod tree;
