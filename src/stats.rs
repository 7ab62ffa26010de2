//! Statistics over the record suite (pure; docs/MODEL.md §5).
//!
//! - [`fractile`]: Hyndman & Fan (1996) sample quantiles of types 5–8, with
//!   +∞ allowed (a record that overturned): an interpolation that gives +∞
//!   any weight is +∞.
//! - [`lilliefors`]: the Lilliefors (1967) test of normality with estimated
//!   mean and variance: the statistic D and a p-value from the Dallal &
//!   Wilkinson (1986) analytic approximation, replaced above 0.1 (where that
//!   approximation is not meant to be used) by Stephens' (1974) modified
//!   statistic Z = D(√n − 0.01 + 0.85/√n) and the quartic fits of R's
//!   `nortest::lillie.test` (J. Gross). So p-values match R's; statsmodels
//!   (which interpolates Dallal–Wilkinson's table above 0.1) and MATLAB
//!   (Monte Carlo tables) can differ in the third digit.
//! - [`normal_cdf`] / [`normal_quantile`]: from statrs.
//! - [`quantile_bands`]: percentile bootstrap bands of sample quantiles,
//!   resampling whole groups (the two components of a record pair), with
//!   [`SplitMix64`] draws so that a seed gives the same bands anywhere.

use statrs::distribution::{ContinuousCDF, Normal};

use serde::Serialize;

/// Fractile definitions (Hyndman & Fan 1996), `reduce.fractile` in a pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FractileDef {
    /// Linear interpolation between order statistics, p(k) = (k − 1)/(n − 1):
    /// numpy's and R's default.
    Type7,
    /// p(k) = (k − 0.5)/n: MATLAB's `prctile`.
    Type5,
    /// p(k) = k/(n + 1): Weibull plotting positions.
    Type6,
    /// p(k) = (k − 1/3)/(n + 1/3): approximately median-unbiased (statrs' default).
    Type8,
}

impl FractileDef {
    pub const NAMES: &'static str = "type7 (default), type5 (MATLAB prctile), type6, type8";

    /// The name a pipeline gives it (`reduce.fractile`).
    pub fn name(self) -> &'static str {
        match self {
            FractileDef::Type7 => "type7",
            FractileDef::Type5 => "type5",
            FractileDef::Type6 => "type6",
            FractileDef::Type8 => "type8",
        }
    }

    /// The definition as a reader names it.
    pub fn describe(self) -> &'static str {
        match self {
            FractileDef::Type7 => {
                "Hyndman & Fan type 7 (linear between order statistics; numpy's and R's default)"
            }
            FractileDef::Type5 => "Hyndman & Fan type 5 (MATLAB's prctile)",
            FractileDef::Type6 => "Hyndman & Fan type 6 (Weibull plotting positions)",
            FractileDef::Type8 => "Hyndman & Fan type 8 (approximately median-unbiased)",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "type7" => Some(FractileDef::Type7),
            "type5" => Some(FractileDef::Type5),
            "type6" => Some(FractileDef::Type6),
            "type8" => Some(FractileDef::Type8),
            _ => None,
        }
    }
}

/// What the bootstrap resamples: whole pairs of components (the two
/// components of a FEMA P695 pair share an earthquake and a station) or
/// single records.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ResampleUnit {
    Pair,
    Record,
}

impl crate::label::Label for ResampleUnit {
    const ALL: &'static [Self] = &[ResampleUnit::Pair, ResampleUnit::Record];
    fn label(self) -> &'static str {
        match self {
            ResampleUnit::Pair => "pair",
            ResampleUnit::Record => "record",
        }
    }
}

/// The 1-based position h in a sorted sample of `n ≥ 1` of its
/// q-quantile by definition `def` (Hyndman & Fan 1996, Table 1), in [1, n]:
/// the quantile interpolates between the ⌊h⌋-th and the ⌈h⌉-th values.
pub fn position(n: usize, q: f64, def: FractileDef) -> f64 {
    let nf = n as f64;
    match def {
        FractileDef::Type5 => nf * q + 0.5,
        FractileDef::Type6 => (nf + 1.0) * q,
        FractileDef::Type7 => (nf - 1.0) * q + 1.0,
        FractileDef::Type8 => (nf + 1.0 / 3.0) * q + 1.0 / 3.0,
    }
    .clamp(1.0, nf.max(1.0))
}

