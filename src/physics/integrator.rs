//! Integrators and the model (an equation × an integrator).
//!
//! An integrator only advances the state on one pivot, over one stretch of a
//! sample interval, until the stretch ends or the first event, and says
//! which ([`super::Stepper::rock`] → [`super::StretchEnd`]), like diffsol's `step`
//! returning why it stopped. Everything else (uplift, the impact map, rest,
//! the fate after the record) is the equation's ([`Equation`]) or the
//! driver's ([`super::simulate`]).
//!
//! Adding an integrator: its file with a [`super::Stepper`], a variant of
//! [`Integrator`], and its arms in [`Integrator::validate`] and
//! [`Integrator::drive`] below; the compiler points at each.

use super::dispatch::{self, Isa};
use super::driver::{self, Outcome};
use super::equation::{Equation, LinearRhs, NonlinearRhs, LINEARIZATION_ERROR_PER_ALPHA2};
use super::history::Observer;
use super::step::Rocking;
use super::{dp5, exact, rk4, Excitation, PhysicsError, RunSpec};

/// How the equation is advanced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Integrator {
    /// Closed-form stepping of the linearised equation ([`exact`]): exact up
    /// to rounding, events located to a few ulps.
    Exact,
    /// Dormand–Prince 5(4) with dense output ([`dp5`]) at relative tolerance `rtol`.
    Dp5 { rtol: f64 },
    /// Classical fixed-step RK4 with `substeps` steps per sample interval and
    /// events by linear interpolation ([`rk4`]): the baseline a user would
    /// write, for benchmarks only.
    Rk4 { substeps: u32 },
}

impl Integrator {
    /// A short name for tables and benchmarks.
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Exact => "exact",
            Integrator::Dp5 { .. } => "dp5",
            Integrator::Rk4 { .. } => "rk4",
        }
    }

    /// DP5's relative tolerance, if it is DP5.
    pub fn rtol(self) -> Option<f64> {
        match self {
            Integrator::Dp5 { rtol } => Some(rtol),
            _ => None,
        }
    }

    /// The setting, for benchmark tables.
    pub fn setting(self) -> String {
        match self {
            Integrator::Exact => "exact".to_string(),
            Integrator::Dp5 { rtol } => format!("rtol {rtol:e}"),
            Integrator::Rk4 { substeps } => format!("{substeps} steps/dt"),
        }
    }

    /// Checks the settings and that the integrator can advance `equation`.
    pub fn validate(self, equation: Equation) -> Result<(), PhysicsError> {
        let bad = |m: String| Err(PhysicsError::BadInput(m));
        match (self, equation) {
            (Integrator::Exact, Equation::Linearized) => Ok(()),
            (Integrator::Exact, Equation::Nonlinear { .. }) => bad(
                "the exact stepper integrates the linearised equation only; the nonlinear one needs DP5"
                    .into(),
            ),
            (Integrator::Dp5 { rtol }, _) if !(rtol > 0.0 && rtol < 1e-2) => {
                bad(format!("nonlinear tolerance {rtol} must be in (0, 0.01)"))
            }
            (Integrator::Dp5 { .. }, _) => Ok(()),
            (Integrator::Rk4 { substeps: 0 }, _) => {
                bad("RK4 needs at least one step per sample interval".into())
            }
            (Integrator::Rk4 { .. }, _) => Ok(()),
        }
    }

    /// Runs the event driver with this integrator on `equation` (validated);
    /// the exact stepper's as compiled for `isa` (available on this CPU).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn drive(
        self,
        equation: Equation,
        exc: &Excitation,
        spec: &RunSpec,
        start: Option<Rocking>,
        limit: f64,
        obs: &mut impl Observer,
        isa: Isa,
    ) -> Outcome {
        let (p, eta, dt) = (spec.p, spec.eta, exc.dt_s);
        // One monomorphised event loop per (integrator, equation).
        macro_rules! with {
            ($stepper:expr) => {
                driver::drive(exc, spec, start, limit, &mut $stepper, obs)
            };
        }
        match (self, equation) {
            (Integrator::Exact, Equation::Linearized) => dispatch::drive(
                exc,
                spec,
                start,
                limit,
                &mut exact::Exact::new(p, eta, dt, limit),
                obs,
                isa,
            ),
            (Integrator::Exact, Equation::Nonlinear { .. }) => {
                unreachable!("validate() refuses the exact stepper for the nonlinear equation")
            }
            (Integrator::Dp5 { rtol }, Equation::Linearized) => {
                with!(dp5::Dp5::new(LinearRhs::new(p, eta), p, rtol, limit))
            }
            (Integrator::Dp5 { rtol }, Equation::Nonlinear { alpha_rad }) => {
                with!(dp5::Dp5::new(
                    NonlinearRhs::new(p, eta, alpha_rad),
                    p,
                    rtol,
                    limit
                ))
            }
            (Integrator::Rk4 { substeps }, Equation::Linearized) => {
                with!(rk4::Rk4::new(LinearRhs::new(p, eta), dt, substeps, limit))
            }
            (Integrator::Rk4 { substeps }, Equation::Nonlinear { alpha_rad }) => {
                with!(rk4::Rk4::new(
                    NonlinearRhs::new(p, eta, alpha_rad),
                    dt,
                    substeps,
                    limit
                ))
            }
        }
    }
}

