//! Rocking of a free-standing rigid block on a rigid base (pure; no I/O).
//!
//! Equations (docs/MODEL.md §2), with `x = θ/α`, pivot `s = sgn(x)`, the
//! record normalised to unit peak `ψ̈` and `η = αg/A_g`:
//!
//! ```text
//! linearised:  ẍ = p² (x − s) + (p²/η) ψ̈(t)
//! nonlinear:   ẍ = −(p²/α) s sin(α(1 − s x)) + (p²/η) cos(α(1 − s x)) ψ̈(t)
//! ```
//!
//! `ψ̈` is linear between samples. A [`Model`] is an [`Equation`] (which owns
//! α, the uplift threshold, the overturning limit, the right-hand side and
//! the fate after the record) advanced by an [`Integrator`] (which only
//! steps and says why it stopped). The events (MODEL.md §3) are handled once,
//! by the driver behind [`simulate`], whatever the integrator:
//!
//! - **uplift** from rest where the interpolated `|ψ̈|` crosses `η·k`
//!   (`k = 1` linearised, `tan α / α` nonlinear), on the side `sgn ψ̈`;
//! - **impact** at `x = 0`: `ẋ⁺ = ε ẋ⁻`, pivot switch;
//! - **rest** when the speed after an impact is below the rest tolerance
//!   ([`REST_TOL`], relative to `p`);
//! - **overturning** per [`Overturn`];
//! - **after the record** the fate is decided from the free-rocking energy
//!   ([`energy`]) instead of integrating a tail of quiet.
//!
//! Integrators: [`exact`] (closed form, linearised), [`taylor`] (the
//! nonlinear equation's Taylor series, one step per sample interval), [`dp5`]
//! (Dormand–Prince 5(4)), [`rk4`] (fixed-step baseline for benchmarks).
//! Time inside an interval is a local offset from the interval's first
//! sample, so events always advance it.

mod dispatch;
pub mod dp5;
mod driver;
pub mod energy;
pub mod equation;
pub mod exact;
mod history;
mod hop;
mod integrator;
#[cfg(target_arch = "x86_64")]
#[allow(unused_unsafe)] // the SSE2 intrinsics are safe to call from Rust 1.87 on
mod lanes;
pub mod rk4;
mod simulate;
mod step;
pub mod taylor;

use std::fmt;

pub use dispatch::Isa;
pub use driver::{Outcome, Stop};
pub use equation::{
    check_alpha, Equation, EquationKind, ALPHA_MIN, LINEARIZATION_ERROR_PER_ALPHA2,
};
pub use history::{EventKind, HistoryPoint, Observer, Recorder};
pub use integrator::{
    check_auto_tol, check_rtol, Integrator, Model, ModelChoice, NonlinearIntegrator, Solver,
    DEFAULT_RTOL, DEFAULT_TAYLOR_TOL, DP5_TIGHTEST_RTOL, MIN_RTOL, TAYLOR_TIGHTEST_TOL,
};
pub use simulate::{
    simulate, simulate_from, simulate_lanes, simulate_observed, simulate_on, simulate_pair,
};
pub use step::{Rocking, Stepper, Stretch, StretchEnd};

/// Speed below which a block is at rest after an impact, relative to `p`:
/// `|ẋ⁺| < REST_TOL · p`. The swing that follows such an impact would reach
/// `|x| ≈ (ẋ⁺/p)²/2 < 5·10⁻¹⁹`, far below any reported digit; the tests
/// check that θmax/α does not move when the tolerance changes by 100×.
pub const REST_TOL: f64 = 1e-9;

/// The frequency parameters p (1/s) the model is computed for: blocks with
/// R = 3g/(4p²) from 7.4 µm (p = 1000) to 74 km (p = 0.01), every real
/// block and far beyond. Above, the arithmetic fails before the physics:
/// the exact step's e^{p·Δt} overflows at p·Δt ≈ 709 (p ≈ 1.4e5 on a
/// 0.005-s record), and on Kobe NIS η_c, which tends to 1 as p grows (a
/// tiny block overturns as soon as it uplifts), was 0.99993 at p = 1e4 but
/// 0.31 at 1e6 and 0.0025 at 1e7.
pub const P_RANGE: std::ops::RangeInclusive<f64> = 0.01..=1000.0;

