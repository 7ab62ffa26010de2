//! A logic tree over the commands (`--tree`): each path's block and model
//! for `fragility`, `risk` and `export`, and what their answers say of the
//! tree (each branch's fragility, the mixture's median and equivalent β,
//! the dispersion split). The statistics are [`crate::tree`]'s.

use std::path::Path;

use serde::Serialize;

use super::fragility::{FragilityError, RunModel};
use crate::block::Restitution;
use crate::label::Label;
use crate::risk::Fragility;
use crate::tree::{self, BetaSplit, Mixture, Tree, TreeError, TreePath};

/// The tree `--tree` names: a named tree, or a TOML file.
pub fn load(name_or_file: &str) -> Result<Tree, TreeError> {
    if let Some(t) = Tree::named(name_or_file) {
        return Ok(t);
    }
    let path = Path::new(name_or_file);
    let text = std::fs::read_to_string(path).map_err(|e| {
        TreeError(format!(
            "{name_or_file}: {e}; --tree takes a TOML file or a named tree ({})",
            tree::named_list()
        ))
    })?;
    Tree::parse(&text, name_or_file)
}

/// A path's restitution for a block of half sizes `b_m`, `h_m` whose own
/// is `own`, and the model its runs use: the path's, else the command's
/// (`base`, [`RunModel::of_command`]).
pub fn branch(
    path: &TreePath,
    b_m: f64,
    h_m: f64,
    own: Restitution,
    base: RunModel,
) -> Result<(Restitution, RunModel), FragilityError> {
    // A block's own ε (an inventory's column) is not silently replaced.
    if let (Some(_), Restitution::Value(v)) = (path.eps, own) {
        return Err(FragilityError::TreeEps(v));
    }
    let eps = path.eps.map_or(own, |e| e.restitution(b_m, h_m));
    if let Restitution::Value(v) = eps {
        if !(v > 0.0 && v <= 1.0) {
            return Err(FragilityError::TreeBranchEps {
                branch: path.label.clone(),
                eps: v,
            });
        }
    }
    let model = RunModel {
        choice: path.model.unwrap_or(base.choice),
        ..base
    };
    Ok((eps, model))
}

/// The branches' warnings as one list: a warning of every branch once, one
/// of some branches with their labels.
pub fn merge_warnings(branches: &[(&str, &[String])]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for (label, warnings) in branches {
        for w in *warnings {
            let everywhere = branches.iter().all(|(_, o)| o.contains(w));
            let w = match everywhere || branches.len() == 1 {
                true => w.clone(),
                false => format!("branch {label}: {w}"),
            };
            if !out.contains(&w) {
                out.push(w);
            }
        }
    }
    out
}

/// One branch as the answers state it.
#[derive(Debug, Clone, Serialize)]
pub struct BranchInfo {
    pub branch: String,
    pub weight: f64,
    /// The block's ε on this branch.
    pub eps: f64,
    /// The model chosen by the branch (`None`: the command's own, auto).
    pub model: Option<&'static str>,
    /// The branch's fragility: its median (in the IM's unit) and β.
    pub median: Option<f64>,
    pub beta: Option<f64>,
}

/// What an answer says of its tree.
#[derive(Debug, Clone, Serialize)]
pub struct TreeInfo {
    /// The file, or the named tree.
    pub tree: String,
    pub branches: Vec<BranchInfo>,
    /// The mean fragility (the weighted mixture Σ wᵢ Pᵢ, not a lognormal):
    /// where it reaches 50 %, and its equivalent β, ln(x₈₄/x₁₆)/2.
    pub mean_median: Option<f64>,
    pub mean_beta: Option<f64>,
    /// FEMA P-58's split of the branches' lognormals (a branch of the
    /// records' curve by its equivalent β): β_rtr, β_m,
    /// β_total = √(β_rtr² + β_m²) about exp(Σ wᵢ ln mᵢ).
    pub split: Option<BetaSplit>,
    /// The quantiles the answers state over the branches.
    pub quantiles: Vec<f64>,
}

/// One branch's fragility, as the tree combines it.
pub struct Part {
    pub path: TreePath,
    pub eps: f64,
    pub fragility: Fragility,
    pub median: Option<f64>,
    pub beta: Option<f64>,
}

/// The branches' fragilities with their weights, as a [`Mixture`] takes
/// them.
pub fn weighted(parts: &[Part]) -> Vec<(f64, Fragility)> {
    parts
        .iter()
        .map(|p| (p.path.weight, p.fragility.clone()))
        .collect()
}

