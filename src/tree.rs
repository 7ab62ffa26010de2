//! A logic tree of a block's uncertain parameters (its restitution ε and
//! the model its runs use), as a small TOML file or a named tree: each set
//! of branches with weights summing to 1, combined as the full tree (every
//! combination, its weight the product of its branches'). And what is
//! stated over the branches: the weighted mean, OpenQuake's weighted
//! quantiles, the mixture of fragilities and its dispersion split into
//! record-to-record and epistemic parts. docs/MODEL.md §19.

use serde::Deserialize;

use crate::block::{Block, Restitution};
use crate::label::Label;
use crate::physics::ModelChoice;
use crate::risk::Fragility;

/// The quantiles a tree's answers are stated at, as OpenQuake states
/// hazard (5, 16, 50, 84 and 95 %).
pub const QUANTILES: [f64; 5] = [0.05, 0.16, 0.5, 0.84, 0.95];

/// A set's weights may miss 1 by this much (rounding of decimal weights).
pub const WEIGHT_TOLERANCE: f64 = 1e-9;

/// The full tree is refused above this many branches: its answers are one
/// fragility per branch, and a tree this large is better sampled by the
/// user into fewer, heavier branches.
pub const MAX_BRANCHES: usize = 100;

/// A restitution branch: ε itself, or a ratio to Housner's 1 − 1.5 sin²α.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EpsBranch {
    Value(f64),
    Ratio(f64),
}

impl EpsBranch {
    /// The block's ε on this branch.
    pub fn restitution(self, b_m: f64, h_m: f64) -> Restitution {
        match self {
            EpsBranch::Value(v) => Restitution::Value(v),
            EpsBranch::Ratio(r) => Restitution::Value(r * Block::housner_eps(b_m, h_m)),
        }
    }

    /// ε on this branch of a block of slenderness `alpha` (rad).
    pub fn eps_at(self, alpha: f64) -> f64 {
        match self {
            EpsBranch::Value(v) => v,
            EpsBranch::Ratio(r) => r * crate::block::housner_eps_of_alpha(alpha),
        }
    }

    fn text(self) -> String {
        match self {
            EpsBranch::Value(v) => format!("ε = {v}"),
            EpsBranch::Ratio(r) => format!("ε = {r} × Housner's"),
        }
    }
}

/// One branch of a set: its value and weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Branch<T> {
    pub value: T,
    pub weight: f64,
}

/// A logic tree: its branch sets (an empty set leaves the command's own
/// value), and where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Tree {
    /// The file, or the named tree.
    pub name: String,
    pub eps: Vec<Branch<EpsBranch>>,
    pub model: Vec<Branch<ModelChoice>>,
}

/// One path through the tree: a value from each set (`None`: the
/// command's own), its weight, and a label naming it.
#[derive(Debug, Clone, PartialEq)]
pub struct TreePath {
    pub eps: Option<EpsBranch>,
    pub model: Option<ModelChoice>,
    pub weight: f64,
    pub label: String,
    /// Which branch of each set the path takes (`None`: the set is not
    /// given), for the tornado.
    pub eps_branch: Option<usize>,
    pub model_branch: Option<usize>,
}

impl TreePath {
    /// The one path of no tree: the command's own values, weight 1.
    pub fn plain() -> TreePath {
        TreePath {
            eps: None,
            model: None,
            weight: 1.0,
            label: String::new(),
            eps_branch: None,
            model_branch: None,
        }
    }
}

