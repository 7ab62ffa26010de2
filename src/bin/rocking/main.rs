//! The `rocking` command: parse the arguments, run, map errors to an exit code.
//!
//! Argument handling only: each command is one file under `commands/`, and
//! everything it does beyond parsing and printing is a library call. Stage
//! commands (`rocking sweep`, `reduce`, …) are made from the library's stage
//! registry, so a new stage gets its command without a file here.

mod commands;
mod reporter;

fn main() -> std::process::ExitCode {
    // A reader that stops early (`rocking risk … | head`) ends the command
    // quietly, as it ends `cat`: Rust starts with SIGPIPE ignored, so every
    // later print would fail and `println!` panicked with a backtrace.
    #[cfg(unix)]
    // SAFETY: called once, first, before any thread exists; SIG_DFL is a
    // valid action for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    commands::main()
}
