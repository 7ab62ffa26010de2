//! The assessment: the hazard read, each block's fragility built, the
//! integral at each site.

use std::path::Path;

use super::answer::{Assessment, BinInfo, BlockInfo, FragilityInfo, SiteInfo};
use super::error::RiskError;
use super::inventory::{entries, InventoryBlock};
use super::request::{Hazard, Request};
use crate::block::{Block, Restitution};
use crate::hazard::{self, HazardCurve};
use crate::im::Im;
use crate::label::Label;
use crate::ops::fragility::{self, DirectRecords, FragilityError, Laws};
use crate::ops::im_fragility::ImTable;
use crate::risk::{self, Fragility, SiteRisk};
use crate::stats;

/// Reads the hazard file: the curves of the sites asked, with their indices.
pub fn read_hazard(
    hazard: &Hazard,
    site: Option<usize>,
) -> Result<Vec<(usize, HazardCurve)>, RiskError> {
    let curves = match hazard {
        Hazard::File(path) => {
            let text = std::fs::read_to_string(path).map_err(|source| RiskError::Read {
                path: path.into(),
                source,
            })?;
            hazard::parse(&text).map_err(|error| RiskError::Hazard {
                path: path.into(),
                error,
            })?
        }
        Hazard::Curve(curve) => vec![curve.clone()],
    };
    let path = hazard.name();
    let path = path.as_path();
    let n = curves.len();
    let chosen: Vec<(usize, HazardCurve)> = match site {
        Some(k) if k >= n => {
            return Err(RiskError::NoSuchSite {
                path: path.into(),
                site: k,
                sites: n,
            })
        }
        Some(k) => vec![(k, curves[k].clone())],
        None => curves.into_iter().enumerate().collect(),
    };
    if let Some((k, c)) = chosen.iter().find(|(_, c)| c.iml.len() < 2) {
        return Err(RiskError::OnePoint {
            path: path.into(),
            site: *k,
            iml: c.iml[0],
        });
    }
    Ok(chosen)
}

/// The fragility of a block in terms of `im`, and how to describe it.
fn fragility_of(
    block: &Block,
    laws: &Laws,
    table: Option<&ImTable>,
    im: Im,
    direct: Option<&DirectRecords>,
    auto_tol: f64,
) -> Result<(Fragility, FragilityInfo), FragilityError> {
    let alpha = block.alpha();
    let (name, unit) = (im.name(), im.unit());
    match (direct, table) {
        (None, Some(table)) => {
            let l = table.capacity(block)?;
            Ok((
                Fragility::Lognormal {
                    median: l.median,
                    beta: l.beta,
                },
                FragilityInfo {
                    source: laws.name.clone(),
                    kind: "lognormal",
                    im: name,
                    unit,
                    median: Some(l.median),
                    beta: Some(l.beta),
                    records: None,
                },
            ))
        }
        (None, None) => {
            let (eta50, beta) = laws.median_beta(block)?;
            // η = α/PGA: P(OT | PGA) = Φ((ln PGA − ln(α/η50))/β).
            let median = alpha / eta50;
            Ok((
                Fragility::Lognormal { median, beta },
                FragilityInfo {
                    source: laws.name.clone(),
                    kind: "lognormal",
                    im: name,
                    unit,
                    median: Some(median),
                    beta: Some(beta),
                    records: None,
                },
            ))
        }
        (Some(records), _) => {
            // The level at which each record overturns the block; never: ∞.
            let (thresholds, _) = records.thresholds(block, im, auto_tol)?;
            let q = |q: f64| {
                stats::fractile(&thresholds, q, crate::stats::FractileDef::Type7)
                    .filter(|v| v.is_finite())
            };
            let beta = match (q(0.16), q(0.84)) {
                (Some(a), Some(b)) => Some(0.5 * (b.ln() - a.ln())),
                _ => None,
            };
            Ok((
                Fragility::Empirical {
                    thresholds: thresholds.clone(),
                },
                FragilityInfo {
                    source: "direct".into(),
                    kind: "empirical",
                    im: name,
                    unit,
                    median: q(0.5),
                    beta,
                    records: Some(thresholds.len()),
                },
            ))
        }
    }
}

