//! The records' own fragility curve (MODEL.md §15): the cumulative
//! distribution of a block's capacities over the records, linear between
//! them, with no shape assumed. It is the curve whose quantiles are the
//! records' fractiles (numpy's and R's default, Hyndman & Fan's type 7,
//! as the paper's and `--direct`'s fractiles are): the i-th smallest of n
//! capacities x₍ᵢ₎ has P = (i − 1)/(n − 1), and P rises linearly between
//! two of them; 0 below the smallest; beyond the largest, 1. Its median is
//! the records' 50 % fractile.
//!
//! It is what `--method empirical` means for every command, and what the
//! exports write where a lognormal does not fit (pelicun's
//! `multilinear_CDF`, OpenQuake's `format="discrete"`): both engines
//! interpolate linearly between the points they are given, so they read
//! the same function.
//!
//! Records that never reach the state (+∞) keep their rank: the curve
//! stops rising at the largest finite capacity, at (k − 1)/(n − 1) for k
//! finite of n, and stays there; such a curve is not complete ([`Curve::
//! complete`]) and no engine takes it. Equal capacities (within 1e-9 of
//! each other, relatively) are one point, at the highest P of their ranks:
//! the engines need strictly increasing levels.

/// Levels closer than this (relative) are one point.
const TIE: f64 = 1e-9;

/// A piecewise-linear fragility curve through its points.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Curve {
    /// The levels, strictly increasing, finite and positive (IM unit).
    x: Vec<f64>,
    /// P(state reached | level), non-decreasing, from 0 at the first
    /// (unless one record only: a step to 1).
    p: Vec<f64>,
}

impl Curve {
    /// The curve of `sorted` capacities (ascending, +∞ for a record that
    /// never reaches the state).
    pub fn of_capacities(sorted: &[f64]) -> Curve {
        debug_assert!(sorted.windows(2).all(|w| w[0] <= w[1]));
        let n = sorted.len();
        let mut x: Vec<f64> = Vec::with_capacity(n);
        let mut p: Vec<f64> = Vec::with_capacity(n);
        for (i, &c) in sorted.iter().enumerate() {
            if !c.is_finite() {
                break;
            }
            let pi = if n == 1 {
                1.0
            } else {
                i as f64 / (n - 1) as f64
            };
            match x.last() {
                Some(&last) if c - last <= TIE * c => *p.last_mut().expect("paired") = pi,
                _ => {
                    x.push(c);
                    p.push(pi);
                }
            }
        }
        Curve { x, p }
    }

    /// A curve through `points` (level, P): `None` unless the levels are
    /// finite, positive and strictly increasing and P non-decreasing in
    /// [0, 1].
    pub fn through(points: &[(f64, f64)]) -> Option<Curve> {
        let ok = points
            .iter()
            .all(|&(x, p)| x.is_finite() && x > 0.0 && (0.0..=1.0).contains(&p))
            && points
                .windows(2)
                .all(|w| w[0].0 < w[1].0 && w[0].1 <= w[1].1);
        (ok && !points.is_empty()).then(|| Curve {
            x: points.iter().map(|p| p.0).collect(),
            p: points.iter().map(|p| p.1).collect(),
        })
    }

    /// P(state reached | `a`): 0 below the first point, linear between
    /// points, the last point's beyond it.
    pub fn probability(&self, a: f64) -> f64 {
        let i = self.x.partition_point(|&x| x <= a);
        if i == 0 {
            return 0.0;
        }
        if i == self.x.len() {
            return self.p[i - 1];
        }
        let (x0, x1, p0, p1) = (self.x[i - 1], self.x[i], self.p[i - 1], self.p[i]);
        p0 + (p1 - p0) * ((a - x0) / (x1 - x0))
    }

    /// P just below `a` (the left limit): as [`Curve::probability`] but
    /// for the step at the first point (a curve of one record).
    pub fn probability_below(&self, a: f64) -> f64 {
        if self.x.first().is_some_and(|&x0| a <= x0) {
            0.0
        } else {
            self.probability(a)
        }
    }

    /// P as the level grows without bound: the last point's.
    pub fn limit(&self) -> f64 {
        self.p.last().copied().unwrap_or(0.0)
    }

    /// Whether the curve reaches 1 within its points (every record reaches
    /// the state) from 0, through two points at least: what the engines'
    /// curves must do.
    pub fn complete(&self) -> bool {
        self.x.len() >= 2 && self.p[0] == 0.0 && self.limit() == 1.0
    }

    /// Why the records' curve of `n` records is not [`Curve::complete`],
    /// in words naming `state` (levels in `unit`); `None` where it is. A
    /// curve that reaches 1 falls short by jumping at its first level,
    /// where several records reach the state at once.
    pub fn shortfall(&self, state: &str, unit: &str, n: usize) -> Option<String> {
        if self.complete() {
            return None;
        }
        Some(match self.points().next() {
            Some((first, p)) if self.limit() >= 1.0 => format!(
                "{} of {n} records reach `{state}` first at one level ({first:.4} {unit}), so the \
                 records' curve jumps there instead of rising from 0",
                (p * n.saturating_sub(1) as f64).round() as usize + 1
            ),
            _ => format!("some records never reach `{state}`, so the records' curve stops below 1"),
        })
    }

