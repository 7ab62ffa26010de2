//! The charts of `rocking risk`: a block's deaggregation at a site, and an
//! inventory ranked by its annual rate.

use super::answer::{Assessment, BinInfo, SiteInfo};
use super::error::RiskError;
use crate::im::level_text;
use crate::plot::{self, Bars, Scale};

impl BinInfo {
    /// The bin's range of IM levels in `unit`, as the text and the chart say it.
    pub fn range_text(&self, unit: &str) -> String {
        let from = level_text(self.iml_from);
        match self.iml_to {
            Some(to) if to > self.iml_from => format!("{from}–{} {unit}", level_text(to)),
            Some(_) => format!("> {from} {unit} (not counted)"),
            None => format!("> {from} {unit} (extrapolated)"),
        }
    }
}

/// The deaggregation of one block at one site as a bar chart (SVG).
pub fn deaggregation_chart(a: &Assessment, site: &SiteInfo) -> Result<String, RiskError> {
    let bars = site
        .deaggregation
        .iter()
        .map(|b| (b.range_text(a.fragility.unit), 100.0 * b.share))
        .collect();
    Ok(plot::render_bars(&Bars {
        title: format!(
            "Deaggregation of the overturning rate of {} at site {} (λ = {:.2e}/yr)",
            a.block.name, site.site, site.annual_rate
        ),
        x_desc: "share of the annual rate of overturning (%)".into(),
        x_scale: Scale::Linear,
        bars,
    })?)
}

/// The blocks ranked by their annual rate at `site` (SVG).
pub fn ranking_chart(assessments: &[Assessment], site: usize) -> Result<String, RiskError> {
    let mut bars: Vec<(String, f64)> = assessments
        .iter()
        .filter_map(|a| {
            a.sites
                .iter()
                .find(|s| s.site == site)
                .map(|s| (a.block.name.clone(), s.annual_rate))
        })
        .collect();
    bars.sort_by(|a, b| b.1.total_cmp(&a.1));
    // A log axis shows no rate of 0; where every block's is 0 (blocks that
    // slide and never overturn) a linear one shows them all at 0.
    let x_scale = match bars.iter().any(|b| b.1 > 0.0) {
        true => Scale::Log,
        false => Scale::Linear,
    };
    Ok(plot::render_bars(&Bars {
        title: format!("Blocks ranked by their annual rate of overturning, site {site}"),
        x_desc: "annual rate of overturning (1/year)".into(),
        x_scale,
        bars,
    })?)
}
