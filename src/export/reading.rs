//! How OpenQuake's `classical_damage` reads the hazard curves a job carries
//! (`openquake.risklib.scientific.classical_damage`, engine 3.26): the poes
//! are read in single precision, so a poe within 6e-8 of 1 reads as 1; a
//! poe of 1 is taken as 1 − 2⁻⁵³ (`annual_frequency_of_exceedence`), a rate
//! of exceedance `A = −ln(2⁻⁵³)/T = 36.74/T`; and an IML's rate of
//! occurrence is the difference of the midpoints of its neighbours' rates
//! of exceedance. `risk` instead drops the IMLs whose poe is exactly 1 and
//! reads the rest in double precision.
//!
//! With the first `f` IMLs read as poe = 1 and `a_f` the rate OpenQuake
//! reads at the next one, the midpoint sum gives IML `f − 1` the occurrence
//! `(A − a_f)/2` and IML `f` the occurrence `(A − a_{f+1})/2`, where the
//! curve that starts at IML `f` gives it `(a_f − a_{f+1})/2` and nothing
//! below: the job counts
//!
//! ```text
//! ΔΛ = (A − a_f)/2 · [P(IML_{f−1}) + P(IML_f)]
//! ```
//!
//! more per year than the curve from its first IML read below 1, where P
//! is the state's fragility as the job has it (0 at or below the no-damage
//! limit). `a_f` is at most 16.6/T (the rate of the largest
//! single-precision poe below 1), so `ΔΛ` is at least 10/T per year times
//! those two probabilities: nothing where the saturated IMLs lie below the
//! uplift level, much where a floor or an IM without a cut lets them count.

use crate::hazard::HazardCurve;

/// The IMLs OpenQuake reads as poe = 1 at a site, and what they add.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Saturated {
    /// How many of the first IMLs read as poe = 1.
    pub imls: usize,
    /// The last of them (in the IM's unit).
    pub up_to: f64,
    /// `ΔΛ`: the rate of the state the job counts more than the curve from
    /// its first IML read below 1 (1/yr).
    pub excess_rate: f64,
    /// `A`: the rate of exceedance the job gives a poe of 1 (1/yr).
    pub certain_rate: f64,
}

/// The rate OpenQuake gives a poe of 1 over `t` years: −ln(1 − (1 − 2⁻⁵³))/t.
pub fn certain_rate(investigation_time: f64) -> f64 {
    -(1.0 - 0.999_999_999_999_999_9_f64).ln() / investigation_time
}

/// The poe a rate over `t` years is written as, read in single precision.
fn read_poe(rate: f64, t: f64) -> f64 {
    if rate.is_infinite() {
        return 1.0;
    }
    f64::from(-(-rate * t).exp_m1() as f32)
}

/// The first IMLs of `curve` (over `investigation_time` years) that the job
/// reads as poe = 1 and the rate they add to a state of fragility
/// `probability` (P at an IML, cut as the job cuts it); `None` where none
/// does, or where every IML does (the job then counts nothing at all).
pub fn saturated(
    curve: &HazardCurve,
    investigation_time: f64,
    probability: impl Fn(f64) -> f64,
) -> Option<Saturated> {
    let t = investigation_time;
    let points: Vec<(f64, f64)> = curve
        .infinite
        .iter()
        .map(|&iml| (iml, f64::INFINITY))
        .chain(
            curve
                .iml
                .iter()
                .copied()
                .zip(curve.annual_rate.iter().copied()),
        )
        .collect();
    let f = points
        .iter()
        .take_while(|&&(_, rate)| read_poe(rate, t) == 1.0)
        .count();
    if f == 0 || f == points.len() {
        return None;
    }
    let a = certain_rate(t);
    let a_f = -(-read_poe(points[f].1, t)).ln_1p() / t;
    let (below, first) = (points[f - 1].0, points[f].0);
    Some(Saturated {
        imls: f,
        up_to: below,
        excess_rate: (a - a_f) / 2.0 * (probability(below) + probability(first)),
        certain_rate: a,
    })
}

