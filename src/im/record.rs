//! A record's intensity measures from its samples (pure; docs/MODEL.md §14).
//!
//! The record is linear between samples (MODEL.md §2), so every integral
//! here is exact for it: velocity and displacement by integrating the
//! piecewise-linear acceleration from rest (no baseline correction: the
//! bundled PEER records are already processed, and a correction would
//! change the record the block is shaken by), their peaks between samples
//! included; Arias intensity and CAV in closed form per interval; the
//! significant duration where the Husid curve, cubic per interval, crosses
//! 5 % and 95 %; SA by the exact oscillator step of [`crate::sdof`].

use super::measure::{Im, AVGSA_PERIODS_S, G_M_S2, PERIODS_S, SPECTRAL_DAMPING};
use crate::sdof;

/// The band of Fourier frequencies (Hz) over which the mean period is
/// averaged, and the finest frequency step it is computed on (Rathje,
/// Abrahamson & Bray 1998, J. Geotech. Geoenviron. Eng. 124(2)).
pub const TM_BAND_HZ: (f64, f64) = (0.25, 20.0);
pub const TM_MAX_STEP_HZ: f64 = 0.05;

/// cm/s² in one g.
const CM_S2_PER_G: f64 = G_M_S2 * 100.0;

/// A record's measures, unscaled: each [`Im`] with its value, in the order
/// of [`Im::record_measures`] (SA by period, with any period asked for).
#[derive(Debug, Clone, PartialEq)]
pub struct RecordIms {
    values: Vec<(Im, f64)>,
}

/// What several measures share, computed once for a record.
struct Shared<'a> {
    accel_g: &'a [f64],
    dt_s: f64,
    pga_g: f64,
    /// Peak velocity (cm/s) and displacement (cm).
    peaks: (f64, f64),
    /// SA (g) by period, ascending.
    sa_g: Vec<(f64, f64)>,
}

impl Shared<'_> {
    fn sa(&self, t: f64) -> Option<f64> {
        self.sa_g.iter().find(|(p, _)| *p == t).map(|&(_, v)| v)
    }
}

impl Im {
    /// This measure of the record `s` describes (SA only at a period `s`
    /// computed).
    fn of_record(self, s: &Shared) -> Option<f64> {
        Some(match self {
            Im::Pga => s.pga_g,
            Im::Pgv => s.peaks.0,
            Im::Pgd => s.peaks.1,
            Im::Sa(t) => s.sa(t)?,
            Im::AvgSa => {
                let logs: f64 = AVGSA_PERIODS_S
                    .iter()
                    .map(|&t| s.sa(t).map(f64::ln))
                    .sum::<Option<f64>>()?;
                (logs / AVGSA_PERIODS_S.len() as f64).exp()
            }
            Im::Arias => arias_m_s(s.accel_g, s.dt_s),
            Im::Cav => cav_g_s(s.accel_g, s.dt_s),
            Im::D5_95 => significant_duration_s(s.accel_g, s.dt_s, 0.05, 0.95),
            Im::PgvPga => super::measure::pgv_pga_s(s.pga_g, s.peaks.0),
            Im::Tm => mean_period_s(s.accel_g, s.dt_s),
            // The record as the motion the block feels.
            Im::Pfa => s.pga_g,
            Im::Pfv => s.peaks.0,
            Im::Fsa(t) => s.sa(t)?,
            // Of a pair: not of one record.
            Im::RotD50(_) | Im::RotD100(_) => return None,
        })
    }
}

/// Why a record's measures cannot be had.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RecordImsError {
    #[error("the record has no motion (every sample is 0)")]
    NoMotion,
    #[error(transparent)]
    Oscillator(#[from] sdof::SdofError),
    #[error("{0} cannot be computed from the record")]
    Measure(String),
}

impl RecordIms {
    /// The measures of a record sampled at `dt_s` (accelerations in g):
    /// every one of [`Im::record_measures`], and SA at `extra_periods_s`
    /// too (positive; `None` for a record without a positive peak or a bad
    /// period: [`RecordIms::try_of_record`] says which).
    pub fn of_record(accel_g: &[f64], dt_s: f64, extra_periods_s: &[f64]) -> Option<RecordIms> {
        RecordIms::try_of_record(accel_g, dt_s, extra_periods_s).ok()
    }

