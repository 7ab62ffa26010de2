//! What `risk` is asked: the blocks, the hazard, where the capacities come
//! from.

use std::path::PathBuf;

use crate::hazard::HazardCurve;

use crate::block::Restitution;
use crate::im::Im;
use crate::ops::fragility::{self, Source};
use crate::risk::Beyond;

/// What `--gmf` is asked beyond the blocks: the folder, the effective
/// investigation time when its job does not say, how items fall together,
/// and the vector fragility.
#[derive(Debug, Clone, PartialEq)]
pub struct EventsAsk {
    pub dir: PathBuf,
    pub eff_years: Option<f64>,
    pub together: crate::events::Together,
    pub vector: bool,
    /// Damage states whose rates to state beside overturning (`--states`).
    pub states: Option<crate::damage::DamageStates>,
}

/// The blocks to assess.
#[derive(Debug, Clone)]
pub enum Blocks {
    /// One block: half-width, half-height (m), ε.
    One {
        b_m: f64,
        h_m: f64,
        eps: Restitution,
        /// The base's friction coefficient, when given.
        mu: Option<f64>,
    },
    /// A CSV `name,b,h[,eps]`.
    Inventory(PathBuf),
}

/// A site's hazard: a file of one or several sites' curves, or one curve
/// given as values.
#[derive(Debug, Clone)]
pub enum Hazard {
    File(PathBuf),
    Curve(HazardCurve),
    /// OpenQuake's event-based ground-motion fields (`--gmf DIR`):
    /// [`super::assess_events`].
    Events(EventsAsk),
}

impl Hazard {
    /// What messages and the table's metadata call it: the file, or
    /// `hazard (levels, rates)`.
    pub fn name(&self) -> PathBuf {
        match self {
            Hazard::File(path) => path.clone(),
            Hazard::Curve(_) => PathBuf::from("hazard (levels, rates)"),
            Hazard::Events(e) => e.dir.clone(),
        }
    }
}

/// What the user asks.
#[derive(Debug, Clone)]
pub struct Request {
    pub hazard: Hazard,
    /// One site of the file (index from 0); all when `None`.
    pub site: Option<usize>,
    pub blocks: Blocks,
    pub from: Source,
    /// The fragility's IM; `None`: the hazard's.
    pub im: Option<Im>,
    /// Which component the hazard is of (`None`: unsaid, as recorded).
    pub component: Option<crate::pair::Component>,
    pub direct: bool,
    /// Where `--direct` reports its progress.
    pub progress: fragility::DirectProgress,
    /// For the probability of overturning within this many years.
    pub years: f64,
    pub beyond: Beyond,
    /// The linearised model's accepted error in η_c, for the α warning.
    pub auto_tol: f64,
    /// The building whose floor the blocks stand on (`--direct` only).
    pub floor: Option<crate::floor::Building>,
    /// How each block's fragility is made: a lognormal by the fractiles
    /// (the default) or by likelihood, or the records' curve.
    pub method: crate::damage::FitMethod,
    /// Several damage states: one β for all (the default), or each its own.
    pub dispersion: crate::damage::Dispersion,
    /// Where the capacities fail the lognormal check: their curve (the
    /// default) or the lognormal anyway.
    pub if_not_lognormal: crate::damage::IfNotLognormal,
    /// Which orientations of the records (`--direct`).
    pub orient: fragility::Orient,
    /// A logic tree over ε and the model: each branch's rate, their mean
    /// and quantiles.
    pub tree: Option<crate::tree::Tree>,
    /// With `--direct`: a bootstrap of the rate by the records' pairs.
    pub bootstrap: Option<super::Bootstrap>,
}

impl Request {
    /// How each block's fragility is made.
    pub fn fit(&self) -> crate::damage::FitChoice {
        crate::damage::FitChoice {
            method: self.method,
            dispersion: self.dispersion,
            if_not_lognormal: self.if_not_lognormal,
        }
    }
}
