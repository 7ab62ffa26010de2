//! A lognormal fitted to the records' capacities in an IM (MODEL.md §15):
//!
//! - by the paper's **fractile method**: median the 50 % fractile, β half
//!   the log distance between the 16 % and 84 % fractiles (records that never
//!   reach the state count as +∞, as the paper's survivors do);
//! - by **maximum likelihood** (Baker 2015, Earthquake Spectra 31(1)): the
//!   mean and standard deviation (n in the denominator) of ln capacity, with
//!   the records that never reach the state right-censored at the strongest
//!   intensity they were run at (their capacity lies above it). The censored
//!   likelihood is maximised by expectation–maximisation, which raises it at
//!   every step.

use crate::stats::{self, FractileDef};

/// How a block's fragility is made from its records' capacities: a
/// lognormal fitted two ways, or the records' own curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FitMethod {
    /// The paper's: 16/50/84 % fractiles (the default everywhere).
    Fractile,
    /// Maximum likelihood, censored.
    MaxLikelihood,
    /// No fit: the records' own curve, linear between their capacities
    /// ([`crate::damage::Curve`]; from the records' runs only).
    Empirical,
}

impl FitMethod {
    pub const ALL: [FitMethod; 3] = [
        FitMethod::Fractile,
        FitMethod::MaxLikelihood,
        FitMethod::Empirical,
    ];
    /// The methods that give a lognormal (the damage stage's table, the
    /// exports).
    pub const LOGNORMAL: [FitMethod; 2] = [FitMethod::Fractile, FitMethod::MaxLikelihood];

    pub fn name(self) -> &'static str {
        match self {
            FitMethod::Fractile => "fractile",
            FitMethod::MaxLikelihood => "mle",
            FitMethod::Empirical => "empirical",
        }
    }

    /// The other lognormal fit, to suggest where this one has none.
    pub fn other(self) -> FitMethod {
        match self {
            FitMethod::Fractile => FitMethod::MaxLikelihood,
            FitMethod::MaxLikelihood | FitMethod::Empirical => FitMethod::Fractile,
        }
    }

    pub fn parse(text: &str) -> Option<FitMethod> {
        FitMethod::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(text.trim()))
    }
}

impl crate::label::Label for FitMethod {
    const ALL: &'static [Self] = &FitMethod::ALL;
    const WHAT: &'static str = "fit";
    fn label(self) -> &'static str {
        self.name()
    }
    fn help(self) -> &'static str {
        match self {
            FitMethod::Fractile => "a lognormal by the paper's 16/50/84 % fractiles",
            FitMethod::MaxLikelihood => "a lognormal by censored maximum likelihood",
            FitMethod::Empirical => {
                "the records' own curve: their capacities' distribution, linear between them, \
                 whose quantiles are their fractiles (--direct only)"
            }
        }
    }
}

/// The dispersions of several damage states' lognormals.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Dispersion {
    /// One β for every state of a block (the heaviest state's), medians in
    /// order: a heavier state is never likelier than a lighter one
    /// ([`common_dispersion`]; the default).
    Common,
    /// Each state its own fit: their curves cross somewhere.
    Each,
}

impl crate::label::Label for Dispersion {
    const ALL: &'static [Self] = &[Dispersion::Common, Dispersion::Each];
    const WHAT: &'static str = "dispersion";
    fn label(self) -> &'static str {
        match self {
            Dispersion::Common => "common",
            Dispersion::Each => "each",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Dispersion::Common => {
                "one β for the states of a block, the heaviest state's, medians in order: \
                 the states never cross"
            }
            Dispersion::Each => "each state its own β: the curves cross somewhere",
        }
    }
}

/// What a block's fragility is where its records' capacities fail the
/// lognormal check (Lilliefors on their logarithms, at
/// [`LOGNORMAL_CHECK_LEVEL`]; `--direct` only).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IfNotLognormal {
    /// The records' own curve ([`crate::damage::Curve`]; the default).
    Curve,
    /// The lognormal anyway.
    Lognormal,
}

