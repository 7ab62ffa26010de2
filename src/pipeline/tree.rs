//! `[tree]`: a logic tree over the report's example block, each path's
//! block built as the pipeline builds its blocks (docs/MODEL.md §19).

use super::checks::check_eps;
use super::checks::{block_run, Unresolved};
use crate::physics::{ModelChoice, Overturn, Solver};

/// `[tree]`: the example block on each path of the tree (ε by the path, a
/// ratio to Housner's from its α; the model by the path, else the
/// pipeline's).
pub(super) fn tree_plan(
    raw: toml::Value,
    example: Option<&Unresolved>,
    model: ModelChoice,
    solver: Solver,
    auto_tol: f64,
    overturn: Overturn,
) -> Result<super::plan::TreePlan, String> {
    // `named = "…"` takes a named tree; otherwise the keys of a tree file.
    let named = raw.get("named").map(|n| n.as_str().map(str::to_string));
    let tree = match named {
        Some(Some(name)) if raw.as_table().is_some_and(|t| t.len() == 1) => {
            crate::tree::Tree::named(&name).ok_or_else(|| {
                format!(
                    "`[tree] named` = {name:?}; the named trees are {}",
                    crate::tree::named_list()
                )
            })?
        }
        Some(_) => {
            return Err("`[tree] named` takes a named tree's name, alone in `[tree]`".into())
        }
        None => crate::tree::Tree::of_value(raw, "[tree]").map_err(|e| e.0)?,
    };
    let Some(ex) = example else {
        return Err(
            "`[tree]` runs the report's example block over its branches: give `[example]`".into(),
        );
    };
    let branches =
        tree.paths()
            .into_iter()
            .map(|path| {
                let eps =
                    match (path.eps, ex.alpha_rad) {
                        (None, _) => ex.eps,
                        (Some(crate::tree::EpsBranch::Ratio(_)), None) => return Err(
                            "`[tree]`: a `ratio` to Housner's ε needs the example's α (b and h \
                                in `[example]`, or `model.alpha`)"
                                .to_string(),
                        ),
                        (Some(e), alpha) => e.eps_at(alpha.unwrap_or(0.0)),
                    };
                check_eps("[tree] eps", eps)?;
                let b = Unresolved {
                    name: ex.name.clone(),
                    p: ex.p,
                    eps,
                    alpha_rad: ex.alpha_rad,
                    mu: ex.mu,
                    mu_k: ex.mu_k,
                };
                let block = block_run(b, path.model.unwrap_or(model), solver, auto_tol, overturn)?;
                Ok(super::plan::TreeBranch {
                    label: path.label,
                    weight: path.weight,
                    block,
                })
            })
            .collect::<Result<Vec<_>, String>>()?;
    Ok(super::plan::TreePlan { tree, branches })
}
