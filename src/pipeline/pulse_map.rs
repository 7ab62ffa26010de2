//! `[pulses]`: a pulse map's section resolved into its plan (the records
//! study's sections refused, not ignored).

use std::path::Path;

use super::checks::{check_eps, model, refuse_repeats, values};
use super::plan::*;
use super::raw::*;
use crate::physics::{ModelChoice, Overturn};

/// A pipeline with `[pulses]`: the pulse map, its model and criterion
/// (`escape` unless `model.overturn` says otherwise); the records study's
/// sections are refused, not ignored.
pub(super) fn resolve(raw: RawPipeline, name: String, base: &Path) -> Result<Plan, String> {
    use crate::pulse::Cycle;
    let rp = raw.pulses.as_ref().expect("called for [pulses]");
    refuse_stray_sections(&raw)?;
    let (model, overturn, solver) = model(&raw.model, Overturn::Escape)?;
    if model == ModelChoice::Auto {
        return Err("a pulse map takes `model.kind` = \"linearized\" or \"nonlinear\"".into());
    }
    if model == ModelChoice::Nonlinear && raw.model.alpha.is_none() {
        return Err("`model.kind` = \"nonlinear\" needs `model.alpha`".into());
    }
    let shapes = pulse_shapes(rp)?;
    if let Some(betas) = &rp.beta {
        refuse_repeats("pulses.beta", betas)?;
    }
    let cycle: Cycle = rp
        .cycle
        .parse()
        .map_err(|e: crate::physics::PhysicsError| format!("`pulses.cycle`: {e}"))?;
    let f = values("pulses.f", &rp.f)?;
    for &x in &f {
        crate::pulse::check_f(x).map_err(|e| format!("`pulses.f`: {e}"))?;
    }
    let mut eta = values("pulses.eta", &rp.eta)?;
    if let Some(bad) = eta.iter().find(|e| !(e.is_finite() && **e > 0.0)) {
        return Err(format!("`pulses.eta` holds {bad}; η must be positive"));
    }
    eta.sort_by(|a, b| b.total_cmp(a));
    let eps = values("pulses.eps", &rp.eps)?;
    for &e in &eps {
        check_eps("pulses.eps", e)?;
    }
    if let Some(n) = rp.intervals {
        if n < 2 || n % 2 != 0 || n > crate::pulse::MAX_INTERVALS {
            return Err(format!(
                "`pulses.intervals` = {n}: an even number from 2 to {}",
                crate::pulse::MAX_INTERVALS
            ));
        }
    }
    let walls = shapes.len() * eps.len() * f.len();
    if walls > MAX_PULSE_WALLS || walls.saturating_mul(eta.len()) > MAX_PULSE_CELLS {
        return Err(format!(
            "the pulse map has {walls} walls and {} cells; at most {MAX_PULSE_WALLS} and {MAX_PULSE_CELLS}",
            walls.saturating_mul(eta.len())
        ));
    }
    Ok(Plan {
        name,
        description: raw.description.unwrap_or_default(),
        model,
        solver,
        auto_tol: raw.model.auto_tol,
        overturn,
        study: StudyKind::PulseMap(PulsePlan {
            shapes,
            cycle,
            f,
            eta,
            eps,
            intervals: rp.intervals,
            alpha: raw.model.alpha,
        }),
        base: base.to_path_buf(),
    })
}

/// The records study's sections, refused in a pulse map rather than ignored.
fn refuse_stray_sections(raw: &RawPipeline) -> Result<(), String> {
    let stray = [
        ("[records]", raw.records.is_some()),
        (
            "[blocks]",
            raw.blocks.p.is_some() || raw.blocks.eps.is_some(),
        ),
        ("[[block]]", !raw.block.is_empty()),
        ("[convergence]", raw.convergence.is_some()),
        ("[uncertainty]", raw.uncertainty.is_some()),
        ("[example]", raw.example.is_some()),
        ("[floor]", raw.floor.is_some()),
        ("[damage]", raw.damage.is_some()),
        ("[tree]", raw.tree.is_some()),
    ];
    if let Some((section, _)) = stray.iter().find(|(_, present)| *present) {
        return Err(format!(
            "a pulse map (`[pulses]`) runs no records: remove {section}"
        ));
    }
    Ok(())
}

/// `pulses.shape` and `pulses.beta`: the pulse shapes of the map.
fn pulse_shapes(rp: &RawPulses) -> Result<Vec<crate::pulse::Shape>, String> {
    use crate::label::Label;
    use crate::pulse::{Shape, ShapeKind};
    let kind = ShapeKind::parse_label(&rp.shape).map_err(|e| format!("`pulses.shape`: {e}"))?;
    let shapes = match (kind, &rp.beta) {
        (ShapeKind::Rect, None) => vec![Shape::Rect],
        (ShapeKind::Rect, Some(_)) => {
            return Err("`pulses.beta` is the exponential pulse's shape; `rect` takes none".into())
        }
        (ShapeKind::Exp, Some(betas)) if !betas.is_empty() => betas
            .iter()
            .map(|&beta| {
                if beta.is_finite() && beta.abs() <= 500.0 {
                    Ok(Shape::Exp { beta })
                } else {
                    Err(format!("`pulses.beta` = {beta} must lie in [−500, 500]"))
                }
            })
            .collect::<Result<_, _>>()?,
        (ShapeKind::Exp, _) => {
            return Err("`pulses.shape` = \"exp\" needs `pulses.beta`, a list of β".into())
        }
    };
    Ok(shapes)
}