impl crate::label::Label for IfNotLognormal {
    const ALL: &'static [Self] = &[IfNotLognormal::Curve, IfNotLognormal::Lognormal];
    const WHAT: &'static str = "choice where the lognormal does not fit";
    fn label(self) -> &'static str {
        match self {
            IfNotLognormal::Curve => "curve",
            IfNotLognormal::Lognormal => "lognormal",
        }
    }
    fn help(self) -> &'static str {
        match self {
            IfNotLognormal::Curve => {
                "the records' own curve (as --method empirical), which the exports write as \
                 pelicun's multilinear_CDF and OpenQuake's discrete function"
            }
            IfNotLognormal::Lognormal => "the lognormal fit anyway",
        }
    }
}

crate::deserialize_by_label!(FitMethod, Dispersion, IfNotLognormal);

/// The significance level of the lognormal check: Lilliefors' p below it
/// rejects the lognormal (the paper's check of its fractile fits, at 5 %).
pub const LOGNORMAL_CHECK_LEVEL: f64 = 0.05;

/// How a block's fragility is made: the fit, the states' dispersions, and
/// what to do where the lognormal does not fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FitChoice {
    pub method: FitMethod,
    pub dispersion: Dispersion,
    pub if_not_lognormal: IfNotLognormal,
}

/// Damage states' lognormals (lightest first; `None` where a state has no
/// fit) made sequential: every state given the dispersion of the heaviest
/// state that has a fit, and each median lowered to the one after (the
/// next heavier state's) where it lies above it, so that the heaviest state
/// is never moved. Lognormals of one β cross nowhere, and with medians in
/// order a heavier state's probability never exceeds a lighter one's at
/// any level. Sequential damage states share one dispersion in many of
/// FEMA P-58's component fragilities (209 of the 459 with two or more
/// lognormal states in its database as pelicun carries it), and Porter,
/// Kennedy & Bachman (2007, Earthquake Spectra 23(2)) treat crossing
/// fragility functions as an error to correct (docs/MODEL.md §15). The
/// heaviest state's β and median are kept because that state (overturning)
/// is what the risk turns on: its fragility is then the block's own, one
/// answer whether or not the lighter states are asked for (a lighter
/// state's median above it, where the states come from different sources,
/// once raised it, and `risk --states` then differed from `risk`). The
/// lighter states' onsets are spread wider than their own fits say.
pub fn common_dispersion(fits: &mut [Option<Lognormal>]) {
    let Some(beta) = fits.iter().rev().flatten().map(|l| l.beta).next() else {
        return;
    };
    let mut ceiling = f64::INFINITY;
    for l in fits.iter_mut().rev().flatten() {
        l.beta = beta;
        l.median = l.median.min(ceiling);
        ceiling = l.median;
    }
}

/// A lognormal capacity: median θ (in the IM's unit) and dispersion β.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Lognormal {
    pub median: f64,
    pub beta: f64,
}

impl Lognormal {
    /// P(capacity ≤ x).
    pub fn cdf(&self, x: f64) -> f64 {
        if x <= 0.0 {
            return 0.0;
        }
        stats::normal_cdf((x / self.median).ln() / self.beta)
    }
}

/// Where the curve of a heavier state `b` rises above that of the lighter
/// state `a` (fitted lognormals of unequal β always cross once): the IML
/// and the probability there, when that probability lies within
/// [1e-3, 1 − 1e-3], where an engine's damage-state shares feel it.
pub fn crossing(a: &Lognormal, b: &Lognormal) -> Option<(f64, f64)> {
    if a.beta == b.beta {
        return None;
    }
    let ln_x = (b.beta * a.median.ln() - a.beta * b.median.ln()) / (b.beta - a.beta);
    let x = ln_x.exp();
    let p = a.cdf(x);
    (1e-3..=1.0 - 1e-3).contains(&p).then_some((x, p))
}

