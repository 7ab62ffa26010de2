//! Why a fragility cannot be made: every refusal of `fragility`, `risk` and
//! `export` about a block, its capacities or its records.

use std::path::PathBuf;

use crate::ops::im_fragility;
use crate::physics::PhysicsError;
use crate::records::CollectError;
use crate::records::SelectError;
use crate::stages::fit::FitError;
use crate::stages::LoadError;

/// Why a block's fragility cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum FragilityError {
    #[error(
        "damage state `{state}`: {from}'s regression knows only overturning; the other states \
         come from a study's damage table (--from PIPELINE.toml, after `rocking run`) or the \
         records' runs (--direct)"
    )]
    StatesNeedRecords { from: String, state: String },
    #[error(
        "limit state `{state}` is on the slide: it needs the records' runs of the slide-rock \
         model (--direct, with the base's friction --mu or an inventory's `mu`)"
    )]
    SlideNeedsRuns { state: String },
    #[error("--auto-tol: {0}")]
    AutoTol(String),
    #[error("--b and --h must be positive (m); got b = {b}, h = {h}")]
    Size { b: f64, h: f64 },
    #[error("--eps = {0}: ε must be in (0, 1]")]
    Eps(f64),
    #[error(
        "Housner's ε = 1 − 1.5 sin²α = {eps:.3} is not positive for a block this stocky \
         (b/h = {ratio:.3}, α = {alpha:.3} rad): give --eps, a coefficient of restitution in (0, 1]"
    )]
    HousnerEps { eps: f64, ratio: f64, alpha: f64 },
    #[error("--mu")]
    Mu(#[source] crate::block::BlockError),
    #[error("--at {0}: levels must be positive")]
    Level(f64),
    #[error("give at least one level (--pga, or --im and --at)")]
    NoLevel,
    #[error(
        "the paper's regression is in PGA; a fragility in {0} comes from a study's IM table (--from PIPELINE.toml, after `rocking run`) or from the records (--direct)"
    )]
    PaperIsPga(String),
    #[error(transparent)]
    ImTable(#[from] im_fragility::ImTableError),
    #[error("the records' intensity measures")]
    RecordIms(#[from] crate::im::RecordImsError),
    #[error(
        "{0}: a study's records carry SA at {periods} s only (docs/MODEL.md §14); ask for one \
         of them, or run the block through the records (--direct), which computes SA at any \
         period",
        periods = crate::im::PERIODS_S.map(crate::im::period_text).join(", ")
    )]
    NoPeriod(String),
    #[error(
        "{0} is a measure of the ground's motion, and text records are the motions the block \
         stands on (a structural model's floors, each scaled itself): their {0} would be the \
         floor's, labelled the ground's. A hazard (risk, an NRML export) is in a ground IM, \
         which text records cannot give: run the building (--floor or --building) over AT2 \
         ground records. A fragility alone is stated in a demand of these motions, from the \
         block's own runs (fragility or a pelicun export with --direct --im pfa, pfv or fsa(T); \
         for ground motions given as text, pfa is their PGA)"
    )]
    TextGroundIm(String),
    #[error(
        "--records-ground makes the text records relative floor motions, the floor's own once \
         their ground is added, and --floor (or --building) runs records through the building \
         as its ground motions: they would go through it twice; drop --floor, or give the ground \
         motions as the records with --floor"
    )]
    TextFloorTwice,
    #[error(
        "the {0} model is chosen (a tree's [[model]] branch), but a regression or a study's \
         tables are of the model they were made by: add --direct to run the records"
    )]
    ModelNeedsRuns(&'static str),
    #[error(
        "the tree sets ε on every branch, and the block has its own ε = {0}: leave its eps empty \
         (Housner's) or drop the tree's [[eps]]"
    )]
    TreeEps(f64),
    #[error("the tree's branch `{branch}` gives this block ε = {eps}; ε must be in (0, 1]")]
    TreeBranchEps { branch: String, eps: f64 },
    #[error(
        "damage state `{state}`: β = {beta}{}: a lognormal without spread, which the engines \
         cannot evaluate (OpenQuake's gives NaN); run more records (--records), or export fewer \
         states",
        match reached {
            Some(1) => " (one record reaches it)".to_string(),
            Some(n) => format!(" ({n} records reach it, all at one level)"),
            None => String::new(),
        }
    )]
    NoSpread {
        state: String,
        beta: f64,
        reached: Option<usize>,
    },
    #[error(
        "damage state `{state}`: no record's runs reach it (its probability is 0 at every level \
         they ran), which no engine's fragility function can state{}",
        if *slides_first {
            ": the block slides before it rocks, so under horizontal shaking it neither rocks \
             nor overturns; export its states on the slide (--states NAME=Xm,…)"
        } else {
            "; leave the state out (--states)"
        }
    )]
    NeverReached { state: String, slides_first: bool },
    #[error(
        "damage state `{state}`: {why}, which no engine's curve can; export a lognormal \
         (--method fractile or mle)"
    )]
    CurveShort {
        state: String,
        /// [`crate::damage::Curve::shortfall`]'s words.
        why: String,
    },
    #[error("damage state `{state}` has no {method} fit ({why}); try --method {other}")]
    NoStateFit {
        state: String,
        method: &'static str,
        other: &'static str,
        why: &'static str,
    },
    #[error("too few of the records overturn the block within the grid to fit a lognormal in {0}")]
    FewCapacities(String),
    #[error(
        "--direct runs the block through a folder of AT2 records, and {} is not a folder{}: \
         give --records FOLDER (the FEMA P695 far-field set is records/fema-p695/far-field \
         in rocking's repository), or --from PIPELINE.toml to use a pipeline's records",
        .0.display(),
        if .0.is_relative() { " (relative to the current directory)" } else { "" }
    )]
    NoRecords(PathBuf),
    /// The records do not come in pairs where an orientation or a pair's IM needs them.
    #[error("{0}")]
    Pairs(String),
    #[error(
        "the regression gives no valid capacity fractiles at p = {p:.3}, ε = {eps:.3} (its \
         polynomials in ε leave their valid range there); run the block itself through the \
         records with --direct"
    )]
    NoFractiles { p: f64, eps: f64 },
    #[error(transparent)]
    Pipeline(#[from] LoadError),
    #[error(transparent)]
    Fit(#[from] FitError),
    #[error(
        "{pipeline} has no regression to take fractiles from: {why}; add --direct to run the \
         block through the study's records, or use --from paper for the published regression"
    )]
    NoFit { pipeline: PathBuf, why: String },
    #[error(
        "the {what} in {dir} is not {pipeline}'s as it stands ({why}): another pipeline of the \
         same name, or an earlier version of this one, wrote it; run `rocking run {pipeline}` \
         (`rocking status {pipeline}` shows what changed)",
        dir = .dir.display(),
        pipeline = .pipeline.display()
    )]
    Stale {
        /// `fit`, `IM table` or `damage table`.
        what: &'static str,
        pipeline: PathBuf,
        dir: PathBuf,
        why: String,
    },
    #[error("--direct")]
    Records(#[source] SelectError),
    #[error("--direct")]
    Ingest(#[source] CollectError),
    #[error("--direct: the model for this block")]
    Model(#[source] PhysicsError),
    #[error(
        "--floor: the capacities of {from} are of blocks on the ground; a block on a floor is \
         run through the building with the records (add --direct)"
    )]
    FloorNeedsDirect { from: String },
    #[error(
        "--floor: {0} has its own building (`[floor]`); its records run through it with --direct"
    )]
    FloorTwice(String),
    #[error(
        "{0} is a study of blocks on a building's floor (`[floor]`): its fit and tables are \
         not carried to another block; add --direct to run its records through its building \
         for this one"
    )]
    FloorStudy(String),
    #[error("--direct: record {record}")]
    Physics {
        record: String,
        #[source]
        source: PhysicsError,
    },
}
