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
//! `ψ̈` is linear between samples. The events (MODEL.md §3) are handled by
//! one driver, [`simulate`], whatever the integrator:
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
//! The integrators ([`linear`], [`nonlinear`], [`rk4`]) implement
//! [`Rocker`]: advance on one pivot until the end of a sample interval or the
//! first event, whichever comes first, like diffsol's `step` returning why it
//! stopped. Time inside an interval is a local offset from the interval's
//! first sample, so events always advance it.

pub mod energy;
pub mod linear;
pub mod nonlinear;
pub mod rk4;

use std::fmt;

/// Speed below which a block is at rest after an impact, relative to `p`:
/// `|ẋ⁺| < REST_TOL · p`. The swing that follows such an impact would reach
/// `|x| ≈ (ẋ⁺/p)²/2 < 5·10⁻¹⁹`, far below any reported digit; the tests
/// check that θmax/α does not move when the tolerance changes by 100×.
pub const REST_TOL: f64 = 1e-9;

/// Hard cap on events in one run; a run that reaches it is reported as
/// [`Stop::EventLimit`] instead of looping. No physical run comes close:
/// a Zeno sequence from `ẋ/p = 1` to rest at ε = 0.99 has about 2,100 impacts.
pub const MAX_EVENTS: u64 = 50_000_000;

/// Which equation of motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Model {
    /// Paper Eq. 8: depends on p, η, ε only (α → 0).
    Linearized,
    /// Paper Eq. 7 with slenderness `alpha_rad`, integrated by Dormand–Prince
    /// 5(4) with relative tolerance `rtol`.
    Nonlinear { alpha_rad: f64, rtol: f64 },
    /// Classical fixed-step RK4 with `substeps` steps per sample interval and
    /// events located by linear interpolation: the baseline a user would write,
    /// for benchmarks only. `alpha_rad: None` integrates the linearised equation.
    Rk4 {
        substeps: u32,
        alpha_rad: Option<f64>,
    },
}

/// Median relative difference in η_c between the nonlinear and the
/// linearised model, per α² (α in rad): measured as 0.43·α² (α from 0.025 to
/// 0.4 rad, 11 far-field records × p ∈ {1, 3, 8} × ε ∈ {0.6, 0.9}; see
/// docs/BENCHMARKS.md), rounded up. Single records can differ more, because a
/// capacity is the first of possibly several overturning islands.
pub const LINEARIZATION_ERROR_PER_ALPHA2: f64 = 0.45;

/// The model as a user asks for it; [`ModelChoice::resolve`] makes it a [`Model`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelChoice {
    Linearized,
    Nonlinear,
    /// The linearised model where its error for the block's α is within the
    /// tolerance ([`LINEARIZATION_ERROR_PER_ALPHA2`]·α² ≤ tol), else the nonlinear one.
    Auto,
}

impl ModelChoice {
    /// The model to run and a sentence saying why.
    pub fn resolve(
        self,
        alpha_rad: Option<f64>,
        rtol: f64,
        auto_tol: f64,
    ) -> Result<(Model, String), PhysicsError> {
        match (self, alpha_rad) {
            (ModelChoice::Linearized, _) => {
                Ok((Model::Linearized, "linearised model, as asked".into()))
            }
            (ModelChoice::Nonlinear, Some(a)) => Ok((
                Model::Nonlinear { alpha_rad: a, rtol },
                "nonlinear model, as asked".into(),
            )),
            (ModelChoice::Nonlinear, None) => Err(PhysicsError::BadInput(
                "the nonlinear model needs the block's slenderness α (--alpha, in rad)".into(),
            )),
            (ModelChoice::Auto, None) => Ok((
                Model::Linearized,
                "linearised model: no α given, so the α → 0 limit".into(),
            )),
            (ModelChoice::Auto, Some(a)) => {
                let err = LINEARIZATION_ERROR_PER_ALPHA2 * a * a;
                if err <= auto_tol {
                    Ok((
                        Model::Linearized,
                        format!("linearised model: its η_c error for α = {a} is about {err:.2e} ≤ {auto_tol:e}"),
                    ))
                } else {
                    Ok((
                        Model::Nonlinear { alpha_rad: a, rtol },
                        format!("nonlinear model: the linearised one would err by about {err:.2e} > {auto_tol:e} for α = {a}"),
                    ))
                }
            }
        }
    }
}

