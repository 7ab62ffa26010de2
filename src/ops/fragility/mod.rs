//! `rocking fragility`: the probability that a real block overturns at given
//! levels of an IM: in PGA from the paper's regression or a pipeline's fit,
//! in another IM from a study's IM table or the records' own capacities
//! ([`super::im_fragility`]); optionally the share of records it overturns
//! under when run through them directly.
//!
//! - this file: the request and the assessment;
//! - `direct`: `--direct`'s records and the progress of their searches;
//! - `laws`: where the capacities come from (the paper, a study's fit, IM
//!   and damage tables), checked to be the pipeline's as it stands;
//! - `error`: every refusal.

mod direct;
mod error;
mod laws;

use super::im_fragility;

use crate::block::{Block, BlockError, Restitution};
use crate::floor::Building;
use crate::im::Im;
use crate::physics::LINEARIZATION_ERROR_PER_ALPHA2;
pub use direct::{DirectProgress, DirectRecords};
pub use error::FragilityError;
pub use laws::{default_records, laws, Laws, Source};

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
    /// The base's friction coefficient, checked: a block with μ < b/h is warned of.
    pub mu: Option<f64>,
}

/// One level of the answer.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Point {
    /// The level, in the IM's unit.
    pub iml: f64,
    /// For PGA: the level again (g), and the block's η there.
    pub pga_g: Option<f64>,
    pub eta: Option<f64>,
    pub probability: f64,
    /// With `--direct`: the share of records whose capacity the block exceeds.
    pub empirical: Option<f64>,
}

/// The answer.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Assessment {
    pub b_m: f64,
    pub h_m: f64,
    pub alpha_rad: f64,
    pub p: f64,
    pub eps: f64,
    /// The IM (`pga`, `pgv`, `sa(1.0)`, …) and its unit.
    pub im: String,
    pub unit: &'static str,
    /// `paper`, the pipeline file, or `direct` (the records' capacities).
    pub source: String,
    /// The median capacity in the IM's unit.
    pub median: f64,
    /// For PGA: the median η_c.
    pub eta_c_median: Option<f64>,
    pub beta: f64,
    /// Records run with `--direct`.
    pub records: Option<usize>,
    /// With `--direct`: the model the records were run with, and why.
    pub model: Option<String>,
    pub points: Vec<Point>,
    /// On a floor: the building's modes (`T,ζ,Γφ; …`); levels and
    /// capacities are then the ground's.
    pub floor: Option<String>,
    /// The base's friction coefficient, when given.
    pub mu: Option<f64>,
    /// With `mu`: whether the block slides before it rocks (μ < b/h).
    pub slides_first: Option<bool>,
    /// Where the regression is stretched for this block (none with
    /// `--direct`), and a block that slides first.
    pub warnings: Vec<String>,
}

/// Checks the request and computes the fragility.
pub fn assess(req: &Request) -> Result<Assessment, FragilityError> {
    let block = check(req)?;
    let (alpha, p, eps) = (block.alpha(), block.p(), block.eps);
    let im = req.im;
    let (source, records) =
        laws_and_records(&req.from, req.direct, &req.progress, 1, req.floor.as_ref())?;
    let floor = records
        .as_ref()
        .and_then(|r| r.floor())
        .map(|b| b.to_string());
    let direct = match records {
        Some(records) => Some(records.thresholds(&block, im, req.auto_tol)?),
        None => None,
    };
    let (median, beta, eta_c_median, name, mut warnings) = if im == Im::Pga {
        // On a floor only the records run through the building know the block.
        let law = match floor {
            Some(_) => Err(FragilityError::FloorNeedsDirect {
                from: source.name.clone(),
            }),
            None => source.median_beta(&block),
        };
        match (law, &direct) {
            (Ok((eta50, beta)), _) => {
                let w = if req.direct {
                    Vec::new()
                } else {
                    warnings(&block, req.auto_tol)
                };
                (alpha / eta50, beta, Some(eta50), source.name.clone(), w)
            }
            // A pipeline without a regression, or a floor: the records' own lognormal.
            (
                Err(FragilityError::NoFit { .. } | FragilityError::FloorNeedsDirect { .. }),
                Some((t, _)),
            ) => {
                let (m, b) = im_fragility::lognormal_of(t)
                    .ok_or_else(|| FragilityError::FewCapacities(im.name()))?;
                (m, b, Some(alpha / m), "direct".to_string(), Vec::new())
            }
            (Err(e), _) => return Err(e),
        }
    } else {
        match &direct {
            None => {
                let l = source.im_table(im)?.capacity(&block)?;
                let mut w = l.warnings;
                // The study's table rests on its model, as the regression does.
                w.extend(alpha_warning(&block, req.auto_tol));
                (l.median, l.beta, None, source.name.clone(), w)
            }
            Some((t, _)) => {
                let (m, b) = im_fragility::lognormal_of(t)
                    .ok_or_else(|| FragilityError::FewCapacities(im.name()))?;
                (m, b, None, "direct".to_string(), Vec::new())
            }
        }
    };
    let points = req
        .levels
        .iter()
        .map(|&x| Point {
            iml: x,
            pga_g: (im == Im::Pga).then_some(x),
            eta: (im == Im::Pga).then(|| alpha / x),
            probability: crate::stats::normal_cdf((x / median).ln() / beta),
            empirical: direct
                .as_ref()
                .map(|(t, _)| t.partition_point(|&c| c < x) as f64 / t.len() as f64),
        })
        .collect();
    let slides_first = req.mu.map(|mu| crate::block::slides_first(mu, alpha));
    if slides_first == Some(true) {
        warnings.push(crate::block::sliding_warning(req.mu.unwrap_or(0.0), alpha));
    }
    Ok(Assessment {
        b_m: req.b_m,
        h_m: req.h_m,
        alpha_rad: alpha,
        p,
        eps,
        im: im.name(),
        unit: im.unit(),
        source: name,
        median,
        eta_c_median,
        beta,
        records: direct.as_ref().map(|(t, _)| t.len()),
        model: direct.map(|(_, m)| m),
        points,
        floor,
        mu: req.mu,
        slides_first,
        warnings,
    })
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
            let records = DirectRecords::load(from, laws.plan.as_ref(), progress.clone(), floor)?;
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
    let err = LINEARIZATION_ERROR_PER_ALPHA2 * alpha * alpha;
    (err > auto_tol).then(|| format!(
        "α = {alpha:.3} rad: the regression rests on the linearised model, which errs by about {err:.1e} > {auto_tol:e} in η_c here; use --direct (the nonlinear model)"
    ))
}

/// Where the paper's regression is stretched for a block (not for
/// `--direct`): shared by `fragility` and `risk`, so both warn alike.
pub fn warnings(block: &Block, auto_tol: f64) -> Vec<String> {
    let mut w = Vec::new();
    if !(0.5..=0.95).contains(&block.eps) {
        w.push(format!(
            "ε = {:.3} is outside the regression's 0.5–0.95",
            block.eps
        ));
    }
    let p = block.p();
    if !(0.33..=10.0).contains(&p) {
        w.push(format!(
            "p = {p:.3} 1/s is outside the regression's 0.33–10 1/s"
        ));
    }
    w.extend(alpha_warning(block, auto_tol));
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
