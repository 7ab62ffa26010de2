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
//! [`Integrator`], its arms in [`Integrator::validate`] below and in the
//! stepper's construction in `simulate.rs` (`drive`); the compiler points
//! at each.

use super::equation::{linearization_error, Equation};
use super::error::PhysicsError;
use super::friction::Friction;

/// How the equation is advanced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Integrator {
    /// Closed-form stepping of the linearised equation ([`exact`]): exact up
    /// to rounding, events located to a few ulps.
    Exact,
    /// Dormand–Prince 5(4) with dense output ([`dp5`]) at relative tolerance `rtol`.
    Dp5 { rtol: f64 },
    /// The nonlinear equation's Taylor series, one step per sample interval
    /// ([`taylor`]), its tail below `tol` relative.
    Taylor { tol: f64 },
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
            Integrator::Taylor { .. } => "taylor",
            Integrator::Rk4 { .. } => "rk4",
        }
    }

    /// The tolerance of a tolerance-controlled integrator (DP5's per step,
    /// the Taylor series' tail per sample interval).
    pub fn tol(self) -> Option<f64> {
        match self {
            Integrator::Dp5 { rtol } => Some(rtol),
            Integrator::Taylor { tol } => Some(tol),
            Integrator::Exact | Integrator::Rk4 { .. } => None,
        }
    }

    /// The tightest tolerance a certification may check at: below 1e-14
    /// DP5's error estimate is rounding noise; the Taylor series' tail can
    /// be asked below the rounding of the sum (a few more terms).
    pub fn tightest_tol(self) -> f64 {
        match self {
            Integrator::Taylor { .. } => TAYLOR_TIGHTEST_TOL,
            _ => DP5_TIGHTEST_RTOL,
        }
    }

    /// The same integrator at tolerance `tol` (itself if it has none).
    pub fn with_tol(self, tol: f64) -> Integrator {
        match self {
            Integrator::Dp5 { .. } => Integrator::Dp5 { rtol: tol },
            Integrator::Taylor { .. } => Integrator::Taylor { tol },
            other => other,
        }
    }

    /// The setting, for benchmark tables.
    pub fn setting(self) -> String {
        match self {
            Integrator::Exact => "exact".to_string(),
            Integrator::Dp5 { rtol } => format!("rtol {rtol:e}"),
            Integrator::Taylor { tol } => format!("tail {tol:e}"),
            Integrator::Rk4 { substeps } => format!("{substeps} steps/dt"),
        }
    }

    /// Checks the settings and that the integrator can advance `equation`.
    pub fn validate(self, equation: Equation) -> Result<(), PhysicsError> {
        let bad = |m: String| Err(PhysicsError::BadInput(m));
        match (self, equation) {
            (Integrator::Exact, Equation::Linearized) => Ok(()),
            (Integrator::Exact, Equation::Nonlinear { .. } | Equation::SlideRock { .. }) => bad(
                "the exact stepper integrates the linearised equation only; the nonlinear one needs DP5"
                    .into(),
            ),
            (Integrator::Dp5 { rtol }, _) if !(rtol > 0.0 && rtol < 1e-2) => {
                bad(format!("nonlinear tolerance {rtol} must be in (0, 0.01)"))
            }
            (Integrator::Dp5 { .. }, _) => Ok(()),
            (Integrator::Taylor { .. }, Equation::Linearized) => bad(
                "the Taylor stepper integrates the nonlinear equation only; the linearised one is stepped exactly"
                    .into(),
            ),
            (Integrator::Taylor { tol }, _) if !(tol > 0.0 && tol < 1e-2) => {
                bad(format!("Taylor tolerance {tol} must be in (0, 0.01)"))
            }
            (Integrator::Taylor { .. }, _) => Ok(()),
            (Integrator::Rk4 { substeps: 0 }, _) => {
                bad("RK4 needs at least one step per sample interval".into())
            }
            (Integrator::Rk4 { .. }, _) => Ok(()),
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

    /// The nonlinear equation for slenderness `alpha_rad` by `solver`.
    pub fn nonlinear(alpha_rad: f64, solver: Solver) -> Model {
        Model {
            equation: Equation::Nonlinear { alpha_rad },
            integrator: solver.integrator(),
        }
    }

    /// The nonlinear equation with sliding on a base of `friction`, for
    /// slenderness `alpha_rad`, its rocking by `solver`.
    pub fn slide_rock(
        alpha_rad: f64,
        friction: super::friction::Friction,
        solver: Solver,
    ) -> Model {
        Model {
            equation: Equation::SlideRock {
                alpha_rad,
                friction,
            },
            integrator: solver.integrator(),
        }
    }

    /// The nonlinear equation for slenderness `alpha_rad` by DP5 at `rtol`.
    pub fn dp5(alpha_rad: f64, rtol: f64) -> Model {
        Model {
            equation: Equation::Nonlinear { alpha_rad },
            integrator: Integrator::Dp5 { rtol },
        }
    }

    /// The nonlinear equation for slenderness `alpha_rad` by the Taylor
    /// stepper with tail tolerance `tol`.
    pub fn taylor(alpha_rad: f64, tol: f64) -> Model {
        Model {
            equation: Equation::Nonlinear { alpha_rad },
            integrator: Integrator::Taylor { tol },
        }
    }

    pub fn validate(&self) -> Result<(), PhysicsError> {
        self.equation.validate()?;
        self.integrator.validate(self.equation)
    }
}

/// The nonlinear equation's integrators, as a user names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NonlinearIntegrator {
    /// The Taylor stepper ([`super::taylor`]): the default.
    Taylor,
    /// Dormand–Prince 5(4) ([`super::dp5`]).
    Dp5,
}

