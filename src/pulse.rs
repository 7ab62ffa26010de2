//! Pulse excitations, their closed-form safety walls and the walls found by
//! simulation (pure; MODEL.md §9–10; the paper's Eqs. 3–6).
//!
//! A pulse is one lobe of duration `t_d` (the *half cycle*) or that lobe
//! followed by its negative (the *full cycle*), with `f = p·t_d`:
//!
//! ```text
//! rectangular:  ψ̈ = 1 on the lobe
//! exponential:  ψ̈ = (1 − e^{β(1 − |2t/t_d − 1|)}) / (1 − e^β)     (paper Eq. 4)
//! ```
//!
//! β → −∞ gives the rectangle, β = 0 the triangle, β → +∞ a spike. Every
//! pulse is an [`Excitation`] whose discontinuities (a rectangle's start,
//! its switch between lobes) and kinks (the exponential lobe's peak) fall on
//! samples, so the exact stepper integrates a rectangle with no error but
//! rounding; the curved exponential lobe is interpolated linearly between
//! samples, an error of second order in the step (below 3e-8 relative in
//! η_w at the default step, [`default_intervals`]).
//!
//! The safety wall `η_w` of a pulse is the largest η at which the block
//! overturns ([`wall`]); `η_w,0` the largest at which it overturns with no
//! impact (Mode 0).

use std::fmt;

use crate::physics::{simulate, Equation, Excitation, Outcome, Overturn, PhysicsError, RunSpec};

/// The lobe's shape.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    Rect,
    /// The paper's Eq. 4 with shape parameter β (any finite value).
    Exp {
        beta: f64,
    },
}

/// A lobe's shape as a user names it (its parameter given apart).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShapeKind {
    Rect,
    Exp,
}

impl crate::label::Label for ShapeKind {
    const ALL: &'static [Self] = &[ShapeKind::Rect, ShapeKind::Exp];
    const WHAT: &'static str = "pulse shape";
    fn label(self) -> &'static str {
        match self {
            ShapeKind::Rect => "rect",
            ShapeKind::Exp => "exp",
        }
    }
    fn help(self) -> &'static str {
        match self {
            ShapeKind::Rect => "rectangular lobe (Housner's pulse)",
            ShapeKind::Exp => "the paper's exponential lobe (Eq. 4), shape β",
        }
    }
}

/// One lobe, or the lobe followed by its negative.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Cycle {
    Half,
    Full,
}

impl crate::label::Label for Cycle {
    const ALL: &'static [Self] = &[Cycle::Half, Cycle::Full];
    const WHAT: &'static str = "pulse cycle";
    fn label(self) -> &'static str {
        match self {
            Cycle::Half => "half",
            Cycle::Full => "full",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Cycle::Half => "one lobe",
            Cycle::Full => "the lobe, then its negative",
        }
    }
}

crate::deserialize_by_label!(ShapeKind, Cycle);

/// A pulse: shape, cycle and the lobe's duration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pulse {
    pub shape: Shape,
    pub cycle: Cycle,
    /// The duration of one lobe, t_d (s).
    pub t_d_s: f64,
}

impl Shape {
    pub fn name(self) -> &'static str {
        match self {
            Shape::Rect => "rect",
            Shape::Exp { .. } => "exp",
        }
    }

    pub fn beta(self) -> Option<f64> {
        match self {
            Shape::Rect => None,
            Shape::Exp { beta } => Some(beta),
        }
    }

    /// ψ̈ on one lobe at `u = t/t_d` ∈ [0, 1]; the peak (u = 1/2 for the
    /// exponential lobe) is exactly 1.
    pub fn lobe(self, u: f64) -> f64 {
        match self {
            Shape::Rect => 1.0,
            Shape::Exp { beta } => {
                let v = 1.0 - (2.0 * u - 1.0).abs();
                if beta == 0.0 {
                    v
                } else if beta < 0.0 {
                    (beta * v).exp_m1() / beta.exp_m1()
                } else {
                    // e^{β(v−1)} (1 − e^{−βv}) / (1 − e^{−β}): no overflow.
                    (beta * (v - 1.0)).exp() * (-beta * v).exp_m1() / (-beta).exp_m1()
                }
            }
        }
    }
}

