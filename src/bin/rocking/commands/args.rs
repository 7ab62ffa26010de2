//! Arguments shared by several commands.

use std::path::PathBuf;

use clap::ValueEnum;
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
    /// Records for --direct when --from paper: a folder of AT2 files.
    #[arg(long, default_value = "records/fema-p695/far-field")]
    pub records: PathBuf,
}

impl LawArgs {
    pub fn source(&self) -> rocking::ops::fragility::Source {
        use rocking::ops::fragility::Source;
        if self.from == "paper" {
            Source::Paper {
                records: self.records.clone(),
            }
        } else {
            Source::Pipeline {
                file: PathBuf::from(&self.from),
                outputs: self.outputs.clone(),
            }
        }
    }
}

/// `--eps`: a coefficient of restitution, or `housner` (`None`) for
/// Housner's bound 1 − 1.5 sin²α.
#[derive(Debug, Clone, Copy)]
pub struct EpsArg(pub Option<f64>);

pub fn parse_eps(text: &str) -> Result<EpsArg, String> {
    if text == "housner" {
        return Ok(EpsArg(None));
    }
    text.parse::<f64>()
        .map(|e| EpsArg(Some(e)))
        .map_err(|_| format!("`{text}`: a number in (0, 1] or `housner`"))
}

/// The model as chosen on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ModelArg {
    /// Paper Eq. 8, exact stepping (depends on p, η, ε only).
    Linearized,
    /// Paper Eq. 7 by Dormand–Prince 5(4); needs --alpha.
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
    /// A pulse instead of a record: rect or exp (paper Eq. 4).
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

/// One record (or pulse) and one block, for `simulate` and `capacity`.
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct BlockArgs {
    /// The AT2 record (acceleration in g).
    #[arg(
        long,
        value_name = "FILE.AT2",
        required_unless_present = "pulse",
        conflicts_with = "pulse"
    )]
    pub record: Option<PathBuf>,
    #[command(flatten)]
    pub pulse: PulseArgs,
    /// The pulse's lobe duration t_d (s); f = p·t_d.
    #[arg(long, value_name = "s", default_value_t = TD_S, requires = "pulse")]
    pub td: f64,
    /// Frequency parameter p = sqrt(3g/(4R)) of the block (1/s).
    #[arg(long, value_name = "1/s")]
    pub p: f64,
    /// Coefficient of restitution ε in (0, 1].
    #[arg(long, value_name = "ε")]
    pub eps: f64,
    /// Equation of motion.
    #[arg(long, value_enum, default_value_t = ModelArg::Linearized)]
    pub model: ModelArg,
    /// Slenderness α = atan(b/h) of the block (rad), for the nonlinear model.
    #[arg(long, value_name = "rad")]
    pub alpha: Option<f64>,
    /// Relative tolerance of the nonlinear integrator (capacities are then
    /// certified at a 100× tighter one).
    #[arg(long, default_value_t = rocking::physics::DEFAULT_RTOL)]
    pub rtol: f64,
    /// For --model auto: the relative error in η_c accepted from the linearisation.
    #[arg(long, default_value_t = AUTO_TOL)]
    pub auto_tol: f64,
    /// Overturning criterion: static (|θ| ≥ α), cap:<c> (|θ| ≥ cα), on-side (θ = π/2,
    /// nonlinear), escape (never comes back: θ = π/2 nonlinear; linearised, proven unbounded).
    #[arg(long, default_value_t = Overturn::Static, value_parser = parse_overturn)]
    pub overturn: Overturn,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn parse_overturn(text: &str) -> Result<Overturn, String> {
    text.parse::<Overturn>().map_err(|e| e.to_string())
}

impl BlockArgs {
    /// The record, or the pulse sampled for this block's p.
    pub fn excitation(&self) -> anyhow::Result<rocking::ops::record::LoadedRecord> {
        use rocking::ops::record;
        match (&self.record, self.pulse.pulse(self.td)?) {
            (_, Some(pulse)) => Ok(record::from_pulse(&pulse, self.p)?),
            (Some(path), None) => Ok(record::load(path)?),
            (None, None) => anyhow::bail!("give --record FILE.AT2 or --pulse rect|exp"),
        }
    }