    /// [`RecordIms::of_record`], saying why where it cannot.
    pub fn try_of_record(
        accel_g: &[f64],
        dt_s: f64,
        extra_periods_s: &[f64],
    ) -> Result<RecordIms, RecordImsError> {
        let pga_g = crate::motion::peak(accel_g, dt_s)
            .ok_or(RecordImsError::NoMotion)?
            .pga_g;
        if !(pga_g > 0.0 && dt_s > 0.0) {
            return Err(RecordImsError::NoMotion);
        }
        let mut periods: Vec<f64> = PERIODS_S.iter().chain(extra_periods_s).copied().collect();
        periods.sort_by(f64::total_cmp);
        periods.dedup();
        let sa_g = periods
            .iter()
            .map(|&t| {
                sdof::pseudo_acceleration(accel_g, dt_s, t, SPECTRAL_DAMPING).map(|sa| (t, sa))
            })
            .collect::<Result<Vec<_>, _>>()?;
        let shared = Shared {
            accel_g,
            dt_s,
            pga_g,
            peaks: peak_velocity_displacement(accel_g, dt_s),
            sa_g,
        };
        let mut values: Vec<(Im, f64)> = Im::record_measures()
            .into_iter()
            .filter(|im| !matches!(im, Im::Sa(_)))
            .map(|im| {
                im.of_record(&shared)
                    .map(|v| (im, v))
                    .ok_or_else(|| RecordImsError::Measure(im.name()))
            })
            .collect::<Result<_, _>>()?;
        values.extend(shared.sa_g.iter().map(|&(t, v)| (Im::Sa(t), v)));
        Ok(RecordIms { values })
    }

    /// Measures as read back (a table's rows): `pga` must be among them.
    pub fn from_values(values: Vec<(Im, f64)>) -> Option<RecordIms> {
        let ims = RecordIms { values };
        ims.value(Im::Pga).map(|_| ims)
    }

    /// Adds measures had elsewhere (a pair's RotD, over this record's scale).
    pub fn extend(&mut self, values: impl IntoIterator<Item = (Im, f64)>) {
        self.values.extend(values);
    }

    /// The record's value of `im` (`None`: an SA period not computed); PFA,
    /// PFV and FSA(T) are its PGA, PGV and SA(T), the record taken as the
    /// motion the block feels.
    pub fn value(&self, im: Im) -> Option<f64> {
        let im = im.of_motion();
        self.values.iter().find(|(m, _)| *m == im).map(|&(_, v)| v)
    }

    /// The record's PGA (g).
    pub fn pga_g(&self) -> f64 {
        self.value(Im::Pga)
            .expect("every record's measures hold its PGA")
    }

    /// Every measure with its value, in order.
    pub fn iter(&self) -> impl Iterator<Item = (Im, f64)> + '_ {
        self.values.iter().copied()
    }

    /// SA (g) by period (s), ascending.
    pub fn spectrum(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.values.iter().filter_map(|&(im, v)| match im {
            Im::Sa(t) => Some((t, v)),
            _ => None,
        })
    }
}

/// As `rocking ims --json` prints it: each measure but SA under its key
/// ([`Im::key`]: `pga_g`, `pgv_cm_s`, …), and `sa_g`, an object from the
/// period in seconds as text ([`super::period_text`]: `"1.0"`) to SA in g.
impl serde::Serialize for RecordIms {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        struct Spectrum<'a>(&'a RecordIms);
        impl serde::Serialize for Spectrum<'_> {
            fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
                serializer.collect_map(
                    self.0
                        .spectrum()
                        .map(|(t, v)| (super::measure::period_text(t), v)),
                )
            }
        }
        let mut map = serializer.serialize_map(None)?;
        for (im, v) in self.iter().filter(|(im, _)| !matches!(im, Im::Sa(_))) {
            map.serialize_entry(&im.key(), &v)?;
        }
        map.serialize_entry("sa_g", &Spectrum(self))?;
        map.end()
    }
}