impl Cycle {
    pub fn name(self) -> &'static str {
        match self {
            Cycle::Half => "half",
            Cycle::Full => "full",
        }
    }

    pub fn lobes(self) -> usize {
        match self {
            Cycle::Half => 1,
            Cycle::Full => 2,
        }
    }
}

impl std::str::FromStr for Cycle {
    type Err = PhysicsError;
    fn from_str(text: &str) -> Result<Self, PhysicsError> {
        <Cycle as crate::label::Label>::parse_label(text).map_err(PhysicsError::BadInput)
    }
}

/// The step a pulse is sampled with: a rectangle is exact at any step, so
/// it only keeps `p·dt ≤ 0.05` (as a record's step does for p ≤ 10) and at
/// least 64 intervals per lobe; the exponential lobe is curved, with
/// `|d²ψ̈/du²| ≤ 4β²` near its ends or its peak, so it takes
/// `4,000·max(2, |β|)` intervals per lobe (the interpolation error in η_w
/// then stays below 3e-8 relative for |β| ≤ 5 and f ≤ 10, measured over
/// the `pulse-exp` pipeline, and below the tests' 1e-6 at |β| = 50).
pub fn default_intervals(shape: Shape, f: f64) -> usize {
    let by_rate = (f / 0.05).ceil() as usize;
    let n = match shape {
        Shape::Rect => by_rate.max(64),
        Shape::Exp { beta } => by_rate.max((4000.0 * beta.abs().max(2.0)).ceil() as usize),
    };
    n + n % 2 // even: the exponential lobe's peak on a sample
}

/// Whether f = p·t_d can be mapped: a pulse is run with lobes of t_d = 1 s,
/// so the block's p is f, and p must lie in [`crate::physics::P_RANGE`].
pub fn check_f(f: f64) -> Result<(), String> {
    let range = crate::physics::P_RANGE;
    if range.contains(&f) {
        Ok(())
    } else {
        Err(format!(
            "f = p·t_d = {f} is outside [{}, {}]: pulses are run with t_d = 1 s, so the block's \
             p is f, and p must lie in that range (1/s)",
            range.start(),
            range.end()
        ))
    }
}

/// The largest number of intervals per lobe a pulse may be sampled with.
pub const MAX_INTERVALS: usize = 10_000_000;

