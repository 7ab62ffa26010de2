//! The equations of motion (docs/MODEL.md §2) and what belongs to them
//! rather than to an integrator: the slenderness α, the uplift threshold, the
//! overturning limit of each criterion, the right-hand side on a pivot, and
//! the fate of the free motion after the record (from energy).
//!
//! ```text
//! linearised:  ẍ = p² (x − s) + (p²/η) ψ̈(t)
//! nonlinear:   ẍ = −(p²/α) s sin(α(1 − s x)) + (p²/η) cos(α(1 − s x)) ψ̈(t)
//! ```

use super::energy::{self, Fate};
use super::friction::Friction;
use super::step::Rocking;
use super::{Overturn, PhysicsError};
use crate::label::Label;

/// Which equation of motion, with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Equation {
    /// Paper Eq. 8: depends on p, η, ε only (the limit α → 0).
    Linearized,
    /// Paper Eq. 7 for a block of slenderness `alpha_rad`.
    Nonlinear { alpha_rad: f64 },
    /// Paper Eq. 7 on a base with Coulomb friction: the block may also
    /// slide, flat or on its pivot (docs/MODEL.md §21). Where friction never
    /// binds, its runs are [`Equation::Nonlinear`]'s to the bit.
    SlideRock { alpha_rad: f64, friction: Friction },
}

/// The smallest slenderness α (rad) the nonlinear equation takes: b/h =
/// 0.001, a 1-mm needle a metre tall. Below it α³ terms underflow and
/// θmax/α loses its digits (α = 1e-308 gave θmax/α = 0); the linearised
/// equation, exact in that limit, needs no α.
pub const ALPHA_MIN: f64 = 1e-3;

/// Whether α (rad) is in [[`ALPHA_MIN`], π/2); else the message.
pub fn check_alpha(a: f64) -> Result<(), String> {
    if (ALPHA_MIN..std::f64::consts::FRAC_PI_2).contains(&a) {
        Ok(())
    } else {
        Err(format!(
            "α = {} rad is outside [{ALPHA_MIN}, π/2): the nonlinear equation takes a block \
             no more slender than b/h = 0.001 (use the linearised model below)",
            crate::decimal::shortest(a)
        ))
    }
}

/// The equation without its parameters: what the tables' `model` column holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EquationKind {
    Linearized,
    Nonlinear,
    SlideRock,
}

impl Label for EquationKind {
    const ALL: &'static [Self] = &[
        EquationKind::Linearized,
        EquationKind::Nonlinear,
        EquationKind::SlideRock,
    ];
    fn label(self) -> &'static str {
        match self {
            EquationKind::Linearized => "linearized",
            EquationKind::Nonlinear => "nonlinear",
            EquationKind::SlideRock => "slide-rock",
        }
    }
}

impl EquationKind {
    /// The equation as a reader names it (reports, command output).
    pub fn describe(self) -> &'static str {
        match self {
            EquationKind::Linearized => "linearised equation (paper Eq. 8)",
            EquationKind::Nonlinear => "nonlinear equation (paper Eq. 7)",
            EquationKind::SlideRock => {
                "nonlinear equation with sliding (rest, slide, rock, slide-rock; MODEL.md §21)"
            }
        }
    }
}

impl Equation {
    pub fn kind(self) -> EquationKind {
        match self {
            Equation::Linearized => EquationKind::Linearized,
            Equation::Nonlinear { .. } => EquationKind::Nonlinear,
            Equation::SlideRock { .. } => EquationKind::SlideRock,
        }
    }

    /// The base's friction, when the equation lets the block slide.
    pub fn friction(self) -> Option<Friction> {
        match self {
            Equation::SlideRock { friction, .. } => Some(friction),
            _ => None,
        }
    }

    /// The equation that rocks the same block without sliding.
    pub fn rocking(self) -> Equation {
        match self {
            Equation::SlideRock { alpha_rad, .. } => Equation::Nonlinear { alpha_rad },
            other => other,
        }
    }

    /// The slenderness α (rad), when the equation has one.
    pub fn alpha(self) -> Option<f64> {
        match self {
            Equation::Linearized => None,
            Equation::Nonlinear { alpha_rad } | Equation::SlideRock { alpha_rad, .. } => {
                Some(alpha_rad)
            }
        }
    }

