//! What `fragility` is asked ([`Request`]), checked: the block, where its
//! capacities come from and the records `--direct` runs it through, the
//! warnings of a regression stretched for it.

use crate::block::{Block, BlockError, Restitution};
use crate::damage::{Dispersion, FitChoice, FitMethod, IfNotLognormal};
use crate::floor::Building;
use crate::im::Im;
use crate::physics::LINEARIZATION_ERROR_PER_ALPHA2;

use super::direct::{DirectProgress, DirectRecords};
use super::error::FragilityError;
use super::laws::{laws, Laws, Source};

/// What the user asks: the block (ε as given), where the capacities come
/// from, the IM and its levels.
#[derive(Debug, Clone)]
pub struct Request {
    pub b_m: f64,
    pub h_m: f64,
    /// `None`: Housner's bound 1 − 1.5 sin²α.
    pub eps: Restitution,
    pub im: Im,
    /// Levels of `im`, in its unit.
    pub levels: Vec<f64>,
    pub from: Source,
    /// Also run the block through the records.
    pub direct: bool,
    /// Where `--direct` reports its progress.
    pub progress: DirectProgress,
    /// The linearised model's accepted error in η_c; a stockier block is warned of.
    pub auto_tol: f64,
    /// The building whose floor the block stands on (`--direct` only);
    /// `None`: the ground.
    pub floor: Option<Building>,
    /// The base's friction coefficient, checked: a block with μ ≤ b/h is warned of.
    pub mu: Option<f64>,
    /// How the fragility is made from the capacities: a lognormal by the
    /// fractiles (the default) or by likelihood, or the records' curve.
    pub method: FitMethod,
    /// Several damage states: one β for all (the default), or each its own.
    pub dispersion: Dispersion,
    /// Where the capacities fail the lognormal check: their curve (the
    /// default) or the lognormal anyway.
    pub if_not_lognormal: IfNotLognormal,
    /// Which orientations of the records (`--direct`; pairs for random and
    /// worst).
    pub orient: super::Orient,
    /// A logic tree over ε and the model: a fragility per branch and their
    /// mixture.
    pub tree: Option<crate::tree::Tree>,
}

impl Request {
    /// Its orientations for a fragility in `im` (a pair's IM needs pairs).
    pub fn orient_for(&self, im: Im) -> super::Orient {
        super::Orient {
            pair_im: im.pair(),
            ..self.orient
        }
    }

    /// How the block's fragility is made.
    pub fn fit(&self) -> FitChoice {
        FitChoice {
            method: self.method,
            dispersion: self.dispersion,
            if_not_lognormal: self.if_not_lognormal,
        }
    }
}

/// Where the capacities come from, and with `direct` the records the
/// `blocks` blocks are run through (read once for every block; the progress
/// counts them all).
pub fn laws_and_records(
    from: &Source,
    direct: bool,
    progress: &DirectProgress,
    blocks: usize,
    floor: Option<&Building>,
    orient: super::Orient,
) -> Result<(Laws, Option<DirectRecords>), FragilityError> {
    let laws = laws(from)?;
    // A floor study's blocks stand on its building's floor.
    let planned = laws
        .plan
        .as_ref()
        .and_then(|p| p.records_study().ok())
        .and_then(|r| r.floor.as_ref());
    let floor = match (floor, planned) {
        (Some(_), Some(_)) => return Err(FragilityError::FloorTwice(laws.name.clone())),
        (None, Some(_)) if !direct => return Err(FragilityError::FloorStudy(laws.name.clone())),
        (asked, planned) => asked.or(planned),
    };
    if floor.is_some() && !direct {
        return Err(FragilityError::FloorNeedsDirect {
            from: laws.name.clone(),
        });
    }
    let records = match direct {
        true => {
            let records =
                DirectRecords::load(from, laws.plan.as_ref(), progress.clone(), floor, orient)?;
            records.expect_blocks(blocks);
            Some(records)
        }
        false => None,
    };
    Ok((laws, records))
}

/// The request's block, its levels and tolerance checked.
pub fn check(req: &Request) -> Result<Block, FragilityError> {
    crate::physics::check_auto_tol(req.auto_tol).map_err(FragilityError::AutoTol)?;
    if let Some(mu) = req.mu {
        crate::block::check_mu(mu).map_err(FragilityError::Mu)?;
    }
    let block = block(req.b_m, req.h_m, req.eps)?;
    if req.levels.is_empty() {
        return Err(FragilityError::NoLevel);
    }
    if let Some(&bad) = req.levels.iter().find(|g| !(**g > 0.0 && g.is_finite())) {
        return Err(FragilityError::Level(bad));
    }
    Ok(block)
}

/// Where the linearised model behind a regression or a study's table errs
/// by more than `auto_tol` for the block's α.
pub fn alpha_warning(block: &Block, auto_tol: f64) -> Option<String> {
    let alpha = block.alpha();
    let err = crate::physics::linearization_error(alpha);
    (err > auto_tol).then(|| format!(
        "α = {alpha:.3} rad: the regression rests on the linearised model, which errs by about {err:.1e} > {auto_tol:e} in η_c here; use --direct (the nonlinear model)"
    ))
}

