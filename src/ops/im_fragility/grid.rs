//! A study's p × ε grid of one IM, carrying a dimensionless median and β
//! to any block by bilinear interpolation in (ln p, ε), and why a study's
//! table may have no answer for a block.

/// A study's block: p, ε, the dimensionless median and β (`None` where it
/// has no fit).
pub(super) type Node = (f64, f64, Option<f64>, Option<f64>);

/// Why a study's table has no answer for a block.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Gap {
    /// Named blocks, not a grid of p × ε; none of them is the block asked.
    NotAGrid,
    /// The grid has one p (the first), and the block asked another: nothing
    /// to carry it by.
    OneP(f64, f64),
    /// A grid of p × ε whose blocks around the one asked (those its value
    /// would be carried from) have no fit: them, as text.
    Holes(String),
    /// The study's own block, run sliding on its friction: its fits are
    /// not those of a block asked without it.
    Slides { block: String, mu: f64 },
    /// The study's own block, without a fit.
    Unfitted { block: String },
}

/// A study's p × ε grid of one IM: ln of the dimensionless median and β,
/// where the block has a fit.
pub(super) struct Grid {
    ps: Vec<f64>,
    es: Vec<f64>,
    /// Row-major by p then ε.
    values: Vec<Option<(f64, f64)>>,
}

impl Grid {
    /// The grid the nodes make, if they hold every pair of their p and ε
    /// (with a fit or not).
    pub(super) fn of(rows: &[Node]) -> Option<Grid> {
        let mut ps: Vec<f64> = rows.iter().map(|r| r.0).collect();
        let mut es: Vec<f64> = rows.iter().map(|r| r.1).collect();
        for v in [&mut ps, &mut es] {
            v.sort_by(f64::total_cmp);
            v.dedup();
        }
        // Two blocks of one p and ε (named blocks of other shapes) are no grid.
        if rows.len() != ps.len() * es.len() {
            return None;
        }
        let mut values = Vec::with_capacity(ps.len() * es.len());
        for &p in &ps {
            for &e in &es {
                let r = rows.iter().find(|r| r.0 == p && r.1 == e)?;
                values.push(r.2.zip(r.3).map(|(m, b)| (m.ln(), b)));
            }
        }
        (!values.is_empty()).then_some(Grid { ps, es, values })
    }

    /// Bilinear in (ln p, ε), clamped to the grid, with what was clamped.
    /// An axis of one value is used as it is. A block of the grid without a
    /// fit is a [`Gap::Holes`] where its weight is not zero, and nothing
    /// where it is (its term is then 0, as any block's would be).
    pub(super) fn at(&self, p: f64, eps: f64) -> Result<(f64, f64, Vec<String>), Gap> {
        // One p carries nothing to a block of another size (a grid of one p
        // gave its capacity to a block ten times smaller), but to one within
        // 5 % of it, with a warning; one ε is used at another with a
        // warning, as the edge of a grid is.
        if let [only] = self.ps[..] {
            if (p - only).abs() > ONE_P_REACH * only {
                return Err(Gap::OneP(only, p));
            }
        }
        let mut warnings = Vec::new();
        let lnp: Vec<f64> = self.ps.iter().map(|v| v.ln()).collect();
        let (ip, jp, tp) = bracket(&lnp, p.ln());
        let (ie, je, te) = bracket(&self.es, eps);
        warnings.extend(outside("p", " 1/s", &self.ps, p));
        warnings.extend(outside("ε", "", &self.es, eps));
        let n = self.es.len();
        let mut holes = Vec::new();
        for (i, wp) in [(ip, 1.0 - tp), (jp, tp)] {
            for (j, we) in [(ie, 1.0 - te), (je, te)] {
                if wp != 0.0 && we != 0.0 && self.values[i * n + j].is_none() {
                    let line = format!("p = {:.3} 1/s, ε = {:.3}", self.ps[i], self.es[j]);
                    if !holes.contains(&line) {
                        holes.push(line);
                    }
                }
            }
        }
        if !holes.is_empty() {
            return Err(Gap::Holes(holes.join("; ")));
        }
        let v = |i: usize, j: usize| self.values[i * n + j].unwrap_or((0.0, 0.0));
        let mix = |f: fn((f64, f64)) -> f64| {
            let a = f(v(ip, ie)) * (1.0 - te) + f(v(ip, je)) * te;
            let b = f(v(jp, ie)) * (1.0 - te) + f(v(jp, je)) * te;
            a * (1.0 - tp) + b * tp
        };
        Ok((mix(|x| x.0), mix(|x| x.1), warnings))
    }
}

/// How far (relative) a grid of one p carries its capacity: a measured
/// block's p is never the grid's to the digit.
const ONE_P_REACH: f64 = 0.05;

/// A warning when `x` lies outside the study's sorted values `xs` of `name`.
fn outside(name: &str, unit: &str, xs: &[f64], x: f64) -> Option<String> {
    let (lo, hi) = (xs[0], xs[xs.len() - 1]);
    // One value: the block's own to four digits (a measured block's).
    if (lo..=hi).contains(&x) || (xs.len() == 1 && (x - lo).abs() <= 1e-4 * lo.abs()) {
        None
    } else if xs.len() == 1 {
        Some(format!(
            "{name} = {x:.4}{unit} is not the study's only {name} = {lo:.4}{unit}: its capacity is used"
        ))
    } else {
        Some(format!(
            "{name} = {x:.3}{unit} is outside the study's {}–{}{unit}: the capacity of the nearest edge is used",
            crate::decimal::level_text(lo),
            crate::decimal::level_text(hi)
        ))
    }
}

/// The cell `(i, j)` of sorted `xs` holding `x` and the weight of `j`,
/// clamped to [0, 1] outside; `i = j` when `xs` has one value.
fn bracket(xs: &[f64], x: f64) -> (usize, usize, f64) {
    if xs.len() == 1 {
        return (0, 0, 0.0);
    }
    let i = xs.partition_point(|&v| v <= x).clamp(1, xs.len() - 1) - 1;
    let t = ((x - xs[i]) / (xs[i + 1] - xs[i])).clamp(0.0, 1.0);
    (i, i + 1, t)
}