    /// The points (level, P), in order.
    pub fn points(&self) -> impl ExactSizeIterator<Item = (f64, f64)> + '_ {
        self.x.iter().copied().zip(self.p.iter().copied())
    }

    /// The levels.
    pub fn levels(&self) -> &[f64] {
        &self.x
    }

    /// The level at which P first reaches `q` (None where it never does).
    pub fn quantile(&self, q: f64) -> Option<f64> {
        let i = self.p.partition_point(|&p| p < q);
        if i == self.p.len() {
            return None;
        }
        if i == 0 {
            return Some(self.x[0]);
        }
        let (x0, x1, p0, p1) = (self.x[i - 1], self.x[i], self.p[i - 1], self.p[i]);
        Some(x0 + (x1 - x0) * ((q - p0) / (p1 - p0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::{fractile, FractileDef};

    /// By hand: of 4 capacities 0.3, 0.3, 0.3, 0.5 the curve is 2/3 at
    /// 0.3 (P = i/(n − 1) at the last of a tie) and 1 at 0.5: complete in
    /// its limit, but it jumps, three records at once; of 0.1, 0.2 and one
    /// that never comes it stops at 1/2. The export's refusal said "stops
    /// below 1" of the first.
    #[test]
    fn a_curve_says_why_it_is_short() {
        let jumps = Curve::of_capacities(&[0.3, 0.3, 0.3, 0.5]);
        assert_eq!(jumps.limit(), 1.0);
        assert_eq!(
            jumps.shortfall("slide", "g", 4).unwrap(),
            "3 of 4 records reach `slide` first at one level (0.3000 g), so the records' curve \
             jumps there instead of rising from 0"
        );
        let stops = Curve::of_capacities(&[0.1, 0.2, f64::INFINITY]);
        assert_eq!(stops.limit(), 0.5);
        assert!(stops
            .shortfall("s", "g", 3)
            .unwrap()
            .contains("stops below 1"));
        assert_eq!(
            Curve::of_capacities(&[0.1, 0.2, 0.4]).shortfall("s", "g", 3),
            None
        );
    }

    /// The curve's quantiles are the type-7 fractiles of the capacities
    /// (its definition, checked against the fractile function written
    /// independently in `stats`), and its probability at each capacity is
    /// the rank's (i − 1)/(n − 1).
    #[test]
    fn its_quantiles_are_the_records_fractiles() {
        let caps = [0.11, 0.17, 0.2, 0.26, 0.31, 0.45, 0.52, 0.9];
        let c = Curve::of_capacities(&caps);
        assert!(c.complete());
        for q in [0.0, 0.05, 0.16, 0.3, 0.5, 0.84, 0.99, 1.0] {
            let want = fractile(&caps, q, FractileDef::Type7).unwrap();
            let got = c.quantile(q).unwrap();
            assert!((got - want).abs() < 1e-15, "q = {q}: {got} against {want}");
        }
        for (i, &x) in caps.iter().enumerate() {
            assert_eq!(c.probability(x), i as f64 / 7.0);
        }
        // Halfway between two capacities, halfway between their ranks.
        assert!((c.probability(0.485) - 5.5 / 7.0).abs() < 1e-15);
        assert_eq!(c.probability(0.05), 0.0);
        assert_eq!(c.probability(3.0), 1.0);
    }

    #[test]
    fn records_that_never_reach_it_hold_the_curve_below_one() {
        let c = Curve::of_capacities(&[0.2, 0.3, 0.4, f64::INFINITY, f64::INFINITY]);
        // Three finite of five: the last finite at rank 3, P = 2/4.
        assert_eq!(c.limit(), 0.5);
        assert_eq!(c.probability(10.0), 0.5);
        assert!(!c.complete());
        assert_eq!(c.quantile(0.6), None);
        assert_eq!(Curve::of_capacities(&[]).probability(1.0), 0.0);
        // One record: a step to 1 at its capacity.
        let one = Curve::of_capacities(&[0.3]);
        assert_eq!((one.probability(0.29), one.probability(0.3)), (0.0, 1.0));
        assert!(!one.complete());
    }

    #[test]
    fn equal_capacities_are_one_point_at_their_highest_rank() {
        let c = Curve::of_capacities(&[0.1, 0.2, 0.2, 0.2 * (1.0 + 1e-12), 0.4]);
        let points: Vec<(f64, f64)> = c.points().collect();
        assert_eq!(points, vec![(0.1, 0.0), (0.2, 0.75), (0.4, 1.0)]);
        assert!(c.levels().windows(2).all(|w| w[0] < w[1]));
    }
}
