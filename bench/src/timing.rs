//! Speed against error of the solvers (`rocking-bench`).
//!
//! For each solver setting, on every case (bundled records and closed-form
//! pulses, each at a few blocks): the capacity search and one run at
//! `η = 1.25·η_c` are timed, and their η_c and θmax/α are compared with a
//! tight reference of the same equation (the exact stepper for the
//! linearised equation, DP5 at rtol 1e-13 for the nonlinear one). Times are
//! medians over repetitions; no file I/O here (the CLI writes the report).

use std::time::Instant;

use rocking::ida::{capacity, ImGrid};
use rocking::physics::{simulate, Equation, Excitation, Model, PhysicsError, RunSpec};

/// One loading case: a record (or pulse) and one block.
pub struct Case {
    pub name: String,
    pub exc: Excitation,
    pub p: f64,
    pub eps: f64,
    /// Closed-form η_c of the linearised equation, when one exists.
    pub exact_eta_c: Option<f64>,
}

/// A solver setting under test.
#[derive(Debug, Clone, Copy)]
pub struct Solver {
    pub family: &'static str,
    pub model: Model,
}

impl Solver {
    pub fn label(&self) -> String {
        self.model.integrator.setting()
    }
}

/// Measurements of one solver setting, aggregated over the cases.
#[derive(Debug, Clone)]
pub struct Row {
    pub solver: Solver,
    /// Median time of one run (s).
    pub time_per_run_s: f64,
    /// Median time per sample interval of the run at 1.25·η_c (ns).
    pub ns_per_interval: f64,
    /// Median and largest |Δη_c| against the reference.
    pub eta_c_err_median: f64,
    pub eta_c_err_max: f64,
    /// Median and largest relative error of θmax/α at 1.25·η_c.
    pub theta_err_median: f64,
    pub theta_err_max: f64,
    /// Largest |η_c − closed form| over the pulse cases (linearised only).
    pub closed_form_err: Option<f64>,
}

pub(crate) fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    if v.is_empty() {
        return f64::NAN;
    }
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Capacity and timing of one solver on one case.
struct Measure {
    eta_c: f64,
    theta: f64,
    time_per_run_s: f64,
    ns_per_interval: f64,
}

fn measure(
    case: &Case,
    model: Model,
    grid: &ImGrid,
    tol: f64,
    eta_probe: f64,
    reps: usize,
) -> Result<Measure, PhysicsError> {
    let spec = RunSpec::new(case.p, case.eps, 1.0, model);
    let mut per_run = Vec::with_capacity(reps);
    let mut eta_c = f64::NAN;
    for _ in 0..reps {
        let t = Instant::now();
        let cap = capacity(&case.exc, &spec, grid, tol)?;
        per_run.push(t.elapsed().as_secs_f64() / cap.runs() as f64);
        eta_c = cap.eta_c.unwrap_or(f64::NAN);
    }
    let mut probe = Vec::with_capacity(reps);
    let mut theta = f64::NAN;
    for _ in 0..reps {
        let t = Instant::now();
        let out = simulate(
            &case.exc,
            &RunSpec {
                eta: eta_probe,
                ..spec
            },
        )?;
        probe.push(t.elapsed().as_secs_f64());
        theta = if out.overturned() {
            f64::INFINITY
        } else {
            out.max_abs_x
        };
    }
    let intervals = (case.exc.psi.len() - 1) as f64;
    Ok(Measure {
        eta_c,
        theta,
        time_per_run_s: median(&mut per_run),
        ns_per_interval: median(&mut probe) * 1e9 / intervals,
    })
}

/// The floor: the bare exact step over every interval of a case (no
/// events), the least any solver of the linearised equation can cost.
#[derive(Debug, Clone, Copy)]
pub struct Floor {
    /// Median time of one pass over the record (s).
    pub time_per_pass_s: f64,
    /// Median over cases of the time per sample interval (ns).
    pub ns_per_interval: f64,
}

