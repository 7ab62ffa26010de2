//! `risk --bootstrap N`: how sure the rate is from the records themselves.
//! The records are resampled by their pairs (as the study's bands
//! resample), each resample's fragility fitted as the whole sample's is
//! ([`damage::resampled`]), and its rate at every site integrated; the
//! band is the percentile band of the resamples' rates (with a tree, of
//! their mean over the branches, every branch seeing the same records).

use serde::Serialize;

use crate::hazard::HazardCurve;
use crate::ops::damage::{self, DamageFragility, StateFragility};
use crate::risk::{self, Beyond, Fragility};
use crate::stats::{self, ResampleUnit, SplitMix64, Units};
use crate::tree::Mixture;

/// The level of the bands: 90 % (the 5 and 95 % percentiles).
pub const BAND_LEVEL: f64 = 0.90;

/// What is asked: how many resamples, and the generator's seed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bootstrap {
    pub resamples: usize,
    pub seed: u64,
}

/// What the answer says of its bootstrap.
#[derive(Debug, Clone, Serialize)]
pub struct BootstrapInfo {
    pub resamples: usize,
    /// Resamples with a fit in every branch (a resample where more than
    /// 16 % of its records never overturn the block has no fractile fit);
    /// the bands are of these.
    pub fitted: usize,
    pub seed: u64,
    /// `pair` (the records' pairs, by their manifest) or `record`.
    pub unit: &'static str,
    pub level: f64,
    /// The band of the fragility's median (in the IM's unit) and of its β
    /// (with a tree, the mixture's and its equivalent β).
    pub median_band: Option<[f64; 2]>,
    pub beta_band: Option<[f64; 2]>,
}

/// One branch as resampled: its weight, fragility and the level below
/// which it is 0.
pub(super) struct Resampled<'a> {
    pub weight: f64,
    pub fragility: &'a DamageFragility,
    pub cut: f64,
}

/// The resamples: `resamples` draws of the units, each the records'
/// indices, from `SplitMix64::new(seed)` in order ([`Units::draw`]).
pub fn draws(units: &[usize], b: Bootstrap) -> Vec<Vec<usize>> {
    let units = Units::new(units);
    let mut rng = SplitMix64::new(b.seed);
    (0..b.resamples)
        .map(|_| {
            let mut d = Vec::new();
            units.draw(&mut rng, &mut d);
            d
        })
        .collect()
}

/// The bootstrap's answer and each site's band of the rate (1/year).
pub(super) fn bands(
    b: Bootstrap,
    (units, unit): (Vec<usize>, ResampleUnit),
    branches: &[Resampled],
    sites: &[(usize, HazardCurve)],
    beyond: Beyond,
) -> (BootstrapInfo, Vec<Option<[f64; 2]>>) {
    let mut rates: Vec<Vec<f64>> = vec![Vec::new(); sites.len()];
    let (mut medians, mut betas) = (Vec::new(), Vec::new());
    for draw in draws(&units, b) {
        let states: Option<Vec<StateFragility>> = branches
            .iter()
            .map(|r| damage::resampled(r.fragility, 0, &draw))
            .collect();
        let Some(states) = states else { continue };
        let fits: Vec<(f64, Fragility)> = states
            .iter()
            .zip(branches)
            .map(|(s, r)| {
                (
                    r.weight,
                    s.fragility(r.fragility.method).expect("resampled fits"),
                )
            })
            .collect();
        for (s, (_, curve)) in sites.iter().enumerate() {
            let rate: f64 = fits
                .iter()
                .zip(branches)
                .map(|((w, f), r)| w * risk::assess_above(curve, f, beyond, r.cut).annual_rate)
                .sum();
            rates[s].push(rate);
        }
        // One branch: its median and β as the answer reads them (for the
        // records' curve, its 50 % level and no β); a tree: the mixture's.
        let (m, beta) = match (&states[..], branches) {
            ([s], [r]) => s.median_beta(r.fragility.method),
            _ => Mixture {
                parts: &fits,
                below: &[],
            }
            .median_beta(),
        };
        medians.extend(m);
        betas.extend(beta);
    }
    let fitted = rates.first().map_or(0, Vec::len);
    let band = |v: &mut Vec<f64>| stats::percentile_band(v, BAND_LEVEL).map(|(lo, hi)| [lo, hi]);
    let info = BootstrapInfo {
        resamples: b.resamples,
        fitted,
        seed: b.seed,
        unit: crate::label::Label::label(unit),
        level: BAND_LEVEL,
        median_band: (medians.len() == fitted)
            .then(|| band(&mut medians))
            .flatten(),
        beta_band: (betas.len() == fitted).then(|| band(&mut betas)).flatten(),
    };
    (info, rates.iter_mut().map(band).collect())
}
