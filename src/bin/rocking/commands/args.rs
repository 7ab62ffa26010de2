//! Arguments shared by several commands.

use std::path::{Path, PathBuf};

use clap::ValueEnum;
use rocking::block::{Block, Restitution};
use rocking::floor::{Building, Mode};
use rocking::ops::capacity::NamedSpec;
use rocking::physics::{ModelChoice, Overturn};

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

/// Where a block's capacity law comes from, for `fragility` and `risk`.
#[derive(Debug, clap::Args)]
pub struct LawArgs {
    /// `paper` (published coefficients) or a pipeline file whose fit to use.
    #[arg(long, default_value = "paper")]
    pub from: String,
    /// Root of the outputs (for --from PIPELINE.toml).
    #[arg(long, default_value = "outputs")]
    pub outputs: PathBuf,
    /// Records for --direct when --from paper: a folder of AT2 files
    /// [default: records/fema-p695/far-field in the current directory, or
    /// else in the repository this binary was built from].
    #[arg(long)]
    pub records: Option<PathBuf>,
}

impl LawArgs {
    pub fn source(&self) -> rocking::ops::fragility::Source {
        rocking::ops::fragility::Source::named(
            &self.from,
            self.outputs.clone(),
            self.records.clone(),
        )
    }
}

/// The model as chosen on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ModelArg {
    /// Paper Eq. 8, exact stepping (depends on p, η, ε only).
    Linearized,
    /// Paper Eq. 7 (by --integrator); needs --alpha.
    Nonlinear,
    /// Linearised where its error for --alpha is below --auto-tol, else nonlinear.
    Auto,
}

impl From<ModelArg> for ModelChoice {
    fn from(m: ModelArg) -> Self {
        match m {
            ModelArg::Linearized => ModelChoice::Linearized,
            ModelArg::Nonlinear => ModelChoice::Nonlinear,
            ModelArg::Auto => ModelChoice::Auto,
        }
    }
}

/// The nonlinear equation's integrator on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum IntegratorArg {
    /// Its Taylor series, one step per sample interval (the default).
    Taylor,
    /// Dormand–Prince 5(4).
    Dp5,
}

/// How the nonlinear equation is integrated.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct SolverArgs {
    /// The nonlinear model's integrator.
    #[arg(long, value_enum, default_value = "taylor")]
    pub integrator: IntegratorArg,
    /// Its tolerance (capacities are then certified at a 100× tighter one):
    /// the Taylor series' tail per sample interval (default 1e-10), or DP5's
    /// relative tolerance per step (default 1e-10).
    #[arg(long)]
    pub rtol: Option<f64>,
}

impl SolverArgs {
    /// The solver asked for, its tolerance checked.
    pub fn solver(&self) -> anyhow::Result<rocking::physics::Solver> {
        use rocking::physics::{NonlinearIntegrator, Solver};
        let integrator = match self.integrator {
            IntegratorArg::Taylor => NonlinearIntegrator::Taylor,
            IntegratorArg::Dp5 => NonlinearIntegrator::Dp5,
        };
        Solver::new(integrator, self.rtol).map_err(|e| anyhow::anyhow!("--rtol: {e}"))
    }
}

/// A pulse's shape on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ShapeArg {
    /// Rectangular lobe (Housner's pulse).
    Rect,
    /// The paper's exponential lobe (Eq. 4), shape --beta.
    Exp,
}

/// Half cycle (one lobe) or full cycle (the lobe, then its negative).
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum CycleArg {
    Half,
    Full,
}

/// A pulse as the excitation (`simulate`, `capacity`, `wall`).
#[derive(Debug, clap::Args)]
pub struct PulseArgs {
    /// Excite the block by a pulse (rect or exp, paper Eq. 4) rather than an AT2 record.
    #[arg(long, value_enum)]
    pub pulse: Option<ShapeArg>,
    /// Shape parameter β of the exponential pulse (→ −∞ rectangle, 0 triangle, → +∞ spike).
    #[arg(long, value_name = "β", requires = "pulse")]
    pub beta: Option<f64>,
    /// One lobe (half) or the lobe followed by its negative (full).
    #[arg(long, value_enum, default_value_t = CycleArg::Half)]
    pub cycle: CycleArg,
}

