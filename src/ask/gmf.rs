//! Where `risk`'s hazard comes from as asked: hazard curves (`hazard`) or
//! OpenQuake's event-based fields (`gmf`, with `eff_years`, `together` and
//! `vector`), one of them.

use std::path::PathBuf;

use super::spelling::{AskError, Spelling};
use serde::Deserialize;

use crate::hazard;
use crate::im::Im;
use crate::ops::risk::{EventsAsk, Hazard};

/// The hazard of `hazard` or, with `gmf`, the fields `events` describes
/// (its `dir` the folder); refused with both, neither, or the fields'
/// options without them.
pub fn hazard(
    hazard: Option<&HazardAsk>,
    gmf: Option<&PathBuf>,
    events: EventsAsk,
    sp: Spelling,
) -> Result<Hazard, AskError> {
    let together = events.together != crate::events::Together::SameRecord;
    if gmf.is_none() && (events.eff_years.is_some() || events.vector || together) {
        return Err(AskError(format!(
            "{}, {} and {} are for {}",
            sp.key("eff_years"),
            sp.key("vector"),
            sp.key("together"),
            sp.key("gmf")
        )));
    }
    match (hazard, gmf) {
        (Some(h), None) => h.resolve(sp),
        (None, Some(_)) => Ok(Hazard::Events(events)),
        (None, None) => Err(AskError(format!(
            "give {} (hazard curves) or {} (event-based fields)",
            sp.key("hazard"),
            sp.key("gmf")
        ))),
        (Some(_), Some(_)) => Err(AskError(format!(
            "give {} or {}, not both",
            sp.key("hazard"),
            sp.key("gmf")
        ))),
    }
}

/// A site's hazard: a file (OpenQuake's hazard-curve CSV or a plain CSV),
/// or one curve given as its levels (in `im`'s unit) and annual rates of
/// exceedance.
#[derive(Debug, Clone, PartialEq)]
pub enum HazardAsk {
    File(PathBuf),
    Arrays {
        im: Im,
        levels: Vec<f64>,
        rates: Vec<f64>,
    },
}

/// A path, or `{im, levels, rates}`; refused in these words (an untagged
/// reading's own message names neither form), an IM it has no name for
/// by the IM's own refusal.
impl<'de> Deserialize<'de> for HazardAsk {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Given {
            File(PathBuf),
            Arrays {
                im: String,
                levels: Vec<f64>,
                rates: Vec<f64>,
            },
        }
        let given = Given::deserialize(d).map_err(|_| {
            serde::de::Error::custom(
                "hazard: a hazard file's path, or one curve as its levels and annual rates of \
                 exceedance (two lists of numbers)",
            )
        })?;
        Ok(match given {
            Given::File(path) => HazardAsk::File(path),
            Given::Arrays { im, levels, rates } => HazardAsk::Arrays {
                im: im
                    .parse()
                    .map_err(|e| serde::de::Error::custom(format!("hazard_im = \"{im}\": {e}")))?,
                levels,
                rates,
            },
        })
    }
}

impl HazardAsk {
    pub fn resolve(&self, sp: Spelling) -> Result<Hazard, AskError> {
        match self {
            HazardAsk::File(path) => Ok(Hazard::File(path.clone())),
            HazardAsk::Arrays { im, levels, rates } => hazard::from_arrays(*im, levels, rates)
                .map(Hazard::Curve)
                .map_err(|e| AskError::of(sp, "hazard", e)),
        }
    }
}
