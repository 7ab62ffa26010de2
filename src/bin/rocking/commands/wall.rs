//! `rocking wall`: a pulse's safety wall by simulation, beside its closed form.

use rocking::ask::{BlockAsk, Spelling};
use rocking::block::Restitution;
use rocking::label::Label;
use rocking::physics::{ModelChoice, NonlinearIntegrator, Overturn};
use rocking::pulse::{self, WallKind, WallSearch};
use serde::Serialize;

use super::args::{label, label_among, parsed, PulseArgs};

/// Find a pulse's safety wall: the largest η at which the block overturns.
#[derive(Debug, clap::Args)]
#[command(
    allow_negative_numbers = true,
    mut_arg("pulse", |a| a.required(true).help("The pulse whose wall is found")),
    long_about = "Find a pulse's safety wall by simulation: the largest η = αg/A_p at which the \
    block overturns (η_w), and the largest at which it overturns with no impact (η_w,0, Mode 0).\n\n\
    The pulse has lobes of t_d = 1 s, so the block's p is f. The search runs a log grid of 500 \
    levels from η = 1 down to 1e-5 and bisects the first overturning to 1e-10 relative. Where a \
    closed form applies (paper Eq. 3: rect half; Eq. 5: exp half; Eq. 6: rect full, Mode 0, \
    under escape; linearised model) it is printed beside the wall. The default criterion is \
    escape: the block never comes back (MODEL.md §10)."
)]
pub struct Args {
    #[command(flatten)]
    pulse: PulseArgs,
    /// f = p·t_d, the pulse's duration against the block's frequency.
    #[arg(long, value_name = "F")]
    f: f64,
    /// Coefficient of restitution ε in (0, 1].
    #[arg(long, value_name = "ε", default_value_t = 0.7)]
    eps: f64,
    /// Overturning criterion: escape, static, cap:<c>, on-side (nonlinear).
    #[arg(long, default_value = "escape", value_parser = parsed::<Overturn>)]
    overturn: Overturn,
    /// Equation of motion (the wall is of one model: neither auto nor
    /// slide-rock, which needs a base's friction, is offered).
    #[arg(long, value_parser = label_among(&[ModelChoice::Linearized, ModelChoice::Nonlinear]), default_value = "linearized")]
    model: ModelChoice,
    /// Slenderness α = atan(b/h) (rad), for the nonlinear model.
    #[arg(long, value_name = "rad")]
    alpha: Option<f64>,
    /// The nonlinear model's integrator.
    #[arg(long, value_parser = label::<NonlinearIntegrator>(), default_value = "taylor")]
    integrator: NonlinearIntegrator,
    /// Its tolerance (the Taylor series' tail per sample interval, or DP5's
    /// relative tolerance per step; default 1e-10).
    #[arg(long)]
    rtol: Option<f64>,
    /// Intervals per lobe (even); by default enough for the shape (see rocking::pulse).
    #[arg(long, value_name = "N")]
    intervals: Option<usize>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct Report {
    f: f64,
    pulse: &'static str,
    beta: Option<f64>,
    cycle: &'static str,
    eps: f64,
    overturn: String,
    model: &'static str,
    alpha_rad: Option<f64>,
    eta_w: Option<f64>,
    eta_w_mode0: Option<f64>,
    /// Eq. 3, 5 or 6 where one applies (linearised model), else null.
    closed_form: Option<f64>,
    closed_form_equation: Option<&'static str>,
    /// Which wall the closed form gives: `eta_w` or `eta_w_mode0`.
    closed_form_of: Option<&'static str>,
    /// Impacts before overturning just below η_w (0: Mode 0, 1: Mode 1…).
    mode: Option<u64>,
    runs: u64,
    intervals_per_lobe: usize,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let Some(pl) = args.pulse.ask(1.0).resolve(Spelling::Cli)? else {
        anyhow::bail!("`rocking wall` needs --pulse rect|exp");
    };
    if let Err(e) = rocking::pulse::check_f(args.f) {
        anyhow::bail!("--f {}: {e}", args.f);
    }
    // The shared refusal names `--model auto`, which the wall does not offer.
    let solver_given = args.integrator != NonlinearIntegrator::Taylor || args.rtol.is_some();
    if args.model == ModelChoice::Linearized && (solver_given || args.alpha.is_some()) {
        anyhow::bail!(
            "--alpha, --integrator and --rtol are the nonlinear model's; the wall's linearised \
             model depends on f and ε alone and is stepped exactly (give --model nonlinear)"
        );
    }
    let block = BlockAsk {
        p: vec![args.f],
        eps: vec![Restitution::Value(args.eps)],
        alpha: args.alpha,
        model: args.model,
        integrator: args.integrator,
        rtol: args.rtol,
        overturn: args.overturn,
        ..BlockAsk::default()
    }
    .resolve_one(Spelling::Cli)?;
    let base = block.named.spec;
    let model = base.model;
    let n = args
        .intervals
        .unwrap_or_else(|| pulse::default_intervals(pl.shape, args.f));
    let exc = pl.excitation(n)?;
    let w = pulse::wall(&exc, &base, WallSearch::default())?;
    let closed = pl.closed_form_for(args.f, &base);
    let report = Report {
        f: args.f,
        pulse: pl.shape.name(),
        beta: pl.shape.beta(),
        cycle: pl.cycle.name(),
        eps: args.eps,
        overturn: args.overturn.to_string(),
        model: model.equation.kind().label(),
        alpha_rad: model.equation.alpha(),
        eta_w: w.eta_w,
        eta_w_mode0: w.eta_w_mode0,
        closed_form: closed.map(|c| c.eta),
        closed_form_equation: closed.map(|c| c.equation),
        closed_form_of: closed.map(|c| c.of.column()),
        mode: w.mode,
        runs: w.runs,
        intervals_per_lobe: n,
    };
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    let show =
        |e: Option<f64>| e.map_or("none above η = 1e-5".to_string(), |e| format!("{e:.10}"));
    println!(
        "pulse        {pl}, f = p·t_d = {} (dimensionless; {n} intervals per lobe)",
        args.f
    );
    println!(
        "block        ε = {}, {}, overturning criterion {}",
        args.eps,
        model.equation.kind().describe(),
        args.overturn
    );
    println!(
        "η_w          {}{}",
        show(w.eta_w),
        w.mode.map_or(String::new(), |m| format!(
            " (overturns just below it after {m} impact{})",
            if m == 1 { "" } else { "s" }
        ))
    );
    println!("η_w, Mode 0  {}", show(w.eta_w_mode0));
    match closed {
        Some(c) => {
            let sim = w.of(c.of);
            let name = match c.of {
                WallKind::Any => "η_w",
                WallKind::Mode0 => "η_w,0",
            };
            println!(
                "closed form  {} for {name}: {:.10}{}",
                c.equation,
                c.eta,
                sim.map_or(String::new(), |s| format!(
                    " (simulation − closed form: {:.1e})",
                    s - c.eta
                ))
            );
        }
        None => println!("closed form  none for this pulse, model and criterion"),
    }
    println!("runs         {}", w.runs);
    Ok(())
}