/// The rate of a state OpenQuake's `classical_damage` counts from a
/// curve, read as `risk` reads it (in double precision, the IMLs of poe 1
/// left out: [`saturated`] tells those apart): at each IML the fragility
/// `probability` times the IML's rate of occurrence, the difference of the
/// midpoints of its neighbours' rates of exceedance, the first IML's and
/// the last's padded by themselves (a midpoint rule, with half-bins at both
/// ends and nothing beyond the last IML). A curve that ends in a rate of 0
/// carries that IML too, as the job's does. Against the integral over the
/// log-log curve (`risk --beyond stop`) its error is of the order of the
/// squared spacing of the IMLs: tenths of a per cent at 100 IMLs a decade
/// and a half, several per cent at 14.
pub fn midpoint_rate(curve: &HazardCurve, probability: impl Fn(f64) -> f64) -> f64 {
    let points: Vec<(f64, f64)> = curve
        .iml
        .iter()
        .copied()
        .zip(curve.annual_rate.iter().copied())
        .chain(curve.ends_at.map(|x| (x, 0.0)))
        .collect();
    let n = points.len();
    let mid = |i: usize| match i {
        0 => points[0].1,
        i if i == n => points[n - 1].1,
        i => 0.5 * (points[i - 1].1 + points[i].1),
    };
    (0..n)
        .map(|i| (mid(i) - mid(i + 1)) * probability(points[i].0))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::im::Im;

    fn curve(infinite: &[f64], points: &[(f64, f64)]) -> HazardCurve {
        HazardCurve {
            im: Im::Pga,
            lon: None,
            lat: None,
            iml: points.iter().map(|p| p.0).collect(),
            annual_rate: points.iter().map(|p| p.1).collect(),
            ends_at: None,
            infinite: infinite.to_vec(),
            kind: None,
        }
    }

    /// Worked by hand: rates 0.1, 0.04, 0.01 /yr at 0.1, 0.2, 0.4 g, then 0
    /// at 0.8 g; the padded midpoints are 0.1, 0.07, 0.025, 0.005, 0, so
    /// the occurrences are 0.03, 0.045, 0.02, 0.005, and with P = 0.1,
    /// 0.2, 0.5, 0.9 the rate is 0.003 + 0.009 + 0.01 + 0.0045 = 0.0265.
    /// Without the 0 the last IML keeps half its bin: 0.025 − 0.01 = 0.015
    /// at P = 0.5, so 0.003 + 0.009 + 0.0075 = 0.0195.
    #[test]
    fn the_jobs_midpoint_sum_by_hand() {
        let p = |x: f64| match x {
            0.1 => 0.1,
            0.2 => 0.2,
            0.4 => 0.5,
            _ => 0.9,
        };
        let mut c = curve(&[0.05], &[(0.1, 0.1), (0.2, 0.04), (0.4, 0.01)]);
        assert!((midpoint_rate(&c, p) - 0.0195).abs() < 1e-15);
        c.ends_at = Some(0.8);
        assert!((midpoint_rate(&c, p) - 0.0265).abs() < 1e-15);
    }

    /// Worked by hand over T = 50 years: poe = 1 at 0.05 g; at 0.1 g the
    /// rate 0.5/yr is poe 1 − e⁻²⁵ = 1 − 1.4e-11, which single precision
    /// reads as 1; at 0.2 g the rate 0.2/yr is poe 1 − e⁻¹⁰ = 1 − 4.54e-5,
    /// read as 0.99995458 (the float32 nearest), the rate
    /// −ln(4.5418e-5)/50 = 0.200 /yr. So f = 2, `A` = 36.7368/50 =
    /// 0.734736 /yr, and with P = 0.1, 0.3 at 0.1 g and 0.2 g,
    /// ΔΛ = (0.734736 − a_f)/2 · 0.4.
    #[test]
    fn the_job_counts_half_the_certain_rate_at_the_edge_of_saturation() {
        let c = curve(&[0.05], &[(0.1, 0.5), (0.2, 0.2), (0.4, 0.01)]);
        let p = |x: f64| {
            if x == 0.1 {
                0.1
            } else if x == 0.2 {
                0.3
            } else {
                0.9
            }
        };
        let s = saturated(&c, 50.0, p).unwrap();
        assert_eq!(s.imls, 2);
        assert_eq!(s.up_to, 0.1);
        assert!((s.certain_rate - 0.734_736).abs() < 1e-6, "{s:?}");
        // The float32 nearest to 1 − 4.54e-5 (spacing 6e-8 below 1) keeps
        // its rate to ln's derivative: |Δa_f| ≤ 6e-8 / 4.5e-5 / 50 = 3e-5.
        let a_f = 0.2;
        let expected = (0.734_736 - a_f) / 2.0 * 0.4;
        assert!(
            (s.excess_rate - expected).abs() < 1e-5,
            "{s:?} against {expected}"
        );
    }

    #[test]
    fn a_curve_read_below_one_from_its_first_iml_adds_nothing() {
        // poe 1 − e⁻⁵ = 0.9933 at its first IML: no saturation.
        let c = curve(&[], &[(0.1, 0.1), (0.2, 0.02)]);
        assert_eq!(saturated(&c, 50.0, |_| 1.0), None);
        // Every IML saturated: the job counts nothing, nothing to add.
        let c = curve(&[0.05], &[(0.1, 5.0)]);
        assert_eq!(saturated(&c, 50.0, |_| 1.0), None);
    }
}
