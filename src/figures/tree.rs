//! A logic tree's figures (`[tree]`): the example block's fragility on
//! each branch with their mean (the mixture) and weighted quantiles, and
//! the tornado of which branch set moves its median capacity most.

use super::figure::Figure;
use crate::block::{Block, Restitution};
use crate::cut;
use crate::damage::{fractile_method, Lognormal};
use crate::im::Im;
use crate::plot::{Chart, Hue, Line, Scale, Style};
use crate::risk::Fragility;
use crate::study::StudyData;
use crate::tree::{self, Mixture};

/// The example block on each branch: its weight, label, the lognormal by
/// the study's fractiles (`[reduce] fractile`, as its damage states) of
/// its capacities in [`Branches::im`] (g; +∞ where it
/// survives every level), and the level below which it cannot move (its probability 0
/// there, as `fragility --tree` and `risk --tree` count it; 0: no cut).
/// `None` without a tree, its capacities or the example's α.
pub struct Branches {
    pub weights: Vec<f64>,
    pub labels: Vec<String>,
    pub fits: Vec<Lognormal>,
    pub below: Vec<f64>,
    /// The IM the fits are in: the peak of the motion the block stands on,
    /// PFA on a floor (the tree's capacities are in the floor motion's η)
    /// or on text records, else PGA.
    pub im: Im,
}

/// [`Branches`] of a study with a tree (cases numbered record × branch).
pub fn branches(d: &StudyData) -> Option<Branches> {
    let t = d.plan.tree()?;
    let caps = d.tree_caps.as_ref()?;
    let alpha = d.plan.example()?.alpha_rad?;
    let n = t.branches.len();
    // The study's fractiles, as its damage states are fitted by.
    let def = d.plan.records_study().ok()?.fractile;
    let fits = (0..n)
        .map(|b| {
            let in_pga: Vec<f64> = caps
                .iter()
                .skip(b)
                .step_by(n)
                .map(|c| {
                    c.eta_c
                        .map_or(f64::INFINITY, |e| crate::im::pga_of_eta(e, alpha))
                })
                .collect();
            fractile_method(&in_pga, def)
        })
        .collect::<Option<Vec<_>>>()?;
    let floor = d.plan.records_study().ok()?.floor.as_ref();
    let im = d.peak();
    let below = t
        .branches
        .iter()
        .map(|br| {
            let alpha = br.block.alpha_rad.unwrap_or(alpha);
            let block = Block::of_p_alpha(br.block.p, alpha, Restitution::Value(br.block.eps));
            let mu = br.block.run.model.equation.friction().map(|f| f.mu_s);
            Some(cut::zero_below(&block.ok()?, im, floor, mu).unwrap_or(0.0))
        })
        .collect::<Option<Vec<_>>>()?;
    Some(Branches {
        weights: t.branches.iter().map(|b| b.weight).collect(),
        labels: t.branches.iter().map(|b| b.label.clone()).collect(),
        fits,
        below,
        im,
    })
}

impl Branches {
    /// Each branch's weight and lognormal, as a [`Mixture`] takes them.
    pub fn parts(&self) -> Vec<(f64, Fragility)> {
        self.weights
            .iter()
            .zip(&self.fits)
            .map(|(&w, l)| {
                (
                    w,
                    Fragility::Lognormal {
                        median: l.median,
                        beta: l.beta,
                    },
                )
            })
            .collect()
    }

    /// Each branch's probability at `x`, 0 below its cut.
    pub fn probabilities(&self, x: f64) -> Vec<f64> {
        self.parts()
            .iter()
            .zip(&self.below)
            .map(|((_, f), &c)| cut::probability_above(f, x, Some(c)))
            .collect()
    }
}

