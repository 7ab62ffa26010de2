//! A request to stop every run under way, for a front end that hears an
//! interrupt (Ctrl-C in Python, where the work runs without the GIL and no
//! signal reaches it): while it is raised, each run refuses to start
//! ([`crate::physics::PhysicsError::Interrupted`]), so a search, a sweep or
//! a batch ends at its next run with that error, which every caller already
//! passes up; runs in step start none. Process-wide, as a signal is: a
//! request stops every computation of the process, whichever thread asked
//! for it, until [`clear`].

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// How many stops have been asked for since the process started.
static REQUESTS: AtomicU64 = AtomicU64::new(0);

/// Asks every run from now on to refuse to start.
pub fn request() {
    // The flag first, then the count: a reader of the count, then the
    // flag, never misses both (see the Python binding's `withdrawn`).
    REQUESTED.store(true, Ordering::SeqCst);
    REQUESTS.fetch_add(1, Ordering::SeqCst);
}

/// How many stops have been asked for so far: a computation that finds
/// the count changed while it ran may have been stopped by another's.
pub fn requests() -> u64 {
    REQUESTS.load(Ordering::SeqCst)
}

/// Withdraws the request: runs start again.
pub fn clear() {
    REQUESTED.store(false, Ordering::Release);
}

/// Whether a stop has been asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}