impl crate::label::Label for NonlinearIntegrator {
    const ALL: &'static [Self] = &[NonlinearIntegrator::Taylor, NonlinearIntegrator::Dp5];
    const WHAT: &'static str = "integrator";
    fn label(self) -> &'static str {
        match self {
            NonlinearIntegrator::Taylor => "taylor",
            NonlinearIntegrator::Dp5 => "dp5",
        }
    }
    fn help(self) -> &'static str {
        match self {
            NonlinearIntegrator::Taylor => "its Taylor series, one step per sample interval",
            NonlinearIntegrator::Dp5 => "Dormand–Prince 5(4)",
        }
    }
}

/// How the nonlinear equation is integrated: which integrator, at which
/// tolerance (checked by [`Solver::new`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Solver {
    pub integrator: NonlinearIntegrator,
    pub tol: f64,
}

impl Default for Solver {
    fn default() -> Self {
        Solver {
            integrator: NonlinearIntegrator::Taylor,
            tol: DEFAULT_TAYLOR_TOL,
        }
    }
}

impl Solver {
    /// `integrator` at `tol`, or at its default tolerance; the tolerance
    /// checked against the integrator's range.
    pub fn new(integrator: NonlinearIntegrator, tol: Option<f64>) -> Result<Solver, String> {
        let tol = match (integrator, tol) {
            (NonlinearIntegrator::Taylor, None) => DEFAULT_TAYLOR_TOL,
            (NonlinearIntegrator::Dp5, None) => DEFAULT_RTOL,
            (NonlinearIntegrator::Taylor, Some(t)) => {
                if !(TAYLOR_MIN_TOL..1e-2).contains(&t) {
                    return Err(format!(
                        "the Taylor stepper's tolerance {t:e} must be in [{TAYLOR_MIN_TOL:e}, 0.01)"
                    ));
                }
                t
            }
            (NonlinearIntegrator::Dp5, Some(t)) => {
                check_rtol(t)?;
                t
            }
        };
        Ok(Solver { integrator, tol })
    }

    pub fn integrator(self) -> Integrator {
        match self.integrator {
            NonlinearIntegrator::Taylor => Integrator::Taylor { tol: self.tol },
            NonlinearIntegrator::Dp5 => Integrator::Dp5 { rtol: self.tol },
        }
    }
}