/// A tree that cannot be used, and why: the message names the file and
/// the key.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct TreeError(pub String);

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTree {
    #[serde(default)]
    description: Option<String>,
    #[serde(default)]
    eps: Vec<RawEps>,
    #[serde(default)]
    mu: Vec<toml::Value>,
    #[serde(default)]
    model: Vec<RawModel>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEps {
    value: Option<f64>,
    ratio: Option<f64>,
    weight: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawModel {
    name: ModelChoice,
    weight: f64,
}

/// The named trees, offered by name and never applied unasked.
pub const NAMED: &[(&str, &str)] = &[(
    RESTITUTION_TESTS,
    "ε of a block on a hard base as tests measure it: 1.0, 0.95 and 0.85 × Housner's, \
     weights 0.35, 0.45, 0.2 (docs/MODEL.md §19)",
)];

/// The name of the default tree of ε from the experimental literature.
pub const RESTITUTION_TESTS: &str = "restitution-tests";

impl Tree {
    /// The tree a file's text gives; `origin` names the file in messages.
    pub fn parse(text: &str, origin: &str) -> Result<Tree, TreeError> {
        let raw: RawTree = toml::from_str(text).map_err(|e| TreeError(format!("{origin}: {e}")))?;
        Tree::of_raw(raw, origin)
    }

    /// The tree of a TOML table (a pipeline's `[tree]`, its keys a file's).
    pub fn of_value(value: toml::Value, origin: &str) -> Result<Tree, TreeError> {
        let raw = RawTree::deserialize(value).map_err(|e| TreeError(format!("{origin}: {e}")))?;
        Tree::of_raw(raw, origin)
    }

    fn of_raw(raw: RawTree, origin: &str) -> Result<Tree, TreeError> {
        let _ = raw.description;
        if !raw.mu.is_empty() {
            return Err(TreeError(format!(
                "{origin}: [[mu]]: a tree does not branch on friction; give the base's μ \
                 itself (--mu, an inventory's `mu`), on which the slide-rock model runs the \
                 block"
            )));
        }
        let eps = raw
            .eps
            .iter()
            .enumerate()
            .map(|(k, b)| {
                let at = format!("{origin}: [[eps]] {}", k + 1);
                let value = match (b.value, b.ratio) {
                    (Some(v), None) if v > 0.0 && v <= 1.0 => EpsBranch::Value(v),
                    (Some(v), None) => {
                        return Err(TreeError(format!("{at}: value = {v}; ε is in (0, 1]")))
                    }
                    (None, Some(r)) if r > 0.0 && r.is_finite() => EpsBranch::Ratio(r),
                    (None, Some(r)) => {
                        return Err(TreeError(format!(
                            "{at}: ratio = {r}; a ratio to Housner's ε is positive"
                        )))
                    }
                    _ => {
                        return Err(TreeError(format!(
                            "{at}: give `value` (ε) or `ratio` (× Housner's 1 − 1.5 sin²α), one \
                             of them"
                        )))
                    }
                };
                Ok(Branch {
                    value,
                    weight: b.weight,
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let model = raw
            .model
            .iter()
            .map(|b| Branch {
                value: b.name,
                weight: b.weight,
            })
            .collect::<Vec<_>>();
        let tree = Tree {
            name: origin.to_string(),
            eps,
            model,
        };
        tree.check()?;
        Ok(tree)
    }

    /// A named tree ([`NAMED`]).
    pub fn named(name: &str) -> Option<Tree> {
        match name {
            RESTITUTION_TESTS => Some(Tree {
                name: name.to_string(),
                eps: [(1.0, 0.35), (0.95, 0.45), (0.85, 0.2)]
                    .into_iter()
                    .map(|(r, w)| Branch {
                        value: EpsBranch::Ratio(r),
                        weight: w,
                    })
                    .collect(),
                model: Vec::new(),
            }),
            _ => None,
        }
    }

    fn check(&self) -> Result<(), TreeError> {
        let weights_of = |set: &str, w: Vec<f64>| -> Result<(), TreeError> {
            if let Some(bad) = w.iter().find(|w| !(**w > 0.0 && w.is_finite())) {
                return Err(TreeError(format!(
                    "{}: [[{set}]]: weight = {bad}; a branch's weight is positive",
                    self.name
                )));
            }
            let sum: f64 = w.iter().sum();
            if !w.is_empty() && (sum - 1.0).abs() > WEIGHT_TOLERANCE {
                return Err(TreeError(format!(
                    "{}: [[{set}]]: the weights sum to {sum}, not 1",
                    self.name
                )));
            }
            Ok(())
        };
        weights_of("eps", self.eps.iter().map(|b| b.weight).collect())?;
        weights_of("model", self.model.iter().map(|b| b.weight).collect())?;
        if self.eps.is_empty() && self.model.is_empty() {
            return Err(TreeError(format!(
                "{}: no branches: give [[eps]] or [[model]] sets",
                self.name
            )));
        }
        let n = self.eps.len().max(1) * self.model.len().max(1);
        if n > MAX_BRANCHES {
            return Err(TreeError(format!(
                "{}: {n} branches in the full tree, above {MAX_BRANCHES}: merge branches",
                self.name
            )));
        }
        Ok(())
    }

    /// Every path of the full tree, ε outermost, in the file's order; a
    /// path's weight is the product of its branches'.
    pub fn paths(&self) -> Vec<TreePath> {
        let eps: Vec<Option<(usize, Branch<EpsBranch>)>> = match self.eps.is_empty() {
            true => vec![None],
            false => self.eps.iter().copied().enumerate().map(Some).collect(),
        };
        let model: Vec<Option<(usize, Branch<ModelChoice>)>> = match self.model.is_empty() {
            true => vec![None],
            false => self.model.iter().copied().enumerate().map(Some).collect(),
        };
        let mut out = Vec::with_capacity(eps.len() * model.len());
        for ei in &eps {
            for mi in &model {
                let (e, m) = (ei.map(|x| x.1), mi.map(|x| x.1));
                let weight = e.map_or(1.0, |b| b.weight) * m.map_or(1.0, |b| b.weight);
                let label = [
                    e.map(|b| b.value.text()),
                    m.map(|b| format!("{} model", b.value.label())),
                ]
                .into_iter()
                .flatten()
                .collect::<Vec<_>>()
                .join(", ");
                out.push(TreePath {
                    eps: e.map(|b| b.value),
                    model: m.map(|b| b.value),
                    weight,
                    label,
                    eps_branch: ei.map(|x| x.0),
                    model_branch: mi.map(|x| x.0),
                });
            }
        }
        out
    }

    /// Whether some branch chooses the model (its runs are then needed).
    pub fn chooses_model(&self) -> bool {
        !self.model.is_empty()
    }
}

/// The weighted mean Σ wᵢ·xᵢ.
pub fn weighted_mean(values: &[f64], weights: &[f64]) -> f64 {
    values.iter().zip(weights).map(|(v, w)| w * v).sum()
}

/// The weighted q-quantile by OpenQuake's rule (`hazardlib.stats.
/// quantile_curve`): the values sorted, their weights accumulated, and q
/// interpolated linearly on that step-free CDF, clamped to the smallest
/// and largest value outside it.
pub fn weighted_quantile(values: &[f64], weights: &[f64], q: f64) -> f64 {
    let mut vw: Vec<(f64, f64)> = values
        .iter()
        .copied()
        .zip(weights.iter().copied())
        .collect();
    vw.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut cum = 0.0;
    let xs: Vec<(f64, f64)> = vw
        .iter()
        .map(|&(v, w)| {
            cum += w;
            (cum, v)
        })
        .collect();
    interp(q, &xs)
}

/// numpy.interp: linear between the points, the end values outside.
fn interp(x: f64, pts: &[(f64, f64)]) -> f64 {
    let (first, last) = (pts[0], pts[pts.len() - 1]);
    if x <= first.0 {
        return first.1;
    }
    if x >= last.0 {
        return last.1;
    }
    let k = pts.partition_point(|p| p.0 <= x);
    let ((x0, y0), (x1, y1)) = (pts[k - 1], pts[k]);
    y0 + (x - x0) * (y1 - y0) / (x1 - x0)
}

/// The dispersion of the branches' lognormals split as FEMA P-58 states
/// it: the record-to-record β (the weighted root mean square of theirs),
/// the epistemic β (the weighted standard deviation of their ln medians),
/// and β_total = √(β_rtr² + β_m²), about exp(Σ wᵢ ln mᵢ).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BetaSplit {
    pub median: f64,
    pub beta_rtr: f64,
    pub beta_m: f64,
    pub beta_total: f64,
}

/// [`BetaSplit`] of lognormals `(median, β)` with `weights`; `None` when
/// some median is not finite.
pub fn beta_split(lognormals: &[(f64, f64)], weights: &[f64]) -> Option<BetaSplit> {
    if lognormals
        .iter()
        .any(|(m, b)| !(m.is_finite() && *m > 0.0 && b.is_finite()))
    {
        return None;
    }
    let ln_m: Vec<f64> = lognormals.iter().map(|(m, _)| m.ln()).collect();
    let mean_ln = weighted_mean(&ln_m, weights);
    let var_m: f64 = ln_m
        .iter()
        .zip(weights)
        .map(|(l, w)| w * (l - mean_ln).powi(2))
        .sum();
    let b2: Vec<f64> = lognormals.iter().map(|(_, b)| b * b).collect();
    let beta_rtr = weighted_mean(&b2, weights).sqrt();
    let beta_m = var_m.sqrt();
    Some(BetaSplit {
        median: mean_ln.exp(),
        beta_rtr,
        beta_m,
        beta_total: beta_rtr.hypot(beta_m),
    })
}

/// A weighted mixture of fragilities: P(x) = Σ wᵢ Pᵢ(x), not a lognormal.
pub struct Mixture<'a> {
    pub parts: &'a [(f64, Fragility)],
    /// Each part's level below which its block cannot move (Pᵢ = 0 there,
    /// as `risk` and `fragility` cut it), in the parts' order; empty: no
    /// cut.
    pub below: &'a [f64],
}

impl Mixture<'_> {
    pub fn probability(&self, x: f64) -> f64 {
        let cut = |i: usize| self.below.get(i).copied().unwrap_or(0.0);
        self.parts
            .iter()
            .enumerate()
            .map(|(i, (w, f))| {
                if x < cut(i) {
                    0.0
                } else {
                    w * f.probability(x)
                }
            })
            .sum()
    }

    /// The level where the mixture reaches `p` (bisection on ln x, to
    /// 1e-12 relative); `None` where it never does (some branch's curve
    /// stops below `p`).
    pub fn level(&self, p: f64) -> Option<f64> {
        let limit: f64 = self.parts.iter().map(|(w, f)| w * f.limit()).sum();
        if !(p > 0.0 && p < limit) {
            return None;
        }
        let (mut lo, mut hi) = (1e-6_f64, 1e-6_f64);
        while self.probability(hi) < p {
            hi *= 2.0;
            if hi > 1e12 {
                return None;
            }
        }
        while self.probability(lo) >= p && lo > 1e-300 {
            lo /= 2.0;
        }
        for _ in 0..200 {
            let mid = (lo * hi).sqrt();
            if self.probability(mid) < p {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi / lo - 1.0 < 1e-13 {
                break;
            }
        }
        Some(hi)
    }

    /// The mixture's median and its equivalent β, ln(x₈₄/x₁₆)/2 (the
    /// lognormal through its Φ(±1) levels, 15.87 and 84.13 %: one
    /// lognormal's own β).
    pub fn median_beta(&self) -> (Option<f64>, Option<f64>) {
        let m = self.level(0.5);
        let beta = match (
            self.level(crate::stats::normal_cdf(-1.0)),
            self.level(crate::stats::normal_cdf(1.0)),
        ) {
            (Some(a), Some(b)) => Some((b / a).ln() / 2.0),
            _ => None,
        };
        (m, beta)
    }
}

/// One branch set's swing of the median capacity (the tornado): for each
/// of its branches, exp of the weighted mean of ln mᵢ over the paths that
/// take it (the other sets at their weights), and the smallest and largest
/// of those.
#[derive(Debug, Clone, PartialEq)]
pub struct Swing {
    pub set: &'static str,
    pub low: f64,
    pub high: f64,
}

/// Which branch of a set a path takes.
type BranchOf = fn(&TreePath) -> Option<usize>;

/// Each set of two or more branches' [`Swing`] of `medians` (one per path
/// of [`Tree::paths`], in its order), widest first.
pub fn swings(tree: &Tree, medians: &[f64]) -> Vec<Swing> {
    let paths = tree.paths();
    let mut out = Vec::new();
    let sets: [(&'static str, usize, BranchOf); 2] = [
        ("ε", tree.eps.len(), |p| p.eps_branch),
        ("model", tree.model.len(), |p| p.model_branch),
    ];
    for (set, n, branch_of) in sets {
        if n < 2 {
            continue;
        }
        let conditional: Vec<f64> = (0..n)
            .map(|b| {
                let (mut sw, mut sl) = (0.0, 0.0);
                for (p, m) in paths.iter().zip(medians) {
                    if branch_of(p) == Some(b) {
                        sw += p.weight;
                        sl += p.weight * m.ln();
                    }
                }
                (sl / sw).exp()
            })
            .collect();
        out.push(Swing {
            set,
            low: conditional.iter().copied().fold(f64::INFINITY, f64::min),
            high: conditional
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max),
        });
    }
    out.sort_by(|a, b| (b.high / b.low).total_cmp(&(a.high / a.low)));
    out
}

/// Named trees' labels and help, for `--tree`'s help and messages.
pub fn named_list() -> String {
    NAMED
        .iter()
        .map(|(n, _)| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// OpenQuake's own doctest: quantile_curve(.8, [.15, .25, .3, .4, .5,
    /// .6, .75, .8, .9]) = 0.76 with equal weights, and a constant array
    /// gives its value.
    #[test]
    fn quantile_as_openquake() {
        let v = [0.15, 0.25, 0.3, 0.4, 0.5, 0.6, 0.75, 0.8, 0.9];
        let w = [1.0 / 9.0; 9];
        assert!((weighted_quantile(&v, &w, 0.8) - 0.76).abs() < 1e-12);
        assert_eq!(weighted_quantile(&[0.15; 3], &[1.0 / 3.0; 3], 0.85), 0.15);
    }

    #[test]
    fn weights_and_keys_checked() {
        let bad = Tree::parse("[[eps]]\nvalue = 0.8\nweight = 0.5\n", "t.toml").unwrap_err();
        assert!(
            bad.0.contains("t.toml: [[eps]]: the weights sum to 0.5"),
            "{bad}"
        );
        let both = Tree::parse("[[eps]]\nvalue = 0.8\nratio = 0.9\nweight = 1\n", "t.toml");
        assert!(both.unwrap_err().0.contains("[[eps]] 1: give `value`"));
        let typo = Tree::parse("[[eps]]\nvalu = 0.8\nweight = 1\n", "t.toml").unwrap_err();
        assert!(typo.0.contains("unknown field `valu`"), "{typo}");
        let mu = Tree::parse("[[mu]]\nvalue = 0.4\nweight = 1\n", "t.toml").unwrap_err();
        assert!(mu.0.contains("[[mu]]"), "{mu}");
    }

    /// The full tree: 2 × 2 paths, weights the products, summing to 1.
    #[test]
    fn full_tree() {
        let t = Tree::parse(
            "[[eps]]\nratio = 0.9\nweight = 0.25\n[[eps]]\nvalue = 0.7\nweight = 0.75\n\
             [[model]]\nname = \"linearized\"\nweight = 0.4\n[[model]]\nname = \"nonlinear\"\n\
             weight = 0.6\n",
            "t.toml",
        )
        .unwrap();
        let p = t.paths();
        assert_eq!(p.len(), 4);
        assert_eq!(p[1].weight, 0.25 * 0.6);
        assert_eq!(p[1].label, "ε = 0.9 × Housner's, nonlinear model");
        assert!((p.iter().map(|p| p.weight).sum::<f64>() - 1.0).abs() < 1e-15);
        assert!(Tree::named(RESTITUTION_TESTS).unwrap().check().is_ok());
    }

    /// A mixture of two lognormals of one β and medians m and 4m is at P =
    /// 0.5 exactly at 2m (by symmetry in ln x).
    #[test]
    fn mixture_median_by_symmetry() {
        let parts = [
            (
                0.5,
                Fragility::Lognormal {
                    median: 0.1,
                    beta: 0.4,
                },
            ),
            (
                0.5,
                Fragility::Lognormal {
                    median: 0.4,
                    beta: 0.4,
                },
            ),
        ];
        let m = Mixture {
            parts: &parts,
            below: &[],
        };
        assert!((m.level(0.5).unwrap() / 0.2 - 1.0).abs() < 1e-12);
        let s = beta_split(&[(0.1, 0.4), (0.4, 0.4)], &[0.5, 0.5]).unwrap();
        assert!((s.beta_m - 4f64.ln() / 2.0).abs() < 1e-15);
        assert!((s.median - 0.2).abs() < 1e-15);
    }
}
