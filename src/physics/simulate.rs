//! The public entry points of a run ([`simulate`] and its variants): they
//! check the run, pick the compilation of the event loop ([`Isa`]), build
//! the integrator's steppers (the one place that does: a lone run in
//! `drive`, runs in step in [`simulate_pair`] and [`simulate_lanes`]) and
//! hand them to the driver.

use super::dispatch::{self, Isa};
use super::driver::{self, Outcome};
use super::equation::{Equation, LinearRhs, NonlinearRhs};
use super::error::PhysicsError;
use super::exact::{self, Exact};
use super::excitation::Excitation;
use super::history::Observer;
use super::integrator::Integrator;
#[cfg(target_arch = "x86_64")]
use super::integrator::Model;
use super::interrupt;
use super::run::RunSpec;
use super::step::Rocking;
use super::taylor::{self, Taylor};
use super::{dp5, rk4};

/// Runs one record at one intensity.
pub fn simulate(exc: &Excitation, spec: &RunSpec) -> Result<Outcome, PhysicsError> {
    simulate_observed(exc, spec, &mut ())
}

/// [`simulate`], reporting history points to `obs`.
pub fn simulate_observed(
    exc: &Excitation,
    spec: &RunSpec,
    obs: &mut impl Observer,
) -> Result<Outcome, PhysicsError> {
    simulate_from(exc, spec, None, obs)
}

/// [`simulate_observed`] from a given rocking state at the first sample
/// (`None`: at rest, the normal start). Used for free-rocking checks.
pub fn simulate_from(
    exc: &Excitation,
    spec: &RunSpec,
    start: Option<Rocking>,
    obs: &mut impl Observer,
) -> Result<Outcome, PhysicsError> {
    run(exc, spec, start, obs, Isa::detected())
}

/// Runs that differ in η alone (for the Taylor stepper, in its tolerance
/// too), as many of them, from the first, as the integrator keeps in step
/// on this CPU: two for the exact stepper ([`simulate_pair`]), two to four
/// for the Taylor stepper ([`simulate_lanes`]). Their outcomes, each the
/// one [`simulate`] gives it alone, to the bit, in the order of `specs`;
/// empty where none can be run in step (one spec, another integrator,
/// specs that differ in more, a CPU without x86-64-v3). The caller runs
/// the rest as it wishes: it need not know the width.
pub fn simulate_in_step(exc: &Excitation, specs: &[RunSpec]) -> Vec<Outcome> {
    let Some(first) = specs.first() else {
        return Vec::new();
    };
    let width = match first.model.integrator {
        Integrator::Exact => 2,
        Integrator::Taylor { .. } => 4,
        _ => 1,
    };
    let specs = &specs[..specs.len().min(width)];
    match specs {
        [_] | [] => Vec::new(),
        [a, b] => simulate_pair(exc, [a, b])
            .map(Vec::from)
            .unwrap_or_default(),
        more => simulate_lanes(exc, more).unwrap_or_default(),
    }
}