/// The Taylor stepper's default tolerance: the last two terms of each
/// sample interval's series of the velocity below 1e-10 of its largest
/// (those of `sin u` and `cos u` below a tenth of 1e-10·α). Chosen from
/// `rocking-bench` (docs/BENCHMARKS.md): certified from 1e-8, 1e-10 or
/// 1e-12, every capacity of the tolerance study equals DP5's at 1e-13 and
/// the same 7 are chaotic; on the solver table its θmax/α error (median
/// 1e-14, max 2e-12) is under a sixtieth of DP5's at its default rtol
/// 1e-10, where 1e-8's (2e-12, max 3e-11) is a fifth of it; 1e-10 costs
/// about 10 % more than 1e-8 and 14 % less than 1e-12.
pub const DEFAULT_TAYLOR_TOL: f64 = 1e-10;

/// DP5's default relative tolerance. Chosen from `rocking-bench --sections
/// tolerance` (docs/BENCHMARKS.md): over 528 far-field cases a plain search
/// at 1e-10 moves 0.2 % of the capacities against 1.3 % at 1e-8; certified,
/// it redoes no search (0.9 % from 1e-8) and its chaos probe (η ± 1e-9) is
/// checked at 1e-12, far below the probe; 1.3 % of the cases are chaotic.
/// It costs 0.086 s per certified capacity against 0.062 s from 1e-8.
pub const DEFAULT_RTOL: f64 = 1e-10;

/// The tightest tolerance DP5 is checked at (its error estimate is
/// rounding noise below).
pub const DP5_TIGHTEST_RTOL: f64 = 1e-14;

/// The tightest tail the Taylor stepper is checked at.
pub const TAYLOR_TIGHTEST_TOL: f64 = 1e-16;

/// The tightest tail a user may ask of the Taylor stepper: a certification
/// checks it at a tighter one, [`TAYLOR_TIGHTEST_TOL`] at the tightest (at
/// 1e-16 itself the check was the run again, and said it agreed).
pub const TAYLOR_MIN_TOL: f64 = 1e-15;

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
    /// tolerance ([`linearization_error`] ≤ tol), else the
    /// nonlinear one; with the base's friction, the slide-rock model.
    Auto,
    /// The nonlinear equation on a base with Coulomb friction (rest, slide,
    /// rock, slide-rock); needs α and μ.
    SlideRock,
}

impl crate::label::Label for ModelChoice {
    const ALL: &'static [Self] = &[
        ModelChoice::Linearized,
        ModelChoice::Nonlinear,
        ModelChoice::Auto,
        ModelChoice::SlideRock,
    ];
    const WHAT: &'static str = "model";
    fn label(self) -> &'static str {
        match self {
            ModelChoice::Linearized => "linearized",
            ModelChoice::Nonlinear => "nonlinear",
            ModelChoice::Auto => "auto",
            ModelChoice::SlideRock => "slide-rock",
        }
    }
    fn help(self) -> &'static str {
        match self {
            ModelChoice::Linearized => "paper Eq. 8, exact stepping (depends on p, η, ε only)",
            ModelChoice::Nonlinear => "paper Eq. 7, by the integrator asked; needs α",
            ModelChoice::Auto => {
                "linearised where its error for α is within the accepted one, else nonlinear; \
                 slide-rock for every block whose μ is given"
            }
            ModelChoice::SlideRock => {
                "paper Eq. 7 on a base with friction μ: rest, slide, rock and slide-rock; needs α and μ"
            }
        }
    }
    fn aliases(self) -> &'static [&'static str] {
        match self {
            ModelChoice::Linearized => &["linearised"],
            ModelChoice::SlideRock => &["slide_rock"],
            _ => &[],
        }
    }
}

crate::deserialize_by_label!(ModelChoice, NonlinearIntegrator);

