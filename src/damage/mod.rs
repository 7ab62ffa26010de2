//! Damage states of a rocking block from its IDA (pure; MODEL.md §15).
//!
//! A limit state is reached when the block's peak rotation θmax/α reaches a
//! threshold, or when it overturns. Its capacity under one record is the
//! first intensity, as intensity rises, at which the IDA curve reaches it
//! (the resurrection rule: once reached, it stays reached), interpolated
//! linearly in 1/η between the two runs that bracket the crossing. For
//! overturning it is η_c itself. Capacities are stated in η = αg/PGA, as
//! the overturning capacity is; [`crate::im::of_eta`] gives them in any IM.
//!
//! - `states`: the states ([`LimitState`], [`DamageStates`]) and a
//!   record's capacities ([`capacities`]);
//! - `lognormal`: a lognormal fitted to the records' capacities, by the
//!   paper's fractiles or by maximum likelihood with censoring;
//! - `curve`: the records' own curve, linear between their capacities
//!   (no shape assumed), where a lognormal does not fit or is not wanted;
//! - `fit`: every state's lognormals over a suite of records, in one IM.

mod curve;
mod fit;
mod lognormal;
mod states;

pub use curve::Curve;
pub use fit::{fit_states, StateFit};
pub use lognormal::{
    common_dispersion, crossed_pairs, crossing, crossing_above, fractile_method, lognormal_p,
    max_likelihood, Dispersion, FitChoice, FitMethod, IfNotLognormal, Lognormal,
    LOGNORMAL_CHECK_LEVEL,
};
pub use states::{
    capacities, Criterion, DamageError, DamageStates, LimitState, StateCapacity, StateRun, DEFAULT,
};
