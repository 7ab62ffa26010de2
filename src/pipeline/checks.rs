//! Checkers shared by both study kinds: value lists and ranges, the
//! `[model]` section, ε, a block's run.

use super::plan::{BlockSpec, MAX_RANGE_VALUES};
use super::raw::*;
use crate::ida::{ImGrid, Spacing, MAX_LEVELS};
use crate::label::Label;
use crate::physics::RunSpec;
use crate::physics::{ModelChoice, NonlinearIntegrator, Overturn, Solver};

/// A list of values, or a `{ from, to, count, spacing }` range expanded,
/// under the key `key`.
pub(super) fn values(key: &str, v: &RawValues) -> Result<Vec<f64>, String> {
    let values = expand(key, v)?;
    refuse_repeats(key, &values)?;
    Ok(values)
}

/// Refuses a value given twice (a list's repeat, or a range whose `from`
/// equals its `to`): it would repeat rows, and a report keyed by the value
/// would show one row's results twice.
pub(super) fn refuse_repeats<T: PartialEq + std::fmt::Debug>(
    key: &str,
    values: &[T],
) -> Result<(), String> {
    for (i, v) in values.iter().enumerate() {
        if values[..i].contains(v) {
            return Err(format!("`{key}` holds {v:?} twice; give each value once"));
        }
    }
    Ok(())
}

/// Linear steps as the pipeline states them: when every value lies within
/// rounding (1e-12 relative) of a decimal of at most nine digits (0.5 to 0.95 in 10 values:
/// 0.55, 0.6, 0.65…), that decimal, read as a number, so that a table's
/// `eps` is 0.65, not 0.6499999999999999, and `eps = 0.65` finds it. Steps
/// that are not decimal (0 to 1 in 4 values) keep their computed values.
fn decimal_steps(values: Vec<f64>, step: f64) -> Vec<f64> {
    let near = |v: f64, d: usize| {
        let s = format!("{v:.d$}");
        let r: f64 = s.parse().expect("a number");
        ((r - v).abs() <= 1e-12 * v.abs().max(step.abs())).then_some(r)
    };
    (0..=9)
        .find_map(|d| {
            values
                .iter()
                .map(|&v| near(v, d))
                .collect::<Option<Vec<f64>>>()
        })
        .unwrap_or(values)
}

fn expand(key: &str, v: &RawValues) -> Result<Vec<f64>, String> {
    match v {
        RawValues::List(list) => {
            if list.is_empty() {
                return Err(format!("`{key}` is an empty list"));
            }
            Ok(list.clone())
        }
        RawValues::Range(r) => {
            if r.count == 0 {
                return Err(format!("`{key}.count` must be at least 1"));
            }
            if r.count > MAX_RANGE_VALUES {
                return Err(format!(
                    "`{key}.count` = {} is more than {MAX_RANGE_VALUES} values",
                    r.count
                ));
            }
            if r.count == 1 {
                // One value cannot span from `from` to `to`: a list says it.
                if r.to != r.from {
                    return Err(format!(
                        "`{key}`: count = 1 takes `from` = {} alone, not `to` = {}; give \
                         `{key} = [{}]`, or a count of 2 or more",
                        r.from, r.to, r.from
                    ));
                }
                return Ok(vec![r.from]);
            }
            if r.spacing == Spacing::Log && !(r.from > 0.0 && r.to > 0.0) {
                return Err(format!(
                    "`{key}`: log spacing needs positive `from` and `to`"
                ));
            }
            let n = (r.count - 1) as f64;
            let values: Vec<f64> = (0..r.count)
                .map(|k| {
                    let f = k as f64 / n;
                    if k == r.count - 1 {
                        return r.to;
                    }
                    match r.spacing {
                        Spacing::Linear => r.from + (r.to - r.from) * f,
                        Spacing::Log => r.from * (r.to / r.from).powf(f),
                    }
                })
                .collect();
            Ok(match r.spacing {
                Spacing::Linear => decimal_steps(values, (r.to - r.from) / n),
                Spacing::Log => values,
            })
        }
    }
}

