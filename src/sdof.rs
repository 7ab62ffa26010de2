//! A linear single-degree-of-freedom oscillator under a sampled ground
//! acceleration, stepped exactly (pure; docs/MODEL.md §13).
//!
//! The oscillator `ü + 2ζω u̇ + ω² u = −a_g(t)` (u relative to the ground)
//! is driven by a record whose acceleration is linear between samples, as
//! everywhere in rocking. Over one sample interval the response is then
//! known in closed form, so each step is a fixed linear map of the state
//! and the two end accelerations, with coefficients that depend only on ω,
//! ζ and Δt (Nigam & Jennings 1969, "Calculation of response spectra from
//! strong-motion earthquake records", BSSA 59(2)). No step size is chosen
//! and no error is made beyond rounding: the response spectra of the
//! intensity measures and a building's floor motion are computed with it.

/// Why an oscillator cannot be stepped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SdofError {
    #[error("period T = {} s must be positive and finite", crate::decimal::shortest(*.0))]
    Period(f64),
    #[error("damping ratio ζ = {} must be in [0, 1)", crate::decimal::shortest(*.0))]
    Damping(f64),
    #[error("time step Δt = {} s must be positive and finite", crate::decimal::shortest(*.0))]
    Step(f64),
    #[error(
        "period T = {} s is below Δt/{} (Δt = {dt_s} s, the record's step): the oscillator is \
         rigid there and SA is the record's PGA; ask for T ≥ {} s, or for PGA",
        crate::im::period_text(*period_s),
        MAX_SUBSTEPS / STEPS_PER_PERIOD,
        crate::im::period_text(dt_s * STEPS_PER_PERIOD / MAX_SUBSTEPS)
    )]
    Rigid { period_s: f64, dt_s: f64 },
}

/// The exact step over Δt: the state (u, v) after it is `a·(u, v) +
/// b·(a_i, a_{i+1})`, with a_i and a_{i+1} the ground accelerations at the
/// interval's ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    pub a: [[f64; 2]; 2],
    pub b: [[f64; 2]; 2],
}

impl Step {
    /// The coefficients for an oscillator of period `period_s` and damping
    /// ratio `zeta`, over `dt_s` (Nigam & Jennings 1969, their Eqs. 25–26,
    /// for ü + 2ζωu̇ + ω²u = −a_g).
    pub fn new(period_s: f64, zeta: f64, dt_s: f64) -> Result<Step, SdofError> {
        if !(period_s > 0.0 && period_s.is_finite()) {
            return Err(SdofError::Period(period_s));
        }
        if !(0.0..1.0).contains(&zeta) {
            return Err(SdofError::Damping(zeta));
        }
        if !(dt_s > 0.0 && dt_s.is_finite()) {
            return Err(SdofError::Step(dt_s));
        }
        let w = std::f64::consts::TAU / period_s;
        let (z, h) = (zeta, dt_s);
        let root = (1.0 - z * z).sqrt();
        let wd = w * root;
        let e = (-z * w * h).exp();
        let (s, c) = (wd * h).sin_cos();
        let a = [
            [e * (z / root * s + c), e * s / wd],
            [-w / root * e * s, e * (c - z / root * s)],
        ];
        let w2 = w * w;
        let w3 = w2 * w;
        let k1 = (2.0 * z * z - 1.0) / (w2 * h);
        let k2 = 2.0 * z / (w3 * h);
        // d/dt of e^{−ζωt}(S/ωd) and of e^{−ζωt}C, at t = h, over e.
        let ds = c - z / root * s;
        let dc = -(wd * s + z * w * c);
        let b = [
            [
                e * ((k1 + z / w) * s / wd + (k2 + 1.0 / w2) * c) - k2,
                -e * (k1 * s / wd + k2 * c) - 1.0 / w2 + k2,
            ],
            [
                e * ((k1 + z / w) * ds + (k2 + 1.0 / w2) * dc) + 1.0 / (w2 * h),
                -e * (k1 * ds + k2 * dc) - 1.0 / (w2 * h),
            ],
        ];
        Ok(Step { a, b })
    }

    /// The state after one step from (`u`, `v`) under accelerations `a0`
    /// then `a1` at the interval's ends.
    #[inline]
    pub fn advance(&self, (u, v): (f64, f64), a0: f64, a1: f64) -> (f64, f64) {
        let (a, b) = (&self.a, &self.b);
        (
            a[0][0] * u + a[0][1] * v + b[0][0] * a0 + b[0][1] * a1,
            a[1][0] * u + a[1][1] * v + b[1][0] * a0 + b[1][1] * a1,
        )
    }
}

