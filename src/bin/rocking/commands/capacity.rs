//! `rocking capacity`: one record's overturning capacity.

use clap::ValueEnum;
use rocking::ida::{ImGrid, RunKind, Spacing, Trace};
use rocking::label::Label;
use serde::Serialize;

use super::args::{named, number, BlockArgs, Flags};

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
    #[arg(long, value_name = "Δη", default_value_t = TOL)]
    tol: f64,
    /// Number of intensity levels below η = 1.
    #[arg(long, default_value_t = LEVELS)]
    levels: usize,
    /// Smallest η (strongest shaking) tried.
    #[arg(long, default_value_t = ETA_MIN)]
    eta_min: f64,
    /// Spacing of the levels in η.
    #[arg(long, value_enum, default_value_t = SpacingArg::Log)]
    spacing: SpacingArg,
}

/// The defaults of `--tol`, `--levels` and `--eta-min`.
const TOL: f64 = 1e-4;
const LEVELS: usize = 200;
const ETA_MIN: f64 = 1e-3;

impl Args {
    /// The arguments after `rocking capacity`, read without clap for a
    /// record's usual command line ([`Flags`]); `None` for anything else (a
    /// pulse, `--help`, a value that does not parse, an unknown or repeated
    /// name), which clap then reads. Scripts call `capacity` in loops: clap's
    /// first parse costs about 0.2 ms of cold code there.
    pub fn quick(args: impl IntoIterator<Item = std::ffi::OsString>) -> Option<Args> {
        let mut flags = Flags::scan(args, &["json"])?;
        let args = Args {
            block: BlockArgs::quick(&mut flags)?,
            tol: flags.value("tol", number)?.unwrap_or(TOL),
            levels: flags.value("levels", number)?.unwrap_or(LEVELS),
            eta_min: flags.value("eta-min", number)?.unwrap_or(ETA_MIN),
            spacing: flags.value("spacing", named)?.unwrap_or(SpacingArg::Log),
        };
        flags.all_taken().then_some(args)
    }
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

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::super::{Cli, Command};
    use super::Args;

    /// What clap makes of `rocking capacity <line>` through the whole
    /// command tree: the reference the quick reading must equal.
    fn by_clap(line: &[&str]) -> Option<Args> {
        let argv = ["rocking", "capacity"].iter().chain(line);
        match Cli::try_parse_from(argv).ok()?.command {
            Command::Capacity(args) => Some(args),
            _ => None,
        }
    }

    fn quick(line: &[&str]) -> Option<Args> {
        Args::quick(line.iter().map(std::ffi::OsString::from))
    }

    /// A command line's words (blanks separate them).
    fn words(line: &str) -> Vec<&str> {
        line.split_whitespace().collect()
    }

    #[test]
    fn quick_reading_equals_clap_or_leaves_the_line_to_it() {
        let mut read: Vec<Vec<&str>> = [
            "--record R.AT2 --p 2 --eps 0.7",
            "--p=2 --eps=0.7 --record=R.AT2 --json",
            "--record R.AT2 --p 2 --eps 0.7 --model nonlinear --alpha 0.2 --rtol 1e-9",
            "--record R.AT2 --p 0.5 --eps 1 --model auto --alpha 0.1 --auto-tol 0.02 --overturn cap:1.5",
            "--record R.AT2 --p 2 --eps 0.7 --tol 1e-3 --levels 50 --eta-min 0.01 --spacing linear --overturn escape",
        ]
        .map(words)
        .into();
        read.push(vec![
            "--json", "--record", "a b.AT2", "--eps", ".7", "--p", "2e0",
        ]);
        for line in &read {
            let (got, want) = (quick(line), by_clap(line));
            assert!(got.is_some() && want.is_some(), "{line:?}");
            assert_eq!(format!("{got:?}"), format!("{want:?}"), "{line:?}");
        }
        // Lines clap must read itself: its help, its errors, and what the
        // quick reading does not know (a pulse, a negative number, a short
        // option, a positional argument); and whether clap reads each.
        let mut left: Vec<(Vec<&str>, bool)> = [
            ("--help", false),
            ("-h", false),
            ("--record R.AT2 --p 2", false),
            ("--record R.AT2 --p two --eps 0.7", false),
            ("--record R.AT2 --p 2 --eps 0.7 --p 3", false),
            ("--record R.AT2 --p 2 --eps 0.7 --json=true", false),
            ("--record R.AT2 --p 2 --eps 0.7 --bogus 1", false),
            ("--record R.AT2 --p 2 --eps 0.7 --model Linearized", false),
            ("--record R.AT2 --p 2 --eps 0.7 --levels 1.5", false),
            ("--record R.AT2 --p 2 --eps 0.7 extra", false),
            ("--record R.AT2 --p 2 --eps", false),
            ("--record R.AT2 --p 2 --eps 0.7 --overturn sideways", false),
            // A pulse, a negative p (refused later by the block's checks),
            // and --td, which only a pulse uses.
            ("--pulse rect --p 2 --eps 0.7", true),
            ("--record R.AT2 --p -2 --eps 0.7", true),
            ("--record R.AT2 --p 2 --eps 0.7 --td 2", true),
        ]
        .map(|(line, clap_reads)| (words(line), clap_reads))
        .into();
        left.push((vec!["--record", "", "--p", "2", "--eps", "0.7"], false));
        for (line, clap_reads) in &left {
            assert!(quick(line).is_none(), "{line:?}");
            assert_eq!(by_clap(line).is_some(), *clap_reads, "{line:?}");
        }
    }
}
