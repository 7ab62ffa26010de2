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
    version = rocking::BUILD,
    about = "Overturning capacity and fragility of free-standing rigid blocks under earthquake records",
    long_about = "Overturning capacity and fragility of free-standing rigid blocks under earthquake records.\n\n\
        A block (statue, cabinet, transformer, server rack) resting on a rigid base rocks about its \
        corners when the ground shakes and may overturn. rocking runs incremental dynamic analysis \
        over a suite of ground-motion records and reduces it to capacity fractiles, a regression \
        and fragility curves, as a pipeline of stages over Parquet tables.",
    after_help = "Each stage reads and writes Parquet tables: their columns are documented in docs/tables.md (at the repository root), which files each command writes and how to query them in outputs/README.md."
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

/// The exit code of a command's result, its error printed with its causes;
/// a command stopped by a signal (Ctrl-C, SIGTERM, SIGHUP) says what it
/// left and ends by that signal (the shell reports 128 + its number: 130
/// for SIGINT, 143 for SIGTERM); stopped by the library's request alone
/// (a test's hook), it exits with 130.
fn exit(result: anyhow::Result<()>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if rocking::physics::interrupt::requested() => {
            // An error of its own (a full disk) is said too: a stopped
            // run's reads "interrupted" however it was wrapped.
            if !format!("{e:#}").contains("interrupted") {
                print_error(&e);
            }
            let (code, name) = crate::signals::stopped_by().unwrap_or((130, "Ctrl-C"));
            eprintln!("{}", interrupted(name));
            crate::signals::end_by_it();
            ExitCode::from(code)
        }
        Err(e) => {
            print_error(&e);
            ExitCode::FAILURE
        }
    }
}

/// An error with its causes, on standard error.
fn print_error(e: &anyhow::Error) {
    eprintln!("error: {e}");
    for cause in e.chain().skip(1) {
        eprintln!("  caused by: {cause}");
    }
}

/// What a command stopped by the signal `name` prints.
fn interrupted(name: &str) -> String {
    format!(
        "interrupted ({name}): every file written is whole and nothing is half-written; a \
         study's sweep keeps the chunks it finished, and the same command resumes from them"
    )
}

/// A number of a printed table in `width` columns: four decimals, or four
/// significant digits in scientific form where four decimals would print
/// hundreds of digits or nothing but zeros (a level of 1e300 g, a rate of
/// 1e-12).
pub(crate) fn cell(v: f64, width: usize) -> String {
    let tiny_or_huge = v != 0.0 && v.is_finite() && !(1e-4..1e9).contains(&v.abs());
    match tiny_or_huge {
        true => format!("{v:>width$.3e}"),
        false => format!("{v:>width$.4}"),
    }
}

/// A return period (years) as printed: whole years, or four significant
/// digits in scientific form where that would print hundreds of digits or
/// 0 (a rate of 1e-300 or 1e300 a year).
pub(crate) fn years(t: f64) -> String {
    match t.is_finite() && !(1.0..1e9).contains(&t) {
        true => format!("{t:.3e}"),
        false => format!("{t:.0}"),
    }
}

#[cfg(test)]
mod tests {
    use super::{cell, years};

    #[test]
    fn return_periods_print_whole_years_or_four_digits() {
        assert_eq!(years(475.2), "475");
        assert_eq!(years(1e-300), "1.000e-300");
        assert_eq!(years(2.5e300), "2.500e300");
        assert_eq!(years(0.25), "2.500e-1");
    }

    #[test]
    fn cells_keep_their_width_at_any_magnitude() {
        assert_eq!(cell(0.3, 10), "    0.3000");
        assert_eq!(cell(0.0, 10), "    0.0000");
        assert_eq!(cell(1e300, 10), " 1.000e300");
        assert_eq!(cell(2.186689e-301, 12), "  2.187e-301");
        assert_eq!(cell(123456.0, 10), "123456.0000");
        assert_eq!(cell(f64::INFINITY, 6), "   inf");
    }
}
