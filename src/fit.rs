//! The two-step regression of the capacity fractiles (pure; docs/MODEL.md §6).
//!
//! Step 1, per ε and fractile: `η_c(p) = a (1 − e^{−b p})^c` by nonlinear
//! least squares. Problem, solver and driver are separate (argmin's shape):
//! [`CapacityCurve`] gives residuals and the Jacobian, [`lm_step`] is one
//! Levenberg–Marquardt iteration (Marquardt's diagonal scaling), [`fit_curve`]
//! loops, tries several starting points and says why it stopped. The
//! parameters are fitted as logarithms, which keeps a, b, c positive (the
//! form needs it) and makes the start far less critical.
//!
//! Step 2, per fractile: a(ε) linear, b(ε) and c(ε) quadratic, by ordinary
//! least squares (QR).

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Why the solver stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The relative change of the cost fell below 1e-14.
    CostConverged,
    /// The step fell below 1e-12 of the parameters.
    StepConverged,
    /// The gradient vanished (below 1e-14 of the cost scale).
    GradientConverged,
    /// Hit the iteration cap without meeting a criterion.
    MaxIterations,
    /// No step lowered the cost even with the damping at its cap.
    Stalled,
    /// A parameter left the sane range (|ln a|, |ln b|, |ln c| > 20).
    Diverged,
    /// The solver stopped where the curve has collapsed to a constant
    /// (c < 10⁻³, or b·p > 20 at every p): b and c are then not identified by
    /// the data and the "minimum" lies at a bound, as when the data fall with p.
    Unbounded,
    /// Fewer than 3 finite points, or non-finite data.
    BadData,
}

impl Stop {
    pub fn converged(self) -> bool {
        matches!(
            self,
            Stop::CostConverged | Stop::StepConverged | Stop::GradientConverged
        )
    }
}

impl crate::label::Label for Stop {
    const ALL: &'static [Self] = &[
        Stop::CostConverged,
        Stop::StepConverged,
        Stop::GradientConverged,
        Stop::MaxIterations,
        Stop::Stalled,
        Stop::Diverged,
        Stop::Unbounded,
        Stop::BadData,
    ];
    fn label(self) -> &'static str {
        match self {
            Stop::CostConverged => "cost_converged",
            Stop::StepConverged => "step_converged",
            Stop::GradientConverged => "gradient_converged",
            Stop::MaxIterations => "max_iterations",
            Stop::Stalled => "stalled",
            Stop::Diverged => "diverged",
            Stop::Unbounded => "unbounded",
            Stop::BadData => "bad_data",
        }
    }
}

/// `η_c(p) = a (1 − e^{−b p})^c`.
pub fn curve(a: f64, b: f64, c: f64, p: f64) -> f64 {
    a * (-(-b * p).exp_m1()).powf(c)
}

/// The least-squares problem of step 1 in log-parameters θ = (ln a, ln b, ln c).
pub struct CapacityCurve<'a> {
    pub p: &'a [f64],
    pub y: &'a [f64],
}

impl CapacityCurve<'_> {
    /// Residuals r = model − data.
    pub fn residuals(&self, th: &Vector3<f64>) -> DVector<f64> {
        let (a, b, c) = (th[0].exp(), th[1].exp(), th[2].exp());
        DVector::from_iterator(
            self.p.len(),
            self.p
                .iter()
                .zip(self.y)
                .map(|(&p, &y)| curve(a, b, c, p) - y),
        )
    }

    /// ∂r/∂θ, analytically.
    pub fn jacobian(&self, th: &Vector3<f64>) -> DMatrix<f64> {
        let (a, b, c) = (th[0].exp(), th[1].exp(), th[2].exp());
        let mut j = DMatrix::zeros(self.p.len(), 3);
        for (i, &p) in self.p.iter().enumerate() {
            let e = (-b * p).exp();
            let u = -(-b * p).exp_m1(); // 1 − e^{−bp}
            let f = a * u.powf(c);
            j[(i, 0)] = f; // ∂f/∂ln a = f
            j[(i, 1)] = f * c * (b * p * e / u); // ∂f/∂ln b = f·c·(bp e^{−bp}/u)
            j[(i, 2)] = f * c * u.ln(); // ∂f/∂ln c = f·c·ln u
        }
        j
    }

    pub fn cost(&self, th: &Vector3<f64>) -> f64 {
        0.5 * self.residuals(th).norm_squared()
    }
}