impl Model {
    pub fn name(&self) -> &'static str {
        match self {
            Model::Linearized => "linearized",
            Model::Nonlinear { .. } => "nonlinear",
            Model::Rk4 { .. } => "rk4",
        }
    }
}

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
        }
    }
}

impl std::str::FromStr for Overturn {
    type Err = PhysicsError;

    /// `static`, `cap:<c>` (c ≥ 1) or `on-side`.
    fn from_str(text: &str) -> Result<Self, PhysicsError> {
        let bad = || {
            PhysicsError::BadInput(format!(
                "unknown overturning criterion `{text}`; valid: static, cap:<c> (c ≥ 1, in units of α), on-side"
            ))
        };
        match text {
            "static" => Ok(Overturn::Static),
            "on-side" => Ok(Overturn::OnSide),
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
#[derive(Debug, Clone)]
pub struct Excitation {
    pub dt_s: f64,
    /// `ψ̈ = ü_g / A_g`, peak absolute value exactly 1 (for a non-zero record).
    pub psi: Vec<f64>,
    /// `suffix_max[k] = max_{j ≥ k} |ψ̈_j|`.
    pub suffix_max: Vec<f64>,
}

impl Excitation {
    /// Normalises `accel_g` by its peak. A record of zeros stays zeros (it
    /// can never lift a block).
    pub fn new(accel_g: &[f64], dt_s: f64) -> Result<Self, PhysicsError> {
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
        let psi: Vec<f64> = if peak > 0.0 {
            accel_g.iter().map(|a| a / peak).collect()
        } else {
            accel_g.to_vec()
        };
        let mut suffix_max = vec![0.0; psi.len()];
        let mut m = 0.0f64;
        for k in (0..psi.len()).rev() {
            m = m.max(psi[k].abs());
            suffix_max[k] = m;
        }
        Ok(Excitation {
            dt_s,
            psi,
            suffix_max,
        })
    }

    /// Record with the sign of every sample flipped (for symmetry checks).
    pub fn negated(&self) -> Self {
        Excitation {
            dt_s: self.dt_s,
            psi: self.psi.iter().map(|v| -v).collect(),
            suffix_max: self.suffix_max.clone(),
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
        if !(self.p > 0.0 && self.p.is_finite()) {
            return bad(format!("p = {} 1/s must be positive", self.p));
        }
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
        let alpha = match self.model {
            Model::Linearized => None,
            Model::Nonlinear { alpha_rad, rtol } => {
                if !(rtol > 0.0 && rtol < 1e-2) {
                    return bad(format!("nonlinear tolerance {rtol} must be in (0, 0.01)"));
                }
                Some(alpha_rad)
            }
            Model::Rk4 {
                substeps,
                alpha_rad,
            } => {
                if substeps == 0 {
                    return bad("RK4 needs at least one step per sample interval".into());
                }
                alpha_rad
            }
        };
        if let Some(a) = alpha {
            if !(a > 0.0 && a < std::f64::consts::FRAC_PI_2) {
                return bad(format!("α = {a} rad must be in (0, π/2)"));
            }
        }
        self.overturn.limit(alpha)?;
        Ok(())
    }

    fn alpha(&self) -> Option<f64> {
        match self.model {
            Model::Linearized => None,
            Model::Nonlinear { alpha_rad, .. } => Some(alpha_rad),
            Model::Rk4 { alpha_rad, .. } => alpha_rad,
        }
    }
}

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The record ended with the block rocking or at rest, and energy says it stays up.
    Survived,
    /// Reached the overturning limit.
    Overturned,
    /// At rest, and the rest of the record stays below the uplift threshold.
    RestForGood,
    /// Hit [`MAX_EVENTS`] (a bug guard; never expected).
    EventLimit,
}

/// Summary of one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// max |x| = θmax/α over the run, including the free rocking after the
    /// record (for an overturned block, the overturning limit).
    pub max_abs_x: f64,
    pub stop: Stop,
    /// Time of overturning (s, from the first sample), if it overturned.
    pub overturn_time_s: Option<f64>,
    /// Whether the overturning happens after the record ends.
    pub overturn_after_record: bool,
    pub impacts: u64,
    pub first_uplift_s: Option<f64>,
    /// Sample intervals the run went through before it stopped (work done).
    pub intervals: u64,
}

impl Outcome {
    pub fn overturned(&self) -> bool {
        self.stop == Stop::Overturned
    }
}

impl Stop {
    pub fn as_str(self) -> &'static str {
        match self {
            Stop::Survived => "survived",
            Stop::Overturned => "overturned",
            Stop::RestForGood => "rest_for_good",
            Stop::EventLimit => "event_limit",
        }
    }
}

/// What happened at a point of the history.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    Start,
    Sample,
    Uplift,
    Impact,
    Rest,
    Overturn,
    RecordEnd,
}

