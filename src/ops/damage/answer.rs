//! What a block's fragility is: each state's fits, capacities and check
//! ([`StateFragility`]), and the block's states with their source
//! ([`DamageFragility`]).

use crate::damage::{Curve, FitMethod, Lognormal};
use crate::risk::Fragility;
use crate::stats::FractileDef;

/// One state's fragility.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StateFragility {
    pub name: String,
    /// `θmax/α ≥ 0.1` or `overturned`.
    pub criterion: String,
    /// The θmax/α threshold; none for overturning.
    pub threshold: Option<f64>,
    /// By the paper's fractiles (or the regression, which is its fit).
    pub fractile: Option<Lognormal>,
    /// By censored maximum likelihood (`--direct` only).
    pub mle: Option<Lognormal>,
    /// Records that reach the state within the runs (`--direct` only).
    pub reached: Option<usize>,
    /// What the `fractile` lognormal is: `fractile` (of the records'
    /// capacities, or a study's damage table), `regression` (the paper's or
    /// a study's fit, overturning in PGA) or `moments` (a study's IM table).
    pub fractile_kind: &'static str,
    /// Every record's capacity in the IM, ascending, +∞ where the state is
    /// not reached (`--direct` only): the records' curve.
    #[serde(skip)]
    pub capacities: Option<Vec<f64>>,
    /// The lognormal check of the capacities: Lilliefors' p of their
    /// logarithms (`--direct`, every record reaching the state, 5 or more).
    pub lognormal_p: Option<f64>,
}

impl StateFragility {
    /// The lognormal of `method` (none for the records' curve).
    pub fn by(&self, method: FitMethod) -> Option<Lognormal> {
        match method {
            FitMethod::Fractile => self.fractile,
            FitMethod::MaxLikelihood => self.mle,
            FitMethod::Empirical => None,
        }
    }

    /// P(state reached | IM) by `method`: its lognormal, or the records'
    /// curve; `None` where the method has none.
    pub fn fragility(&self, method: FitMethod) -> Option<Fragility> {
        match method {
            FitMethod::Empirical => self
                .capacities
                .as_ref()
                .map(|c| Fragility::Curve(Curve::of_capacities(c))),
            lognormal => self.by(lognormal).map(|l| Fragility::Lognormal {
                median: l.median,
                beta: l.beta,
            }),
        }
    }

    /// The median (IM unit) and β that `method` stands for: its
    /// lognormal's, or for the records' curve its median, the records' 50 %
    /// fractile (none where more than half never reach the state), and no
    /// β: the curve has none (a lognormal's β beside it was stated for a
    /// fragility that is not one, in JSON, the bootstrap's band, a tree's
    /// branches, while the text said "no β"). The one place `fragility`,
    /// `risk` and Python read them from.
    pub fn median_beta(&self, method: FitMethod) -> (Option<f64>, Option<f64>) {
        match (self.by(method), &self.capacities) {
            (Some(l), _) => (Some(l.median), Some(l.beta)),
            (None, Some(c)) => (Curve::of_capacities(c).quantile(0.5), None),
            (None, None) => (None, None),
        }
    }

    /// The fit `method` stands for here: `fractile`, `regression`,
    /// `moments`, `mle` or `empirical`.
    pub fn fit_name(&self, method: FitMethod) -> &'static str {
        match method {
            FitMethod::Fractile => self.fractile_kind,
            other => other.name(),
        }
    }
}

/// A block's damage-state fragilities.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DamageFragility {
    pub im: String,
    pub unit: &'static str,
    /// `paper`, the pipeline file, or `direct`.
    pub source: String,
    /// Records run (`--direct`); with the worst orientation, pairs.
    pub records: Option<usize>,
    /// With `--orientation random|worst`: the pairs and angles run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orientation: Option<String>,
    /// With `--direct`: the records folder (or the pipeline) they came from.
    pub records_folder: Option<String>,
    /// On a floor: the building's modes (`T,ζ,Γφ; …`); the IMs are the
    /// ground's, PFA and PFV the floor motion's own.
    pub floor: Option<String>,
    /// `common` (one β for the states, the heaviest's) or `each`.
    pub dispersion: &'static str,
    /// The fit the block's fragility is made by: the one asked, or the
    /// records' curve where their capacities fail the lognormal check
    /// ([`FitChoice::if_not_lognormal`]); every command reads it.
    #[serde(skip)]
    pub method: FitMethod,
    /// The model the records were run with, and why (`--direct`).
    pub model: Option<String>,
    /// The equation the records ran (`--direct`): `linearized`,
    /// `nonlinear` or `slide-rock`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub equation: Option<&'static str>,
    /// Where the records ran the slide-rock model (the block may slide):
    /// the base's static friction coefficient.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub slides_on_mu: Option<f64>,
    pub states: Vec<StateFragility>,
    pub warnings: Vec<String>,
    /// With `--direct`: each fitted capacity's states (in the IM), in the
    /// records' order (a pair's with `worst`), for the bootstrap.
    #[serde(skip)]
    pub per_record: Option<Vec<Vec<crate::damage::StateCapacity>>>,
}

impl DamageFragility {
    /// The warning of a block on a base of friction `mu` where these
    /// fragilities are the rocking model's (a regression's, a study's
    /// tables, or runs that did not slide): it slides before it rocks, or
    /// the friction given is not used at all; none where the runs slid.
    pub fn unmodelled_sliding(&self, mu: Option<f64>, alpha_rad: f64) -> Option<String> {
        let mu = mu?;
        if self.slides_on_mu.is_some() {
            return None;
        }
        if crate::block::slides_first(mu, alpha_rad) {
            return Some(crate::block::sliding_warning(mu, alpha_rad));
        }
        Some(format!(
            "friction μ = {mu} is not used: this fragility ({}) is of a block that rocks on a \
             base it never slips on; it rocks before it slides (μ > b/h = {:.4}), but may slip \
             while rocking, which the slide-rock model of --direct runs",
            self.source,
            alpha_rad.tan()
        ))
    }

    /// The fit `method` stands for (its first state's; one for overturning).
    pub fn fit_name(&self, method: FitMethod) -> &'static str {
        self.states
            .first()
            .map_or(method.name(), |s| s.fit_name(method))
    }
}

/// The fractile definition of the records' fits (`--direct`): numpy's and
/// R's default, as the paper's.
pub const DIRECT_FRACTILE: FractileDef = FractileDef::Type7;
