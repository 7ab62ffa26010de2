//! Long calls that Ctrl-C stops. The work runs on a thread of its own, the
//! GIL released, while the calling thread wakes every [`TICK`] to let
//! Python run its signal handlers: on an exception from one (a
//! `KeyboardInterrupt`), every run of the library is asked to stop
//! ([`rocking::physics::interrupt`]), the work ends at its next run, and
//! the exception is raised once it has (nothing is left running behind
//! the notebook's back, and a stage's writes are whole or absent, as on
//! any failure).
//!
//! The library's stop is process-wide, as a signal is, so Ctrl-C in one
//! thread also stops the calls of other threads under way. Python delivers
//! signals to its main thread only: a computation in another thread was
//! never interrupted itself, and when a stop asked for while it ran made it
//! fail, it runs again from its start once the stop is withdrawn (the same
//! answer, runs being deterministic) instead of failing with an
//! interruption nobody asked it for; one that finished is kept. A call
//! starts only once no stop is asked for. A pipeline's run
//! ([`interruptible_once`]) is not run again: its stages resume at its
//! next call, as after any failure. A panic in the work (a fault of the
//! library) is raised as a `RuntimeError` rather than leaving the caller
//! waiting for a result that never comes.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Condvar, Mutex, PoisonError};
use std::time::Duration;

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use rocking::physics::interrupt;

/// How often the caller looks for a signal while the work runs.
const TICK: Duration = Duration::from_millis(50);

/// `work`'s result, the GIL released meanwhile; a signal handler's
/// exception (Ctrl-C's `KeyboardInterrupt`) instead, raised when `work`
/// has stopped. Run again when it failed while another call's
/// interruption stopped every run.
pub fn interruptible<X: Send, E: Send>(
    py: Python<'_>,
    work: impl Fn() -> Result<X, E> + Sync,
) -> PyResult<Result<X, E>> {
    loop {
        let stops = withdrawn(py)?;
        let result = once(py, &work)?;
        if result.is_ok() || interrupt::requests() == stops {
            return Ok(result);
        }
    }
}

/// [`interruptible`] without running again: a pipeline's run, which a
/// stop leaves resumable and whose answer (what ran) a second attempt
/// would change.
pub fn interruptible_once<T: Send>(py: Python<'_>, work: impl Fn() -> T + Sync) -> PyResult<T> {
    withdrawn(py)?;
    once(py, &work)
}

/// Waits while a stop is asked for (another call's Ctrl-C, its work
/// still ending), hearing this thread's own signals; the count of stops
/// asked for so far.
fn withdrawn(py: Python<'_>) -> PyResult<u64> {
    loop {
        // The count before the flag: a stop raises the flag first, so a
        // count read before a stop's flag is seen to be down is that
        // stop's predecessor, and the stop shows as a changed count.
        let stops = interrupt::requests();
        if !interrupt::requested() {
            return Ok(stops);
        }
        py.detach(|| std::thread::sleep(TICK));
        py.check_signals()?;
    }
}

/// One attempt of [`interruptible`].
fn once<T: Send>(py: Python<'_>, work: &(impl Fn() -> T + Sync)) -> PyResult<T> {
    let slot = Mutex::new(None);
    let ready = Condvar::new();
    let outcome = std::thread::scope(|s| {
        s.spawn(|| {
            let value = catch_unwind(AssertUnwindSafe(work));
            *slot.lock().unwrap_or_else(PoisonError::into_inner) = Some(value);
            ready.notify_one();
        });
        let wait = |tick: Option<Duration>| {
            let guard = slot.lock().unwrap_or_else(PoisonError::into_inner);
            let mut guard = match tick {
                Some(t) => {
                    ready
                        .wait_timeout_while(guard, t, |v| v.is_none())
                        .unwrap_or_else(PoisonError::into_inner)
                        .0
                }
                None => ready
                    .wait_while(guard, |v| v.is_none())
                    .unwrap_or_else(PoisonError::into_inner),
            };
            guard.take()
        };
        loop {
            if let Some(value) = py.detach(|| wait(Some(TICK))) {
                return Ok(value);
            }
            if let Err(signal) = py.check_signals() {
                interrupt::request();
                py.detach(|| wait(None));
                interrupt::clear();
                return Err(signal);
            }
        }
    })?;
    outcome.map_err(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".into());
        PyRuntimeError::new_err(format!(
            "a fault of rocking (please report it, with the call that gave it): {what}"
        ))
    })
}