impl PulseArgs {
    /// The pulse with lobes of `t_d_s`, if one was asked for.
    pub fn pulse(&self, t_d_s: f64) -> anyhow::Result<Option<rocking::pulse::Pulse>> {
        use rocking::pulse::{Cycle, Pulse, Shape};
        let shape = match (self.pulse, self.beta) {
            (None, _) => return Ok(None),
            (Some(ShapeArg::Rect), None) => Shape::Rect,
            (Some(ShapeArg::Rect), Some(_)) => {
                anyhow::bail!("--beta is the exponential pulse's shape; --pulse rect takes none")
            }
            (Some(ShapeArg::Exp), Some(beta)) => Shape::Exp { beta },
            (Some(ShapeArg::Exp), None) => anyhow::bail!("--pulse exp needs --beta"),
        };
        let cycle = match self.cycle {
            CycleArg::Half => Cycle::Half,
            CycleArg::Full => Cycle::Full,
        };
        let pulse = Pulse {
            shape,
            cycle,
            t_d_s,
        };
        pulse.validate()?;
        Ok(Some(pulse))
    }
}

/// A pulse's lobe duration when none is given (s).
const TD_S: f64 = 1.0;
/// `--auto-tol` when none is given.
const AUTO_TOL: f64 = 0.01;

/// The block (or blocks) and the model, for `simulate` and `capacity`: by
/// p and ε, or by its dimensions (half `--b --h`, or full `--width
/// --height`, in m) and ε. Each option takes a comma-separated list; only
/// `capacity` takes more than one block (p × ε, or each size × ε).
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct BlockArgs {
    #[command(flatten)]
    pub pulse: PulseArgs,
    /// The pulse's lobe duration t_d (s); f = p·t_d.
    #[arg(long, value_name = "s", default_value_t = TD_S, requires = "pulse")]
    pub td: f64,
    /// Frequency parameter p = sqrt(3g/(4R)) of the block (1/s).
    #[arg(
        long,
        value_name = "1/s",
        value_delimiter = ',',
        required_unless_present_any = ["b", "width"],
        conflicts_with_all = ["b", "width"]
    )]
    pub p: Vec<f64>,
    /// Half-width b of the block (m); with --h, instead of --p (α = atan(b/h)).
    #[arg(
        long,
        value_name = "m",
        value_delimiter = ',',
        requires = "h",
        conflicts_with = "width"
    )]
    pub b: Vec<f64>,
    /// Half-height h of the block (m), with --b.
    #[arg(long, value_name = "m", value_delimiter = ',', requires = "b")]
    pub h: Vec<f64>,
    /// Full width 2b of the block (m); with --height, instead of --p.
    #[arg(long, value_name = "m", value_delimiter = ',', requires = "height")]
    pub width: Vec<f64>,
    /// Full height 2h of the block (m), with --width.
    #[arg(long, value_name = "m", value_delimiter = ',', requires = "width")]
    pub height: Vec<f64>,
    /// Coefficient of restitution ε in (0, 1], or `housner` (1 − 1.5 sin²α;
    /// needs the block's dimensions).
    #[arg(long, value_name = "ε", value_delimiter = ',', required = true, value_parser = parse_restitution)]
    pub eps: Vec<Restitution>,
    /// Equation of motion.
    #[arg(long, value_enum, default_value_t = ModelArg::Linearized)]
    pub model: ModelArg,
    /// Slenderness α = atan(b/h) of the block (rad), for the nonlinear model
    /// and a PGA; from the dimensions when they are given.
    #[arg(long, value_name = "rad", conflicts_with_all = ["b", "width"])]
    pub alpha: Option<f64>,
    #[command(flatten)]
    pub solver: SolverArgs,
    /// For --model auto: the relative error in η_c accepted from the linearisation.
    #[arg(long, default_value_t = AUTO_TOL)]
    pub auto_tol: f64,
    /// Overturning criterion: static (|θ| ≥ α), cap:<c> (|θ| ≥ cα), on-side (θ = π/2,
    /// nonlinear), escape (never comes back: θ = π/2 nonlinear; linearised, proven unbounded).
    #[arg(long, default_value_t = Overturn::Static, value_parser = parse_overturn)]
    pub overturn: Overturn,
    #[command(flatten)]
    pub scene: SceneArgs,
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
    #[arg(long = "floor", value_name = "T,ZETA,GAMMA_PHI", value_parser = parse_mode)]
    pub floor: Vec<Mode>,
}

