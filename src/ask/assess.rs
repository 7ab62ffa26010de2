//! What `fragility`, `risk` and `export` are asked, in one vocabulary: the
//! blocks (one by its half sizes, or an inventory), where their capacities
//! come from, the levels or the hazard, the damage states. Each `resolve`
//! checks the combination and builds the library's request.

use std::path::PathBuf;

use serde::Deserialize;

use super::block::{building, many_at, many_pga, AUTO_TOL};
use super::gmf::HazardAsk;
use super::law::LawAsk;
use super::spelling::{AskError, Spelling};
use super::tree::tree;
use crate::block::{check_mu, Restitution};
use crate::building::ShapedMode;
use crate::columns::AccelUnit;
use crate::damage::{DamageStates, Dispersion, FitMethod, IfNotLognormal};
use crate::floor::Mode;
use crate::im::Im;
use crate::ops::fragility::{self, DirectProgress};
use crate::ops::risk::{self, Blocks};
use crate::pair::Orientation;
use crate::risk::Beyond;

/// One block by its half sizes (m), its restitution and friction, or every
/// block of an inventory CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct BlocksAsk {
    pub b: Option<f64>,
    pub h: Option<f64>,
    pub eps: Restitution,
    pub inventory: Option<PathBuf>,
    pub mu: Option<f64>,
}

impl BlocksAsk {
    pub fn resolve(&self, sp: Spelling) -> Result<Blocks, AskError> {
        let mu = self
            .mu
            .map(check_mu)
            .transpose()
            .map_err(|e| AskError::of(sp, "mu", e))?;
        match (&self.inventory, self.b, self.h) {
            (Some(path), None, None) => {
                if mu.is_some() {
                    return Err(AskError(format!(
                        "{} is an inventory's column (`mu`): give it there",
                        sp.key("mu")
                    )));
                }
                // It was ignored: every block took its own column's ε, or
                // Housner's.
                if let Restitution::Value(e) = self.eps {
                    return Err(AskError(format!(
                        "{} is an inventory's column (`eps`): give it there",
                        sp.set_number("eps", e)
                    )));
                }
                Ok(Blocks::Inventory(path.clone()))
            }
            (None, Some(b_m), Some(h_m)) => Ok(Blocks::One {
                b_m,
                h_m,
                eps: self.eps,
                mu,
            }),
            (Some(_), _, _) => Err(AskError(format!(
                "give one block's {}, or {}, not both",
                sp.keys(&["b", "h"]),
                sp.key("inventory")
            ))),
            // Neither, or half a block: both of its sizes, or an inventory.
            (None, b, h) => Err(AskError(format!(
                "give a block's {} (half sizes, m), or {}{}",
                sp.keys(&["b", "h"]),
                sp.key("inventory"),
                match (b, h) {
                    (Some(_), None) => format!(": {} is missing", sp.key("h")),
                    (None, Some(_)) => format!(": {} is missing", sp.key("b")),
                    _ => String::new(),
                }
            ))),
        }
    }
}

/// Damage states instead of overturning alone, and the lognormal's fit.
#[derive(Debug, Clone, PartialEq)]
pub struct StatesAsk {
    pub states: Option<DamageStates>,
    pub method: FitMethod,
}

/// `rocking fragility`: P(state | IM) of one block at given levels.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FragilityAsk {
    pub b: f64,
    pub h: f64,
    pub eps: Restitution,
    /// Levels in PGA (g): the same as `im = pga` with `at`.
    #[serde(deserialize_with = "many_pga")]
    pub pga: Vec<f64>,
    pub im: Im,
    /// Levels of `im`, in its unit.
    #[serde(deserialize_with = "many_at")]
    pub at: Vec<f64>,
    #[serde(alias = "from")]
    pub source: String,
    pub outputs: Option<PathBuf>,
    pub records: Option<PathBuf>,
    pub records_unit: Option<AccelUnit>,
    pub records_column: Option<usize>,
    pub records_ground: Option<PathBuf>,
    /// Which orientations of the records `direct` runs (pairs for random and worst).
    pub orientation: Orientation,
    /// The angle step of the random and worst orientations (°).
    pub angle_step: f64,
    #[serde(deserialize_with = "super::spelling::strict_direct")]
    pub direct: bool,
    pub auto_tol: f64,
    #[serde(deserialize_with = "super::block::some_modes")]
    pub floor: Vec<Mode>,
    /// A building with its modes' shapes at every floor, and the floor
    /// the block stands on (instead of `floor`).
    #[serde(deserialize_with = "super::block::some_shaped")]
    pub building: Vec<ShapedMode>,
    pub level: Option<usize>,
    pub mu: Option<f64>,
    pub states: Option<DamageStates>,
    pub method: FitMethod,
    pub dispersion: Dispersion,
    /// `None`: the records' own curve (`curve`), unless asked.
    pub if_not_lognormal: Option<IfNotLognormal>,
    /// A logic tree over ε and the model: a TOML file or a named tree.
    pub tree: Option<String>,
}

