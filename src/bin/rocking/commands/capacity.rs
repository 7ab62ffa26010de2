//! `rocking capacity`: one record's overturning capacity.

use clap::ValueEnum;
use rocking::ida::{ImGrid, RunKind, Spacing, Trace};
use rocking::label::Label;
use serde::Serialize;

use super::args::BlockArgs;

/// Find a record's overturning capacity η_c by incremental dynamic analysis.
#[derive(Debug, clap::Args)]
#[command(
    long_about = "Find a record's overturning capacity η_c by incremental dynamic analysis.\n\n\
    The record is run at --levels intensity levels of decreasing η (log-spaced from 1 down to \
    --eta-min by default) until the block first overturns; η_c is then refined by bisection \
    between the last surviving and the first overturning level to --tol. η_c is the largest \
    η known to overturn: the first overturning met as intensity rises, whatever happens at \
    stronger shaking (the resurrection rule). The capacity is then certified: with the nonlinear \
    model its decisive runs are rerun at a 100× tighter tolerance, and the search is redone there \
    if a verdict flips; with either model each decisive run is rerun with η moved by ±1e-9, and a \
    verdict that changes marks the capacity chaotic (not certified)."
)]
pub struct Args {
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

#[derive(Debug, Clone, Copy, ValueEnum)]
enum SpacingArg {
    Log,
    Linear,
}

#[derive(Serialize)]
struct Report<'a> {
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
    /// Whether the decisive verdicts were confirmed, and how.
    certified: bool,
    certification: String,
    /// DP5's tolerance of the search reported (nonlinear model).
    rtol: Option<f64>,
    /// Runs spent on the certification (checks and searches redone).
    certification_runs: usize,
    tol: f64,
    levels: usize,
    eta_min: f64,
    spacing: &'static str,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let (spec, why) = args.block.spec(1.0)?;
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
    // Checked before the record is read: an absurd --levels is refused at once.
    grid.levels()?;
    let rec = args.block.excitation()?;
    // The main thread is one of the pool's workers: one thread fewer to start
    // (a pool already built is used as it is).
    let _ = rayon::ThreadPoolBuilder::new()
        .use_current_thread()
        .build_global();
    let certified = rocking::ops::record::capacity_certified_parallel(
        &rec.exc,
        &spec,
        &grid,
        args.tol,
        Trace::StopAtFirst,
    )?;
    let cap = &certified.capacity;
    let refinement_runs = cap
        .points
        .iter()
        .filter(|q| q.kind == RunKind::Refinement)
        .count();
    let report = Report {
        record_id: &rec.record_id,
        p: spec.p,
        eps: spec.eps,
        model: spec.model.equation.kind().label(),
        alpha_rad: spec.alpha(),
        overturn: spec.overturn.to_string(),
        eta_c: cap.eta_c,
        pga_scale_c: cap.eta_c.map(|e| 1.0 / e),
        eta_survived: cap.eta_survived,
        level_survived: cap.level_survived,
        level_overturned: cap.level_overturned,
        runs: cap.runs(),
        refinement_runs,
        certified: certified.certification.certified(),
        certification: certified.certification.to_string(),
        rtol: certified.model.integrator.rtol(),
        certification_runs: certified.extra.runs,
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
        "runs        {} ({} levels, {} refinements){}",
        cap.runs(),
        cap.runs() - refinement_runs,
        refinement_runs,
        if certified.extra.runs > 0 {
            format!(", and {} to certify it", certified.extra.runs)
        } else {
            String::new()
        }
    );
    println!("certified   {}", certified.certification);
    Ok(())
}
