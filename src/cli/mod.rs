//! Command-line interface: the only module that knows clap.
//!
//! Parses the arguments into a stage configuration, runs the stage and
//! presents its report. Errors are printed as `error: …` with their causes
//! and give exit code 1; usage errors are clap's (exit code 2).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{bail, Context};
use clap::{Parser, Subcommand, ValueEnum};
use serde::Serialize;

use crate::at2;
use crate::ida::{self, ImGrid, Spacing};
use crate::physics::{self, Excitation, Model, ModelChoice, Overturn, Recorder, RunSpec};
use crate::stages::ingest::{self, IngestConfig};
use crate::stages::sweep::{self, Shard, SweepConfig};
use crate::tables;

mod bench;

#[derive(Debug, Parser)]
#[command(
    name = "rocking",
    version,
    about = "Overturning capacity and fragility of free-standing rigid blocks under earthquake records",
    long_about = "Overturning capacity and fragility of free-standing rigid blocks under earthquake records.\n\n\
        A block (statue, cabinet, transformer, server rack) resting on a rigid base rocks about its \
        corners when the ground shakes and may overturn. rocking runs incremental dynamic analysis \
        over a suite of ground-motion records and reduces it to capacity fractiles, a regression \
        and fragility curves, as a pipeline of stages over Parquet tables.",
    after_help = "Each stage reads and writes Parquet tables documented in outputs/README.md."
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Read PEER AT2 ground-motion files into a records table (Parquet).
    #[command(
        long_about = "Read PEER AT2 ground-motion files into a records table (Parquet).\n\n\
        Each PATH is an AT2 file or a folder searched recursively for *.AT2 (any case). The table \
        has one row per record, sorted by record id (the file stem), with the samples, NPTS, DT, \
        PGA, the header lines, the file's SHA-256 and, with --manifest, the manifest's metadata. \
        Any bad file fails the command and nothing is written, unless --skip-bad is given."
    )]
    Ingest(IngestArgs),
    /// Run one record at one intensity and report the block's response.
    #[command(
        long_about = "Run one record at one intensity and report the block's response.\n\n\
        The record is normalised to unit peak and scaled to the intensity η = αg/A_g (smaller η is \
        stronger shaking). Prints θmax/α, whether and when the block overturned, the number of \
        impacts and the first uplift; --history writes the motion at every event and every \
        --history-every-th sample."
    )]
    Simulate(SimulateArgs),
    /// Find a record's overturning capacity η_c by incremental dynamic analysis.
    #[command(
        long_about = "Find a record's overturning capacity η_c by incremental dynamic analysis.\n\n\
        The record is run at --levels intensity levels of decreasing η (log-spaced from 1 down to \
        --eta-min by default) until the block first overturns; η_c is then refined by bisection \
        between the last surviving and the first overturning level to --tol. η_c is the largest \
        η known to overturn: the first overturning met as intensity rises, whatever happens at \
        stronger shaking (the resurrection rule)."
    )]
    Capacity(CapacityArgs),
    /// Measure the solvers' speed against their error; write docs/BENCHMARKS.md sections and a plot.
    #[command(long_about = "Measure the solvers' speed against their error.\n\n\
        Times the exact linearised stepper, fixed-step RK4 at several step sizes and the nonlinear \
        Dormand–Prince integrator at several tolerances on bundled records and closed-form pulses, \
        compares each with a tight reference, and measures the linearisation error against α \
        (the basis of --model auto). Rewrites the marked sections of BENCHMARKS.md in --out-dir \
        and writes the speed–error plot beside it. Takes a few minutes.")]
    Bench(bench::BenchArgs),
    /// Run a pipeline's IDA study: every record × block, written as Parquet tables.
    #[command(
        long_about = "Run a pipeline's IDA study: every record × block, written as Parquet tables.\n\n\
        Reads pipelines/<name>.toml (keys in pipelines/README.md), traces each record's IDA up to the \
        block's first overturning and refines the capacity, and writes ida_points.parquet and \
        capacities.parquet under <outputs>/<name>/. Work is saved in parts as it goes: an interrupted \
        sweep resumes where it stopped. --shard K/N runs a deterministic K-th of N parts (for batch \
        arrays); the later stages read the N shard tables as one."
    )]
    Sweep(SweepArgs),
    /// Reduce a pipeline's sweep to fractile curves, capacity fractiles and lognormal checks.
    #[command(
        long_about = "Reduce a pipeline's sweep to fractile curves, capacity fractiles and lognormal checks.\n\n\
        Reads <outputs>/<name>/ida_points and capacities (or all their shards) and writes \
        fractiles_horizontal, fractiles_vertical, capacity_fractiles, lognormal and overturn_fraction \
        (.parquet) beside them, with the pipeline's fractile definition ([reduce] fractile). Skips the \
        work when its inputs have not changed since the last run (--force to redo it)."
    )]
    Reduce(StageArgs),
    /// Fit the two-step regression η_c = a(1 − e^{−bp})^c, a, b, c polynomial in ε.
    #[command(
        long_about = "Fit the two-step regression η_c = a(1 − e^{−bp})^c of the capacity fractiles.\n\n\
        Step 1 fits a, b, c per ε and fractile by Levenberg–Marquardt; step 2 fits a(ε) linear and \
        b(ε), c(ε) quadratic. Writes fit_step1, fit_coefficients (beside the paper's published values) \
        and fit_comparison (.parquet). Needs `rocking reduce` first; skips the work when its input \
        has not changed (--force to redo it)."
    )]
    Fit(StageArgs),
    /// Probability that a real block overturns at given PGAs.
    #[command(
        long_about = "Probability that a real block overturns at given peak ground accelerations.\n\n\
        P(overturn | PGA) = Φ((ln η_c,50 − ln η)/β), η = αg/PGA, with the capacity fractiles from the \
        paper's regression (--from paper, the default) or a pipeline's own fit (--from PIPELINE.toml). \
        --direct also runs the block through a record suite (the pipeline's, or the bundled far-field \
        set) and prints the share of records whose capacity it exceeds at each PGA."
    )]
    Fragility(FragilityArgs),
    /// Run a whole pipeline: ingest → sweep → convergence → reduce → fit → report, skipping fresh stages.
    #[command(
        long_about = "Run a whole pipeline: ingest → sweep → convergence → reduce → fit → report.\n\n\
        A stage is skipped when its fingerprint (hashes of its resolved settings, of its input files' \
        contents, of the schema and tool versions; never file times) matches the one saved when it last \
        succeeded and its outputs are unchanged; otherwise the log says why it reruns. Writes every \
        table, the figures (<outputs>/<name>/figures/*.svg) and report.md. One run per output folder \
        at a time (a lock file)."
    )]
    Run(RunArgs),
    /// Show each stage of a pipeline as fresh or stale, and why.
    Status(StageArgs),
}

