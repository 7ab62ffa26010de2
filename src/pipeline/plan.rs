//! The resolved plan: what every stage of a pipeline sees, typed and
//! checked, with the limits a pipeline is held to.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::damage::DamageStates;
use crate::floor::Building;
use crate::ida::{ImGrid, Trace};
use crate::physics::{ModelChoice, Overturn, RunSpec, Solver};
use crate::stats::{FractileDef, ResampleUnit};

/// Most values a `{ from, to, count }` range may expand to.
pub const MAX_RANGE_VALUES: usize = 100_000;

/// Most blocks a pipeline may hold (the p × ε grid or `[[block]]` entries).
pub const MAX_BLOCKS: usize = 1_000_000;
/// Most (family, f) walls and (family, f, η) map cells of a pulse map.
pub const MAX_PULSE_WALLS: usize = 100_000;
pub const MAX_PULSE_CELLS: usize = 2_000_000;

/// A resolved pulse map.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PulsePlan {
    /// One shape per family (one per β for `exp`; `rect` alone).
    pub shapes: Vec<crate::pulse::Shape>,
    pub cycle: crate::pulse::Cycle,
    pub f: Vec<f64>,
    /// The map's levels, decreasing.
    pub eta: Vec<f64>,
    pub eps: Vec<f64>,
    pub intervals: Option<usize>,
    /// `model.alpha`, for the nonlinear model.
    pub alpha: Option<f64>,
}

/// Most bootstrap resamples a pipeline may ask for (percentile bands settle
/// long before: their Monte Carlo error at 1,000 is already below the
/// sampling error they measure).
pub const MAX_RESAMPLES: usize = 10_000;
/// Most resamples × blocks: `capacity_resamples.parquet` has three rows
/// per pair (12 million rows at most, about a gigabyte in memory).
pub const MAX_RESAMPLED_BLOCKS: usize = 4_000_000;

/// `[uncertainty]`: percentile bootstrap bands of the capacity fractiles.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Uncertainty {
    pub resamples: usize,
    /// Two-sided level of the bands, e.g. 0.90 for the 5–95 % percentiles.
    pub level: f64,
    pub unit: ResampleUnit,
    pub seed: u64,
}

/// Where the records come from.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RecordSource {
    /// A records table written by `rocking ingest`.
    Table(PathBuf),
    /// AT2 files or folders, with an optional manifest, read directly.
    At2 {
        paths: Vec<PathBuf>,
        manifest: Option<PathBuf>,
    },
    /// Text files or folders of columns (a structural model's motions),
    /// read as `unit`, `column` and `ground` say (`crate::columns`).
    Text {
        paths: Vec<PathBuf>,
        manifest: Option<PathBuf>,
        unit: crate::columns::AccelUnit,
        column: usize,
        ground: Option<PathBuf>,
    },
}

impl RecordSource {
    /// How text records are read (none for a table or AT2 files).
    pub fn text(&self) -> Option<crate::columns::TextRecords> {
        match self {
            RecordSource::Text {
                unit,
                column,
                ground,
                ..
            } => Some(crate::columns::TextRecords {
                unit: *unit,
                column: *column,
                ground: ground.clone(),
            }),
            _ => None,
        }
    }
}

/// One block of the study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BlockSpec {
    /// Label (physical blocks) or empty (grid).
    pub name: String,
    pub p: f64,
    pub eps: f64,
    /// Slenderness, when known (physical blocks, or the model's `alpha`).
    pub alpha_rad: Option<f64>,
    /// The base's friction coefficient (`[[block]]`'s `mu`), when given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// The kinetic one (`[[block]]`'s `mu_k`), when given apart from `mu`:
    /// in the settings, so that editing it reruns the sweep.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu_k: Option<f64>,
    /// The block's run at η = 1, its model resolved and the whole checked
    /// when the plan is built (the IDA sets η).
    #[serde(skip)]
    pub run: RunSpec,
    /// Why the block runs the model it runs (`model.kind` = "auto" decides
    /// per block).
    #[serde(skip)]
    pub model_why: String,
}

/// What a pipeline studies: the records' IDA, or a pulse map.
#[derive(Debug, Clone, PartialEq)]
pub enum StudyKind {
    Records(Box<RecordsPlan>),
    PulseMap(PulsePlan),
}