impl Pulse {
    /// Checks the parameters.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        if !(self.t_d_s > 0.0 && self.t_d_s.is_finite()) {
            return Err(PhysicsError::BadInput(format!(
                "the pulse's lobe duration t_d = {} s must be positive",
                self.t_d_s
            )));
        }
        if let Shape::Exp { beta } = self.shape {
            if !beta.is_finite() || beta.abs() > 500.0 {
                return Err(PhysicsError::BadInput(format!(
                    "the exponential pulse's β = {beta} must lie in [−500, 500]"
                )));
            }
        }
        Ok(())
    }

    /// The excitation with `n` intervals per lobe (n even); the first lobe
    /// starts at the first sample and the excitation ends with the last lobe.
    pub fn excitation(&self, n: usize) -> Result<Excitation, PhysicsError> {
        self.validate()?;
        if n < 2 || n % 2 != 0 || n > MAX_INTERVALS {
            return Err(PhysicsError::BadInput(format!(
                "a pulse takes an even number of intervals per lobe from 2 to {MAX_INTERVALS}, not {n}"
            )));
        }
        let lobe: Vec<f64> = (0..=n)
            .map(|i| self.shape.lobe(i as f64 / n as f64))
            .collect();
        let (mut starts, mut ends) = (Vec::new(), Vec::new());
        for sign in [1.0, -1.0].into_iter().take(self.cycle.lobes()) {
            starts.extend(lobe[..n].iter().map(|v| sign * v));
            ends.extend(lobe[1..].iter().map(|v| sign * v));
        }
        Excitation::piecewise(self.t_d_s / n as f64, &starts, &ends)
    }

    /// The excitation for a block of frequency `p`, at the default step.
    pub fn excitation_for(&self, p: f64) -> Result<Excitation, PhysicsError> {
        self.excitation(default_intervals(self.shape, p * self.t_d_s))
    }

    /// The closed-form wall for a run of `spec` at `f`: the linearised
    /// model's [`Pulse::closed_form`], none for the nonlinear model.
    pub fn closed_form_for(&self, f: f64, spec: &RunSpec) -> Option<ClosedForm> {
        match spec.model.equation {
            Equation::Linearized => self.closed_form(f, spec.overturn),
            Equation::Nonlinear { .. } | Equation::SlideRock { .. } => None,
        }
    }

    /// The closed-form wall that applies to this pulse under `overturn`
    /// with the linearised model, if one does: Eq. 3 (rectangle, half
    /// cycle), Eq. 5 (exponential, half cycle; a half cycle's forcing never
    /// pushes back, so every criterion agrees), Eq. 6 (rectangle, full
    /// cycle, Mode 0 under `escape` only).
    pub fn closed_form(&self, f: f64, overturn: Overturn) -> Option<ClosedForm> {
        match (self.shape, self.cycle) {
            (Shape::Rect, Cycle::Half) => Some(ClosedForm {
                eta: housner_eq3(f),
                equation: "Eq. 3",
                of: WallKind::Any,
            }),
            (Shape::Exp { beta }, Cycle::Half) => Some(ClosedForm {
                eta: exponential_eq5(beta, f),
                equation: "Eq. 5",
                of: WallKind::Any,
            }),
            (Shape::Rect, Cycle::Full) if overturn == Overturn::Escape => Some(ClosedForm {
                eta: full_cycle_eq6(f),
                equation: "Eq. 6",
                of: WallKind::Mode0,
            }),
            _ => None,
        }
    }
}

impl fmt::Display for Pulse {
    /// `rect-half`, `exp(β=2)-full`, with `, t_d=…s` when t_d ≠ 1 s.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.shape {
            Shape::Rect => write!(f, "rect-{}", self.cycle.name())?,
            Shape::Exp { beta } => write!(f, "exp(β={beta})-{}", self.cycle.name())?,
        }
        if self.t_d_s != 1.0 {
            write!(f, " t_d={}s", self.t_d_s)?;
        }
        Ok(())
    }
}

/// Which wall a closed form gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WallKind {
    /// The largest η at which the block overturns (η_w).
    Any,
    /// The largest η at which it overturns with no impact (η_w,0).
    Mode0,
}

impl WallKind {
    /// The name of the wall it is, as tables and `--json` write it.
    pub fn column(self) -> &'static str {
        match self {
            WallKind::Any => "eta_w",
            WallKind::Mode0 => "eta_w_mode0",
        }
    }
}

/// A closed-form wall and which of the two walls it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosedForm {
    pub eta: f64,
    pub equation: &'static str,
    pub of: WallKind,
}

/// Housner (1963), the paper's Eq. 3: a half-cycle rectangle overturns the
/// linearised block iff `η < 1 − e^{−f}`.
pub fn housner_eq3(f: f64) -> f64 {
    -(-f).exp_m1()
}

/// The paper's Eq. 6: the full-cycle rectangle's Mode 0 wall `(1 − e^{−f})²`
/// (f for one lobe).
pub fn full_cycle_eq6(f: f64) -> f64 {
    housner_eq3(f).powi(2)
}