/// Two runs that differ in η alone (a chaos probe's pair; for the Taylor
/// stepper, in its tolerance too), run in step
/// (`driver::drive_pair`: their eventless intervals cost little more than
/// one run's), each with the outcome [`simulate`] gives it, to the bit.
/// `None` where they cannot be: an integrator other than the exact and
/// Taylor steppers, specs that differ in more or that [`simulate`]
/// refuses, or a CPU without the steppers' x86-64-v3 compilation (run them
/// one by one there).
pub fn simulate_pair(exc: &Excitation, specs: [&RunSpec; 2]) -> Option<[Outcome; 2]> {
    #[cfg(target_arch = "x86_64")]
    {
        let limits = in_step(exc, specs)?;
        let [a, b] = specs;
        let isa = Isa::detected();
        // SAFETY (both arms): `in_step` is Some only where `Isa::detected()`
        // has lanes (v3 or v4), where the CPU has its features.
        match (a.model.integrator, a.model.equation) {
            (Integrator::Exact, Equation::Linearized) => {
                let new = |s: &RunSpec, limit| Exact::new(s.p, s.eta, exc.dt_s, limit);
                let (mut sa, mut sb) = (new(a, limits[0]), new(b, limits[1]));
                Some(unsafe { dispatch::drive_pair(isa, exc, specs, limits, [&mut sa, &mut sb]) })
            }
            (Integrator::Taylor { .. }, Equation::Nonlinear { alpha_rad }) => {
                let new =
                    |s: &RunSpec, limit| Taylor::new(s.p, s.eta, alpha_rad, taylor_tol(s), limit);
                let (mut sa, mut sb) = (new(a, limits[0]), new(b, limits[1]));
                Some(unsafe { dispatch::drive_pair(isa, exc, specs, limits, [&mut sa, &mut sb]) })
            }
            _ => None,
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (exc, specs);
        None
    }
}

/// Two to four Taylor runs that differ in η and the tolerance alone (a
/// decisive run with its chaos probes at the tighter tolerance, two runs'
/// probes), run in step as [`simulate_pair`] runs two: four lanes of one
/// AVX register, a lane left empty for three. Each outcome is the one
/// [`simulate`] gives, to the bit, in the order of `specs`. `None` where
/// they cannot be: another integrator, fewer than two specs or more than
/// four, specs that differ in more or that [`simulate`] refuses, a CPU
/// without x86-64-v3.
pub fn simulate_lanes(exc: &Excitation, specs: &[RunSpec]) -> Option<Vec<Outcome>> {
    #[cfg(target_arch = "x86_64")]
    {
        let (Integrator::Taylor { .. }, Equation::Nonlinear { alpha_rad }) =
            (specs.first()?.model.integrator, specs[0].model.equation)
        else {
            return None;
        };
        if let [a, b] = specs {
            return simulate_pair(exc, [a, b]).map(Vec::from);
        }
        if !(3..=4).contains(&specs.len()) {
            return None;
        }
        // An empty lane repeats the first run, and is not kept.
        let four: [&RunSpec; 4] = std::array::from_fn(|i| specs.get(i).unwrap_or(&specs[0]));
        let limits = in_step(exc, four)?;
        let mut steppers: [Taylor; 4] = std::array::from_fn(|i| {
            Taylor::new(
                four[i].p,
                four[i].eta,
                alpha_rad,
                taylor_tol(four[i]),
                limits[i],
            )
        });
        let present = std::array::from_fn(|i| i < specs.len());
        // SAFETY: `in_step` is Some only where `Isa::detected()` has lanes
        // (v3 or v4), where the CPU has its features.
        let isa = Isa::detected();
        let outs =
            unsafe { dispatch::drive_lanes(isa, exc, four, limits, steppers.each_mut(), present) };
        Some(outs[..specs.len()].to_vec())
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (exc, specs);
        None
    }
}

/// A Taylor run's tolerance (NaN for another integrator, never asked).
#[cfg(target_arch = "x86_64")]
fn taylor_tol(spec: &RunSpec) -> f64 {
    spec.model.integrator.tol().unwrap_or(f64::NAN)
}

/// The overturning limits of runs that can be run in step: on a CPU with
/// x86-64-v3, specs that [`simulate`] takes and that differ in η alone (and
/// the Taylor stepper's tolerance); none while a stop is asked for (the
/// caller's lone runs then refuse to start).
#[cfg(target_arch = "x86_64")]
fn in_step<const N: usize>(exc: &Excitation, specs: [&RunSpec; N]) -> Option<[f64; N]> {
    if interrupt::requested() {
        return None;
    }
    let first = specs[0];
    // A block that may slide walks every interval (its friction is checked
    // at each), so it has no lanes.
    if first.model.equation.friction().is_some() {
        return None;
    }
    let alike = |s: &RunSpec| {
        let integrator = match (s.model.integrator, first.model.integrator) {
            (Integrator::Taylor { .. }, Integrator::Taylor { .. }) => first.model.integrator,
            (other, _) => other,
        };
        let model = Model {
            integrator,
            ..s.model
        };
        RunSpec {
            eta: first.eta,
            model,
            ..*s
        } == *first
    };
    if !(specs.iter().all(|s| alike(s)) && Isa::detected().has_lanes()) {
        return None;
    }
    let mut limits = [0.0; N];
    for (limit, s) in limits.iter_mut().zip(specs) {
        s.validate().ok()?;
        fits_the_step(exc, s).ok()?;
        *limit = s.model.equation.overturn_limit(s.overturn).ok()?;
    }
    Some(limits)
}

/// [`simulate`] with the exact stepper's event loop as compiled for `isa`
/// ([`Isa`]; the other integrators have one compilation): to compare the
/// two. Refused when this CPU cannot run it.
pub fn simulate_on(exc: &Excitation, spec: &RunSpec, isa: Isa) -> Result<Outcome, PhysicsError> {
    if !isa.available() {
        return Err(PhysicsError::BadInput(format!(
            "this CPU cannot run the {isa:?} compilation of the stepper"
        )));
    }
    run(exc, spec, None, &mut (), isa)
}

/// The largest p·Δt the exact stepper takes: its closed form over a sample
/// interval grows as e^{p·Δt}, and beyond about 270 its located events lose
/// their digits (an overturning at p·Δt = 300 came 0.02 s late, and past
/// 709 e^{p·Δt} overflows and a run that overturns read as one that
/// survives). Real records keep p·Δt below 0.5 (p ≤ 10 1/s, Δt ≤ 0.02 s).
pub const MAX_P_DT: f64 = 100.0;

/// Refuses a run of the exact stepper whose sample interval is too long for
/// its block ([`MAX_P_DT`]); the other steppers cut their steps.
fn fits_the_step(exc: &Excitation, spec: &RunSpec) -> Result<(), PhysicsError> {
    let p_dt = spec.p * exc.dt_s;
    if spec.model.integrator != Integrator::Exact || p_dt <= MAX_P_DT {
        return Ok(());
    }
    Err(PhysicsError::BadInput(format!(
        "p·Δt = {p_dt} (p = {} 1/s, a sample step Δt = {} s) is above {MAX_P_DT}: within one \
         step the linearised block's motion grows e^{{p·Δt}}, past what the exact step \
         resolves; give the motion at a step of {} s or less (a record sampled finer, a pulse \
         in more intervals), or run the nonlinear model",
        spec.p,
        exc.dt_s,
        MAX_P_DT / spec.p
    )))
}

fn run(
    exc: &Excitation,
    spec: &RunSpec,
    start: Option<Rocking>,
    obs: &mut impl Observer,
    isa: Isa,
) -> Result<Outcome, PhysicsError> {
    if interrupt::requested() {
        return Err(PhysicsError::Interrupted);
    }
    spec.validate()?;
    fits_the_step(exc, spec)?;
    if let Some(st) = start {
        if !(st.s == 1.0 || st.s == -1.0)
            || !(st.x.is_finite() && st.v.is_finite())
            || st.s * st.x < 0.0
        {
            return Err(PhysicsError::BadInput(format!(
                "start state {st:?}: pivot must be ±1 and x on its side"
            )));
        }
    }
    let equation = spec.model.equation;
    let limit = equation.overturn_limit(spec.overturn)?;
    if let Some(st) = start {
        if spec.overturn.needs_escape_proof(equation.alpha()) && st.s * st.x >= limit {
            return Err(PhysicsError::BadInput(format!(
                "start state {st:?}: under `escape` a start must lie below |x| = {limit}"
            )));
        }
    }
    Ok(drive(
        spec.model.integrator,
        equation,
        exc,
        spec,
        start,
        limit,
        obs,
        isa,
    ))
}

/// Runs the event driver with `integrator` on `equation` (validated): the
/// one place a lone run's stepper is built; the exact and Taylor
/// steppers' event loops as compiled for `isa` (available on this CPU).
#[allow(clippy::too_many_arguments)]
fn drive(
    integrator: Integrator,
    equation: Equation,
    exc: &Excitation,
    spec: &RunSpec,
    start: Option<Rocking>,
    limit: f64,
    obs: &mut impl Observer,
    isa: Isa,
) -> Outcome {
    let (p, eta, dt) = (spec.p, spec.eta, exc.dt_s);
    // One monomorphised event loop per (integrator, equation).
    macro_rules! with {
        ($stepper:expr) => {
            driver::drive(exc, spec, start, limit, &mut $stepper, obs)
        };
    }
    // A block that may slide rocks by its rocking equation's stepper; the
    // driver carries the rest.
    match (integrator, equation.rocking()) {
        (Integrator::Exact, Equation::Linearized) => dispatch::drive(
            exc,
            spec,
            start,
            limit,
            &mut exact::Exact::new(p, eta, dt, limit),
            obs,
            isa,
        ),
        (Integrator::Exact, Equation::Nonlinear { .. }) => {
            unreachable!("validate() refuses the exact stepper for the nonlinear equation")
        }
        (_, Equation::SlideRock { .. }) => unreachable!("`rocking()` has no friction"),
        (Integrator::Dp5 { rtol }, Equation::Linearized) => {
            with!(dp5::Dp5::new(LinearRhs::new(p, eta), p, rtol, limit))
        }
        (Integrator::Dp5 { rtol }, Equation::Nonlinear { alpha_rad }) => {
            with!(dp5::Dp5::new(
                NonlinearRhs::new(p, eta, alpha_rad),
                p,
                rtol,
                limit
            ))
        }
        (Integrator::Taylor { .. }, Equation::Linearized) => {
            unreachable!("validate() refuses the Taylor stepper for the linearised equation")
        }
        (Integrator::Taylor { tol }, Equation::Nonlinear { alpha_rad }) => dispatch::drive(
            exc,
            spec,
            start,
            limit,
            &mut taylor::Taylor::new(p, eta, alpha_rad, tol, limit),
            obs,
            isa,
        ),
        (Integrator::Rk4 { substeps }, Equation::Linearized) => {
            with!(rk4::Rk4::new(LinearRhs::new(p, eta), dt, substeps, limit))
        }
        (Integrator::Rk4 { substeps }, Equation::Nonlinear { alpha_rad }) => {
            with!(rk4::Rk4::new(
                NonlinearRhs::new(p, eta, alpha_rad),
                dt,
                substeps,
                limit
            ))
        }
    }
}
