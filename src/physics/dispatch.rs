//! The CPU dispatch of the event loop: [`Isa`] names the compilations (the
//! x86-64 baseline, x86-64-v3 and x86-64-v4), and the functions here
//! compile the event loop ([`driver::drive`], [`driver::drive_pair`],
//! [`driver::drive_lanes`]) with the exact stepper and with the Taylor
//! stepper, once per compilation, and pick one at run time.

use super::driver::{self, Outcome};
use super::history::Observer;
use super::step::{Rocking, Stepper};
use super::{Excitation, RunSpec};

/// Which compilation of the exact and Taylor steppers' event loops runs.
/// The loops and the steppers are compiled three times, for the x86-64
/// baseline, for x86-64-v3 (AVX2, FMA, BMI: VEX-encoded three-operand
/// arithmetic) and for x86-64-v4 (AVX-512: 32 vector registers, EVEX
/// encoding), chosen at run time by the CPU's features, so one binary runs
/// on any x86-64 CPU and at its best on the newest. All do the same IEEE
/// operations in the same order (Rust never fuses a product and a sum
/// unless asked to, and the steppers never ask), so their results are
/// identical to the bit; `tests/physics.rs` holds them equal.
///
/// The lanes are the same width in v3 and v4 (two runs of the exact
/// stepper, up to four of the Taylor stepper: more runs part too often to
/// gain, BENCHMARKS "Where the search's time goes"); what v4 adds is
/// room: the Taylor stepper's four lanes of series keep their terms in
/// registers instead of spilling them.
/// Ordered Baseline < V3 < V4: each runs what the one before it does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Isa {
    /// The x86-64 baseline (SSE2), or any other architecture's default.
    Baseline,
    /// x86-64-v3: AVX2, FMA, BMI1/2, LZCNT, MOVBE.
    V3,
    /// x86-64-v4: x86-64-v3 and AVX-512 F, BW, CD, DQ and VL.
    V4,
}

impl Isa {
    /// The best compilation this CPU runs ([`Isa::V4`], else [`Isa::V3`],
    /// else the baseline), unless the environment variable `ROCKING_ISA`
    /// names a lesser one, `baseline` or `v3` (to compare them, or to rule
    /// a faster one out; another value changes nothing). Decided once per
    /// process.
    pub fn detected() -> Isa {
        static DETECTED: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *DETECTED.get_or_init(|| {
            let cap = match std::env::var("ROCKING_ISA").as_deref() {
                Ok("baseline") => Isa::Baseline,
                Ok("v3") => Isa::V3,
                _ => Isa::V4,
            };
            [Isa::V4, Isa::V3]
                .into_iter()
                .find(|&isa| isa <= cap && isa.available())
                .unwrap_or(Isa::Baseline)
        })
    }

    /// Whether this compilation keeps runs in step (in lanes of AVX
    /// registers): x86-64-v3 and v4.
    pub fn has_lanes(self) -> bool {
        self != Isa::Baseline
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
            #[cfg(target_arch = "x86_64")]
            Isa::V4 => {
                Isa::V3.available()
                    && std::arch::is_x86_feature_detected!("avx512f")
                    && std::arch::is_x86_feature_detected!("avx512bw")
                    && std::arch::is_x86_feature_detected!("avx512cd")
                    && std::arch::is_x86_feature_detected!("avx512dq")
                    && std::arch::is_x86_feature_detected!("avx512vl")
            }
            #[cfg(not(target_arch = "x86_64"))]
            Isa::V3 | Isa::V4 => false,
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
        // SAFETY (both arms): this function's callers pass an isa only
        // where the CPU has its features: `Isa::detected()`
        // (`simulate_from`), or an isa `simulate_on` checked with
        // `Isa::available`.
        #[cfg(target_arch = "x86_64")]
        Isa::V3 => unsafe { drive_v3(exc, spec, start, limit, stepper, obs) },
        #[cfg(target_arch = "x86_64")]
        Isa::V4 => unsafe { drive_v4(exc, spec, start, limit, stepper, obs) },
        _ => driver::drive(exc, spec, start, limit, stepper, obs),
    }
}

