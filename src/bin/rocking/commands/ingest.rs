//! `rocking ingest PATH…`: AT2 files → a records table.

use std::path::PathBuf;
use std::time::Instant;

use rocking::stages::ingest::{self, IngestConfig, OnBad, SKIP_BAD_HINT};

/// Read PEER AT2 ground-motion files into a records table (Parquet).
#[derive(Debug, clap::Args)]
#[command(
    long_about = "Read PEER AT2 ground-motion files into a records table (Parquet).\n\n\
    Each PATH is an AT2 file or a folder searched recursively for *.AT2 (any case). The table \
    has one row per record, sorted by record id (the file stem), with the samples, NPTS, DT, \
    PGA, the header lines, the file's SHA-256 and, with --manifest, the manifest's metadata. \
    Any bad file fails the command and nothing is written, unless --skip-bad is given."
)]
pub struct Args {
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

pub fn run(args: Args) -> anyhow::Result<()> {
    let started = Instant::now();
    let no_set = match args.manifest {
        Some(_) => "without a set in the manifest",
        None => "without a set (no --manifest)",
    };
    let config = IngestConfig {
        text: None,
        paths: args.paths,
        manifest: args.manifest,
        out: args.out,
        on_bad: if args.skip_bad {
            OnBad::Skip
        } else {
            OnBad::Refuse(SKIP_BAD_HINT)
        },
    };
    rocking::outpath::check("--out", &config.out, "parquet", &config.inputs())?;
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
    for line in report.warnings() {
        eprintln!("warning: {line}");
    }
    let sets: Vec<String> = report
        .per_set
        .iter()
        .map(|(s, n)| match s {
            None => format!("{n} {no_set}"),
            Some(s) => format!("{n} {s}"),
        })
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
