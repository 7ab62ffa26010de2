//! A logic tree over the commands (`--tree`): each path's block and model
//! for `fragility`, `risk` and `export`, and what their answers say of the
//! tree (each branch's fragility, the mixture's median and equivalent β,
//! the dispersion split). The statistics are [`crate::tree`]'s.

use std::path::Path;

use serde::Serialize;

use super::fragility::{FragilityError, RunModel};
use crate::block::Restitution;
use crate::label::Label;
use crate::physics::ModelChoice;
use crate::risk::Fragility;
use crate::tree::{self, BetaSplit, Mixture, Tree, TreePath, TreeError};

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
/// is `own`, and the model its runs use.
pub fn branch(path: &TreePath, b_m: f64, h_m: f64, own: Restitution, auto_tol: f64) -> (Restitution, RunModel) {
    let eps = path.eps.map_or(own, |e| e.restitution(b_m, h_m));
    let model = RunModel {
        choice: path.model.unwrap_or(ModelChoice::Auto),
        auto_tol,
    };
    (eps, model)
}

/// A tree's model branches need the records' runs.
pub fn check(tree: &Tree, direct: bool) -> Result<(), FragilityError> {
    match tree.model.first() {
        Some(b) if !direct => Err(FragilityError::ModelNeedsRuns(b.value.label())),
        _ => Ok(()),
    }
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
    /// FEMA P-58's split of the branches' lognormals: β_rtr, β_m,
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

/// What an answer says of a tree of `parts`.
pub fn info(tree: &Tree, parts: &[Part]) -> TreeInfo {
    let weighted: Vec<(f64, Fragility)> = parts
        .iter()
        .map(|p| (p.path.weight, p.fragility.clone()))
        .collect();
    let (mean_median, mean_beta) = Mixture { parts: &weighted }.median_beta();
    let lognormals: Option<Vec<(f64, f64)>> =
        parts.iter().map(|p| Some((p.median?, p.beta?))).collect();
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

/// The mean of `values` over the branches (their weights `weights`) and
/// its quantiles at [`tree::QUANTILES`].
pub fn mean_and_quantiles(values: &[f64], weights: &[f64]) -> (f64, Vec<f64>) {
    (
        tree::weighted_mean(values, weights),
        tree::QUANTILES
            .iter()
            .map(|&q| tree::weighted_quantile(values, weights, q))
            .collect(),
    )
}