#[derive(Debug, clap::Args)]
struct RunArgs {
    /// The pipeline file.
    #[arg(value_name = "PIPELINE.toml")]
    pipeline: PathBuf,
    /// Root of the outputs; everything goes to <outputs>/<pipeline name>/.
    #[arg(long, default_value = "outputs")]
    outputs: PathBuf,
    /// Rerun every stage.
    #[arg(long)]
    force: bool,
    /// Rerun this stage and every later one: ingest, sweep, convergence, reduce, fit, report.
    #[arg(long, value_name = "STAGE", value_parser = parse_stage)]
    from: Option<crate::stages::run::Stage>,
}

fn parse_stage(s: &str) -> Result<crate::stages::run::Stage, String> {
    crate::stages::run::Stage::parse(s).ok_or_else(|| {
        format!("unknown stage `{s}`; valid: ingest, sweep, convergence, reduce, fit, report")
    })
}

#[derive(Debug, clap::Args)]
struct StageArgs {
    /// The pipeline file.
    #[arg(value_name = "PIPELINE.toml")]
    pipeline: PathBuf,
    /// Root of the outputs; the tables are in <outputs>/<pipeline name>/.
    #[arg(long, default_value = "outputs")]
    outputs: PathBuf,
    /// Redo the work even if the inputs have not changed.
    #[arg(long)]
    force: bool,
}

#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
struct FragilityArgs {
    /// Half-width of the block (m).
    #[arg(long, value_name = "m")]
    b: f64,
    /// Half-height of the block (m).
    #[arg(long, value_name = "m")]
    h: f64,
    /// Coefficient of restitution, or `housner` for 1 − 1.5 sin²α.
    #[arg(long, default_value = "housner")]
    eps: String,
    /// Peak ground accelerations (g), comma-separated.
    #[arg(long, value_name = "g[,g…]", value_delimiter = ',', required = true)]
    pga: Vec<f64>,
    /// `paper` (published coefficients) or a pipeline file whose fit to use.
    #[arg(long, default_value = "paper")]
    from: String,
    /// Root of the outputs (for --from PIPELINE.toml).
    #[arg(long, default_value = "outputs")]
    outputs: PathBuf,
    /// Also run the block through the record suite and report the empirical fraction.
    #[arg(long)]
    direct: bool,
    /// Records for --direct when --from paper: a folder of AT2 files.
    #[arg(long, default_value = "records/fema-p695/far-field")]
    records: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(Debug, clap::Args)]
