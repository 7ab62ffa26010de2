//! `rocking ims`: the intensity measures of one record.

use std::path::PathBuf;

use anyhow::Context;
use rocking::im::{self, Im, RecordIms, SPECTRAL_DAMPING};
use rocking::records;

/// Intensity measures of one record.
#[derive(Debug, clap::Args)]
#[command(
    long_about = "Intensity measures of one AT2 record: PGA (g), PGV (cm/s) and PGD (cm) by exact \
    integration of the piecewise-linear record from rest (no baseline correction), SA (g, 5 % \
    damping) at 0.05–4 s and any --period, AvgSA (geometric mean of SA over 0.1–2 s), Arias \
    intensity (m/s), CAV (g·s), the 5–95 % significant duration (s), PGV/PGA (s) and the mean \
    period Tm (s, Rathje et al. 1998). Definitions: docs/MODEL.md §14.\n\n\
    With --json, `sa_g` maps each period to its SA; a period's key is the shortest decimal that \
    reads back as the period, never in exponent form, whole seconds with `.0` (0.05, 1.0, \
    0.000001, 1000.0). A period below Δt/250 is refused (the oscillator is rigid: SA is the PGA)."
)]
pub struct Args {
    /// The AT2 file.
    #[arg(long, value_name = "FILE.AT2")]
    record: PathBuf,
    /// A period (s) at which SA is also computed; repeatable.
    #[arg(long = "period", value_name = "s")]
    periods: Vec<f64>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    if let Some(bad) = args.periods.iter().find(|t| !(**t > 0.0 && t.is_finite())) {
        anyhow::bail!("--period {bad}: a period must be a positive number of seconds");
    }
    let (accel, dt) = records::read_samples(&args.record)?;
    let ims = RecordIms::try_of_record(&accel, dt, &args.periods)
        .with_context(|| args.record.display().to_string())?;
    if args.json {
        // Through a JSON value: its keys sorted, as they always were.
        println!("{}", serde_json::to_value(&ims)?);
        return Ok(());
    }
    println!(
        "{} ({} samples at {} s)",
        args.record.display(),
        accel.len(),
        dt
    );
    for (im, v) in ims.iter().filter(|(im, _)| !matches!(im, Im::Sa(_))) {
        println!("  {:<16} {v:>10.4} {}", im.title(), im.unit());
    }
    println!("  SA ({:.0} % damping):", SPECTRAL_DAMPING * 100.0);
    for (t, sa) in ims.spectrum() {
        println!("    T = {:<6} s  {sa:>8.4} g", im::period_text(t));
    }
    Ok(())
}
