//! What `risk` answers: each block at each site, with its fragility and
//! deaggregation.

use serde::Serialize;

use crate::hazard::HazardCurve;
use crate::risk::{self, SiteRisk};

/// A block as assessed.
#[derive(Debug, Clone, Serialize)]
pub struct BlockInfo {
    pub name: String,
    pub b_m: f64,
    pub h_m: f64,
    pub alpha_rad: f64,
    pub p: f64,
    pub eps: f64,
    pub eps_housner: bool,
    /// The base's friction coefficient, when given.
    pub mu: Option<f64>,
    /// With `mu`: whether the block slides before it rocks (μ ≤ b/h).
    pub slides_first: Option<bool>,
    /// On a floor: the building's modes (`T,ζ,Γφ; …`).
    pub floor: Option<String>,
}

/// A block's fragility, as used.
#[derive(Debug, Clone, Serialize)]
pub struct FragilityInfo {
    /// `paper`, the pipeline file, or `direct`.
    pub source: String,
    /// How it is made: `fractile`, `mle` (lognormals of the records'
    /// capacities or a study's damage table), `regression` (the paper's or a
    /// study's, PGA), `moments` (a study's IM table) or `empirical` (the
    /// records' curve, `--method empirical`).
    pub fit: &'static str,
    /// The IM of the fragility and of the hazard, and its unit.
    pub im: String,
    pub unit: &'static str,
    /// The IM level (in `unit`) at which P(OT) = 0.5; `None` when more than
    /// half the records never overturn the block.
    pub median: Option<f64>,
    pub beta: Option<f64>,
    /// With `--direct`: Lilliefors' p of the logarithms of the records'
    /// capacities (below 0.05 a lognormal does not fit them).
    pub lognormal_p: Option<f64>,
    /// Records run, with `--direct`.
    pub records: Option<usize>,
    /// With `--direct`: the records folder (or pipeline) they came from.
    pub records_folder: Option<String>,
    /// With `--direct`: the equation the records ran (`linearized`,
    /// `nonlinear`, `slide-rock`: `auto` runs a block with μ on its
    /// friction), and why.
    pub equation: Option<&'static str>,
    pub model: Option<String>,
    /// With `--tree`: each branch's fragility, the mixture's median and
    /// equivalent β, the dispersion split; with several branches `fit` is
    /// `mixture` and `median`, `beta` the mixture's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tree: Option<crate::ops::tree::TreeInfo>,
    /// With `--bootstrap`: the resamples and the bands of the median and β.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bootstrap: Option<super::BootstrapInfo>,
}

/// One branch's rate at a site.
#[derive(Debug, Clone, Serialize)]
pub struct BranchRate {
    pub branch: String,
    pub weight: f64,
    pub annual_rate: f64,
}

/// One range of the IM in the deaggregation.
#[derive(Debug, Clone, Serialize)]
pub struct BinInfo {
    pub iml_from: f64,
    /// `None`: extrapolated without end.
    pub iml_to: Option<f64>,
    pub annual_rate: f64,
    pub share: f64,
}

/// The result at one site.
#[derive(Debug, Clone, Serialize)]
pub struct SiteInfo {
    /// Index in the hazard file, from 0.
    pub site: usize,
    pub lon: Option<f64>,
    pub lat: Option<f64>,
    /// λ (1/year); with a tree, the mean over its branches.
    pub annual_rate: f64,
    /// The weighted mean of the branches' rates (1/year): `annual_rate`,
    /// and the plain rate without a tree.
    pub mean_annual_rate: f64,
    /// With a tree: each branch's rate.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub branches: Vec<BranchRate>,
    /// With a tree: the branches' rates' weighted quantiles at
    /// `fragility.tree.quantiles` (1/year).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quantile_annual_rates: Option<Vec<f64>>,
    /// With `--bootstrap`: the rate's band from the records (1/year), at
    /// `fragility.bootstrap.level` (5 and 95 % of the resamples' rates).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub annual_rate_band: Option<[f64; 2]>,
    /// `None` when the rate is 0.
    pub return_period_years: Option<f64>,
    /// P(overturn within `years`) = 1 − e^(−λ·years); with a tree the
    /// branches' weighted mean of theirs.
    pub p_overturn_in_years: f64,
    pub first_iml: f64,
    pub last_iml: f64,
    /// P(OT | first IML): overturning probability below where the curve starts.
    pub fragility_at_first_iml: f64,
    /// IMLs dropped at the start because their probability of exceedance is 1.
    pub imls_dropped: usize,
    pub share_beyond_last_iml: f64,
    pub deaggregation: Vec<BinInfo>,
}

/// One block at every site asked.
#[derive(Debug, Clone, Serialize)]
pub struct Assessment {
    pub block: BlockInfo,
    pub fragility: FragilityInfo,
    pub years: f64,
    pub beyond: &'static str,
    pub sites: Vec<SiteInfo>,
    /// Where the regression is stretched for this block.
    pub warnings: Vec<String>,
}

/// What a site's answer says of its risk.
pub(super) fn site_info(k: usize, curve: &HazardCurve, r: &SiteRisk, years: f64) -> SiteInfo {
    SiteInfo {
        site: k,
        lon: curve.lon,
        lat: curve.lat,
        annual_rate: r.annual_rate,
        mean_annual_rate: r.annual_rate,
        branches: Vec::new(),
        quantile_annual_rates: None,
        annual_rate_band: None,
        return_period_years: (r.annual_rate > 0.0).then(|| 1.0 / r.annual_rate),
        p_overturn_in_years: risk::probability_in(r.annual_rate, years),
        first_iml: r.first_iml,
        last_iml: r.last_iml,
        fragility_at_first_iml: r.fragility_at_first_iml,
        imls_dropped: curve.infinite.len(),
        share_beyond_last_iml: r.share_beyond_last_iml,
        deaggregation: r
            .bins
            .iter()
            .map(|b| BinInfo {
                iml_from: b.iml_from,
                iml_to: b.iml_to,
                annual_rate: b.annual_rate,
                share: if r.annual_rate > 0.0 {
                    b.annual_rate / r.annual_rate
                } else {
                    0.0
                },
            })
            .collect(),
    }
}
