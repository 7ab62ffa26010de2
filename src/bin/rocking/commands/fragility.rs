//! `rocking fragility`: P(overturn | PGA) of a real block.

use rocking::ops::fragility::{self, Request};

use rocking::block::Restitution;

use super::args::{parse_restitution, LawArgs};

/// Probability that a real block overturns at given PGAs.
#[derive(Debug, clap::Args)]
#[command(
    allow_negative_numbers = true,
    long_about = "Probability that a real block overturns at given peak ground accelerations.\n\n\
    P(overturn | PGA) = Φ((ln η_c,50 − ln η)/β), η = αg/PGA, with the capacity fractiles from the \
    paper's regression (--from paper, the default) or a pipeline's own fit (--from PIPELINE.toml). \
    --direct also runs the block through a record suite (the pipeline's, or the bundled far-field \
    set) and prints the share of records whose capacity it exceeds at each PGA."
)]
pub struct Args {
    /// Half-width of the block (m).
    #[arg(long, value_name = "m")]
    b: f64,
    /// Half-height of the block (m).
    #[arg(long, value_name = "m")]
    h: f64,
    /// Coefficient of restitution, or `housner` for 1 − 1.5 sin²α.
    #[arg(long, default_value = "housner", value_parser = parse_restitution)]
    eps: Restitution,
    /// Peak ground accelerations (g), comma-separated.
    #[arg(long, value_name = "g[,g…]", value_delimiter = ',', required = true)]
    pga: Vec<f64>,
    #[command(flatten)]
    law: LawArgs,
    /// Also run the block through the record suite and report the empirical fraction.
    #[arg(long)]
    direct: bool,
    /// The linearised model's accepted error in η_c; a block whose α exceeds it is flagged.
    #[arg(long, default_value_t = 0.01)]
    auto_tol: f64,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let req = Request {
        b_m: args.b,
        h_m: args.h,
        eps: args.eps,
        pga_g: args.pga.clone(),
        from: args.law.source(),
        direct: args.direct,
        auto_tol: args.auto_tol,
    };
    let a = fragility::assess(&req)?;
    for w in &a.warnings {
        eprintln!("warning: {w}");
    }
    if args.json {
        println!("{}", serde_json::to_string(&a)?);
        return Ok(());
    }
    println!(
        "block of half-width b = {} m, half-height h = {} m: α = {:.4} rad, p = {:.4} 1/s, ε = {:.4}; capacity from {}: median η_c = {:.4} (PGA {:.3} g), β = {:.3}",
        a.b_m, a.h_m, a.alpha_rad, a.p, a.eps, a.source, a.eta_c_median, a.alpha_rad / a.eta_c_median, a.beta
    );
    let direct = a.records.is_some();
    if let (Some(n), Some(m)) = (a.records, &a.model) {
        println!(
            "--direct: {n} records run with the {m}; the last column is the share of them \
             whose capacity the PGA exceeds"
        );
    }
    println!(
        "{:>10} {:>10} {:>14}{}",
        "PGA (g)",
        "η",
        "P(overturn)",
        if direct { "  share overturned" } else { "" }
    );
    for pt in &a.points {
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
