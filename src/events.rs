//! Risk from events rather than hazard curves (pure; docs/MODEL.md §20):
//! the annual rate of a damage state as OpenQuake's event-based damage
//! states it (the sum over events of each event's probability, over the
//! effective investigation time), and how many items of an inventory fall
//! in one event: its count distribution given the event's ground motion,
//! the rate of k or more items per year and the number at a return period.

use serde::Serialize;

/// How the items at one site fall together, given the event's ground
/// motion at the site.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Together {
    /// One record shakes every item at the site: an item falls when the
    /// record is stronger than its capacity, and the record's strength
    /// relative to the IM (the fragility's record-to-record dispersion) is
    /// shared, so the items fall in the order of their fragilities, with
    /// one common uniform draw U: item i falls when U < pᵢ (identical items
    /// all fall or none). The default: it is what the fragility's
    /// dispersion is.
    SameRecord,
    /// Each item falls on its own draw (independent given the IMs): the
    /// narrowest count distribution, for items whose dispersion is their
    /// own rather than the record's.
    Independent,
}

impl crate::label::Label for Together {
    const ALL: &'static [Self] = &[Together::SameRecord, Together::Independent];
    const WHAT: &'static str = "dependence of the items at a site";
    fn label(self) -> &'static str {
        match self {
            Together::SameRecord => "same-record",
            Together::Independent => "independent",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Together::SameRecord => {
                "one record shakes them all: they fall in the order of their fragilities (identical items all or none)"
            }
            Together::Independent => "each item falls on its own draw, given the IMs",
        }
    }
}

crate::deserialize_by_label!(Together);

/// P(N = k), k = 0..=n, of the number N of items that fall, item i with
/// probability `p[i]`, as `together` says.
pub fn count_pmf(p: &[f64], together: Together) -> Vec<f64> {
    let n = p.len();
    match together {
        // Poisson-binomial, by the exact recursion over the items.
        Together::Independent => {
            let mut pmf = vec![0.0; n + 1];
            pmf[0] = 1.0;
            // An item of pᵢ = 0 leaves the pmf as it is, to the bit (×1,
            // +0): skipped, so that an event few items feel costs little.
            for (i, &q) in p.iter().filter(|&&q| q != 0.0).enumerate() {
                for k in (0..=i + 1).rev() {
                    let stay = pmf[k] * (1.0 - q);
                    let from = if k > 0 { pmf[k - 1] * q } else { 0.0 };
                    pmf[k] = stay + from;
                }
            }
            pmf
        }
        // N ≥ k exactly when U is below the k-th largest pᵢ.
        Together::SameRecord => {
            let mut sorted: Vec<f64> = p.to_vec();
            sorted.sort_by(|a, b| b.total_cmp(a));
            let at_least = |k: usize| if k == 0 { 1.0 } else { sorted[k - 1] };
            (0..=n)
                .map(|k| at_least(k) - if k < n { at_least(k + 1) } else { 0.0 })
                .collect()
        }
    }
}

/// The distribution of a sum of independent counts (sites apart: the
/// fields' correlation is already in their IMs): the convolution of their
/// pmfs.
pub fn convolve(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

/// Rates of at least k items per year (k = 0..), from each event's pmf:
/// Σ_events P(N ≥ k) / `eff_years`.
pub fn exceedance_rates(pmfs: &[Vec<f64>], eff_years: f64) -> Vec<f64> {
    let n = pmfs.iter().map(Vec::len).max().unwrap_or(1);
    let mut rates = vec![0.0; n];
    for pmf in pmfs {
        let mut tail = 0.0;
        for k in (0..pmf.len()).rev() {
            tail += pmf[k];
            rates[k] += tail;
        }
    }
    rates.iter().map(|r| r / eff_years).collect()
}

/// The number of items at return period `years`: the largest k whose rate
/// of k or more per year is at least 1/`years` (0 when none is).
pub fn number_at(rates: &[f64], years: f64) -> usize {
    rates
        .iter()
        .enumerate()
        .skip(1)
        .filter(|(_, &r)| r >= 1.0 / years)
        .map(|(k, _)| k)
        .next_back()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both rules sum to 1 and have the mean Σ pᵢ; the same-record rule of
    /// identical items is all or none.
    #[test]
    fn counts_sum_to_one_with_the_mean_of_the_items() {
        let p = [0.1, 0.5, 0.25, 0.9];
        for t in [Together::Independent, Together::SameRecord] {
            let pmf = count_pmf(&p, t);
            assert!((pmf.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            let mean: f64 = pmf.iter().enumerate().map(|(k, q)| k as f64 * q).sum();
            assert!((mean - 1.75).abs() < 1e-15, "{t:?}: {mean}");
        }
        let same = count_pmf(&[0.3; 3], Together::SameRecord);
        assert_eq!(same, [0.7, 0.0, 0.0, 0.3]);
        // Binomial for identical independent items: C(3,k) 0.3^k 0.7^(3−k).
        let ind = count_pmf(&[0.3; 3], Together::Independent);
        for (k, c) in [1.0, 3.0, 3.0, 1.0].iter().enumerate() {
            let b = c * 0.3f64.powi(k as i32) * 0.7f64.powi(3 - k as i32);
            assert!((ind[k] - b).abs() < 1e-15);
        }
    }
}
