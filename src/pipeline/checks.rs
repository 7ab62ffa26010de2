//! Checkers shared by both study kinds: value lists and ranges, the
//! `[model]` section, ε.

use super::plan::MAX_RANGE_VALUES;
use super::raw::*;
use crate::ida::Spacing;
use crate::physics::{ModelChoice, Overturn};

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
                return Ok(vec![r.from]);
            }
            if r.spacing == Spacing::Log && !(r.from > 0.0 && r.to > 0.0) {
                return Err(format!(
                    "`{key}`: log spacing needs positive `from` and `to`"
                ));
            }
            let n = (r.count - 1) as f64;
            Ok((0..r.count)
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
                .collect())
        }
    }
}

/// `[model]`: the equation choice and the overturning criterion.
pub(super) fn model(raw: &RawModel, default: Overturn) -> Result<(ModelChoice, Overturn), String> {
    let model = match raw.kind.as_str() {
        "linearized" => ModelChoice::Linearized,
        "nonlinear" => ModelChoice::Nonlinear,
        "auto" => ModelChoice::Auto,
        other => {
            return Err(format!(
                "`model.kind` = \"{other}\"; valid: linearized, nonlinear, auto"
            ));
        }
    };
    let overturn: Overturn = match &raw.overturn {
        None => default,
        Some(text) => text
            .parse()
            .map_err(|e: crate::physics::PhysicsError| format!("`model.overturn`: {e}"))?,
    };
    if overturn == Overturn::OnSide && model == ModelChoice::Linearized {
        return Err("`model.overturn` = \"on-side\" needs the nonlinear model".into());
    }
    crate::physics::check_rtol(raw.rtol).map_err(|e| format!("`model.rtol`: {e}"))?;
    crate::physics::check_auto_tol(raw.auto_tol).map_err(|e| format!("`model.auto_tol`: {e}"))?;
    if let Some(a) = raw.alpha {
        crate::physics::check_alpha(a).map_err(|e| format!("`model.alpha`: {e}"))?;
    }
    Ok((model, overturn))
}

/// ε under the key `key`: in (0, 1] ([`crate::block::check_eps`]).
pub(super) fn check_eps(key: &str, e: f64) -> Result<(), String> {
    crate::block::check_eps(e)
        .map(|_| ())
        .map_err(|err| format!("`{key}` holds {err}"))
}
