//! The `rocking` command: parse the arguments, run, map errors to an exit code.
//!
//! Argument handling only: each command is one file under `commands/`, and
//! everything it does beyond parsing and printing is a library call. Stage
//! commands (`rocking sweep`, `reduce`, …) are made from the library's stage
//! registry, so a new stage gets its command without a file here.

mod commands;
mod reporter;
mod signals;

fn main() -> std::process::ExitCode {
    signals::install();
    commands::main()
}