/// Peak |velocity| (cm/s) and |displacement| (cm) of the record integrated
/// from rest, exactly: velocity is quadratic and displacement cubic on each
/// interval, and their extrema inside one (where the acceleration,
/// respectively the velocity, vanishes) count.
pub fn peak_velocity_displacement(accel_g: &[f64], dt_s: f64) -> (f64, f64) {
    let h = dt_s;
    let (mut v, mut u) = (0.0f64, 0.0f64);
    let (mut pgv, mut pgd) = (0.0f64, 0.0f64);
    for w in accel_g.windows(2) {
        let (a0, a1) = (w[0] * CM_S2_PER_G, w[1] * CM_S2_PER_G);
        let j = (a1 - a0) / h;
        // v(s) = v + a0 s + j s²/2; u(s) = u + v s + a0 s²/2 + j s³/6.
        let vel = |s: f64| v + s * (a0 + 0.5 * j * s);
        let disp = |s: f64| u + s * (v + s * (0.5 * a0 + j * s / 6.0));
        if a0 * a1 < 0.0 {
            pgv = pgv.max(vel(a0 / (a0 - a1) * h).abs());
        }
        for s in roots_in(0.5 * j, a0, v, h) {
            pgd = pgd.max(disp(s).abs());
        }
        let (v1, u1) = (vel(h), disp(h));
        v = v1;
        u = u1;
        pgv = pgv.max(v.abs());
        pgd = pgd.max(u.abs());
    }
    (pgv, pgd)
}

/// The roots of `c2 s² + c1 s + c0` strictly inside (0, h).
fn roots_in(c2: f64, c1: f64, c0: f64, h: f64) -> Vec<f64> {
    let inside = |s: f64| s > 0.0 && s < h;
    if c2 == 0.0 {
        return if c1 != 0.0 && inside(-c0 / c1) {
            vec![-c0 / c1]
        } else {
            Vec::new()
        };
    }
    let disc = c1 * c1 - 4.0 * c2 * c0;
    if disc < 0.0 {
        return Vec::new();
    }
    // The stable pair: q = −(c1 + sgn(c1)√disc)/2, roots q/c2 and c0/q.
    let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
    let mut roots = vec![q / c2];
    if q != 0.0 {
        roots.push(c0 / q);
    }
    roots.retain(|&s| inside(s));
    roots
}

/// `∫ a² dt` over one interval of a linear `a` (g²·s).
fn square_integral(a0: f64, a1: f64, h: f64) -> f64 {
    h / 3.0 * (a0 * a0 + a0 * a1 + a1 * a1)
}

/// Arias intensity `π/(2g) ∫ a² dt` (m/s), a in m/s².
pub fn arias_m_s(accel_g: &[f64], dt_s: f64) -> f64 {
    // From +0 (a float sum starts at −0: one sample printed −0.0).
    let sum: f64 = accel_g
        .windows(2)
        .map(|w| square_integral(w[0], w[1], dt_s))
        .fold(0.0, |s, x| s + x);
    std::f64::consts::PI / (2.0 * G_M_S2) * G_M_S2 * G_M_S2 * sum
}

/// Cumulative absolute velocity `∫ |a| dt` (g·s), exact for a linear `a`
/// that changes sign within an interval.
pub fn cav_g_s(accel_g: &[f64], dt_s: f64) -> f64 {
    accel_g
        .windows(2)
        .map(|w| {
            let (a0, a1) = (w[0], w[1]);
            if a0 * a1 >= 0.0 {
                0.5 * dt_s * (a0.abs() + a1.abs())
            } else {
                0.5 * dt_s * (a0 * a0 + a1 * a1) / (a0.abs() + a1.abs())
            }
        })
        .fold(0.0, |s, x| s + x)
}