/// The branches' fragilities (faint), their mean (the mixture) and the 5,
/// 50 and 95 % weighted quantiles over them, against the peak of the
/// motion the block stands on.
pub(super) fn tree_fragility(d: &StudyData) -> Vec<Figure> {
    let Some(b) = branches(d) else {
        return Vec::new();
    };
    let parts = b.parts();
    let mix = Mixture {
        parts: &parts,
        below: &b.below,
    };
    let top = b
        .fits
        .iter()
        .map(|l| l.median * (2.5 * l.beta).exp())
        .fold(0.0, f64::max);
    let xs: Vec<f64> = (1..=120).map(|k| top * k as f64 / 120.0).collect();
    let each: Vec<Vec<f64>> = xs.iter().map(|&x| b.probabilities(x)).collect();
    let mut lines: Vec<Line> = (0..parts.len())
        .map(|i| Line {
            name: None,
            points: xs.iter().zip(&each).map(|(&x, ps)| (x, ps[i])).collect(),
            style: Style::Faint,
            hue: Hue::Ink,
        })
        .collect();
    for (k, q) in [0.05, 0.5, 0.95].into_iter().enumerate() {
        lines.push(Line {
            name: Some(format!("{:.0} % over the branches", 100.0 * q)),
            points: xs
                .iter()
                .zip(&each)
                .map(|(&x, ps)| (x, tree::weighted_quantile(ps, &b.weights, q)))
                .collect(),
            style: Style::Dashed,
            hue: Hue::Fractile(k),
        });
    }
    lines.push(Line {
        name: Some("mean (the mixture)".into()),
        points: xs.iter().map(|&x| (x, mix.probability(x))).collect(),
        style: Style::Line,
        hue: Hue::Ink,
    });
    let block = d.plan.example().expect("a tree has an example");
    vec![Figure {
        file: "tree_fragility.svg".into(),
        chart: Chart {
            title: format!(
                "The example block over the logic tree ({} branches): p = {:.2} 1/s, α = {:.3} rad",
                b.weights.len(),
                block.p,
                block.alpha_rad.unwrap_or(f64::NAN)
            ),
            x_desc: format!("{} (g)", b.im.short()),
            y_desc: format!("P(overturn | {})", b.im.short()),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.0, top)),
            y_range: Some((0.0, 1.0)),
            x_ticks: None,
            lines,
        },
        caption: format!(
            "The example block's fragility on each branch of the tree (grey: a lognormal by the \
             fractiles of its capacities in {im}, `tree_capacities.parquet`; 0 below the {im} \
             that lifts the block, g·tan α, as `fragility --tree` and `risk --tree` count it), \
             their weighted mean (black: the mixture, which is what the tree's rate integrates) \
             and the 5, 50 and 95 % weighted quantiles over the branches at each {im} \
             (OpenQuake's rule; docs/MODEL.md §19).",
            im = b.im.short()
        ),
    }]
}

