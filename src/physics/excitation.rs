//! A record prepared for many runs ([`Excitation`]): normalised to unit
//! peak, its slopes, its running maximum and the blocks of quiet a resting
//! block cannot leave.

use super::error::PhysicsError;

/// A record prepared for many runs: normalised to unit peak, with the
/// running maximum of |ψ̈| from each sample to the end (to stop a run early
/// once the block is at rest and the rest of the record cannot lift it).
///
/// The forcing is linear over each sample interval and may jump at a
/// sample: interval `k` runs from `psi[k]` (the value just after sample k)
/// to `psi_end[k]` (the value just before sample k + 1). For a sampled
/// record `psi_end[k] = psi[k + 1]`; a pulse with a discontinuity (a
/// rectangle's switch, [`crate::pulse`]) puts it on a sample, so every
/// stepper sees it exactly on a step boundary.
#[derive(Debug, Clone)]
pub struct Excitation {
    pub dt_s: f64,
    /// `ψ̈ = ü_g / A_g` just after each sample, peak absolute value exactly
    /// 1 (for a non-zero record).
    pub psi: Vec<f64>,
    /// The forcing at the end of each interval where it is not the next
    /// sample's ([`Excitation::psi_end`]); `None` for a record, whose
    /// forcing is continuous: `psi` serves for both then.
    ends: Option<Vec<f64>>,
    /// `suffix_max[k] = max |ψ̈|` over the record from sample k on (both
    /// sides of every later jump).
    pub suffix_max: Vec<f64>,
    /// `slope[k] = (psi_end[k] − psi[k])/dt`, the forcing's slope over
    /// interval k, computed once per record rather than once per run.
    pub slope: Vec<f64>,
    /// `quiet[j]`: the largest `|psi_end[k]|` and `|psi[k + 1]|` over the
    /// intervals k of block j (`QUIET_BLOCK` of them), so that a block a
    /// resting block cannot leave is crossed at once ([`Excitation::quiet_until`]).
    quiet: Vec<f64>,
}

/// Intervals per block of [`Excitation::quiet_until`]'s scan.
const QUIET_BLOCK: usize = 32;

impl Excitation {
    /// Normalises `accel_g` by its peak. A record of zeros stays zeros (it
    /// can never lift a block).
    pub fn new(accel_g: &[f64], dt_s: f64) -> Result<Self, PhysicsError> {
        Excitation::from_samples(accel_g.to_vec(), dt_s)
    }

    /// [`Excitation::new`], normalising the samples where they are (no
    /// second array: a record read for one command is used once).
    pub fn from_samples(mut accel_g: Vec<f64>, dt_s: f64) -> Result<Self, PhysicsError> {
        if !(dt_s > 0.0 && dt_s.is_finite()) {
            return Err(PhysicsError::BadInput(format!(
                "time step {dt_s} s must be positive"
            )));
        }
        if accel_g.is_empty() {
            return Err(PhysicsError::BadInput("the record has no samples".into()));
        }
        if let Some(bad) = accel_g.iter().find(|a| !a.is_finite()) {
            return Err(PhysicsError::BadInput(format!(
                "the record holds a non-finite sample {bad}"
            )));
        }
        let peak = accel_g.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        if peak > 0.0 {
            accel_g.iter_mut().for_each(|a| *a /= peak);
        }
        Ok(Excitation::prepared(dt_s, accel_g))
    }

    /// The record of normalised samples `psi`, with what runs derive from it.
    fn prepared(dt_s: f64, psi: Vec<f64>) -> Self {
        Excitation::pieces(dt_s, psi, None)
    }

    /// A forcing linear on each interval from `psi[k]` to `psi_end[k]`
    /// (`psi` has one value more: the last sample's).
    /// `ends` are kept only where they differ from the next samples (to
    /// the bit).
    fn pieces(dt_s: f64, psi: Vec<f64>, ends: Option<Vec<f64>>) -> Self {
        let next = psi.get(1..).unwrap_or_default();
        let ends = ends.filter(|e| {
            e.len() != next.len() || e.iter().zip(next).any(|(a, b)| a.to_bits() != b.to_bits())
        });
        let psi_end = ends.as_deref().unwrap_or(next);
        debug_assert_eq!(psi_end.len() + 1, psi.len().max(1));
        let mut suffix_max = vec![0.0; psi.len()];
        let mut m = 0.0f64;
        for k in (0..psi.len()).rev() {
            m = m.max(psi[k].abs());
            if let Some(e) = psi_end.get(k) {
                m = m.max(e.abs());
            }
            suffix_max[k] = m;
        }
        let slope = psi
            .iter()
            .zip(psi_end)
            .map(|(a, b)| (b - a) / dt_s)
            .collect();
        let quiet = psi_end
            .chunks(QUIET_BLOCK)
            .zip(psi.get(1..).unwrap_or_default().chunks(QUIET_BLOCK))
            .map(|(ends, nexts)| ends.iter().chain(nexts).fold(0.0f64, |m, v| m.max(v.abs())))
            .collect();
        Excitation {
            dt_s,
            psi,
            ends,
            suffix_max,
            slope,
            quiet,
        }
    }

