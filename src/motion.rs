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
/// every 0.001–0.05 s; 1 s resolves nothing a block responds to.
pub const MAX_DT_S: f64 = 1.0;

/// The finest sampling accepted (s): a hundred times finer than any
/// strong-motion record's; below it a header's DT is wrong, and would
/// stretch the record's seconds by as much.
pub const MIN_DT_S: f64 = 1e-5;

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