impl Default for FragilityAsk {
    fn default() -> Self {
        let law = LawAsk::default();
        FragilityAsk {
            b: f64::NAN,
            h: f64::NAN,
            eps: Restitution::Housner,
            pga: Vec::new(),
            im: Im::Pga,
            at: Vec::new(),
            source: law.source,
            outputs: law.outputs,
            records: None,
            records_unit: None,
            records_column: None,
            records_ground: None,
            orientation: Orientation::AsRecorded,
            angle_step: crate::pair::ANGLE_STEP_DEG,
            direct: false,
            auto_tol: AUTO_TOL,
            floor: Vec::new(),
            building: Vec::new(),
            level: None,
            mu: None,
            states: None,
            method: FitMethod::Fractile,
            dispersion: Dispersion::Common,
            if_not_lognormal: None,
            tree: None,
        }
    }
}

/// PFA and PFV are demands of the motion the block feels, and RotD a
/// measure of a record pair: from the block's own runs (`--direct`), not a
/// study's or the paper's ground-motion tables.
pub(super) fn needs_own_runs(im: Im, direct: bool, sp: Spelling) -> Result<(), AskError> {
    if im.pair() && !direct {
        return Err(AskError(format!(
            "{}: {} is a measure of a record pair, had from the records' own pairs; add {}",
            sp.set("im", &im.name()),
            im.short(),
            sp.key("direct")
        )));
    }
    if im.floor() && !direct {
        return Err(AskError(format!(
            "{}: {} is a demand of the motion the block stands on, stated from its own runs; \
             add {}",
            sp.set("im", &im.name()),
            im.short(),
            sp.key("direct")
        )));
    }
    Ok(())
}

/// The fit's options that only the records' own runs use (`--direct`):
/// the records' curve (`--method empirical`) and what to do where their
/// capacities fail the lognormal check (`--if-not-lognormal`, the records'
/// curve unless asked). Refused without the runs: the paper's regression
/// and a study's tables give lognormals only, and the option did nothing.
pub(super) fn fit_of_runs(
    method: FitMethod,
    if_not_lognormal: Option<IfNotLognormal>,
    direct: bool,
    sp: Spelling,
) -> Result<IfNotLognormal, AskError> {
    use crate::label::Label;
    if !direct && method == FitMethod::Empirical {
        return Err(AskError(format!(
            "{}: the records' own curve needs their runs; add {}",
            sp.set("method", method.name()),
            sp.key("direct")
        )));
    }
    match (if_not_lognormal, direct) {
        (Some(v), false) => Err(AskError(format!(
            "{}: the lognormal check is of the records' own capacities; add {} (the paper's \
             regression and a study's tables give lognormals)",
            sp.set("if_not_lognormal", v.label()),
            sp.key("direct")
        ))),
        (v, _) => Ok(v.unwrap_or(IfNotLognormal::Curve)),
    }
}