/// The paper's Eq. 5, the exponential half-cycle's wall,
///
/// ```text
/// η_w = 1/(1 − e^β) · { 1 − [ e^f (f + 2β) / (2f e^{f/2+β} − (f − 2β)) ]^{2β/(f − 2β)} }
/// ```
///
/// evaluated in logarithms (no overflow for |β| ≤ 500), with its removable
/// singularities: at β = 0 bridged by the straight line through points
/// 1e-5 to either side (error of order 1e-12); within 1 of f = 2β, where
/// B → 1 and its power's logarithm 2β·ln B/(f − 2β) is 0/0, written without
/// the cancellation ([`eq5_exponent_near_line`]; the straight line across
/// it was 1.3e-10 off, the formula as it stands up to 1e-8 at large β).
/// NaN for f ≤ 0.
pub fn exponential_eq5(beta: f64, f: f64) -> f64 {
    if f.is_nan() || f <= 0.0 {
        return f64::NAN;
    }
    let h = 1e-5;
    if beta.abs() < h {
        let (a, b) = (eq5_direct(-h, f), eq5_direct(h, f));
        return a + (b - a) * (beta + h) / (2.0 * h);
    }
    if beta > 0.0 && (f - 2.0 * beta).abs() < 1.0 {
        return eq5_of_exponent(beta, eq5_exponent_near_line(beta, f));
    }
    eq5_direct(beta, f)
}

/// Eq. 5's power's logarithm e = 2β·ln B/u near the line u = f − 2β = 0
/// (β > 0), where B → 1. Worked by hand from B: with N = e^f(f + 2β) − D
/// and D = 2f e^{f/2+β} − u, B − 1 = N/D = u·n/d, where (after dividing by
/// e^{2β})
///
/// ```text
/// n = 4β·(e^{u/2}(e^{u/2} − 1)/u − ½) + (2β + e^{−2β} − 1) + (e^{u/2} − 1)²
/// d = 2f·e^{u/2} − u·e^{−2β}
/// ```
///
/// so e = 2β·(n/d)·ln(1 + x)/x with x = u·n/d: no difference of near
/// equals but 2β + e^{−2β} − 1, taken by its series for small β. At u = 0
/// it is β + (e^{−2β} − 1)/2.
fn eq5_exponent_near_line(beta: f64, f: f64) -> f64 {
    let u = f - 2.0 * beta;
    let half = (u / 2.0).exp_m1();
    let grow = if u == 0.0 {
        0.0
    } else {
        (u / 2.0).exp() * half / u - 0.5
    };
    let y = 2.0 * beta;
    // y + e^{−y} − 1 = y²/2 − y³/6 + y⁴/24 − …
    let lead = if y < 1e-2 {
        y * y * (0.5 - y * (1.0 / 6.0 - y * (1.0 / 24.0 - y * (1.0 / 120.0 - y / 720.0))))
    } else {
        y + (-y).exp_m1()
    };
    let n = 4.0 * beta * grow + lead + half * half;
    let d = 2.0 * f * (u / 2.0).exp() - u * (-y).exp();
    let x = u * n / d;
    let ln1p_over = if x == 0.0 { 1.0 } else { x.ln_1p() / x };
    y * (n / d) * ln1p_over
}

/// ln(e^a − c) for e^a > c, without forming e^a when it would overflow.
fn ln_exp_minus(a: f64, c: f64) -> f64 {
    if a > 0.0 {
        a + (-c * (-a).exp()).ln_1p()
    } else {
        (a.exp() - c).ln()
    }
}

fn eq5_direct(beta: f64, f: f64) -> f64 {
    eq5_of_exponent(beta, eq5_exponent(beta, f))
}