impl EventKind {
    pub fn as_str(self) -> &'static str {
        match self {
            EventKind::Start => "start",
            EventKind::Sample => "sample",
            EventKind::Uplift => "uplift",
            EventKind::Impact => "impact",
            EventKind::Rest => "rest",
            EventKind::Overturn => "overturn",
            EventKind::RecordEnd => "record_end",
        }
    }
}

/// A point of the response history.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HistoryPoint {
    pub t_s: f64,
    pub x: f64,
    pub v: f64,
    /// Pivot: +1, −1, or 0 at rest.
    pub pivot: i8,
    /// ψ̈ at that instant (record normalised to unit peak).
    pub psi: f64,
    pub kind: EventKind,
}

/// Receives history points; `()` ignores them at no cost.
pub trait Observer {
    fn point(&mut self, p: HistoryPoint);
}

impl Observer for () {
    #[inline(always)]
    fn point(&mut self, _: HistoryPoint) {}
}

/// Records every event and every `every`-th sample.
pub struct Recorder {
    pub every: usize,
    pub points: Vec<HistoryPoint>,
    samples_seen: usize,
}

impl Recorder {
    pub fn new(every: usize) -> Self {
        Recorder {
            every: every.max(1),
            points: Vec::new(),
            samples_seen: 0,
        }
    }
}

impl Observer for Recorder {
    fn point(&mut self, p: HistoryPoint) {
        if p.kind == EventKind::Sample {
            self.samples_seen += 1;
            if self.samples_seen % self.every != 0 {
                return;
            }
        }
        self.points.push(p);
    }
}

/// State of a rocking block: position, velocity, pivot `s = ±1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rocking {
    pub x: f64,
    pub v: f64,
    pub s: f64,
}

/// One stretch of a sample interval: from local offset `tau0` to `len`,
/// with `ψ̈(tau0 + σ) = g_a + g1 σ`.
#[derive(Debug, Clone, Copy)]
pub struct Stretch {
    pub tau0: f64,
    pub len: f64,
    pub g_a: f64,
    pub g1: f64,
}

/// How a stretch ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StretchEnd {
    /// Reached the end of the stretch without an event.
    End,
    /// Returned to `x = 0` at local offset `sigma` (from `tau0`) with velocity `v`.
    Impact { sigma: f64, v: f64 },
    /// Reached the overturning limit at `sigma`.
    Overturn { sigma: f64 },
    /// Never left the pivot (a departure swamped by rounding): at rest from
    /// `sigma` on, with no impact.
    Settled { sigma: f64 },
}

/// An integrator on one pivot.
pub trait Rocker {
    /// Uplift happens where |ψ̈| exceeds `η · uplift_factor()`.
    fn uplift_factor(&self) -> f64;
    /// Advances `state` over `stretch` or to its first event; raises
    /// `max_abs_x` to every extremum passed. On `End` and `Overturn`, `state`
    /// is the state at that instant (at overturning `|x|` is the limit); on
    /// `Impact` it is left for the driver to apply the impact map.
    fn rock(&mut self, stretch: Stretch, state: &mut Rocking, max_abs_x: &mut f64) -> StretchEnd;
    /// Free rocking after the record: the largest |x| still to come and
    /// whether the block passes the crest (`|x| = 1`), from energy.
    fn free_fate(&self, state: Rocking, eps: f64) -> energy::Fate;
}

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
    spec.validate()?;
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
    let limit = spec.overturn.limit(spec.alpha())?;
    Ok(match spec.model {
        Model::Linearized => drive(
            exc,
            spec,
            start,
            limit,
            &mut linear::Linear::new(spec.p, spec.eta, exc.dt_s, limit),
            obs,
        ),
        Model::Nonlinear { alpha_rad, rtol } => drive(
            exc,
            spec,
            start,
            limit,
            &mut nonlinear::Nonlinear::new(spec.p, spec.eta, alpha_rad, rtol, limit),
            obs,
        ),
        Model::Rk4 {
            substeps,
            alpha_rad,
        } => drive(
            exc,
            spec,
            start,
            limit,
            &mut rk4::Rk4::new(spec.p, spec.eta, alpha_rad, exc.dt_s, substeps, limit),
            obs,
        ),
    })
}

