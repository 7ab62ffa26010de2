//! `export` as Python's keyword arguments name it: flat, as `risk`'s are,
//! turned into the [`ExportAsk`] the command line builds.

use std::path::PathBuf;

use serde::Deserialize;

use super::assess::{fit_of_runs, needs_own_runs, BlocksAsk};
use super::block::building;
use super::block::AUTO_TOL;
use super::law::LawAsk;
use super::spelling::{AskError, Spelling};
use super::tree::tree;
use crate::block::Restitution;
use crate::building::ShapedMode;
use crate::columns::AccelUnit;
use crate::damage::{DamageStates, Dispersion, FitMethod, IfNotLognormal};
use crate::floor::Mode;
use crate::im::Im;
use crate::ops::export::{self, Format};
use crate::ops::fragility::{DirectProgress, Source};
use crate::pair::Orientation;

/// The keyword arguments of `rocking.export`.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ExportKw {
    pub format: Option<Format>,
    pub b: Option<f64>,
    pub h: Option<f64>,
    pub eps: Restitution,
    pub inventory: Option<PathBuf>,
    pub mu: Option<f64>,
    #[serde(alias = "from")]
    pub source: String,
    pub outputs: Option<PathBuf>,
    pub records: Option<PathBuf>,
    pub records_unit: Option<AccelUnit>,
    pub records_column: Option<usize>,
    pub records_ground: Option<PathBuf>,
    pub orientation: Orientation,
    pub angle_step: f64,
    #[serde(deserialize_with = "super::spelling::strict_direct")]
    pub direct: bool,
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
    pub im: Option<Im>,
    pub hazard: Option<PathBuf>,
    /// OpenQuake's risk investigation time; `None`: 50 years.
    pub years: Option<f64>,
    pub auto_tol: f64,
    pub out: Option<PathBuf>,
    /// A logic tree over ε and the model: a TOML file or a named tree.
    pub tree: Option<String>,
}

impl Default for ExportKw {
    fn default() -> Self {
        let law = LawAsk::default();
        ExportKw {
            format: None,
            b: None,
            h: None,
            eps: Restitution::Housner,
            inventory: None,
            mu: None,
            source: law.source,
            outputs: law.outputs,
            records: None,
            records_unit: None,
            records_column: None,
            records_ground: None,
            orientation: Orientation::AsRecorded,
            angle_step: crate::pair::ANGLE_STEP_DEG,
            direct: false,
            floor: Vec::new(),
            building: Vec::new(),
            level: None,
            states: None,
            method: FitMethod::Fractile,
            dispersion: Dispersion::Common,
            if_not_lognormal: None,
            im: None,
            hazard: None,
            years: None,
            auto_tol: AUTO_TOL,
            out: None,
            tree: None,
        }
    }
}

impl ExportKw {
    /// The request the command line would build from the same options.
    pub fn ask(&self, sp: Spelling) -> Result<ExportAsk, AskError> {
        let need = |key: &str| AskError(format!("give {}", sp.key(key)));
        Ok(ExportAsk {
            format: self.format.ok_or_else(|| need("format"))?,
            blocks: BlocksAsk {
                b: self.b,
                h: self.h,
                eps: self.eps,
                inventory: self.inventory.clone(),
                mu: self.mu,
            },
            law: LawAsk {
                source: self.source.clone(),
                outputs: self.outputs.clone(),
                records: self.records.clone(),
                records_unit: self.records_unit,
                records_column: self.records_column,
                records_ground: self.records_ground.clone(),
                orientation: self.orientation,
                angle_step: self.angle_step,
            },
            direct: self.direct,
            floor: self.floor.clone(),
            building: self.building.clone(),
            level: self.level,
            states: self.states.clone(),
            method: self.method,
            dispersion: self.dispersion,
            if_not_lognormal: self.if_not_lognormal,
            im: self.im,
            hazard: self.hazard.clone(),
            years: self.years,
            auto_tol: self.auto_tol,
            // An empty folder name is the current directory: not asked for.
            out: self
                .out
                .clone()
                .filter(|o| !o.as_os_str().is_empty())
                .ok_or_else(|| need("out"))?,
            tree: self.tree.clone(),
        })
    }
}

/// `rocking export`: damage-state fragilities for OpenQuake or pelicun.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportAsk {
    pub format: Format,
    pub blocks: BlocksAsk,
    pub law: LawAsk,
    pub direct: bool,
    pub floor: Vec<Mode>,
    /// A building with its modes' shapes at every floor, and the floor
    /// the block stands on (instead of `floor`).
    pub building: Vec<ShapedMode>,
    pub level: Option<usize>,
    /// `None`: the default states ([`crate::damage::DEFAULT`]), or, from
    /// the paper's regression, which knows overturning only, that alone.
    pub states: Option<DamageStates>,
    pub method: FitMethod,
    pub dispersion: Dispersion,
    /// `None`: the records' own curve (`curve`), unless asked.
    pub if_not_lognormal: Option<IfNotLognormal>,
    pub im: Option<Im>,
    pub hazard: Option<PathBuf>,
    /// OpenQuake's risk investigation time; `None`: 50 years.
    pub years: Option<f64>,
    pub auto_tol: f64,
    pub out: PathBuf,
    /// A logic tree over ε and the model: a TOML file or a named tree.
    pub tree: Option<String>,
}

impl ExportAsk {
    /// The request, and whether the states are the ones asked (`false`:
    /// overturning alone, the paper's regression knowing no other).
    pub fn resolve(
        &self,
        sp: Spelling,
        progress: DirectProgress,
    ) -> Result<(export::Request, bool), AskError> {
        let from = self.law.resolve(sp)?;
        if let Some(im) = self.im {
            needs_own_runs(im, self.direct, sp)?;
        }
        let paper_alone = !self.direct && matches!(from, Source::Paper { .. });
        let (states, asked) = match &self.states {
            Some(s) => (s.clone(), true),
            None if paper_alone => (
                DamageStates::parse("overturned=overturned").expect("a valid state"),
                false,
            ),
            None => (DamageStates::default(), true),
        };
        let req = export::Request {
            format: self.format,
            blocks: self.blocks.resolve(sp)?,
            from,
            direct: self.direct,
            progress,
            states,
            method: self.method,
            dispersion: self.dispersion,
            if_not_lognormal: fit_of_runs(self.method, self.if_not_lognormal, self.direct, sp)?,
            im: self.im,
            hazard: self.hazard.clone(),
            years: self.job_years(sp)?,
            auto_tol: self.auto_tol,
            floor: building(&self.floor, &self.building, self.level, sp)?,
            out: self.out.clone(),
            orient: self.law.orient(self.direct, sp)?,
            tree: tree(self.tree.as_deref(), self.blocks.eps, self.direct, sp)?,
        };
        Ok((req, asked))
    }

    /// The job's risk investigation time: written only into OpenQuake's
    /// `job.ini`, which a hazard (`--format nrml --hazard`) brings.
    fn job_years(&self, sp: Spelling) -> Result<f64, AskError> {
        match (self.years, &self.hazard, self.format) {
            (Some(y), Some(_), Format::Nrml) => Ok(y),
            (Some(y), _, _) => Err(AskError(format!(
                "{}: the risk investigation time of OpenQuake's job.ini, written only with \
                 {} (OpenQuake's hazard curves) and {}",
                sp.set_number("years", y),
                sp.key("hazard"),
                sp.set("format", "nrml")
            ))),
            (None, _, _) => Ok(50.0),
        }
    }
}
