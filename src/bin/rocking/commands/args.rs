//! Arguments shared by several commands. Each group parses into the
//! library's request vocabulary (`rocking::ask`), which does every check;
//! closed sets take their possible values from the library's labels
//! ([`label`]), so a new member appears here without a line changed.

use std::path::{Path, PathBuf};

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use rocking::ask::{AskedBlock, BlockAsk, LawAsk, PulseAsk, Spelling};
use rocking::block::Restitution;
use rocking::building::ShapedMode;
use rocking::columns::AccelUnit;
use rocking::damage::{DamageStates, Dispersion, FitMethod, IfNotLognormal};
use rocking::floor::Mode;
use rocking::im::Im;
use rocking::label::Label;
use rocking::pair::Orientation;
use rocking::physics::{ModelChoice, NonlinearIntegrator, Overturn};
use rocking::pulse::{Cycle, ShapeKind};

/// The value parser of a closed set: its labels as the possible values,
/// each with its help, its aliases accepted.
pub fn label<T: Label + Clone + Send + Sync>() -> impl TypedValueParser<Value = T> {
    label_among(T::ALL)
}

/// [`label`] offering only `members` (their help and aliases as there):
/// for a command that takes a few of a set's members.
pub fn label_among<T: Label + Clone + Send + Sync>(
    members: &'static [T],
) -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(members.iter().map(|m| {
        let value = PossibleValue::new(m.label()).aliases(m.aliases().iter().copied());
        match m.help() {
            "" => value,
            help => value.help(help),
        }
    }))
    .map(|text| T::parse_label(&text).expect("clap admits the possible values only"))
}

/// A value parsed by the library's `FromStr` (an IM, ε, a floor's mode,
/// the overturning criterion, damage states), its message as the error.
pub fn parsed<T>(text: &str) -> Result<T, String>
where
    T: std::str::FromStr,
    T::Err: std::fmt::Display,
{
    not_an_option(text)?;
    text.parse::<T>().map_err(|e| e.to_string())
}

/// A number of a list option (`--pga 0.3,0.5`), which, taking values that
/// start with a minus sign, would take the next option for its value.
pub fn number(text: &str) -> Result<f64, String> {
    not_an_option(text)?;
    text.trim()
        .parse::<f64>()
        .map_err(|_| format!("`{text}` is not a number"))
}

/// Refuses the next option taken for a value (`--floor --json`: an option
/// that takes a value starting with a minus sign takes whatever follows).
fn not_an_option(text: &str) -> Result<(), String> {
    let option = text
        .strip_prefix("--")
        .is_some_and(|rest| rest.starts_with(|c: char| c.is_ascii_alphabetic()));
    match option {
        true => Err(format!("a value is missing: `{text}` is the next option")),
        false => Ok(()),
    }
}

/// A pipeline and where its outputs go.
#[derive(Debug, clap::Args)]
pub struct PipelineArgs {
    /// The pipeline file.
    #[arg(value_name = "PIPELINE.toml")]
    pub pipeline: PathBuf,
    /// Root of the outputs; everything goes to <outputs>/<pipeline name>/.
    #[arg(long, default_value = "outputs")]
    pub outputs: PathBuf,
}

impl PipelineArgs {
    pub fn study(&self) -> anyhow::Result<rocking::stages::Study> {
        Ok(rocking::stages::Study::load(&self.pipeline, &self.outputs)?)
    }
}

