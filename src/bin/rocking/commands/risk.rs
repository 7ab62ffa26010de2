//! `rocking risk`: the annual rate of overturning at a site.

use rocking::figures::ims::display_name;
use std::path::PathBuf;

use rocking::ask::{HazardAsk, RiskAsk, Spelling};
use rocking::damage::{DamageStates, FitMethod};
use rocking::im::level_text;
use rocking::ops::risk::{self, Assessment, Blocks, Request};
use rocking::risk::Beyond;
use rocking::tables::atomic_write;

use super::args::{direct_progress, label, parse_im, BlocksArgs, FloorArgs, LawArgs, StatesArgs};

/// Annual rate of overturning of a block (or an inventory) at the sites of a hazard file.
#[derive(Debug, clap::Args)]
#[command(
    allow_negative_numbers = true,
    long_about = "Annual rate of overturning of a block (or of every block of an inventory) at the \
    sites of a hazard curve in PGA, PGV, SA(T) or AvgSA.\n\n\
    λ_OT = ∫ P(OT | a) |dλ(a)|, the hazard interpolated log-log between its points (closed form on \
    each segment), P(OT | a) in the hazard's IM: in PGA from the paper's regression (default) or a \
    pipeline's fit (--from PIPELINE.toml); in another IM from a study's damage table (its overturned \
    state's fit, --from PIPELINE.toml); or from the block's own capacities under the records (--direct). The hazard is \
    an OpenQuake hazard-curve CSV (poe within investigation_time, several sites; imt='PGA', 'PGV' \
    (cm/s), 'SA(T)' or 'AvgSA') or a plain CSV `pga_g,annual_rate` (or `pgv_cm_s`, `sa(1.0)_g`, \
    `avgsa_g`; one site). Prints per site the annual rate, the return period, the probability of \
    overturning within --years, the fragility's median and β, and the deaggregation by the IM. \
    With --inventory, writes one row per block × site to --out (Parquet).\n\n\
    --states gives the annual rate at which each damage state is reached instead (θmax/α \
    thresholds, then overturning; docs/MODEL.md §15), each from its lognormal fragility (by \
    --method) as in `fragility --states`: from the records' runs (--direct) or a study (--from \
    PIPELINE.toml); printed, or JSON with --json."
)]
pub struct Args {
    /// The hazard curves: OpenQuake's hazard_curve-…-<IMT>_….csv, or `pga_g,annual_rate`.
    #[arg(long, value_name = "FILE.csv", required_unless_present = "gmf")]
    hazard: Option<PathBuf>,
    /// Instead of --hazard: OpenQuake's event-based ground-motion fields, the
    /// folder `oq run … --exports csv` wrote (gmf-data, events, sitemesh):
    /// each site's rate as Σ over events ÷ the effective time, and how many
    /// of the blocks fall in one event (docs/MODEL.md §20).
    #[arg(long, value_name = "DIR", conflicts_with = "hazard")]
    gmf: Option<PathBuf>,
    /// With --gmf: the effective investigation time (years), when no job.ini
    /// beside the CSVs says it (investigation_time × ses_per_logic_tree_path
    /// × realisations).
    #[arg(long, value_name = "Y")]
    eff_years: Option<f64>,
    /// With --gmf: how the blocks at a site fall together in one event.
    #[arg(long, value_parser = label::<rocking::events::Together>(), default_value = "same-record")]
    together: rocking::events::Together,
    /// With --gmf and --direct: also the rate by the two-parameter fragility
    /// P(OT | PGA, PGV/PGA) of the block's own capacities.
    #[arg(long)]
    vector: bool,
    /// The fragility's IM; it must be the hazard's (the default).
    #[arg(long, value_parser = parse_im)]
    im: Option<rocking::im::Im>,
    /// Which component the hazard is of: rotd50 (the ground-motion models')
    /// states the fragility in RotD50 with --direct, and warns of the
    /// mismatch without.
    #[arg(long, value_parser = label::<rocking::pair::Component>())]
    component: Option<rocking::pair::Component>,
    /// Only this site of the file (index from 0).
    #[arg(long, value_name = "N")]
    site: Option<usize>,
    #[command(flatten)]
    blocks: BlocksArgs,
    /// Where --inventory's table goes (one row per block × site) [default: risk.parquet].
    #[arg(long, value_name = "FILE.parquet")]
    out: Option<PathBuf>,
    #[command(flatten)]
    law: LawArgs,
    /// Use the block's own capacities under the records instead of a regression.
    #[arg(long)]
    direct: bool,
    /// With --direct: the blocks stand on a building's floor (see `--floor` below).
    #[command(flatten)]
    floor: FloorArgs,
    /// Years for the probability of overturning within them.
    #[arg(long, default_value_t = 50.0)]
    years: f64,
    /// Beyond the hazard's last IML.
    #[arg(long, value_parser = label::<Beyond>(), default_value = "extrapolate")]
    beyond: Beyond,
    /// The linearised model's accepted error in η_c; a block whose α exceeds it is flagged.
    /// --direct picks the model by it (the pipeline's [model] does with --from).
    #[arg(long, default_value_t = rocking::ask::block::AUTO_TOL)]
    auto_tol: f64,
    /// Write a bar chart (SVG): the deaggregation of the block at --site (default 0),
    /// or with --inventory the blocks ranked by their rate at --site.
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// The rate of each damage state (prints only; no table, no chart), and its fit.
    #[command(flatten)]
    states: StatesArgs,
    /// With --direct: resample the records' pairs this many times for a 90 %
    /// band on each site's rate (and on the fragility's median and β).
    #[arg(long, value_name = "N", default_value_t = 0)]
    bootstrap: usize,
    /// The bootstrap's seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Print JSON instead of text (one object; an array with --inventory).
    #[arg(long)]
    json: bool,
}

