//! The annual rate of overturning at a site (pure): a block's fragility
//! P(OT | a) convolved with the site's hazard curve λ(a), the annual rate
//! of exceedance of PGA a,
//!
//! ```text
//! λ_OT = ∫ P(OT | a) |dλ(a)|
//! ```
//!
//! (Cornell et al. 2002, "Probabilistic basis for 2000 SAC FEMA steel moment
//! frame guidelines", J. Struct. Eng. 128(4), Eq. 5.) Between its points
//! the hazard is interpolated log-log, so on each segment it is a power law
//! `λ(a) = λ₀ (a/a₀)^(−k)` and the integral has a closed form for both
//! fragilities this tool makes:
//!
//! - **lognormal**, `P = Φ(ln(a/m)/β)`: integrating by parts and completing
//!   the square, with `u = ln a`, `μ = ln m`,
//!
//!   ```text
//!   ∫ P |dλ| = P(a₀)λ(a₀) − P(a₁)λ(a₁)
//!            + λ₀ e^{k(u₀−μ) + k²β²/2} [Φ((u₁−μ+kβ²)/β) − Φ((u₀−μ+kβ²)/β)];
//!   ```
//!
//!   over a whole power-law curve this is Cornell's `k₀ m^(−k) e^{k²β²/2}`;
//! - **the records' curve** ([`Curve`]: linear between the records'
//!   capacities), on each piece `[u, v]` between its points, where
//!   `P(a) = P(u) + s (a − u)` and `L = ln(v/u)`:
//!
//!   ```text
//!   ∫ P |dλ| = P(u) [λ(u) − λ(v)] + s k u λ(u) L [φ((1−k)L) − φ(−kL)],
//!   φ(x) = (eˣ − 1)/x,
//!   ```
//!
//!   (with `a = u eᵗ`, `∫ (a − u) k λ(a)/a da = k u λ(u) ∫₀ᴸ (eᵗ − 1) e^{−kt} dt`);
//!   a jump at the first point (a curve of one record) is the `P(u)` term.
//!
//! Below the curve's first IML the rate is unknown (files give poe = 1
//! there): the integral starts at the first IML, and the fragility there,
//! P(OT | a_first), says how much overturning probability lies below it.
//! Beyond the last IML the curve is either extrapolated with its last
//! log-log slope or stopped ([`Beyond`]), and the share of the rate that
//! comes from beyond it is reported. A curve whose file gives a rate of 0 at
//! some IML ends there, under either rule: the events still exceeding the
//! last positive IML are spread evenly in the IM up to that 0
//! ([`closing_rate`]), nothing beyond it.

use crate::damage::Curve;
use crate::hazard::HazardCurve;
use crate::stats::normal_cdf;

/// P(overturn | PGA) of a block.
#[derive(Debug, Clone, PartialEq)]
pub enum Fragility {
    /// `Φ(ln(a / median) / beta)`.
    Lognormal { median: f64, beta: f64 },
    /// The records' own curve, linear between their capacities.
    Curve(Curve),
}

impl Fragility {
    /// P(state | IM) as the IM grows without bound: 1 for a lognormal, the
    /// last point's for the records' curve (below 1 where some records
    /// never reach the state).
    pub fn limit(&self) -> f64 {
        match self {
            Fragility::Lognormal { .. } => 1.0,
            Fragility::Curve(c) => c.limit(),
        }
    }

    /// P(overturn | PGA = a).
    pub fn probability(&self, a: f64) -> f64 {
        match self {
            Fragility::Lognormal { median, beta } => crate::damage::Lognormal {
                median: *median,
                beta: *beta,
            }
            .cdf(a),
            Fragility::Curve(c) => c.probability(a),
        }
    }
}

/// What to assume beyond the hazard curve's last IML.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Beyond {
    /// Continue with the last segment's log-log slope.
    Extrapolate,
    /// No exceedance beyond the last IML is counted (a file that ends in
    /// probabilities of 0 ends at its first 0, under either rule).
    Stop,
}

