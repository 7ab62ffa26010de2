//! The hard cases' table ([`rocking::ida::HARD_CASES`]): plain and
//! certified searches against DP5's at 1e-13.

use std::fmt::Write as _;

use rayon::prelude::*;

use crate::sections::options::{BenchError, BenchOptions};
use crate::sections::records::load;
use rocking::ida::{capacity_certified, capacity_traced, Trace, HARD_CASES};
use rocking::physics::{Model, RunSpec};

/// The hard cases: plain searches by DP5 at several tolerances and by the
/// Taylor stepper at its default, and the certified searches from both
/// defaults, against DP5's search at 1e-13.
pub fn hard_cases_markdown(args: &BenchOptions) -> Result<String, BenchError> {
    use rocking::physics::{DEFAULT_RTOL, DEFAULT_TAYLOR_TOL};
    let mut s = String::new();
    let _ = writeln!(
        s,
        "**Hard cases** (kept in the tests, `tests/certify.rs` and `tests/taylor.rs`): η_c by plain \
         searches (DP5 at four tolerances, the Taylor stepper at its default {DEFAULT_TAYLOR_TOL:e}) \
         and by the certified search from each default (DP5 {DEFAULT_RTOL:e}, Taylor \
         {DEFAULT_TAYLOR_TOL:e}).\n"
    );
    let _ = writeln!(
        s,
        "| record | p | ε | α | grid | DP5 1e-8 | 1e-10 | 1e-12 | 1e-13 | Taylor | certified (DP5) | certified (Taylor) | Taylor's certification |"
    );
    let _ = writeln!(
        s,
        "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---|"
    );
    let rows = HARD_CASES
        .par_iter()
        .map(|c| {
            let exc = load(&args.records, c.record)?;
            let dp5 = |rtol| RunSpec::new(c.p, c.eps, 1.0, Model::dp5(c.alpha, rtol));
            let taylor = RunSpec::new(c.p, c.eps, 1.0, Model::taylor(c.alpha, DEFAULT_TAYLOR_TOL));
            let specs = [dp5(1e-8), dp5(1e-10), dp5(1e-12), dp5(1e-13), taylor];
            let plain = specs
                .iter()
                .map(|spec| {
                    Ok(
                        capacity_traced(&exc, spec, &c.grid, c.tol, Trace::StopAtFirst)?
                            .eta_c
                            .unwrap_or(0.0),
                    )
                })
                .collect::<Result<Vec<f64>, rocking::physics::PhysicsError>>()?;
            let certified =
                |spec| capacity_certified(&exc, &spec, &c.grid, c.tol, Trace::StopAtFirst);
            Ok((c, plain, certified(dp5(DEFAULT_RTOL))?, certified(taylor)?))
        })
        .collect::<Result<Vec<_>, BenchError>>()?;
    for (c, plain, by_dp5, by_taylor) in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} {:?} to {} | {:.6} | {:.6} | {:.6} | {:.6} | {:.6} | {:.6} | {:.6} | {} |",
            c.record,
            c.p,
            c.eps,
            c.alpha,
            c.grid.count,
            c.grid.spacing,
            c.grid.eta_min,
            plain[0],
            plain[1],
            plain[2],
            plain[3],
            plain[4],
            by_dp5.capacity.eta_c.unwrap_or(0.0),
            by_taylor.capacity.eta_c.unwrap_or(0.0),
            by_taylor.certification
        );
    }
    let _ = writeln!(s);
    Ok(s)
}