/// The tornado: each branch set's range of the median capacity (its
/// branches' conditional medians, the other sets at their weights), the
/// widest on top, about the mixture's median.
pub(super) fn tree_tornado(d: &StudyData) -> Vec<Figure> {
    let (Some(b), Some(t)) = (branches(d), d.plan.tree()) else {
        return Vec::new();
    };
    let medians: Vec<f64> = b.fits.iter().map(|l| l.median).collect();
    let swings = tree::swings(&t.tree, &medians);
    if swings.is_empty() {
        return Vec::new();
    }
    let parts = b.parts();
    let n = swings.len();
    let mut lines: Vec<Line> = swings
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let y = (n - k) as f64;
            Line {
                name: Some(format!(
                    "{}: {:.3}–{:.3} g ({:+.0} %)",
                    s.set,
                    s.low,
                    s.high,
                    100.0 * (s.high / s.low - 1.0)
                )),
                points: vec![(s.low, y), (s.high, y)],
                style: Style::LinePoints,
                hue: Hue::Series(k),
            }
        })
        .collect();
    if let Some(m) = (Mixture {
        parts: &parts,
        below: &[],
    })
    .level(0.5)
    {
        lines.push(Line {
            name: Some(format!("the mixture's median, {m:.3} g")),
            points: vec![(m, 0.5), (m, n as f64 + 0.5)],
            style: Style::Dashed,
            hue: Hue::Ink,
        });
    }
    let lo = swings.iter().map(|s| s.low).fold(f64::INFINITY, f64::min);
    let hi = swings.iter().map(|s| s.high).fold(0.0, f64::max);
    vec![Figure {
        file: "tree_tornado.svg".into(),
        chart: Chart {
            title: "Which branch set moves the example block's median capacity most".into(),
            x_desc: format!("median capacity, {} (g)", b.im.short()),
            y_desc: "branch set (widest on top)".into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            x_range: Some((0.9 * lo, 1.1 * hi)),
            y_range: Some((0.0, n as f64 + 1.0)),
            x_ticks: None,
            lines,
        },
        caption: "For each branch set of two or more branches, the example block's median \
                  capacity on each of its branches (exp of the weighted mean of ln median over \
                  the paths that take it, the other sets at their weights): the segment spans \
                  the set's smallest to largest, the widest set on top; dashed, the mean \
                  fragility's median."
            .into(),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::fixture::{cap, tree_study};

    /// Three branches whose capacities are known: the fit by the fractiles
    /// of each, the mixture's median where Σ wᵢ Φ(ln(x/mᵢ)/βᵢ) = 1/2, and
    /// the tornado's one set spanning the smallest to the largest median.
    #[test]
    fn branches_mixture_and_tornado_from_the_capacities() {
        let mut d = tree_study(
            "[[tree.eps]]\nratio = 1.0\nweight = 0.5\n[[tree.eps]]\nratio = 0.9\nweight = 0.3\n\
             [[tree.eps]]\nratio = 0.8\nweight = 0.2\n",
        );
        let alpha = d.plan.example().unwrap().alpha_rad.unwrap();
        // Five records × three branches, record-major: η_c = 1/(k+1) on
        // branch 0, scaled by 0.9 and 0.8 on the others.
        let mut caps = Vec::new();
        for r in 0..5 {
            for (b, s) in [1.0, 0.9, 0.8].into_iter().enumerate() {
                caps.push(cap((3 * r + b) as i64, Some(s / (r as f64 + 1.0))));
            }
        }
        d.tree_caps = Some(caps);
        let b = branches(&d).unwrap();
        // Branch 0 in PGA: α·(k+1), k = 0..4; type-7 median the middle one.
        assert!((b.fits[0].median - 3.0 * alpha).abs() < 1e-12);
        assert!((b.fits[2].median - 3.0 * alpha / 0.8).abs() < 1e-12);
        let figs = tree_fragility(&d);
        assert_eq!(figs[0].file, "tree_fragility.svg");
        // The mean is the cut mixture `fragility --tree` and `risk --tree`
        // count: 0 below the uplift PGA g·tan α, Σ wᵢ Φ(ln(x/mᵢ)/βᵢ) above
        // (Φ by statrs here).
        use statrs::distribution::{ContinuousCDF, Normal};
        let phi = Normal::new(0.0, 1.0).unwrap();
        let mean = figs[0].chart.lines.last().unwrap();
        assert_eq!(mean.name.as_deref(), Some("mean (the mixture)"));
        let uplift = alpha.tan();
        let (mut below, mut above) = (0, 0);
        for &(x, y) in &mean.points {
            let want: f64 = if x < uplift {
                below += 1;
                0.0
            } else {
                above += 1;
                [0.5, 0.3, 0.2]
                    .iter()
                    .zip(&b.fits)
                    .map(|(w, l)| w * phi.cdf((x / l.median).ln() / l.beta))
                    .sum()
            };
            assert!((y - want).abs() < 1e-12, "x {x}: {y} vs {want}");
        }
        assert!(below > 0 && above > 0, "{below} {above}");
        // Each branch's own line is cut too.
        let first = &figs[0].chart.lines[0].points;
        assert!(first.iter().all(|&(x, y)| x >= uplift || y == 0.0));
        assert_eq!(figs[0].chart.x_desc, "PGA (g)");
        let t = tree_tornado(&d);
        let seg = &t[0].chart.lines[0].points;
        assert!(
            (seg[0].0 - 3.0 * alpha).abs() < 1e-12 && (seg[1].0 - 3.0 * alpha / 0.8).abs() < 1e-12
        );
    }

    /// On a building's floor the tree's capacities are in the floor
    /// motion's η: the figure is in PFA, cut at the PFA that lifts the
    /// block (g·tan α), as `fragility --tree --im pfa` counts it; in PGA a
    /// floor has no cut, and the axis said PGA.
    #[test]
    fn on_a_floor_the_tree_is_in_pfa() {
        let mut d = tree_study(
            "[floor]\nmodes = [[0.5, 0.05, 1.3]]\n[[tree.eps]]\nratio = 1.0\nweight = 0.6\n\
             [[tree.eps]]\nratio = 0.9\nweight = 0.4\n",
        );
        let alpha = d.plan.example().unwrap().alpha_rad.unwrap();
        let mut caps = Vec::new();
        for r in 0..5 {
            for (b, s) in [1.0, 0.9].into_iter().enumerate() {
                caps.push(cap((2 * r + b) as i64, Some(s / (r as f64 + 1.0))));
            }
        }
        d.tree_caps = Some(caps);
        let b = branches(&d).unwrap();
        assert_eq!(b.im, Im::Pfa);
        let figs = tree_fragility(&d);
        assert_eq!(figs[0].chart.x_desc, "PFA (g)");
        let mean = figs[0].chart.lines.last().unwrap();
        let uplift = alpha.tan();
        assert!(mean.points.iter().any(|&(x, _)| x < uplift));
        for &(x, y) in &mean.points {
            assert!(x >= uplift || y == 0.0, "x {x}: {y}");
        }
    }
}
