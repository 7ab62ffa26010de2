//! Each block's entries in the engines' files: its states' functions by
//! its fit, its taxonomy, and over a logic tree each branch's (OpenQuake,
//! with the taxonomy mapping that weights them) or their mean (pelicun).

use super::request::{
    BranchExport, Entries, ExportOpError, ExportedBlock, Format, Request, TreeExport,
};
use crate::block::Block;
use crate::damage::FitMethod;
use crate::export::{Entry, Shape};
use crate::im::Im;
use crate::ops::damage::{self, DamageFragility};
use crate::ops::fragility::FragilityError;
use crate::ops::risk;

/// The block's entry: its states' functions by the fit its fragility is
/// made by (the records' curves, or a lognormal each).
pub(super) fn entry(
    e: &risk::BlockInfo,
    f: &DamageFragility,
    im: Im,
    block: &Block,
    floor: Option<&crate::floor::Building>,
) -> Result<Entry, ExportOpError> {
    let method = f.method;
    let refuse = |source| ExportOpError::Block {
        name: e.name.clone(),
        source,
    };
    let states = if method == FitMethod::Empirical {
        let curves = f
            .states
            .iter()
            .map(|s| match s.fragility(method) {
                Some(crate::risk::Fragility::Curve(c)) if c.complete() => Ok(c),
                _ if s.reached == Some(0) => Err(refuse(FragilityError::NeverReached {
                    state: s.name.clone(),
                    slides_first: e.slides_first == Some(true) && f.slides_on_mu.is_some(),
                })),
                Some(crate::risk::Fragility::Curve(c)) => Err(refuse(FragilityError::CurveShort {
                    state: s.name.clone(),
                    why: c
                        .shortfall(&s.name, f.unit, f.records.unwrap_or(0))
                        .unwrap_or_default(),
                })),
                Some(_) => Err(refuse(damage::no_fit(f, s, method))),
                None => Err(refuse(damage::no_fit(f, s, method))),
            })
            .collect::<Result<Vec<_>, _>>()?;
        Shape::Curve(curves)
    } else {
        Shape::Lognormal(lognormals(e, f)?)
    };
    let slides = match (e.mu, e.slides_first) {
        (Some(mu), Some(true)) => format!(
            "; slides before it rocks (μ = {mu} ≤ b/h = {:.4}): these fragilities assume it \
             does not",
            e.b_m / e.h_m
        ),
        _ => String::new(),
    };
    Ok(Entry {
        id: taxonomy(&e.name),
        description: format!(
            "{}: half-width {} m, half-height {} m, α = {:.4} rad, p = {:.4} 1/s, ε = {:.4}{slides}",
            e.name, e.b_m, e.h_m, e.alpha_rad, e.p, e.eps
        ),
        // The level below which no state is reached, as `risk` cuts it.
        no_damage_limit: damage::zero_below(block, im, floor, f.slides_on_mu),
        states,
    })
}

/// The block's states' lognormals by its fit, each with a spread.
fn lognormals(
    e: &risk::BlockInfo,
    f: &DamageFragility,
) -> Result<Vec<crate::damage::Lognormal>, ExportOpError> {
    let method = f.method;
    f.states
        .iter()
        .map(|s| {
            let refuse = |source| ExportOpError::Block {
                name: e.name.clone(),
                source,
            };
            let l = s
                .by(method)
                .ok_or_else(|| refuse(damage::no_fit(f, s, method)))?;
            if l.beta > 0.0 && l.beta.is_finite() {
                Ok(l)
            } else {
                Err(refuse(FragilityError::NoSpread {
                    state: s.name.clone(),
                    beta: l.beta,
                    reached: s.reached,
                }))
            }
        })
        .collect()
}

/// The block's name as a taxonomy the engines read as one key: every
/// character but letters, digits, `_`, `-` and `.` becomes `_`.
pub fn taxonomy(name: &str) -> String {
    name.trim()
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// What every block's export shares: the request, the IM, the capacities.
pub(super) struct Asked<'a> {
    pub req: &'a Request,
    pub im: Im,
    pub laws: &'a crate::ops::fragility::Laws,
    pub records: Option<&'a crate::ops::fragility::DirectRecords>,
}

/// Why a block cannot be exported: its fragility (named by the caller), or
/// what the engine cannot take.
pub(super) enum Refused {
    Fragility(FragilityError),
    Export(Box<ExportOpError>),
}

impl From<FragilityError> for Refused {
    fn from(e: FragilityError) -> Self {
        Refused::Fragility(e)
    }
}

impl From<ExportOpError> for Refused {
    fn from(e: ExportOpError) -> Self {
        Refused::Export(Box::new(e))
    }
}