/// The q-quantile (0 ≤ q ≤ 1) of `sorted` (ascending, +∞ allowed at the
/// end, no NaN) by definition `def`. `None` for an empty sample.
pub fn fractile(sorted: &[f64], q: f64, def: FractileDef) -> Option<f64> {
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    let h = position(n, q, def);
    let lo = h.floor();
    let frac = h - lo;
    let i = lo as usize - 1;
    let a = sorted[i];
    if frac == 0.0 || i + 1 >= n {
        return Some(a);
    }
    let b = sorted[i + 1];
    if a.is_infinite() || b.is_infinite() {
        return Some(f64::INFINITY);
    }
    Some(a + frac * (b - a))
}

/// The distinct values of `v`, ascending (NaN-free input).
pub fn distinct(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(|a, b| a.total_cmp(b));
    v.dedup();
    v
}

/// Standard normal CDF Φ.
pub fn normal_cdf(z: f64) -> f64 {
    Normal::standard().cdf(z)
}

/// Inverse of Φ.
pub fn normal_quantile(p: f64) -> f64 {
    Normal::standard().inverse_cdf(p)
}

/// The lognormal dispersion of the 16 and 84 % fractiles, the paper's
/// fractile method: β = ln(q₈₄/q₁₆)/2. Every fit by fractiles (a study's
/// lognormal table, `--direct`, the regression's laws) takes it here.
pub fn beta_of_fractiles(q16: f64, q84: f64) -> f64 {
    0.5 * (q84 / q16).ln()
}

/// Mean and sample standard deviation (n − 1).
pub fn mean_sd(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

/// Result of the Lilliefors test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lilliefors {
    /// max |F_n − Φ((x − x̄)/s)|.
    pub d: f64,
    pub p_value: f64,
}

/// Lilliefors test of `x` (at least 5 values, not all equal).
pub fn lilliefors(x: &[f64]) -> Option<Lilliefors> {
    let n = x.len();
    if n < 5 {
        return None;
    }
    let (mean, sd) = mean_sd(x);
    if sd.is_nan() || sd <= 0.0 {
        return None;
    }
    let mut z: Vec<f64> = x.iter().map(|v| (v - mean) / sd).collect();
    z.sort_by(|a, b| a.total_cmp(b));
    let nf = n as f64;
    let mut d: f64 = 0.0;
    for (i, zi) in z.iter().enumerate() {
        let p = normal_cdf(*zi);
        d = d.max((i as f64 + 1.0) / nf - p).max(p - i as f64 / nf);
    }
    Some(Lilliefors {
        d,
        p_value: lilliefors_p_value(d, n),
    })
}

/// P(D ≥ d) under normality for a sample of `n` (see the module docs).
pub fn lilliefors_p_value(d: f64, n: usize) -> f64 {
    let nf = n as f64;
    let (kd, nd) = if n <= 100 {
        (d, nf)
    } else {
        (d * (nf / 100.0).powf(0.49), 100.0)
    };
    let dw = (-7.01256 * kd * kd * (nd + 2.78019) + 2.99587 * kd * (nd + 2.78019).sqrt()
        - 0.122119
        + 0.974598 / nd.sqrt()
        + 1.67997 / nd)
        .exp();
    if dw <= 0.1 {
        return dw;
    }
    let k = (nf.sqrt() - 0.01 + 0.85 / nf.sqrt()) * d;
    let p = if k <= 0.302 {
        1.0
    } else if k <= 0.5 {
        2.76773 - 19.828315 * k + 80.709644 * k.powi(2) - 138.55152 * k.powi(3)
            + 81.218052 * k.powi(4)
    } else if k <= 0.9 {
        -4.901232 + 40.662806 * k - 97.490286 * k.powi(2) + 94.029866 * k.powi(3)
            - 32.355711 * k.powi(4)
    } else if k <= 1.31 {
        6.198765 - 19.558097 * k + 23.186922 * k.powi(2) - 12.234627 * k.powi(3)
            + 2.423045 * k.powi(4)
    } else {
        0.0
    };
    p.clamp(0.0, 1.0)
}