/// Whether `p` is in [`P_RANGE`]; else the message, naming the range.
pub fn check_p(p: f64) -> Result<(), String> {
    if P_RANGE.contains(&p) {
        Ok(())
    } else {
        // 1e300 as such, not as its 301 digits.
        let p = if p == 0.0 || !p.is_finite() || (1e-4..1e7).contains(&p.abs()) {
            format!("{p}")
        } else {
            format!("{p:e}")
        };
        Err(format!(
            "p = {p} 1/s is outside [{}, {}] 1/s, the range the model is computed for \
             (a block's R = 3g/(4p²) from 74 km down to 7.4 µm)",
            P_RANGE.start(),
            P_RANGE.end()
        ))
    }
}

/// Hard cap on events in one run; a run that reaches it is reported as
/// [`Stop::EventLimit`] instead of looping. No physical run comes close:
/// a Zeno sequence from `ẋ/p = 1` to rest at ε = 0.99 has about 2,100 impacts.
pub const MAX_EVENTS: u64 = 50_000_000;

/// When a block counts as overturned.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Overturn {
    /// `|x| ≥ 1`: θ reaches α, the static stability limit (the paper's choice).
    Static,
    /// `|x| ≥ cap` for a cap above 1.
    Cap(f64),
    /// Nonlinear model only: the block lies on its side, `θ = π/2`.
    OnSide,
    /// True overturning: the block never comes back (MODEL.md §10). The
    /// nonlinear model: θ reaches π/2, as [`Overturn::OnSide`]. The
    /// linearised model has no such angle: nothing is decided while the
    /// ground moves unless a bound proves the escape (the growing mode
    /// outruns the largest forcing still to come, [`escape_proven`]), and
    /// after the excitation the free motion's energy decides.
    Escape,
}

/// Whether a linearised block on pivot `s` at `(x, v)` escapes for sure
/// whatever the forcing does from now on, given a bound `m_over_eta` on
/// `|ψ̈|/η` for the rest of the excitation. With `y = s·x`, `w = s·ẋ`, the
/// growing mode `u = y − 1 + w/p` obeys `u̇ = p(u + sψ̈/η) ≥ p(u − M/η)`,
/// so `u > M/η` keeps growing; the other mode `y − 1 − w/p` stays within
/// `M/η` of its free decay, which keeps `y ≥ min(y₀, 1) > 0`: no impact,
/// and `y → ∞`. (Proof in MODEL.md §10.) A relative margin of 1e-9 covers
/// the rounding of `u`.
pub fn escape_proven(p: f64, st: Rocking, m_over_eta: f64) -> bool {
    let (y, w) = (st.s * st.x, st.s * st.v);
    let u = y - 1.0 + w / p;
    y > 0.0 && u > m_over_eta * (1.0 + 1e-9) + 1e-9 * (y.abs() + 1.0)
}

impl Overturn {
    /// The `|x|` at which the run stops, for a block of slenderness `alpha_rad`.
    pub fn limit(self, alpha_rad: Option<f64>) -> Result<f64, PhysicsError> {
        match self {
            Overturn::Static => Ok(1.0),
            Overturn::Cap(c) if c.is_finite() && c >= 1.0 => Ok(c),
            Overturn::Cap(c) => Err(PhysicsError::BadInput(format!(
                "overturning cap {c} must be a finite number ≥ 1 (in units of α)"
            ))),
            Overturn::OnSide => match alpha_rad {
                Some(a) => Ok(std::f64::consts::FRAC_PI_2 / a),
                None => Err(PhysicsError::BadInput(
                    "the `on-side` criterion (θ = π/2) needs the nonlinear model and α".into(),
                )),
            },
            // Linearised: the first |x| at which the driver tries to prove
            // the escape (it doubles after each try that fails).
            Overturn::Escape => Ok(alpha_rad.map_or(1.0, |a| std::f64::consts::FRAC_PI_2 / a)),
        }
    }

    /// Whether runs under this criterion stop only on a proof of escape
    /// (the linearised model under [`Overturn::Escape`]) rather than at
    /// the limit.
    pub fn needs_escape_proof(self, alpha_rad: Option<f64>) -> bool {
        self == Overturn::Escape && alpha_rad.is_none()
    }
}

impl std::str::FromStr for Overturn {
    type Err = PhysicsError;

