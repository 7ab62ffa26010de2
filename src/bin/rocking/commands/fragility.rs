//! `rocking fragility`: P(overturn | IM) of a real block.

use rocking::ask::{FragilityAsk, Spelling};
use rocking::block::Restitution;
use rocking::damage::{DamageStates, FitMethod};
use rocking::figures::ims::display_name;
use rocking::im::Im;
use rocking::ops::damage;
use rocking::ops::fragility::{self, Request};

use super::args::{direct_progress, number, parse_im, parsed, LawArgs, SceneArgs, StatesArgs};
use super::states::print_fits;

/// Probability that a real block overturns at given PGAs.
#[derive(Debug, clap::Args)]
#[command(
    allow_negative_numbers = true,
    long_about = "Probability that a real block overturns at given levels of an intensity measure.\n\n\
    In PGA (--pga, the default IM): P(overturn | PGA) = Φ((ln η_c,50 − ln η)/β), η = αg/PGA, with \
    the capacity fractiles from the paper's regression (--from paper, the default) or a pipeline's \
    own fit (--from PIPELINE.toml). In another IM (--im pgv|pgd|sa(T)|avgsa|arias|cav --at …): \
    lognormal, from a study's damage table (its overturned state's fractile fit) carried over p \
    and ε (--from PIPELINE.toml) or from the records' own capacities (--direct). --direct also runs the block through a record suite (the \
    pipeline's, run and searched as its stages run them: its [model] (kind, integrator, rtol, \
    auto_tol, overturn), its [im] grid and tolerance; or the bundled far-field set, on `rocking capacity`'s default grid and tolerance, with the \
    model `--model auto` chooses: `rocking capacity` runs the linearised one unless told) \
    and prints the share of records whose capacity it exceeds at each level. In FEMA P-58's floor demands (--im pfa|pfv --direct), the capacity is \
    in the peak acceleration or velocity of the motion the block stands on: with --floor, the \
    floor motion's own (not restated in the ground's IMs); on the ground, its PGA or PGV.\n\n\
    --states gives several damage states instead (θmax/α thresholds, then overturning; \
    docs/MODEL.md §15): from the records' runs (--direct), or from a study (--from \
    PIPELINE.toml: overturning from its regression in PGA, every state from its damage table \
    carried over p and ε); the paper's regression knows overturning only."
)]
pub struct Args {
    /// Half-width of the block (m).
    #[arg(long, value_name = "m")]
    b: f64,
    /// Half-height of the block (m).
    #[arg(long, value_name = "m")]
    h: f64,
    /// Coefficient of restitution, or `housner` for 1 − 1.5 sin²α.
    #[arg(long, default_value = "housner", value_parser = parsed::<Restitution>)]
    eps: Restitution,
    /// Peak ground accelerations (g), comma-separated: the same as --im pga --at ….
    #[arg(
        long,
        value_name = "g[,g…]",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = number
    )]
    pga: Vec<f64>,
    /// The intensity measure: pga, pgv (cm/s), pgd (cm), sa(T) (g, T in s), avgsa (g), arias (m/s), cav (g·s);
    /// or a demand of the motion the block stands on, pfa (g), pfv (cm/s) or fsa(T) (g, the floor's
    /// spectral acceleration) (--direct).
    #[arg(long, default_value = "pga", value_parser = parse_im)]
    im: Im,
    /// Levels of --im in its unit, comma-separated.
    #[arg(
        long,
        value_name = "IML[,IML…]",
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = number
    )]
    at: Vec<f64>,
    #[command(flatten)]
    law: LawArgs,
    /// Run the block itself through the records (a pipeline's with --from, else --records)
    /// and fit its fragility to their capacities, instead of the regression or a study's
    /// tables; each level also gets the share of records that overturn it there.
    #[arg(long)]
    direct: bool,
    #[command(flatten)]
    scene: SceneArgs,
    /// The linearised model's accepted error in η_c; a block whose α exceeds it is flagged.
    /// --direct picks the model by it (the pipeline's [model] does with --from).
    #[arg(long, default_value_t = rocking::ask::block::AUTO_TOL)]
    auto_tol: f64,
    #[command(flatten)]
    states: StatesArgs,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// The request the options make.
fn ask(args: &Args) -> FragilityAsk {
    let law = args.law.ask();
    FragilityAsk {
        b: args.b,
        h: args.h,
        eps: args.eps,
        pga: args.pga.clone(),
        im: args.im,
        at: args.at.clone(),
        source: law.source,
        outputs: law.outputs,
        records: law.records,
        records_unit: law.records_unit,
        records_column: law.records_column,
        records_ground: law.records_ground,
        orientation: law.orientation,
        angle_step: law.angle_step,
        direct: args.direct,
        auto_tol: args.auto_tol,
        floor: args.scene.floor.floor.clone(),
        building: args.scene.floor.building.clone(),
        level: args.scene.floor.level,
        mu: args.scene.mu,
        states: args.states.states.clone(),
        method: args.states.method,
        dispersion: args.states.dispersion,
        if_not_lognormal: args.states.if_not_lognormal,
        tree: args.law.tree.clone(),
    }
}

