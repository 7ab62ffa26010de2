//! The `solvers` section: every solver's speed against its error on bundled
//! records and closed-form pulses, the bare exact step as the floor, and
//! the plot beside BENCHMARKS.md.

use std::fmt::Write as _;

use super::options::{BenchError, BenchOptions};
use super::records::load;
use crate::timing::{self, Case, Row, Solver};
use rocking::ida::ImGrid;
use rocking::physics::{Equation, Integrator, Model};
use rocking::plot::{self, Series};
use rocking::pulse::{Cycle, Pulse, Shape};
use rocking::tables::atomic_write;

const ALPHA_NL: f64 = 0.1;

/// Far-field records with every time step of the set (0.0025 to 0.02 s).
const RECORDS: [&str; 4] = [
    "RSN848_LANDERS_CLW-LN",
    "RSN1148_KOCAELI_ARC000",
    "RSN1111_KOBE_NIS000",
    "RSN1633_MANJIL_ABBAR--L",
];

/// Every solver's speed against its error; writes the plot beside BENCHMARKS.md.
pub(super) fn solvers(
    args: &BenchOptions,
    say: &mut impl FnMut(&str),
) -> Result<String, BenchError> {
    let mut cases = Vec::new();
    let stems: &[&str] = if args.quick { &RECORDS[2..3] } else { &RECORDS };
    for stem in stems {
        let exc = load(&args.records, stem)?;
        for p in [1.0, 4.0] {
            cases.push(Case {
                name: format!("{stem} p={p}"),
                exc: exc.clone(),
                p,
                eps: 0.8,
                exact_eta_c: None,
            });
        }
    }
    // One lobe of 1 s sampled at 0.01 s, as a record would be.
    let pulse = |shape| {
        let half = Pulse {
            shape,
            cycle: Cycle::Half,
            t_d_s: 1.0,
        };
        half.excitation(100).expect("a valid pulse")
    };
    cases.push(Case {
        name: "rectangle f=2".into(),
        exc: pulse(Shape::Rect),
        p: 2.0,
        eps: 0.8,
        exact_eta_c: Some(rocking::pulse::housner_eq3(2.0)),
    });
    cases.push(Case {
        name: "exponential β=1 f=3".into(),
        exc: pulse(Shape::Exp { beta: 1.0 }),
        p: 3.0,
        eps: 0.8,
        exact_eta_c: None,
    });
    let solvers = solver_list(args.quick);
    // The reference of each equation: exact for the linearised one, DP5 at
    // a tolerance far below any setting measured for the nonlinear one.
    let reference = |s: &Solver| match s.model.equation {
        Equation::Linearized => Model::LINEARIZED,
        Equation::Nonlinear { alpha_rad } | Equation::SlideRock { alpha_rad, .. } => {
            Model::dp5(alpha_rad, 1e-13)
        }
    };
    let grid = ImGrid::default();
    let tol = 1e-6;
    let rows = timing::run(
        &cases, &solvers, reference, &grid, tol, args.reps, &mut *say,
    )?;
    say("floor: the bare exact step");
    let floor = timing::floor(&cases, args.reps.max(5));
    let svg = plot::log_log(
        "Speed against error: θmax/α at 1.25·η_c, bundled records and pulses",
        "median time per sample interval (ns)",
        "median relative error of θmax/α (1e-16: exact)",
        &series(&rows, &floor),
        1e-16,
    )?;
    let svg_name = "bench-speed-error.svg";
    atomic_write(&args.out_dir.join(svg_name), svg.as_bytes())?;
    Ok(solver_section(
        &rows, &floor, &cases, args, svg_name, grid.count, tol,
    ))
}

/// The solver settings measured.
fn solver_list(quick: bool) -> Vec<Solver> {
    let mut solvers = vec![Solver {
        family: "exact (linearised)",
        model: Model::LINEARIZED,
    }];
    let rk_steps: &[u32] = if quick {
        &[1, 8]
    } else {
        &[1, 2, 4, 8, 16, 32, 64]
    };
    for &m in rk_steps {
        solvers.push(Solver {
            family: "RK4 (linearised)",
            model: Model {
                equation: Equation::Linearized,
                integrator: Integrator::Rk4 { substeps: m },
            },
        });
    }
    let rtols: &[f64] = if quick {
        &[1e-4, 1e-8]
    } else {
        &[1e-3, 1e-4, 1e-6, 1e-8, 1e-10]
    };
    for &rtol in rtols {
        solvers.push(Solver {
            family: "DP5 (nonlinear, α = 0.1)",
            model: Model::dp5(ALPHA_NL, rtol),
        });
    }
    let tails: &[f64] = if quick {
        &[rocking::physics::DEFAULT_TAYLOR_TOL]
    } else {
        &[1e-8, 1e-10, 1e-12, 1e-14]
    };
    for &tol in tails {
        solvers.push(Solver {
            family: "Taylor (nonlinear, α = 0.1)",
            model: Model::taylor(ALPHA_NL, tol),
        });
    }
    let rk_nl: &[u32] = if quick { &[4] } else { &[1, 4, 16, 64] };
    for &m in rk_nl {
        solvers.push(Solver {
            family: "RK4 (nonlinear, α = 0.1)",
            model: Model {
                equation: Equation::Nonlinear {
                    alpha_rad: ALPHA_NL,
                },
                integrator: Integrator::Rk4 { substeps: m },
            },
        });
    }
    solvers
}

