//! `rocking ims`: the intensity measures of one record.

use std::path::PathBuf;

use rocking::im::{self, Im, SPECTRAL_DAMPING};
use rocking::ops::record_ims::{Measures, MeasuresError};
use rocking::records;

/// Intensity measures of one record.
#[derive(Debug, clap::Args)]
#[command(
    allow_negative_numbers = true,
    long_about = "Intensity measures of one AT2 record: PGA (g), PGV (cm/s) and PGD (cm) by exact \
    integration of the piecewise-linear record from rest (no baseline correction), SA (g, 5 % \
    damping) at 0.05–4 s and any --period, AvgSA (geometric mean of SA over 0.1–2 s), Arias \
    intensity (m/s), CAV (g·s), the 5–95 % significant duration (s), PGV/PGA (s) and the mean \
    period Tm (s, Rathje et al. 1998). Definitions: docs/MODEL.md §14.\n\n\
    With --json, `sa_g` maps each period to its SA; a period's key is the shortest decimal that \
    reads back as the period, never in exponent form, whole seconds with `.0` (0.05, 1.0, \
    0.000001, 1000.0). A period below Δt/250 is refused (the oscillator is rigid: SA is the PGA).\n\n\
    With --pair, the record and the pair's other horizontal component (90° from it, at the same \
    sample step; the shorter taken as 0 after its end) also give the orientation-independent \
    RotD50 and RotD100 of PGA, PGV and SA (Boore 2010: the median and the largest over the \
    angles 0–179° of the rotated component's peak), under `rotd50` and `rotd100` with --json, \
    each keyed as the record's measures are (docs/MODEL.md §18)."
)]
pub struct Args {
    /// The AT2 file.
    #[arg(long, value_name = "FILE.AT2")]
    record: PathBuf,
    /// The pair's other horizontal component (AT2, 90° from --record): adds
    /// RotD50 and RotD100.
    #[arg(long, value_name = "FILE.AT2")]
    pair: Option<PathBuf>,
    /// A period (s) at which SA is also computed; repeatable.
    #[arg(long = "period", value_name = "s")]
    periods: Vec<f64>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let (accel, dt) = records::read_samples(&args.record)?;
    let pair = match &args.pair {
        Some(b) => Some(records::read_samples(b)?),
        None => None,
    };
    let what = match &args.pair {
        Some(b) => format!("{} and {}", args.record.display(), b.display()),
        None => args.record.display().to_string(),
    };
    let measures = Measures::of(
        &accel,
        dt,
        pair.as_ref().map(|(b, b_dt)| (&b[..], *b_dt)),
        &args.periods,
    )
    .map_err(|e| match e {
        MeasuresError::Period(t) => {
            anyhow::anyhow!("--period {t}: a period must be a positive number of seconds")
        }
        e => anyhow::Error::new(e).context(what),
    })?;
    if args.json {
        println!("{}", measures.json());
        return Ok(());
    }
    let (ims, rotd) = (&measures.ims, &measures.rotd);
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
    if let (Some(r), Some(b)) = (&rotd, &args.pair) {
        println!("with {} (the pair, over the angles 0–179°):", b.display());
        println!("  {:<16} {:>10} {:>10}", "", "RotD50", "RotD100");
        println!(
            "  {:<16} {:>10.4} {:>10.4} g",
            "PGA", r.pga_g.d50, r.pga_g.d100
        );
        println!(
            "  {:<16} {:>10.4} {:>10.4} cm/s",
            "PGV", r.pgv_cm_s.d50, r.pgv_cm_s.d100
        );
        for (t, m) in &r.sa_g {
            let name = format!("SA({})", im::period_text(*t));
            println!("  {name:<16} {:>10.4} {:>10.4} g", m.d50, m.d100);
        }
    }
    Ok(())
}