/// ln of B^{2β/(f−2β)}, Eq. 5's power.
fn eq5_exponent(beta: f64, f: f64) -> f64 {
    // ln B = f + ln(f + 2β) − ln(2f e^{f/2+β} − (f − 2β)). With s = f + 2β
    // the denominator is s·(1 + 2f·g(s)), g(s) = (e^{s/2} − 1)/s > 0, so
    // B = e^f / (1 + 2f·g(s)): numerator and denominator vanish together at
    // f = −2β (β < 0), a removable singularity where B → e^f/(1 + f). Near
    // it (|s| < 1, where g cannot overflow) B is taken in that form; away
    // from it, in logarithms of both factors (same sign, so as positives).
    let s = f + 2.0 * beta;
    let ln_b = if s.abs() < 1.0 {
        let g = if s == 0.0 {
            0.5
        } else {
            (s / 2.0).exp_m1() / s
        };
        f - (2.0 * f * g).ln_1p()
    } else if s > 0.0 {
        let ln_den = (2.0 * f).ln() + ln_exp_minus(f / 2.0 + beta, (f - 2.0 * beta) / (2.0 * f));
        f + s.ln() - ln_den
    } else {
        // −(2f e^{f/2+β} − (f − 2β)) = (f − 2β) − 2f e^{f/2+β} > 0.
        let d = (f - 2.0 * beta) - 2.0 * f * (f / 2.0 + beta).exp();
        f + (-s).ln() - d.ln()
    };
    2.0 * beta / (f - 2.0 * beta) * ln_b
}

/// Eq. 5 from the logarithm `e` of its power: (e^e − 1)/(e^β − 1).
fn eq5_of_exponent(beta: f64, e: f64) -> f64 {
    if beta < 0.0 {
        e.exp_m1() / beta.exp_m1()
    } else if e > 0.0 {
        // (e^e − 1)/(e^β − 1) = e^{e−β} (1 − e^{−e})/(1 − e^{−β})
        (e - beta).exp() * (-e).exp_m1() / (-beta).exp_m1()
    } else {
        e.exp_m1() / beta.exp_m1()
    }
}

/// The walls of one pulse for one block, found by simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wall {
    /// The largest η at which the block overturns (None: not above the
    /// grid's bottom).
    pub eta_w: Option<f64>,
    /// The largest η at which it overturns with no impact.
    pub eta_w_mode0: Option<f64>,
    /// Impacts before overturning just below `eta_w` (0: Mode 0, 1: Mode 1…).
    pub mode: Option<u64>,
    /// Simulations run.
    pub runs: u64,
}

impl Wall {
    /// The wall of that kind.
    pub fn of(&self, kind: WallKind) -> Option<f64> {
        match kind {
            WallKind::Any => self.eta_w,
            WallKind::Mode0 => self.eta_w_mode0,
        }
    }
}

/// How [`wall`] searches: a log grid from η = 1 (nothing lifts: |ψ̈| ≤ 1)
/// down to `eta_min`, `count` levels, then bisection in ln η until the
/// bracket is `rel_tol` wide.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallSearch {
    pub eta_min: f64,
    pub count: usize,
    pub rel_tol: f64,
}

impl Default for WallSearch {
    /// 500 levels over five decades (2.3 % apart), refined to 1e-10: an
    /// overturning island narrower than one level above the wall could be
    /// missed, as in any grid search.
    fn default() -> Self {
        WallSearch {
            eta_min: 1e-5,
            count: 500,
            rel_tol: 1e-10,
        }
    }
}