/// Where a block's capacity law comes from, for `fragility`, `risk` and
/// `export`.
#[derive(Debug, clap::Args)]
pub struct LawArgs {
    /// `paper` (published coefficients) or a pipeline file whose fit to use.
    #[arg(long, default_value = "paper")]
    pub from: String,
    /// Root of the outputs, for --from PIPELINE.toml [default: outputs].
    #[arg(long, value_name = "DIR")]
    pub outputs: Option<PathBuf>,
    /// Records for --direct when --from paper: a folder of AT2 files
    /// [default: records/fema-p695/far-field in the current directory, or
    /// else in the repository this binary was built from].
    #[arg(long)]
    pub records: Option<PathBuf>,
    /// With --direct: the --records are text files of columns in this unit, not AT2 files:
    /// a structural model's floor motions (an OpenSees Node recorder with
    /// -time, or time and acceleration), each scaled itself.
    #[arg(long, value_parser = label::<AccelUnit>(), value_name = "UNIT")]
    pub records_unit: Option<AccelUnit>,
    /// With --records-unit: the value column to read (1 = the first after
    /// time) [default: 1].
    #[arg(long, value_name = "K")]
    pub records_column: Option<usize>,
    /// With --records-unit: the records are accelerations relative to the
    /// ground (an OpenSees Node recorder without -timeSeries); the ground
    /// motions they were run with, as run (scaled), are in this folder, one
    /// of the same name each (AT2 in g, or time and acceleration in the
    /// records' unit), and are added at the records' times.
    #[arg(long, value_name = "DIR")]
    pub records_ground: Option<PathBuf>,
    /// With --direct: which orientations of the block the records are run
    /// at; random and worst need record pairs (the records' manifest gives
    /// each its pair and component).
    #[arg(long, value_parser = label::<Orientation>(), default_value = "as-recorded")]
    pub orientation: Orientation,
    /// With --orientation random or worst: the angle step over [0°, 180°).
    #[arg(long, value_name = "DEG", default_value_t = rocking::pair::ANGLE_STEP_DEG)]
    pub angle_step: f64,
    /// A logic tree over the block's ε and the model (a TOML file of
    /// `[[eps]]` and `[[model]]` branches with weights, or a named tree:
    /// `restitution-tests`): each branch's answer, their weighted mean and
    /// quantiles (docs/MODEL.md §19).
    #[arg(long, value_name = "TREE.toml")]
    pub tree: Option<String>,
}

impl LawArgs {
    pub fn ask(&self) -> LawAsk {
        LawAsk {
            source: self.from.clone(),
            outputs: self.outputs.clone(),
            records: self.records.clone(),
            records_unit: self.records_unit,
            records_column: self.records_column,
            records_ground: self.records_ground.clone(),
            orientation: self.orientation,
            angle_step: self.angle_step,
        }
    }
}

/// A pulse as the excitation (`simulate`, `capacity`, `wall`).
#[derive(Debug, clap::Args)]
pub struct PulseArgs {
    /// Excite the block by a pulse rather than an AT2 record.
    #[arg(long, value_parser = label::<ShapeKind>())]
    pub pulse: Option<ShapeKind>,
    /// Shape parameter β of the exponential pulse (→ −∞ rectangle, 0 triangle, → +∞ spike).
    #[arg(long, value_name = "β")]
    pub beta: Option<f64>,
    /// With --pulse: one lobe (half) or the lobe followed by its negative (full).
    #[arg(long, value_parser = label::<Cycle>(), default_value = "half", requires = "pulse")]
    pub cycle: Cycle,
}

impl PulseArgs {
    /// The pulse asked, with lobes of `td` seconds.
    pub fn ask(&self, td: f64) -> PulseAsk {
        PulseAsk {
            pulse: self.pulse,
            beta: self.beta,
            cycle: self.cycle,
            td,
        }
    }
}