struct SweepArgs {
    /// The pipeline file.
    #[arg(value_name = "PIPELINE.toml")]
    pipeline: PathBuf,
    /// Root of the outputs; the tables go to <outputs>/<pipeline name>/.
    #[arg(long, default_value = "outputs")]
    outputs: PathBuf,
    /// Run only the K-th of N deterministic parts (1 ≤ K ≤ N).
    #[arg(long, value_name = "K/N")]
    shard: Option<Shard>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
}

/// The model as chosen on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum ModelArg {
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

#[derive(Debug, clap::Args)]
#[command(allow_negative_numbers = true)]
struct BlockArgs {
    /// The AT2 record (acceleration in g).
    #[arg(long, value_name = "FILE.AT2")]
    record: PathBuf,
    /// Frequency parameter p = sqrt(3g/(4R)) of the block (1/s).
    #[arg(long, value_name = "1/s")]
    p: f64,
    /// Coefficient of restitution ε in (0, 1].
    #[arg(long, value_name = "ε")]
    eps: f64,
    /// Equation of motion.
    #[arg(long, value_enum, default_value = "linearized")]
    model: ModelArg,
    /// Slenderness α = atan(b/h) of the block (rad), for the nonlinear model.
    #[arg(long, value_name = "rad")]
    alpha: Option<f64>,
    /// Relative tolerance of the nonlinear integrator.
    #[arg(long, default_value_t = 1e-8)]
    rtol: f64,
    /// For --model auto: the relative error in η_c accepted from the linearisation.
    #[arg(long, default_value_t = 0.01)]
    auto_tol: f64,
    /// Overturning criterion: static (|θ| ≥ α), cap:<c> (|θ| ≥ cα), on-side (θ = π/2, nonlinear).
    #[arg(long, default_value = "static", value_parser = parse_overturn)]
    overturn: Overturn,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

fn parse_overturn(text: &str) -> Result<Overturn, String> {
    text.parse::<Overturn>().map_err(|e| e.to_string())
}

#[derive(Debug, clap::Args)]
struct SimulateArgs {
    #[command(flatten)]
    block: BlockArgs,
    /// Uplift strength η = αg/A_g (> 0).
    #[arg(long, value_name = "η")]
    eta: f64,
    /// Write the response history (t, x, ẋ, pivot, ψ̈, event) to a .parquet or .csv file.
    #[arg(long, value_name = "FILE")]
    history: Option<PathBuf>,
    /// Keep every N-th sample in the history (events are always kept).
    #[arg(long, value_name = "N", default_value_t = 1)]
    history_every: usize,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum SpacingArg {
    Log,
    Linear,
}

#[derive(Debug, clap::Args)]
struct CapacityArgs {
    #[command(flatten)]
    block: BlockArgs,
    /// Refine η_c until the bracket is at most this wide (in η).
    #[arg(long, value_name = "Δη", default_value_t = 1e-4)]
    tol: f64,
    /// Number of intensity levels below η = 1.
    #[arg(long, default_value_t = 200)]
    levels: usize,
    /// Smallest η (strongest shaking) tried.
    #[arg(long, default_value_t = 1e-3)]
    eta_min: f64,
    /// Spacing of the levels in η.
    #[arg(long, value_enum, default_value = "log")]
    spacing: SpacingArg,
}

#[derive(Debug, clap::Args)]
struct IngestArgs {
    /// AT2 files, or folders to search recursively for *.AT2.
    #[arg(required = true, value_name = "PATH")]
    paths: Vec<PathBuf>,
    /// Where to write the records table.
    #[arg(
        long,
        value_name = "FILE.parquet",
        default_value = "outputs/records.parquet"
    )]
    out: PathBuf,
    /// CSV of per-record metadata with a `file` column (path relative to the CSV),
    /// matched to the AT2 files by file stem; NPTS and DT are checked against it.
    #[arg(long, value_name = "CSV")]
    manifest: Option<PathBuf>,
    /// Ingest the good files and list the bad ones instead of failing.
    #[arg(long)]
    skip_bad: bool,
}

