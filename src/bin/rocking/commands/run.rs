//! `rocking run`: the whole study, each stage only when stale.

use std::time::Instant;

use rocking::stages::engine::{self, Outcome, RunOptions, StageResult};
use rocking::stages::{Stage, Study};

use super::args::PipelineArgs;
use crate::reporter::Terminal;

/// Run a whole pipeline, skipping fresh stages (help texts made by `describe`).
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pipeline: PipelineArgs,
    /// Rerun every stage.
    #[arg(long)]
    force: bool,
    /// Rerun this stage and every later one (a stage name; see --help).
    #[arg(long, value_name = "STAGE", value_parser = parse_stage)]
    from: Option<&'static dyn Stage>,
    /// Stop after this stage (a stage name; see --help).
    #[arg(long, value_name = "STAGE", value_parser = parse_stage)]
    to: Option<&'static dyn Stage>,
    /// Worker threads (default: one per core).
    #[arg(long)]
    threads: Option<usize>,
}

/// Sets `rocking run`'s help from the stage registry, so that it lists the
/// stages there are.
pub fn describe(cli: clap::Command) -> clap::Command {
    let order = engine::names().replace(", ", " → ");
    cli.mut_subcommand("run", |c| {
        c.about(format!(
            "Run a whole pipeline: {order}, skipping fresh stages"
        ))
        .long_about(format!(
            "Run a whole pipeline: {order}.\n\n\
                 A stage is skipped when its fingerprint (hashes of its resolved settings, of its \
                 input files' contents, of the tool's version; never file times) matches the one \
                 saved when it last succeeded and its outputs (tables, figures, report) are there \
                 unchanged; otherwise the log says why it reruns. Writes every table, the figures \
                 (<outputs>/<name>/figures/*.svg) and report.md. One writer per output folder at a \
                 time (a lock file). Stages: {}.",
            engine::names()
        ))
    })
}

pub fn parse_stage(s: &str) -> Result<&'static dyn Stage, String> {
    engine::find(s).ok_or_else(|| format!("unknown stage `{s}`; valid: {}", engine::names()))
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let started = Instant::now();
    let study = args.pipeline.study()?;
    let opts = RunOptions::run(args.to, args.from, args.force, args.threads, command_line());
    let results = engine::run(&study, &opts, &Terminal::new())?;
    print_results(&study, &results, started);
    Ok(())
}

/// The command line as typed, for the lock file.
pub fn command_line() -> String {
    std::env::args().collect::<Vec<_>>().join(" ")
}

/// Each stage that ran, its time, and where the report is.
fn print_results(study: &Study, results: &[StageResult], started: Instant) {
    let ran: Vec<(&str, f64)> = results
        .iter()
        .filter_map(|r| match &r.outcome {
            Outcome::Ran { seconds, .. } => Some((r.stage, *seconds)),
            Outcome::Skipped(_) => None,
        })
        .collect();
    if ran.is_empty() {
        println!(
            "nothing to do: every stage of `{}` is up to date ({})",
            study.plan.name,
            study.dir.display()
        );
        return;
    }
    for (stage, seconds) in &ran {
        println!("{stage:<12} {seconds:.2} s");
    }
    // The headline results, as each stage marks them.
    for r in results {
        if let Outcome::Ran {
            lines, headline, ..
        } = &r.outcome
        {
            for line in &lines[..(*headline).min(lines.len())] {
                println!("{}: {line}", r.stage);
            }
        }
    }
    let names: Vec<&str> = ran.iter().map(|r| r.0).collect();
    // The report only when this run covered it (ran, or found it fresh):
    // `--to sweep` leaves none, or one of an earlier state.
    let html = study.path(rocking::stages::report::HTML);
    let report = if results
        .iter()
        .any(|r| r.stage == rocking::stages::report::Report.name())
        && html.exists()
    {
        format!("; report: {} (and report.md beside it)", html.display())
    } else {
        String::new()
    };
    println!(
        "ran {} in {:.1} s{report}",
        names.join(", "),
        started.elapsed().as_secs_f64(),
    );
}