/// The D at which the p-value falls to `alpha` (bisection; p is decreasing in D).
pub fn lilliefors_critical_value(n: usize, alpha: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if lilliefors_p_value(mid, n) > alpha {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use FractileDef::*;

    #[test]
    fn fractiles_by_hand() {
        // [1, 2, 3, 4], q = 0.25 — type 7: h = 1 + 3·0.25 = 1.75 → 1.75;
        // type 5: h = 4·0.25 + 0.5 = 1.5 → 1.5; type 6: h = 5·0.25 = 1.25 → 1.25;
        // type 8: h = (4 + 1/3)·0.25 + 1/3 = 1.41667 → 1.41667 (statrs' default).
        let x = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(fractile(&x, 0.25, Type7), Some(1.75));
        assert_eq!(fractile(&x, 0.25, Type5), Some(1.5));
        assert_eq!(fractile(&x, 0.25, Type6), Some(1.25));
        assert!((fractile(&x, 0.25, Type8).unwrap() - (1.0 + 5.0 / 12.0)).abs() < 1e-15);
        // The median of an even sample is the mean of the middle two for all four.
        for def in [Type5, Type6, Type7, Type8] {
            assert_eq!(fractile(&x, 0.5, def), Some(2.5));
        }
        // Ends clamp to the extremes.
        assert_eq!(fractile(&x, 0.0, Type5), Some(1.0));
        assert_eq!(fractile(&x, 1.0, Type6), Some(4.0));
        assert_eq!(fractile(&[], 0.5, Type7), None);
    }

    #[test]
    fn infinity_wins_any_interpolation_it_takes_part_in() {
        // 10 records, 3 overturned (EDP = +∞).
        let mut x: Vec<f64> = (1..=7).map(|k| k as f64 / 10.0).collect();
        x.extend([f64::INFINITY; 3]);
        // type 7, q = 0.5: h = 1 + 9·0.5 = 5.5 → between x5 = 0.5 and x6 = 0.6.
        assert!((fractile(&x, 0.5, Type7).unwrap() - 0.55).abs() < 1e-15);
        // q = 0.84: h = 1 + 9·0.84 = 8.56 → between x8 = ∞ and x9 = ∞.
        assert_eq!(fractile(&x, 0.84, Type7), Some(f64::INFINITY));
        // q = 0.7: h = 7.3 → between x7 = 0.7 and x8 = ∞: touches ∞.
        assert_eq!(fractile(&x, 0.7, Type7), Some(f64::INFINITY));
        // q = 2/3: h = 7 exactly → x7 = 0.7, ∞ gets no weight.
        assert!((fractile(&x, 2.0 / 3.0, Type7).unwrap() - 0.7).abs() < 1e-12);
        // type 5, q = 0.16: h = 10·0.16 + 0.5 = 2.1 → 0.2 + 0.1·0.1 = 0.21.
        assert!((fractile(&x, 0.16, Type5).unwrap() - 0.21).abs() < 1e-15);
    }

    #[test]
    fn lilliefors_statistic_by_hand() {
        // x = −1, 0, 1, 2, 3: mean 1, s = sqrt(2.5). The largest gap is at the
        // extremes: z = ±2/sqrt(2.5) = ±1.26491, Φ(−1.26491) = 0.10295;
        // D = max(1/5 − 0.10295, …) = 0.09705 (symmetric sample).
        let t = lilliefors(&[-1.0, 0.0, 1.0, 2.0, 3.0]).unwrap();
        let phi = normal_cdf(-2.0 / 2.5f64.sqrt());
        let expected = (0.2 - phi)
            .max(phi - 0.0)
            .max(0.4 - normal_cdf(-1.0 / 2.5f64.sqrt()));
        assert!((t.d - expected).abs() < 1e-15);
        assert!(
            t.p_value > 0.2,
            "an evenly spread sample is not rejected: {}",
            t.p_value
        );
        assert!(lilliefors(&[1.0; 8]).is_none());
        assert!(lilliefors(&[1.0, 2.0, 3.0]).is_none());
    }

    #[test]
    fn critical_values_match_lilliefors_1967() {
        // Lilliefors (1967), Table 1, 5 % column: n = 5: 0.337, 10: 0.258,
        // 15: 0.220, 20: 0.190, 25: 0.173, 30: 0.161, over 30: 0.886/√n; 1 %:
        // n = 20: 0.231, over 30: 1.031/√n. His table came from 1,000-sample
        // Monte Carlo runs and Dallal & Wilkinson (1986) found it slightly
        // low; agreement to 0.01 (about 5 % of D) is what to expect.
        for (n, d5) in [
            (5, 0.337),
            (10, 0.258),
            (15, 0.220),
            (20, 0.190),
            (25, 0.173),
            (30, 0.161),
        ] {
            let c = lilliefors_critical_value(n, 0.05);
            assert!((c - d5).abs() < 0.01, "n = {n}: {c} vs {d5}");
        }
        for n in [44usize, 60, 100] {
            let c = lilliefors_critical_value(n, 0.05);
            let published = 0.886 / (n as f64).sqrt();
            assert!((c - published).abs() < 0.01, "n = {n}: {c} vs {published}");
            let c1 = lilliefors_critical_value(n, 0.01);
            assert!(
                (c1 - 1.031 / (n as f64).sqrt()).abs() < 0.01,
                "n = {n}, 1 %: {c1}"
            );
        }
        assert!((lilliefors_critical_value(20, 0.01) - 0.231).abs() < 0.01);
    }

    #[test]
    fn p_value_is_continuous_and_decreasing() {
        let mut last = 1.0;
        for k in 0..400 {
            let d = 0.01 + k as f64 * 0.001;
            let p = lilliefors_p_value(d, 44);
            assert!(p <= last + 0.02, "d = {d}: {p} after {last}");
            last = p;
        }
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014, the generator Java's
/// `SplittableRandom` and the xoshiro authors use for seeding): 64 bits of
/// state, one add and two multiply-xorshifts per draw.
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    /// A generator for stream `stream` of `seed` (a block, say): streams
    /// start far apart and are drawn independently of each other.
    pub fn stream(seed: u64, stream: u64) -> Self {
        let mut g = SplitMix64(seed ^ stream.wrapping_mul(0xD1B5_4A32_D192_ED03));
        let start = g.next_u64();
        SplitMix64(start)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (Lemire's multiply-shift; its bias, below
    /// n/2⁶⁴, is far below anything a bootstrap can see).
    pub fn below(&mut self, n: usize) -> usize {
        ((u128::from(self.next_u64()) * n as u128) >> 64) as usize
    }
}

/// Resampling units of a sample (the pairs of a record set, say): which
/// members (indices into the sample) each unit holds. One draw picks as many
/// units as there are, with replacement, and keeps every member of a drawn
/// unit, so one resample of indices can be applied to many statistics at
/// once (every block of a grid sees the same records).
#[derive(Debug, Clone)]
pub struct Units {
    members: Vec<Vec<usize>>,
}

impl Units {
    /// Units from each member's unit number (`unit_of[i]` for member `i`;
    /// numbers need not be dense: unused numbers are dropped).
    pub fn new(unit_of: &[usize]) -> Self {
        let n = unit_of.iter().max().map_or(0, |m| m + 1);
        let mut members = vec![Vec::new(); n];
        for (i, &u) in unit_of.iter().enumerate() {
            members[u].push(i);
        }
        members.retain(|m| !m.is_empty());
        Units { members }
    }

    /// How many units there are.
    pub fn count(&self) -> usize {
        self.members.len()
    }

    /// One resample: the members of `count()` units drawn with replacement,
    /// into `out` (cleared first), in draw order.
    pub fn draw(&self, rng: &mut SplitMix64, out: &mut Vec<usize>) {
        out.clear();
        for _ in 0..self.members.len() {
            out.extend_from_slice(&self.members[rng.below(self.members.len())]);
        }
    }
}

/// Each key's number, the keys numbered in order of first appearance
/// (0, 1, …): the resampling units of records by their pairs.
pub fn numbered_by_first<T: PartialEq>(keys: &[T]) -> Vec<usize> {
    let mut seen: Vec<&T> = Vec::new();
    keys.iter()
        .map(|k| match seen.iter().position(|s| *s == k) {
            Some(i) => i,
            None => {
                seen.push(k);
                seen.len() - 1
            }
        })
        .collect()
}

/// The percentile band of bootstrap estimates at `level`: their
/// (1 − level)/2 and (1 + level)/2 fractiles (type 7). Sorts `estimates`;
/// `None` when empty or a value is NaN.
pub fn percentile_band(estimates: &mut [f64], level: f64) -> Option<(f64, f64)> {
    if estimates.iter().any(|v| v.is_nan()) {
        return None;
    }
    estimates.sort_by(|x, y| x.total_cmp(y));
    let (a, b) = ((1.0 - level) / 2.0, (1.0 + level) / 2.0);
    Some((
        fractile(estimates, a, FractileDef::Type7)?,
        fractile(estimates, b, FractileDef::Type7)?,
    ))
}

/// The `quantiles` of `values` over the members `draw` (indices into
/// `values`, repeats allowed) into `out`, sorting them in `pooled` (reused
/// across calls). `None` for an empty draw. One resample of one statistic:
/// the reduce stage applies one draw to every block's values.
pub fn fractiles_of_draw(
    values: &[f64],
    draw: &[usize],
    quantiles: &[f64],
    def: FractileDef,
    pooled: &mut Vec<f64>,
    out: &mut [f64],
) -> Option<()> {
    pooled.clear();
    pooled.extend(draw.iter().map(|&i| values[i]));
    pooled.sort_by(|a, b| a.total_cmp(b));
    for (o, &q) in out.iter_mut().zip(quantiles) {
        *o = fractile(pooled, q, def)?;
    }
    Some(())
}

/// Percentile bootstrap bands of the `quantiles` of the pooled values of
/// `groups` (the non-empty groups are the units; each resample draws as many
/// units with replacement, [`Units::draw`]): for each quantile,
/// [`percentile_band`] of its estimate over `resamples` resamples. `None`
/// without values.
pub fn quantile_bands(
    groups: &[Vec<f64>],
    quantiles: &[f64],
    def: FractileDef,
    resamples: usize,
    level: f64,
    rng: &mut SplitMix64,
) -> Option<Vec<(f64, f64)>> {
    let values: Vec<f64> = groups.iter().flatten().copied().collect();
    if values.is_empty() || resamples == 0 {
        return None;
    }
    let unit_of: Vec<usize> = groups
        .iter()
        .enumerate()
        .flat_map(|(u, g)| std::iter::repeat_n(u, g.len()))
        .collect();
    let units = Units::new(&unit_of);
    let mut estimates: Vec<Vec<f64>> = vec![Vec::with_capacity(resamples); quantiles.len()];
    let (mut draw, mut pooled, mut q) = (Vec::new(), Vec::new(), vec![0.0; quantiles.len()]);
    for _ in 0..resamples {
        units.draw(rng, &mut draw);
        fractiles_of_draw(&values, &draw, quantiles, def, &mut pooled, &mut q)?;
        for (est, &v) in estimates.iter_mut().zip(&q) {
            est.push(v);
        }
    }
    estimates
        .iter_mut()
        .map(|est| percentile_band(est, level))
        .collect()
}

#[cfg(test)]
mod bootstrap_tests {
    use super::*;

    /// Pair resampling keeps both components of a pair together: in every
    /// resample each pair's two (distinct) values appear equally often.
    #[test]
    fn pairs_stay_together() {
        let values: Vec<f64> = (0..22).flat_map(|i| [i as f64, 100.0 + i as f64]).collect();
        let units = Units::new(&(0..44).map(|k| k / 2).collect::<Vec<_>>());
        let mut rng = SplitMix64::new(7);
        let mut draw = Vec::new();
        for _ in 0..200 {
            units.draw(&mut rng, &mut draw);
            let out: Vec<f64> = draw.iter().map(|&k| values[k]).collect();
            assert_eq!(out.len(), 44);
            for i in 0..22 {
                let a = out.iter().filter(|&&v| v == i as f64).count();
                let b = out.iter().filter(|&&v| v == 100.0 + i as f64).count();
                assert_eq!(a, b, "pair {i}");
            }
        }
    }

    /// `Units` keeps a unit's members together too, and draws as many units
    /// as there are: record i of 44 belongs to pair i / 2 (the manifest's
    /// order), and every resample holds both records of each drawn pair.
    #[test]
    fn units_draw_whole_pairs() {
        let unit_of: Vec<usize> = (0..44).map(|i| 2 * (i / 2) + 7).collect();
        let units = Units::new(&unit_of);
        assert_eq!(units.count(), 22);
        let mut rng = SplitMix64::new(11);
        let mut out = Vec::new();
        for _ in 0..200 {
            units.draw(&mut rng, &mut out);
            assert_eq!(out.len(), 44);
            for pair in 0..22 {
                let first = out.iter().filter(|&&i| i == 2 * pair).count();
                let second = out.iter().filter(|&&i| i == 2 * pair + 1).count();
                assert_eq!(first, second, "pair {pair}");
            }
        }
        let mut est = vec![3.0, 1.0, 2.0, 5.0, 4.0];
        // Type 7 at 0.05 and 0.95 of 1..5: 1 + 4·0.05 = 1.2 and 4.8.
        let (lo, hi) = percentile_band(&mut est, 0.9).unwrap();
        assert!((lo - 1.2).abs() < 1e-12 && (hi - 4.8).abs() < 1e-12);
        assert!(percentile_band(&mut [], 0.9).is_none());
    }

    /// The draws are uniform: over 220,000 draws of 0..22 every value's
    /// count is within 5 standard deviations of 10,000 (sd ≈ 97.6).
    #[test]
    fn draws_are_uniform_and_repeatable() {
        let mut rng = SplitMix64::stream(3, 5);
        let mut counts = [0usize; 22];
        for _ in 0..220_000 {
            counts[rng.below(22)] += 1;
        }
        assert!(
            counts
                .iter()
                .all(|&c| (c as f64 - 10_000.0).abs() < 5.0 * 97.6),
            "{counts:?}"
        );
        let a: Vec<u64> = (0..5)
            .map(|_| SplitMix64::stream(3, 5).next_u64())
            .collect();
        assert!(a.windows(2).all(|w| w[0] == w[1]));
        assert_ne!(
            SplitMix64::stream(3, 5).next_u64(),
            SplitMix64::stream(3, 6).next_u64()
        );
    }

    /// Coverage: 44 standard normal samples, bands of the 16/50/84 %
    /// quantiles at level 0.90 from 500 resamples, over 2,000 data sets. The
    /// true quantiles (−0.994, 0, 0.994) should be covered about 90 % of the
    /// time. Tolerance: the binomial sd of 2,000 trials is 0.7 points; the
    /// percentile bootstrap of a sample quantile at n = 44 is itself off its
    /// nominal level by a few points, low in the tails (its coverage error is
    /// O(n^-1/2) for quantiles; Hall & Martin 1988), so 0.84–0.95. A band of
    /// the wrong level (0.8: about 80 %) or of the wrong statistic misses it.
    #[test]
    fn bands_cover_the_true_quantiles_at_about_the_nominal_rate() {
        let truth = [normal_quantile(0.16), 0.0, normal_quantile(0.84)];
        let mut data_rng = SplitMix64::new(12);
        let mut covered = [0usize; 3];
        let trials = 2000;
        for t in 0..trials {
            // Standard normals from uniform draws, through the quantile function.
            let groups: Vec<Vec<f64>> = (0..44)
                .map(|_| {
                    let u = (data_rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
                    vec![normal_quantile(u.clamp(1e-12, 1.0 - 1e-12))]
                })
                .collect();
            let mut rng = SplitMix64::stream(1, t);
            let bands = quantile_bands(
                &groups,
                &[0.16, 0.5, 0.84],
                FractileDef::Type7,
                500,
                0.9,
                &mut rng,
            )
            .unwrap();
            for (i, (lo, hi)) in bands.iter().enumerate() {
                covered[i] += usize::from(*lo <= truth[i] && truth[i] <= *hi);
            }
        }
        for c in covered {
            let rate = c as f64 / trials as f64;
            assert!(
                (0.84..=0.95).contains(&rate),
                "coverage {covered:?} of {trials}"
            );
        }
    }
}