/// Entry point of the binary.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            for cause in e.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Ingest(args) => run_ingest(args),
        Command::Simulate(args) => run_simulate(args),
        Command::Capacity(args) => run_capacity(args),
        Command::Bench(args) => bench::run(args),
        Command::Sweep(args) => run_sweep(args),
        Command::Reduce(args) => run_reduce(args),
        Command::Fit(args) => run_fit(args),
        Command::Fragility(args) => run_fragility(args),
        Command::Run(args) => run_pipeline(args),
        Command::Status(args) => run_status(args),
    }
}

/// A record read for the solvers, with what the reports need.
struct LoadedRecord {
    record_id: String,
    npts: usize,
    pga_g: f64,
    exc: Excitation,
}

fn load_record(path: &std::path::Path) -> anyhow::Result<LoadedRecord> {
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let parsed = at2::parse(&bytes)
        .map_err(|e| anyhow::anyhow!("{}:{}: {}", path.display(), e.line, e.kind))?;
    let pga_g = crate::motion::peak(&parsed.accel_g, parsed.dt_s).map_or(0.0, |p| p.pga_g);
    let exc = Excitation::new(&parsed.accel_g, parsed.dt_s)
        .with_context(|| path.display().to_string())?;
    Ok(LoadedRecord {
        record_id: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        npts: parsed.accel_g.len(),
        pga_g,
        exc,
    })
}

/// The run specification from the block arguments, and why that model.
fn block_spec(b: &BlockArgs, eta: f64) -> anyhow::Result<(RunSpec, String)> {
    let (model, why) = ModelChoice::from(b.model).resolve(b.alpha, b.rtol, b.auto_tol)?;
    let spec = RunSpec {
        overturn: b.overturn,
        ..RunSpec::new(b.p, b.eps, eta, model)
    };
    spec.validate()?;
    Ok((spec, why))
}

fn alpha_of(model: Model) -> Option<f64> {
    match model {
        Model::Nonlinear { alpha_rad, .. } => Some(alpha_rad),
        Model::Rk4 { alpha_rad, .. } => alpha_rad,
        Model::Linearized => None,
    }
}

#[derive(Serialize)]
struct SimulateReport<'a> {
    record_id: &'a str,
    p: f64,
    eps: f64,
    eta: f64,
    model: &'static str,
    alpha_rad: Option<f64>,
    overturn: String,
    theta_max_over_alpha: f64,
    overturned: bool,
    overturn_time_s: Option<f64>,
    overturn_after_record: bool,
    impacts: u64,
    first_uplift_s: Option<f64>,
    stop: &'static str,
}

fn run_simulate(args: SimulateArgs) -> anyhow::Result<()> {
    let rec = load_record(&args.block.record)?;
    let (spec, why) = block_spec(&args.block, args.eta)?;
    let mut recorder = Recorder::new(args.history_every);
    let out = if args.history.is_some() {
        physics::simulate_observed(&rec.exc, &spec, &mut recorder)?
    } else {
        physics::simulate(&rec.exc, &spec)?
    };
    if let Some(path) = &args.history {
        let settings = vec![
            (
                "rocking.simulate.record".to_string(),
                args.block.record.display().to_string(),
            ),
            ("rocking.simulate.spec".to_string(), format!("{spec:?}")),
        ];
        tables::history::write(path, &recorder.points, &settings)?;
    }
    let report = SimulateReport {
        record_id: &rec.record_id,
        p: spec.p,
        eps: spec.eps,
        eta: spec.eta,
        model: spec.model.name(),
        alpha_rad: alpha_of(spec.model),
        overturn: spec.overturn.to_string(),
        theta_max_over_alpha: out.max_abs_x,
        overturned: out.overturned(),
        overturn_time_s: out.overturn_time_s,
        overturn_after_record: out.overturn_after_record,
        impacts: out.impacts,
        first_uplift_s: out.first_uplift_s,
        stop: out.stop.as_str(),
    };
    if args.block.json {
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    println!(
        "record      {} ({} samples, dt {} s, PGA {:.4} g)",
        rec.record_id, rec.npts, rec.exc.dt_s, rec.pga_g
    );
    println!(
        "block       p = {} 1/s, ε = {}, η = {} ({why})",
        spec.p, spec.eps, spec.eta
    );
    println!("overturning {}", spec.overturn);
    println!("θmax/α      {:.12}", out.max_abs_x);
    match out.overturn_time_s {
        Some(t) if out.overturn_after_record => {
            println!("overturned  yes, at {t:.6} s, after the record ended")
        }
        Some(t) => println!("overturned  yes, at {t:.6} s"),
        None => println!("overturned  no ({})", out.stop.as_str().replace('_', " ")),
    }
    println!("impacts     {}", out.impacts);
    match out.first_uplift_s {
        Some(t) => println!("uplift      first at {t:.6} s"),
        None => println!("uplift      never (the record stays below the uplift threshold)"),
    }
    if let Some(path) = &args.history {
        println!(
            "history     {} points in {}",
            recorder.points.len(),
            path.display()
        );
    }
    Ok(())
}

#[derive(Serialize)]
struct CapacityReport<'a> {
    record_id: &'a str,
    p: f64,
    eps: f64,
    model: &'static str,
    alpha_rad: Option<f64>,
    overturn: String,
    eta_c: Option<f64>,
    /// A_g at the capacity in units of αg (= 1/η_c).
    pga_scale_c: Option<f64>,
    eta_survived: f64,
    level_survived: f64,
    level_overturned: Option<f64>,
    runs: usize,
    refinement_runs: usize,
    tol: f64,
    levels: usize,
    eta_min: f64,
    spacing: &'static str,
}