impl FragilityAsk {
    /// The request, and the damage states asked (with their fit), if any.
    pub fn resolve(
        &self,
        sp: Spelling,
        progress: DirectProgress,
    ) -> Result<(fragility::Request, StatesAsk), AskError> {
        if !self.im.scales() {
            return Err(AskError(format!(
                "{}: a capacity cannot be stated in {} (it does not scale with the record); \
                 give one of {}",
                sp.set("im", &self.im.name()),
                self.im.short(),
                Im::listed(Im::scales, false)
            )));
        }
        needs_own_runs(self.im, self.direct, sp)?;
        let levels = match (&self.pga[..], &self.at[..]) {
            ([], []) if self.im != Im::Pga => {
                return Err(AskError(format!(
                    "give the levels of {} with {} (in {})",
                    self.im.name(),
                    sp.key("at"),
                    self.im.unit()
                )))
            }
            ([], []) => {
                return Err(AskError(format!(
                    "give the levels: {} (g), or {} and {}",
                    sp.key("pga"),
                    sp.key("im"),
                    sp.key("at")
                )))
            }
            (pga, []) if self.im == Im::Pga => super::spelling::positive_levels(pga, "pga", sp)?,
            ([], at) => super::spelling::positive_levels(at, "at", sp)?,
            _ => {
                return Err(AskError(format!(
                    "give {}, or {} and {}, not both",
                    sp.key("pga"),
                    sp.key("im"),
                    sp.key("at")
                )))
            }
        };
        let mu = self
            .mu
            .map(check_mu)
            .transpose()
            .map_err(|e| AskError::of(sp, "mu", e))?;
        let law = LawAsk {
            source: self.source.clone(),
            outputs: self.outputs.clone(),
            records: self.records.clone(),
            records_unit: self.records_unit,
            records_column: self.records_column,
            records_ground: self.records_ground.clone(),
            orientation: self.orientation,
            angle_step: self.angle_step,
        };
        let req = fragility::Request {
            b_m: self.b,
            h_m: self.h,
            eps: self.eps,
            im: self.im,
            levels,
            from: law.resolve(sp)?,
            direct: self.direct,
            progress,
            auto_tol: self.auto_tol,
            floor: building(&self.floor, &self.building, self.level, sp)?,
            mu,
            method: self.method,
            dispersion: self.dispersion,
            if_not_lognormal: fit_of_runs(self.method, self.if_not_lognormal, self.direct, sp)?,
            orient: law.orient(self.direct, sp)?,
            tree: tree(self.tree.as_deref(), self.eps, self.direct, sp)?,
        };
        // As `risk` refuses them together: the damage states' answer has no
        // tree, and the tree's was silently dropped.
        if req.tree.is_some() && self.states.is_some() {
            return Err(AskError(format!(
                "{} states P(overturn) over its branches; give it or {}, not both",
                sp.key("tree"),
                sp.key("states")
            )));
        }
        let states = StatesAsk {
            states: self.states.clone(),
            method: self.method,
        };
        Ok((req, states))
    }
}

/// `rocking risk`: the annual rate of overturning (or of each damage
/// state) of a block or an inventory at a hazard's sites.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RiskAsk {
    pub hazard: Option<HazardAsk>,
    pub site: Option<usize>,
    pub b: Option<f64>,
    pub h: Option<f64>,
    pub eps: Restitution,
    pub inventory: Option<PathBuf>,
    pub mu: Option<f64>,
    pub im: Option<Im>,
    /// Which component the hazard is of (`None`: unsaid, as recorded).
    pub component: Option<crate::pair::Component>,
    #[serde(alias = "from")]
    pub source: String,
    pub outputs: Option<PathBuf>,
    pub records: Option<PathBuf>,
    pub records_unit: Option<AccelUnit>,
    pub records_column: Option<usize>,
    pub records_ground: Option<PathBuf>,
    /// Which orientations of the records `direct` runs (pairs for random and worst).
    pub orientation: Orientation,
    /// The angle step of the random and worst orientations (°).
    pub angle_step: f64,
    #[serde(deserialize_with = "super::spelling::strict_direct")]
    pub direct: bool,
    pub years: f64,
    pub beyond: Beyond,
    pub auto_tol: f64,
    #[serde(deserialize_with = "super::block::some_modes")]
    pub floor: Vec<Mode>,
    /// A building with its modes' shapes at every floor, and the floor
    /// the block stands on (instead of `floor`).
    #[serde(deserialize_with = "super::block::some_shaped")]
    pub building: Vec<ShapedMode>,
    pub level: Option<usize>,
    pub states: Option<DamageStates>,
    pub method: FitMethod,
    pub dispersion: Dispersion,
    /// `None`: the records' own curve (`curve`), unless asked.
    pub if_not_lognormal: Option<IfNotLognormal>,
    /// A logic tree over ε and the model: a TOML file or a named tree.
    pub tree: Option<String>,
    /// With `direct`: resamples of the records' pairs for the rate's
    /// band (0: none).
    pub bootstrap: usize,
    /// The bootstrap generator's seed.
    pub seed: u64,
    /// OpenQuake's event-based fields (a folder of its exported CSVs)
    /// instead of `hazard`.
    pub gmf: Option<PathBuf>,
    /// With `gmf`: the effective investigation time, when its job does not say.
    pub eff_years: Option<f64>,
    /// With `gmf`: how the items at a site fall together.
    pub together: crate::events::Together,
    /// With `gmf` and `direct`: also P(OT | PGA, PGV/PGA).
    #[serde(deserialize_with = "super::spelling::strict_vector")]
    pub vector: bool,
}