/// The block (or blocks) and the model, for `simulate` and `capacity`: by
/// p and ε, or by its dimensions (half `--b --h`, or full `--width
/// --height`, in m) and ε. Each option takes a comma-separated list; only
/// `capacity` takes more than one block (p × ε, or each size × ε).
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct BlockArgs {
    #[command(flatten)]
    pub pulse: PulseArgs,
    /// With --pulse: the lobe's duration t_d (s); f = p·t_d.
    #[arg(long, value_name = "s", default_value_t = rocking::ask::excitation::TD_S,
          requires = "pulse")]
    pub td: f64,
    /// Frequency parameter p = sqrt(3g/(4R)) of the block (1/s).
    #[arg(
        long,
        value_name = "1/s",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = number
    )]
    pub p: Vec<f64>,
    /// Half-width b of the block (m); with --h, instead of --p (α = atan(b/h)).
    #[arg(
        long,
        value_name = "m",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = number
    )]
    pub b: Vec<f64>,
    /// Half-height h of the block (m), with --b.
    #[arg(
        long,
        value_name = "m",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = number
    )]
    pub h: Vec<f64>,
    /// Full width 2b of the block (m); with --height, instead of --p.
    #[arg(
        long,
        value_name = "m",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = number
    )]
    pub width: Vec<f64>,
    /// Full height 2h of the block (m), with --width.
    #[arg(
        long,
        value_name = "m",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = number
    )]
    pub height: Vec<f64>,
    /// Coefficient of restitution ε in (0, 1], or `housner` (1 − 1.5 sin²α;
    /// needs the block's dimensions).
    #[arg(long, value_name = "ε", value_delimiter = ',', allow_hyphen_values = true, required = true, value_parser = parsed::<Restitution>)]
    pub eps: Vec<Restitution>,
    /// Equation of motion.
    #[arg(long, value_parser = label::<ModelChoice>(), default_value = "linearized")]
    pub model: ModelChoice,
    /// Slenderness α = atan(b/h) of the block (rad), for the nonlinear model
    /// and a PGA; from the dimensions when they are given.
    #[arg(long, value_name = "rad")]
    pub alpha: Option<f64>,
    /// The nonlinear model's integrator.
    #[arg(long, value_parser = label::<NonlinearIntegrator>(), default_value = "taylor")]
    pub integrator: NonlinearIntegrator,
    /// Its tolerance (capacities are then certified at a 100× tighter one):
    /// the Taylor series' tail per sample interval (default 1e-10), or DP5's
    /// relative tolerance per step (default 1e-10).
    #[arg(long)]
    pub rtol: Option<f64>,
    /// For --model auto: the relative error in η_c accepted from the linearisation.
    #[arg(long, default_value_t = rocking::ask::block::AUTO_TOL)]
    pub auto_tol: f64,
    /// Overturning criterion: static (|θ| ≥ α), cap:<c> (|θ| ≥ cα), on-side (θ = π/2,
    /// nonlinear), escape (never comes back: θ = π/2 nonlinear; linearised, proven unbounded).
    #[arg(long, default_value_t = Overturn::Static, value_parser = parsed::<Overturn>)]
    pub overturn: Overturn,
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Kinetic friction coefficient of the base (≤ --mu; --mu when not
    /// given), for the slide-rock model.
    #[arg(long, value_name = "μₖ")]
    pub mu_k: Option<f64>,
    /// Print JSON (one object a line) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// The building whose floor the block stands on.
#[derive(Debug, Clone, clap::Args)]
pub struct FloorArgs {
    /// The block stands on a floor of a linear building: one mode of it as
    /// T,ZETA,GAMMA_PHI (period in s, damping ratio, participation factor ×
    /// mode shape at the floor); repeat for each mode. The records are the
    /// ground's; the block feels the floor's absolute acceleration.
    #[arg(long = "floor", value_name = "T,ZETA,GAMMA_PHI", value_parser = parsed::<Mode>, allow_hyphen_values = true)]
    pub floor: Vec<Mode>,
    /// Or a building with every floor: one mode as T,ZETA,GAMMA,PHI1,…,PHIn
    /// (period in s, damping ratio, participation factor, the mode's shape
    /// at each floor, lowest first); repeat for each mode. --level picks
    /// the block's floor (Γφ = Γ·φ there).
    #[arg(
        long = "building",
        value_name = "T,ZETA,GAMMA,PHI…",
        value_parser = parsed::<ShapedMode>,
        allow_hyphen_values = true
    )]
    pub building: Vec<ShapedMode>,
    /// The floor of --building the block stands on (1 = the lowest its
    /// shapes give).
    #[arg(long, value_name = "K")]
    pub level: Option<usize>,
}

/// Where the block stands: on the ground, or on a building's floor; and
/// how firmly (its base's friction).
#[derive(Debug, Clone, clap::Args)]
pub struct SceneArgs {
    #[command(flatten)]
    pub floor: FloorArgs,
    /// Static friction coefficient μ between the block and its base: a block
    /// with μ up to b/h slides before it rocks, and one above may slip as it
    /// rocks; `--model auto` (and `--direct`) runs a block with μ on its
    /// friction (the slide-rock model).
    #[arg(long, value_name = "μ")]
    pub mu: Option<f64>,
}

impl BlockArgs {
    /// The block asked, in the library's vocabulary.
    pub fn ask(&self) -> BlockAsk {
        BlockAsk {
            p: self.p.clone(),
            b: self.b.clone(),
            h: self.h.clone(),
            width: self.width.clone(),
            height: self.height.clone(),
            eps: self.eps.clone(),
            alpha: self.alpha,
            model: self.model,
            integrator: self.integrator,
            rtol: self.rtol,
            auto_tol: self.auto_tol,
            overturn: self.overturn,
            mu: self.scene.mu,
            mu_k: self.mu_k,
            floor: self.scene.floor.floor.clone(),
            building: self.scene.floor.building.clone(),
            level: self.scene.floor.level,
        }
    }

    /// The blocks asked, in order, each checked, at η = 1; a block that
    /// slides first, or of sizes in another unit, is warned of on stderr.
    pub fn blocks(&self) -> anyhow::Result<Vec<AskedBlock>> {
        let blocks = self.ask().resolve(Spelling::Cli)?;
        for w in AskedBlock::warnings_of(&blocks) {
            eprintln!("warning: {w}");
        }
        Ok(blocks)
    }