/// A records study: the records, the blocks, the IM grid and what the
/// reduce, fit, convergence and uncertainty stages do with them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordsPlan {
    pub records: RecordSource,
    pub sets: Vec<String>,
    pub ids: Vec<String>,
    /// Blocks in study order (p outer, ε inner for the grid).
    pub blocks: Vec<BlockSpec>,
    pub grid: ImGrid,
    pub tol: f64,
    pub trace: Trace,
    pub fractile: FractileDef,
    /// Grid resolutions (level counts) of the capacity-convergence study,
    /// ascending; empty for none.
    pub convergence: Vec<usize>,
    /// Bootstrap bands of the capacity fractiles, if asked for.
    pub uncertainty: Option<Uncertainty>,
    /// The block of the report's Fig. 5 (`[example]`), run by the
    /// `example` stage whether or not it is one of `blocks`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub example: Option<BlockSpec>,
    /// The limit states of the damage stage (`[damage]`).
    #[serde(skip_serializing_if = "DamageStates::is_default")]
    pub damage: DamageStates,
    /// The building whose floor the blocks stand on (`[floor]`): every
    /// stage runs the floor's motion under each record.
    #[serde(
        skip_serializing_if = "Option::is_none",
        serialize_with = "floor_modes"
    )]
    pub floor: Option<Building>,
    /// `[records] orientation = "random"`: every record pair run at every
    /// angle this many degrees apart over [0°, 180°), each a record of the
    /// study (`<a>@<θ>`; docs/MODEL.md §18).
    #[serde(
        skip_serializing_if = "Option::is_none",
        rename = "random_orientation_step_deg"
    )]
    pub random_orientation: Option<f64>,
    /// `[tree]`: the example block on each path of a logic tree over ε and
    /// the model (the tree stage runs them; docs/MODEL.md §19).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tree: Option<TreePlan>,
}

/// A logic tree over the example block: each path's label, weight and
/// block (its ε and model the path's).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TreePlan {
    #[serde(skip)]
    pub tree: crate::tree::Tree,
    pub branches: Vec<TreeBranch>,
}

/// One path of [`TreePlan`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TreeBranch {
    pub label: String,
    pub weight: f64,
    pub block: BlockSpec,
}

/// A building as its modes `[T, ζ, Γφ]`, as `[floor]` writes them.
fn floor_modes<S: serde::Serializer>(b: &Option<Building>, s: S) -> Result<S::Ok, S::Error> {
    let modes: Option<Vec<[f64; 3]>> = b.as_ref().map(|b| {
        b.modes()
            .iter()
            .map(|m| [m.period_s, m.zeta, m.gamma_phi])
            .collect()
    });
    modes.serialize(s)
}

impl BlockSpec {
    /// Whether the block slides before it rocks (μ ≤ b/h), when its μ and
    /// α are known.
    pub fn slides_first(&self) -> bool {
        self.mu
            .zip(self.alpha_rad)
            .is_some_and(|(mu, a)| crate::block::slides_first(mu, a))
    }
}

impl RecordsPlan {
    /// Whether the blocks are a p × ε grid (`[blocks]`, unnamed) rather
    /// than physical `[[block]]` entries.
    pub fn is_grid(&self) -> bool {
        self.blocks.iter().all(|b| b.name.is_empty())
    }
}

/// The resolved plan: what every stage of a pipeline sees.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub name: String,
    pub description: String,
    pub model: ModelChoice,
    /// The nonlinear equation's integrator and tolerance.
    pub solver: Solver,
    pub auto_tol: f64,
    pub overturn: Overturn,
    pub study: StudyKind,
    /// The pipeline file's folder: relative paths in the file are relative
    /// to it, and fingerprints store paths relative to it.
    pub base: PathBuf,
}

/// A records study's stage or command asked of a pulse map.
#[derive(Debug, Clone, thiserror::Error)]
#[error("pipeline `{name}` is a pulse map (`[pulses]`): it runs no records")]
pub struct NotRecords {
    pub name: String,
}

impl Plan {
    /// The records study, or an error saying this plan is a pulse map.
    pub fn records_study(&self) -> Result<&RecordsPlan, NotRecords> {
        match &self.study {
            StudyKind::Records(r) => Ok(r),
            StudyKind::PulseMap(_) => Err(NotRecords {
                name: self.name.clone(),
            }),
        }
    }

    /// The pulse map, when this plan is one.
    pub fn pulse_map(&self) -> Option<&PulsePlan> {
        match &self.study {
            StudyKind::PulseMap(p) => Some(p),
            StudyKind::Records(_) => None,
        }
    }

    /// The study's blocks; none for a pulse map.
    pub fn blocks(&self) -> &[BlockSpec] {
        self.records_study().map_or(&[], |r| &r.blocks)
    }

    /// The bootstrap bands asked for; none for a pulse map.
    pub fn uncertainty(&self) -> Option<Uncertainty> {
        self.records_study().ok().and_then(|r| r.uncertainty)
    }

    /// The convergence study's grid resolutions; none for a pulse map.
    pub fn convergence(&self) -> &[usize] {
        self.records_study().map_or(&[], |r| &r.convergence)
    }

    /// The example block (`[example]`); none for a pulse map.
    /// The logic tree over the example block (`[tree]`), if any.
    pub fn tree(&self) -> Option<&TreePlan> {
        self.records_study().ok().and_then(|r| r.tree.as_ref())
    }

    pub fn example(&self) -> Option<&BlockSpec> {
        self.records_study().ok().and_then(|r| r.example.as_ref())
    }

