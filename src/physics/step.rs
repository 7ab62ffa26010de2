//! The stepper's vocabulary: the state on one pivot ([`Rocking`]), a stretch of
//! a sample interval ([`Stretch`]), how a stretch ended ([`StretchEnd`]) and
//! the trait every integrator implements ([`Stepper`]).

use super::Excitation;

/// State of a rocking block: position, velocity, pivot `s = ±1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rocking {
    pub x: f64,
    pub v: f64,
    pub s: f64,
}

/// One stretch of a sample interval: from local offset `tau0` to `len`,
/// with `ψ̈(tau0 + σ) = g_a + g1 σ`.
#[derive(Debug, Clone, Copy)]
pub struct Stretch {
    pub tau0: f64,
    pub len: f64,
    pub g_a: f64,
    pub g1: f64,
}

/// How a stretch ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StretchEnd {
    /// Reached the end of the stretch without an event.
    End,
    /// Returned to `x = 0` at local offset `sigma` (from `tau0`) with velocity `v`.
    Impact { sigma: f64, v: f64 },
    /// Reached the overturning limit at `sigma`.
    Overturn { sigma: f64 },
    /// Never left the pivot (a departure swamped by rounding): at rest from
    /// `sigma` on, with no impact.
    Settled { sigma: f64 },
}

/// An integrator on one pivot.
pub trait Stepper {
    /// Advances `state` over `stretch` or to its first event; raises
    /// `max_abs_x` to every extremum passed. On `End` and `Overturn`, `state`
    /// is the state at that instant (at overturning `|x|` is the limit); on
    /// `Impact` it is left for the driver to apply the impact map.
    fn rock(&mut self, stretch: Stretch, state: &mut Rocking, max_abs_x: &mut f64) -> StretchEnd;

    /// Moves the `|x|` at which [`Stepper::rock`] reports `Overturn` (the
    /// driver raises it when a run under `escape` passes it unproven).
    fn set_limit(&mut self, limit: f64);

    /// A fast path over whole sample intervals from `k` up to `end`
    /// (exclusive): advances `state` through every interval it can prove
    /// eventless (no impact, no overturning, nothing for [`Stepper::rock`] to
    /// locate) with the same arithmetic `rock` would use, raises `max_abs_x`,
    /// and returns the first interval it left to `rock` (or `end`). The
    /// default proves nothing.
    #[inline]
    fn cruise(
        &mut self,
        _exc: &Excitation,
        k: usize,
        _end: usize,
        _state: &mut Rocking,
        _max_abs_x: &mut f64,
    ) -> usize {
        k
    }
}