/// What an answer says of a tree of `parts`.
pub fn info(tree: &Tree, parts: &[Part]) -> TreeInfo {
    let weighted = weighted(parts);
    let (mean_median, mean_beta) = Mixture {
        parts: &weighted,
        below: &[],
    }
    .median_beta();
    // A branch of the records' own curve has no lognormal β; its spread in
    // the split is its equivalent β, ln(x₈₄/x₁₆)/2, as the mixture's is.
    let lognormals: Option<Vec<(f64, f64)>> = parts
        .iter()
        .map(|p| {
            let own = || {
                let alone = [(1.0, p.fragility.clone())];
                Mixture {
                    parts: &alone,
                    below: &[],
                }
                .median_beta()
                .1
            };
            Some((p.median?, p.beta.or_else(own)?))
        })
        .collect();
    let weights: Vec<f64> = parts.iter().map(|p| p.path.weight).collect();
    TreeInfo {
        tree: tree.name.clone(),
        branches: parts
            .iter()
            .map(|p| BranchInfo {
                branch: p.path.label.clone(),
                weight: p.path.weight,
                eps: p.eps,
                model: p.path.model.map(Label::label),
                median: p.median,
                beta: p.beta,
            })
            .collect(),
        mean_median,
        mean_beta,
        split: lognormals.and_then(|l| tree::beta_split(&l, &weights)),
        quantiles: tree::QUANTILES.to_vec(),
    }
}

/// The quantiles of `values` over the branches (their weights `weights`)
/// at [`tree::QUANTILES`]; their mean is the mixture's.
pub fn quantiles(values: &[f64], weights: &[f64]) -> Vec<f64> {
    tree::QUANTILES
        .iter()
        .map(|&q| tree::weighted_quantile(values, weights, q))
        .collect()
}

/// Levels of the mean curve a multilinear export carries over each
/// state's range (more where states' ranges differ or branches have kinks).
pub const MEAN_POINTS: usize = 60;

/// How the mean of a tree's damage-state fragilities is carried as one
/// function per state (pelicun takes one), and how far each way is from
/// the mixture: the largest |ΔP| over its 0.01–99.99 % range.
#[derive(Debug, Clone, Serialize)]
pub struct MeanFit {
    /// `curve` (multilinear through levels of the mixture, [`mean_shape`])
    /// or `lognormal` (the median exp(Σ wᵢ ln mᵢ) and β_total): whichever
    /// is closer, the curve where both are or where the lognormals cross.
    pub written_as: &'static str,
    pub curve_error: f64,
    /// `None` where a branch is not a lognormal.
    pub lognormal_error: Option<f64>,
    /// Whether the states' lognormals keep their order (no two cross
    /// within 0.1–99.9 %); `None` where a branch is not a lognormal.
    pub lognormals_in_order: Option<bool>,
}

