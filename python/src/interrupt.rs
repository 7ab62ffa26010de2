//! Long calls that Ctrl-C stops. The work runs on a thread of its own, the
//! GIL released, while the calling thread wakes every [`TICK`] to let
//! Python run its signal handlers: on an exception from one (a
//! `KeyboardInterrupt`), every run of the library is asked to stop
//! ([`rocking::physics::interrupt`]), the work ends at its next run, and
//! the exception is raised once it has (nothing is left running behind
//! the notebook's back, and a stage's writes are whole or absent, as on
//! any failure).

use std::sync::{Condvar, Mutex, PoisonError};
use std::time::Duration;

use pyo3::prelude::*;
use rocking::physics::interrupt;

/// How often the caller looks for a signal while the work runs.
const TICK: Duration = Duration::from_millis(50);

/// `work`'s result, the GIL released meanwhile; a signal handler's
/// exception (Ctrl-C's `KeyboardInterrupt`) instead, raised when `work`
/// has stopped.
pub fn interruptible<T: Send>(py: Python<'_>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    let slot = Mutex::new(None);
    let ready = Condvar::new();
    std::thread::scope(|s| {
        s.spawn(|| {
            let value = work();
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
    })
}
