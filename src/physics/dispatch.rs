//! The CPU dispatch of the event loop: [`Isa`] names the compilations (the
//! x86-64 baseline and x86-64-v3), and the functions here compile the event
//! loop ([`driver::drive`], [`driver::drive_pair`], [`driver::drive_lanes`])
//! with the exact stepper and with the Taylor stepper, once per
//! compilation, and pick one at run time.

use super::driver::{self, Outcome};
use super::history::Observer;
use super::step::{Rocking, Stepper};
use super::{Excitation, RunSpec};

/// Which compilation of the exact stepper's event loop runs. The loop and
/// the stepper are compiled twice, for the x86-64 baseline and for
/// x86-64-v3 (AVX2, FMA, BMI: VEX-encoded three-operand arithmetic),
/// chosen at run time by the CPU's features, so one binary runs on any
/// x86-64 CPU and at its best on those of the last decade. Both do the
/// same IEEE operations in the same order (Rust never fuses a product and
/// a sum unless asked to, and the stepper never asks), so their results
/// are identical to the bit; `tests/physics.rs` holds them equal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Isa {
    /// The x86-64 baseline (SSE2), or any other architecture's default.
    Baseline,
    /// x86-64-v3: AVX2, FMA, BMI1/2, LZCNT, MOVBE.
    V3,
}

impl Isa {
    /// The best compilation this CPU runs: [`Isa::V3`] where it has the
    /// features, unless the environment variable `ROCKING_ISA` is
    /// `baseline` (to compare the two, or to rule the faster one out; any
    /// other value changes nothing). Decided once per process.
    pub fn detected() -> Isa {
        static DETECTED: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *DETECTED.get_or_init(|| {
            let forced = std::env::var_os("ROCKING_ISA").is_some_and(|v| v == "baseline");
            if !forced && Isa::V3.available() {
                Isa::V3
            } else {
                Isa::Baseline
            }
        })
    }

    /// Whether this CPU can run this compilation.
    pub fn available(self) -> bool {
        match self {
            Isa::Baseline => true,
            #[cfg(target_arch = "x86_64")]
            Isa::V3 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
                    && std::arch::is_x86_feature_detected!("bmi1")
                    && std::arch::is_x86_feature_detected!("bmi2")
                    && std::arch::is_x86_feature_detected!("lzcnt")
                    && std::arch::is_x86_feature_detected!("movbe")
                    && std::arch::is_x86_feature_detected!("popcnt")
            }
            #[cfg(not(target_arch = "x86_64"))]
            Isa::V3 => false,
        }
    }
}

/// [`driver::drive`] with a stepper whose methods are `#[inline(always)]`
/// (the exact stepper, the Taylor stepper), compiled for `isa` (see [`Isa`]).
#[inline]
pub(super) fn drive<S: Stepper, O: Observer>(
    exc: &Excitation,
    spec: &RunSpec,
    start: Option<Rocking>,
    limit: f64,
    stepper: &mut S,
    obs: &mut O,
    isa: Isa,
) -> Outcome {
    match isa {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: this function's callers pass `Isa::V3` only where the CPU
        // has its features: `Isa::detected()` (`simulate_from`), or an isa
        // `simulate_on` checked with `Isa::available`.
        Isa::V3 => unsafe { drive_v3(exc, spec, start, limit, stepper, obs) },
        _ => driver::drive(exc, spec, start, limit, stepper, obs),
    }
}

/// [`drive`] compiled for x86-64-v3: the event loop and the stepper's
/// methods are `#[inline(always)]`, so they are compiled into this
/// function, with its features.
///
/// # Safety
/// The CPU must have the features enabled here.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,bmi1,bmi2,fma,lzcnt,movbe,popcnt")]
unsafe fn drive_v3<S: Stepper, O: Observer>(
    exc: &Excitation,
    spec: &RunSpec,
    start: Option<Rocking>,
    limit: f64,
    stepper: &mut S,
    obs: &mut O,
) -> Outcome {
    driver::drive(exc, spec, start, limit, stepper, obs)
}

/// [`driver::drive_pair`] compiled for x86-64-v3, the one
/// compilation with runs in step ([`super::simulate_pair`]).
///
/// # Safety
/// The CPU must have the features enabled here.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,bmi1,bmi2,fma,lzcnt,movbe,popcnt")]
pub(super) unsafe fn drive_pair_v3<S: driver::CruisePair>(
    exc: &Excitation,
    specs: [&RunSpec; 2],
    limits: [f64; 2],
    steppers: [&mut S; 2],
) -> [Outcome; 2] {
    driver::drive_pair(exc, specs, limits, steppers)
}

/// [`driver::drive_lanes`] compiled for x86-64-v3 ([`super::simulate_lanes`]).
///
/// # Safety
/// The CPU must have the features enabled here.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,bmi1,bmi2,fma,lzcnt,movbe,popcnt")]
pub(super) unsafe fn drive_lanes_v3<S: driver::CruiseLanes<N>, const N: usize>(
    exc: &Excitation,
    specs: [&RunSpec; N],
    limits: [f64; N],
    steppers: [&mut S; N],
    present: [bool; N],
) -> [Outcome; N] {
    driver::drive_lanes(exc, specs, limits, steppers, present)
}