/// [`crossing`] where the block can move: none where the curves cross
/// below `cut` (the level below which every state's P is 0,
/// [`crate::cut::zero_below`]) and the heavier state `b` is the less
/// likely above it. What every command warns of and the report states.
pub fn crossing_above(a: &Lognormal, b: &Lognormal, cut: Option<f64>) -> Option<(f64, f64)> {
    let (x, p) = crossing(a, b)?;
    if cut.is_some_and(|c| x < c && b.cdf(c) <= a.cdf(c)) {
        return None;
    }
    Some((x, p))
}

/// Every pair of states, lighter `i` before heavier `j` (not only
/// neighbours: two neighbours may cross well away from where the lightest
/// and the heaviest do), whose fitted curves cross where the block can move
/// ([`crossing_above`]): `(i, j, x, P)`. States without a fit are skipped.
/// What every command warns of and the report states.
pub fn crossed_pairs(
    fits: &[Option<Lognormal>],
    cut: Option<f64>,
) -> Vec<(usize, usize, f64, f64)> {
    let mut out = Vec::new();
    for (i, a) in fits.iter().enumerate() {
        for (j, b) in fits.iter().enumerate().skip(i + 1) {
            if let (Some(a), Some(b)) = (a, b) {
                if let Some((x, p)) = crossing_above(a, b, cut) {
                    out.push((i, j, x, p));
                }
            }
        }
    }
    out
}

/// Lilliefors' p of the logarithms of `capacities` (sorted) where every
/// record reaches the state (5 or more) at two levels at least: capacities
/// all equal (to [`super::Curve`]'s ties: a state every record reaches as it
/// lifts, say) are a step, not a spread to test.
pub fn lognormal_p(capacities: &[f64]) -> Option<f64> {
    if capacities.iter().any(|c| !c.is_finite() || *c <= 0.0) {
        return None;
    }
    if super::Curve::of_capacities(capacities).levels().len() < 2 {
        return None;
    }
    let logs: Vec<f64> = capacities.iter().map(|c| c.ln()).collect();
    crate::stats::lilliefors(&logs).map(|l| l.p_value)
}

/// The fractile method on capacities (+∞ for a record that never reaches
/// the state). `None` when the 84 % fractile is +∞ (more records never
/// reach it than the fractile allows) or a fractile is not positive.
pub fn fractile_method(capacities: &[f64], def: FractileDef) -> Option<Lognormal> {
    let mut sorted = capacities.to_vec();
    sorted.sort_by(f64::total_cmp);
    let q = |q: f64| stats::fractile(&sorted, q, def).filter(|v| v.is_finite() && *v > 0.0);
    let (q16, q50, q84) = (q(0.16)?, q(0.5)?, q(0.84)?);
    Some(Lognormal {
        median: q50,
        beta: stats::beta_of_fractiles(q16, q84),
    })
}

/// Maximum likelihood on `reached` capacities, with `censored` ones known
/// only to exceed the given levels. `None` with fewer than two reached
/// values or reached values all equal.
pub fn max_likelihood(reached: &[f64], censored: &[f64]) -> Option<Lognormal> {
    let y: Vec<f64> = reached.iter().map(|v| v.ln()).collect();
    let c: Vec<f64> = censored.iter().map(|v| v.ln()).collect();
    if y.len() < 2 || y.iter().chain(&c).any(|v| !v.is_finite()) {
        return None;
    }
    let n = (y.len() + c.len()) as f64;
    let sum_y: f64 = y.iter().sum();
    let sum_y2: f64 = y.iter().map(|v| v * v).sum();
    let m = sum_y / y.len() as f64;
    let mut s = (y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / y.len() as f64).sqrt();
    if s <= 0.0 {
        return None;
    }
    let mut mu = m;
    // EM for right-censored normal data: the censored values replaced by
    // their conditional moments E[y | y > c] = μ + σλ and
    // E[y² | y > c] = μ² + σ² + σ(c + μ)λ, λ = φ(w)/Q(w), w = (c − μ)/σ.
    for _ in 0..100_000 {
        let (mut e1, mut e2) = (0.0, 0.0);
        for &ck in &c {
            let w = (ck - mu) / s;
            let lambda = inverse_mills(w);
            e1 += mu + s * lambda;
            e2 += mu * mu + s * s + s * (ck + mu) * lambda;
        }
        let mu_next = (sum_y + e1) / n;
        let var = (sum_y2 + e2) / n - mu_next * mu_next;
        let s_next = var.max(0.0).sqrt();
        let done =
            (mu_next - mu).abs() <= 1e-14 * (1.0 + mu.abs()) && (s_next - s).abs() <= 1e-14 * s;
        mu = mu_next;
        s = s_next;
        if done || c.is_empty() {
            break;
        }
    }
    (s > 0.0 && s.is_finite()).then(|| Lognormal {
        median: mu.exp(),
        beta: s,
    })
}