    pub fn validate(self) -> Result<(), PhysicsError> {
        if let Some(a) = self.alpha() {
            check_alpha(a).map_err(PhysicsError::BadInput)?;
        }
        match self.friction() {
            Some(f) => f.validate(),
            None => Ok(()),
        }
    }

    /// A block at rest leaves it where |ψ̈| exceeds `η · uplift_factor()`:
    /// 1 for the linearised equation, tan α / α for the nonlinear one, and
    /// for a block that may slide the smaller of that and μₛ/α (it slides
    /// first where μₛ ≤ tan α).
    pub fn uplift_factor(self) -> f64 {
        match self {
            Equation::Linearized => 1.0,
            Equation::Nonlinear { alpha_rad } => alpha_rad.tan() / alpha_rad,
            Equation::SlideRock {
                alpha_rad,
                friction,
            } => {
                if crate::block::slides_first(friction.mu_s, alpha_rad) {
                    friction.mu_s / alpha_rad
                } else {
                    alpha_rad.tan() / alpha_rad
                }
            }
        }
    }

    /// The `|x|` at which a run stops under `overturn`.
    pub fn overturn_limit(self, overturn: Overturn) -> Result<f64, PhysicsError> {
        overturn.limit(self.alpha())
    }

    /// Free rocking after the record: the largest |x| still to come and
    /// whether the block passes the crest, from energy.
    pub fn free_fate(self, p: f64, state: Rocking, eps: f64) -> Fate {
        match self {
            Equation::Linearized => energy::linear_fate(p, state, eps),
            Equation::Nonlinear { alpha_rad } | Equation::SlideRock { alpha_rad, .. } => {
                energy::nonlinear_fate(p, alpha_rad, state, eps)
            }
        }
    }
}

/// The acceleration ẍ on pivot `s` at position `x` under forcing `g = ψ̈`,
/// for integrators that sample the right-hand side (DP5, RK4). One type per
/// equation, so the integrator's inner loop is monomorphised.
pub trait Rhs: Copy {
    fn accel(&self, s: f64, x: f64, g: f64) -> f64;
}

/// The linearised right-hand side `p² (x − s) + (p²/η) g`.
#[derive(Debug, Clone, Copy)]
pub struct LinearRhs {
    pub p2: f64,
    pub p2_over_eta: f64,
}

impl LinearRhs {
    pub fn new(p: f64, eta: f64) -> Self {
        LinearRhs {
            p2: p * p,
            p2_over_eta: p * p / eta,
        }
    }
}

impl Rhs for LinearRhs {
    #[inline]
    fn accel(&self, s: f64, x: f64, g: f64) -> f64 {
        self.p2 * (x - s) + self.p2_over_eta * g
    }
}

/// The nonlinear right-hand side
/// `−(p²/α) s sin(α(1 − s x)) + (p²/η) cos(α(1 − s x)) g`.
#[derive(Debug, Clone, Copy)]
pub struct NonlinearRhs {
    pub p2_over_alpha: f64,
    pub p2_over_eta: f64,
    pub alpha: f64,
}

impl NonlinearRhs {
    pub fn new(p: f64, eta: f64, alpha: f64) -> Self {
        NonlinearRhs {
            p2_over_alpha: p * p / alpha,
            p2_over_eta: p * p / eta,
            alpha,
        }
    }
}

impl Rhs for NonlinearRhs {
    #[inline]
    fn accel(&self, s: f64, x: f64, g: f64) -> f64 {
        let (sin, cos) = (self.alpha * (1.0 - s * x)).sin_cos();
        -self.p2_over_alpha * s * sin + self.p2_over_eta * cos * g
    }
}

/// Median relative difference in η_c between the nonlinear and the
/// linearised model, per α² (α in rad): measured as 0.43·α² (α from 0.025 to
/// 0.4 rad, 11 far-field records × p ∈ {1, 3, 8} × ε ∈ {0.6, 0.9}; see
/// docs/BENCHMARKS.md), rounded up. Single records can differ more, because a
/// capacity is the first of possibly several overturning islands.
pub const LINEARIZATION_ERROR_PER_ALPHA2: f64 = 0.45;

/// The linearised model's expected relative error in η_c at slenderness
/// `alpha_rad`: [`LINEARIZATION_ERROR_PER_ALPHA2`]·α², what `auto` and
/// every warning of the model compare with `auto_tol`.
pub fn linearization_error(alpha_rad: f64) -> f64 {
    LINEARIZATION_ERROR_PER_ALPHA2 * alpha_rad * alpha_rad
}
