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

use statrs::distribution::{ContinuousCDF, Normal};

use crate::pipeline::FractileDef;

/// The q-quantile (0 ≤ q ≤ 1) of `sorted` (ascending, +∞ allowed at the
/// end, no NaN) by definition `def`. `None` for an empty sample.
pub fn fractile(sorted: &[f64], q: f64, def: FractileDef) -> Option<f64> {
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    let nf = n as f64;
    // 1-based position h (Hyndman & Fan 1996, Table 1).
    let h = match def {
        FractileDef::Type5 => nf * q + 0.5,
        FractileDef::Type6 => (nf + 1.0) * q,
        FractileDef::Type7 => (nf - 1.0) * q + 1.0,
        FractileDef::Type8 => (nf + 1.0 / 3.0) * q + 1.0 / 3.0,
    }
    .clamp(1.0, nf);
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