/// One line per solver family (speed against error), and the floor as a
/// vertical line across the errors drawn.
fn series(rows: &[Row], floor: &timing::Floor) -> Vec<Series> {
    let mut out: Vec<Series> = Vec::new();
    for r in rows {
        let point = (r.ns_per_interval, r.theta_err_median);
        match out.iter_mut().find(|s| s.name == r.solver.family) {
            Some(s) => s.points.push(point),
            None => out.push(Series {
                name: r.solver.family.to_string(),
                points: vec![point],
            }),
        }
    }
    let errors = rows
        .iter()
        .map(|r| r.theta_err_median)
        .filter(|e| e.is_finite() && *e > 1e-16);
    let (lo, hi) = errors.fold((1e-16f64, 1e-16f64), |(a, b), e| (a.min(e), b.max(e)));
    out.push(Series {
        name: "floor: bare exact step, no events".to_string(),
        points: vec![(floor.ns_per_interval, lo), (floor.ns_per_interval, hi)],
    });
    out
}

/// The CPU, the cores available, one thread, the profile.
pub(super) fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    // The steppers' loops this CPU runs (ROCKING_ISA may cap them).
    let loops = match rocking::physics::Isa::detected() {
        rocking::physics::Isa::V4 => "the x86-64-v4 loops (AVX-512)",
        rocking::physics::Isa::V3 => "the x86-64-v3 loops (AVX2)",
        rocking::physics::Isa::Baseline => "the baseline loops",
    };
    format!("{cpu}, {cores} cores available, {loops}; one thread; release profile")
}

fn solver_section(
    rows: &[Row],
    floor: &timing::Floor,
    cases: &[Case],
    args: &BenchOptions,
    svg: &str,
    levels: usize,
    tol: f64,
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "## Solvers: speed against error\n");
    let _ = writeln!(
        s,
        "Generated by `rocking-bench{}` on {}.\n",
        if args.quick { " --quick" } else { "" },
        machine()
    );
    let names: Vec<&str> = cases.iter().map(|c| c.name.as_str()).collect();
    let _ = writeln!(
        s,
        "Cases ({}): {}; ε = 0.8. Each solver traces the capacity over {levels} log-spaced levels \
         refined to Δη = {tol:e}, and runs once at η = 1.25·η_c(reference). Errors are against a \
         tight reference of the same equation: the exact stepper for the linearised equation, \
         DP5 at rtol 1e-13 for the nonlinear one (α = {ALPHA_NL} rad). Times are medians of {} \
         repetitions, then the median over cases; \"ns/interval\" is the run at 1.25·η_c divided by \
         its sample intervals (a run that settles for good stops early). The floor is the \
         closed-form step of the exact stepper with its sign tests over every interval of each \
         case, no event handled: the distance of each solver from it is what events and \
         bookkeeping cost.\n",
        cases.len(),
        names.join(", "),
        args.reps
    );
    let _ = writeln!(
        s,
        "| solver | setting | time/run (µs) | ns/interval | Δη_c median | Δη_c max | θmax/α rel. err median | max | closed form Δη_c |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|");
    let _ = writeln!(
        s,
        "| floor: bare exact step | no events | {:.1} (a whole record) | {:.1} | | | | | |",
        floor.time_per_pass_s * 1e6,
        floor.ns_per_interval
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {:.1} | {:.1e} | {:.1e} | {:.1e} | {:.1e} | {} |",
            r.solver.family,
            r.solver.label(),
            r.time_per_run_s * 1e6,
            r.ns_per_interval,
            r.eta_c_err_median,
            r.eta_c_err_max,
            r.theta_err_median,
            r.theta_err_max,
            r.closed_form_err.map_or("".into(), |e| format!("{e:.1e}"))
        );
    }
    let _ = writeln!(s, "\n![speed against error]({svg})\n");
    s
}
