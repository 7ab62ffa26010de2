//! What `export` is asked and answers: the engine, the request, the
//! refusals, the blocks as exported and the entries of the files.

use std::path::PathBuf;

use crate::damage::{DamageStates, FitMethod};
use crate::export::{ExportError, Site};
use crate::im::Im;
use crate::ops::damage::DamageFragility;
use crate::ops::fragility::{self, FragilityError, Source};
use crate::ops::risk::{self, Blocks, RiskError};
use crate::tables::TableError;

/// The engine to write for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Nrml,
    Pelicun,
}

impl crate::label::Label for Format {
    const ALL: &'static [Self] = &[Format::Nrml, Format::Pelicun];
    const WHAT: &'static str = "export format";
    fn label(self) -> &'static str {
        match self {
            Format::Nrml => "nrml",
            Format::Pelicun => "pelicun",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Format::Nrml => "OpenQuake's NRML 0.5 fragility model (and exposure and job.ini)",
            Format::Pelicun => "pelicun's fragility CSV and its metadata JSON",
        }
    }
}

crate::deserialize_by_label!(Format);

#[derive(Debug, Clone)]
pub struct Request {
    pub format: Format,
    pub blocks: Blocks,
    pub from: Source,
    pub direct: bool,
    /// Where `--direct` reports its progress.
    pub progress: fragility::DirectProgress,
    pub states: DamageStates,
    pub method: FitMethod,
    /// One β for the states of a block (the default), or each its own.
    pub dispersion: crate::damage::Dispersion,
    /// Where the capacities fail the lognormal check: their curve (the
    /// default; pelicun's multilinear_CDF, OpenQuake's discrete function)
    /// or the lognormal anyway.
    pub if_not_lognormal: crate::damage::IfNotLognormal,
    /// The IM; with `--hazard` it must be the hazard's (the default).
    pub im: Option<Im>,
    /// OpenQuake hazard curves: their sites make the exposure, and the job
    /// runs on them (NRML only).
    pub hazard: Option<PathBuf>,
    /// The risk investigation time of the job (years).
    pub years: f64,
    pub auto_tol: f64,
    /// The building whose floor the blocks stand on (`--direct` only).
    pub floor: Option<crate::floor::Building>,
    pub out: PathBuf,
    /// Which orientations of the records (`--direct`).
    pub orient: fragility::Orient,
    /// A logic tree over ε and the model: OpenQuake gets each branch's
    /// functions and a taxonomy mapping with their weights, pelicun the
    /// mean.
    pub tree: Option<crate::tree::Tree>,
}

#[derive(Debug, thiserror::Error)]
pub enum ExportOpError {
    #[error(transparent)]
    Risk(#[from] RiskError),
    #[error("block {name}")]
    Block {
        name: String,
        #[source]
        source: FragilityError,
    },
    #[error(transparent)]
    Fragility(#[from] FragilityError),
    #[error(transparent)]
    Format(#[from] ExportError),
    #[error(transparent)]
    OutPath(#[from] crate::outpath::OutPathError),
    #[error(
        "--method empirical is the records' own curve, which needs their runs: add --direct, or \
         export a lognormal (--method fractile or mle)"
    )]
    EmpiricalExport,
    #[error(
        "--hazard {}: OpenQuake's job needs its hazard-curve CSV with sites (lon, lat) and an \
         investigation_time; a plain `<im>,annual_rate` file has neither",
        .0.display()
    )]
    PlainHazard(PathBuf),
    #[error("--hazard is for --format nrml (the job's sites); pelicun takes demands, not hazard")]
    HazardForPelicun,
    #[error("--out {}: {why}", path.display())]
    Out { path: PathBuf, why: String },
    #[error(
        "block {0}: the mean over the tree never reaches 99.9 % in some state (a branch's \
         records' curve stops below 1): pelicun needs a complete function"
    )]
    TreeMean(String),
    #[error(
        "{}:{line}: block `{name}` is keyed `{taxonomy}` in the engines' files, as block \
         `{first}` (line {first_line}) is: a taxonomy keeps ASCII letters, digits, `_`, `-` and `.` \
         and makes `_` of the rest; rename one",
        .path.display()
    )]
    SameTaxonomy {
        path: PathBuf,
        line: u64,
        name: String,
        first: String,
        first_line: u64,
        taxonomy: String,
    },
    #[error(transparent)]
    Lock(#[from] crate::stages::lock::LockError),
    #[error(transparent)]
    Write(#[from] TableError),
}

/// One block as exported: itself, its taxonomy in the files, and its
/// fragilities.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ExportedBlock {
    pub block: risk::BlockInfo,
    /// The block's key in the engines' files ([`taxonomy`]).
    pub taxonomy: String,
    /// What its states are written as: `lognormal`, or `curve` (the
    /// records' own: pelicun's `multilinear_CDF`, OpenQuake's discrete
    /// function).
    pub written_as: &'static str,
    /// The block's damage-state fragilities; with `--tree`, its first
    /// branch's (every branch's in `tree.branches`), with every branch's
    /// warnings.
    pub fragility: DamageFragility,
    /// With `--tree`: its branches as the engines' files carry them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tree: Option<TreeExport>,
}

/// The entries of the engines' files: the fragility functions (a
/// branch's each with a tree, for OpenQuake), the exposure's blocks, and
/// the taxonomy mapping (taxonomy, function id, weight) of a tree.
#[derive(Debug, Default)]
pub(crate) struct Entries {
    pub functions: Vec<crate::export::Entry>,
    pub exposure: Vec<crate::export::Entry>,
    pub mapping: Vec<(String, String, f64)>,
}

/// What was written, and the fragilities behind it.
#[derive(Debug)]
pub struct Written {
    pub files: Vec<PathBuf>,
    pub blocks: Vec<ExportedBlock>,
}

/// An OpenQuake hazard file: its text, IM, sites and investigation time.
pub(super) struct HazardSites {
    /// The curves as `risk` reads them, by site.
    pub curves: Vec<(usize, crate::hazard::HazardCurve)>,
    /// The file as OpenQuake's job reads it ([`crate::hazard::openquake_input`]).
    pub text: String,
    pub im: Im,
    pub sites: Vec<Site>,
    pub investigation_time: f64,
    /// Of its curves' units ([`risk::hazard_warnings`]).
    pub warnings: Vec<String>,
}

/// A block over a logic tree, as the engines' files carry it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct TreeExport {
    pub tree: String,
    /// Each branch: its function id in the fragility model (OpenQuake),
    /// weight, ε and model.
    pub branches: Vec<BranchExport>,
    /// How pelicun's one function per state carries the mean (with
    /// `--format pelicun`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mean: Option<crate::ops::tree::MeanFit>,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct BranchExport {
    pub risk_id: String,
    pub branch: String,
    pub weight: f64,
    pub eps: f64,
    /// The branch's damage-state fragilities (OpenQuake gets them as its
    /// functions; pelicun their mean).
    pub fragility: DamageFragility,
}
