//! `rocking export`: damage-state fragilities for OpenQuake or pelicun.

use rocking::figures::ims::display_name;
use std::path::PathBuf;

use rocking::ask::{ExportAsk, Spelling};
use rocking::damage::{DamageStates, Dispersion, FitMethod, IfNotLognormal};
use rocking::ops::export::{self, Format};

use super::args::{direct_progress, label, parse_im, parsed, BlocksArgs, LawArgs};
use super::states::print_fits;

/// Damage-state fragilities of a block (or an inventory) as OpenQuake NRML or pelicun CSV.
#[derive(Debug, clap::Args)]
#[command(
    allow_negative_numbers = true,
    long_about = "Damage-state fragilities of a block (or of every block of an inventory) in the \
    formats of the loss and risk engines.\n\n\
    --format nrml writes OpenQuake's NRML 0.5 fragility model (continuous, logncdf; one \
    fragilityFunction per block, its taxonomy the block's name; OpenQuake's mean and stddev are \
    those of the IML: mean = θ·exp(β²/2), stddev = mean·√(exp(β²) − 1)) and, with --hazard (an \
    OpenQuake hazard-curve CSV), an exposure placing one of each block at each of its sites and a \
    job.ini for classical_damage: `oq engine --run job.ini` in --out.\n\n\
    --format pelicun writes pelicun's fragility CSV (one component per block; LSk-Theta_0 the \
    median, LSk-Theta_1 β) and its metadata JSON; in PFA or PFV (--im pfa|pfv --direct) its \
    demand type is FEMA P-58's contents' (Peak Floor Acceleration, Peak Floor Velocity), and \
    pelicun's default demand offset of −1 for them puts a component at location k on floor \
    k − 1.\n\n\
    The states (--states, default rocking=0.1,large_rocking=0.5,overturned=overturned: θmax/α \
    thresholds, then overturning) come from the block's runs under the records (--direct), each \
    record's capacity the first crossing as intensity rises; the lognormal by the paper's \
    fractiles (--method fractile) or censored maximum likelihood (--method mle). With --from \
    PIPELINE.toml, overturning comes from the study's regression in PGA, as in `fragility` and \
    `risk`, and every other fit from its damage table (`damage_states.parquet`, \
    the pipeline's [damage] states) carried over p and ε; the paper's regression (--from paper, \
    the default) gives overturning only."
)]
pub struct Args {
    /// The engine.
    #[arg(long, value_parser = label::<Format>())]
    format: Format,
    #[command(flatten)]
    blocks: BlocksArgs,
    #[command(flatten)]
    law: LawArgs,
    /// Use the block's own runs under the records: every damage state.
    #[arg(long)]
    direct: bool,
    /// With --direct: the blocks stand on a building's floor (see `--floor` below).
    #[command(flatten)]
    floor: super::args::FloorArgs,
    /// The limit states, lightest first: NAME=X (θmax/α ≥ X), NAME=Xm (the
    /// base slides X metres: the slide-rock model, --mu) or NAME=overturned
    /// [default: rocking=0.1,large_rocking=0.5,overturned=overturned; from the
    /// paper's regression, overturned=overturned alone].
    #[arg(long, value_parser = parsed::<DamageStates>)]
    states: Option<DamageStates>,
    /// The fit of each state: a lognormal (fractile or mle), or (--direct)
    /// the records' own curve, written as pelicun's multilinear_CDF and
    /// OpenQuake's discrete function.
    #[arg(long, value_parser = label::<FitMethod>(), default_value = "fractile")]
    method: FitMethod,
    /// The states' dispersions: one β for all (the heaviest state's, medians
    /// in order: no heavier state likelier than a lighter one) or each its own.
    #[arg(long, value_parser = label::<Dispersion>(), default_value = "common")]
    dispersion: Dispersion,
    /// Where a block's records' capacities fail the lognormal check
    /// (Lilliefors at 5 % on their logarithms; --direct): their own curve
    /// (pelicun's multilinear_CDF, OpenQuake's discrete function), or the
    /// lognormal anyway [default: curve].
    #[arg(long, value_parser = label::<IfNotLognormal>())]
    if_not_lognormal: Option<IfNotLognormal>,
    /// The IM [default: the hazard's, or PGA]; pelicun also takes FEMA P-58's
    /// floor demands pfa (g) and pfv (cm/s) (--direct; on a --floor, the floor
    /// motion's own).
    #[arg(long, value_parser = parse_im)]
    im: Option<rocking::im::Im>,
    /// OpenQuake hazard curves (nrml): the exposure's sites and the job's hazard.
    #[arg(long, value_name = "FILE.csv")]
    hazard: Option<PathBuf>,
    /// The job's risk investigation time (years; with --hazard) [default: 50].
    #[arg(long)]
    years: Option<f64>,
    /// The linearised model's accepted error in η_c (--direct picks the model by it; the
    /// pipeline's [model] does with --from).
    #[arg(long, default_value_t = rocking::ask::block::AUTO_TOL)]
    auto_tol: f64,
    /// The folder to write (created if needed).
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Print the fragilities as JSON (an array, one object per block).
    #[arg(long)]
    json: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let ask = ExportAsk {
        format: args.format,
        blocks: args.blocks.ask(),
        law: args.law.ask(),
        direct: args.direct,
        floor: args.floor.floor.clone(),
        building: args.floor.building.clone(),
        level: args.floor.level,
        states: args.states.clone(),
        method: args.method,
        dispersion: args.dispersion,
        if_not_lognormal: args.if_not_lognormal,
        im: args.im,
        hazard: args.hazard.clone(),
        years: args.years,
        auto_tol: args.auto_tol,
        out: args.out.clone(),
        tree: args.law.tree.clone(),
    };
    let (req, asked_states) = ask.resolve(Spelling::Cli, direct_progress(args.direct))?;
    let written = export::export(&req)?;
    for x in &written.blocks {
        for w in &x.fragility.warnings {
            eprintln!("warning: block {}: {w}", x.block.name);
        }
    }
    if args.json {
        println!("{}", serde_json::to_string(&written.blocks)?);
        return Ok(());
    }
    if !asked_states {
        eprintln!(
            "note: the paper's regression gives overturning only; --direct runs the records, and \
             --from PIPELINE.toml takes a study's damage table, for every damage state"
        );
    }
    for x in &written.blocks {
        let (b, f) = (&x.block, &x.fragility);
        println!(
            "{} (half-width {} m, half-height {} m): {} from {}{}",
            b.name,
            b.b_m,
            b.h_m,
            display_name(&f.im),
            f.source,
            super::states::records_text(f.records, f.records_folder.as_deref())
        );
        match &x.tree {
            None => {
                print_fits(f);
                if x.written_as == "curve" {
                    println!(
                        "  written as the records' own curves, linear between their capacities \
                         (pelicun's multilinear_CDF, OpenQuake's discrete function)"
                    );
                }
            }
            Some(t) => print_tree(t, x.written_as),
        }
    }
    for f in &written.files {
        println!("wrote {}", f.display());
    }
    Ok(())
}

