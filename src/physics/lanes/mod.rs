//! Runs in lanes: the numerics that advance several runs at once (the exact
//! stepper's motion and sign tests, the Taylor series) are written once,
//! generic over [`Lanes`], and the lone run is the one-lane case, `f64`
//! itself. [`x86`] has the vector registers: two lanes of SSE2 ([`F2`]),
//! four of AVX ([`F4`]). Every lane does the scalar IEEE operations in the
//! scalar order, so each run's results are the lone run's to the bit.

mod lane;
#[cfg(target_arch = "x86_64")]
#[allow(unused_unsafe)] // the SSE2 intrinsics are safe to call from Rust 1.87 on
mod x86;

pub use lane::{Lane, Lanes, Mask};
#[cfg(target_arch = "x86_64")]
pub use x86::{F2, F4};