fn run_capacity(args: CapacityArgs) -> anyhow::Result<()> {
    let rec = load_record(&args.block.record)?;
    let (spec, why) = block_spec(&args.block, 1.0)?;
    let spacing = match args.spacing {
        SpacingArg::Log => Spacing::Log,
        SpacingArg::Linear => Spacing::Linear,
    };
    let grid = ImGrid {
        eta_max: 1.0,
        eta_min: args.eta_min,
        count: args.levels,
        spacing,
    };
    if !(args.eta_min > 0.0 && args.eta_min < 1.0) {
        bail!("--eta-min {} must be in (0, 1)", args.eta_min);
    }
    let cap = ida::capacity(&rec.exc, &spec, &grid, args.tol)?;
    let refinement_runs = cap
        .points
        .iter()
        .filter(|q| q.kind == ida::RunKind::Refinement)
        .count();
    let report = CapacityReport {
        record_id: &rec.record_id,
        p: spec.p,
        eps: spec.eps,
        model: spec.model.name(),
        alpha_rad: alpha_of(spec.model),
        overturn: spec.overturn.to_string(),
        eta_c: cap.eta_c,
        pga_scale_c: cap.eta_c.map(|e| 1.0 / e),
        eta_survived: cap.eta_survived,
        level_survived: cap.level_survived,
        level_overturned: cap.level_overturned,
        runs: cap.runs(),
        refinement_runs,
        tol: args.tol,
        levels: args.levels,
        eta_min: args.eta_min,
        spacing: match spacing {
            Spacing::Log => "log",
            Spacing::Linear => "linear",
        },
    };
    if args.block.json {
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    println!(
        "record      {} ({} samples, dt {} s)",
        rec.record_id, rec.npts, rec.exc.dt_s
    );
    println!("block       p = {} 1/s, ε = {} ({why})", spec.p, spec.eps);
    match cap.eta_c {
        Some(c) => {
            println!(
                "η_c         {c:.6} (A_g = {:.4} αg), survives at η = {:.6}",
                1.0 / c,
                cap.eta_survived
            );
            println!(
                "bracket     grid levels {:.6} (survived) → {:.6} (overturned), refined to {:e}",
                cap.level_survived,
                cap.level_overturned.unwrap_or(f64::NAN),
                args.tol
            );
        }
        None => println!(
            "η_c         none: the block survives every level down to η = {}",
            args.eta_min
        ),
    }
    println!(
        "runs        {} ({} levels, {} refinements)",
        cap.runs(),
        cap.runs() - refinement_runs,
        refinement_runs
    );
    Ok(())
}

fn run_ingest(args: IngestArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let config = IngestConfig {
        paths: args.paths,
        manifest: args.manifest,
        out: args.out,
        skip_bad: args.skip_bad,
    };
    let report = ingest::run(&config)?;
    for b in &report.skipped {
        eprintln!("skipped: {b}");
    }
    if !report.ignored_manifest_columns.is_empty() {
        eprintln!(
            "warning: manifest columns not stored: {}",
            report.ignored_manifest_columns.join(", ")
        );
    }
    if !report.not_in_manifest.is_empty() {
        eprintln!(
            "warning: {} record(s) not in the manifest (their metadata columns are empty): {}",
            report.not_in_manifest.len(),
            report.not_in_manifest.join(", ")
        );
    }
    let sets: Vec<String> = report
        .per_set
        .iter()
        .map(|(s, n)| format!("{s} {n}"))
        .collect();
    println!(
        "ingested {} records ({} samples; {}) into {} in {:.2} s{}",
        report.records,
        report.samples,
        sets.join(", "),
        report.out.display(),
        started.elapsed().as_secs_f64(),
        if report.skipped.is_empty() {
            String::new()
        } else {
            format!("; skipped {} bad file(s)", report.skipped.len())
        }
    );
    Ok(())
}

/// Reads and resolves a pipeline file.
pub fn load_pipeline(path: &std::path::Path) -> anyhow::Result<crate::pipeline::Plan> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read the pipeline", path.display()))?;
    Ok(crate::pipeline::load_str(&text, path)?)
}

