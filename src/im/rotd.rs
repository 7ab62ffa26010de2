//! Orientation-independent measures of a record pair (pure; docs/MODEL.md
//! §18): RotD50 and RotD100 of PGA, PGV and SA(T) (Boore, Watson-Lamprey &
//! Abrahamson 2006; Boore 2010, BSSA 100(4)).
//!
//! For each rotation angle θ = 0°, 1°, …, 179° the pair's component at θ
//! ([`crate::pair::Pair::rotated`]) has a peak; RotD100 is the largest of
//! the 180 peaks, RotD50 their median (the mean of the 90th and 91st
//! smallest). Each peak is the one-component measure of the rotated
//! component, computed as the record's own is: PGA its largest sample, PGV
//! the exact peak of its velocity from rest ([`super::record`]), SA from
//! the oscillator stepped exactly with the continuous peak
//! ([`crate::sdof`]). The oscillator is linear, so the response to the
//! rotated component is the rotated responses: each component's is stepped
//! once, and every angle combines them. At θ = 0° each peak is component
//! a's own measure, bit for bit.

use super::measure::{Im, Rotated, PERIODS_S, SPECTRAL_DAMPING};
use super::record::{peak_velocity_displacement, RecordImsError};
use crate::pair::{cos_sin_deg, Pair};
use crate::sdof;

/// The rotation angles RotD is taken over (°): 0 to 179 every 1°, as
/// Boore (2010) defines it (θ and θ + 180° have the same peak).
pub const ANGLES_DEG: usize = 180;

/// RotD50 and RotD100 of one measure.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RotD {
    /// The median over angles of the rotated component's peak.
    pub d50: f64,
    /// The largest over angles.
    pub d100: f64,
}

impl RotD {
    /// From the peaks at the angles 0°, 1°, …, 179°.
    fn of_peaks(mut peaks: Vec<f64>) -> RotD {
        peaks.sort_by(f64::total_cmp);
        let n = peaks.len();
        let d50 = if n % 2 == 0 {
            0.5 * (peaks[n / 2 - 1] + peaks[n / 2])
        } else {
            peaks[n / 2]
        };
        RotD {
            d50,
            d100: peaks[n - 1],
        }
    }
}

/// A pair's RotD measures: PGA (g), PGV (cm/s) and SA (g, 5 % damping) at
/// every period of [`PERIODS_S`] and the extra ones asked.
#[derive(Debug, Clone, PartialEq)]
pub struct PairIms {
    pub pga_g: RotD,
    pub pgv_cm_s: RotD,
    /// (period (s), SA), periods ascending.
    pub sa_g: Vec<(f64, RotD)>,
}

/// The unit vectors of the angles 0°, 1°, …, 179°.
fn directions() -> Vec<(f64, f64)> {
    (0..ANGLES_DEG).map(|k| cos_sin_deg(k as f64)).collect()
}

/// RotD of the pair's PGA: each angle's largest |sample|.
pub fn pga(pair: &Pair) -> RotD {
    let (a, b) = pair.padded();
    RotD::of_peaks(
        directions()
            .iter()
            .map(|&(c, s)| {
                a.iter()
                    .zip(&b)
                    .fold(0.0f64, |m, (x, y)| m.max((c * x + s * y).abs()))
            })
            .collect(),
    )
}

/// RotD of the pair's PGV (cm/s): each angle's rotated component's exact
/// peak velocity.
pub fn pgv(pair: &Pair) -> RotD {
    let (a, b) = pair.padded();
    RotD::of_peaks(
        directions()
            .iter()
            .map(|&(c, s)| {
                let rotated: Vec<f64> = a.iter().zip(&b).map(|(x, y)| c * x + s * y).collect();
                peak_velocity_displacement(&rotated, pair.dt_s).0
            })
            .collect(),
    )
}

/// RotD of the pair's SA at `period_s` (g, damping ζ): both components'
/// oscillators stepped once, each angle's response their combination.
pub fn sa(pair: &Pair, period_s: f64, zeta: f64) -> Result<RotD, sdof::SdofError> {
    let (a, b) = pair.padded();
    let (ua, h) = sdof::substep_states(&a, pair.dt_s, period_s, zeta)?;
    let (ub, _) = sdof::substep_states(&b, pair.dt_s, period_s, zeta)?;
    let w = std::f64::consts::TAU / period_s;
    Ok(RotD::of_peaks(
        directions()
            .iter()
            .map(|&(c, s)| {
                let states = ua
                    .iter()
                    .zip(&ub)
                    .map(|(p, q)| (c * p.0 + s * q.0, c * p.1 + s * q.1));
                w * w * sdof::peak_of_states(states, h)
            })
            .collect(),
    ))
}

