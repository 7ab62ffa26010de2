//! A sampled ground-acceleration history and its summary values (pure).
//!
//! Samples are equally spaced in time, the first at t = 0; between samples the
//! record is taken as linear (MODEL.md §2). Hence the duration of an N-sample
//! record is (N − 1)·dt.

/// The largest |sample| accepted (g): more than twice the strongest ground
/// motion recorded (about 4 g at IWTH25 in the 2008 Iwate-Miyagi
/// earthquake; Aoi et al. 2008, Science 322, 727-730). A file past it is in
/// another unit, or broken.
pub const MAX_ACCEL_G: f64 = 10.0;

/// The coarsest sampling accepted (s): strong-motion records are sampled
/// every 0.001–0.05 s, and a step of 0.1 s (5 Hz at most) already misses
/// the shaking a block rocks under. Past it is a sample number taken for
/// a time (a step of exactly 1) or a time in other units.
pub const MAX_DT_S: f64 = 0.1;

/// The finest sampling accepted (s): a hundred times finer than any
/// strong-motion record's; below it a header's DT is wrong, and would
/// stretch the record's seconds by as much.
pub const MIN_DT_S: f64 = 1e-5;

/// Whether a time step (s) is within [`MIN_DT_S`]–[`MAX_DT_S`], to
/// rounding: a mean step of times printed in decimals (0.1 plus an ulp, by
/// `(t_last − t_0)/(n − 1)`) is the limit itself.
pub fn dt_accepted(dt_s: f64) -> bool {
    (MIN_DT_S * (1.0 - 1e-9)..=MAX_DT_S * (1.0 + 1e-9)).contains(&dt_s)
}

/// Why samples (g) at a step (s) are no motion a block can be run under:
/// fewer than two, a step outside [`MIN_DT_S`]–[`MAX_DT_S`], a sample past
/// [`MAX_ACCEL_G`], or none but 0 (nothing to scale to a PGA). Files are
/// held to the same limits where their lines are read (`at2`, `columns`),
/// to name the line; samples given as numbers (Python's arrays) here.
pub fn check(accel_g: &[f64], dt_s: f64) -> Result<(), String> {
    if accel_g.len() < 2 {
        return Err(format!(
            "{} sample(s): a motion needs two at least",
            accel_g.len()
        ));
    }
    if !dt_accepted(dt_s) {
        return Err(format!(
            "a time step of {dt_s:e} s: a motion is sampled every 0.001–0.05 s (accepted: \
             {MIN_DT_S:e} to {MAX_DT_S} s); is it in seconds?"
        ));
    }
    if let Some(i) = accel_g.iter().position(|a| !a.is_finite()) {
        return Err(format!("sample {} is {}: not a number", i + 1, accel_g[i]));
    }
    if let Some(i) = accel_g.iter().position(|a| a.abs() > MAX_ACCEL_G) {
        return Err(format!(
            "sample {} is {:e} g, past {MAX_ACCEL_G} g: no ground motion is that strong; are \
             the samples in g?",
            i + 1,
            accel_g[i]
        ));
    }
    if accel_g.iter().all(|&a| a == 0.0) {
        return Err("every sample is 0: no motion to scale to a PGA".into());
    }
    Ok(())
}

/// Peak ground acceleration of a record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// Largest absolute sample, in g.
    pub pga_g: f64,
    /// Index of the first sample reaching it.
    pub index: usize,
    /// Time of that sample, `index · dt` (s).
    pub time_s: f64,
}

/// Peak of a record sampled at `dt_s`. An empty record has no peak.
pub fn peak(accel_g: &[f64], dt_s: f64) -> Option<Peak> {
    let mut best: Option<(usize, f64)> = None;
    for (i, a) in accel_g.iter().map(|a| a.abs()).enumerate() {
        if best.is_none_or(|(_, b)| a > b) {
            best = Some((i, a));
        }
    }
    best.map(|(index, pga_g)| Peak {
        pga_g,
        index,
        time_s: index as f64 * dt_s,
    })
}

/// Duration from the first to the last sample, `(N − 1)·dt` (s).
pub fn duration_s(npts: usize, dt_s: f64) -> f64 {
    npts.saturating_sub(1) as f64 * dt_s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each limit by a case on each side of it.
    #[test]
    fn samples_are_held_to_a_motions_limits() {
        let ok = [0.1, -0.2, 0.0];
        assert_eq!(check(&ok, 0.01), Ok(()));
        assert_eq!(check(&ok, MIN_DT_S), Ok(()));
        assert_eq!(check(&ok, MAX_DT_S), Ok(()));
        // The limit to rounding (the mean step of 642 times printed from 0.1
        // by 0.1 s is 0.1 and an ulp).
        assert_eq!((64.2 - 0.1) / 641.0, MAX_DT_S.next_up());
        assert_eq!(check(&ok, MAX_DT_S.next_up()), Ok(()));
        assert_eq!(check(&[0.0, MAX_ACCEL_G], 0.01), Ok(()));
        for (accel, dt, says) in [
            (&[0.1][..], 0.01, "1 sample(s)"),
            (&ok[..], 0.0, "a time step of 0e0 s"),
            (&ok[..], 2.0 * MAX_DT_S, "a time step of 2e-1 s"),
            (&ok[..], 1.0, "a time step of 1e0 s"),
            (&ok[..], 0.5 * MIN_DT_S, "a time step of 5e-6 s"),
            (&[0.0, -10.5][..], 0.01, "sample 2 is -1.05e1 g, past 10 g"),
            (&[0.0, f64::NAN][..], 0.01, "sample 2 is NaN"),
            (&[0.0, 0.0, 0.0][..], 0.01, "every sample is 0"),
        ] {
            let e = check(accel, dt).unwrap_err();
            assert!(e.starts_with(says), "{e}");
        }
    }

    #[test]
    fn peak_takes_the_first_largest_absolute_sample() {
        let p = peak(&[0.1, -0.5, 0.3, 0.5, -0.2], 0.02).unwrap();
        assert_eq!(
            p,
            Peak {
                pga_g: 0.5,
                index: 1,
                time_s: 0.02
            }
        );
        assert_eq!(peak(&[], 0.01), None);
        assert_eq!(peak(&[0.0, 0.0], 0.01).unwrap().index, 0);
    }

    #[test]
    fn duration_counts_intervals_not_samples() {
        assert_eq!(duration_s(2999, 0.01), 2998.0 * 0.01);
        assert_eq!(duration_s(1, 0.01), 0.0);
    }
}