fn run_sweep(args: SweepArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let plan = load_pipeline(&args.pipeline)?;
    if args.threads == Some(0) {
        bail!("--threads must be at least 1");
    }
    let config = SweepConfig {
        plan,
        outputs: args.outputs,
        shard: args.shard,
        threads: args.threads,
    };
    let mut show = ProgressLine::new("sweep");
    let report = sweep::run(&config, |p| {
        show.update(p.cases_done, p.cases_total, p.cases_resumed, p.runs)
    })?;
    show.finish();
    for m in &report.models {
        eprintln!("model: {m}");
    }
    let secs = started.elapsed().as_secs_f64();
    let threads = config.threads.unwrap_or_else(rayon::current_num_threads);
    println!(
        "swept {} records × {} blocks = {} cases{} ({} resumed from an earlier run): {} runs in {:.1} s \
         ({:.0} runs/s; {} sample intervals, {:.0} ns each per thread)",
        report.records,
        report.blocks,
        report.cases,
        config.shard.map_or(String::new(), |s| format!(" in shard {s}")),
        report.cases_resumed,
        report.runs,
        secs,
        report.runs as f64 / secs.max(1e-9),
        report.intervals,
        secs * threads as f64 * 1e9 / (report.intervals.max(1) as f64)
    );
    println!(
        "wrote {} and {}",
        report.ida_path.display(),
        report.capacities_path.display()
    );
    Ok(())
}

/// A progress bar with rate and ETA on a terminal, plain log lines otherwise.
struct ProgressLine {
    what: &'static str,
    tty: bool,
    started: Instant,
    last_log: Option<Instant>,
    drawn: bool,
}

impl ProgressLine {
    fn new(what: &'static str) -> Self {
        use std::io::IsTerminal;
        ProgressLine {
            what,
            tty: std::io::stderr().is_terminal(),
            started: Instant::now(),
            last_log: None,
            drawn: false,
        }
    }

    fn update(&mut self, done: usize, total: usize, resumed: usize, runs: u64) {
        let elapsed = self.started.elapsed().as_secs_f64();
        let computed = done.saturating_sub(resumed);
        let rate = computed as f64 / elapsed.max(1e-9);
        let eta = if computed > 0 {
            (total - done) as f64 / rate
        } else {
            f64::NAN
        };
        let eta_text = if eta.is_finite() {
            format!("{eta:.0} s")
        } else {
            "?".into()
        };
        let runs_rate = runs as f64 / elapsed.max(1e-9);
        if self.tty {
            let width = 30;
            let filled = (done * width).checked_div(total).unwrap_or(width);
            eprint!(
                "\r{} [{}{}] {done}/{total} cases, {runs_rate:.0} runs/s, ETA {eta_text}   ",
                self.what,
                "#".repeat(filled),
                " ".repeat(width - filled)
            );
            self.drawn = true;
        } else if self
            .last_log
            .is_none_or(|t| t.elapsed().as_secs_f64() >= 10.0)
            || done == total
        {
            eprintln!(
                "{}: {done}/{total} cases, {runs} runs, {runs_rate:.0} runs/s, ETA {eta_text}",
                self.what
            );
            self.last_log = Some(Instant::now());
        }
    }

    fn finish(&mut self) {
        if self.drawn {
            eprintln!();
        }
    }
}