    /// For a block at rest at sample `k` (`|psi[k]|` within `thr`): the first
    /// interval from `k` on whose end or the next sample's start exceeds
    /// `thr` (it may lift the block), or at whose end the record stays
    /// within `thr` for good, or the record's end: every interval before it
    /// has both ends within `thr` and lifts nothing (the forcing is linear
    /// between). Whole blocks of [`QUIET_BLOCK`] intervals are crossed by
    /// their maximum.
    #[inline(always)]
    pub fn quiet_until(&self, mut k: usize, thr: f64) -> usize {
        let (psi, psi_end, suffix) = (&self.psi[..], self.psi_end(), &self.suffix_max[..]);
        let n = psi_end.len();
        while k < n {
            // The suffix maximum falls with k: above `thr` after the block's
            // last interval, it is above it after every one of them.
            if k % QUIET_BLOCK == 0
                && k + QUIET_BLOCK <= n
                && self.quiet[k / QUIET_BLOCK] <= thr
                && suffix[k + QUIET_BLOCK] > thr
            {
                k += QUIET_BLOCK;
                continue;
            }
            if !(psi_end[k].abs() <= thr && psi[k + 1].abs() <= thr && suffix[k + 1] > thr) {
                break;
            }
            k += 1;
        }
        k
    }

    /// A piecewise-linear forcing that may jump at samples: interval k goes
    /// from `starts[k]` to `ends[k]`; the last sample holds `ends`' last
    /// value. Used as given (no normalisation): its peak must be at most 1,
    /// as a normalised record's is, and equal 1 for η to mean what it does.
    pub fn piecewise(dt_s: f64, starts: &[f64], ends: &[f64]) -> Result<Self, PhysicsError> {
        let bad = |m: String| Err(PhysicsError::BadInput(m));
        if !(dt_s > 0.0 && dt_s.is_finite()) {
            return bad(format!("time step {dt_s} s must be positive"));
        }
        if starts.is_empty() || starts.len() != ends.len() {
            return bad(format!(
                "a piecewise forcing needs as many interval starts as ends, and at least one ({} and {})",
                starts.len(),
                ends.len()
            ));
        }
        if let Some(v) = starts
            .iter()
            .chain(ends)
            .find(|v| v.is_nan() || v.abs() > 1.0)
        {
            return bad(format!(
                "a piecewise forcing's values must lie in [−1, 1]; found {v}"
            ));
        }
        let mut psi = starts.to_vec();
        psi.push(ends[ends.len() - 1]);
        Ok(Excitation::pieces(dt_s, psi, Some(ends.to_vec())))
    }

    /// Record with the sign of every sample flipped (for symmetry checks).
    pub fn negated(&self) -> Self {
        self.mapped(|v| -v)
    }

    /// The normalised record with every sample mapped by `f` (e.g. moved by
    /// one ulp, to measure how rounding moves a verdict).
    pub fn mapped(&self, f: impl Fn(f64) -> f64) -> Self {
        Excitation::pieces(
            self.dt_s,
            self.psi.iter().map(|&v| f(v)).collect(),
            Some(self.psi_end().iter().map(|&v| f(v)).collect()),
        )
    }

    /// `psi_end[k]`: the forcing at the end of interval k (its left limit at
    /// sample k + 1); one per interval.
    #[inline(always)]
    pub fn psi_end(&self) -> &[f64] {
        match &self.ends {
            Some(ends) => ends,
            None => &self.psi[1..],
        }
    }

    pub fn duration_s(&self) -> f64 {
        (self.psi.len() - 1) as f64 * self.dt_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The block scan against its definition, interval by interval, from
    /// every resting start, on records with quiet stretches longer and
    /// shorter than a block, a jump, and a tail that stays quiet for good.
    #[test]
    fn quiet_scan_matches_the_interval_by_interval_scan() {
        let mut seed = 12_345u64;
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut starts = Vec::new();
        for k in 0..1_000 {
            // Bursts every 150 samples, quiet between, quieter for good at the end.
            let loud = k % 150 < 20 && k < 900;
            starts.push((if loud { 1.0 } else { 0.3 }) * (2.0 * next() - 1.0));
        }
        let mut ends: Vec<f64> = starts[1..].to_vec();
        ends.push(0.0);
        ends[500] = 0.9; // a jump down at sample 501
        starts[700] = 0.8; // and one up at sample 700
        let exc = Excitation::piecewise(0.01, &starts, &ends).unwrap();
        let n = exc.psi_end().len();
        let mut crossed = 0;
        for thr in [0.05, 0.25, 0.3, 0.5, 0.95] {
            for k0 in (0..n).filter(|&k| exc.psi[k].abs() <= thr) {
                let mut k = k0;
                while k < n
                    && exc.psi_end()[k].abs() <= thr
                    && exc.psi[k + 1].abs() <= thr
                    && exc.suffix_max[k + 1] > thr
                {
                    k += 1;
                }
                assert_eq!(exc.quiet_until(k0, thr), k, "from {k0} at {thr}");
                crossed += k - k0;
            }
        }
        assert!(
            crossed > 10_000,
            "the scans crossed only {crossed} intervals"
        );
    }
}