impl ModelChoice {
    /// The solver option this model would take and not use, of those
    /// given: the linearised equation is stepped exactly, so an integrator
    /// (`integrator`, other than the default) or its tolerance (`rtol`)
    /// beside it does nothing. The key's name, for each door to spell.
    pub fn unused_solver_key(self, integrator: bool, rtol: bool) -> Option<&'static str> {
        match self {
            ModelChoice::Linearized => [("integrator", integrator), ("rtol", rtol)]
                .into_iter()
                .find_map(|(key, given)| given.then_some(key)),
            _ => None,
        }
    }

    /// The model to run and a sentence saying why. `friction`, the base's
    /// where known, makes `auto` choose the slide-rock model, whose rocking
    /// is the nonlinear model's: a block with μ can slide, whether it slides
    /// first (μₛ < b/h) or slips as it rocks (its friction is checked at
    /// every interval, and the runs are the nonlinear model's to the bit
    /// until it binds).
    pub fn resolve(
        self,
        alpha_rad: Option<f64>,
        friction: Option<Friction>,
        solver: Solver,
        auto_tol: f64,
    ) -> Result<(Model, String), PhysicsError> {
        check_auto_tol(auto_tol).map_err(PhysicsError::BadInput)?;
        if let Some(f) = friction {
            f.validate()?;
        }
        match (self, alpha_rad, friction) {
            (ModelChoice::SlideRock, Some(a), Some(f)) => Ok((
                Model::slide_rock(a, f, solver),
                format!("slide-rock model: {}", sliding_reason(a, f)),
            )),
            (ModelChoice::SlideRock, None, _) => Err(PhysicsError::BadInput(
                "the slide-rock model needs the block's slenderness α (--alpha, in rad, or its sizes)"
                    .into(),
            )),
            (ModelChoice::SlideRock, Some(_), None) => Err(PhysicsError::BadInput(
                "the slide-rock model needs the base's friction coefficient μ (--mu)".into(),
            )),
            // Any block with μ can slide, a slender one too: its friction
            // demand while rocking is not bounded by tan α (MODEL.md §21).
            (ModelChoice::Auto, Some(a), Some(f)) => Ok((
                Model::slide_rock(a, f, solver),
                format!("slide-rock model: {}", sliding_reason(a, f)),
            )),
            (choice, alpha, _) => choice.resolve_rocking(alpha, solver, auto_tol),
        }
    }

    /// [`ModelChoice::resolve`] without friction.
    fn resolve_rocking(
        self,
        alpha_rad: Option<f64>,
        solver: Solver,
        auto_tol: f64,
    ) -> Result<(Model, String), PhysicsError> {
        match (self, alpha_rad) {
            (ModelChoice::SlideRock, _) => Err(PhysicsError::BadInput(
                "the slide-rock model needs the base's friction coefficient μ (--mu)".into(),
            )),
            (ModelChoice::Linearized, None) => Ok((Model::LINEARIZED, "linearised model".into())),
            // Chosen or defaulted, it says what it costs at this α.
            (ModelChoice::Linearized, Some(a)) => {
                let err = linearization_error(a);
                let hint = if err > auto_tol {
                    "; --model auto or nonlinear runs the nonlinear equation"
                } else {
                    ""
                };
                Ok((
                    Model::LINEARIZED,
                    format!(
                        "linearised model, which errs by about {err:.1e} in η_c at α = {a:.4} \
                         rad{hint}"
                    ),
                ))
            }
            (ModelChoice::Nonlinear, Some(a)) => {
                Ok((Model::nonlinear(a, solver), "nonlinear model".into()))
            }
            (ModelChoice::Nonlinear, None) => Err(PhysicsError::BadInput(
                "the nonlinear model needs the block's slenderness α (--alpha, in rad)".into(),
            )),
            (ModelChoice::Auto, None) => Ok((
                Model::LINEARIZED,
                "linearised model: no α given, so the α → 0 limit".into(),
            )),
            (ModelChoice::Auto, Some(a)) => {
                let err = linearization_error(a);
                if err <= auto_tol {
                    Ok((
                        Model::LINEARIZED,
                        format!("linearised model: its η_c error for α = {a:.4} rad is about {err:.2e} ≤ {auto_tol:e}"),
                    ))
                } else {
                    Ok((
                        Model::nonlinear(a, solver),
                        format!("nonlinear model: the linearised one would err by about {err:.2e} > {auto_tol:e} for α = {a:.4} rad"),
                    ))
                }
            }
        }
    }
}

/// Why a block on a base of `friction` may slide, in words.
fn sliding_reason(alpha_rad: f64, friction: Friction) -> String {
    let b_over_h = alpha_rad.tan();
    let mu = friction.mu_s;
    if crate::block::slides_first(mu, alpha_rad) {
        format!("the block slides before it rocks (μ = {mu} ≤ b/h = {b_over_h:.4})")
    } else {
        format!(
            "μ = {mu} > b/h = {b_over_h:.4}: it rocks first, and slides where its friction \
             demand reaches μN"
        )
    }
}