/// The median η_c for the summary line. On a floor it is α/PGA of the
/// ground here, where `capacity --floor` states the floor's α/PFA: said,
/// so the two are not read as one.
fn eta_c_text(a: &fragility::Assessment, im: rocking::im::Im) -> String {
    let whose = match (&a.floor, im.floor()) {
        (Some(_), false) => " (α/PGA of the ground)",
        _ => "",
    };
    a.eta_c_median
        .map_or(String::new(), |e| format!("median η_c = {e:.4}{whose}, "))
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let (req, states) = ask(&args).resolve(Spelling::Cli, direct_progress(args.direct))?;
    if let Some(s) = &states.states {
        return run_states(&req, s, states.method, args.json);
    }
    let a = fragility::assess(&req)?;
    for w in &a.warnings {
        eprintln!("warning: {w}");
    }
    if args.json {
        println!("{}", serde_json::to_string(&a)?);
        return Ok(());
    }
    let unit = a.unit;
    let eta = eta_c_text(&a, args.im);
    println!(
        "block of half-width b = {} m, half-height h = {} m: α = {:.4} rad, p = {:.4} 1/s, ε {}; capacity in {} from {} ({}{}): {eta}median {:.4} {unit}, {}",
        a.b_m,
        a.h_m,
        a.alpha_rad,
        a.p,
        if a.eps.is_nan() {
            "by the tree".to_string()
        } else {
            format!("= {:.4}", a.eps)
        },
        a.im,
        a.source,
        a.fit,
        super::states::records_text(a.records, a.records_folder.as_deref()),
        a.median,
        if a.fit == "empirical" {
            let why = match a.lognormal_p {
                Some(p) if p < rocking::damage::LOGNORMAL_CHECK_LEVEL => format!(
                    " (a lognormal does not fit them: Lilliefors p = {p:.3} < 0.05; \
                     --if-not-lognormal lognormal keeps it)"
                ),
                _ => String::new(),
            };
            format!("no β: the records' own curve, linear between their capacities{why}")
        } else {
            format!("β = {:.3}", a.beta)
        }
    );
    let direct = a.records.is_some();
    if let Some(t) = &a.tree {
        super::tree::print_tree(t, unit);
    }
    if let Some(floor) = &a.floor {
        println!(
            "{}",
            super::states::floor_line(floor, args.im.floor(), "capacities")
        );
    }
    if let Some(o) = &a.orientation {
        println!("orientation {o}");
    }
    if let (Some(n), Some(m)) = (a.records, &a.model) {
        println!(
            "--direct: {n} records run with the {m}; the last column is the share of them \
             whose capacity the level exceeds (--method empirical draws the records' curve \
             through their capacities)"
        );
    }
    let head = format!("{} ({unit})", display_name(&a.im));
    let pga = a.im == "pga";
    println!(
        "{head:>14} {:>10} {:>14}{}{}",
        if pga { "η" } else { "" },
        "P(overturn)",
        if direct { "  share overturned" } else { "" },
        if a.points.iter().any(|p| p.quantiles.is_some()) {
            "  over the tree: 5 %    16 %    50 %    84 %    95 %"
        } else {
            ""
        }
    );
    for pt in &a.points {
        let eta = pt.eta.map_or(String::new(), |e| super::cell(e, 10));
        let share = pt
            .empirical
            .map_or(String::new(), |e| format!("  {e:>18.4}"));
        let q = pt.quantiles.as_ref().map_or(String::new(), |q| {
            let cells: Vec<String> = q.iter().map(|v| format!("{v:.4}")).collect();
            format!("  {:>15}", cells.join("  "))
        });
        println!(
            "{} {eta:>10} {:>14.4}{share}{q}",
            super::cell(pt.iml, 14),
            pt.probability
        );
    }
    Ok(())
}

/// `--states`: each state's fits, then its probability at each level.
fn run_states(
    req: &Request,
    states: &DamageStates,
    method: FitMethod,
    json: bool,
) -> anyhow::Result<()> {
    let a = damage::assess(req, states, method)?;
    let f = &a.fragility;
    for w in &f.warnings {
        eprintln!("warning: {w}");
    }
    if json {
        println!("{}", serde_json::to_string(&a)?);
        return Ok(());
    }
    println!(
        "block of half-width b = {} m, half-height h = {} m: α = {:.4} rad, p = {:.4} 1/s, ε = {:.4}; damage states in {} from {}{}{}",
        a.b_m,
        a.h_m,
        a.alpha_rad,
        a.p,
        a.eps,
        f.im,
        f.source,
        f.equation.map_or(String::new(), |e| format!(" ({e} model)")),
        super::states::records_text(f.records, f.records_folder.as_deref())
    );
    print_fits(f);
    println!(
        "P(state reached | {}) by the {} fit:",
        display_name(&f.im),
        a.method
    );
    let head = format!("{} ({})", display_name(&f.im), f.unit);
    let names: String = f
        .states
        .iter()
        .map(|s| format!(" {:>14}", s.name))
        .collect();
    println!("{head:>14}{names}");
    for pt in &a.points {
        let cells: String = pt
            .probabilities
            .iter()
            .map(|p| p.map_or(format!(" {:>14}", "—"), |p| format!(" {p:>14.4}")))
            .collect();
        println!("{}{cells}", super::cell(pt.iml, 14));
    }
    Ok(())
}
