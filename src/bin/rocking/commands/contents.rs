//! `rocking contents`: FEMA P-58's unanchored contents beside the tool's
//! fragilities of the same blocks in PFV.

use std::path::PathBuf;

use rocking::contents::FEMA_P58;
use rocking::ops::contents::{self, Request, Row};

use super::args::{direct_progress, number};

/// FEMA P-58's bookcases and filing cabinets beside the tool's own
/// fragilities of the same blocks in Peak Floor Velocity.
#[derive(Debug, clap::Args)]
#[command(
    allow_negative_numbers = true,
    long_about = "FEMA P-58's unanchored bookcases and filing cabinets (E.20.22.102a–125a of its \
    component database, as pelicun's DLML carries it: lognormal in Peak Floor Velocity, β = 0.5) \
    beside the tool's fragility of the same rigid blocks (their depth and height from the \
    descriptions, Housner's restitution), in PFV, from their runs under each record set on the \
    ground and under the first set on the roof of modal buildings of the given first-mode \
    periods. Each tool row is that block's one fragility (`fragility --im pfv --direct \
    --if-not-lognormal lognormal`): the paper's fractile fit, a lognormal as FEMA's are."
)]
pub struct Args {
    /// A record set on the ground: NAME=FOLDER of AT2 files, repeatable
    /// [default: the bundled far-field, near-field-pulse and
    /// near-field-no-pulse sets]; the first also shakes the buildings.
    #[arg(long = "set", value_name = "NAME=DIR", value_parser = parse_set)]
    sets: Vec<(String, PathBuf)>,
    /// The buildings' first-mode periods (s), comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        value_parser = number,
        default_value = "0.25,0.5,1,1.5,2"
    )]
    periods: Vec<f64>,
    /// Their damping ratio.
    #[arg(long, default_value_t = 0.05)]
    zeta: f64,
    /// The roof's participation factor × mode shape, Γφ (about 1.3 for a
    /// regular building's first mode).
    #[arg(long, default_value_t = 1.3)]
    gamma_phi: f64,
    /// The linearised model's accepted error in η_c (the model is chosen by it).
    #[arg(long, default_value_t = rocking::ask::block::AUTO_TOL)]
    auto_tol: f64,
    /// Draw the ratio of the medians against the building's period (SVG).
    #[arg(long, value_name = "FILE.svg")]
    plot: Option<PathBuf>,
    /// Print the rows as JSON.
    #[arg(long)]
    json: bool,
}

fn parse_set(text: &str) -> Result<(String, PathBuf), String> {
    match text.split_once('=') {
        Some((name, dir)) if !name.trim().is_empty() && !dir.trim().is_empty() => {
            Ok((name.trim().to_string(), PathBuf::from(dir.trim())))
        }
        _ => Err(format!("`{text}`: give NAME=FOLDER")),
    }
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let sets = if args.sets.is_empty() {
        let root = rocking::ops::fragility::default_records();
        let parent = root.parent().map(PathBuf::from).unwrap_or_default();
        ["far-field", "near-field-pulse", "near-field-no-pulse"]
            .map(|s| (s.to_string(), parent.join(s)))
            .to_vec()
    } else {
        args.sets.clone()
    };
    if let Some(plot) = &args.plot {
        let inputs: Vec<&std::path::Path> = sets.iter().map(|(_, d)| d.as_path()).collect();
        rocking::outpath::check("--plot", plot, "svg", &inputs)?;
    }
    let req = Request {
        sets,
        periods: args.periods.clone(),
        zeta: args.zeta,
        gamma_phi: args.gamma_phi,
        auto_tol: args.auto_tol,
        progress: direct_progress(true),
    };
    let contents::Comparison { rows, warnings } = contents::compare(&req)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    if let Some(plot) = &args.plot {
        let svg = contents::chart(&rows, &req.sets[0].0)?;
        rocking::tables::atomic_write(plot, svg.as_bytes())?;
    }
    if args.json {
        println!("{}", serde_json::to_string(&rows)?);
        return Ok(());
    }
    print_rows(&rows);
    if let Some(plot) = &args.plot {
        println!("wrote {}", plot.display());
    }
    Ok(())
}

fn print_rows(rows: &[Row]) {
    println!(
        "median PFV at overturning (m/s, FEMA P-58's unit; fragility and export state PFV in cm/s) \
         and β: FEMA P-58's, and the tool's from the records' runs (on a roof: a building of first \
         period T, ζ and Γφ as given); b and h are half the width and half the height"
    );
    let mut scenes: Vec<(String, Option<f64>)> = Vec::new();
    for r in rows {
        let key = (r.records.clone(), r.period_s);
        if !scenes.contains(&key) {
            scenes.push(key);
        }
    }
    // Sizes to 0.1 mm: FEMA's inches halved, which a `fragility --b --h`
    // copied from the table takes as they are (0.160 for 0.16034 m moved
    // the median PFV by 2 %).
    print!(
        "{:<14} {:>7} {:>7} {:>11}",
        "item", "b (m)", "h (m)", "FEMA"
    );
    for (set, t) in &scenes {
        let head = match t {
            None => format!("ground {}", short(set)),
            Some(t) => format!("roof T={t}s"),
        };
        print!(" {head:>16}");
    }
    println!();
    for c in &FEMA_P58 {
        print!(
            "{:<14} {:>7.4} {:>7.4} {:>11}",
            c.id.trim_start_matches("E.20.22."),
            c.b_m(),
            c.h_m(),
            format!("{:.3}, {:.2}", c.median_mps, c.beta)
        );
        for key in &scenes {
            let cell = rows
                .iter()
                .find(|r| r.id == c.id && (r.records.clone(), r.period_s) == *key)
                .map_or("—".to_string(), |r| {
                    let flag = if r.lognormal_p.is_some_and(|p| p < 0.05) {
                        "*"
                    } else {
                        ""
                    };
                    format!("{:.3}, {:.2}{flag}", r.median_mps, r.beta)
                });
            print!(" {cell:>16}");
        }
        println!();
    }
    println!("* the records' capacities fail the lognormal check (Lilliefors, 5 %)");
}

/// A set's name, shortened for a column head.
fn short(set: &str) -> String {
    match set {
        "far-field" => "far".into(),
        "near-field-pulse" => "pulse".into(),
        "near-field-no-pulse" => "no-pulse".into(),
        other => other.chars().take(8).collect(),
    }
}
