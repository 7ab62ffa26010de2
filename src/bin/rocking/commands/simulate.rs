//! `rocking simulate`: one record at one intensity.

use std::path::PathBuf;

use rocking::ask::Spelling;
use rocking::decimal::shortest;
use rocking::label::Label;
use rocking::ops::reports::{Scene, SimulateReport};
use rocking::physics::{self, Recorder};
use rocking::tables;

use super::args::BlockArgs;

/// Run one record at one intensity and report the block's response.
#[derive(Debug, clap::Args)]
#[command(
    long_about = "Run one record at one intensity and report the block's response.\n\n\
    The record is normalised to unit peak and scaled to the intensity η = αg/PGA (smaller η is \
    stronger shaking). Prints θmax/α, whether and when the block overturned, the number of \
    impacts and the first uplift; --history writes the motion at every event and every \
    --history-every-th sample."
)]
pub struct Args {
    /// The AT2 record (acceleration in g).
    #[arg(long, value_name = "FILE.AT2")]
    record: Option<PathBuf>,
    #[command(flatten)]
    block: BlockArgs,
    /// Uplift strength η = αg/PGA (> 0).
    #[arg(long, value_name = "η")]
    eta: Option<f64>,
    /// The record's PGA after scaling (g), instead of η: η = α/PGA (needs α:
    /// the block's dimensions or --alpha). With --floor, the ground's PGA:
    /// η = α/(PGA · PFA/PGA).
    #[arg(long, value_name = "g")]
    pga: Option<f64>,
    /// Write the response history (t, x, ẋ, pivot, ψ̈, event, and the slide and its velocity) to a
    /// .parquet or .csv file (columns: docs/tables.md, `history`).
    #[arg(long, value_name = "FILE")]
    history: Option<PathBuf>,
    /// With --history: keep every N-th sample (events are always kept).
    #[arg(long, value_name = "N", default_value_t = 1, requires = "history",
          value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    history_every: usize,
}

/// `--history` is a .csv or .parquet file that is not the record read.
fn check_history(args: &Args) -> anyhow::Result<()> {
    let Some(path) = &args.history else {
        return Ok(());
    };
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let csv = ext.eq_ignore_ascii_case("csv");
    if !csv && !ext.eq_ignore_ascii_case("parquet") {
        anyhow::bail!("--history {}: give a .parquet or .csv file", path.display());
    }
    let inputs: Vec<&std::path::Path> = args.record.as_deref().into_iter().collect();
    let want = if csv { "csv" } else { "parquet" };
    rocking::outpath::check("--history", path, want, &inputs)?;
    Ok(())
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let block = args.block.one()?;
    check_history(&args)?;
    let rec = args
        .block
        .excitation(args.record.as_deref(), block.named.spec.p)?;
    let amplification = rec.floor.map_or(1.0, |f| f.pfa_over_pga);
    let eta = rocking::ask::excitation::eta(
        Spelling::Cli,
        args.eta,
        args.pga,
        block.named.alpha_rad,
        amplification,
    )?;
    let spec = physics::RunSpec {
        eta,
        ..block.named.spec
    };
    spec.validate()?;
    let (why, block_alpha) = (&block.why, block.named.alpha_rad);
    let mut recorder = Recorder::new(args.history_every);
    let out = if args.history.is_some() {
        physics::simulate_observed(&rec.exc, &spec, &mut recorder)?
    } else {
        physics::simulate(&rec.exc, &spec)?
    };
    if let Some(path) = &args.history {
        let record = match &args.record {
            Some(path) => path.display().to_string(),
            None => rec.record_id.clone(),
        };
        let settings = tables::history::settings(&record, &spec);
        tables::history::write(path, &recorder.points, &settings)?;
    }
    let scene = Scene {
        floor: None,
        mu: block.named.mu,
        slides_first: block.named.slides_first,
    };
    let report = SimulateReport::new(&rec, &spec, block_alpha, &out, &scene);
    if args.block.json {
        println!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    print_text(&args, &rec, &spec, why, &out, recorder.points.len());
    Ok(())
}

/// The response as text.
fn print_text(
    args: &Args,
    rec: &rocking::records::LoadedRecord,
    spec: &physics::RunSpec,
    why: &str,
    out: &physics::Outcome,
    history_points: usize,
) {
    match rec.pulse {
        Some(pulse) => println!(
            "pulse       {} (f = p·t_d = {}; {} samples, dt {} s)",
            rec.record_id,
            spec.p * pulse.t_d_s,
            rec.npts,
            rec.exc.dt_s
        ),
        None => println!(
            "record      {} ({} samples, dt {} s, {} {:.4} g)",
            rec.record_id,
            rec.npts,
            rec.exc.dt_s,
            if rec.floor.is_some() {
                "its floor motion's, PFA"
            } else {
                "PGA"
            },
            rec.pga_g
        ),
    }
    if let Some(f) = rec.floor {
        println!(
            "floor       PFA/PGA = {:.4} (ground PGA {:.4} g, floor motion sampled {}× finer); η is the floor's",
            f.pfa_over_pga, f.ground_pga_g, f.substeps
        );
    }
    println!(
        "block       p = {} 1/s, ε = {}, η = {} ({why})",
        shortest(spec.p),
        shortest(spec.eps),
        shortest(spec.eta)
    );
    println!("overturning {}", spec.overturn);
    println!("θmax/α      {:.12}", out.max_abs_x);
    match out.overturn_time_s {
        Some(t) if out.overturn_after_record => {
            println!("overturned  yes, at {t:.6} s, after the record ended")
        }
        Some(t) => println!("overturned  yes, at {t:.6} s"),
        None => println!("overturned  no ({})", out.stop.label().replace('_', " ")),
    }
    println!("impacts     {}", out.impacts);
    if let Some(s) = rocking::ops::reports::Sliding::of(spec, out) {
        println!(
            "slide       max {:.6} m, ends at {:+.6} m ({} slips)",
            s.slide_max_m, s.slide_residual_m, s.slips
        );
        println!(
            "modes       rest {:.3} s, slide {:.3} s, rock {:.3} s, slide-rock {:.3} s",
            s.rest_s, s.slide_s, s.rock_s, s.slide_rock_s
        );
    }
    match out.first_uplift_s {
        Some(t) => println!("uplift      first at {t:.6} s"),
        None if spec.model.equation.friction().is_some() => println!("uplift      never"),
        None => println!("uplift      never (the record stays below the uplift threshold)"),
    }
    if let Some(path) = &args.history {
        println!("history     {history_points} points in {}", path.display());
    }
}
