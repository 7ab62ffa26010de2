//! The commands: one file each (cargo's `src/bin/cargo/commands/`), wired
//! by one line in [`Command`] and one in [`dispatch`]. Stage commands come
//! from the library's registry ([`stage`]).

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

mod args;
mod capacity;
mod contents;
mod events;
mod export;
mod fragility;
mod ims;
mod ingest;
mod reference;
mod risk;
mod run;
mod simulate;
mod stage;
mod states;
mod status;
mod submit;
mod tree;
mod wall;

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
    after_help = "Each stage reads and writes Parquet tables: their columns are documented in the README's \"Tables\" section (README.md at the repository root), which files each command writes and how to query them in outputs/README.md."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    Ingest(ingest::Args),
    Ims(ims::Args),
    Simulate(simulate::Args),
    Capacity(capacity::Args),
    Wall(wall::Args),
    Fragility(fragility::Args),
    Risk(risk::Args),
    Export(export::Args),
    Contents(contents::Args),
    Run(run::Args),
    Status(status::Args),
    Submit(submit::Args),
    #[command(hide = true)]
    Reference(reference::Args),
}

fn dispatch(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Ingest(a) => ingest::run(a),
        Command::Ims(a) => ims::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Capacity(a) => capacity::run(a),
        Command::Wall(a) => wall::run(a),
        Command::Fragility(a) => fragility::run(a),
        Command::Risk(a) => risk::run(a),
        Command::Export(a) => export::run(a),
        Command::Contents(a) => contents::run(a),
        Command::Run(a) => run::run(a),
        Command::Status(a) => status::run(a),
        Command::Submit(a) => submit::run(a),
        Command::Reference(a) => reference::run(a, full_command()),
    }
}

/// The whole command tree: the commands, and one per stage that has one.
fn full_command() -> clap::Command {
    stage::augment(run::describe(Cli::command()))
}

/// Parses the command line, runs the command, prints errors with their causes.
pub fn main() -> ExitCode {
    let matches = full_command().get_matches();
    let result = match stage::matching(&matches) {
        Some((stage, sub)) => stage::run(stage, sub),
        None => match Cli::from_arg_matches(&matches) {
            Ok(cli) => dispatch(cli.command),
            Err(e) => e.exit(),
        },
    };
    exit(result)
}

/// The exit code of a command's result, its error printed with its causes.
fn exit(result: anyhow::Result<()>) -> ExitCode {
    match result {
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