    /// `static`, `cap:<c>` (c ≥ 1), `on-side` or `escape`.
    fn from_str(text: &str) -> Result<Self, PhysicsError> {
        let bad = || {
            PhysicsError::BadInput(format!(
                "unknown overturning criterion `{text}`; valid: static, cap:<c> (c ≥ 1, in units of α), on-side, escape"
            ))
        };
        match text {
            "static" => Ok(Overturn::Static),
            "on-side" => Ok(Overturn::OnSide),
            "escape" => Ok(Overturn::Escape),
            _ => {
                let c = text
                    .strip_prefix("cap:")
                    .ok_or_else(bad)?
                    .parse::<f64>()
                    .map_err(|_| bad())?;
                Overturn::Cap(c).limit(None).map(|_| Overturn::Cap(c))
            }
        }
    }
}

impl fmt::Display for Overturn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Overturn::Static => write!(f, "static"),
            Overturn::Cap(c) => write!(f, "cap:{c}"),
            Overturn::OnSide => write!(f, "on-side"),
            Overturn::Escape => write!(f, "escape"),
        }
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    #[error("{0}")]
    BadInput(String),
}

/// A record prepared for many runs: normalised to unit peak, with the
/// running maximum of |ψ̈| from each sample to the end (to stop a run early
/// once the block is at rest and the rest of the record cannot lift it).
///
/// The forcing is linear over each sample interval and may jump at a
/// sample: interval `k` runs from `psi[k]` (the value just after sample k)
/// to `psi_end[k]` (the value just before sample k + 1). For a sampled
/// record `psi_end[k] = psi[k + 1]`; a pulse with a discontinuity (a
/// rectangle's switch, [`crate::pulse`]) puts it on a sample, so every
/// stepper sees it exactly on a step boundary.
#[derive(Debug, Clone)]
pub struct Excitation {
    pub dt_s: f64,
    /// `ψ̈ = ü_g / A_g` just after each sample, peak absolute value exactly
    /// 1 (for a non-zero record).
    pub psi: Vec<f64>,
    /// The forcing at the end of each interval where it is not the next
    /// sample's ([`Excitation::psi_end`]); `None` for a record, whose
    /// forcing is continuous: `psi` serves for both then.
    ends: Option<Vec<f64>>,
    /// `suffix_max[k] = max |ψ̈|` over the record from sample k on (both
    /// sides of every later jump).
    pub suffix_max: Vec<f64>,
    /// `slope[k] = (psi_end[k] − psi[k])/dt`, the forcing's slope over
    /// interval k, computed once per record rather than once per run.
    pub slope: Vec<f64>,
    /// `quiet[j]`: the largest `|psi_end[k]|` and `|psi[k + 1]|` over the
    /// intervals k of block j (`QUIET_BLOCK` of them), so that a block a
    /// resting block cannot leave is crossed at once ([`Excitation::quiet_until`]).
    quiet: Vec<f64>,
}

/// Intervals per block of [`Excitation::quiet_until`]'s scan.
const QUIET_BLOCK: usize = 32;

impl Excitation {
    /// Normalises `accel_g` by its peak. A record of zeros stays zeros (it
    /// can never lift a block).
    pub fn new(accel_g: &[f64], dt_s: f64) -> Result<Self, PhysicsError> {
        Excitation::from_samples(accel_g.to_vec(), dt_s)
    }

    /// [`Excitation::new`], normalising the samples where they are (no
    /// second array: a record read for one command is used once).
    pub fn from_samples(mut accel_g: Vec<f64>, dt_s: f64) -> Result<Self, PhysicsError> {
        if !(dt_s > 0.0 && dt_s.is_finite()) {
            return Err(PhysicsError::BadInput(format!(
                "time step {dt_s} s must be positive"
            )));
        }
        if accel_g.is_empty() {
            return Err(PhysicsError::BadInput("the record has no samples".into()));
        }
        if let Some(bad) = accel_g.iter().find(|a| !a.is_finite()) {
            return Err(PhysicsError::BadInput(format!(
                "the record holds a non-finite sample {bad}"
            )));
        }
        let peak = accel_g.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        if peak > 0.0 {
            accel_g.iter_mut().for_each(|a| *a /= peak);
        }
        Ok(Excitation::prepared(dt_s, accel_g))
    }

