//! Incremental dynamic analysis: the overturning capacity of one record
//! (pure; MODEL.md §4).
//!
//! How the parts fit, each using only those listed before it:
//!
//! - `grid`: the intensity levels ([`ImGrid`]);
//! - `capacity`: what a search finds ([`Capacity`], its [`IdaPoint`]s);
//! - `runs`: the record's simulations, remembered ([`Runs`]), run ahead
//!   of need by a [`Batch`] of workers;
//! - `decisive`: the runs whose verdicts decide a capacity, and their
//!   chaos probes;
//! - `search`: the levels up to the first overturning, then bisection
//!   ([`capacity()`], [`capacity_in`]);
//! - `certify`: the search checked at a tighter tolerance and for chaos
//!   ([`capacity_certified`]).

mod capacity;
mod certify;
mod decisive;
mod grid;
mod hard_cases;
mod runs;
mod search;

pub use capacity::{Capacity, IdaPoint, RunKind, Trace};
pub use certify::{
    capacity_certified, capacity_certified_in, Certification, CertificationKind, Certified, TIGHTEN,
};
pub use decisive::{decisive_runs, tol_warning, CHAOS_PROBE, NEAR_MISS};
pub use grid::{ImGrid, Spacing, DEFAULT_TOL, MAX_LEVELS};
pub use hard_cases::{HardCase, HARD_CASES};
pub use runs::{run_pair, Batch, Hand, Runs, Work};
pub use search::{capacity, capacity_in, capacity_traced};