fn run_reduce(args: StageArgs) -> anyhow::Result<()> {
    let plan = load_pipeline(&args.pipeline)?;
    let started = Instant::now();
    let r = crate::stages::reduce::run(&plan, &args.outputs, args.force)?;
    if r.up_to_date {
        println!(
            "reduce: up to date (the sweep tables have not changed) in {}",
            r.dir.display()
        );
        return Ok(());
    }
    println!(
        "reduced {} records × {} blocks in {:.2} s ({:?} fractiles): lognormality of η_c not rejected at 5 % in {} of {} blocks ({:.0} %)",
        r.records,
        r.blocks,
        started.elapsed().as_secs_f64(),
        r.fractile,
        r.lognormal_pass.0,
        r.lognormal_pass.1,
        100.0 * r.lognormal_pass.0 as f64 / r.lognormal_pass.1.max(1) as f64
    );
    println!("wrote fractiles_horizontal, fractiles_vertical, capacity_fractiles, lognormal, overturn_fraction in {}", r.dir.display());
    Ok(())
}

fn run_fit(args: StageArgs) -> anyhow::Result<()> {
    let plan = load_pipeline(&args.pipeline)?;
    let r = crate::stages::fit::run(&plan, &args.outputs, args.force)?;
    if r.up_to_date {
        println!(
            "fit: up to date (capacity_fractiles has not changed) in {}",
            r.dir.display()
        );
        return Ok(());
    }
    println!(
        "step 1: {} of {} fits converged",
        r.converged.0, r.converged.1
    );
    let paper = crate::fragility::paper();
    for law in &r.laws {
        let pl = paper
            .iter()
            .find(|l| (l.quantile - law.quantile).abs() < 1e-9);
        let fmt = |c: &[f64]| {
            c.iter()
                .map(|v| format!("{v:+.3}"))
                .collect::<Vec<_>>()
                .join(" ")
        };
        println!(
            "q = {:.2}: a {} | b {} | c {}",
            law.quantile,
            fmt(&law.a),
            fmt(&law.b),
            fmt(&law.c)
        );
        if let Some(pl) = pl {
            println!(
                "  paper:  a {} | b {} | c {}",
                fmt(&pl.a),
                fmt(&pl.b),
                fmt(&pl.c)
            );
        }
    }
    println!(
        "wrote fit_step1, fit_coefficients, fit_comparison in {}",
        r.dir.display()
    );
    Ok(())
}

#[derive(Serialize)]
struct FragilityPoint {
    pga_g: f64,
    eta: f64,
    probability: f64,
    empirical: Option<f64>,
}

#[derive(Serialize)]
struct FragilityReport {
    b_m: f64,
    h_m: f64,
    alpha_rad: f64,
    p: f64,
    eps: f64,
    source: String,
    eta_c_median: f64,
    beta: f64,
    records: Option<usize>,
    points: Vec<FragilityPoint>,
}