/// The event loop shared by every integrator.
fn drive<R: Rocker>(
    exc: &Excitation,
    spec: &RunSpec,
    start: Option<Rocking>,
    limit: f64,
    rocker: &mut R,
    obs: &mut impl Observer,
) -> Outcome {
    let dt = exc.dt_s;
    let psi = &exc.psi;
    let n = psi.len();
    let threshold = spec.eta * rocker.uplift_factor();
    let v_rest = spec.rest_tol * spec.p;
    let mut out = Outcome {
        max_abs_x: 0.0,
        stop: Stop::Survived,
        overturn_time_s: None,
        overturn_after_record: false,
        impacts: 0,
        first_uplift_s: None,
        intervals: 0,
    };
    let mut state: Option<Rocking> = start; // None = at rest
    let mut events: u64 = 0;
    let pivot = |st: &Option<Rocking>| st.map_or(0, |r| r.s as i8);
    if let Some(st) = start {
        out.max_abs_x = st.x.abs();
    }
    let (x0, v0) = start.map_or((0.0, 0.0), |r| (r.x, r.v));
    obs.point(HistoryPoint {
        t_s: 0.0,
        x: x0,
        v: v0,
        pivot: pivot(&start),
        psi: psi[0],
        kind: EventKind::Start,
    });

    for k in 0..n.saturating_sub(1) {
        if state.is_none() && exc.suffix_max[k] <= threshold {
            out.stop = Stop::RestForGood;
            return out;
        }
        out.intervals += 1;
        let (g0, g_end) = (psi[k], psi[k + 1]);
        let g1 = (g_end - g0) / dt;
        let t_k = k as f64 * dt;
        let mut tau = 0.0;
        // Forcing at `tau`; exactly ±threshold/… at an uplift instant.
        let mut g_a = g0;
        while tau < dt {
            events += 1;
            if events > MAX_EVENTS {
                out.stop = Stop::EventLimit;
                return out;
            }
            match state {
                None => {
                    // At rest: find where |ψ̈| first exceeds the threshold in [tau, dt].
                    let Some((at, side)) = uplift_in(g_a, g_end, g1, dt - tau, threshold) else {
                        break;
                    };
                    tau += at;
                    // The forcing at the crossing is exactly ±threshold (or beyond it
                    // when the block was already pushed past it at rest).
                    g_a = if at > 0.0 { side * threshold } else { g_a };
                    state = Some(Rocking {
                        x: 0.0,
                        v: 0.0,
                        s: side,
                    });
                    let t = t_k + tau;
                    out.first_uplift_s.get_or_insert(t);
                    obs.point(HistoryPoint {
                        t_s: t,
                        x: 0.0,
                        v: 0.0,
                        pivot: side as i8,
                        psi: g_a,
                        kind: EventKind::Uplift,
                    });
                }
                Some(ref mut st) => {
                    let stretch = Stretch {
                        tau0: tau,
                        len: dt - tau,
                        g_a,
                        g1,
                    };
                    match rocker.rock(stretch, st, &mut out.max_abs_x) {
                        StretchEnd::End => break,
                        StretchEnd::Overturn { sigma } => {
                            let t = t_k + tau + sigma;
                            out.stop = Stop::Overturned;
                            out.overturn_time_s = Some(t);
                            obs.point(HistoryPoint {
                                t_s: t,
                                x: st.x,
                                v: st.v,
                                pivot: st.s as i8,
                                psi: g_a + g1 * sigma,
                                kind: EventKind::Overturn,
                            });
                            return out;
                        }
                        StretchEnd::Settled { sigma } => {
                            tau += sigma;
                            g_a = g0 + g1 * tau;
                            state = None;
                            obs.point(HistoryPoint {
                                t_s: t_k + tau,
                                x: 0.0,
                                v: 0.0,
                                pivot: 0,
                                psi: g_a,
                                kind: EventKind::Rest,
                            });
                        }
                        StretchEnd::Impact { sigma, v } => {
                            tau += sigma;
                            g_a = g0 + g1 * tau;
                            out.impacts += 1;
                            let t = t_k + tau;
                            let v_plus = spec.eps * v;
                            if v_plus.abs() < v_rest {
                                state = None;
                                obs.point(HistoryPoint {
                                    t_s: t,
                                    x: 0.0,
                                    v: 0.0,
                                    pivot: 0,
                                    psi: g_a,
                                    kind: EventKind::Rest,
                                });
                            } else {
                                *st = Rocking {
                                    x: 0.0,
                                    v: v_plus,
                                    s: -st.s,
                                };
                                obs.point(HistoryPoint {
                                    t_s: t,
                                    x: 0.0,
                                    v: v_plus,
                                    pivot: st.s as i8,
                                    psi: g_a,
                                    kind: EventKind::Impact,
                                });
                            }
                        }
                    }
                }
            }
        }
        let (x, v) = state.map_or((0.0, 0.0), |r| (r.x, r.v));
        obs.point(HistoryPoint {
            t_s: (k + 1) as f64 * dt,
            x,
            v,
            pivot: pivot(&state),
            psi: g_end,
            kind: EventKind::Sample,
        });
    }

    // After the record: free rocking, settled by energy.
    let t_end = exc.duration_s();
    let (x, v) = state.map_or((0.0, 0.0), |r| (r.x, r.v));
    obs.point(HistoryPoint {
        t_s: t_end,
        x,
        v,
        pivot: pivot(&state),
        psi: 0.0,
        kind: EventKind::RecordEnd,
    });
    if let Some(mut st) = state {
        let fate = rocker.free_fate(st, spec.eps);
        if fate.passes_crest {
            out.max_abs_x = out.max_abs_x.max(limit);
            // It will overturn: follow the free motion (no forcing) to the limit
            // to time it. At most one impact lies on the way.
            out.stop = Stop::Overturned;
            out.overturn_after_record = true;
            let mut t = t_end;
            let horizon = 60.0 / spec.p;
            for _ in 0..8 {
                let stretch = Stretch {
                    tau0: 0.0,
                    len: horizon,
                    g_a: 0.0,
                    g1: 0.0,
                };
                let mut scratch = 0.0;
                match rocker.rock(stretch, &mut st, &mut scratch) {
                    StretchEnd::Overturn { sigma } => {
                        out.overturn_time_s = Some(t + sigma);
                        break;
                    }
                    StretchEnd::Settled { .. } => break,
                    StretchEnd::Impact { sigma, v } => {
                        t += sigma;
                        out.impacts += 1;
                        st = Rocking {
                            x: 0.0,
                            v: spec.eps * v,
                            s: -st.s,
                        };
                    }
                    StretchEnd::End => t += horizon,
                }
            }
        } else {
            out.max_abs_x = out.max_abs_x.max(fate.max_abs_x);
        }
    }
    out
}

/// First offset in `[0, len]` where `|g_a + g1 σ| > threshold`, and its side.
/// Strict: a record that only touches the threshold does not lift the block.
/// `g_b` is the forcing at the end of the stretch, the next sample itself
/// (not `g_a + g1·len`, which can round past a threshold the sample only touches).
fn uplift_in(g_a: f64, g_b: f64, g1: f64, len: f64, threshold: f64) -> Option<(f64, f64)> {
    if g_a.abs() > threshold {
        return Some((0.0, g_a.signum()));
    }
    if g_b.abs() <= threshold {
        // Linear in σ: if neither end exceeds it, no point between does.
        return None;
    }
    let side = g_b.signum();
    // g_a + g1 σ = side·threshold; the crossing lies in (0, len].
    let sigma = ((side * threshold - g_a) / g1).clamp(0.0, len);
    Some((sigma, side))
}