/// The fewest resamples a bootstrap band is drawn from: with 20 the 5 and
/// 95 % points (type 7) lie between the two smallest and the two largest.
pub const MIN_RESAMPLES: usize = 20;

impl Default for RiskAsk {
    fn default() -> Self {
        let law = LawAsk::default();
        RiskAsk {
            hazard: None,
            site: None,
            b: None,
            h: None,
            eps: Restitution::Housner,
            inventory: None,
            mu: None,
            im: None,
            component: None,
            source: law.source,
            outputs: law.outputs,
            records: None,
            records_unit: None,
            records_column: None,
            records_ground: None,
            orientation: Orientation::AsRecorded,
            angle_step: crate::pair::ANGLE_STEP_DEG,
            direct: false,
            years: 50.0,
            beyond: Beyond::Extrapolate,
            auto_tol: AUTO_TOL,
            floor: Vec::new(),
            building: Vec::new(),
            level: None,
            states: None,
            method: FitMethod::Fractile,
            dispersion: Dispersion::Common,
            if_not_lognormal: None,
            tree: None,
            bootstrap: 0,
            seed: 0,
            gmf: None,
            eff_years: None,
            together: crate::events::Together::SameRecord,
            vector: false,
        }
    }
}

impl RiskAsk {
    /// The blocks asked.
    pub fn blocks(&self) -> BlocksAsk {
        BlocksAsk {
            b: self.b,
            h: self.h,
            eps: self.eps,
            inventory: self.inventory.clone(),
            mu: self.mu,
        }
    }

    /// The request, and the damage states asked (with their fit), if any.
    pub fn resolve(
        &self,
        sp: Spelling,
        progress: DirectProgress,
    ) -> Result<(risk::Request, StatesAsk), AskError> {
        let hazard = super::gmf::hazard(
            self.hazard.as_ref(),
            self.gmf.as_ref(),
            risk::EventsAsk {
                dir: self.gmf.clone().unwrap_or_default(),
                eff_years: self.eff_years,
                together: self.together,
                vector: self.vector,
                states: self.states.clone(),
            },
            sp,
        )?;
        if let Some(im) = self
            .im
            .filter(|im| !im.hazard() && !matches!(im, Im::RotD50(_)))
        {
            return Err(AskError(format!(
                "{}: a hazard curve is in {}, never in {}",
                sp.set("im", &im.name()),
                Im::listed(Im::hazard, false),
                im.short()
            )));
        }
        if let Some(im) = self.im {
            needs_own_runs(im, self.direct, sp)?;
        }
        let law = LawAsk {
            source: self.source.clone(),
            outputs: self.outputs.clone(),
            records: self.records.clone(),
            records_unit: self.records_unit,
            records_column: self.records_column,
            records_ground: self.records_ground.clone(),
            orientation: self.orientation,
            angle_step: self.angle_step,
        };
        let req = risk::Request {
            hazard,
            site: self.site,
            blocks: self.blocks().resolve(sp)?,
            from: law.resolve(sp)?,
            im: self.im,
            component: self.component,
            direct: self.direct,
            progress,
            years: self.years,
            beyond: self.beyond,
            auto_tol: self.auto_tol,
            floor: building(&self.floor, &self.building, self.level, sp)?,
            method: self.method,
            dispersion: self.dispersion,
            if_not_lognormal: fit_of_runs(self.method, self.if_not_lognormal, self.direct, sp)?,
            orient: law.orient(self.direct, sp)?,
            tree: tree(self.tree.as_deref(), self.eps, self.direct, sp)?,
            bootstrap: match (self.bootstrap, self.direct) {
                (0, _) => None,
                (_, false) => {
                    return Err(AskError(format!(
                        "{} resamples the records' own capacities: add {}",
                        sp.key("bootstrap"),
                        sp.key("direct")
                    )))
                }
                // The band's 5 and 95 % points need resamples beyond them:
                // one resample made a "band" that excluded the estimate.
                (resamples, true) if resamples < MIN_RESAMPLES => {
                    return Err(AskError(format!(
                        "{}: a 90 % band needs at least {MIN_RESAMPLES} resamples (1,000 is usual)",
                        sp.set_number("bootstrap", resamples)
                    )))
                }
                (resamples, true) => Some(risk::Bootstrap {
                    resamples,
                    seed: self.seed,
                }),
            },
        };
        self.refuse_together(&req, sp)?;
        let states = StatesAsk {
            states: self.states.clone(),
            method: self.method,
        };
        Ok((req, states))
    }