    /// The one block of a command that takes one.
    pub fn one(&self) -> anyhow::Result<AskedBlock> {
        let mut blocks = self.blocks()?;
        if blocks.len() != 1 {
            anyhow::bail!(
                "{} blocks given; this command runs one (give one value to each block option)",
                blocks.len()
            );
        }
        Ok(blocks.remove(0))
    }

    /// The record at `path`, or the pulse sampled for the block's p.
    pub fn excitation(
        &self,
        path: Option<&Path>,
        p: f64,
    ) -> anyhow::Result<rocking::records::LoadedRecord> {
        let pulse = self.pulse.ask(self.td).resolve(Spelling::Cli)?;
        let building = self.ask().building(Spelling::Cli)?;
        Ok(rocking::records::excitation(
            path,
            pulse.as_ref(),
            building.as_ref(),
            p,
        )?)
    }
}

/// `--direct`'s progress on stderr (a bar on a terminal, log lines
/// otherwise), or none without `--direct`.
pub fn direct_progress(direct: bool) -> rocking::ops::fragility::DirectProgress {
    use rocking::ops::fragility::DirectProgress;
    match direct {
        true => DirectProgress::to(std::sync::Arc::new(crate::reporter::Terminal::new())),
        false => DirectProgress::default(),
    }
}

/// One block by its half sizes, or every block of an inventory (`risk`,
/// `export`).
#[derive(Debug, Clone, clap::Args)]
pub struct BlocksArgs {
    /// Half-width of the block (m).
    #[arg(long, value_name = "m", required_unless_present = "inventory")]
    pub b: Option<f64>,
    /// Half-height of the block (m).
    #[arg(long, value_name = "m", required_unless_present = "inventory")]
    pub h: Option<f64>,
    /// Coefficient of restitution, or `housner` for 1 − 1.5 sin²α.
    #[arg(long, default_value = "housner", value_parser = parsed::<Restitution>)]
    pub eps: Restitution,
    /// A CSV of blocks `name,b,h[,eps][,mu]` (m; eps empty or `housner` for
    /// Housner's bound; mu the base's friction coefficient, empty if not
    /// known; in an export, a name's spaces become `_` in its taxonomy).
    /// Other columns are passed over; one like a misspelt or renamed known
    /// column (`epsilon`, `friction`, `Mu`) is refused.
    #[arg(long, value_name = "BLOCKS.csv")]
    pub inventory: Option<PathBuf>,
    /// Static friction coefficient μ between the block and its base: a block
    /// with μ up to b/h slides before it rocks, and is warned of (an
    /// inventory gives it in its `mu` column).
    #[arg(long, value_name = "μ")]
    pub mu: Option<f64>,
}

impl BlocksArgs {
    pub fn ask(&self) -> rocking::ask::BlocksAsk {
        rocking::ask::BlocksAsk {
            b: self.b,
            h: self.h,
            eps: self.eps,
            inventory: self.inventory.clone(),
            mu: self.mu,
        }
    }
}

/// Damage states instead of overturning alone, and their fit.
#[derive(Debug, Clone, clap::Args)]
pub struct StatesArgs {
    /// Damage states instead of overturning alone, lightest first: NAME=X
    /// (θmax/α ≥ X), NAME=Xm (the base slides X metres: the slide-rock
    /// model, --mu) or NAME=overturned, e.g.
    /// rocking=0.1,large_rocking=0.5,overturned=overturned.
    #[arg(long, value_parser = parsed::<DamageStates>)]
    pub states: Option<DamageStates>,
    /// How the fragility is made from the capacities: a lognormal by the
    /// paper's fractiles or by maximum likelihood, or (--direct) the
    /// records' own curve.
    #[arg(long, value_parser = label::<FitMethod>(), default_value = "fractile")]
    pub method: FitMethod,
    /// Several states' dispersions: one β for all (the heaviest state's,
    /// medians in order, so no heavier state is ever likelier than a
    /// lighter one) or each its own.
    #[arg(long, value_parser = label::<Dispersion>(), default_value = "common")]
    pub dispersion: Dispersion,
    /// Where the records' capacities fail the lognormal check (Lilliefors at
    /// 5 % on their logarithms; --direct): their own curve, as --method
    /// empirical, or the lognormal anyway [default: curve].
    #[arg(long, value_parser = label::<IfNotLognormal>())]
    pub if_not_lognormal: Option<IfNotLognormal>,
}

/// The IM of a fragility.
pub fn parse_im(text: &str) -> Result<Im, String> {
    parsed::<Im>(text)
}
