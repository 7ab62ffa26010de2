//! `risk --tree`: each branch's fragility and rates, combined into the
//! mean rate (the rate of the mixture of fragilities) and the branches'
//! quantiles at every site.

use super::answer::{site_info, BranchRate, FragilityInfo, SiteInfo};
use crate::hazard::HazardCurve;
use crate::ops::tree::{self as ops_tree, Part};
use crate::risk::{self, Fragility, SiteRisk};
use crate::tree::TreePath;

/// One branch of a block: its path, ε, fragility and risk at every site.
pub(super) struct Branch {
    pub path: TreePath,
    pub eps: f64,
    pub frag: Fragility,
    pub info: FragilityInfo,
    pub warnings: Vec<String>,
    pub risks: Vec<SiteRisk>,
    /// The whole fragility (its records' capacities, for the bootstrap).
    pub whole: crate::ops::damage::DamageFragility,
    /// The level below which the fragility is 0.
    pub cut: f64,
}

/// The block's fragility, warnings and sites over the tree: a one-branch
/// tree's are its branch's; otherwise each site's rate is the branches'
/// weighted mean (the mixture's, [`risk::mixed`]), with each branch's and
/// their quantiles beside it, and the fragility the mixture's.
pub(super) fn combine(
    tree: &crate::tree::Tree,
    branches: Vec<Branch>,
    sites: &[(usize, HazardCurve)],
    years: f64,
) -> (FragilityInfo, Vec<String>, Vec<SiteInfo>) {
    let weights: Vec<f64> = branches.iter().map(|b| b.path.weight).collect();
    let parts: Vec<Part> = branches
        .iter()
        .map(|b| Part {
            path: b.path.clone(),
            eps: b.eps,
            fragility: b.frag.clone(),
            median: b.info.median,
            beta: b.info.beta,
        })
        .collect();
    let tree_info = ops_tree::info(tree, &parts);
    let warnings = ops_tree::merge_warnings(
        &branches
            .iter()
            .map(|b| (b.path.label.as_str(), &b.warnings[..]))
            .collect::<Vec<_>>(),
    );
    let several = branches.len() > 1;
    let infos = sites
        .iter()
        .enumerate()
        .map(|(s, (k, c))| {
            let rates: Vec<f64> = branches.iter().map(|b| b.risks[s].annual_rate).collect();
            let r = match several {
                true => risk::mixed(
                    &branches
                        .iter()
                        .map(|b| (b.path.weight, b.risks[s].clone()))
                        .collect::<Vec<_>>(),
                ),
                false => branches[0].risks[s].clone(),
            };
            // The mean rate is the mixture's (site_info's `annual_rate`).
            let mut info = site_info(*k, c, &r, years);
            let quantiles = ops_tree::quantiles(&rates, &weights);
            // The mean probability within the years, Σ wᵢ (1 − e^(−λᵢ·t)), as
            // OpenQuake's mean damage over a taxonomy mapping states it.
            if several {
                info.p_overturn_in_years = branches
                    .iter()
                    .zip(&rates)
                    .map(|(b, &r)| b.path.weight * risk::probability_in(r, years))
                    .sum();
            }
            info.branches = branches
                .iter()
                .zip(&rates)
                .map(|(b, &annual_rate)| BranchRate {
                    branch: b.path.label.clone(),
                    weight: b.path.weight,
                    annual_rate,
                })
                .collect();
            info.quantile_annual_rates = Some(quantiles);
            info
        })
        .collect();
    let mut info = branches
        .into_iter()
        .next()
        .expect("a tree has a branch")
        .info;
    if several {
        info.fit = "mixture";
        info.median = tree_info.mean_median;
        info.beta = tree_info.mean_beta;
        info.lognormal_p = None;
    }
    info.tree = Some(tree_info);
    (info, warnings, infos)
}