fn site_info(k: usize, curve: &HazardCurve, r: &SiteRisk, years: f64) -> SiteInfo {
    SiteInfo {
        site: k,
        lon: curve.lon,
        lat: curve.lat,
        annual_rate: r.annual_rate,
        return_period_years: (r.annual_rate > 0.0).then(|| 1.0 / r.annual_rate),
        p_overturn_in_years: risk::probability_in(r.annual_rate, years),
        first_iml: r.first_iml,
        last_iml: r.last_iml,
        fragility_at_first_iml: r.fragility_at_first_iml,
        imls_dropped: curve.dropped_below,
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

/// What an assessment reads before its first block: the request checked,
/// the sites' hazard curves and their IM, the blocks asked, and the
/// capacities (the study's laws, or the records for `--direct`).
pub(super) struct Prepared {
    pub sites: Vec<(usize, HazardCurve)>,
    pub im: Im,
    pub entries: Vec<InventoryBlock>,
    pub laws: Laws,
    pub records: Option<DirectRecords>,
}

/// [`Prepared`] for `req`, for [`assess`] and `states::assess_states`.
pub(super) fn prepare(req: &Request) -> Result<Prepared, RiskError> {
    if !(req.years > 0.0 && req.years.is_finite()) {
        return Err(RiskError::Years(req.years));
    }
    crate::physics::check_auto_tol(req.auto_tol).map_err(RiskError::AutoTol)?;
    let sites = read_hazard(&req.hazard, req.site)?;
    let entries = entries(&req.blocks)?;
    let im = hazard_im(&req.hazard.name(), &sites, req.im)?;
    let (laws, records) = fragility::laws_and_records(
        &req.from,
        req.direct,
        &req.progress,
        entries.len(),
        req.floor.as_ref(),
    )?;
    Ok(Prepared {
        sites,
        im,
        entries,
        laws,
        records,
    })
}

/// Assesses every block asked at every site asked.
pub fn assess(req: &Request) -> Result<Vec<Assessment>, RiskError> {
    let Prepared {
        sites,
        im,
        entries,
        laws,
        records,
    } = prepare(req)?;
    // Another IM than PGA without --direct: the study's table, read once.
    let table = if im != Im::Pga && !req.direct {
        Some(laws.im_table(im)?)
    } else {
        None
    };
    let mut out = Vec::with_capacity(entries.len());
    for e in &entries {
        let in_block = |source| RiskError::Block {
            name: e.name.clone(),
            source,
        };
        let block = fragility::block(e.b_m, e.h_m, e.eps).map_err(in_block)?;
        let (frag, info) = fragility_of(
            &block,
            &laws,
            table.as_ref(),
            im,
            records.as_ref(),
            req.auto_tol,
        )
        .map_err(in_block)?;
        let site_infos: Vec<SiteInfo> = sites
            .iter()
            .map(|(k, c)| site_info(*k, c, &risk::assess(c, &frag, req.beyond), req.years))
            .collect();
        let mut warnings = match (req.direct, im) {
            (true, _) => Vec::new(),
            (false, Im::Pga) => fragility::warnings(&block, req.auto_tol),
            // A study's IM table: its α warning; the grid's are the table's own.
            (false, _) => fragility::alpha_warning(&block, req.auto_tol)
                .into_iter()
                .collect(),
        };
        warnings.extend(extrapolated(&site_infos));
        let assessed = block_info(e, &block, records.as_ref().and_then(|r| r.floor()));
        warnings.extend(sliding_warning(&assessed));
        out.push(Assessment {
            block: assessed,
            fragility: info,
            years: req.years,
            beyond: req.beyond.label(),
            sites: site_infos,
            warnings,
        });
    }
    Ok(out)
}

/// A block as assessed: its geometry, and whether it slides first.
pub(super) fn block_info(
    e: &InventoryBlock,
    block: &Block,
    floor: Option<&crate::floor::Building>,
) -> BlockInfo {
    BlockInfo {
        name: e.name.clone(),
        b_m: e.b_m,
        h_m: e.h_m,
        alpha_rad: block.alpha(),
        p: block.p(),
        eps: block.eps,
        eps_housner: e.eps == Restitution::Housner,
        mu: e.mu,
        slides_first: e.mu.map(|mu| crate::block::slides_first(mu, block.alpha())),
        floor: floor.map(|b| b.to_string()),
    }
}

/// The warning of a block that slides before it rocks.
pub(super) fn sliding_warning(b: &BlockInfo) -> Option<String> {
    match (b.mu, b.slides_first) {
        (Some(mu), Some(true)) => Some(crate::block::sliding_warning(mu, b.alpha_rad)),
        _ => None,
    }
}

/// The hazard's IM, the same at every site, and the fragility's when it is
/// asked for: they must agree.
pub fn hazard_im(
    path: &Path,
    sites: &[(usize, HazardCurve)],
    asked: Option<Im>,
) -> Result<Im, RiskError> {
    let im = sites.first().map_or(Im::Pga, |(_, c)| c.im);
    match asked {
        Some(a) if a != im => Err(RiskError::ImMismatch {
            path: path.into(),
            hazard: im.name(),
            unit: im.unit(),
            asked: a.name(),
        }),
        _ => Ok(im),
    }
}

/// Sites whose rate comes mostly (over half) from beyond the hazard
/// curve's last IML, where the curve's last slope is extrapolated: the
/// answer is then more the extrapolation's than the hazard model's.
fn extrapolated(sites: &[SiteInfo]) -> Vec<String> {
    sites
        .iter()
        .filter(|s| s.share_beyond_last_iml > 0.5)
        .map(|s| {
            format!(
                "site {}: {:.0} % of the rate comes from beyond the hazard curve's last IML \
                 ({} g), where its last slope is extrapolated; the rate and return period are \
                 an extrapolation (compare --beyond stop)",
                s.site,
                100.0 * s.share_beyond_last_iml,
                s.last_iml
            )
        })
        .collect()
}
