//! `rocking <stage> PIPELINE.toml`: one command per registered stage that
//! has one (sweep, convergence, reduce, fit, report), made from the
//! library's registry. It runs the stale stages it reads from (found from
//! the stages' declared inputs and outputs), then the stage itself if it is
//! stale (`--force`: always), through the same fingerprints and lock as
//! `rocking run`.

use std::path::PathBuf;

use clap::{Arg, ArgAction, ArgMatches, Command};
use rocking::stages::engine::{self, Force, Outcome, RunOptions, Target};
use rocking::stages::{Shard, Stage, Study, STAGES};

use crate::reporter::Terminal;

/// Adds a subcommand for every stage that has one.
pub fn augment(cli: Command) -> Command {
    STAGES
        .iter()
        .filter(|s| s.has_command())
        .fold(cli, |cli, s| cli.subcommand(command(*s)))
}

fn command(stage: &'static dyn Stage) -> Command {
    let mut cmd = Command::new(stage.name())
        .about(stage.about())
        .long_about(format!(
            "{}.\n\nRuns the stale stages whose outputs `{name}` reads, then `{name}` if its inputs, \
             settings or outputs changed since it last succeeded here (the same fingerprints as \
             `rocking run`; `rocking status` shows them). Tables go to <outputs>/<pipeline name>/.",
            stage.about(),
            name = stage.name()
        ))
        .arg(
            Arg::new("pipeline")
                .value_name("PIPELINE.toml")
                .required(true)
                .value_parser(clap::value_parser!(PathBuf))
                .help("The pipeline file"),
        )
        .arg(
            Arg::new("outputs")
                .long("outputs")
                .default_value("outputs")
                .value_parser(clap::value_parser!(PathBuf))
                .help("Root of the outputs; the tables are in <outputs>/<pipeline name>/"),
        )
        .arg(
            Arg::new("force")
                .long("force")
                .action(ArgAction::SetTrue)
                .help("Run this stage even if it is fresh"),
        )
        .arg(
            Arg::new("threads")
                .long("threads")
                .value_parser(clap::value_parser!(usize))
                .help("Worker threads (default: one per core)"),
        );
    if stage.shardable() {
        cmd = cmd.arg(
            Arg::new("shard")
                .long("shard")
                .value_name("K/N")
                .value_parser(|s: &str| s.parse::<Shard>())
                .help(
                    "Run only the K-th of N deterministic parts (1 ≤ K ≤ N), for batch arrays; \
                     the later stages read the N shard tables as one",
                ),
        );
    }
    cmd
}

/// The stage a parsed command line names, if it names one.
pub fn matching(matches: &ArgMatches) -> Option<(&'static dyn Stage, &ArgMatches)> {
    let (name, sub) = matches.subcommand()?;
    let stage = engine::find(name).filter(|s| s.has_command())?;
    Some((stage, sub))
}

pub fn run(stage: &'static dyn Stage, m: &ArgMatches) -> anyhow::Result<()> {
    let pipeline = m.get_one::<PathBuf>("pipeline").expect("required");
    let outputs = m.get_one::<PathBuf>("outputs").expect("has a default");
    let study = Study::load(pipeline, outputs)?;
    let opts = RunOptions {
        target: Target::For(stage),
        force: if m.get_flag("force") {
            Force::Target
        } else {
            Force::Nothing
        },
        shard: if stage.shardable() {
            m.get_one::<Shard>("shard").copied()
        } else {
            None
        },
        threads: m.get_one::<usize>("threads").copied(),
        command: super::run::command_line(),
    };
    let results = engine::run(&study, &opts, &Terminal::new())?;
    for r in &results {
        if let Outcome::Ran { lines, .. } = &r.outcome {
            for line in lines {
                println!("{line}");
            }
        }
    }
    if let Some(last) = results.last() {
        if matches!(last.outcome, Outcome::Skipped(_)) && last.stage == stage.name() {
            println!(
                "{}: up to date (nothing it reads has changed) in {}",
                stage.name(),
                study.dir.display()
            );
        }
    }
    Ok(())
}