/// A block over a logic tree: each branch's fits, then how the engine gets
/// them (OpenQuake each branch's functions and their weights, pelicun their
/// mean).
fn print_tree(t: &rocking::ops::export::TreeExport, written_as: &str) {
    println!(
        "  over the logic tree {} ({} branches)",
        t.tree,
        t.branches.len()
    );
    for b in &t.branches {
        println!(
            "  branch {} (weight {}, ε = {:.4}):",
            b.branch, b.weight, b.eps
        );
        print_fits(&b.fragility);
    }
    match &t.mean {
        None => println!(
            "  written as each branch's functions (ids {}_b1…), mixed by their weights \
             (taxonomy_mapping.csv)",
            t.branches.first().map_or("", |b| b
                .risk_id
                .rsplit_once("_b")
                .map_or(b.risk_id.as_str(), |(tax, _)| tax))
        ),
        Some(m) if written_as == "lognormal" => println!(
            "  written as the mean over the branches: FEMA P-58's lognormal of β_total per \
             state (largest |ΔP| from the mixture {:.4}; the curve's {:.4})",
            m.lognormal_error.unwrap_or(f64::NAN),
            m.curve_error
        ),
        Some(m) => println!(
            "  written as the mean over the branches: a multilinear_CDF through the mixture \
             (largest |ΔP| from it {:.4})",
            m.curve_error
        ),
    }
}