impl crate::label::Label for Beyond {
    const ALL: &'static [Self] = &[Beyond::Extrapolate, Beyond::Stop];
    const WHAT: &'static str = "rule beyond the hazard curve";
    fn label(self) -> &'static str {
        match self {
            Beyond::Extrapolate => "extrapolate",
            Beyond::Stop => "stop",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Beyond::Extrapolate => "continue the curve's last log-log slope",
            Beyond::Stop => "count no exceedance beyond the last IML",
        }
    }
}

crate::deserialize_by_label!(Beyond);

/// The contribution of one range of PGA to the rate of overturning.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Bin {
    pub iml_from: f64,
    /// `None`: no upper end (beyond the last IML, extrapolated).
    pub iml_to: Option<f64>,
    pub annual_rate: f64,
}

/// The risk at one site.
#[derive(Debug, Clone, PartialEq)]
pub struct SiteRisk {
    /// λ_OT (1/year).
    pub annual_rate: f64,
    pub first_iml: f64,
    pub last_iml: f64,
    /// P(OT | first IML): overturning probability below where the curve starts.
    pub fragility_at_first_iml: f64,
    /// Share of λ_OT from beyond the last IML (0 with [`Beyond::Stop`]).
    pub share_beyond_last_iml: f64,
    /// λ_OT by range of PGA (deaggregation), in increasing PGA; the last bin
    /// is beyond the last IML.
    pub bins: Vec<Bin>,
}

/// One power-law piece of the hazard: `λ(a) = rate0 (a / a0)^(−k)` on
/// `[a0, a1]` (`a1` may be infinite).
#[derive(Debug, Clone, Copy)]
struct Segment {
    a0: f64,
    a1: f64,
    rate0: f64,
    k: f64,
}

impl Segment {
    /// The part of the segment at or above `cut` (`None` when none is).
    fn above(self, cut: f64) -> Option<Segment> {
        if self.a1 <= cut {
            return None;
        }
        if self.a0 >= cut {
            return Some(self);
        }
        Some(Segment {
            a0: cut,
            rate0: self.rate(cut),
            ..self
        })
    }

    fn rate(&self, a: f64) -> f64 {
        if a.is_infinite() {
            return if self.k > 0.0 { 0.0 } else { self.rate0 };
        }
        self.rate0 * (a / self.a0).powf(-self.k)
    }

    /// ∫_{a0}^{a1} P |dλ| in closed form: exactly 0 where the hazard is
    /// flat (no event exceeds a0 without exceeding a1), and never below 0
    /// (the integrand P·k·λ is not; the closed form's two terms cancel to
    /// rounding on a nearly flat piece, which gave −1e-18 and "−14 %" bins).
    fn integral(&self, f: &Fragility) -> f64 {
        if self.k == 0.0 {
            return 0.0;
        }
        let value = self.integral_of(f);
        if value > 0.0 {
            value
        } else {
            0.0
        }
    }

    fn integral_of(&self, f: &Fragility) -> f64 {
        match f {
            Fragility::Lognormal { median, beta } => {
                let closed = self.lognormal(median.ln(), *beta, f);
                if closed.is_finite() {
                    closed
                } else {
                    // The closed form's exponential overflowed (an extremely
                    // steep hazard): integrate numerically instead.
                    self.quadrature(f)
                }
            }
            Fragility::Curve(c) => self.curve(c),
        }
    }

    /// ∫ P |dλ| for the records' curve: piece by piece between its points
    /// (module docs).
    fn curve(&self, c: &Curve) -> f64 {
        let inside = c
            .levels()
            .iter()
            .copied()
            .filter(|&x| x > self.a0 && x < self.a1);
        let mut ends: Vec<f64> = std::iter::once(self.a0).chain(inside).collect();
        ends.push(self.a1);
        ends.windows(2)
            .map(|w| {
                let (u, v) = (w[0], w[1]);
                let pu = c.probability(u);
                let (lu, lv) = (self.rate(u), self.rate(v));
                let mut sum = pu * (lu - lv);
                if v.is_finite() {
                    let s = (c.probability_below(v) - pu) / (v - u);
                    if s > 0.0 {
                        let l = (v / u).ln();
                        let phi = |x: f64| if x == 0.0 { 1.0 } else { x.exp_m1() / x };
                        let k = self.k;
                        sum += s * k * u * lu * l * (phi((1.0 - k) * l) - phi(-k * l));
                    }
                }
                sum
            })
            .sum()
    }