impl PairIms {
    /// Every RotD measure of `pair`, SA at [`PERIODS_S`] and
    /// `extra_periods_s`.
    pub fn of_pair(pair: &Pair, extra_periods_s: &[f64]) -> Result<PairIms, RecordImsError> {
        let mut periods: Vec<f64> = PERIODS_S.iter().chain(extra_periods_s).copied().collect();
        periods.sort_by(f64::total_cmp);
        periods.dedup();
        let pga_g = pga(pair);
        if pga_g.d100.is_nan() || pga_g.d100 <= 0.0 {
            return Err(RecordImsError::NoMotion);
        }
        let sa_g = periods
            .iter()
            .map(|&t| sa(pair, t, SPECTRAL_DAMPING).map(|r| (t, r)))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(PairIms {
            pga_g,
            pgv_cm_s: pgv(pair),
            sa_g,
        })
    }

    /// Every measure as an IM and its value: RotD50 then RotD100 of PGA,
    /// PGV and SA at each period.
    pub fn values(&self) -> Vec<(Im, f64)> {
        let mut out = Vec::new();
        for (make, of) in [
            (
                Im::RotD50 as fn(Rotated) -> Im,
                (|r: &RotD| r.d50) as fn(&RotD) -> f64,
            ),
            (Im::RotD100, |r: &RotD| r.d100),
        ] {
            out.push((make(Rotated::Pga), of(&self.pga_g)));
            out.push((make(Rotated::Pgv), of(&self.pgv_cm_s)));
            out.extend(
                self.sa_g
                    .iter()
                    .map(|(t, r)| (make(Rotated::Sa(*t)), of(r))),
            );
        }
        out
    }

    /// One percentile's measures as `rocking ims --json` keys a record's:
    /// `pga_g`, `pgv_cm_s` and `sa_g` by period.
    pub fn json(&self, of: impl Fn(&RotD) -> f64) -> serde_json::Value {
        let sa: serde_json::Map<String, serde_json::Value> = self
            .sa_g
            .iter()
            .map(|(t, r)| (super::period_text(*t), of(r).into()))
            .collect();
        serde_json::json!({
            "pga_g": of(&self.pga_g),
            "pgv_cm_s": of(&self.pgv_cm_s),
            "sa_g": sa,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Circular motion a = (cos ωt, sin ωt): every direction's peak is the
    /// amplitude, so RotD50 = RotD100 = 1; a pair of one component and
    /// zeros has RotD100 = that component's PGA and RotD50 its median over
    /// |cos θ| (the mean of |cos 89.5°|-neighbours: cos 89° and cos 90°
    /// around the 90th and 91st… here the 180 values |cos k°| sorted).
    #[test]
    fn rotd_of_pairs_known_by_hand() {
        let n = 2000;
        let dt = 0.001;
        let w = std::f64::consts::TAU * 2.0;
        let a: Vec<f64> = (0..n).map(|i| (w * i as f64 * dt).cos()).collect();
        let b: Vec<f64> = (0..n).map(|i| (w * i as f64 * dt).sin()).collect();
        let circle = pga(&Pair::new(a.clone(), dt, b, dt).unwrap());
        assert!((circle.d100 - 1.0).abs() < 1e-6 && (circle.d50 - 1.0).abs() < 2e-4);
        let zeros = vec![0.0; n];
        let line = pga(&Pair::new(a.clone(), dt, zeros, dt).unwrap());
        assert_eq!(line.d100, 1.0);
        let mut cosines: Vec<f64> = (0..180)
            .map(|k| (k as f64).to_radians().cos().abs())
            .collect();
        cosines.sort_by(f64::total_cmp);
        // |cos| of 45° and 135° are the 90th and 91st: the median is cos 45°.
        assert!((line.d50 - 0.5 * (cosines[89] + cosines[90])).abs() < 1e-12);
        assert!((line.d50 - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12);
    }

    /// At θ = 0° the rotated SA is component a's own, bit for bit, so
    /// RotD100 of a pair of a and zeros is SA(a).
    #[test]
    fn rotd100_of_a_lone_component_is_its_sa() {
        let dt = 0.01;
        let a: Vec<f64> = (0..500)
            .map(|i| (0.3 * i as f64).sin() * (-(i as f64) / 200.0).exp())
            .collect();
        let pair = Pair::new(a.clone(), dt, vec![0.0; 400], dt).unwrap();
        for t in [0.1, 1.0, 3.0] {
            let one = sdof::pseudo_acceleration(&a, dt, t, 0.05).unwrap();
            assert_eq!(sa(&pair, t, 0.05).unwrap().d100, one, "T = {t}");
        }
        let (pgv_a, _) = peak_velocity_displacement(&a, dt);
        assert_eq!(pgv(&pair).d100, pgv_a);
    }
}
