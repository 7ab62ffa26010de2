//! One run's specification ([`RunSpec`]: the block, the intensity, the
//! model and the overturning criterion) and the ranges it is checked
//! against.

use super::error::PhysicsError;
use super::integrator::Model;
use super::overturn::Overturn;

/// Speed below which a block is at rest after an impact, relative to `p`:
/// `|ẋ⁺| < REST_TOL · p`. The swing that follows such an impact would reach
/// `|x| ≈ (ẋ⁺/p)²/2 < 5·10⁻¹⁹`, far below any reported digit; the tests
/// check that θmax/α does not move when the tolerance changes by 100×.
pub const REST_TOL: f64 = 1e-9;

/// The frequency parameters p (1/s) the model is computed for: blocks with
/// R = 3g/(4p²) from 7.4 µm (p = 1000) to 74 km (p = 0.01), every real
/// block and far beyond. Above, the arithmetic fails before the physics:
/// the exact step's e^{p·Δt} overflows at p·Δt ≈ 709 (p ≈ 1.4e5 on a
/// 0.005-s record), and on Kobe NIS η_c, which tends to 1 as p grows (a
/// tiny block overturns as soon as it uplifts), was 0.99993 at p = 1e4 but
/// 0.31 at 1e6 and 0.0025 at 1e7.
pub const P_RANGE: std::ops::RangeInclusive<f64> = 0.01..=1000.0;

/// Whether `p` is in [`P_RANGE`]; else the message, naming the range.
pub fn check_p(p: f64) -> Result<(), String> {
    if P_RANGE.contains(&p) {
        Ok(())
    } else {
        // 1e300 as such, not as its 301 digits.
        let p = if p == 0.0 || !p.is_finite() || (1e-4..1e7).contains(&p.abs()) {
            format!("{p}")
        } else {
            format!("{p:e}")
        };
        Err(format!(
            "p = {p} 1/s is outside [{}, {}] 1/s, the range the model is computed for \
             (a block's R = 3g/(4p²) from 74 km down to 7.4 µm)",
            P_RANGE.start(),
            P_RANGE.end()
        ))
    }
}

/// Hard cap on events in one run; a run that reaches it is reported as
/// [`Stop::EventLimit`] instead of looping. No physical run with ε < 1
/// comes close: a Zeno sequence from `ẋ/p = 1` to rest at ε = 0.99 has
/// about 2,100 impacts; at ε = 1 a block that barely lifts hops without
/// end, and a large p can reach it within a record.
pub const MAX_EVENTS: u64 = 50_000_000;

/// The block and the run: everything except the record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSpec {
    /// Frequency parameter p (1/s).
    pub p: f64,
    /// Coefficient of restitution ε ∈ (0, 1].
    pub eps: f64,
    /// Uplift strength η = αg/A_g (> 0; smaller is stronger shaking).
    pub eta: f64,
    pub model: Model,
    pub overturn: Overturn,
    /// Rest tolerance (relative to p); [`REST_TOL`] unless testing.
    pub rest_tol: f64,
}

/// The smallest η a run takes: a PGA 10¹² times the one that lifts the
/// block. The Taylor stepper's steps shrink with the forcing, and near
/// η = 1e-40 they no longer end; no study comes near either.
pub const ETA_MIN: f64 = 1e-12;

impl RunSpec {
    pub fn new(p: f64, eps: f64, eta: f64, model: Model) -> Self {
        RunSpec {
            p,
            eps,
            eta,
            model,
            overturn: Overturn::Static,
            rest_tol: REST_TOL,
        }
    }

    /// Checks ranges; called by [`simulate`].
    pub fn validate(&self) -> Result<(), PhysicsError> {
        let bad = |m: String| Err(PhysicsError::BadInput(m));
        check_p(self.p).map_err(PhysicsError::BadInput)?;
        if !(self.eps > 0.0 && self.eps <= 1.0) {
            return bad(format!(
                "ε = {} must be in (0, 1]",
                crate::decimal::shortest(self.eps)
            ));
        }
        if !(self.eta > 0.0 && self.eta.is_finite()) {
            return bad(format!(
                "η = {} must be positive",
                crate::decimal::shortest(self.eta)
            ));
        }
        if self.eta < ETA_MIN {
            return bad(format!(
                "η = {:e} is below {ETA_MIN:e}: a motion over 10¹² times the acceleration that \
                 lifts the block (η = αg/PGA), beyond any record, where the nonlinear steppers' \
                 steps shrink without end",
                self.eta
            ));
        }
        if !(self.rest_tol > 0.0 && self.rest_tol < 1e-3) {
            return bad(format!(
                "rest tolerance {} must be in (0, 1e-3)",
                self.rest_tol
            ));
        }
        self.model.validate()?;
        self.model.equation.overturn_limit(self.overturn)?;
        Ok(())
    }

    /// The slenderness α of the model's equation, if it has one.
    pub fn alpha(&self) -> Option<f64> {
        self.model.equation.alpha()
    }
}