    /// The record of normalised samples `psi`, with what runs derive from it.
    fn prepared(dt_s: f64, psi: Vec<f64>) -> Self {
        Excitation::pieces(dt_s, psi, None)
    }

    /// A forcing linear on each interval from `psi[k]` to `psi_end[k]`
    /// (`psi` has one value more: the last sample's).
    /// `ends` are kept only where they differ from the next samples (to
    /// the bit).
    fn pieces(dt_s: f64, psi: Vec<f64>, ends: Option<Vec<f64>>) -> Self {
        let next = psi.get(1..).unwrap_or_default();
        let ends = ends.filter(|e| {
            e.len() != next.len() || e.iter().zip(next).any(|(a, b)| a.to_bits() != b.to_bits())
        });
        let psi_end = ends.as_deref().unwrap_or(next);
        debug_assert_eq!(psi_end.len() + 1, psi.len().max(1));
        let mut suffix_max = vec![0.0; psi.len()];
        let mut m = 0.0f64;
        for k in (0..psi.len()).rev() {
            m = m.max(psi[k].abs());
            if let Some(e) = psi_end.get(k) {
                m = m.max(e.abs());
            }
            suffix_max[k] = m;
        }
        let slope = psi
            .iter()
            .zip(psi_end)
            .map(|(a, b)| (b - a) / dt_s)
            .collect();
        let quiet = psi_end
            .chunks(QUIET_BLOCK)
            .zip(psi.get(1..).unwrap_or_default().chunks(QUIET_BLOCK))
            .map(|(ends, nexts)| ends.iter().chain(nexts).fold(0.0f64, |m, v| m.max(v.abs())))
            .collect();
        Excitation {
            dt_s,
            psi,
            ends,
            suffix_max,
            slope,
            quiet,
        }
    }

    /// For a block at rest at sample `k` (`|psi[k]|` within `thr`): the first
    /// interval from `k` on whose end or the next sample's start exceeds
    /// `thr` (it may lift the block), or at whose end the record stays
    /// within `thr` for good, or the record's end: every interval before it
    /// has both ends within `thr` and lifts nothing (the forcing is linear
    /// between). Whole blocks of [`QUIET_BLOCK`] intervals are crossed by
    /// their maximum.
    #[inline(always)]
    pub fn quiet_until(&self, mut k: usize, thr: f64) -> usize {
        let (psi, psi_end, suffix) = (&self.psi[..], self.psi_end(), &self.suffix_max[..]);
        let n = psi_end.len();
        while k < n {
            // The suffix maximum falls with k: above `thr` after the block's
            // last interval, it is above it after every one of them.
            if k % QUIET_BLOCK == 0
                && k + QUIET_BLOCK <= n
                && self.quiet[k / QUIET_BLOCK] <= thr
                && suffix[k + QUIET_BLOCK] > thr
            {
                k += QUIET_BLOCK;
                continue;
            }
            if !(psi_end[k].abs() <= thr && psi[k + 1].abs() <= thr && suffix[k + 1] > thr) {
                break;
            }
            k += 1;
        }
        k
    }

    /// A piecewise-linear forcing that may jump at samples: interval k goes
    /// from `starts[k]` to `ends[k]`; the last sample holds `ends`' last
    /// value. Used as given (no normalisation): its peak must be at most 1,
    /// as a normalised record's is, and equal 1 for η to mean what it does.
    pub fn piecewise(dt_s: f64, starts: &[f64], ends: &[f64]) -> Result<Self, PhysicsError> {
        let bad = |m: String| Err(PhysicsError::BadInput(m));
        if !(dt_s > 0.0 && dt_s.is_finite()) {
            return bad(format!("time step {dt_s} s must be positive"));
        }
        if starts.is_empty() || starts.len() != ends.len() {
            return bad(format!(
                "a piecewise forcing needs as many interval starts as ends, and at least one ({} and {})",
                starts.len(),
                ends.len()
            ));
        }
        if let Some(v) = starts
            .iter()
            .chain(ends)
            .find(|v| v.is_nan() || v.abs() > 1.0)
        {
            return bad(format!(
                "a piecewise forcing's values must lie in [−1, 1]; found {v}"
            ));
        }
        let mut psi = starts.to_vec();
        psi.push(ends[ends.len() - 1]);
        Ok(Excitation::pieces(dt_s, psi, Some(ends.to_vec())))
    }

