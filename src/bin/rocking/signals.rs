//! The signals that stop a command: Ctrl-C (SIGINT), and what a scheduler
//! or a closing terminal sends (SIGTERM: Slurm's time limit, preemption and
//! `scancel`, `timeout`, `docker stop`; SIGHUP).
//!
//! The first such signal asks every run to stop
//! ([`rocking::physics::interrupt`]): a sweep saves the chunks it finished
//! and the command fails at its next run with its tables whole or absent,
//! says so, and ends by the same signal (its default action, re-raised), as
//! a shell and a scheduler expect of a process a signal stopped. Work that
//! runs no simulation does not hear the request: a watch ends the process
//! by the signal [`GRACE`] after it, and the same signal again ends it at
//! once; such work that ends within the grace exits as it ends (0 when it
//! succeeds: its files are whole). After SIGHUP the terminal is gone, and
//! the output that went to it goes to /dev/null rather than failing (a
//! print to a hung-up terminal panics); output to a file or a pipe goes on
//! there.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::time::Duration;

/// How long a command may take to stop after the first signal before the
/// watch ends it: ample for a sweep to save its finished chunks (0.3 s on
/// the paper sweep), well inside what schedulers wait before SIGKILL
/// (Slurm's KillWait 30 s, `docker stop` 10 s).
pub const GRACE: Duration = Duration::from_secs(5);

/// The signal that stopped the command (0: none).
static STOPPED_BY: AtomicI32 = AtomicI32::new(0);

/// Whether standard output and standard error are a terminal (read once,
/// at start: the handler may only redirect those).
static TERMINAL: [AtomicBool; 2] = [AtomicBool::new(false), AtomicBool::new(false)];

/// Installs the handlers (a signal inherited as ignored, under `nohup` or
/// as a script's background job, stays ignored) and the watch.
pub fn install() {
    #[cfg(unix)]
    // SAFETY: called once, first, before any other thread exists; the
    // handler does only async-signal-safe things (atomics, open, dup2,
    // signal).
    unsafe {
        TERMINAL[0].store(libc::isatty(1) == 1, Ordering::Release);
        TERMINAL[1].store(libc::isatty(2) == 1, Ordering::Release);
        // A reader that stops early (`rocking risk … | head`) ends the
        // command quietly, as it ends `cat`: Rust starts with SIGPIPE
        // ignored, so every later print would fail and `println!` panicked.
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            let before = libc::signal(
                signal,
                on_stop as extern "C" fn(libc::c_int) as libc::sighandler_t,
            );
            if before == libc::SIG_IGN {
                libc::signal(signal, libc::SIG_IGN);
            }
        }
    }
    #[cfg(unix)]
    let _ = std::thread::Builder::new()
        .name("stop-watch".into())
        .spawn(watch);
}

/// The signal that asked the command to stop, if one did: the exit code
/// the shell gives a process it ends (128 + its number) and its name.
pub fn stopped_by() -> Option<(u8, &'static str)> {
    let signal = STOPPED_BY.load(Ordering::Acquire);
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

/// Ends the process by the signal that stopped it (its default action,
/// restored by the handler), output flushed; returns where none did.
pub fn end_by_it() {
    use std::io::Write;
    let _ = std::io::stdout().flush();
    let _ = std::io::stderr().flush();
    #[cfg(unix)]
    raise();
}

/// Raises the signal that stopped the command, with its default action:
/// it ends the process as that signal does (returns where none did, or
/// where the process ignores it).
#[cfg(unix)]
fn raise() {
    let signal = STOPPED_BY.load(Ordering::Acquire);
    if signal != 0 {
        // SAFETY: signal(2) with SIG_DFL and raise(3) are always valid.
        unsafe {
            libc::signal(signal, libc::SIG_DFL);
            libc::raise(signal);
        }
    }
}

#[cfg(unix)]
extern "C" fn on_stop(signal: libc::c_int) {
    let _ = STOPPED_BY.compare_exchange(0, signal, Ordering::AcqRel, Ordering::Acquire);
    rocking::physics::interrupt::request();
    // SAFETY: open(2), dup2(2), close(2) and signal(2) are async-signal-safe;
    // the path is a NUL-terminated literal; SIG_DFL is a valid action;
    // errno is restored for the code the signal interrupted.
    unsafe {
        #[cfg(target_os = "linux")]
        let errno = *libc::__errno_location();
        if signal == libc::SIGHUP {
            let null = libc::open(c"/dev/null".as_ptr(), libc::O_WRONLY);
            if null >= 0 {
                for fd in [1, 2] {
                    if TERMINAL[fd as usize - 1].load(Ordering::Acquire) {
                        libc::dup2(null, fd);
                    }
                }
                libc::close(null);
            }
        }
        libc::signal(signal, libc::SIG_DFL);
        #[cfg(target_os = "linux")]
        {
            *libc::__errno_location() = errno;
        }
    }
}

/// Waits for a stop; a command still running [`GRACE`] after it is ended
/// by the signal, saying so (stdout is not flushed: a reader that stopped
/// reading must not hold the end up). Where the signal cannot end it (the
/// first process of a container ignores signals' default actions), it
/// exits with the shell's code for the signal.
#[cfg(unix)]
fn watch() {
    while STOPPED_BY.load(Ordering::Acquire) == 0 {
        std::thread::sleep(Duration::from_millis(50));
    }
    std::thread::sleep(GRACE);
    let Some((code, name)) = stopped_by() else {
        return;
    };
    eprintln!(
        "interrupted ({name}): the work under way did not stop within {} s; ended \
         now (every file written is whole; one being written is left as a temporary file, \
         which the next run removes)",
        GRACE.as_secs()
    );
    raise();
    // SAFETY: _exit(2) ends the process where the signal did not.
    unsafe { libc::_exit(i32::from(code)) }
}