    fn lognormal(&self, mu: f64, beta: f64, f: &Fragility) -> f64 {
        let (u0, u1) = (self.a0.ln(), self.a1.ln());
        let boundary = f.probability(self.a0) * self.rate0
            - if self.a1.is_infinite() {
                if self.k > 0.0 {
                    0.0
                } else {
                    self.rate0
                }
            } else {
                f.probability(self.a1) * self.rate(self.a1)
            };
        let shift = self.k * beta * beta;
        let (x0, x1) = ((u0 - mu + shift) / beta, (u1 - mu + shift) / beta);
        // Φ(x1) − Φ(x0), from the tail that keeps its digits.
        let d = if x0 > 0.0 {
            normal_cdf(-x0) - normal_cdf(-x1)
        } else {
            normal_cdf(x1) - normal_cdf(x0)
        };
        let body = if d > 0.0 {
            (self.rate0.ln() + self.k * (u0 - mu) + 0.5 * shift * self.k + d.ln()).exp()
        } else {
            0.0
        };
        boundary + body
    }

    /// ∫ P k λ du over the segment by Gauss–Legendre on pieces of ln a
    /// (an infinite end is cut where λ has fallen by 10⁻¹⁶).
    fn quadrature(&self, f: &Fragility) -> f64 {
        const NODES: [(f64, f64); 5] = [
            (0.0, 0.568_888_888_888_888_9),
            (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (0.906_179_845_938_664, 0.236_926_885_056_189_1),
            (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
        ];
        if self.k <= 0.0 {
            return 0.0;
        }
        let u0 = self.a0.ln();
        let u1 = if self.a1.is_infinite() {
            u0 + 16.0 * std::f64::consts::LN_10 / self.k
        } else {
            self.a1.ln()
        };
        let pieces = 400;
        let h = (u1 - u0) / pieces as f64;
        let mut sum = 0.0;
        for j in 0..pieces {
            let mid = u0 + (j as f64 + 0.5) * h;
            for (x, w) in NODES {
                let u = mid + 0.5 * h * x;
                let a = u.exp();
                sum += w * 0.5 * h * f.probability(a) * self.k * self.rate(a);
            }
        }
        sum
    }
}

/// How a curve ends past its last IML of a positive rate.
#[derive(Debug, Clone, Copy)]
enum End {
    /// The file's own 0 at `.1` after the rate `.0.rate0` at `.0.a0`: its
    /// events between are inside the file, counted under either rule
    /// ([`closing_rate`]).
    Closed(Segment, f64),
    /// Extrapolated on the last slope (`Beyond::Extrapolate`).
    Beyond(Segment),
    /// Nothing counted past the last IML (`Beyond::Stop`, or one point).
    Open,
}

/// The power-law pieces of a curve, and how it ends ([`End`]).
fn segments(curve: &HazardCurve, beyond: Beyond) -> (Vec<Segment>, End) {
    let (a, r) = (&curve.iml, &curve.annual_rate);
    let slope = |i: usize| (r[i] / r[i + 1]).ln() / (a[i + 1] / a[i]).ln();
    let inner: Vec<Segment> = (0..a.len().saturating_sub(1))
        .map(|i| Segment {
            a0: a[i],
            a1: a[i + 1],
            rate0: r[i],
            k: slope(i),
        })
        .collect();
    let last = a.len() - 1;
    let on = |s: &Segment, a1: f64| Segment {
        a0: a[last],
        a1,
        rate0: r[last],
        k: s.k,
    };
    let end = match (curve.ends_at, beyond, inner.last()) {
        // One point has no slope to go on with.
        (_, _, None) => End::Open,
        (Some(e), _, Some(s)) => End::Closed(on(s, e), e),
        (None, Beyond::Stop, _) => End::Open,
        (None, Beyond::Extrapolate, Some(s)) => End::Beyond(on(s, f64::INFINITY)),
    };
    (inner, end)
}

/// The rate of a file's closing piece: `rate` of events exceed `a0` and
/// none exceed `a1`, where the file gives 0. A power law cannot reach 0;
/// the events are taken spread evenly in the IM between (λ linear in a,
/// the rate falling straight to the file's 0), so the piece counts `rate`
/// times the fragility's mean over `[max(a0, cut), a1]`: what OpenQuake's
/// classical calculators count for that bin, its fragility at the bin's
/// middle, to second order. Exact for both fragilities: for the lognormal
/// `∫ Φ(z) da = a Φ(z) − m e^{β²/2} Φ(z − β)`, `z = ln(a/m)/β`; the
/// records' curve is linear between its points.
fn closing_rate(a0: f64, a1: f64, rate: f64, f: &Fragility, cut: f64) -> f64 {
    let from = a0.max(cut);
    if from >= a1 {
        return 0.0;
    }
    let integral = match f {
        Fragility::Lognormal { median, beta } => {
            let tail = median * (0.5 * beta * beta).exp();
            let big_f = |a: f64| {
                let z = (a / median).ln() / beta;
                a * normal_cdf(z) - tail * normal_cdf(z - beta)
            };
            big_f(a1) - big_f(from)
        }
        Fragility::Curve(c) => {
            let inside = c.levels().iter().copied().filter(|&x| x > from && x < a1);
            let mut ends: Vec<f64> = std::iter::once(from).chain(inside).collect();
            ends.push(a1);
            ends.windows(2)
                .map(|w| 0.5 * (w[1] - w[0]) * (c.probability(w[0]) + c.probability_below(w[1])))
                .sum()
        }
    };
    rate * (integral / (a1 - a0)).max(0.0)
}

/// λ_OT at one site, with its deaggregation by PGA.
pub fn assess(curve: &HazardCurve, fragility: &Fragility, beyond: Beyond) -> SiteRisk {
    assess_above(curve, fragility, beyond, 0.0)
}

/// [`assess`] for a fragility that is 0 below the IM level `cut` (a block
/// on the ground cannot move below its uplift PGA, g·tan α: its fragility
/// is cut there, as the OpenQuake export's `noDamageLimit` cuts it; 0 for
/// none; docs/MODEL.md §13). A curve whose last segment is flat under
/// [`Beyond::Extrapolate`] says that events at that rate exceed every
/// level: its rate is carried beyond the curve at the fragility's limit
/// (P → 1 for a lognormal), the limit of an extrapolation whose slope
/// tends to 0, so that a flat curve and a nearly flat one agree.
pub fn assess_above(
    curve: &HazardCurve,
    fragility: &Fragility,
    beyond: Beyond,
    cut: f64,
) -> SiteRisk {
    let (inner, end) = segments(curve, beyond);
    let in_segment = |s: &Segment| s.above(cut).map_or(0.0, |s| s.integral(fragility));
    let mut bins: Vec<Bin> = inner
        .iter()
        .map(|s| Bin {
            iml_from: s.a0,
            iml_to: Some(s.a1),
            annual_rate: in_segment(s),
        })
        .collect();
    let first = curve.iml[0];
    let mut last = *curve.iml.last().expect("a curve has a point");
    if let End::Closed(s, e) = end {
        bins.push(Bin {
            iml_from: last,
            iml_to: Some(e),
            annual_rate: closing_rate(s.a0, e, s.rate0, fragility, cut),
        });
        last = e;
    }
    let beyond_rate = match end {
        End::Open | End::Closed(..) => 0.0,
        // A flat end: its events exceed every level.
        End::Beyond(s) if s.k == 0.0 => s.rate0 * fragility.limit(),
        End::Beyond(s) => in_segment(&s),
    };
    bins.push(Bin {
        iml_from: last,
        iml_to: match end {
            End::Beyond(_) => None,
            End::Open | End::Closed(..) => Some(last),
        },
        annual_rate: beyond_rate,
    });
    let total: f64 = bins.iter().map(|b| b.annual_rate).sum();
    SiteRisk {
        annual_rate: total,
        first_iml: first,
        last_iml: last,
        fragility_at_first_iml: if first < cut {
            0.0
        } else {
            fragility.probability(first)
        },
        share_beyond_last_iml: if total > 0.0 {
            beyond_rate / total
        } else {
            0.0
        },
        bins,
    }
}

/// The risk at one site of a weighted mixture of fragilities Σ wᵢ Pᵢ (a
/// logic tree's mean), from each part's risk there: the integral is linear
/// in the fragility and the bins are the curve's, so the rate, each bin's
/// and P at the first IML are the weighted means, and the share beyond the
/// last IML is that of the mean rate.
pub fn mixed(parts: &[(f64, SiteRisk)]) -> SiteRisk {
    let first = &parts[0].1;
    let mean = |f: &dyn Fn(&SiteRisk) -> f64| parts.iter().map(|(w, r)| w * f(r)).sum::<f64>();
    let annual_rate = mean(&|r| r.annual_rate);
    let beyond = mean(&|r| r.annual_rate * r.share_beyond_last_iml);
    SiteRisk {
        annual_rate,
        first_iml: first.first_iml,
        last_iml: first.last_iml,
        fragility_at_first_iml: mean(&|r| r.fragility_at_first_iml),
        share_beyond_last_iml: if annual_rate > 0.0 {
            beyond / annual_rate
        } else {
            0.0
        },
        bins: first
            .bins
            .iter()
            .enumerate()
            .map(|(k, b)| Bin {
                annual_rate: mean(&|r| r.bins[k].annual_rate),
                ..*b
            })
            .collect(),
    }
}

/// The probability of at least one overturning in `years` (Poisson).
pub fn probability_in(annual_rate: f64, years: f64) -> f64 {
    -(-annual_rate * years).exp_m1()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A power-law hazard λ(a) = k0 a^(−k) sampled at `n` IMLs from a_lo to a_hi.
    fn power_law(k0: f64, k: f64, a_lo: f64, a_hi: f64, n: usize) -> HazardCurve {
        let iml: Vec<f64> = (0..n)
            .map(|i| a_lo * (a_hi / a_lo).powf(i as f64 / (n - 1) as f64))
            .collect();
        HazardCurve {
            im: crate::im::Im::Pga,
            lon: None,
            lat: None,
            annual_rate: iml.iter().map(|a| k0 * a.powf(-k)).collect(),
            iml,
            ends_at: None,
            infinite: Vec::new(),
            kind: None,
        }
    }

    #[test]
    fn cornell_closed_form_for_a_power_law_hazard_and_a_lognormal_fragility() {
        // λ_OT = k0 m^(−k) exp(k²β²/2) (Cornell et al. 2002). The curve starts
        // 9β below the median, so the rate left out below it is a fraction
        // Φ(−9 + kβ) ≈ 1e-14 of the whole; the tail is extrapolated exactly.
        for (k0, k, m, beta) in [
            (1e-4, 2.5, 0.4, 0.5f64),
            (3e-3, 1.2, 0.15, 0.8),
            (1e-5, 4.0, 1.2, 0.3),
        ] {
            let curve = power_law(k0, k, m * (-9.0 * beta).exp(), m * (3.0 * beta).exp(), 25);
            let f = Fragility::Lognormal { median: m, beta };
            let r = assess(&curve, &f, Beyond::Extrapolate);
            let exact = k0 * m.powf(-k) * (k * k * beta * beta / 2.0).exp();
            assert!(
                (r.annual_rate / exact - 1.0).abs() < 1e-10,
                "k = {k}: {} vs {exact}",
                r.annual_rate
            );
            let sum: f64 = r.bins.iter().map(|b| b.annual_rate).sum();
            assert!((sum / r.annual_rate - 1.0).abs() < 1e-12);
            // Stopping at the last IML leaves out exactly the share beyond it.
            let stopped = assess(&curve, &f, Beyond::Stop);
            assert!(stopped.annual_rate < r.annual_rate);
            let share = 1.0 - stopped.annual_rate / r.annual_rate;
            assert!((share - r.share_beyond_last_iml).abs() < 1e-12);
        }
    }

    /// A flat hazard curve has no events: the rate and every bin are 0
    /// exactly (not 1.5e-18 with bins of −14 % and 113 %), and not −0.
    #[test]
    fn a_flat_hazard_carries_its_rate_beyond_the_curve() {
        let curve = HazardCurve {
            im: crate::im::Im::Pga,
            lon: None,
            lat: None,
            iml: vec![0.1, 0.2, 0.3],
            annual_rate: vec![0.01; 3],
            ends_at: None,
            infinite: Vec::new(),
            kind: None,
        };
        for (f, limit) in [
            (
                Fragility::Lognormal {
                    median: 0.25,
                    beta: 0.4,
                },
                1.0,
            ),
            (
                // Two of four records reach it: the curve stops at 1/3.
                Fragility::Curve(Curve::of_capacities(&[
                    0.15,
                    0.25,
                    f64::INFINITY,
                    f64::INFINITY,
                ])),
                1.0 / 3.0,
            ),
        ] {
            // No event inside the curve: its rate never drops.
            let stop = assess(&curve, &f, Beyond::Stop);
            assert_eq!(stop.annual_rate.to_bits(), 0, "{f:?}");
            assert!(stop.bins.iter().all(|b| b.annual_rate.to_bits() == 0));
            // Beyond it, 0.01/yr exceed every level: P there is the limit.
            let r = assess(&curve, &f, Beyond::Extrapolate);
            assert_eq!(r.annual_rate, 0.01 * limit, "{f:?}");
            assert_eq!(r.share_beyond_last_iml, 1.0);
            // A nearly flat tail tends to it (the slope 1e-9 spreads its
            // events over levels ~e^(1e9) times the last: P there is 1).
            let nearly = HazardCurve {
                annual_rate: vec![0.01, 0.01, 0.01 * (1.0 - 1e-9 * 1.5f64.ln())],
                ..curve.clone()
            };
            let n = assess(&nearly, &f, Beyond::Extrapolate);
            assert!((n.annual_rate / r.annual_rate - 1.0).abs() < 1e-6, "{n:?}");
        }
        // The fault's curve: 1e-3/yr exceed 0.6 g, where P(OT) ≥ 0.63.
        let fault = HazardCurve {
            iml: vec![0.1, 0.3, 0.6],
            annual_rate: vec![0.01, 0.001, 0.001],
            ..curve.clone()
        };
        let f = Fragility::Lognormal {
            median: 0.5,
            beta: 0.4,
        };
        let r = assess(&fault, &f, Beyond::Extrapolate);
        assert!(r.annual_rate >= 1e-3 * f.probability(0.6), "{r:?}");
        // A nearly flat piece: never negative, and bins sum to the rate.
        let curve = HazardCurve {
            annual_rate: vec![0.01, 0.01 * (1.0 - 1e-15), 0.001],
            ..curve
        };
        let f = Fragility::Lognormal {
            median: 0.25,
            beta: 0.4,
        };
        let r = assess(&curve, &f, Beyond::Stop);
        assert!(r.bins.iter().all(|b| b.annual_rate >= 0.0), "{r:?}");
    }

    #[test]
    fn a_step_fragility_gives_the_hazard_at_its_step() {
        // P = 1 above m: λ_OT = λ(m), log-log interpolated between IMLs.
        let curve = power_law(2e-4, 3.0, 0.01, 2.0, 9);
        for m in [0.013, 0.05, 0.3, 1.7] {
            let f = Fragility::Curve(Curve::of_capacities(&[m]));
            let r = assess(&curve, &f, Beyond::Extrapolate);
            let exact = 2e-4 * f64::powf(m, -3.0);
            assert!((r.annual_rate / exact - 1.0).abs() < 1e-12, "m = {m}");
        }
    }

    /// The records' curve against the antiderivative on a power law
    /// λ = k₀a^(−k): a ramp from 0 at x₁ to 1 at x₂ gives
    /// `k k₀/(x₂−x₁) [a^(1−k)/(1−k) + x₁a^(−k)/k]` over [x₁, x₂] (for
    /// k = 1, `k₀/(x₂−x₁) [ln a + x₁/a]`), plus λ(x₂); for k = 1, 2.5, 3
    /// and 1 ± 1e-7 (where φ's series must hold), and the ramp cut by the
    /// curve's first IML or the segment's ends anywhere.
    #[test]
    fn the_records_curve_integrates_to_its_antiderivative() {
        for k in [1.0, 1.0 + 1e-7, 1.0 - 1e-7, 2.5, 3.0] {
            let curve = power_law(2e-4, k, 0.01, 2.0, 7);
            let rate = |a: f64| 2e-4 * a.powf(-k);
            let anti = |x1: f64, x2: f64, a: f64| {
                if k == 1.0 {
                    2e-4 / (x2 - x1) * (a.ln() + x1 / a)
                } else {
                    k * 2e-4 / (x2 - x1) * (a.powf(1.0 - k) / (1.0 - k) + x1 * a.powf(-k) / k)
                }
            };
            for (x1, x2) in [(0.05, 0.3), (0.013, 0.021), (0.2, 1.7), (0.005, 0.04)] {
                let f = Fragility::Curve(Curve::of_capacities(&[x1, x2]));
                let r = assess(&curve, &f, Beyond::Extrapolate);
                let lo = x1.max(0.01);
                let exact = anti(x1, x2, x2) - anti(x1, x2, lo) + rate(x2);
                let tol = if (k - 1.0f64).abs() < 1e-6 && k != 1.0 {
                    1e-6
                } else {
                    1e-11
                };
                assert!(
                    (r.annual_rate / exact - 1.0).abs() < tol,
                    "k = {k}, ramp {x1}..{x2}: {} against {exact}",
                    r.annual_rate
                );
            }
        }
    }

    /// On a bent hazard curve, a curve of many records against
    /// Gauss–Legendre quadrature on pieces (accurate to ~1e-7 across the
    /// curve's kinks, which fall inside its pieces).
    #[test]
    fn the_records_curve_agrees_with_quadrature_on_a_bent_hazard() {
        let curve = HazardCurve {
            im: crate::im::Im::Pga,
            lon: None,
            lat: None,
            iml: vec![0.02, 0.05, 0.1, 0.2, 0.4, 0.8],
            annual_rate: vec![0.2, 0.05, 0.012, 0.002, 2e-4, 1e-5],
            ends_at: Some(1.5),
            infinite: Vec::new(),
            kind: None,
        };
        let caps = [
            0.03, 0.07, 0.071, 0.12, 0.19, 0.33, 0.41, 0.6, 0.95, 1.2, 2.4,
        ];
        let f = Fragility::Curve(Curve::of_capacities(&caps));
        let (inner, end) = segments(&curve, Beyond::Extrapolate);
        let End::Closed(closing, _) = end else {
            panic!("{end:?}")
        };
        for s in inner.iter().chain([&closing]) {
            let (c, q) = (s.integral(&f), s.quadrature(&f));
            assert!((c - q).abs() <= 1e-6 * c.max(1e-300), "{s:?}: {c} vs {q}");
        }
    }

    /// A file that ends in probabilities of 0 (as OpenQuake writes above
    /// what the hazard can reach) states where its events end: from its
    /// last positive rate to its first 0 they are inside the file, counted
    /// under either rule, and nothing is beyond it. The piece adds that
    /// rate times the fragility's mean over it (Simpson's rule on 10,000
    /// steps here) to the curve cut at its last IML, for the lognormal and
    /// the records' curve alike, and nothing below the cut. It was called
    /// 68 % "beyond the last IML, extrapolated", and `--beyond stop`
    /// dropped it.
    #[test]
    fn a_file_that_ends_in_zeros_ends_there() {
        let open = HazardCurve {
            im: crate::im::Im::Pga,
            lon: None,
            lat: None,
            iml: vec![0.05, 0.1, 0.3019, 0.3557],
            annual_rate: vec![1e-2, 2e-3, 1e-5, 1e-5],
            ends_at: None,
            infinite: Vec::new(),
            kind: None,
        };
        let closed = HazardCurve {
            ends_at: Some(0.4191),
            ..open.clone()
        };
        let mean_over = |f: &Fragility, lo: f64, hi: f64| {
            let n = 10_000;
            let h = (hi - lo) / n as f64;
            let sum: f64 = (0..=n)
                .map(|i| {
                    let w = if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    w * f.probability(lo + i as f64 * h)
                })
                .sum();
            sum * h / 3.0 / (hi - lo)
        };
        let lognormal = Fragility::Lognormal {
            median: 0.4,
            beta: 0.3,
        };
        let records = Fragility::Curve(Curve::of_capacities(&[0.2, 0.33, 0.37, 0.41, 0.5]));
        for f in [lognormal, records] {
            let open_rate = assess(&open, &f, Beyond::Stop).annual_rate;
            let by_hand = open_rate + 1e-5 * mean_over(&f, 0.3557, 0.4191);
            for beyond in [Beyond::Stop, Beyond::Extrapolate] {
                let r = assess(&closed, &f, beyond);
                assert!(
                    (r.annual_rate / by_hand - 1.0).abs() < 1e-9,
                    "{f:?} {beyond:?}: {} against {by_hand}",
                    r.annual_rate
                );
                assert_eq!(r.share_beyond_last_iml, 0.0);
                assert_eq!(r.last_iml, 0.4191);
                let bins: f64 = r.bins.iter().map(|b| b.annual_rate).sum();
                assert!((bins / r.annual_rate - 1.0).abs() < 1e-14);
            }
            // Cut inside the piece: the mean over the part above the cut,
            // times the share of the piece it is.
            let cut = 0.39;
            let r = assess_above(&closed, &f, Beyond::Stop, cut);
            let inner = assess_above(&open, &f, Beyond::Stop, cut).annual_rate;
            let piece = 1e-5 * mean_over(&f, cut, 0.4191) * (0.4191 - cut) / (0.4191 - 0.3557);
            assert!(
                ((r.annual_rate - inner) / piece - 1.0).abs() < 1e-9,
                "{f:?}: {} against {piece}",
                r.annual_rate - inner
            );
        }
    }

    #[test]
    fn closed_form_agrees_with_quadrature_on_a_bent_curve() {
        // A curve whose slope changes at every point, and a file end at rate 0.
        let curve = HazardCurve {
            im: crate::im::Im::Pga,
            lon: None,
            lat: None,
            iml: vec![0.02, 0.05, 0.1, 0.2, 0.4, 0.8],
            annual_rate: vec![0.2, 0.05, 0.012, 0.002, 2e-4, 1e-5],
            ends_at: Some(1.5),
            infinite: Vec::new(),
            kind: None,
        };
        let f = Fragility::Lognormal {
            median: 0.25,
            beta: 0.45,
        };
        let (inner, end) = segments(&curve, Beyond::Extrapolate);
        let End::Closed(closing, _) = end else {
            panic!("{end:?}")
        };
        for s in inner.iter().chain([&closing]) {
            let (c, q) = (s.integral(&f), s.quadrature(&f));
            assert!((c - q).abs() <= 1e-9 * c.max(1e-300), "{s:?}: {c} vs {q}");
        }
        let r = assess(&curve, &f, Beyond::Extrapolate);
        assert!(
            (r.fragility_at_first_iml - normal_cdf((0.02f64 / 0.25).ln() / 0.45)).abs() < 1e-15
        );
        // Probability in 50 years under Poisson arrivals.
        assert!((probability_in(0.01, 50.0) - (1.0 - (-0.5f64).exp())).abs() < 1e-15);
    }
}