/// `[model]`: the equation choice and the overturning criterion.
pub(super) fn model(
    raw: &RawModel,
    default: Overturn,
) -> Result<(ModelChoice, Overturn, Solver), String> {
    let model = ModelChoice::parse_label(&raw.kind).map_err(|e| format!("`model.kind`: {e}"))?;
    let overturn: Overturn = match &raw.overturn {
        None => default,
        Some(text) => text
            .parse()
            .map_err(|e: crate::physics::PhysicsError| format!("`model.overturn`: {e}"))?,
    };
    if overturn == Overturn::OnSide && model == ModelChoice::Linearized {
        return Err("`model.overturn` = \"on-side\" needs the nonlinear model".into());
    }
    let integrator = match raw.integrator.as_deref() {
        None => NonlinearIntegrator::Taylor,
        Some(name) => NonlinearIntegrator::parse_label(name)
            .map_err(|e| format!("`model.integrator`: {e}"))?,
    };
    // The linearised equation is stepped exactly: an integrator or its
    // tolerance would be read and do nothing.
    if let Some(key) = model.unused_solver_key(raw.integrator.is_some(), raw.rtol.is_some()) {
        return Err(format!(
            "`model.{key}` is the nonlinear model's; `model.kind` = \"linearized\" is stepped \
             exactly (give kind = \"nonlinear\" or \"auto\", or remove it)"
        ));
    }
    let solver = Solver::new(integrator, raw.rtol).map_err(|e| format!("`model.rtol`: {e}"))?;
    crate::physics::check_auto_tol(raw.auto_tol).map_err(|e| format!("`model.auto_tol`: {e}"))?;
    if let Some(a) = raw.alpha {
        crate::physics::check_alpha(a).map_err(|e| format!("`model.alpha`: {e}"))?;
    }
    Ok((model, overturn, solver))
}

/// ε under the key `key`: in (0, 1] ([`crate::block::check_eps`]).
pub(super) fn check_eps(key: &str, e: f64) -> Result<(), String> {
    crate::block::check_eps(e)
        .map(|_| ())
        .map_err(|err| format!("`{key}` holds {err}"))
}

/// A block's run at η = 1: its model resolved (`auto` per block) and the
/// whole checked, so that a block that cannot run is refused with the
/// pipeline, not found by the sweep.
pub(super) fn block_run(
    b: Unresolved,
    model: ModelChoice,
    solver: Solver,
    auto_tol: f64,
    overturn: Overturn,
) -> Result<BlockSpec, String> {
    let what = || match b.name.as_str() {
        "" => format!("the block p = {} 1/s, ε = {}", b.p, b.eps),
        name => format!("block `{name}`"),
    };
    // Said in the file's keys: the physics names the command line's.
    if model == ModelChoice::SlideRock && b.mu.is_none() {
        return Err(format!(
            "{}: `model.kind` = \"slide-rock\" needs the base's friction coefficient: give \
             the block's `mu`",
            what()
        ));
    }
    let (model, why) = model
        .resolve(
            b.alpha_rad,
            b.mu.map(|mu| crate::physics::friction::Friction {
                mu_s: mu,
                mu_k: b.mu_k.unwrap_or(mu),
            }),
            solver,
            auto_tol,
        )
        // The physics names the command line's `--alpha`: in the file's keys.
        .map_err(|e| {
            let e = e
                .to_string()
                .replace(
                    "--alpha, in rad, or its sizes",
                    "its `b` and `h`, or `model.alpha`",
                )
                .replace("--alpha, in rad", "its `b` and `h`, or `model.alpha`");
            format!("{}: {e}", what())
        })?;
    let run = RunSpec {
        overturn,
        ..RunSpec::new(b.p, b.eps, 1.0, model)
    };
    run.validate().map_err(|e| format!("{}: {e}", what()))?;
    Ok(BlockSpec {
        name: b.name,
        p: b.p,
        eps: b.eps,
        alpha_rad: b.alpha_rad,
        mu: b.mu,
        mu_k: b.mu_k,
        run,
        model_why: why,
    })
}