/// The oscillator's relative displacement at every sample of `accel`
/// (starting at rest), in the units of `accel` times s².
pub fn displacements(
    accel: &[f64],
    dt_s: f64,
    period_s: f64,
    zeta: f64,
) -> Result<Vec<f64>, SdofError> {
    let step = Step::new(period_s, zeta, dt_s)?;
    let mut state = (0.0, 0.0);
    let mut out = Vec::with_capacity(accel.len());
    out.push(0.0);
    for w in accel.windows(2) {
        state = step.advance(state, w[0], w[1]);
        out.push(state.0);
    }
    out.truncate(accel.len());
    Ok(out)
}

/// Sub-steps per natural period at least: the peak of |u| is then sought
/// on every sub-step, between its ends by cubic Hermite interpolation of
/// (u, u̇), whose error at 40 steps a period is below 1e-6 of the peak.
pub const STEPS_PER_PERIOD: f64 = 40.0;

/// Sub-steps per sample at most: periods below Δt/250 are refused
/// ([`SdofError::Rigid`]); at Δt = 0.005 s that is T < 0.02 ms.
pub const MAX_SUBSTEPS: f64 = 10_000.0;

/// Pseudo-spectral acceleration ω²·max|u| of the record `accel` (any unit;
/// the result is in the same one) for period `period_s` and damping `zeta`,
/// over the record's duration (no free vibration after it).
///
/// The peak is that of the continuous response, not of its samples: a
/// sample interval longer than T/40 is cut into equal sub-steps (the
/// forcing stays linear on each, so they are exact too), and where the
/// velocity changes sign within a sub-step the extremum is located on the
/// cubic through the sub-step's end displacements and velocities.
pub fn pseudo_acceleration(
    accel: &[f64],
    dt_s: f64,
    period_s: f64,
    zeta: f64,
) -> Result<f64, SdofError> {
    let mut peak = Peak::new(substep(dt_s, period_s));
    each_substep(accel, dt_s, period_s, zeta, |state, next| {
        peak.step(state, next)
    })?;
    let w = std::f64::consts::TAU / period_s;
    Ok(w * w * peak.peak)
}

/// The states (u, u̇) at every sub-step's end of the oscillator under
/// `accel` (as [`pseudo_acceleration`] steps it), the state at rest first,
/// and the sub-step (s): the response of a pair's component, which any
/// rotation of the pair combines linearly.
pub fn substep_states(
    accel: &[f64],
    dt_s: f64,
    period_s: f64,
    zeta: f64,
) -> Result<(Vec<(f64, f64)>, f64), SdofError> {
    let mut states = vec![(0.0, 0.0)];
    let h = each_substep(accel, dt_s, period_s, zeta, |_, next| states.push(next))?;
    Ok((states, h))
}

/// The peak |u| (continuous, as [`pseudo_acceleration`] seeks it) of a
/// response given by its states at the ends of sub-steps of `h` (s).
pub fn peak_of_states(states: impl IntoIterator<Item = (f64, f64)>, h: f64) -> f64 {
    let mut peak = Peak::new(h);
    let mut states = states.into_iter();
    if let Some(mut state) = states.next() {
        for next in states {
            peak.step(state, next);
            state = next;
        }
    }
    peak.peak
}

/// The running peak of |u| over sub-steps of `h` (s), with the extremum
/// inside a sub-step whose velocity changes sign.
struct Peak {
    peak: f64,
    h: f64,
}

impl Peak {
    fn new(h: f64) -> Self {
        Peak { peak: 0.0, h }
    }

    #[inline]
    fn step(&mut self, state: (f64, f64), next: (f64, f64)) {
        self.peak = self.peak.max(next.0.abs());
        if state.1 * next.1 < 0.0 {
            self.peak = self.peak.max(hermite_extremum(state, next, self.h));
        }
    }
}

/// The sub-step (s) of a record's step `dt_s` for a period `period_s`:
/// at most T/40, the step cut into equal parts.
fn substep(dt_s: f64, period_s: f64) -> f64 {
    dt_s / (dt_s * STEPS_PER_PERIOD / period_s).ceil().max(1.0)
}

