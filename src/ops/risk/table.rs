//! `risk.parquet`: one row per block × site.

use std::path::Path;

use super::answer::Assessment;
use super::error::RiskError;
use crate::risk::Beyond;
use crate::tables::risk::RiskRow;
use crate::tables::{self};

/// The rows of `risk.parquet`: one per block × site.
pub fn rows(assessments: &[Assessment], beyond: Beyond) -> Vec<RiskRow> {
    assessments
        .iter()
        .flat_map(|a| {
            a.sites.iter().map(move |s| RiskRow {
                block: a.block.name.clone(),
                b_m: a.block.b_m,
                h_m: a.block.h_m,
                alpha_rad: a.block.alpha_rad,
                p: a.block.p,
                eps: a.block.eps,
                eps_housner: a.block.eps_housner,
                mu: a.block.mu,
                slides_first: a.block.slides_first == Some(true),
                model: a.fragility.equation.map(str::to_string),
                floor: a.block.floor.clone(),
                site: s.site as i64,
                lon: s.lon,
                lat: s.lat,
                fragility: a.fragility.source.clone(),
                fit: a.fragility.fit.to_string(),
                im: a.fragility.im.clone(),
                unit: a.fragility.unit.to_string(),
                median: a.fragility.median,
                // None for the records' own curve ([`StateFragility::median_beta`]).
                beta: a.fragility.beta,
                annual_rate: s.annual_rate,
                annual_rate_lo: s.annual_rate_band.map(|b| b[0]),
                annual_rate_hi: s.annual_rate_band.map(|b| b[1]),
                return_period_years: s.return_period_years,
                years: a.years,
                p_overturn_in_years: s.p_overturn_in_years,
                first_iml: s.first_iml,
                last_iml: s.last_iml,
                fragility_at_first_iml: s.fragility_at_first_iml,
                share_beyond_last_iml: s.share_beyond_last_iml,
                beyond,
                warnings: a.warnings.join("; "),
            })
        })
        .collect()
}

/// Writes `risk.parquet`.
pub fn write_table(dest: &Path, rows: &[RiskRow], hazard: &Path) -> Result<(), RiskError> {
    Ok(tables::write(
        dest,
        rows,
        &[("rocking.risk.hazard".into(), hazard.display().to_string())],
    )?)
}