    /// Options that do not go together: the fields with a tree or a
    /// bootstrap, damage states with either.
    fn refuse_together(&self, req: &risk::Request, sp: Spelling) -> Result<(), AskError> {
        // The fields count their own events over their own years, to their
        // largest value: a time or a rule beyond a curve was ignored.
        if self.gmf.is_some() {
            let ignored = if self.years != 50.0 {
                Some(sp.set_number("years", self.years))
            } else if self.beyond != Beyond::Extrapolate {
                Some(sp.set("beyond", "stop"))
            } else {
                None
            };
            if let Some(given) = ignored {
                return Err(AskError(format!(
                    "{given} is for hazard curves; {} rates events over the fields' own years \
                     ({} when their job.ini does not say)",
                    sp.key("gmf"),
                    sp.key("eff_years")
                )));
            }
        }
        if self.bootstrap == 0 && self.seed != Self::default().seed {
            return Err(AskError(format!(
                "{} seeds {}'s resamples: give it with {}",
                sp.set_number("seed", self.seed),
                sp.key("bootstrap"),
                sp.key("bootstrap")
            )));
        }
        if self.gmf.is_some() && (req.tree.is_some() || req.bootstrap.is_some()) {
            return Err(AskError(format!(
                "{} states the rate over the fields' events for the block as given; {} and {} \
                 are for hazard curves",
                sp.key("gmf"),
                sp.key("tree"),
                sp.key("bootstrap")
            )));
        }
        if req.bootstrap.is_some() && self.states.is_some() {
            return Err(AskError(format!(
                "{} bands the rate of overturning; give it or {}, not both",
                sp.key("bootstrap"),
                sp.key("states")
            )));
        }
        if req.tree.is_some() && self.states.is_some() {
            return Err(AskError(format!(
                "{} states the rate of overturning over its branches; give it or {}, not both",
                sp.key("tree"),
                sp.key("states")
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{BlocksAsk, Spelling};
    use crate::block::Restitution;

    /// A block half given, or none at all, is asked for as such (Python
    /// said "give one block's b and h, or inventory, not both" when no
    /// block was given, or b alone); both a block and an inventory are
    /// "not both".
    #[test]
    fn a_missing_block_is_asked_for_and_two_are_refused_as_both() {
        let ask = |b: Option<f64>, h: Option<f64>, inventory: Option<&str>| {
            BlocksAsk {
                b,
                h,
                eps: Restitution::Housner,
                inventory: inventory.map(Into::into),
                mu: None,
            }
            .resolve(Spelling::Python)
            .unwrap_err()
            .to_string()
        };
        assert_eq!(
            ask(None, None, None),
            "give a block's b and h (half sizes, m), or inventory"
        );
        assert_eq!(
            ask(Some(0.2), None, None),
            "give a block's b and h (half sizes, m), or inventory: h is missing"
        );
        assert!(ask(Some(0.2), Some(0.9), Some("museum.csv")).ends_with("not both"));
        let cli = BlocksAsk {
            b: None,
            h: Some(0.9),
            eps: Restitution::Housner,
            inventory: None,
            mu: None,
        }
        .resolve(Spelling::Cli)
        .unwrap_err()
        .to_string();
        assert_eq!(
            cli,
            "give a block's --b --h (half sizes, m), or --inventory: --b is missing"
        );
    }
}