/// Times [`rocking::physics::exact::Exact::bare_pass`] on every case.
pub fn floor(cases: &[Case], reps: usize) -> Floor {
    let (mut per_pass, mut ns) = (Vec::new(), Vec::new());
    for case in cases {
        let exact = rocking::physics::exact::Exact::new(case.p, 0.5, case.exc.dt_s, 1.0);
        let mut times = Vec::with_capacity(reps);
        for _ in 0..reps {
            let t = Instant::now();
            std::hint::black_box(exact.bare_pass(std::hint::black_box(&case.exc), 1.0));
            times.push(t.elapsed().as_secs_f64());
        }
        let t = median(&mut times);
        per_pass.push(t);
        ns.push(t * 1e9 / (case.exc.psi.len() - 1) as f64);
    }
    Floor {
        time_per_pass_s: median(&mut per_pass),
        ns_per_interval: median(&mut ns),
    }
}

/// Runs the benchmark: `solvers` against `reference(solver)` on every case.
pub fn run(
    cases: &[Case],
    solvers: &[Solver],
    reference: impl Fn(&Solver) -> Model,
    grid: &ImGrid,
    tol: f64,
    reps: usize,
    mut progress: impl FnMut(&str),
) -> Result<Vec<Row>, PhysicsError> {
    // References per (reference model, case), computed once: (η_c, probe η, θmax/α at the probe).
    type CaseRefs = Vec<(f64, f64, f64)>;
    let mut refs: Vec<(Model, CaseRefs)> = Vec::new();
    let mut rows = Vec::new();
    for solver in solvers {
        let ref_model = reference(solver);
        if !refs.iter().any(|(m, _)| *m == ref_model) {
            progress(&format!(
                "reference {} ({})",
                ref_model.integrator.name(),
                ref_model.integrator.setting()
            ));
            let mut v = Vec::new();
            for case in cases {
                let spec = RunSpec::new(case.p, case.eps, 1.0, ref_model);
                let c = capacity(&case.exc, &spec, grid, tol)?
                    .eta_c
                    .unwrap_or(f64::NAN);
                let probe = 1.25 * c;
                let out = simulate(&case.exc, &RunSpec { eta: probe, ..spec })?;
                let theta = if out.overturned() {
                    f64::INFINITY
                } else {
                    out.max_abs_x
                };
                v.push((c, probe, theta));
            }
            refs.push((ref_model, v));
        }
        let reference = &refs
            .iter()
            .find(|(m, _)| *m == ref_model)
            .expect("computed above")
            .1;
        progress(&format!("{} {}", solver.family, solver.label()));
        let (mut times, mut ns, mut ec, mut et) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut closed: Option<f64> = None;
        for (case, &(c_ref, probe, theta_ref)) in cases.iter().zip(reference) {
            let m = measure(case, solver.model, grid, tol, probe, reps)?;
            times.push(m.time_per_run_s);
            ns.push(m.ns_per_interval);
            ec.push((m.eta_c - c_ref).abs());
            et.push(if theta_ref.is_finite() && m.theta.is_finite() {
                (m.theta - theta_ref).abs() / theta_ref
            } else if theta_ref == m.theta {
                0.0
            } else {
                f64::INFINITY
            });
            if let (Some(exact), Equation::Linearized) = (case.exact_eta_c, solver.model.equation) {
                let e = (m.eta_c - exact).abs();
                closed = Some(closed.map_or(e, |c: f64| c.max(e)));
            }
        }
        let max = |v: &[f64]| v.iter().cloned().fold(0.0f64, f64::max);
        rows.push(Row {
            solver: *solver,
            time_per_run_s: median(&mut times),
            ns_per_interval: median(&mut ns),
            eta_c_err_max: max(&ec),
            eta_c_err_median: median(&mut ec),
            theta_err_max: max(&et),
            theta_err_median: median(&mut et),
            closed_form_err: closed,
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), 2.5);
    }
}