/// [`driver::drive_pair`] compiled for `isa`, one with lanes
/// ([`Isa::has_lanes`]; [`super::simulate_pair`]).
///
/// # Safety
/// The CPU must run `isa` ([`Isa::available`]), and `isa` must have lanes.
#[cfg(target_arch = "x86_64")]
#[inline]
pub(super) unsafe fn drive_pair<S: driver::CruisePair>(
    isa: Isa,
    exc: &Excitation,
    specs: [&RunSpec; 2],
    limits: [f64; 2],
    steppers: [&mut S; 2],
) -> [Outcome; 2] {
    match isa {
        Isa::V4 => drive_pair_v4(exc, specs, limits, steppers),
        _ => drive_pair_v3(exc, specs, limits, steppers),
    }
}

/// [`driver::drive_lanes`] compiled for `isa`, one with lanes
/// ([`Isa::has_lanes`]; [`super::simulate_lanes`]).
///
/// # Safety
/// The CPU must run `isa` ([`Isa::available`]), and `isa` must have lanes.
#[cfg(target_arch = "x86_64")]
#[inline]
pub(super) unsafe fn drive_lanes<S: driver::CruiseLanes<N>, const N: usize>(
    isa: Isa,
    exc: &Excitation,
    specs: [&RunSpec; N],
    limits: [f64; N],
    steppers: [&mut S; N],
    present: [bool; N],
) -> [Outcome; N] {
    match isa {
        Isa::V4 => drive_lanes_v4(exc, specs, limits, steppers, present),
        _ => drive_lanes_v3(exc, specs, limits, steppers, present),
    }
}

/// The event loops compiled for one x86-64 level: `$drive`, `$pair`,
/// `$lanes` are [`driver::drive`], [`driver::drive_pair`] and
/// [`driver::drive_lanes`] with `$features` enabled. The event loop and
/// the steppers' methods are `#[inline(always)]`, so they are compiled
/// into these functions, with their features.
macro_rules! compiled_for {
    ($level:literal, $features:literal, $drive:ident, $pair:ident, $lanes:ident) => {
        #[doc = concat!("[`driver::drive`] compiled for ", $level, ".")]
        ///
        /// # Safety
        /// The CPU must have the features enabled here.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $features)]
        unsafe fn $drive<S: Stepper, O: Observer>(
            exc: &Excitation,
            spec: &RunSpec,
            start: Option<Rocking>,
            limit: f64,
            stepper: &mut S,
            obs: &mut O,
        ) -> Outcome {
            driver::drive(exc, spec, start, limit, stepper, obs)
        }

        #[doc = concat!("[`driver::drive_pair`] compiled for ", $level, ".")]
        ///
        /// # Safety
        /// The CPU must have the features enabled here.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $features)]
        unsafe fn $pair<S: driver::CruisePair>(
            exc: &Excitation,
            specs: [&RunSpec; 2],
            limits: [f64; 2],
            steppers: [&mut S; 2],
        ) -> [Outcome; 2] {
            driver::drive_pair(exc, specs, limits, steppers)
        }

        #[doc = concat!("[`driver::drive_lanes`] compiled for ", $level, ".")]
        ///
        /// # Safety
        /// The CPU must have the features enabled here.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $features)]
        unsafe fn $lanes<S: driver::CruiseLanes<N>, const N: usize>(
            exc: &Excitation,
            specs: [&RunSpec; N],
            limits: [f64; N],
            steppers: [&mut S; N],
            present: [bool; N],
        ) -> [Outcome; N] {
            driver::drive_lanes(exc, specs, limits, steppers, present)
        }
    };
}

compiled_for!(
    "x86-64-v3",
    "avx,avx2,bmi1,bmi2,fma,lzcnt,movbe,popcnt",
    drive_v3,
    drive_pair_v3,
    drive_lanes_v3
);
compiled_for!(
    "x86-64-v4",
    "avx,avx2,bmi1,bmi2,fma,lzcnt,movbe,popcnt,avx512f,avx512bw,avx512cd,avx512dq,avx512vl",
    drive_v4,
    drive_pair_v4,
    drive_lanes_v4
);
