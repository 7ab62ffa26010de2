//! `rocking capacity`: one record's overturning capacity.

use std::io::Write;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};

use rocking::ask::{AskedBlock, SearchAsk, Spelling};
use rocking::decimal::shortest;
use rocking::ida::{Certified, Spacing};
use rocking::ops::capacity::{self, NamedSpec};
use rocking::ops::reports::{self, CapacityReport};
use rocking::records::LoadedRecord;
use rocking::stages::{Progress, Reporter};

use super::args::{label, number, BlockArgs};
use crate::reporter::Terminal;

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
    verdict that changes marks the capacity chaotic (not certified).\n\n\
    Many capacities in one process: give several records (files or folders) and several blocks \
    (comma-separated --p and --eps, a p × ε grid; or --b/--h or --width/--height lists, each size \
    with every ε). The record × block cases run on every core and print one JSON object a line, \
    records in path order and blocks in the order given, each equal to the capacity of that \
    record and block alone; --out also writes them as a Parquet table.\n\n\
    Any direction: with --pair B.AT2 (the other horizontal component of --record's station, 90° \
    from it, at the same sample step) and --angle θ (degrees; a list, or --angle-step for every \
    step over [0°, 180°)), the block rocks in the plane at θ from --record towards B and feels \
    a cos θ + b sin θ (the shorter component taken as 0 after its end): one capacity per angle, \
    the record named `<stem>@<θ>`, `angle_deg` in the JSON. θ = 0° is --record itself and 90° \
    B itself, bit for bit; θ + 180° is θ's mirror image (docs/MODEL.md §18)."
)]
pub struct Args {
    /// AT2 records, or folders searched recursively for `*.AT2` (several:
    /// one capacity per record and block, one JSON line each).
    #[arg(long, value_name = "PATH", num_args = 1..)]
    record: Vec<PathBuf>,
    /// The other horizontal component of --record's station (AT2, 90° from
    /// it): the block then rocks at each --angle.
    #[arg(long, value_name = "B.AT2", requires = "record")]
    pair: Option<PathBuf>,
    /// With --pair: the angles (°) of the rocking plane from --record
    /// towards --pair, comma-separated.
    #[arg(
        long,
        value_name = "DEG",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = number,
        requires = "pair",
        conflicts_with = "angle_step"
    )]
    angle: Vec<f64>,
    /// With --pair: every angle over [0°, 180°) this many degrees apart.
    #[arg(long, value_name = "DEG", requires = "pair")]
    angle_step: Option<f64>,
    #[command(flatten)]
    block: BlockArgs,
    /// Refine η_c until the bracket is at most this wide (in η; finer than 1e-7, the
    /// certification cannot tell a sharp edge from chaos, and says so).
    #[arg(long, value_name = "Δη", default_value_t = 1e-4)]
    tol: f64,
    /// Number of intensity levels below η = 1.
    #[arg(long, default_value_t = 200)]
    levels: usize,
    /// Smallest η (strongest shaking) tried.
    #[arg(long, default_value_t = 1e-3)]
    eta_min: f64,
    /// Spacing of the levels in η.
    #[arg(long, value_parser = label::<Spacing>(), default_value = "log")]
    spacing: Spacing,
    /// Also write the capacities as a Parquet table (the sweep's `capacities` schema).
    #[arg(long, value_name = "FILE.parquet")]
    out: Option<PathBuf>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let search = SearchAsk {
        levels: args.levels,
        eta_min: args.eta_min,
        spacing: args.spacing,
        tol: args.tol,
    }
    // Checked before any record is read: an absurd --levels is refused at once.
    .resolve(Spelling::Cli)?;
    if let Some(w) = rocking::ida::tol_warning(search.tol, search.grid.eta_max) {
        eprintln!("warning: --tol: {w}");
    }
    let blocks = args.block.blocks()?;
    let building = args.block.ask().building(Spelling::Cli)?;
    if let Some(out) = &args.out {
        capacity::check_out(out, &args.record)?;
    }
    let records = if args.record.is_empty() {
        if blocks.len() != 1 {
            anyhow::bail!("a pulse is sampled for one block's p: give one block with --pulse");
        }
        vec![args.block.excitation(None, blocks[0].named.spec.p)?]
    } else {
        if args.block.pulse.pulse.is_some() {
            anyhow::bail!("give records (--record) or a pulse (--pulse), not both");
        }
        match &args.pair {
            Some(b) => {
                let angles = pair_angles(&args)?;
                let [a] = &args.record[..] else {
                    anyhow::bail!("--pair is the other component of one record: give one --record");
                };
                rocking::records::pair_at(a, b, &angles, building.as_ref())?
            }
            None => capacity::load_records(&args.record, building.as_ref())?,
        }
    };
    let named: Vec<NamedSpec> = blocks.iter().map(|b| b.named.clone()).collect();
    let total = records.len() * named.len();
    // A batch shows its progress as a stage does (one capacity alone is
    // over in milliseconds and says nothing on stderr).
    let terminal = (total > 1).then(Terminal::new);
    let (done, runs) = (AtomicU64::new(0), AtomicU64::new(0));
    let tick = |c: &Certified| {
        let Some(terminal) = &terminal else { return };
        let ran = (c.capacity.runs() + c.extra.runs) as u64;
        terminal.progress(&Progress {
            stage: "capacity",
            done: done.fetch_add(1, Ordering::Relaxed) + 1,
            total: total as u64,
            resumed: 0,
            runs: runs.fetch_add(ran, Ordering::Relaxed) + ran,
        });
    };
    let results = capacity::capacities(&records, &named, &search.grid, search.tol, &tick)?;
    drop(terminal);
    if let Some(out) = &args.out {
        let settings = vec![(
            "rocking.capacity.command".to_string(),
            std::env::args().skip(1).collect::<Vec<_>>().join(" "),
        )];
        rocking::tables::write(out, &capacity::rows(&records, &named, &results), &settings)?;
    }
    let reports = rocking::ops::reports::capacity_reports(
        &records,
        &named,
        &results,
        &search,
        building.as_ref(),
    );
    if args.block.json || total > 1 {
        if !args.block.json {
            eprintln!("{total} capacities, one JSON object a line (--json says so explicitly)");
        }
        let mut stdout = std::io::stdout().lock();
        for report in reports {
            writeln!(stdout, "{}", serde_json::to_string(&report)?)?;
        }
        return Ok(());
    }
    print_text(&args, &records[0], &blocks[0], (&results[0], &reports[0]));
    Ok(())
}

