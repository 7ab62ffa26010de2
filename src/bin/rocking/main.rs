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
    // SAFETY: as above; the handler only stores to atomics and restores the
    // default action, both async-signal-safe. A signal inherited as ignored
    // (`nohup`, a background job of a script) stays ignored.
    unsafe {
        for signal in STOP_SIGNALS {
            let before = libc::signal(
                signal,
                on_stop as extern "C" fn(libc::c_int) as libc::sighandler_t,
            );
            if before == libc::SIG_IGN {
                libc::signal(signal, libc::SIG_IGN);
            }
        }
    }
    commands::main()
}

/// The signals that ask a command to stop: Ctrl-C (SIGINT), and what a
/// scheduler or a closing terminal sends (SIGTERM: Slurm's time limit,
/// preemption and `scancel`; SIGHUP).
#[cfg(unix)]
const STOP_SIGNALS: [libc::c_int; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];

/// The signal that stopped the command (0: none).
static STOPPED_BY: std::sync::atomic::AtomicI32 = std::sync::atomic::AtomicI32::new(0);

/// The signal that asked the command to stop, if one did: the exit code
/// the shell gives a process it ends (128 + its number) and its name.
pub(crate) fn stopped_by() -> Option<(u8, &'static str)> {
    let signal = STOPPED_BY.load(std::sync::atomic::Ordering::Acquire);
    #[cfg(unix)]
    let name = match signal {
        libc::SIGTERM => "SIGTERM",
        libc::SIGHUP => "SIGHUP",
        _ => "Ctrl-C",
    };
    #[cfg(not(unix))]
    let name = "Ctrl-C";
    (signal != 0).then(|| (128 + signal as u8, name))
}

/// A stop signal: every run under way ends and none starts
/// ([`rocking::physics::interrupt`]), so the command fails at its next run
/// with its tables whole or absent (a sweep keeps the chunks it finished,
/// which a requeued task resumes from) and says so; the same signal again
/// ends the process at once (the default action, restored here), for work
/// that runs no simulation to hear the first.
#[cfg(unix)]
extern "C" fn on_stop(signal: libc::c_int) {
    let _ = STOPPED_BY.compare_exchange(
        0,
        signal,
        std::sync::atomic::Ordering::AcqRel,
        std::sync::atomic::Ordering::Acquire,
    );
    rocking::physics::interrupt::request();
    // SAFETY: signal(2) is async-signal-safe; SIG_DFL is a valid action.
    unsafe {
        libc::signal(signal, libc::SIG_DFL);
    }
}