fn run_fragility(args: FragilityArgs) -> anyhow::Result<()> {
    use crate::fragility::{self, Block};
    if !(args.b > 0.0 && args.h > 0.0) {
        bail!("--b and --h must be positive (m)");
    }
    let eps = if args.eps == "housner" {
        Block::housner_eps(args.b, args.h)
    } else {
        args.eps
            .parse::<f64>()
            .map_err(|_| anyhow::anyhow!("--eps `{}`: a number in (0, 1] or `housner`", args.eps))?
    };
    if !(eps > 0.0 && eps <= 1.0) {
        bail!("--eps = {eps}: ε must be in (0, 1]");
    }
    if let Some(bad) = args.pga.iter().find(|g| !(**g > 0.0 && g.is_finite())) {
        bail!("--pga {bad}: accelerations must be positive (g)");
    }
    let block = Block {
        b_m: args.b,
        h_m: args.h,
        eps,
    };
    let (alpha, p) = (block.alpha(), block.p());
    let (laws, plan) = if args.from == "paper" {
        (fragility::paper().to_vec(), None)
    } else {
        let plan = load_pipeline(std::path::Path::new(&args.from))?;
        let laws = crate::stages::fit::read_laws(&args.outputs.join(&plan.name))?;
        (laws, Some(plan))
    };
    let (median, beta) = fragility::median_beta(&laws, p, eps).ok_or_else(|| {
        anyhow::anyhow!(
            "the regression gives no valid capacity fractiles at p = {p:.3}, ε = {eps:.3}"
        )
    })?;

    // --direct: the block's capacity under every record (auto model for its α).
    let capacities: Option<Vec<f64>> = if args.direct {
        let records = match &plan {
            Some(plan) => sweep::load_records(plan)?,
            None => ingest::collect(std::slice::from_ref(&args.records), None, false)?.rows,
        };
        let (model, _) = ModelChoice::Auto.resolve(Some(alpha), 1e-8, 0.01)?;
        let spec = RunSpec::new(p, eps, 1.0, model);
        use rayon::prelude::*;
        let caps = records
            .par_iter()
            .map(|r| {
                let exc = Excitation::new(&r.accel_g, r.dt_s)?;
                Ok(ida::capacity(&exc, &spec, &ImGrid::default(), 1e-4)?
                    .eta_c
                    .unwrap_or(0.0))
            })
            .collect::<Result<Vec<f64>, physics::PhysicsError>>()?;
        Some(caps)
    } else {
        None
    };
    let points: Vec<FragilityPoint> = args
        .pga
        .iter()
        .map(|&pga| {
            let eta = alpha / pga;
            FragilityPoint {
                pga_g: pga,
                eta,
                probability: fragility::probability(median, beta, alpha, pga),
                empirical: capacities
                    .as_ref()
                    .map(|c| c.iter().filter(|&&ec| eta < ec).count() as f64 / c.len() as f64),
            }
        })
        .collect();
    let report = FragilityReport {
        b_m: args.b,
        h_m: args.h,
        alpha_rad: alpha,
        p,
        eps,
        source: args.from.clone(),
        eta_c_median: median,
        beta,
        records: capacities.as_ref().map(Vec::len),
        points,
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    println!(
        "block b = {} m, h = {} m: α = {:.4} rad, p = {:.4} 1/s, ε = {:.4}; capacity from {}: median η_c = {:.4} (PGA {:.3} g), β = {:.3}",
        args.b, args.h, alpha, p, eps, args.from, median, alpha / median, beta
    );
    println!(
        "{:>10} {:>10} {:>14}{}",
        "PGA (g)",
        "η",
        "P(overturn)",
        if capacities.is_some() {
            "  records overturned"
        } else {
            ""
        }
    );
    for pt in &report.points {
        match pt.empirical {
            Some(e) => println!(
                "{:>10.4} {:>10.4} {:>14.4}  {:>18.4}",
                pt.pga_g, pt.eta, pt.probability, e
            ),
            None => println!(
                "{:>10.4} {:>10.4} {:>14.4}",
                pt.pga_g, pt.eta, pt.probability
            ),
        }
    }
    Ok(())
}

fn run_pipeline(args: RunArgs) -> anyhow::Result<()> {
    use crate::stages::run::{self, RunConfig};
    let started = Instant::now();
    let plan = load_pipeline(&args.pipeline)?;
    let cfg = RunConfig {
        plan,
        pipeline_path: args.pipeline.clone(),
        outputs: args.outputs,
        force: args.force,
        from: args.from,
    };
    let results = run::run(&cfg, |r| {
        if r.ran && r.seconds == 0.0 {
            eprintln!("{:<12} running: {}", r.stage.name(), r.reason);
        } else if !r.ran {
            eprintln!("{:<12} skipped: {}", r.stage.name(), r.reason);
        }
    })?;
    let ran: Vec<&str> = results
        .iter()
        .filter(|r| r.ran)
        .map(|r| r.stage.name())
        .collect();
    let dir = cfg.outputs.join(&cfg.plan.name);
    if ran.is_empty() {
        println!(
            "nothing to do: every stage of `{}` is up to date ({})",
            cfg.plan.name,
            dir.display()
        );
    } else {
        for r in results.iter().filter(|r| r.ran) {
            println!("{:<12} {:.2} s", r.stage.name(), r.seconds);
        }
        println!(
            "ran {} in {:.1} s; report: {}",
            ran.join(", "),
            started.elapsed().as_secs_f64(),
            dir.join("report.md").display()
        );
    }
    Ok(())
}

fn run_status(args: StageArgs) -> anyhow::Result<()> {
    use crate::stages::run::{freshness, Freshness, Layout, Stage};
    let plan = load_pipeline(&args.pipeline)?;
    let layout = Layout::new(&plan, &args.outputs);
    for stage in Stage::ALL {
        match freshness(stage, &plan, &layout) {
            Freshness::Fresh => println!("{:<12} fresh", stage.name()),
            Freshness::Stale(why) => println!("{:<12} stale: {why}", stage.name()),
            Freshness::NotNeeded(why) => println!("{:<12} not needed: {why}", stage.name()),
        }
    }
    Ok(())
}
