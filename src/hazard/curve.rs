//! One site's hazard curve, as the parsers make it.

use crate::im::Im;

/// One site's hazard curve: annual rates of exceedance of an IM.
#[derive(Debug, Clone, PartialEq)]
pub struct HazardCurve {
    /// The IM the levels are of (in its unit, [`Im::unit`]).
    pub im: Im,
    pub lon: Option<f64>,
    pub lat: Option<f64>,
    /// IMLs, increasing, each with a finite positive rate.
    pub iml: Vec<f64>,
    /// Annual rate of exceedance at each IML, non-increasing.
    pub annual_rate: Vec<f64>,
    /// The IML at which the file gives a rate of exactly 0 (no exceedance
    /// beyond it), if it does.
    pub ends_at: Option<f64>,
    /// The IMLs dropped from the start because their rate is infinite
    /// (poe = 1), increasing.
    pub infinite: Vec<f64>,
    /// OpenQuake's statistic of the curve (its `kind=`: `mean`,
    /// `quantile-0.84`, `rlz-003`, …); `None` for a plain CSV.
    pub kind: Option<String>,
}
