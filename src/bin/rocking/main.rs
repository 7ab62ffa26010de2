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
    #[cfg(unix)]
    // SAFETY: as above; the handler only stores to an atomic and restores
    // the default action, both async-signal-safe. A SIGINT inherited as
    // ignored (`nohup`, a background job of a script) stays ignored.
    unsafe {
        let before = libc::signal(
            libc::SIGINT,
            on_interrupt as extern "C" fn(libc::c_int) as libc::sighandler_t,
        );
        if before == libc::SIG_IGN {
            libc::signal(libc::SIGINT, libc::SIG_IGN);
        }
    }
    commands::main()
}

/// Ctrl-C: every run under way ends and none starts
/// ([`rocking::physics::interrupt`]), so the command fails at its next run
/// with its tables whole or absent and says so; a second Ctrl-C ends the
/// process at once (the default action, restored here), for work that
/// runs no simulation to hear the first.
#[cfg(unix)]
extern "C" fn on_interrupt(_: libc::c_int) {
    rocking::physics::interrupt::request();
    // SAFETY: signal(2) is async-signal-safe; SIG_DFL is a valid action.
    unsafe {
        libc::signal(libc::SIGINT, libc::SIG_DFL);
    }
}