/// One Levenberg–Marquardt iteration: the damped Gauss–Newton step for `lambda`.
pub fn lm_step(jac: &DMatrix<f64>, r: &DVector<f64>, lambda: f64) -> Option<Vector3<f64>> {
    let jtj: Matrix3<f64> = (jac.transpose() * jac)
        .fixed_view::<3, 3>(0, 0)
        .into_owned();
    let g: Vector3<f64> = (jac.transpose() * r).fixed_view::<3, 1>(0, 0).into_owned();
    let mut a = jtj;
    for k in 0..3 {
        a[(k, k)] += lambda * jtj[(k, k)].max(1e-300);
    }
    a.cholesky().map(|ch| -ch.solve(&g))
}

/// A fitted curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveFit {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    /// sqrt(mean squared residual).
    pub rms: f64,
    pub iterations: usize,
    pub stop: Stop,
}

const MAX_ITER: usize = 500;

fn drive(problem: &CapacityCurve, start: Vector3<f64>) -> (Vector3<f64>, f64, usize, Stop) {
    let mut th = start;
    let mut cost = problem.cost(&th);
    let mut lambda = 1e-3;
    for it in 1..=MAX_ITER {
        let r = problem.residuals(&th);
        let jac = problem.jacobian(&th);
        let grad = jac.transpose() * &r;
        if grad.amax() <= 1e-14 * (1.0 + cost) {
            return (th, cost, it, Stop::GradientConverged);
        }
        loop {
            let Some(step) = lm_step(&jac, &r, lambda) else {
                lambda *= 10.0;
                if lambda > 1e16 {
                    return (th, cost, it, Stop::Stalled);
                }
                continue;
            };
            let trial = th + step;
            let trial_cost = problem.cost(&trial);
            if trial_cost.is_finite() && trial_cost <= cost {
                let rel = (cost - trial_cost) / cost.max(1e-300);
                th = trial;
                lambda = (lambda / 3.0).max(1e-12);
                if th.amax() > 20.0 {
                    return (th, trial_cost, it, Stop::Diverged);
                }
                let done = if step.amax() <= 1e-12 * (1.0 + th.amax()) {
                    Some(Stop::StepConverged)
                } else if rel <= 1e-14 {
                    Some(Stop::CostConverged)
                } else {
                    None
                };
                cost = trial_cost;
                if let Some(stop) = done {
                    return (th, cost, it, stop);
                }
                break;
            }
            lambda *= 4.0;
            if lambda > 1e16 {
                return (th, cost, it, Stop::Stalled);
            }
        }
    }
    (th, cost, MAX_ITER, Stop::MaxIterations)
}

/// Step 1: fits `a (1 − e^{−bp})^c` to (p, y) from several starts and keeps
/// the lowest cost among converged runs (or the lowest overall, marked as
/// not converged).
pub fn fit_curve(p: &[f64], y: &[f64]) -> CurveFit {
    let finite: Vec<(f64, f64)> = p
        .iter()
        .zip(y)
        .filter(|(p, y)| p.is_finite() && y.is_finite() && **y > 0.0)
        .map(|(&p, &y)| (p, y))
        .collect();
    if finite.len() < 3 {
        return CurveFit {
            a: f64::NAN,
            b: f64::NAN,
            c: f64::NAN,
            rms: f64::NAN,
            iterations: 0,
            stop: Stop::BadData,
        };
    }
    let (ps, ys): (Vec<f64>, Vec<f64>) = finite.into_iter().unzip();
    let problem = CapacityCurve { p: &ps, y: &ys };
    let y_max = ys.iter().cloned().fold(0.0, f64::max);
    // Starts from the data: a just above the largest value; b, c on a coarse grid.
    let mut best: Option<(Vector3<f64>, f64, usize, Stop)> = None;
    for b0 in [0.3f64, 1.0, 3.0] {
        for c0 in [0.5f64, 1.5, 4.0] {
            let start = Vector3::new((1.05 * y_max).ln(), b0.ln(), c0.ln());
            let (th, cost, it, stop) = drive(&problem, start);
            let better = match &best {
                None => true,
                Some((_, bc, _, bs)) => {
                    (stop.converged() && !bs.converged())
                        || (stop.converged() == bs.converged() && cost < *bc)
                }
            };
            if better {
                best = Some((th, cost, it, stop));
            }
        }
    }
    let (th, cost, it, mut stop) = best.expect("nine starts");
    let p_min = ps.iter().cloned().fold(f64::INFINITY, f64::min);
    if stop.converged() && (th[2].exp() < 1e-3 || th[1].exp() * p_min > 20.0) {
        stop = Stop::Unbounded;
    }
    CurveFit {
        a: th[0].exp(),
        b: th[1].exp(),
        c: th[2].exp(),
        rms: (2.0 * cost / ps.len() as f64).sqrt(),
        iterations: it,
        stop,
    }
}

