//! Rocking of a free-standing rigid block on a rigid base (pure; no I/O).
//!
//! Equations (docs/MODEL.md §2), with `x = θ/α`, pivot `s = sgn(x)`, the
//! record normalised to unit peak `ψ̈` and `η = αg/A_g`:
//!
//! ```text
//! linearised:  ẍ = p² (x − s) + (p²/η) ψ̈(t)
//! nonlinear:   ẍ = −(p²/α) s sin(α(1 − s x)) + (p²/η) cos(α(1 − s x)) ψ̈(t)
//! ```
//!
//! `ψ̈` is linear between samples. A [`Model`] is an [`Equation`] (which owns
//! α, the uplift threshold, the overturning limit, the right-hand side and
//! the fate after the record) advanced by an [`Integrator`] (which only
//! steps and says why it stopped). The events (MODEL.md §3) are handled once,
//! by the driver behind [`simulate`], whatever the integrator:
//!
//! - **uplift** from rest where the interpolated `|ψ̈|` crosses `η·k`
//!   (`k = 1` linearised, `tan α / α` nonlinear), on the side `sgn ψ̈`;
//! - **impact** at `x = 0`: `ẋ⁺ = ε ẋ⁻`, pivot switch;
//! - **rest** when the speed after an impact is below the rest tolerance
//!   ([`REST_TOL`], relative to `p`);
//! - **overturning** per [`Overturn`];
//! - **after the record** the fate is decided from the free-rocking energy
//!   ([`energy`]) instead of integrating a tail of quiet.
//!
//! Integrators: [`exact`] (closed form, linearised), [`taylor`] (the
//! nonlinear equation's Taylor series, one step per sample interval), [`dp5`]
//! (Dormand–Prince 5(4)), [`rk4`] (fixed-step baseline for benchmarks).
//! Time inside an interval is a local offset from the interval's first
//! sample, so events always advance it.

mod dispatch;
pub mod dp5;
mod driver;
pub mod energy;
pub mod equation;
mod error;
pub mod exact;
mod excitation;
pub mod friction;
mod history;
mod hop;
mod integrator;
pub mod interrupt;
mod lanes;
mod overturn;
pub mod rk4;
mod run;
mod simulate;
mod slide_rock;
mod step;
pub mod taylor;

pub use dispatch::Isa;
pub use driver::{Mode, Outcome, Stop};
pub use equation::{
    check_alpha, linearization_error, Equation, EquationKind, ALPHA_MIN,
    LINEARIZATION_ERROR_PER_ALPHA2,
};
pub use history::{EventKind, HistoryPoint, Observer, Recorder};
pub use integrator::{
    check_auto_tol, check_rtol, Integrator, Model, ModelChoice, NonlinearIntegrator, Solver,
    DEFAULT_RTOL, DEFAULT_TAYLOR_TOL, DP5_TIGHTEST_RTOL, MIN_RTOL, TAYLOR_TIGHTEST_TOL,
};
pub use simulate::{
    simulate, simulate_from, simulate_in_step, simulate_lanes, simulate_observed, simulate_on,
    simulate_pair,
};
pub use step::{Rocking, Stepper, Stretch, StretchEnd};

pub use error::PhysicsError;
pub use excitation::Excitation;
pub use overturn::{escape_proven, Overturn};
pub use run::{check_p, RunSpec, ETA_MIN, MAX_EVENTS, P_RANGE, REST_TOL};