/// A block as the file gives it, before its model is resolved.
pub(super) struct Unresolved {
    pub(super) name: String,
    pub(super) p: f64,
    pub(super) eps: f64,
    pub(super) alpha_rad: Option<f64>,
    pub(super) mu: Option<f64>,
    pub(super) mu_k: Option<f64>,
}

/// `[im]`: the grid of intensity levels and the refinement tolerance.
pub(super) fn grid(im: &RawIm) -> Result<ImGrid, String> {
    if im.count > MAX_LEVELS {
        return Err(format!(
            "`im.count` = {} is more than {MAX_LEVELS} levels (each is a simulation per record and block; the paper used 100–200)",
            im.count
        ));
    }
    let grid = ImGrid {
        eta_max: im.eta_max,
        eta_min: im.eta_min,
        count: im.count,
        spacing: im.spacing,
    };
    grid.levels().map_err(|e| format!("`im`: {e}"))?;
    if !(im.tol > 0.0 && im.tol.is_finite()) {
        return Err(format!("`im.tol` = {} must be positive", im.tol));
    }
    grid.check_tol(im.tol)
        .map_err(|e| format!("`im.tol` = {}: {e}", im.tol))?;
    Ok(grid)
}

/// `[convergence] levels`: ascending, without repeats.
pub(super) fn convergence(raw: Option<&RawConvergence>) -> Result<Vec<usize>, String> {
    let Some(c) = raw else {
        return Ok(Vec::new());
    };
    if let Some(&n) = c.levels.iter().find(|&&n| n > MAX_LEVELS) {
        return Err(format!(
            "`convergence.levels` holds {n}, more than {MAX_LEVELS} levels"
        ));
    }
    if c.levels.len() < 2 || c.levels.iter().any(|&n| n < 2) {
        return Err(format!(
            "`convergence.levels` = {:?}: give at least two level counts, each at least 2",
            c.levels
        ));
    }
    refuse_repeats("convergence.levels", &c.levels)?;
    let mut levels = c.levels.clone();
    levels.sort_unstable();
    Ok(levels)
}

#[cfg(test)]
mod decimal_tests {
    use super::*;

    /// ε from 0.5 to 0.95 in ten values is the decimals 0.50, 0.55, …, 0.95
    /// (the bare computation gave 0.6499999999999999 and 0.7999999999999999);
    /// 0 to 1 in four values is thirds, not decimals.
    #[test]
    fn linear_steps_are_the_decimals_stated() {
        let r = |from, to, count| {
            RawValues::Range(RawRange {
                from,
                to,
                count,
                spacing: Spacing::Linear,
            })
        };
        let eps = expand("eps", &r(0.5, 0.95, 10)).unwrap();
        let want: Vec<f64> = [
            "0.5", "0.55", "0.6", "0.65", "0.7", "0.75", "0.8", "0.85", "0.9", "0.95",
        ]
        .iter()
        .map(|s| s.parse().unwrap())
        .collect();
        assert_eq!(eps, want);
        let thirds = expand("p", &r(0.0, 1.0, 4)).unwrap();
        assert_eq!(thirds[1], 1.0 / 3.0);
        assert_eq!(thirds[2], 2.0 / 3.0);
    }

    /// `{ from = 0.5, to = 0.95, count = 1 }` ran ε = 0.5 alone, `to`
    /// passed over without a word; one value is refused unless it is both.
    #[test]
    fn one_value_cannot_span_a_range() {
        let r = |from, to| {
            RawValues::Range(RawRange {
                from,
                to,
                count: 1,
                spacing: Spacing::Linear,
            })
        };
        let e = expand("eps", &r(0.5, 0.95)).unwrap_err();
        assert!(
            e.contains("`eps`: count = 1 takes `from` = 0.5 alone, not `to` = 0.95"),
            "{e}"
        );
        assert_eq!(expand("eps", &r(0.7, 0.7)).unwrap(), vec![0.7]);
    }
}