impl FloorArgs {
    /// The building asked for, checked; `None` on the ground.
    pub fn building(&self) -> anyhow::Result<Option<Building>> {
        if self.floor.is_empty() {
            return Ok(None);
        }
        Building::new(self.floor.clone())
            .map(Some)
            .map_err(|e| anyhow::anyhow!("--floor: {e}"))
    }
}

/// Where the block stands: on the ground, or on a building's floor; and
/// how firmly (its base's friction).
#[derive(Debug, Clone, clap::Args)]
pub struct SceneArgs {
    #[command(flatten)]
    pub floor: FloorArgs,
    /// Static friction coefficient μ between the block and its base: a block
    /// with μ below b/h slides before it rocks, and is warned of.
    #[arg(long, value_name = "μ")]
    pub mu: Option<f64>,
}

pub fn parse_mode(text: &str) -> Result<Mode, String> {
    text.parse::<Mode>().map_err(|e| e.to_string())
}

impl SceneArgs {
    pub fn building(&self) -> anyhow::Result<Option<Building>> {
        self.floor.building()
    }

    /// μ checked.
    pub fn mu(&self) -> anyhow::Result<Option<f64>> {
        self.mu
            .map(rocking::block::check_mu)
            .transpose()
            .map_err(|e| anyhow::anyhow!("--mu: {e}"))
    }

    /// Whether the block of slenderness `alpha` slides first (`None`
    /// without --mu); says so on stderr when it does. --mu needs α.
    pub fn sliding(&self, alpha: Option<f64>) -> anyhow::Result<Option<bool>> {
        let Some(mu) = self.mu()? else {
            return Ok(None);
        };
        let Some(alpha) = alpha else {
            anyhow::bail!(
                "--mu is compared with the block's b/h: give --b --h, --width --height or --alpha"
            );
        };
        let slides = rocking::block::slides_first(mu, alpha);
        if slides {
            eprintln!("warning: {}", rocking::block::sliding_warning(mu, alpha));
        }
        Ok(Some(slides))
    }
}

pub fn parse_overturn(text: &str) -> Result<Overturn, String> {
    text.parse::<Overturn>().map_err(|e| e.to_string())
}

pub fn parse_restitution(text: &str) -> Result<Restitution, String> {
    text.parse::<Restitution>().map_err(|e| e.to_string())
}

/// One block as asked for: its name (empty for p and ε), its run
/// specification at η = 1, and why that model.
pub struct AskedBlock {
    pub named: NamedSpec,
    pub why: String,
}

impl BlockArgs {
    /// The record at `path`, or the pulse sampled for the block's p.
    pub fn excitation(
        &self,
        path: Option<&Path>,
        p: f64,
    ) -> anyhow::Result<rocking::ops::record::LoadedRecord> {
        use rocking::ops::record;
        match (path, self.pulse.pulse(self.td)?) {
            (_, Some(_)) if !self.scene.floor.floor.is_empty() => {
                anyhow::bail!("--floor filters a ground record through a building; a pulse is given as the block's own excitation")
            }
            (_, Some(pulse)) => Ok(record::from_pulse(&pulse, p)?),
            (Some(path), None) => Ok(record::load_on(path, self.scene.building()?.as_ref())?),
            (None, None) => anyhow::bail!("give --record FILE.AT2 or --pulse rect|exp"),
        }
    }

