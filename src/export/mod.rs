//! Damage-state fragilities in the formats of the loss and risk engines
//! (pure text, no I/O; README "Into OpenQuake and pelicun"):
//!
//! - `nrml`: OpenQuake's NRML 0.5 `fragilityModel` (continuous logncdf, or
//!   discrete for the records' curve), an exposure model and a `job.ini`
//!   for `classical_damage`;
//! - `pelicun`: pelicun's fragility CSV (lognormal, or `multilinear_CDF`
//!   for the records' curve) and its metadata JSON.
//!
//! - `reading`: how OpenQuake reads the job's hazard curves near poe = 1.
//!
//! Both engines read the records' curve as the tool does: linear between
//! its points, 0 below the first, 1 from the last.

pub mod nrml;
pub mod pelicun;
pub mod reading;

use crate::damage::{Curve, Lognormal};
use crate::im::Im;

/// The states' functions of one block, all of one kind (OpenQuake's
/// `format` is per block).
#[derive(Debug, Clone)]
pub enum Shape {
    /// A lognormal per state.
    Lognormal(Vec<Lognormal>),
    /// The records' curve per state, each complete (from 0 to 1).
    Curve(Vec<Curve>),
}

/// One block's fragility function: its taxonomy and a function per state.
#[derive(Debug, Clone)]
pub struct Entry {
    /// The taxonomy (block name): letters, digits, `_`, `-`, `.`.
    pub id: String,
    /// The block in words (half-dimensions, α, p, ε, the source).
    pub description: String,
    /// The IM below which the block cannot move (its uplift level), if one
    /// is known in the IM.
    pub no_damage_limit: Option<f64>,
    /// A function for each of the model's limit states, in their order.
    pub states: Shape,
}

/// A site of the exposure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site {
    pub lon: f64,
    pub lat: f64,
}

/// What the engines cannot take.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExportError {
    #[error("{format}: a fragility in {im} is not exported ({why}); export in {valid}")]
    Im {
        format: &'static str,
        im: String,
        why: String,
        valid: String,
    },
    #[error(
        "taxonomy `{id}`, state {state}: a lognormal of median {median} and β = {beta} cannot be \
         exported (an engine's lognormal needs a positive, finite median and β)"
    )]
    Spread {
        id: String,
        state: usize,
        median: f64,
        beta: f64,
    },
    #[error(
        "taxonomy `{id}`, state {state}: the records' curve does not rise from 0 to 1 through \
         two levels or more (some records never reach the state, or one record only), which an \
         engine's curve must"
    )]
    Incomplete { id: String, state: usize },
    #[error(
        "taxonomy `{0}`: use letters, digits, `_`, `-` and `.` only (the block's name is its \
         taxonomy in the engines)"
    )]
    Taxonomy(String),
    #[error("taxonomy `{0}` is given twice")]
    Repeated(String),
    #[error("nothing to export")]
    Empty,
}

/// Refuses taxonomies the engines would misread, and repeats.
pub fn check_entries(entries: &[Entry]) -> Result<(), ExportError> {
    if entries.is_empty() {
        return Err(ExportError::Empty);
    }
    let mut seen = std::collections::HashSet::new();
    for e in entries {
        let ok = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.');
        if e.id.is_empty() || !e.id.chars().all(ok) {
            return Err(ExportError::Taxonomy(e.id.clone()));
        }
        if !seen.insert(e.id.as_str()) {
            return Err(ExportError::Repeated(e.id.clone()));
        }
        let good = |x: f64| x.is_finite() && x > 0.0;
        match &e.states {
            Shape::Lognormal(states) => {
                if let Some((i, l)) = states
                    .iter()
                    .enumerate()
                    .find(|(_, l)| !good(l.median) || !good(l.beta))
                {
                    return Err(ExportError::Spread {
                        id: e.id.clone(),
                        state: i + 1,
                        median: l.median,
                        beta: l.beta,
                    });
                }
            }
            Shape::Curve(curves) => {
                if let Some(i) = curves
                    .iter()
                    .position(|c| !c.complete() || c.levels().iter().any(|&x| !good(x)))
                {
                    return Err(ExportError::Incomplete {
                        id: e.id.clone(),
                        state: i + 1,
                    });
                }
            }
        }
    }
    Ok(())
}

/// The range of IMLs a fragility function spans: from the smallest
/// state's median·e^(−6β) to the largest one's median·e^(6β), where
/// P(state) is below 1e-9 and above 1 − 1e-9. OpenQuake clips a curve to
/// this range, so below it the curve keeps its value at the end: with
/// e^(∓4β) that floor, 3.2e-5, times a hazard's high rates at small IMLs
/// (0.5 a year at 5 cm/s) moved P(rocking in 50 years) by 5e-4.
pub fn iml_range(states: &[Lognormal]) -> (f64, f64) {
    let lo = states
        .iter()
        .map(|l| l.median * (-6.0 * l.beta).exp())
        .fold(f64::INFINITY, f64::min);
    let hi = states
        .iter()
        .map(|l| l.median * (6.0 * l.beta).exp())
        .fold(0.0, f64::max);
    (lo, hi)
}

/// The levels of all of a block's curves, merged in order (each curve is
/// linear between its own levels, so its values at these are the same
/// function: OpenQuake's discrete function takes one list of levels for
/// every state).
pub fn merged_levels(curves: &[Curve]) -> Vec<f64> {
    let mut all: Vec<f64> = curves
        .iter()
        .flat_map(|c| c.levels().iter().copied())
        .collect();
    all.sort_by(f64::total_cmp);
    all.dedup();
    all
}

/// OpenQuake's name of the IM.
pub fn openquake_imt(im: Im) -> Result<String, ExportError> {
    // A RotD50 fragility is named as its measure: the component of the
    // ground-motion models behind OpenQuake's hazard.
    let takes = |im: Im| im.hazard() || matches!(im, Im::RotD50(_));
    im.openquake()
        .filter(|_| takes(im))
        .ok_or_else(|| ExportError::Im {
            format: "OpenQuake",
            im: im.name(),
            why: match im.openquake() {
                Some(oq) => format!(
                    "OpenQuake calls it {oq}, but the job runs on hazard curves, which rocking \
                     reads in the IMs `risk` takes only"
                ),
                None => "OpenQuake has no such IM".into(),
            },
            valid: Im::listed(|im| takes(im) && im.openquake().is_some(), true),
        })
}