    /// The arguments of a record's block from `flags` without clap
    /// ([`Flags`]): `None` for a pulse (left to clap), or where a value does
    /// not parse or a required one is missing (clap then says which).
    pub fn quick(flags: &mut Flags) -> Option<BlockArgs> {
        Some(BlockArgs {
            record: Some(flags.value("record", |v| Some(PathBuf::from(v)))??),
            pulse: PulseArgs {
                pulse: None,
                beta: None,
                cycle: CycleArg::Half,
            },
            td: TD_S,
            p: flags.value("p", number)??,
            eps: flags.value("eps", number)??,
            model: flags.value("model", named)?.unwrap_or(ModelArg::Linearized),
            alpha: flags.value("alpha", number)?,
            rtol: flags
                .value("rtol", number)?
                .unwrap_or(rocking::physics::DEFAULT_RTOL),
            auto_tol: flags.value("auto-tol", number)?.unwrap_or(AUTO_TOL),
            overturn: flags
                .value("overturn", |v| parse_overturn(v).ok())?
                .unwrap_or(Overturn::Static),
            json: flags.switch("json"),
        })
    }

    /// The run specification at intensity `eta`, and why that model.
    pub fn spec(&self, eta: f64) -> anyhow::Result<(rocking::physics::RunSpec, String)> {
        let (model, why) =
            ModelChoice::from(self.model).resolve(self.alpha, self.rtol, self.auto_tol)?;
        let spec = rocking::physics::RunSpec {
            overturn: self.overturn,
            ..rocking::physics::RunSpec::new(self.p, self.eps, eta, model)
        };
        spec.validate()?;
        Ok((spec, why))
    }
}

/// A command line of `--name value`, `--name=value` and bare `--switch`
/// arguments, read without clap: for a command scripts call in loops, where
/// clap's first parse costs about 0.2 ms of cold code. Wherever clap's
/// reading could differ, the line is left to clap (which gives its help or
/// its error): [`Flags::scan`] declines an argument that is not a long
/// option, a value that is empty or starts with `-`, a switch given a value
/// and text that is not UTF-8; [`Flags::all_taken`] is false for a name the
/// command does not know or one given twice.
pub struct Flags {
    /// Each name, its value (`None` for a switch), and whether it was taken.
    given: Vec<(String, Option<String>, bool)>,
}

impl Flags {
    /// Reads `args` (those after the command's name); `switches` are the
    /// names that take no value.
    pub fn scan(
        args: impl IntoIterator<Item = std::ffi::OsString>,
        switches: &[&str],
    ) -> Option<Flags> {
        let mut args = args.into_iter();
        let mut given: Vec<(String, Option<String>, bool)> = Vec::new();
        while let Some(arg) = args.next() {
            let arg = arg.into_string().ok()?;
            let long = arg.strip_prefix("--").filter(|n| !n.is_empty())?;
            let (name, value) = match long.split_once('=') {
                Some((name, value)) => (name, Some(value.to_string())),
                None => (long, None),
            };
            let value = match (switches.contains(&name), value) {
                (true, None) => None,
                (true, Some(_)) => return None,
                (false, Some(v)) => Some(v),
                (false, None) => Some(args.next()?.into_string().ok()?),
            };
            if value
                .as_deref()
                .is_some_and(|v| v.is_empty() || v.starts_with('-'))
            {
                return None;
            }
            given.push((name.to_string(), value, false));
        }
        Some(Flags { given })
    }

    /// The value of `--name` read by `parse`: `Some(None)` when absent,
    /// `None` when it does not parse.
    pub fn value<T>(&mut self, name: &str, parse: impl Fn(&str) -> Option<T>) -> Option<Option<T>> {
        let Some((_, value, taken)) = self.given.iter_mut().find(|(n, ..)| n == name) else {
            return Some(None);
        };
        *taken = true;
        parse(value.as_deref()?).map(Some)
    }

    /// Whether the switch `--name` was given.
    pub fn switch(&mut self, name: &str) -> bool {
        match self.given.iter_mut().find(|(n, ..)| n == name) {
            Some((_, None, taken)) => {
                *taken = true;
                true
            }
            _ => false,
        }
    }

    /// Whether every name given was taken: an unknown one, or one given
    /// twice (only its first is taken), leaves the line to clap.
    pub fn all_taken(&self) -> bool {
        self.given.iter().all(|(.., taken)| *taken)
    }
}

/// `text` as a number, as clap's parser of `f64` and `usize` reads it.
pub fn number<T: std::str::FromStr>(text: &str) -> Option<T> {
    text.parse().ok()
}

/// `text` as one of `E`'s names, as clap's `ValueEnum` parser reads it
/// (exact, case-sensitive).
pub fn named<E: ValueEnum>(text: &str) -> Option<E> {
    E::from_str(text, false).ok()
}
