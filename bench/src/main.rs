//! `rocking-bench`: the solvers' speed against their error, written into
//! the marked sections of `docs/BENCHMARKS.md` (and the plot beside it).
//! The harness is not part of the library or the wheel: it is this
//! workspace member, run from the repository root with
//! `cargo run --release -p rocking-bench -- [--sections …]`.
//!
//! - [`timing`]: timing helpers (medians of repeated runs, no files);
//! - [`sections`]: one module per section of BENCHMARKS.md.

mod sections;
mod timing;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use rocking::label::Label;
use sections::{BenchOptions, Section};

/// Measure the solvers' speed against their error; write docs/BENCHMARKS.md sections and a plot.
#[derive(Debug, Parser)]
#[command(name = "rocking-bench", version)]
#[command(long_about = "Measure the solvers' speed against their error.\n\n\
    Times the exact linearised stepper, fixed-step RK4 at several step sizes and the nonlinear \
    Dormand–Prince integrator at several tolerances on bundled records and closed-form pulses, \
    compares each with a tight reference, and measures the linearisation error against α \
    (the basis of --model auto). Rewrites the marked sections of BENCHMARKS.md in --out-dir \
    and writes the speed–error plot beside it. Takes a few minutes.")]
pub struct Args {
    /// Folder of the bundled records (with far-field/ inside).
    #[arg(long, default_value = "records/fema-p695")]
    records: PathBuf,
    /// Where BENCHMARKS.md and the plot are written.
    #[arg(long, default_value = "docs")]
    out_dir: PathBuf,
    /// Repetitions per timing (the median is reported).
    #[arg(long, default_value_t = 5)]
    reps: usize,
    /// Fewer cases and settings: a smoke run, not for the record.
    #[arg(long)]
    quick: bool,
    /// The `rocking` binary whose `capacity` command the `calls` section
    /// times per call, process start included (build it first with `cargo
    /// build --release`).
    #[arg(long, default_value = "target/release/rocking")]
    rocking: PathBuf,
    /// The sections to measure (the others keep their text): solvers,
    /// linearisation, criteria, tolerance, rounding, calls (`rocking
    /// capacity` per call, process start included), certified (a certified
    /// nonlinear capacity against the linearised one). Default: all.
    #[arg(long, value_delimiter = ',', value_parser = parse_section)]
    sections: Vec<Section>,
}

fn parse_section(s: &str) -> Result<Section, String> {
    Section::from_label(s)
        .ok_or_else(|| format!("unknown section `{s}`; valid: {}", Section::labels()))
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            for cause in e.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            ExitCode::FAILURE
        }
    }
}

fn run(args: Args) -> anyhow::Result<()> {
    let opts = BenchOptions {
        records: args.records,
        out_dir: args.out_dir,
        reps: args.reps,
        quick: args.quick,
        sections: if args.sections.is_empty() {
            Section::ALL.to_vec()
        } else {
            args.sections
        },
        exe: args.rocking,
    };
    if opts.sections.contains(&Section::Calls) && !opts.exe.is_file() {
        anyhow::bail!(
            "--rocking {}: no such binary; the calls section times it (cargo build --release)",
            opts.exe.display()
        );
    }
    sections::run(&opts, |line| eprintln!("{line}"))?;
    Ok(())
}