/// One block's fragility (each branch's with a tree) and its entries in
/// `out`: its functions, its exposure entry and, with a tree, OpenQuake's
/// mapping of its taxonomy to its branches or pelicun's mean.
pub(super) fn of_block(
    at: &Asked,
    e: &risk::InventoryBlock,
    out: &mut Entries,
) -> Result<ExportedBlock, Refused> {
    let req = at.req;
    // The floor the records ran on (`--floor`, or a pipeline's `[floor]`
    // with `--from`), as `risk` and `fragility` take it.
    let floor = at.records.and_then(|r| r.floor());
    let fit = crate::damage::FitChoice {
        method: req.method,
        dispersion: req.dispersion,
        if_not_lognormal: req.if_not_lognormal,
    };
    let paths = req.tree.as_ref().map(|t| t.paths());
    let one = crate::tree::TreePath::plain();
    let mut branches = Vec::new();
    let base = crate::ops::fragility::RunModel::of_command(req.auto_tol, at.records);
    for path in paths.clone().unwrap_or_else(|| vec![one]) {
        let (eps, model) = crate::ops::tree::branch(&path, e.b_m, e.h_m, e.eps, base)?;
        let model = model.on(e.mu);
        let block = crate::ops::fragility::block(e.b_m, e.h_m, eps)?;
        let mut f = damage::of_block(&block, &req.states, at.im, at.laws, at.records, model, fit)?;
        let info = risk::block_info(e, &block, floor);
        let entry = entry(&info, &f, at.im, &block, floor)?;
        let cut = damage::zero_below(&block, at.im, floor, f.slides_on_mu);
        f.warnings.extend(damage::crossings(&f, f.method, cut));
        let sliding = f.unmodelled_sliding(info.mu, info.alpha_rad);
        f.warnings.extend(sliding);
        branches.push((path, block, info, entry, f));
    }
    let tax = taxonomy(&e.name);
    let Some(tree) = &req.tree else {
        let (_, _, info, entry, f) = branches.pop().expect("one branch");
        out.exposure.push(entry.clone());
        let written_as = shape_name(&entry.states);
        out.functions.push(entry);
        return Ok(ExportedBlock {
            block: info,
            taxonomy: tax,
            written_as,
            fragility: f,
            tree: None,
        });
    };
    let (listed, mean) = over_tree(req, tree, &tax, &branches, &e.name, out)?;
    let warnings = crate::ops::tree::merge_warnings(
        &branches
            .iter()
            .map(|b| (b.0.label.as_str(), &b.4.warnings[..]))
            .collect::<Vec<_>>(),
    );
    let (_, _, info, entry, mut f) = branches.swap_remove(0);
    f.warnings = warnings;
    out.exposure.push(Entry {
        id: tax.clone(),
        ..entry
    });
    Ok(ExportedBlock {
        block: info,
        taxonomy: tax,
        written_as: mean.as_ref().map_or("branches", |m| m.written_as),
        fragility: f,
        tree: Some(TreeExport {
            tree: tree.name.clone(),
            branches: listed,
            mean,
        }),
    })
}

/// A block's branches, each its path, block, answer, entry and fragility.
type Branches = [(
    crate::tree::TreePath,
    Block,
    risk::BlockInfo,
    Entry,
    DamageFragility,
)];

/// A block's branches into the files: for OpenQuake each branch's
/// functions under its own id and the mapping of the block's taxonomy to
/// them with their weights; for pelicun the mean as one function per
/// state ([`crate::ops::tree::mean_shape`]).
fn over_tree(
    req: &Request,
    tree: &crate::tree::Tree,
    tax: &str,
    branches: &Branches,
    name: &str,
    out: &mut Entries,
) -> Result<(Vec<BranchExport>, Option<crate::ops::tree::MeanFit>), ExportOpError> {
    let mut listed = Vec::new();
    for (k, (path, block, _, entry, fragility)) in branches.iter().enumerate() {
        let id = format!("{tax}_b{}", k + 1);
        listed.push(BranchExport {
            risk_id: id.clone(),
            branch: path.label.clone(),
            weight: path.weight,
            eps: block.eps,
            fragility: fragility.clone(),
        });
        if req.format == Format::Nrml {
            out.mapping.push((tax.to_string(), id.clone(), path.weight));
            out.functions.push(Entry {
                id,
                description: format!(
                    "{} (branch {}, weight {})",
                    entry.description, path.label, path.weight
                ),
                ..entry.clone()
            });
        }
    }
    if req.format == Format::Nrml {
        return Ok((listed, None));
    }
    // Each branch cut where its block cannot move (its no-damage limit), as
    // `risk --tree` and `fragility --tree` count it.
    let parts: Vec<(f64, &DamageFragility, f64)> = branches
        .iter()
        .map(|b| (b.0.weight, &b.4, b.3.no_damage_limit.unwrap_or(0.0)))
        .collect();
    let (states, fit) = crate::ops::tree::mean_shape(&parts)
        .ok_or_else(|| ExportOpError::TreeMean(name.to_string()))?;
    out.functions.push(Entry {
        id: tax.to_string(),
        description: format!(
            "{name}: the mean over the logic tree {} ({} branches)",
            tree.name,
            branches.len()
        ),
        no_damage_limit: branches[0].3.no_damage_limit,
        states,
    });
    Ok((listed, Some(fit)))
}

fn shape_name(s: &Shape) -> &'static str {
    match s {
        Shape::Lognormal(_) => "lognormal",
        Shape::Curve(_) => "curve",
    }
}
