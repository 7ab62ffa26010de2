//! Fragility of a real block from the regression (pure; docs/MODEL.md §6–7).
//!
//! The capacity fractiles at (p, ε) come from the step-2 polynomials:
//! `η_c,q = a_q(ε) (1 − e^{−b_q(ε) p})^{c_q(ε)}`. With ln η_c normal,
//! median η_c,50 and dispersion β = (ln η_c,84 − ln η_c,16)/2, a block
//! overturns at PGA `A_g` (η = αg/A_g) with probability
//! `Φ((ln η_c,50 − ln η)/β)`.

use crate::block::Block;
use crate::fit::{curve, polyval};

/// The step-2 coefficients of one fractile: a linear, b and c quadratic in ε.
#[derive(Debug, Clone, PartialEq)]
pub struct FractileLaw {
    pub quantile: f64,
    pub a: Vec<f64>,
    pub b: Vec<f64>,
    pub c: Vec<f64>,
}

impl FractileLaw {
    /// Whether every polynomial was fitted (step 2 leaves one empty when too
    /// few step-1 fits of the fractile converged).
    pub fn is_complete(&self) -> bool {
        !(self.a.is_empty() || self.b.is_empty() || self.c.is_empty())
    }

    pub fn eta_c(&self, p: f64, eps: f64) -> f64 {
        curve(
            polyval(&self.a, eps),
            polyval(&self.b, eps),
            polyval(&self.c, eps),
            p,
        )
    }
}

/// The published coefficients (the paper's Eqs. 10–12, docs/MODEL.md §6).
pub fn paper() -> [FractileLaw; 3] {
    [
        FractileLaw {
            quantile: 0.16,
            a: vec![0.5, 0.33],
            b: vec![1.64, -4.39, 3.44],
            c: vec![7.17, -15.65, 12.0],
        },
        FractileLaw {
            quantile: 0.5,
            a: vec![0.44, 0.43],
            b: vec![0.56, -1.14, 1.25],
            c: vec![1.66, -0.38, 1.4],
        },
        FractileLaw {
            quantile: 0.84,
            a: vec![0.64, 0.24],
            b: vec![-0.66, 2.32, -0.94],
            c: vec![-2.28, 10.3, -6.27],
        },
    ]
}

/// The example block of the report's fragility figure and of `fit_bands`:
/// a 0.5 m × 2 m cabinet (b = 0.25 m, h = 1 m) with Housner's ε.
pub fn example_block() -> Block {
    Block {
        b_m: 0.25,
        h_m: 1.0,
        eps: Block::housner_eps(0.25, 1.0),
    }
}

/// The PGAs (g) at which the example fragility is drawn: 0.01, 0.02, …, 1.20.
pub fn example_pgas() -> Vec<f64> {
    (1..=120).map(|k| k as f64 * 0.01).collect()
}

/// Median and dispersion of the capacity of a block, from three laws
/// (16, 50, 84 %) in any order.
pub fn median_beta(laws: &[FractileLaw], p: f64, eps: f64) -> Option<(f64, f64)> {
    let at = |q: f64| {
        laws.iter()
            .find(|l| (l.quantile - q).abs() < 1e-9)
            .map(|l| l.eta_c(p, eps))
    };
    let (q16, q50, q84) = (at(0.16)?, at(0.5)?, at(0.84)?);
    if !(q16 > 0.0 && q50 > 0.0 && q84 > q16) {
        return None;
    }
    Some((q50, crate::stats::beta_of_fractiles(q16, q84)))
}

/// P(overturn | PGA) for `block` on the ground from its η_c,50 (`median`)
/// and β: the lognormal in PGA (g) of median α/η50, and 0 below the PGA
/// that lifts the block, g·tan α = b/h (it cannot move there; MODEL.md
/// §13): as `fragility`, `risk` and the exports count it, the same
/// functions ([`crate::cut::zero_below`], [`crate::cut::probability_above`]).
pub fn probability(median: f64, beta: f64, block: &Block, pga_g: f64) -> f64 {
    let f = crate::risk::Fragility::Lognormal {
        median: crate::im::pga_of_eta(median, block.alpha()),
        beta,
    };
    let cut = crate::cut::zero_below(block, crate::im::Im::Pga, None, None);
    crate::cut::probability_above(&f, pga_g, cut)
}