/// Steps the oscillator over `accel` in sub-steps of at most T/40 (exact:
/// the forcing is linear on each), calling `f(state, next)` on each;
/// returns the sub-step (s).
fn each_substep(
    accel: &[f64],
    dt_s: f64,
    period_s: f64,
    zeta: f64,
    mut f: impl FnMut((f64, f64), (f64, f64)),
) -> Result<f64, SdofError> {
    Step::new(period_s, zeta, dt_s)?;
    let n = (dt_s * STEPS_PER_PERIOD / period_s).ceil().max(1.0);
    if n > MAX_SUBSTEPS {
        // Time would grow as 1/T (a period of 1e-9 s never ended).
        return Err(SdofError::Rigid { period_s, dt_s });
    }
    let h = substep(dt_s, period_s);
    let step = Step::new(period_s, zeta, h)?;
    let n = n as usize;
    let mut state = (0.0, 0.0);
    for win in accel.windows(2) {
        let slope = (win[1] - win[0]) / n as f64;
        for j in 0..n {
            let a0 = win[0] + slope * j as f64;
            let a1 = if j + 1 == n { win[1] } else { a0 + slope };
            let next = step.advance(state, a0, a1);
            f(state, next);
            state = next;
        }
    }
    Ok(h)
}

/// The largest |u| inside a step of length `h` from `(u0, v0)` to
/// `(u1, v1)`, on the cubic Hermite interpolant (where its slope is zero).
fn hermite_extremum((u0, v0): (f64, f64), (u1, v1): (f64, f64), h: f64) -> f64 {
    // u(s) = c0 + c1 s + c2 s² + c3 s³ on s ∈ [0, 1].
    let c1 = h * v0;
    let c2 = -3.0 * u0 - 2.0 * h * v0 + 3.0 * u1 - h * v1;
    let c3 = 2.0 * u0 + h * v0 - 2.0 * u1 + h * v1;
    let at = |s: f64| (u0 + s * (c1 + s * (c2 + s * c3))).abs();
    // u'(s) = c1 + 2 c2 s + 3 c3 s².
    let (qa, qb, qc) = (3.0 * c3, 2.0 * c2, c1);
    let mut best: f64 = 0.0;
    if qa.abs() < 1e-300 {
        if qb != 0.0 {
            let s = -qc / qb;
            if (0.0..=1.0).contains(&s) {
                best = best.max(at(s));
            }
        }
        return best;
    }
    let disc = qb * qb - 4.0 * qa * qc;
    if disc >= 0.0 {
        let r = disc.sqrt();
        for s in [(-qb + r) / (2.0 * qa), (-qb - r) / (2.0 * qa)] {
            if (0.0..=1.0).contains(&s) {
                best = best.max(at(s));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix4;

    /// A second derivation: the exact propagator of the augmented system
    /// (u, v, a, ȧ) with ȧ constant over the step, by nalgebra's matrix
    /// exponential. u(h) = E₀₀u + E₀₁v + E₀₂a₀ + E₀₃(a₁ − a₀)/h.
    fn by_exponential(period: f64, zeta: f64, h: f64) -> Step {
        let w = std::f64::consts::TAU / period;
        #[rustfmt::skip]
        let m = Matrix4::new(
            0.0, 1.0, 0.0, 0.0,
            -w * w, -2.0 * zeta * w, -1.0, 0.0,
            0.0, 0.0, 0.0, 1.0,
            0.0, 0.0, 0.0, 0.0,
        ) * h;
        let e = m.exp();
        let row = |i: usize| {
            (
                [e[(i, 0)], e[(i, 1)]],
                [e[(i, 2)] - e[(i, 3)] / h, e[(i, 3)] / h],
            )
        };
        let (r0, r1) = (row(0), row(1));
        Step {
            a: [r0.0, r1.0],
            b: [r0.1, r1.1],
        }
    }

    /// The closed-form coefficients against the matrix exponential, over
    /// periods 0.05–4 s, damping 0–20 % and the record steps of FEMA P695
    /// (0.005–0.02 s): the same to 1e-11 relative to the largest of each
    /// matrix (the exponential's Padé approximant is good to ~1e-13).
    #[test]
    fn closed_form_agrees_with_the_matrix_exponential() {
        for period in [0.05, 0.2, 1.0, 4.0] {
            for zeta in [0.0, 0.02, 0.05, 0.2] {
                for dt in [0.005, 0.01, 0.02] {
                    let nj = Step::new(period, zeta, dt).unwrap();
                    let ex = by_exponential(period, zeta, dt);
                    for (m, n) in [(nj.a, ex.a), (nj.b, ex.b)] {
                        let scale = n.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
                        for i in 0..2 {
                            for j in 0..2 {
                                let d = (m[i][j] - n[i][j]).abs() / scale;
                                assert!(d < 1e-11, "T {period} ζ {zeta} Δt {dt}: {m:?} vs {n:?}");
                            }
                        }
                    }
                }
            }
        }
    }

    /// Free vibration from u = 1, v = 0: u(t) = e^{−ζωt}(cos ω_d t +
    /// ζ/√(1 − ζ²) sin ω_d t), after 10,000 steps, to 1e-12.
    #[test]
    fn free_vibration_is_the_closed_form() {
        let (period, zeta, dt) = (0.7, 0.05, 0.01);
        let step = Step::new(period, zeta, dt).unwrap();
        let w = std::f64::consts::TAU / period;
        let wd = w * (1.0 - zeta * zeta).sqrt();
        let mut state = (1.0, 0.0);
        for k in 1..=10_000 {
            state = step.advance(state, 0.0, 0.0);
            let t = k as f64 * dt;
            let exact = (-zeta * w * t).exp()
                * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin());
            assert!(
                (state.0 - exact).abs() < 1e-12,
                "t = {t}: {} vs {exact}",
                state.0
            );
        }
    }

    /// A harmonic ground acceleration A sin Ωt: after the transient has
    /// decayed (e^{−ζωt} < 1e-9), the displacement amplitude is the steady
    /// state's A/ω² / √((1 − r²)² + (2ζr)²), r = Ω/ω. Sampled at 1/2000 of
    /// the forcing period, the piecewise-linear forcing differs from the
    /// sine by (ΩΔt)²/8 ≈ 1e-6 relative: tolerance 1e-4.
    #[test]
    fn harmonic_input_reaches_the_steady_state_amplitude() {
        let (period, zeta) = (0.5, 0.05);
        let w = std::f64::consts::TAU / period;
        for r in [0.5, 1.0, 2.0] {
            let big_w = r * w;
            let dt = std::f64::consts::TAU / big_w / 2000.0;
            let settle = (9.0 * 10f64.ln() / (zeta * w) / dt) as usize;
            let n = settle + 4000;
            let accel: Vec<f64> = (0..n).map(|k| (big_w * k as f64 * dt).sin()).collect();
            let u = displacements(&accel, dt, period, zeta).unwrap();
            let amplitude = u[settle..].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let exact = 1.0 / (w * w) / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt();
            assert!(
                (amplitude / exact - 1.0).abs() < 1e-4,
                "r = {r}: {amplitude} vs {exact}"
            );
        }
    }

    /// A very stiff oscillator follows the ground quasi-statically: its
    /// pseudo-acceleration tends to the record's peak (to 1 % at T = 0.01 s
    /// for a slowly varying record), and bad inputs are refused.
    #[test]
    fn a_stiff_oscillator_gives_the_peak_and_inputs_are_checked() {
        let dt = 0.001;
        let accel: Vec<f64> = (0..5000)
            .map(|k| (std::f64::consts::TAU * 0.5 * k as f64 * dt).sin())
            .collect();
        let sa = pseudo_acceleration(&accel, dt, 0.01, 0.05).unwrap();
        assert!((sa - 1.0).abs() < 0.01, "{sa}");
        assert_eq!(Step::new(0.0, 0.05, 0.01), Err(SdofError::Period(0.0)));
        assert_eq!(Step::new(1.0, 1.0, 0.01), Err(SdofError::Damping(1.0)));
        assert_eq!(Step::new(1.0, 0.05, -1.0), Err(SdofError::Step(-1.0)));
    }

    /// The continuous peak of a record sampled far coarser than the period:
    /// the same record resampled 2000 times finer (exactly, since it is
    /// linear between samples) and its peak taken at the fine samples,
    /// whose miss is at most 1 − cos(π Δt/T) < 3e-6 here: agreement to 1e-5.
    #[test]
    fn the_peak_between_samples_is_found() {
        let dt = 0.02;
        let accel: Vec<f64> = (0..400)
            .map(|k| {
                let t = k as f64 * dt;
                (7.0 * t).sin() * (-0.2 * t).exp() + 0.3 * (23.0 * t).cos()
            })
            .collect();
        for period in [0.05, 0.1, 0.3, 1.0] {
            let fine_n = 2000;
            let mut fine = Vec::with_capacity(accel.len() * fine_n);
            for w in accel.windows(2) {
                for j in 0..fine_n {
                    fine.push(w[0] + (w[1] - w[0]) * j as f64 / fine_n as f64);
                }
            }
            fine.push(*accel.last().unwrap());
            let u = displacements(&fine, dt / fine_n as f64, period, 0.05).unwrap();
            let w = std::f64::consts::TAU / period;
            let reference = w * w * u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let sa = pseudo_acceleration(&accel, dt, period, 0.05).unwrap();
            assert!(
                (sa / reference - 1.0).abs() < 1e-5,
                "T = {period}: {sa} vs {reference}"
            );
        }
    }
}