/// φ(w)/(1 − Φ(w)), accurate far into the upper tail.
fn inverse_mills(w: f64) -> f64 {
    let q = stats::normal_cdf(-w);
    let phi = (-0.5 * w * w).exp() / (2.0 * std::f64::consts::PI).sqrt();
    if q > 1e-300 {
        phi / q
    } else {
        // Q(w) ~ φ(w)/w (1 − 1/w² + 3/w⁴): λ ~ w + 1/w − 2/w³.
        w + 1.0 / w - 2.0 / w.powi(3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The heaviest state is never moved, whatever the lighter ones: a
    /// lighter median above a heavier one is lowered to it (it once raised
    /// the heavier one, overturning's included), a state without a fit is
    /// passed over, and every state takes the heaviest's β.
    #[test]
    fn common_dispersion_keeps_the_heaviest_state_as_it_is() {
        let l = |median, beta| Some(Lognormal { median, beta });
        let mut fits = [l(0.5, 0.1), None, l(0.3, 0.2), l(0.4, 0.35)];
        common_dispersion(&mut fits);
        let got: Vec<Option<(f64, f64)>> =
            fits.iter().map(|f| f.map(|l| (l.median, l.beta))).collect();
        assert_eq!(
            got,
            [
                Some((0.3, 0.35)),
                None,
                Some((0.3, 0.35)),
                Some((0.4, 0.35))
            ]
        );
        // Already in order: only the dispersions change.
        let mut fits = [l(0.2, 0.1), l(0.3, 0.2), l(0.4, 0.35)];
        common_dispersion(&mut fits);
        assert_eq!(fits.map(|f| f.unwrap().median), [0.2, 0.3, 0.4]);
    }
    use crate::stats::SplitMix64;

    fn normal(rng: &mut SplitMix64) -> f64 {
        // Box–Muller on two uniforms in (0, 1).
        let u = |r: &mut SplitMix64| ((r.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
        let (a, b) = (u(rng), u(rng));
        (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    }

    #[test]
    fn without_censoring_the_mle_is_the_log_mean_and_n_denominator_sd() {
        let x = [0.2, 0.35, 0.5, 0.9, 1.4];
        let logs: Vec<f64> = x.iter().map(|v: &f64| v.ln()).collect();
        let m = logs.iter().sum::<f64>() / 5.0;
        let s = (logs.iter().map(|v| (v - m).powi(2)).sum::<f64>() / 5.0).sqrt();
        let l = max_likelihood(&x, &[]).unwrap();
        assert!((l.median.ln() - m).abs() < 1e-15 && (l.beta - s).abs() < 1e-15);
    }

    /// 200,000 draws of a lognormal (median 0.5, β 0.4), every capacity
    /// above 0.8 censored there (about 12 %): the censored MLE recovers the
    /// truth within sampling error (standard errors about 1e-3), while the
    /// mean of the reached ones alone is biased low by about 0.07.
    #[test]
    fn censored_mle_recovers_a_known_lognormal() {
        let mut rng = SplitMix64::new(7);
        let (ln_median, beta, cut) = (0.5f64.ln(), 0.4, 0.8);
        let (mut reached, mut censored) = (Vec::new(), Vec::new());
        for _ in 0..200_000 {
            let v = (ln_median + beta * normal(&mut rng)).exp();
            if v > cut {
                censored.push(cut);
            } else {
                reached.push(v);
            }
        }
        let share = censored.len() as f64 / 200_000.0;
        assert!((share - 0.1195).abs() < 0.005, "{share}");
        let l = max_likelihood(&reached, &censored).unwrap();
        assert!((l.median.ln() - ln_median).abs() < 5e-3, "{l:?}");
        assert!((l.beta - beta).abs() < 5e-3, "{l:?}");
        let naive = max_likelihood(&reached, &[]).unwrap();
        assert!(naive.median.ln() < ln_median - 0.05);
    }

    /// The fractile method by hand on five values (type 7: the 16 % point
    /// at h = 1.64, the 84 % at 4.36), and +∞ beyond 84 % gives none.
    #[test]
    fn fractile_method_by_hand() {
        let x = [1.0, 2.0, 4.0, 8.0, 16.0];
        let l = fractile_method(&x, FractileDef::Type7).unwrap();
        let q16: f64 = 1.0 + 0.64 * 1.0;
        let q84 = 8.0 + 0.36 * 8.0;
        assert!((l.median - 4.0).abs() < 1e-15);
        assert!((l.beta - 0.5 * (q84 / q16).ln()).abs() < 1e-15);
        let inf = f64::INFINITY;
        assert!(fractile_method(&[1.0, 2.0, 4.0, inf, inf], FractileDef::Type7).is_none());
        assert!((l.cdf(4.0) - 0.5).abs() < 1e-15);
    }

    /// Curves that cross below the cut, the heavier state the less likely
    /// above it, are not said to cross (every state is 0 there); with no
    /// cut, or a cut below the crossing, they are.
    #[test]
    fn a_crossing_below_the_cut_is_not_one() {
        let lighter = Lognormal {
            median: 1.0,
            beta: 0.2,
        };
        let heavier = Lognormal {
            median: 1.5,
            beta: 0.6,
        };
        let (x, _) = crossing(&lighter, &heavier).unwrap();
        // ln x = (0.6·0 − 0.2·ln 1.5)/(0.6 − 0.2): below the lighter median.
        assert!((x.ln() + 0.5 * 1.5f64.ln()).abs() < 1e-12, "{x}");
        assert_eq!(
            crossing_above(&lighter, &heavier, None),
            crossing(&lighter, &heavier)
        );
        assert_eq!(
            crossing_above(&lighter, &heavier, Some(0.5 * x)),
            crossing(&lighter, &heavier)
        );
        assert_eq!(crossing_above(&lighter, &heavier, Some(1.0)), None);
    }

    /// Two curves crossing by hand: medians 1 and 2, β 0.2 and 0.6 meet
    /// where ln x/0.2 = (ln x − ln 2)/0.6, ln x = −ln 2/2, P = Φ(−1.733).
    #[test]
    fn crossing_by_hand() {
        let a = Lognormal {
            median: 1.0,
            beta: 0.2,
        };
        let b = Lognormal {
            median: 2.0,
            beta: 0.6,
        };
        let (x, p) = crossing(&a, &b).unwrap();
        assert!((x - 0.5f64.sqrt()).abs() < 1e-15);
        assert!((p - stats::normal_cdf(-0.5 * 2f64.ln() / 0.2)).abs() < 1e-15);
        assert!((b.cdf(x) - p).abs() < 1e-12);
        // Far apart: they cross where both are ~0.
        let c = Lognormal {
            median: 100.0,
            beta: 0.21,
        };
        assert!(crossing(&a, &c).is_none());
        assert!(crossing(&a, &a).is_none());
    }

    #[test]
    fn the_inverse_mills_ratio_is_continuous_into_the_tail() {
        // Exact values: λ(0) = 2φ(0) = 0.7978845608; λ(3) = 3.2830987.
        assert!((inverse_mills(0.0) - 0.797_884_560_802_865_4).abs() < 1e-12);
        assert!((inverse_mills(3.0) - 3.283_098_654_930_434).abs() < 1e-9);
        let (a, b) = (inverse_mills(37.0), inverse_mills(40.0));
        assert!((a - (37.0 + 1.0 / 37.0)).abs() < 1e-3 && b > a);
    }
}
