//! The exact stepper's constants for one (p, η, dt): the coefficients of a
//! whole sample interval, computed once, and the overturning limit.

use super::closed_form::{Coeffs, Motion};

/// The exact stepper of the linearised equation; one per (p, η, dt).
#[derive(Clone)]
pub struct Exact {
    pub(super) p: f64,
    pub(super) eta: f64,
    pub(super) inv_eta: f64,
    pub(super) limit: f64,
    /// Coefficients of a whole sample interval, computed once.
    pub(super) full: Coeffs,
    /// e^{p·dt} − 1
    pub(super) full_expm1: f64,
}

impl Exact {
    pub fn new(p: f64, eta: f64, dt: f64, limit: f64) -> Self {
        Exact {
            p,
            eta,
            inv_eta: 1.0 / eta,
            limit,
            full: Coeffs::new(p, dt),
            full_expm1: (p * dt).exp_m1(),
        }
    }

    /// The motion on pivot `s` from `(x, v)` under the forcing `g_a + g1·σ`.
    #[inline(always)]
    pub(super) fn motion(&self, x: f64, v: f64, s: f64, g_a: f64, g1: f64) -> Motion {
        Motion::new(self.p, s * self.eta, self.inv_eta, x, v, g_a, g1)
    }
}
