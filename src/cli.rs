//! Command-line interface: the only module that knows clap.
//!
//! Parses the arguments into a stage configuration, runs the stage and
//! presents its report. Errors are printed as `error: …` with their causes
//! and give exit code 1; usage errors are clap's (exit code 2).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand};

use crate::stages::ingest::{self, IngestConfig};

#[derive(Debug, Parser)]
#[command(
    name = "rocking",
    version,
    about = "Overturning capacity and fragility of free-standing rigid blocks under earthquake records",
    long_about = "Overturning capacity and fragility of free-standing rigid blocks under earthquake records.\n\n\
        A block (statue, cabinet, transformer, server rack) resting on a rigid base rocks about its \
        corners when the ground shakes and may overturn. rocking runs incremental dynamic analysis \
        over a suite of ground-motion records and reduces it to capacity fractiles, a regression \
        and fragility curves, as a pipeline of stages over Parquet tables.",
    after_help = "Each stage reads and writes Parquet tables documented in outputs/README.md."
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Read PEER AT2 ground-motion files into a records table (Parquet).
    #[command(
        long_about = "Read PEER AT2 ground-motion files into a records table (Parquet).\n\n\
        Each PATH is an AT2 file or a folder searched recursively for *.AT2 (any case). The table \
        has one row per record, sorted by record id (the file stem), with the samples, NPTS, DT, \
        PGA, the header lines, the file's SHA-256 and, with --manifest, the manifest's metadata. \
        Any bad file fails the command and nothing is written, unless --skip-bad is given."
    )]
    Ingest(IngestArgs),
}

#[derive(Debug, clap::Args)]
struct IngestArgs {
    /// AT2 files, or folders to search recursively for *.AT2.
    #[arg(required = true, value_name = "PATH")]
    paths: Vec<PathBuf>,
    /// Where to write the records table.
    #[arg(
        long,
        value_name = "FILE.parquet",
        default_value = "outputs/records.parquet"
    )]
    out: PathBuf,
    /// CSV of per-record metadata with a `file` column (path relative to the CSV),
    /// matched to the AT2 files by file stem; NPTS and DT are checked against it.
    #[arg(long, value_name = "CSV")]
    manifest: Option<PathBuf>,
    /// Ingest the good files and list the bad ones instead of failing.
    #[arg(long)]
    skip_bad: bool,
}

/// Entry point of the binary.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
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

fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Ingest(args) => run_ingest(args),
    }
}

fn run_ingest(args: IngestArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let config = IngestConfig {
        paths: args.paths,
        manifest: args.manifest,
        out: args.out,
        skip_bad: args.skip_bad,
    };
    let report = ingest::run(&config)?;
    for b in &report.skipped {
        eprintln!("skipped: {b}");
    }
    if !report.ignored_manifest_columns.is_empty() {
        eprintln!(
            "warning: manifest columns not stored: {}",
            report.ignored_manifest_columns.join(", ")
        );
    }
    if !report.not_in_manifest.is_empty() {
        eprintln!(
            "warning: {} record(s) not in the manifest (their metadata columns are empty): {}",
            report.not_in_manifest.len(),
            report.not_in_manifest.join(", ")
        );
    }
    let sets: Vec<String> = report
        .per_set
        .iter()
        .map(|(s, n)| format!("{s} {n}"))
        .collect();
    println!(
        "ingested {} records ({} samples; {}) into {} in {:.2} s{}",
        report.records,
        report.samples,
        sets.join(", "),
        report.out.display(),
        started.elapsed().as_secs_f64(),
        if report.skipped.is_empty() {
            String::new()
        } else {
            format!("; skipped {} bad file(s)", report.skipped.len())
        }
    );
    Ok(())
}