/// The model warning of capacities not run for this block: a linearised
/// regression or study ([`alpha_warning`]), or a study that ran the
/// nonlinear equation at other slendernesses. Its η_c moves with α² as the
/// linearisation's error does (`LINEARIZATION_ERROR_PER_ALPHA2`·α²), so a
/// block of α_b read from capacities of α_s errs by about that constant
/// times |α_b² − α_s²|, α_s the study's nearest: warned of above
/// `auto_tol`, as the linearisation is.
pub fn model_warning(
    block: &Block,
    study: Option<&[crate::pipeline::BlockSpec]>,
    auto_tol: f64,
) -> Option<String> {
    let alphas: Vec<f64> = study
        .unwrap_or_default()
        .iter()
        .filter_map(|b| b.run.model.equation.alpha())
        .collect();
    let alpha = block.alpha();
    let Some(nearest) = alphas
        .iter()
        .copied()
        .min_by(|a, b| (a - alpha).abs().total_cmp(&(b - alpha).abs()))
    else {
        return alpha_warning(block, auto_tol);
    };
    let err = LINEARIZATION_ERROR_PER_ALPHA2 * (alpha * alpha - nearest * nearest).abs();
    (err > auto_tol).then(|| {
        let lo = alphas.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = alphas.iter().copied().fold(0.0, f64::max);
        let span = match lo == hi {
            true => format!("α = {lo:.3} rad"),
            false => format!("α {lo:.3}–{hi:.3} rad"),
        };
        format!(
            "α = {alpha:.3} rad: the study's capacities are of the nonlinear model at {span}, \
             whose η_c differs from this block's by about {err:.1e} > {auto_tol:e}; use --direct \
             (this block's own runs)"
        )
    })
}

/// Where a regression is stretched for a block (not for `--direct`): the
/// paper's beyond its grid (p 0.33–10 1/s, ε 0.5–0.95), a study's beyond
/// its blocks' (`blocks`, from `--from PIPELINE.toml`), as the study's IM
/// tables say of theirs. Shared by `fragility`, `risk` and `export`, so all
/// warn alike.
pub fn warnings(
    block: &Block,
    blocks: Option<&[crate::pipeline::BlockSpec]>,
    auto_tol: f64,
) -> Vec<String> {
    // The regression's law continues beyond the grid (a study's IM tables
    // instead hold at their nearest edge, and say so): said, as the two
    // can stand side by side in one answer.
    let mut w: Vec<String> = crate::fragility::stretched(block, blocks)
        .into_iter()
        .map(|s| format!("{s}: the fitted law is extrapolated there"))
        .collect();
    w.extend(model_warning(block, blocks, auto_tol));
    w
}

/// A real block from its half-width and half-height (m) and ε (`None`:
/// Housner's bound, refused where it is not positive).
pub fn block(b_m: f64, h_m: f64, eps: Restitution) -> Result<Block, FragilityError> {
    Block::new(b_m, h_m, eps).map_err(|e| match e {
        BlockError::Size { b, h } => FragilityError::Size { b, h },
        BlockError::Eps(e) => FragilityError::Eps(e),
        BlockError::HousnerEps { eps, ratio, alpha } => {
            FragilityError::HousnerEps { eps, ratio, alpha }
        }
        BlockError::Restitution(_) | BlockError::Mu(_) => {
            unreachable!("ε is given as a number or Housner's, and μ is not part of a block")
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A study's blocks, from a pipeline of `model` (TOML lines).
    fn study(model: &str) -> Vec<crate::pipeline::BlockSpec> {
        let text = format!(
            "name = \"a\"\n[records]\nat2 = [\"r\"]\n[model]\n{model}\n[blocks]\n\
             p = [1.0, 2.0, 4.0]\neps = [0.6, 0.75, 0.9]\n"
        );
        crate::pipeline::load_str(&text, std::path::Path::new("a.toml"))
            .unwrap()
            .blocks()
            .to_vec()
    }

    /// A block of slenderness `alpha` (rad), 1 m tall.
    fn of_alpha(alpha: f64) -> Block {
        Block::new(0.5 * alpha.tan(), 0.5, Restitution::Value(0.75)).unwrap()
    }

    /// A study that ran the nonlinear equation at α = 0.3 was said to rest
    /// on the linearised model for a block of that α, and a block of
    /// α = 0.05 took its capacities without a word. The warning is now of
    /// the study's α: none at it, and at 0.05 the error by hand, the
    /// linearisation's constant times |0.05² − 0.3²|. A linearised study
    /// warns as the regression does.
    #[test]
    fn a_nonlinear_study_warns_of_its_own_alpha() {
        let nonlinear = study("kind = \"nonlinear\"\nalpha = 0.3");
        let tol = 1e-2;
        assert_eq!(model_warning(&of_alpha(0.3), Some(&nonlinear), tol), None);
        let w = model_warning(&of_alpha(0.05), Some(&nonlinear), tol).unwrap();
        let err = LINEARIZATION_ERROR_PER_ALPHA2 * (0.3f64.powi(2) - 0.05f64.powi(2));
        assert!(
            w.contains("nonlinear model at α = 0.300 rad") && w.contains(&format!("{err:.1e}")),
            "{w}"
        );
        assert!(!w.contains("linearised"), "{w}");
        let linear = study("kind = \"linearized\"");
        let block = of_alpha(0.3);
        assert_eq!(
            model_warning(&block, Some(&linear), tol),
            alpha_warning(&block, tol)
        );
        assert!(alpha_warning(&block, tol).is_some());
        // The regression's (no study) is the linearisation's.
        assert_eq!(model_warning(&block, None, tol), alpha_warning(&block, tol));
    }
}