/// The angles asked with --pair, checked.
fn pair_angles(args: &Args) -> anyhow::Result<Vec<f64>> {
    if let Some(step) = args.angle_step {
        rocking::ask::check_angle_step(step, Spelling::Cli)?;
        return Ok(rocking::pair::angles(step));
    }
    if args.angle.is_empty() {
        anyhow::bail!(
            "--pair: give the rocking plane's --angle (degrees from --record), or --angle-step"
        );
    }
    rocking::ask::check_angles(&args.angle, Spelling::Cli)?;
    Ok(args.angle.clone())
}

/// One capacity as text: its peaks at the capacity are its JSON's.
fn print_text(
    args: &Args,
    rec: &LoadedRecord,
    block: &AskedBlock,
    (certified, report): (&Certified, &CapacityReport),
) {
    let (spec, cap) = (&block.named.spec, &certified.capacity);
    if let Some(theta) = rec.angle_deg {
        println!("direction   {theta}° from the pair's first component towards its second");
    }
    println!(
        "record      {} ({} samples, dt {} s{})",
        rec.record_id,
        rec.npts,
        rec.exc.dt_s,
        if rec.floor.is_some() {
            ": its floor motion's"
        } else {
            ""
        }
    );
    if let Some(f) = rec.floor {
        println!(
            "floor       PFA/PGA = {:.4} (ground PGA {:.4} g, floor motion sampled {}× finer); η is the floor's",
            f.pfa_over_pga, f.ground_pga_g, f.substeps
        );
    }
    println!(
        "block       p = {} 1/s, ε = {} ({})",
        shortest(spec.p),
        shortest(spec.eps),
        block.why
    );
    match cap.eta_c {
        Some(c) => {
            let peak = if rec.floor.is_some() { "PFA" } else { "PGA" };
            let peak_g = report.pfa_c_g.or(report.pga_c_g);
            let pga = peak_g
                .map(|g| format!(", {peak} {g:.4} g"))
                .unwrap_or_default();
            println!(
                "η_c         {c:.6} ({peak} = {:.4} αg{pga}), survives at η = {:.6}",
                1.0 / c,
                cap.eta_survived
            );
            if let (Some(ground), Some(_)) = (report.pga_c_g, report.pfa_c_g) {
                println!("ground      PGA {ground:.4} g at the capacity");
            }
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
    let refinements = reports::refinement_runs(certified);
    println!(
        "runs        {} ({} levels, {} refinements){}",
        cap.runs(),
        cap.runs() - refinements,
        refinements,
        if certified.extra.runs > 0 {
            format!(", and {} to certify it", certified.extra.runs)
        } else {
            String::new()
        }
    );
    println!("certified   {}", certified.certification);
}
