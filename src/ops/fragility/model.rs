//! The model `--direct` runs its records with: the choice, the solver,
//! `auto`'s accepted error and the base's friction, resolved for a block
//! by one function.

use super::error::FragilityError;
use crate::block::Block;
use crate::physics::friction::Friction;
use crate::physics::{Model, ModelChoice, Solver};

/// The model the records' runs use: the choice, and the linearised
/// model's accepted error in η_c that `auto` chooses by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunModel {
    pub choice: ModelChoice,
    /// The nonlinear equation's integrator and tolerance.
    pub solver: Solver,
    pub auto_tol: f64,
    /// The base's friction, where known: `auto` then runs the slide-rock
    /// model.
    pub friction: Option<Friction>,
    /// Whether it is a pipeline's `[model]`: its notes then name the
    /// pipeline's keys, not `capacity`'s options.
    pub of_pipeline: bool,
}

impl RunModel {
    /// `auto` at `auto_tol`: what every command runs unless a tree's
    /// branch chooses.
    pub fn auto(auto_tol: f64) -> Self {
        RunModel {
            choice: ModelChoice::Auto,
            solver: Solver::default(),
            auto_tol,
            friction: None,
            of_pipeline: false,
        }
    }

    /// The model for `block` and why: the one function `--direct`'s runs
    /// and the answers that describe them resolve it by.
    pub fn resolve(&self, block: &Block) -> Result<(Model, String), FragilityError> {
        let (model, why) = self
            .choice
            .resolve(
                Some(block.alpha()),
                self.friction,
                self.solver,
                self.auto_tol,
            )
            .map_err(FragilityError::Model)?;
        let why = match self.of_pipeline {
            true => why.replace(
                "--model auto or nonlinear",
                "kind = \"auto\" or \"nonlinear\" in the pipeline's [model]",
            ),
            false => why,
        };
        Ok((model, why))
    }

    /// The same on a base of friction coefficient `mu` (static and
    /// kinetic), where known.
    pub fn on(self, mu: Option<f64>) -> Self {
        RunModel {
            friction: mu.map(Friction::new),
            ..self
        }
    }
}