/// Where a regression is stretched for `block`: its ε or p beyond the
/// paper's grid (p 0.33–10 1/s, ε 0.5–0.95), or beyond a study's `blocks`
/// (given). One sentence each; none inside. What `fragility`, `risk`,
/// `export` warn of and the study's example fragility figure says.
pub fn stretched(block: &Block, blocks: Option<&[crate::pipeline::BlockSpec]>) -> Vec<String> {
    let span = |f: fn(&crate::pipeline::BlockSpec) -> f64, paper: (f64, f64)| {
        blocks.filter(|b| !b.is_empty()).map_or(paper, |b| {
            let v = b.iter().map(f);
            (
                v.clone().fold(f64::INFINITY, f64::min),
                v.fold(0.0, f64::max),
            )
        })
    };
    let whose = match blocks {
        Some(_) => "the study's",
        None => "the regression's",
    };
    let (eps_lo, eps_hi) = span(|b| b.eps, (0.5, 0.95));
    let (p_lo, p_hi) = span(|b| b.p, (0.33, 10.0));
    let mut w = Vec::new();
    // A grid's ends are written to three digits: within 1e-9 of them is on them.
    let inside = |x: f64, lo: f64, hi: f64| x >= lo * (1.0 - 1e-9) && x <= hi * (1.0 + 1e-9);
    if !inside(block.eps, eps_lo, eps_hi) {
        w.push(format!(
            "ε = {:.3} is outside {whose} {}–{}",
            block.eps,
            crate::im::level_text(eps_lo),
            crate::im::level_text(eps_hi)
        ));
    }
    let p = block.p();
    if !inside(p, p_lo, p_hi) {
        w.push(format!(
            "p = {p:.3} 1/s is outside {whose} {}–{} 1/s",
            crate::im::level_text(p_lo),
            crate::im::level_text(p_hi)
        ));
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_at_the_median_and_rising_with_pga() {
        let block = Block {
            b_m: 0.25,
            h_m: 1.0,
            eps: 0.85,
        };
        let (median, beta) = median_beta(&paper(), block.p(), block.eps).unwrap();
        let alpha = block.alpha();
        // η = η50 exactly when PGA = α/η50 (in g).
        assert!((probability(median, beta, &block, alpha / median) - 0.5).abs() < 1e-12);
        let mut last = 0.0;
        for k in 1..50 {
            let pr = probability(median, beta, &block, 0.02 * k as f64);
            assert!(pr >= last && (0.0..=1.0).contains(&pr));
            last = pr;
        }
        // One β of extra ln-intensity is Φ(1).
        let pga_1beta = alpha / (median * (-beta).exp());
        assert!(
            (probability(median, beta, &block, pga_1beta) - crate::stats::normal_cdf(1.0)).abs()
                < 1e-12
        );
    }

    #[test]
    fn paper_median_law_by_hand() {
        // ε = 0.5: a = 0.655, b = 0.3025, c = 1.82; at p = 2: 0.655 (1 − e^{−0.605})^{1.82}.
        let law = &paper()[1];
        let expected = 0.655 * (1.0 - (-0.605f64).exp()).powf(1.82);
        assert!((law.eta_c(2.0, 0.5) - expected).abs() < 1e-12);
        // A block of b = 0.2 m, h = 1 m: R = sqrt(1.04), p = sqrt(3g/(4R)).
        let b = Block {
            b_m: 0.2,
            h_m: 1.0,
            eps: 0.8,
        };
        assert!((b.p() - (3.0 * 9.80665 / (4.0 * 1.04f64.sqrt())).sqrt()).abs() < 1e-12);
        assert!(
            (Block::housner_eps(0.2, 1.0) - (1.0 - 1.5 * (0.2f64.atan().sin()).powi(2))).abs()
                < 1e-15
        );
    }
}