    /// Why a stage of the records study does not run for this plan: a
    /// pulse map runs no records.
    pub fn pulse_map_skips(&self) -> Option<String> {
        self.pulse_map()
            .map(|_| "a pulse map (`[pulses]`) runs no records".to_string())
    }

    /// `path` relative to the pipeline's folder when it lies inside it (as
    /// the file wrote it), else as it is: what fingerprints store, so that
    /// the same study run from another folder or a copied output folder
    /// keeps its fingerprints.
    pub fn relative(&self, path: &Path) -> String {
        path.strip_prefix(&self.base)
            .unwrap_or(path)
            .display()
            .to_string()
    }

    /// The plan as JSON with the record paths relative to the pipeline's
    /// folder: every setting, independent of where the tool was started.
    pub fn portable_json(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("a plan serialises");
        let records = match self.records_study().map(|r| &r.records) {
            Ok(RecordSource::Table(t)) => serde_json::json!({ "table": self.relative(t) }),
            Ok(RecordSource::At2 { paths, manifest }) => serde_json::json!({
                "at2": {
                    "paths": paths.iter().map(|p| self.relative(p)).collect::<Vec<_>>(),
                    "manifest": manifest.as_deref().map(|m| self.relative(m)),
                }
            }),
            Ok(RecordSource::Text {
                paths,
                manifest,
                unit,
                column,
                ground,
            }) => serde_json::json!({
                "text": {
                    "paths": paths.iter().map(|p| self.relative(p)).collect::<Vec<_>>(),
                    "manifest": manifest.as_deref().map(|m| self.relative(m)),
                    "unit": crate::label::Label::label(*unit),
                    "column": column,
                    "ground": ground.as_deref().map(|g| self.relative(g)),
                }
            }),
            Err(_) => serde_json::json!({ "at2": { "paths": [], "manifest": null } }),
        };
        v["records"] = records;
        v
    }

    /// JSON of exactly the settings that determine the sweep's results (not
    /// the name, the description, where the records are, or what reduce
    /// does); `null` for a pulse map.
    pub fn sweep_settings(&self) -> String {
        self.sweep_settings_json().to_string()
    }

    /// [`Plan::sweep_settings`] as a JSON value.
    pub fn sweep_settings_json(&self) -> serde_json::Value {
        let Ok(r) = self.records_study() else {
            return serde_json::Value::Null;
        };
        let mut v = serde_json::json!({
            "sets": r.sets,
            "ids": r.ids,
            "model": self.model,
            "solver": self.solver,
            "auto_tol": self.auto_tol,
            "overturn": self.overturn,
            "blocks": r.blocks,
            "grid": r.grid,
            "tol": r.tol,
            "trace": r.trace,
        });
        if let Some(b) = &r.floor {
            v["floor"] = serde_json::Value::String(b.to_string());
        }
        if let Some(step) = r.random_orientation {
            // The angles the pairs are run at: which records the study has.
            v["random_orientation_step_deg"] = step.into();
        }
        v
    }
}

/// The plan's JSON (fingerprints, the tables' `rocking.plan` metadata): one
/// flat object whatever the study kind, a pulse map's under `pulses` and a
/// records study's keys at the top (empty for a pulse map), so that the
/// fingerprints of existing studies stay valid.
impl Serialize for Plan {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        struct Flat<'a> {
            name: &'a str,
            description: &'a str,
            #[serde(flatten)]
            records: std::borrow::Cow<'a, RecordsPlan>,
            model: ModelChoice,
            solver: Solver,
            auto_tol: f64,
            overturn: Overturn,
            pulses: Option<&'a PulsePlan>,
        }
        let (records, pulses) = match &self.study {
            StudyKind::Records(r) => (std::borrow::Cow::Borrowed(&**r), None),
            StudyKind::PulseMap(p) => {
                let empty = RecordsPlan {
                    records: RecordSource::At2 {
                        paths: Vec::new(),
                        manifest: None,
                    },
                    sets: Vec::new(),
                    ids: Vec::new(),
                    blocks: Vec::new(),
                    grid: ImGrid::default(),
                    tol: super::raw::default_tol(),
                    trace: Trace::StopAtFirst,
                    fractile: FractileDef::parse(&super::raw::default_fractile())
                        .expect("the default parses"),
                    convergence: Vec::new(),
                    uncertainty: None,
                    example: None,
                    damage: DamageStates::default(),
                    floor: None,
                    random_orientation: None,
                    tree: None,
                };
                (std::borrow::Cow::Owned(empty), Some(p))
            }
        };
        Flat {
            name: &self.name,
            description: &self.description,
            records,
            model: self.model,
            solver: self.solver,
            auto_tol: self.auto_tol,
            overturn: self.overturn,
            pulses,
        }
        .serialize(s)
    }
}

/// A pipeline file that cannot be used, and why: names the file and the key.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct PipelineError {
    pub path: PathBuf,
    pub message: String,
}