/// A model: which equation, advanced by which integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    pub equation: Equation,
    pub integrator: Integrator,
}

impl Model {
    /// The linearised equation stepped exactly: the tool's default.
    pub const LINEARIZED: Model = Model {
        equation: Equation::Linearized,
        integrator: Integrator::Exact,
    };

    /// The nonlinear equation for slenderness `alpha_rad` by DP5 at `rtol`.
    pub fn nonlinear(alpha_rad: f64, rtol: f64) -> Model {
        Model {
            equation: Equation::Nonlinear { alpha_rad },
            integrator: Integrator::Dp5 { rtol },
        }
    }

    pub fn validate(&self) -> Result<(), PhysicsError> {
        self.equation.validate()?;
        self.integrator.validate(self.equation)
    }
}

/// DP5's default relative tolerance. Chosen from `rocking bench --sections
/// tolerance` (docs/BENCHMARKS.md): over 528 far-field cases a plain search
/// at 1e-10 moves 0.2 % of the capacities against 1.3 % at 1e-8; certified,
/// it redoes no search (0.9 % from 1e-8) and its chaos probe (η ± 1e-9) is
/// checked at 1e-12, far below the probe; 1.3 % of the cases are chaotic.
/// It costs 0.100 s per certified capacity against 0.071 s from 1e-8.
pub const DEFAULT_RTOL: f64 = 1e-10;

/// The tightest DP5 tolerance a user may ask for: capacities are certified
/// at a 100× tighter one, and below 1e-14 DP5's error estimate is rounding
/// noise.
pub const MIN_RTOL: f64 = 1e-13;

/// Checks a user's DP5 tolerance: in [[`MIN_RTOL`], 0.01).
pub fn check_rtol(rtol: f64) -> Result<(), String> {
    if (MIN_RTOL..1e-2).contains(&rtol) {
        Ok(())
    } else {
        Err(format!(
            "nonlinear tolerance {rtol:e} must be in [{MIN_RTOL:e}, 0.01)"
        ))
    }
}

/// Whether `auto_tol`, the relative error in η_c accepted from the
/// linearisation, is in (0, 1): a NaN, an infinity or a negative value
/// would silently pick a model (or hide the linearisation warning).
pub fn check_auto_tol(auto_tol: f64) -> Result<(), String> {
    if auto_tol > 0.0 && auto_tol < 1.0 {
        Ok(())
    } else {
        Err(format!(
            "auto tolerance {auto_tol} must be in (0, 1): a relative error in η_c, e.g. 0.01"
        ))
    }
}

/// The model as a user asks for it; [`ModelChoice::resolve`] makes it a [`Model`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelChoice {
    Linearized,
    Nonlinear,
    /// The linearised model where its error for the block's α is within the
    /// tolerance ([`LINEARIZATION_ERROR_PER_ALPHA2`]·α² ≤ tol), else the nonlinear one.
    Auto,
}

impl crate::label::Label for ModelChoice {
    const ALL: &'static [Self] = &[
        ModelChoice::Linearized,
        ModelChoice::Nonlinear,
        ModelChoice::Auto,
    ];
    fn label(self) -> &'static str {
        match self {
            ModelChoice::Linearized => "linearized",
            ModelChoice::Nonlinear => "nonlinear",
            ModelChoice::Auto => "auto",
        }
    }
}

impl ModelChoice {
    /// The model to run and a sentence saying why.
    pub fn resolve(
        self,
        alpha_rad: Option<f64>,
        rtol: f64,
        auto_tol: f64,
    ) -> Result<(Model, String), PhysicsError> {
        if self != ModelChoice::Linearized {
            check_rtol(rtol).map_err(PhysicsError::BadInput)?;
        }
        check_auto_tol(auto_tol).map_err(PhysicsError::BadInput)?;
        match (self, alpha_rad) {
            (ModelChoice::Linearized, _) => {
                Ok((Model::LINEARIZED, "linearised model, as asked".into()))
            }
            (ModelChoice::Nonlinear, Some(a)) => Ok((
                Model::nonlinear(a, rtol),
                "nonlinear model, as asked".into(),
            )),
            (ModelChoice::Nonlinear, None) => Err(PhysicsError::BadInput(
                "the nonlinear model needs the block's slenderness α (--alpha, in rad)".into(),
            )),
            (ModelChoice::Auto, None) => Ok((
                Model::LINEARIZED,
                "linearised model: no α given, so the α → 0 limit".into(),
            )),
            (ModelChoice::Auto, Some(a)) => {
                let err = LINEARIZATION_ERROR_PER_ALPHA2 * a * a;
                if err <= auto_tol {
                    Ok((
                        Model::LINEARIZED,
                        format!("linearised model: its η_c error for α = {a:.4} rad is about {err:.2e} ≤ {auto_tol:e}"),
                    ))
                } else {
                    Ok((
                        Model::nonlinear(a, rtol),
                        format!("nonlinear model: the linearised one would err by about {err:.2e} > {auto_tol:e} for α = {a:.4} rad"),
                    ))
                }
            }
        }
    }
}