/// Step 2: least-squares polynomial of `degree` in x through (x, y);
/// coefficients c0, c1, … (None if under-determined or singular).
pub fn polyfit(x: &[f64], y: &[f64], degree: usize) -> Option<Vec<f64>> {
    let n = x.len();
    if n <= degree || y.len() != n || x.iter().chain(y).any(|v| !v.is_finite()) {
        return None;
    }
    let a = DMatrix::from_fn(n, degree + 1, |i, k| x[i].powi(k as i32));
    let b = DVector::from_column_slice(y);
    let qr = a.qr();
    let qtb = qr.q().transpose() * b;
    let r = qr.r();
    let sol = r.solve_upper_triangular(&qtb.rows(0, degree + 1).into_owned())?;
    Some(sol.iter().copied().collect())
}

/// 61 log-spaced p over the range of `ps` (ascending, non-empty): where the
/// fitted laws are drawn and their bands evaluated.
pub fn p_curve(ps: &[f64]) -> Vec<f64> {
    let (lo, hi) = (ps[0], ps[ps.len() - 1]);
    (0..=60)
        .map(|k| lo * (hi / lo).powf(k as f64 / 60.0))
        .collect()
}

/// Evaluates c0 + c1 x + c2 x² + ….
pub fn polyval(coeffs: &[f64], x: f64) -> f64 {
    coeffs.iter().rev().fold(0.0, |acc, c| acc * x + c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobian_matches_finite_differences() {
        let p = [0.33, 1.0, 3.0, 10.0];
        let y = [0.1, 0.3, 0.6, 0.7];
        let prob = CapacityCurve { p: &p, y: &y };
        let th = Vector3::new(0.7f64.ln(), 0.5f64.ln(), 1.7f64.ln());
        let j = prob.jacobian(&th);
        for k in 0..3 {
            let h = 1e-6;
            let mut tp = th;
            tp[k] += h;
            let mut tm = th;
            tm[k] -= h;
            let fd = (prob.residuals(&tp) - prob.residuals(&tm)) / (2.0 * h);
            for i in 0..p.len() {
                assert!(
                    (fd[i] - j[(i, k)]).abs() < 1e-8,
                    "∂r{i}/∂θ{k}: {} vs {}",
                    fd[i],
                    j[(i, k)]
                );
            }
        }
    }

    #[test]
    fn polyfit_recovers_a_quadratic_exactly() {
        let x = [0.5, 0.6, 0.7, 0.8, 0.9];
        let y: Vec<f64> = x.iter().map(|&e| 0.56 - 1.14 * e + 1.25 * e * e).collect();
        let c = polyfit(&x, &y, 2).unwrap();
        for (got, want) in c.iter().zip([0.56, -1.14, 1.25]) {
            assert!((got - want).abs() < 1e-10, "{c:?}");
        }
        assert!((polyval(&c, 0.75) - (0.56 - 1.14 * 0.75 + 1.25 * 0.5625)).abs() < 1e-12);
        assert!(polyfit(&[1.0, 2.0], &[1.0, 2.0], 2).is_none());
    }
}
