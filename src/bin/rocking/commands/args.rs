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

/// One record and one block, for `simulate` and `capacity`.
#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct BlockArgs {
    /// The AT2 record (acceleration in g).
    #[arg(long, value_name = "FILE.AT2")]
    pub record: PathBuf,
    /// Frequency parameter p = sqrt(3g/(4R)) of the block (1/s).
    #[arg(long, value_name = "1/s")]
    pub p: f64,
    /// Coefficient of restitution ε in (0, 1].
    #[arg(long, value_name = "ε")]
    pub eps: f64,
    /// Equation of motion.
    #[arg(long, value_enum, default_value = "linearized")]
    pub model: ModelArg,
    /// Slenderness α = atan(b/h) of the block (rad), for the nonlinear model.
    #[arg(long, value_name = "rad")]
    pub alpha: Option<f64>,
    /// Relative tolerance of the nonlinear integrator (capacities are then
    /// certified at a 100× tighter one).
    #[arg(long, default_value_t = rocking::physics::DEFAULT_RTOL)]
    pub rtol: f64,
    /// For --model auto: the relative error in η_c accepted from the linearisation.
    #[arg(long, default_value_t = 0.01)]
    pub auto_tol: f64,
    /// Overturning criterion: static (|θ| ≥ α), cap:<c> (|θ| ≥ cα), on-side (θ = π/2, nonlinear).
    #[arg(long, default_value = "static", value_parser = parse_overturn)]
    pub overturn: Overturn,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

fn parse_overturn(text: &str) -> Result<Overturn, String> {
    text.parse::<Overturn>().map_err(|e| e.to_string())
}

impl BlockArgs {
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
