//! What shakes the block, and how its capacity is searched for: a pulse
//! instead of a record ([`PulseAsk`]), and the IDA's levels and tolerance
//! ([`SearchAsk`]).

use serde::Deserialize;

use super::spelling::{AskError, Spelling};
use crate::ida::{ImGrid, Spacing};
use crate::ops::reports::Search;
use crate::pulse::{Cycle, Pulse, Shape, ShapeKind};

/// A pulse's lobe duration when none is given (s).
pub const TD_S: f64 = 1.0;

/// A pulse as the excitation, if one is asked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PulseAsk {
    pub pulse: Option<ShapeKind>,
    /// The exponential lobe's shape β.
    pub beta: Option<f64>,
    pub cycle: Cycle,
    /// The lobe's duration t_d (s).
    pub td: f64,
}

impl PulseAsk {
    /// The pulse asked, checked; `None` without one.
    pub fn resolve(&self, sp: Spelling) -> Result<Option<Pulse>, AskError> {
        let shape = match (self.pulse, self.beta) {
            (None, None) => return Ok(None),
            (None, Some(_)) => {
                return Err(AskError(format!(
                    "{} is the exponential pulse's shape: give {}",
                    sp.key("beta"),
                    sp.set("pulse", "exp")
                )))
            }
            (Some(ShapeKind::Rect), None) => Shape::Rect,
            (Some(ShapeKind::Rect), Some(_)) => {
                return Err(AskError(format!(
                    "{} is the exponential pulse's shape; {} takes none",
                    sp.key("beta"),
                    sp.set("pulse", "rect")
                )))
            }
            (Some(ShapeKind::Exp), Some(beta)) => Shape::Exp { beta },
            (Some(ShapeKind::Exp), None) => {
                return Err(AskError(format!(
                    "{} needs {}",
                    sp.set("pulse", "exp"),
                    sp.key("beta")
                )))
            }
        };
        let pulse = Pulse {
            shape,
            cycle: self.cycle,
            t_d_s: self.td,
        };
        pulse.validate().map_err(|e| AskError(e.to_string()))?;
        Ok(Some(pulse))
    }
}

/// The intensity of one run: η itself, or the PGA (g) the record is scaled
/// to (on a floor, the ground's: η = α/(PGA · `pfa_over_pga`)), which
/// needs the block's slenderness.
pub fn eta(
    sp: Spelling,
    eta: Option<f64>,
    pga: Option<f64>,
    alpha_rad: Option<f64>,
    pfa_over_pga: f64,
) -> Result<f64, AskError> {
    match (eta, pga, alpha_rad) {
        (Some(eta), None, _) => Ok(eta),
        (None, Some(pga), Some(alpha)) if pga > 0.0 && pga.is_finite() => {
            Ok(crate::im::eta_of_pga(pga * pfa_over_pga, alpha))
        }
        (None, Some(pga), Some(_)) => Err(AskError(format!(
            "{}: a PGA must be positive (g)",
            sp.set("pga", &pga.to_string())
        ))),
        (None, Some(_), None) => Err(AskError(format!(
            "{} needs the block's slenderness α: give {}, {} or {}",
            sp.key("pga"),
            sp.keys(&["b", "h"]),
            sp.keys(&["width", "height"]),
            sp.key("alpha")
        ))),
        _ => Err(AskError(format!(
            "give {} or {}, one of them",
            sp.key("eta"),
            sp.key("pga")
        ))),
    }
}

/// The capacity search: `levels` intensity levels from η = 1 down to
/// `eta_min`, spaced by `spacing`, the capacity refined to `tol` in η.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SearchAsk {
    pub levels: usize,
    pub eta_min: f64,
    pub spacing: Spacing,
    pub tol: f64,
}

impl Default for SearchAsk {
    fn default() -> Self {
        SearchAsk {
            levels: 200,
            eta_min: 1e-3,
            spacing: Spacing::Log,
            tol: crate::ida::DEFAULT_TOL,
        }
    }
}

impl SearchAsk {
    /// The search, its grid checked (an absurd count is refused before
    /// anything is allocated), each bad value named as `sp` spells its key.
    pub fn resolve(&self, sp: Spelling) -> Result<Search, AskError> {
        let bad = |key: &str, value: String, want: &str| {
            AskError(format!("{}: {want}", sp.set_number(key, value)))
        };
        if !(self.tol > 0.0 && self.tol.is_finite()) {
            return Err(bad(
                "tol",
                crate::decimal::shortest(self.tol),
                "give a positive width in η",
            ));
        }
        if self.levels == 0 {
            return Err(bad("levels", "0".into(), "give one level or more"));
        }
        if !(self.eta_min >= crate::physics::ETA_MIN && self.eta_min < 1.0) {
            return Err(bad(
                "eta_min",
                crate::decimal::shortest(self.eta_min),
                &format!("give an η in [{:e}, 1)", crate::physics::ETA_MIN),
            ));
        }
        let grid = ImGrid {
            eta_max: 1.0,
            eta_min: self.eta_min,
            count: self.levels,
            spacing: self.spacing,
        };
        grid.levels().map_err(|e| AskError(e.to_string()))?;
        grid.check_tol(self.tol)
            .map_err(|e| bad("tol", crate::decimal::shortest(self.tol), &e.to_string()))?;
        Ok(Search {
            grid,
            tol: self.tol,
        })
    }
}

/// The rocking planes' angles of a pair (degrees from its first
/// component), each a finite number; else the first that is not, named as
/// `sp` spells the key (a NaN once reached the record's reader, which blamed
/// the record).
pub fn check_angles(angles: &[f64], sp: Spelling) -> Result<(), AskError> {
    match angles.iter().find(|t| !t.is_finite()) {
        Some(bad) => Err(AskError(format!(
            "{}: an angle in degrees",
            sp.set_number("angle", bad)
        ))),
        None => Ok(()),
    }
}

/// A step between a pair's angles (degrees), in
/// [`crate::pair::ANGLE_STEPS_DEG`].
pub fn check_angle_step(step: f64, sp: Spelling) -> Result<(), AskError> {
    if crate::pair::ANGLE_STEPS_DEG.contains(&step) {
        return Ok(());
    }
    Err(AskError(format!(
        "{}: the angle step is in degrees, in [1, 180]",
        sp.set_number("angle_step", step)
    )))
}