    /// Record with the sign of every sample flipped (for symmetry checks).
    pub fn negated(&self) -> Self {
        self.mapped(|v| -v)
    }

    /// The normalised record with every sample mapped by `f` (e.g. moved by
    /// one ulp, to measure how rounding moves a verdict).
    pub fn mapped(&self, f: impl Fn(f64) -> f64) -> Self {
        Excitation::pieces(
            self.dt_s,
            self.psi.iter().map(|&v| f(v)).collect(),
            Some(self.psi_end().iter().map(|&v| f(v)).collect()),
        )
    }

    /// `psi_end[k]`: the forcing at the end of interval k (its left limit at
    /// sample k + 1); one per interval.
    #[inline(always)]
    pub fn psi_end(&self) -> &[f64] {
        match &self.ends {
            Some(ends) => ends,
            None => &self.psi[1..],
        }
    }

    pub fn duration_s(&self) -> f64 {
        (self.psi.len() - 1) as f64 * self.dt_s
    }
}

/// The block and the run: everything except the record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSpec {
    /// Frequency parameter p (1/s).
    pub p: f64,
    /// Coefficient of restitution ε ∈ (0, 1].
    pub eps: f64,
    /// Uplift strength η = αg/A_g (> 0; smaller is stronger shaking).
    pub eta: f64,
    pub model: Model,
    pub overturn: Overturn,
    /// Rest tolerance (relative to p); [`REST_TOL`] unless testing.
    pub rest_tol: f64,
}

impl RunSpec {
    pub fn new(p: f64, eps: f64, eta: f64, model: Model) -> Self {
        RunSpec {
            p,
            eps,
            eta,
            model,
            overturn: Overturn::Static,
            rest_tol: REST_TOL,
        }
    }

    /// Checks ranges; called by [`simulate`].
    pub fn validate(&self) -> Result<(), PhysicsError> {
        let bad = |m: String| Err(PhysicsError::BadInput(m));
        check_p(self.p).map_err(PhysicsError::BadInput)?;
        if !(self.eps > 0.0 && self.eps <= 1.0) {
            return bad(format!("ε = {} must be in (0, 1]", self.eps));
        }
        if !(self.eta > 0.0 && self.eta.is_finite()) {
            return bad(format!("η = {} must be positive", self.eta));
        }
        if !(self.rest_tol > 0.0 && self.rest_tol < 1e-3) {
            return bad(format!(
                "rest tolerance {} must be in (0, 1e-3)",
                self.rest_tol
            ));
        }
        self.model.validate()?;
        self.model.equation.overturn_limit(self.overturn)?;
        Ok(())
    }

    /// The slenderness α of the model's equation, if it has one.
    pub fn alpha(&self) -> Option<f64> {
        self.model.equation.alpha()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The block scan against its definition, interval by interval, from
    /// every resting start, on records with quiet stretches longer and
    /// shorter than a block, a jump, and a tail that stays quiet for good.
    #[test]
    fn quiet_scan_matches_the_interval_by_interval_scan() {
        let mut seed = 12_345u64;
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut starts = Vec::new();
        for k in 0..1_000 {
            // Bursts every 150 samples, quiet between, quieter for good at the end.
            let loud = k % 150 < 20 && k < 900;
            starts.push((if loud { 1.0 } else { 0.3 }) * (2.0 * next() - 1.0));
        }
        let mut ends: Vec<f64> = starts[1..].to_vec();
        ends.push(0.0);
        ends[500] = 0.9; // a jump down at sample 501
        starts[700] = 0.8; // and one up at sample 700
        let exc = Excitation::piecewise(0.01, &starts, &ends).unwrap();
        let n = exc.psi_end().len();
        let mut crossed = 0;
        for thr in [0.05, 0.25, 0.3, 0.5, 0.95] {
            for k0 in (0..n).filter(|&k| exc.psi[k].abs() <= thr) {
                let mut k = k0;
                while k < n
                    && exc.psi_end()[k].abs() <= thr
                    && exc.psi[k + 1].abs() <= thr
                    && exc.suffix_max[k + 1] > thr
                {
                    k += 1;
                }
                assert_eq!(exc.quiet_until(k0, thr), k, "from {k0} at {thr}");
                crossed += k - k0;
            }
        }
        assert!(
            crossed > 10_000,
            "the scans crossed only {crossed} intervals"
        );
    }
}