/// Each state's mixture over the branches (weight, fragility, the level
/// below which the branch's block cannot move: 0 there, as `risk --tree`
/// and `fragility --tree` count it), as the closer of a multilinear curve
/// and FEMA P-58's lognormal of β_total; `None` where some state's mixture
/// never reaches 99.9 %.
///
/// Every state's curve has the same levels: each state's [`MEAN_POINTS`]
/// over its own 0.1–99.9 % range and every kink of a branch's records'
/// curve within them, P = 0 at the first and 1 at the last. Where the
/// branches' states are in order (a heavier state never the likelier),
/// their mixtures are at every level, so the curves, linear between
/// common levels, are everywhere. The lognormals (one β_total per state)
/// are written only where no two states' cross within 0.1–99.9 %
/// ([`crate::damage::crossing`]). A cut is a step, which the curve takes
/// from 0 at the cut to the mixture's P one part in 10⁶ above it.
pub fn mean_shape(
    branches: &[(f64, &crate::ops::damage::DamageFragility, f64)],
) -> Option<(crate::export::Shape, MeanFit)> {
    use crate::damage::{Curve, Lognormal};
    let n = branches.first()?.1.states.len();
    let weights: Vec<f64> = branches.iter().map(|b| b.0).collect();
    let below: Vec<f64> = branches.iter().map(|b| b.2).collect();
    let parts: Vec<Vec<(f64, Fragility)>> = (0..n)
        .map(|j| {
            branches
                .iter()
                .map(|(w, f, _)| Some((*w, f.states[j].fragility(f.method)?)))
                .collect::<Option<_>>()
        })
        .collect::<Option<_>>()?;
    let ranges: Vec<(f64, f64)> = parts
        .iter()
        .map(|p| {
            let mix = Mixture {
                parts: p,
                below: &below,
            };
            Some((mix.level(1e-3)?, mix.level(0.999)?))
        })
        .collect::<Option<_>>()?;
    let levels = mean_levels(&parts, &ranges, &below);
    let (mut curves, mut lognormals) = (Vec::new(), Vec::new());
    let (mut curve_error, mut lognormal_error) = (0.0f64, Some(0.0f64));
    for (p, &(lo, hi)) in parts.iter().zip(&ranges) {
        let mix = Mixture {
            parts: p,
            below: &below,
        };
        let mut pts: Vec<(f64, f64)> = levels.iter().map(|&x| (x, mix.probability(x))).collect();
        let last = pts.len() - 1;
        pts[0].1 = 0.0;
        pts[last].1 = 1.0;
        let curve = Curve::through(&pts)?;
        let lognormal = p
            .iter()
            .map(|(_, f)| match f {
                Fragility::Lognormal { median, beta } => Some((*median, *beta)),
                Fragility::Curve(_) => None,
            })
            .collect::<Option<Vec<_>>>()
            .and_then(|l| tree::beta_split(&l, &weights))
            .map(|s| Lognormal {
                median: s.median,
                beta: s.beta_total,
            });
        // The errors on a fine grid over the mixture's 0.01–99.99 % range,
        // but on a cut's step (no curve takes a step at one level).
        let (a, b) = (
            mix.level(1e-4).unwrap_or(lo),
            mix.level(0.9999).unwrap_or(hi),
        );
        let on_step = |x: f64| below.iter().any(|&c| x >= c && x <= c * (1.0 + 1e-6));
        for k in 0..=400 {
            let x = a * (b / a).powf(k as f64 / 400.0);
            if on_step(x) {
                continue;
            }
            let p = mix.probability(x);
            curve_error = curve_error.max((curve.probability(x) - p).abs());
            lognormal_error = match (lognormal_error, lognormal) {
                (Some(e), Some(l)) => {
                    let q = Fragility::Lognormal {
                        median: l.median,
                        beta: l.beta,
                    };
                    Some(e.max((q.probability(x) - p).abs()))
                }
                _ => None,
            };
        }
        curves.push(curve);
        lognormals.extend(lognormal);
    }
    let in_order = lognormals
        .windows(2)
        .all(|w| w[1].median >= w[0].median && crate::damage::crossing(&w[0], &w[1]).is_none());
    let lognormal_better =
        lognormal_error.is_some_and(|e| e < curve_error) && lognormals.len() == n && in_order;
    let fit = MeanFit {
        written_as: if lognormal_better {
            "lognormal"
        } else {
            "curve"
        },
        curve_error,
        lognormal_error,
        lognormals_in_order: (lognormals.len() == n).then_some(in_order),
    };
    let shape = match lognormal_better {
        true => crate::export::Shape::Lognormal(lognormals),
        false => crate::export::Shape::Curve(curves),
    };
    Some((shape, fit))
}

/// The levels every state's mean curve goes through (see [`mean_shape`]):
/// increasing, none within 1e-9 (relative) of the one before.
fn mean_levels(parts: &[Vec<(f64, Fragility)>], ranges: &[(f64, f64)], below: &[f64]) -> Vec<f64> {
    let from = ranges.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
    let to = ranges.iter().map(|r| r.1).fold(0.0, f64::max);
    let mut levels: Vec<f64> = ranges
        .iter()
        .flat_map(|&(lo, hi)| {
            (0..MEAN_POINTS).map(move |k| lo * (hi / lo).powf(k as f64 / (MEAN_POINTS - 1) as f64))
        })
        .chain(parts.iter().flatten().flat_map(|(_, f)| match f {
            Fragility::Curve(c) => c.levels().to_vec(),
            Fragility::Lognormal { .. } => Vec::new(),
        }))
        // A cut's step: from 0 at the cut (where the range starts, if it
        // lies inside) to the mixture's P just above it.
        .chain(
            below
                .iter()
                .filter(|&&c| c > 0.0)
                .flat_map(|&c| [c, c * (1.0 + 1e-6)]),
        )
        .filter(|&x| (from..=to).contains(&x))
        .collect();
    levels.sort_by(f64::total_cmp);
    let mut kept: Vec<f64> = Vec::with_capacity(levels.len());
    for x in levels {
        if kept.last().is_none_or(|&l| x - l > 1e-9 * x) {
            kept.push(x);
        }
    }
    kept
}