/// The request the options make.
fn ask(args: &Args) -> RiskAsk {
    let law = args.law.ask();
    RiskAsk {
        hazard: args.hazard.clone().map(HazardAsk::File),
        gmf: args.gmf.clone(),
        eff_years: args.eff_years,
        together: args.together,
        vector: args.vector,
        site: args.site,
        b: args.blocks.b,
        h: args.blocks.h,
        eps: args.blocks.eps,
        inventory: args.blocks.inventory.clone(),
        mu: args.blocks.mu,
        im: args.im,
        component: args.component,
        source: law.source,
        outputs: law.outputs,
        records: law.records,
        records_unit: law.records_unit,
        records_column: law.records_column,
        records_ground: law.records_ground,
        orientation: law.orientation,
        angle_step: law.angle_step,
        direct: args.direct,
        years: args.years,
        beyond: args.beyond,
        auto_tol: args.auto_tol,
        floor: args.floor.floor.clone(),
        building: args.floor.building.clone(),
        level: args.floor.level,
        states: args.states.states.clone(),
        method: args.states.method,
        dispersion: args.states.dispersion,
        if_not_lognormal: args.states.if_not_lognormal,
        tree: args.law.tree.clone(),
        bootstrap: args.bootstrap,
        seed: args.seed,
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let (req, states) = ask(&args).resolve(Spelling::Cli, direct_progress(args.direct))?;
    let beyond = req.beyond;
    if let risk::Hazard::Events(e) = &req.hazard {
        if args.plot.is_some() || args.out.is_some() {
            anyhow::bail!(
                "--gmf prints its answer (or --json); --plot and --out are for hazard curves"
            );
        }
        let a = risk::assess_events(&req, e)?;
        return super::events::print(&a, args.json);
    }
    if let Some(s) = &states.states {
        if args.plot.is_some() || args.out.is_some() {
            anyhow::bail!(
                "--states prints each state's rate (or --json); --plot and --out are for \
                 overturning alone"
            );
        }
        return run_states(&req, s, states.method, args.json);
    }

    let out = args.out.clone().unwrap_or_else(|| "risk.parquet".into());
    if args.out.is_some() && args.blocks.inventory.is_none() {
        anyhow::bail!(
            "--out writes an inventory's table; one block's answer is printed (or --json)"
        );
    }
    let mut inputs: Vec<&std::path::Path> = args.hazard.as_deref().into_iter().collect();
    inputs.extend(args.blocks.inventory.as_deref());
    if let rocking::ops::fragility::Source::Pipeline { file, .. } = &req.from {
        inputs.push(file.as_path());
    }
    if args.blocks.inventory.is_some() {
        rocking::outpath::check("--out", &out, "parquet", &inputs)?;
        inputs.push(out.as_path());
    }
    if let Some(plot) = &args.plot {
        rocking::outpath::check("--plot", plot, "svg", &inputs)?;
    }
    let all = risk::assess(&req)?;
    // The chart is drawn before anything is written: a chart that cannot
    // be drawn (every rate 0) leaves no table behind either.
    let inventory = args.blocks.inventory.is_some();
    let site = args.site.unwrap_or(0);
    let chart = args
        .plot
        .as_ref()
        .map(|_| chart(&all, site, inventory))
        .transpose()?;
    // The chart first, then the table: a chart that cannot be written (its
    // folder cannot be made) leaves no table; a table that cannot be
    // written takes its chart away.
    if let (Some(plot), Some(chart)) = (&args.plot, chart) {
        atomic_write(plot, chart.as_bytes())?;
    }
    if args.blocks.inventory.is_some() {
        if let Err(e) = risk::write_table(&out, &risk::rows(&all, beyond), &req.hazard.name()) {
            if let Some(plot) = &args.plot {
                let _ = std::fs::remove_file(plot);
            }
            return Err(e.into());
        }
    }
    for a in &all {
        for w in &a.warnings {
            eprintln!("warning: block {}: {w}", a.block.name);
        }
    }
    if args.json {
        let text = if args.blocks.inventory.is_some() {
            serde_json::to_string(&all)?
        } else {
            serde_json::to_string(&all[0])?
        };
        println!("{text}");
        return Ok(());
    }
    if args.blocks.inventory.is_some() {
        print_inventory(&all, args.years);
        println!(
            "wrote {} ({} rows){}",
            out.display(),
            all.iter().map(|a| a.sites.len()).sum::<usize>(),
            args.plot
                .as_ref()
                .map_or(String::new(), |p| format!(" and {}", p.display()))
        );
    } else {
        print_one(&all[0]);
        if let Some(p) = &args.plot {
            println!("deaggregation chart: {}", p.display());
        }
    }
    Ok(())
}

/// `--states`: each block's states at each site.
fn run_states(
    req: &Request,
    states: &DamageStates,
    method: FitMethod,
    json: bool,
) -> anyhow::Result<()> {
    let all = risk::assess_states(req, states, method)?;
    for a in &all {
        for w in &a.warnings {
            eprintln!("warning: block {}: {w}", a.block.name);
        }
    }
    if json {
        let text = match &req.blocks {
            Blocks::Inventory(_) => serde_json::to_string(&all)?,
            Blocks::One { .. } => serde_json::to_string(&all[0])?,
        };
        println!("{text}");
        return Ok(());
    }
    for a in &all {
        let b = &a.block;
        println!(
            "{}: α = {:.4} rad, p = {:.4} 1/s, ε = {:.4}; damage states in {} from {}{}, {} fit{}{}",
            b.name,
            b.alpha_rad,
            b.p,
            b.eps,
            a.im,
            a.source,
            a.equation.map_or(String::new(), |e| format!(" ({e} model)")),
            a.method,
            super::states::records_text(a.records, a.records_folder.as_deref()),
            if a.dispersion == "common" && a.sites.first().is_some_and(|s| s.states.len() > 1) {
                ", one β for the states (--dispersion common)"
            } else {
                ""
            }
        );
        let wide = a
            .sites
            .iter()
            .flat_map(|s| &s.states)
            .map(|s| s.criterion.chars().count())
            .max()
            .unwrap_or(0)
            .max(16);
        println!(
            "  {:>5} {:<16} {:<wide$} {:>20} {:>12} {:>16} {:>10}",
            "site",
            "state",
            "criterion",
            "median, β",
            "annual rate",
            "return period",
            format!("P({} yr)", a.years)
        );
        for site in &a.sites {
            for s in &site.states {
                let fit = match (s.median, s.beta) {
                    (Some(m), Some(b)) => format!("{} {}, {b:.3}", level_text(m), a.unit),
                    // Integrated all the same: a curve has no median and β.
                    _ if s.fit == "empirical" && s.annual_rate.is_some() => {
                        "the records' curve".to_string()
                    }
                    _ => "no fit".to_string(),
                };
                println!(
                    "  {:>5} {:<16} {:<wide$} {:>20} {:>12} {:>16} {:>10}",
                    site.site,
                    s.state,
                    s.criterion,
                    fit,
                    s.annual_rate.map_or("—".to_string(), rate),
                    s.return_period_years
                        .map_or("—".to_string(), |t| format!("{} yr", super::years(t))),
                    s.p_in_years.map_or("—".to_string(), |p| format!("{p:.4}")),
                );
            }
        }
    }
    Ok(())
}

/// The SVG of `--plot`: the blocks ranked at `site` (an inventory), or the
/// one block's deaggregation there.
fn chart(all: &[Assessment], site: usize, inventory: bool) -> anyhow::Result<String> {
    if inventory {
        return Ok(risk::ranking_chart(all, site)?);
    }
    let a = &all[0];
    let s = a
        .sites
        .iter()
        .find(|s| s.site == site)
        .unwrap_or(&a.sites[0]);
    Ok(risk::deaggregation_chart(a, s)?)
}

fn rate(r: f64) -> String {
    format!("{r:.3e}")
}

/// The fragility a risk rests on, in one line.
fn fragility_line(f: &rocking::ops::risk::FragilityInfo) -> String {
    let u = f.unit;
    let spread = if f.fit == "empirical" {
        let why = match f.lognormal_p {
            Some(p) if p < rocking::damage::LOGNORMAL_CHECK_LEVEL => {
                format!(", as a lognormal does not fit them (Lilliefors p = {p:.3})")
            }
            _ => String::new(),
        };
        format!("the records' own curve{why}")
    } else {
        format!("β {}", f.beta.map_or("—".into(), |v| format!("{v:.3}")))
    };
    format!(
        "fragility in {} from {} ({}): median {}, {spread}{}",
        f.im,
        f.source,
        f.fit,
        f.median
            .map_or("—".into(), |m| format!("{} {u}", level_text(m))),
        super::states::records_text(f.records, f.records_folder.as_deref())
    )
}

fn print_one(a: &Assessment) {
    let b = &a.block;
    let f = &a.fragility;
    println!(
        "block of half-width b = {} m, half-height h = {} m: α = {:.4} rad, p = {:.4} 1/s, ε {}",
        b.b_m,
        b.h_m,
        b.alpha_rad,
        b.p,
        match &f.tree {
            Some(t) if t.branches.len() > 1 => "by the tree".to_string(),
            _ => format!(
                "= {:.4}{}",
                b.eps,
                if b.eps_housner { " (Housner)" } else { "" }
            ),
        }
    );
    println!("{}", fragility_line(f));
    // It said nothing of the floor the block's records ran through.
    if let Some(floor) = &b.floor {
        let demand = f.im.parse::<rocking::im::Im>().is_ok_and(|im| im.floor());
        println!("{}", super::states::floor_line(floor, demand, "rates"));
    }
    if let Some(t) = &f.tree {
        super::tree::print_tree(t, f.unit);
    }
    if let Some(b) = &f.bootstrap {
        super::tree::print_bootstrap(b, f.unit);
    }
    let u = f.unit;
    for s in &a.sites {
        println!();
        let place = match (s.lon, s.lat) {
            (Some(lon), Some(lat)) => format!(" (lon {lon}°, lat {lat}°)"),
            _ => String::new(),
        };
        println!("site {}{place}", s.site);
        let lv = level_text;
        let rows = [
            (
                "annual rate of overturning".to_string(),
                rate(s.annual_rate),
            ),
            (
                "return period".into(),
                s.return_period_years.map_or("∞ (never)".into(), |t| {
                    format!("{} years", super::years(t))
                }),
            ),
            (
                format!("P(overturn within {} years)", a.years),
                format!("{:.4}", s.p_overturn_in_years),
            ),
            (
                "hazard curve used".into(),
                match s.imls_dropped {
                    0 => format!("{}–{} {u}", lv(s.first_iml), lv(s.last_iml)),
                    n => format!(
                        "{}–{} {u} ({n} IML(s) with poe = 1 dropped below)",
                        lv(s.first_iml),
                        lv(s.last_iml)
                    ),
                },
            ),
            (
                format!("P(OT | {} {u}), below the curve", lv(s.first_iml)),
                format!("{:.2e}", s.fragility_at_first_iml),
            ),
            (
                format!("rate beyond {} {u} ({})", lv(s.last_iml), a.beyond),
                format!("{:.1} % of the total", 100.0 * s.share_beyond_last_iml),
            ),
        ];
        let mut rows = rows.to_vec();
        if let (Some([lo, hi]), Some(b)) = (s.annual_rate_band, &f.bootstrap) {
            rows.insert(
                1,
                (
                    format!("{:.0} % band from the records", 100.0 * b.level),
                    format!("{} – {}", rate(lo), rate(hi)),
                ),
            );
        }
        let width = rows
            .iter()
            .map(|(l, _)| l.chars().count())
            .max()
            .unwrap_or(0);
        for (label, value) in &rows {
            println!("  {label:<width$} {value}");
        }
        if let (Some(t), Some(q)) = (&f.tree, &s.quantile_annual_rates) {
            super::tree::print_rates(&s.branches, &t.quantiles, q, s.mean_annual_rate);
        }
        print_deaggregation(s, f);
    }
}

/// A site's deaggregation by the IM, one row a bin.
fn print_deaggregation(s: &rocking::ops::risk::SiteInfo, f: &rocking::ops::risk::FragilityInfo) {
    let u = f.unit;
    let im = display_name(&f.im);
    println!("  deaggregation by {im}:");
    let ranges: Vec<String> = s.deaggregation.iter().map(|b| b.range_text(u)).collect();
    let width = ranges
        .iter()
        .map(|r| r.chars().count())
        .max()
        .unwrap_or(0)
        .max(im.len() + 4);
    println!(
        "    {:<width$} {:>11}  {:>7}",
        format!("{im} bin"),
        "rate (1/yr)",
        "share"
    );
    for (range, bin) in ranges.iter().zip(&s.deaggregation) {
        println!(
            "    {range:<width$} {:>11}  {:>5.1} %",
            rate(bin.annual_rate),
            100.0 * bin.share
        );
    }
}

fn print_inventory(all: &[Assessment], years: f64) {
    // With --bootstrap, each rate's band over resamples of the records.
    let level = all
        .iter()
        .find_map(|a| a.fragility.bootstrap.as_ref().map(|b| b.level));
    let banded = level.is_some();
    let band_head = match level {
        Some(l) => format!(" {:>21}", format!("{:.0} % band (1/yr)", 100.0 * l)),
        None => String::new(),
    };
    println!(
        "{:<24} {:>5} {:>12}{band_head} {:>14} {:>10}  model",
        "block",
        "site",
        "rate (1/yr)",
        "return (yr)",
        format!("P({years} yr)"),
    );
    for a in all {
        for s in &a.sites {
            let band = match (banded, s.annual_rate_band) {
                (false, _) => String::new(),
                (true, Some([lo, hi])) => {
                    format!(" {:>21}", format!("{} – {}", rate(lo), rate(hi)))
                }
                (true, None) => format!(" {:>21}", "—"),
            };
            println!(
                "{:<24} {:>5} {:>12}{band} {:>14} {:>10.4}  {}",
                a.block.name,
                s.site,
                rate(s.annual_rate),
                s.return_period_years.map_or("∞".into(), super::years),
                s.p_overturn_in_years,
                a.fragility.equation.unwrap_or("regression")
            );
        }
    }
}