/// The walls of `exc` (a pulse) for the block and criterion of `base`
/// (its η is ignored): `eta_w` is the first overturning level met from η = 1
/// down, refined; `eta_w_mode0` likewise for overturning with no impact.
pub fn wall(exc: &Excitation, base: &RunSpec, search: WallSearch) -> Result<Wall, PhysicsError> {
    if !(search.eta_min > 0.0 && search.eta_min < 1.0 && search.count >= 2 && search.rel_tol > 0.0)
    {
        return Err(PhysicsError::BadInput(format!(
            "bad wall search {search:?}"
        )));
    }
    let mut runs = 0u64;
    let mut run = |eta: f64| -> Result<Outcome, PhysicsError> {
        runs += 1;
        simulate(exc, &RunSpec { eta, ..*base })
    };
    let any = |o: &Outcome| o.overturned();
    let mode0 = |o: &Outcome| o.overturned() && o.impacts == 0;
    let ratio = search.eta_min.ln() / (search.count - 1) as f64;
    let level = |i: usize| (ratio * i as f64).exp();
    // Brackets (safe above, overturning below) for both walls.
    let (mut b_any, mut b_mode0) = (None, None);
    let mut above = 1.0;
    for i in 1..search.count {
        let eta = level(i);
        let o = run(eta)?;
        if b_any.is_none() && any(&o) {
            b_any = Some((above, eta, o));
        }
        if mode0(&o) {
            b_mode0 = Some((above, eta, o));
            break;
        }
        above = eta;
    }
    let mut refine = |bracket: Option<(f64, f64, Outcome)>,
                      pred: &dyn Fn(&Outcome) -> bool|
     -> Result<Option<(f64, Outcome)>, PhysicsError> {
        let Some((mut hi, mut lo, mut at_lo)) = bracket else {
            return Ok(None);
        };
        while hi / lo - 1.0 > search.rel_tol {
            let mid = (hi.ln() + 0.5 * (lo.ln() - hi.ln())).exp();
            if mid <= lo || mid >= hi {
                break;
            }
            let o = run(mid)?;
            if pred(&o) {
                (lo, at_lo) = (mid, o);
            } else {
                hi = mid;
            }
        }
        Ok(Some((lo, at_lo)))
    };
    let w_any = refine(b_any, &any)?;
    let w_mode0 = refine(b_mode0, &mode0)?;
    Ok(Wall {
        eta_w: w_any.map(|w| w.0),
        eta_w_mode0: w_mode0.map(|w| w.0),
        mode: w_any.map(|w| w.1.impacts),
        runs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lobes_peak_at_one_and_tend_to_their_limits() {
        for beta in [-300.0, -5.0, -1e-9, 0.0, 1e-9, 2.0, 300.0] {
            let s = Shape::Exp { beta };
            assert_eq!(s.lobe(0.5), 1.0, "β = {beta}");
            assert!(s.lobe(0.0).abs() < 1e-15 && s.lobe(1.0).abs() < 1e-15);
        }
        // β → 0: the triangle; β → −∞: the rectangle (1 − e^{βv} away from the ends).
        assert!((Shape::Exp { beta: 1e-9 }.lobe(0.2) - 0.4).abs() < 1e-9);
        assert!((Shape::Exp { beta: -300.0 }.lobe(0.2) - 1.0).abs() < 1e-15);
        // β = 1 at u = 1/4 (v = 1/2): (1 − e^{1/2})/(1 − e) by hand = 0.377541…
        let by_hand = (1.0 - 0.5f64.exp()) / (1.0 - 1f64.exp());
        assert!((Shape::Exp { beta: 1.0 }.lobe(0.25) - by_hand).abs() < 1e-15);
    }

    #[test]
    fn full_cycle_jumps_on_a_sample() {
        let p = Pulse {
            shape: Shape::Rect,
            cycle: Cycle::Full,
            t_d_s: 1.0,
        };
        let exc = p.excitation(4).unwrap();
        assert_eq!(
            exc.psi,
            vec![1.0, 1.0, 1.0, 1.0, -1.0, -1.0, -1.0, -1.0, -1.0]
        );
        assert_eq!(
            exc.psi_end(),
            vec![1.0, 1.0, 1.0, 1.0, -1.0, -1.0, -1.0, -1.0]
        );
        assert!(exc.slope.iter().all(|&s| s == 0.0));
        assert_eq!(exc.duration_s(), 2.0);
        assert_eq!(exc.suffix_max, vec![1.0; 9]);
    }

    /// Eq. 5 at points computed with mpmath at 50 digits (independent of
    /// this code), including the removable singularities and large |β|.
    #[test]
    #[allow(clippy::excessive_precision)] // mpmath's digits, as printed
    fn eq5_matches_high_precision_values() {
        let cases = [
            // (β, f, η_w by mpmath); β = 0 and f = 2β taken 1e-40 away.
            (1.0, 1.0, 0.28675836799266589),
            (-5.0, 8.0, 0.9746230221777602),
            (3.0, 3.0, 0.42054618156524175),
            (-1.0, 3.0, 0.68278370258940736),
            (0.0, 1.0, 0.33640686849762755),
            (0.0, 4.0, 0.68845936980016805),
            (1.0, 2.0, 0.44471611825027558),
            (2.0, 4.0, 0.55139914566263047),
            (5.0, 10.0, 0.60387536127280286),
            (-50.0, 2.0, 0.85362206374269092),
            (50.0, 2.0, 0.036707509336451083),
            (-300.0, 1.0, 0.63027963020613152),
            (300.0, 3.0, 0.0097223847179774125),
            (-1e7, 2.0, 0.8646646626292686),
            (1.0, 0.05, 0.020394857500877988),
            (-2.0, 0.3, 0.17090858847445738),
            (10.0, 20.0, 0.60651279604628792),
            // Beside the line f = 2β, from 1e-7 to ½ of it.
            (1.0, 2.0000002, 0.44471614309153575),
            (1.0, 2.001, 0.44484029830914506),
            (1.0, 2.00002, 0.44471860236589465),
            (1.0, 1.99999, 0.44471487618459021),
            (1.0, 2.5, 0.50089502816125014),
            (1.0, 1.6, 0.3904300553698321),
            (5.0, 10.0001, 0.60387765039890422),
            (100.0, 200.001, 0.60653179695426395),
            (499.0, 998.5, 0.60664457842715375),
            (0.01, 0.02001, 0.0098894641425687382),
            (0.001, 0.002002, 0.00099983241797735567),
            (3.0, 6.9, 0.6193656513181404),
        ];
        for (beta, f, want) in cases {
            let got = exponential_eq5(beta, f);
            assert!(
                (got - want).abs() < 1e-12 * want,
                "β = {beta}, f = {f}: {got}, mpmath {want}"
            );
        }
        // Near the singular lines, the bridge and the form without the
        // cancellation join the direct formula.
        for (beta, f, tol) in [(1e-5 * 1.01, 2.0, 1e-9), (2.0, 4.999, 1e-13)] {
            let (a, b) = (exponential_eq5(beta, f), eq5_direct(beta, f));
            assert!((a - b).abs() < tol, "β = {beta}, f = {f}: {a} vs {b}");
        }
        // f = −2β: numerator and denominator of B vanish together; the
        // limit B = e^f/(1 + f) and exponent 2β/(f − 2β) = −1/2 give
        // η_w = (1 − √((1 + f)/e^f))/(1 − e^{−f/2}) (worked by hand).
        for f in [0.5f64, 2.0, 10.0, 40.0] {
            let want = (1.0 - ((1.0 + f) * (-f).exp()).sqrt()) / -(-f / 2.0).exp_m1();
            let got = exponential_eq5(-f / 2.0, f);
            assert!((got - want).abs() < 1e-13, "f = {f}: {got}, limit {want}");
            // and the values beside it join the limit smoothly.
            for df in [1e-9, 1e-6, -1e-6] {
                let near = exponential_eq5(-f / 2.0, f + df);
                assert!(
                    (near - want).abs() < 1e-5,
                    "f = {f} + {df}: {near} vs {want}"
                );
            }
        }
        // β → −∞ is Housner's rectangle.
        assert!((exponential_eq5(-1e7, 2.0) - housner_eq3(2.0)).abs() < 1e-6);
    }
}