    /// The blocks asked for, in order (p outer and ε inner; or each size,
    /// then ε), each checked, at η = 1.
    pub fn blocks(&self) -> anyhow::Result<Vec<AskedBlock>> {
        let sizes: Vec<(f64, f64)> = match (&self.b[..], &self.width[..]) {
            ([], []) => Vec::new(),
            (b, []) => pairs("--b", b, "--h", &self.h)?,
            ([], w) => pairs("--width", w, "--height", &self.height)?
                .into_iter()
                .map(|(w, h)| (w / 2.0, h / 2.0))
                .collect(),
            _ => anyhow::bail!("give the block's half sizes --b --h or its full --width --height"),
        };
        let mut out = Vec::new();
        if sizes.is_empty() {
            for &p in &self.p {
                for &eps in &self.eps {
                    let Restitution::Value(eps) = eps else {
                        anyhow::bail!(
                            "--eps housner needs the block's dimensions (--b --h or --width --height)"
                        );
                    };
                    out.push(self.asked(String::new(), p, eps, self.alpha)?);
                }
            }
        }
        for &(b_m, h_m) in &sizes {
            for &eps in &self.eps {
                let block = Block::new(b_m, h_m, eps)?;
                let name = format!("b{b_m}xh{h_m}");
                out.push(self.asked(name, block.p(), block.eps, Some(block.alpha()))?);
            }
        }
        Ok(out)
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

    fn asked(
        &self,
        name: String,
        p: f64,
        eps: f64,
        alpha: Option<f64>,
    ) -> anyhow::Result<AskedBlock> {
        let asked = rocking::ops::capacity::Asked {
            model: ModelChoice::from(self.model),
            solver: self.solver.solver()?,
            auto_tol: self.auto_tol,
            overturn: self.overturn,
        };
        let (named, why) = NamedSpec::ask(name, p, eps, alpha, &asked)?;
        Ok(AskedBlock { named, why })
    }
}

/// `a` and `b` as pairs, when they are as long as each other.
fn pairs(a_name: &str, a: &[f64], b_name: &str, b: &[f64]) -> anyhow::Result<Vec<(f64, f64)>> {
    if a.len() != b.len() {
        anyhow::bail!(
            "{a_name} has {} values and {b_name} {}: give one {b_name} for each {a_name}",
            a.len(),
            b.len()
        );
    }
    Ok(a.iter().copied().zip(b.iter().copied()).collect())
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
    #[arg(
        long,
        value_name = "m",
        required_unless_present = "inventory",
        conflicts_with = "inventory"
    )]
    pub b: Option<f64>,
    /// Half-height of the block (m).
    #[arg(
        long,
        value_name = "m",
        required_unless_present = "inventory",
        conflicts_with = "inventory"
    )]
    pub h: Option<f64>,
    /// Coefficient of restitution, or `housner` for 1 − 1.5 sin²α.
    #[arg(long, default_value = "housner", value_parser = parse_restitution, conflicts_with = "inventory")]
    pub eps: Restitution,
    /// A CSV of blocks `name,b,h[,eps][,mu]` (m; eps empty or `housner` for
    /// Housner's bound; mu the base's friction coefficient, empty if not
    /// known; in an export, a name's spaces become `_` in its taxonomy).
    #[arg(long, value_name = "BLOCKS.csv")]
    pub inventory: Option<PathBuf>,
    /// Static friction coefficient μ between the block and its base: a block
    /// with μ below b/h slides before it rocks, and is warned of (an
    /// inventory gives it in its `mu` column).
    #[arg(long, value_name = "μ", conflicts_with = "inventory")]
    pub mu: Option<f64>,
}

impl BlocksArgs {
    pub fn blocks(&self) -> anyhow::Result<rocking::ops::risk::Blocks> {
        use rocking::ops::risk::Blocks;
        let mu = self
            .mu
            .map(rocking::block::check_mu)
            .transpose()
            .map_err(|e| anyhow::anyhow!("--mu: {e}"))?;
        Ok(match (&self.inventory, self.b, self.h) {
            (Some(path), _, _) => Blocks::Inventory(path.clone()),
            (None, Some(b_m), Some(h_m)) => Blocks::One {
                b_m,
                h_m,
                eps: self.eps,
                mu,
            },
            _ => unreachable!("clap requires --b and --h without --inventory"),
        })
    }
}