/// Time (s) between the instants the Husid curve `∫₀ᵗ a²` reaches the
/// fractions `from` and `to` of its total, each located inside its
/// interval on the exact cubic (by bisection to 1e-12 of the interval).
pub fn significant_duration_s(accel_g: &[f64], dt_s: f64, from: f64, to: f64) -> f64 {
    // On the record over its peak: a duration does not change with
    // scaling, and ∫a² of a record scaled by 1e300 overflows (it gave 0).
    let peak = accel_g.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    if !(peak > 0.0 && peak.is_finite()) {
        return 0.0;
    }
    let norm: Vec<f64> = accel_g.iter().map(|a| a / peak).collect();
    let accel_g = norm.as_slice();
    let total: f64 = accel_g
        .windows(2)
        .map(|w| square_integral(w[0], w[1], dt_s))
        .fold(0.0, |s, x| s + x);
    if total <= 0.0 {
        return 0.0;
    }
    let crossing = |fraction: f64| -> f64 {
        let target = fraction * total;
        let mut before = 0.0;
        for (i, w) in accel_g.windows(2).enumerate() {
            let here = square_integral(w[0], w[1], dt_s);
            if before + here >= target {
                // ∫₀ˢ over the interval's start, increasing in s.
                let (a0, j) = (w[0], (w[1] - w[0]) / dt_s);
                let part = |s: f64| s * (a0 * a0 + s * (a0 * j + s * j * j / 3.0));
                let (mut lo, mut hi) = (0.0, dt_s);
                while hi - lo > 1e-12 * dt_s {
                    let mid = 0.5 * (lo + hi);
                    if before + part(mid) < target {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                return i as f64 * dt_s + 0.5 * (lo + hi);
            }
            before += here;
        }
        (accel_g.len() - 1) as f64 * dt_s
    };
    crossing(to) - crossing(from)
}

/// Mean period `Tm = Σ Cᵢ²/fᵢ / Σ Cᵢ²` (s) over the discrete Fourier
/// frequencies fᵢ in 0.25–20 Hz (Rathje et al. 1998), Cᵢ the Fourier
/// amplitudes of the samples. The record is padded with zeros to at least
/// 1/0.05 Hz = 20 s, so the step between frequencies is at most 0.05 Hz as
/// Rathje et al. ask. One FFT of that length (any length: rustfft's mixed
/// radix, Rader and Bluestein plans, scalar so that every machine gets the
/// same bits), O(m log m): a DFT bin by bin is O(m²), 10 s for a record of
/// 120,000 samples.
pub fn mean_period_s(accel_g: &[f64], dt_s: f64) -> f64 {
    let n = accel_g.len();
    let m = n.max((1.0 / (TM_MAX_STEP_HZ * dt_s)).ceil() as usize);
    let df = 1.0 / (m as f64 * dt_s);
    let first = ((TM_BAND_HZ.0 / df).ceil() as usize).max(1);
    let last = ((TM_BAND_HZ.1 / df).floor() as usize).min(m / 2);
    if first > last {
        return f64::NAN;
    }
    let power = dft_power(accel_g, m);
    let (mut num, mut den) = (0.0, 0.0);
    for (k, &c2) in power.iter().enumerate().take(last + 1).skip(first) {
        num += c2 / (k as f64 * df);
        den += c2;
    }
    if den > 0.0 {
        num / den
    } else {
        f64::NAN
    }
}

/// |Σⱼ xⱼ e^{−2πi jk/m}|² for k = 0..m, the samples `x` padded with zeros
/// to `m ≥ x.len()`.
fn dft_power(x: &[f64], m: usize) -> Vec<f64> {
    use rustfft::{num_complex::Complex, FftPlannerScalar};
    let mut buffer: Vec<Complex<f64>> = x
        .iter()
        .map(|&re| Complex { re, im: 0.0 })
        .chain(std::iter::repeat(Complex { re: 0.0, im: 0.0 }))
        .take(m)
        .collect();
    // The scalar plans: the same bits on every CPU (the SIMD plans, chosen
    // at run time, round differently).
    FftPlannerScalar::new()
        .plan_fft_forward(m)
        .process(&mut buffer);
    buffer.iter().map(|c| c.norm_sqr()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A constant acceleration A (g) for T seconds: v = A g t, u = A g t²/2,
    /// Arias = π g A² T / 2, CAV = A T, the Husid curve is linear so
    /// D5–95 = 0.9 T, and PGV/PGA = T.
    #[test]
    fn a_constant_acceleration_by_hand() {
        let (a, dt, n) = (0.3, 0.01, 501);
        let accel = vec![a; n];
        let t = (n - 1) as f64 * dt;
        let (pgv, pgd) = peak_velocity_displacement(&accel, dt);
        assert!((pgv - a * CM_S2_PER_G * t).abs() < 1e-9 * pgv);
        assert!((pgd - 0.5 * a * CM_S2_PER_G * t * t).abs() < 1e-9 * pgd);
        let ia = arias_m_s(&accel, dt);
        assert!((ia - PI * G_M_S2 * a * a * t / 2.0).abs() < 1e-12 * ia);
        assert!((cav_g_s(&accel, dt) - a * t).abs() < 1e-12);
        let d = significant_duration_s(&accel, dt, 0.05, 0.95);
        assert!((d - 0.9 * t).abs() < 1e-9, "{d}");
        let ims = RecordIms::of_record(&accel, dt, &[]).unwrap();
        assert!((ims.value(Im::PgvPga).unwrap() - t).abs() < 1e-9);
    }

    /// A ramp a = t (g) on [0, 1] s: the Husid curve is t³/3, so D5–95 =
    /// 0.95^(1/3) − 0.05^(1/3); a triangle up and down crosses zero inside
    /// an interval and its CAV counts both lobes.
    #[test]
    fn ramps_and_a_sign_change_inside_an_interval() {
        let d = significant_duration_s(&[0.0, 1.0], 1.0, 0.05, 0.95);
        let want = 0.95f64.cbrt() - 0.05f64.cbrt();
        assert!((d - want).abs() < 1e-10, "{d} vs {want}");
        // From +1 to −3 over 1 s: zero at 0.25 s; ∫|a| = 0.25·1/2 + 0.75·3/2.
        assert!((cav_g_s(&[1.0, -3.0], 1.0) - (0.125 + 1.125)).abs() < 1e-15);
        // Velocity peaks where a crosses zero: v(0.25) = 1·0.25/2 g.
        let (pgv, _) = peak_velocity_displacement(&[1.0, -3.0], 1.0);
        let v_end = (1.0 - 3.0) / 2.0 * CM_S2_PER_G;
        assert!((pgv - (0.125 * CM_S2_PER_G).max(v_end.abs())).abs() < 1e-9);
    }

    /// A sine a = A sin ωt over whole periods, sampled finely: v = (A/ω)(1 −
    /// cos ωt) peaks at 2A/ω; u = (A/ω)(t − sin(ωt)/ω) peaks at the end,
    /// A T_total/ω. The chords of the sampled sine integrate it to within
    /// (ωΔt)²/12 = 3.3e-6 relative: tolerance 1e-5.
    #[test]
    fn a_sine_s_velocity_and_displacement() {
        let (amp, w, dt) = (0.2, 2.0 * PI, 1e-3);
        let n = 3001; // three whole periods of 1 s
        let accel: Vec<f64> = (0..n).map(|k| amp * (w * k as f64 * dt).sin()).collect();
        let (pgv, pgd) = peak_velocity_displacement(&accel, dt);
        let a = amp * CM_S2_PER_G;
        assert!((pgv / (2.0 * a / w) - 1.0).abs() < 1e-5, "{pgv}");
        assert!((pgd / (a * 3.0 / w) - 1.0).abs() < 1e-5, "{pgd}");
        // A full sine period then −v: u(t) = (A/ω)(t − sin ωt/ω) on the period,
        // reaching A/ω·1 at t = 1 s with v = 0 there: then a = 0 holds it still.
        let mut one: Vec<f64> = (0..1001).map(|k| amp * (w * k as f64 * dt).sin()).collect();
        one.extend(std::iter::repeat_n(0.0, 500));
        let (_, pgd) = peak_velocity_displacement(&one, dt);
        assert!((pgd / (a / w) - 1.0).abs() < 1e-5, "{pgd}");
    }

    /// The mean period of one sinusoid on a Fourier bin is its period; of two,
    /// the C²-weighted mean of 1/f (no leakage when both fill whole cycles
    /// of the padded length).
    #[test]
    fn mean_period_of_sinusoids_on_bins() {
        let dt = 0.01;
        let n = 4000; // 40 s: Δf = 0.025 Hz, no padding
        let (f1, f2) = (0.5, 2.0);
        let one: Vec<f64> = (0..n)
            .map(|k| (std::f64::consts::TAU * f1 * k as f64 * dt).sin())
            .collect();
        assert!((mean_period_s(&one, dt) - 2.0).abs() < 1e-9);
        let two: Vec<f64> = (0..n)
            .map(|k| {
                let t = k as f64 * dt;
                (std::f64::consts::TAU * f1 * t).sin()
                    + 2.0 * (std::f64::consts::TAU * f2 * t).cos()
            })
            .collect();
        let want = (1.0 / f1 + 4.0 / f2) / 5.0;
        assert!(
            (mean_period_s(&two, dt) - want).abs() < 1e-9,
            "{}",
            mean_period_s(&two, dt)
        );
    }

    /// The FFT against the DFT's definition, a sum with sin_cos at every
    /// term, on lengths with large prime factors (Rader's and Bluestein's
    /// plans) and with padding; rounding of a sum of ~5,000 terms of
    /// magnitude ≤ 1 stays far below 1e-9 of the larger bins.
    #[test]
    fn the_fft_is_the_direct_sum() {
        let x: Vec<f64> = (0..5000)
            .map(|k| ((k * 7919) % 211) as f64 / 100.0 - 1.0)
            .collect();
        for m in [5000usize, 6000, 5003, 2 * 2503] {
            let power = dft_power(&x, m);
            assert_eq!(power.len(), m);
            for k in [1usize, 37, 999, m / 2] {
                let (mut re, mut im) = (0.0, 0.0);
                for (j, v) in x.iter().enumerate() {
                    let (s, c) =
                        (-std::f64::consts::TAU * ((j * k) % m) as f64 / m as f64).sin_cos();
                    re += v * c;
                    im += v * s;
                }
                let direct = re * re + im * im;
                assert!(
                    (power[k] - direct).abs() < 1e-9 * direct.max(1.0),
                    "m = {m}, k = {k}: {} vs {direct}",
                    power[k]
                );
            }
        }
    }

    /// A record of 1,000,000 samples (2.8 h at 0.01 s) takes one FFT: the
    /// mean period of a sinusoid on a bin is its period, in a fraction of a
    /// second where a bin-by-bin DFT would take some ten minutes (not
    /// timed: a wrong complexity shows as a test that does not end).
    #[test]
    fn the_mean_period_of_a_long_record() {
        let (dt, n) = (0.01, 1_000_000);
        let f = 1.25; // 12,500 cycles: on a bin of the 10,000 s record
        let x: Vec<f64> = (0..n)
            .map(|k| (std::f64::consts::TAU * f * k as f64 * dt).sin())
            .collect();
        assert!((mean_period_s(&x, dt) - 1.0 / f).abs() < 1e-9);
    }

    /// SA against the oscillator module's own peak, AvgSA as the geometric
    /// mean of its periods, extra periods kept and sorted.
    #[test]
    fn spectra_and_avgsa() {
        let dt = 0.01;
        let accel: Vec<f64> = (0..2000)
            .map(|k| 0.2 * (3.0 * k as f64 * dt).sin() * (-0.1 * k as f64 * dt).exp())
            .collect();
        let ims = RecordIms::of_record(&accel, dt, &[0.33, 1.0]).unwrap();
        let spectrum: Vec<(f64, f64)> = ims.spectrum().collect();
        assert_eq!(spectrum.len(), PERIODS_S.len() + 1);
        assert!(spectrum.windows(2).all(|w| w[0].0 < w[1].0));
        let sa1 = sdof::pseudo_acceleration(&accel, dt, 1.0, 0.05).unwrap();
        assert_eq!(ims.value(Im::Sa(1.0)), Some(sa1));
        assert!(ims.value(Im::Sa(0.33)).is_some());
        let product: f64 = AVGSA_PERIODS_S
            .iter()
            .map(|&t| ims.value(Im::Sa(t)).unwrap())
            .product();
        let geo = product.powf(1.0 / AVGSA_PERIODS_S.len() as f64);
        assert!((ims.value(Im::AvgSa).unwrap() / geo - 1.0).abs() < 1e-12);
        assert!(RecordIms::of_record(&[0.0, 0.0], dt, &[]).is_none());
    }

    /// Peaks between samples: a coarse record against itself resampled
    /// 1000 times finer (the same piecewise-linear motion), whose peaks at
    /// samples miss the continuous ones by at most ~1e-6 relative here.
    #[test]
    fn peaks_between_samples_are_found() {
        let dt = 0.05;
        let accel: Vec<f64> = (0..200)
            .map(|k| ((k * 7919) % 97) as f64 / 48.0 - 1.0 + 0.3 * (k as f64 * 0.21).sin())
            .collect();
        let n = 1000;
        let mut fine = Vec::new();
        for w in accel.windows(2) {
            fine.extend((0..n).map(|j| w[0] + (w[1] - w[0]) * j as f64 / n as f64));
        }
        fine.push(*accel.last().unwrap());
        let (v, u) = peak_velocity_displacement(&accel, dt);
        let (vf, uf) = peak_velocity_displacement(&fine, dt / n as f64);
        assert!((v / vf - 1.0).abs() < 1e-6, "{v} vs {vf}");
        assert!((u / uf - 1.0).abs() < 1e-6, "{u} vs {uf}");
        // The coarse samples alone miss the velocity's peaks (a check that
        // the interior search matters on this record).
        let mut vel = 0.0f64;
        let mut sampled = 0.0f64;
        for w in accel.windows(2) {
            vel += 0.5 * dt * (w[0] + w[1]) * CM_S2_PER_G;
            sampled = sampled.max(vel.abs());
        }
        assert!(sampled < v * (1.0 - 1e-4), "{sampled} vs {v}");
    }
}
