//! `rocking risk`: the annual rate of overturning of a block (or of every
//! block of an inventory) at the sites of a hazard file, with its
//! deaggregation by PGA. The integral is [`crate::risk`]'s; this module reads
//! the files, builds each block's fragility (the paper's regression, a
//! pipeline's fit, or `--direct` capacities under the records), says where
//! the regression is stretched, and writes the table and the figures.

mod charts;
mod inventory;
mod states;

pub use charts::{deaggregation_chart, ranking_chart};
use inventory::entries;
pub use inventory::{read_inventory, InventoryBlock};
pub use states::{assess_states, StateRisk, StatesAssessment, StatesSite};

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::fragility::{self, DirectRecords, FragilityError, Laws, Source};
use super::im_fragility::ImTable;
use crate::block::{Block, Restitution};
use crate::hazard::{self, HazardCurve, HazardError};
use crate::im::Im;
use crate::label::Label;
use crate::plot::PlotError;
use crate::risk::{self, Beyond, Fragility, SiteRisk};
use crate::stats;
use crate::tables::risk::RiskRow;
use crate::tables::{self, TableError};

/// The blocks to assess.
#[derive(Debug, Clone)]
pub enum Blocks {
    /// One block: half-width, half-height (m), ε.
    One {
        b_m: f64,
        h_m: f64,
        eps: Restitution,
        /// The base's friction coefficient, when given.
        mu: Option<f64>,
    },
    /// A CSV `name,b,h[,eps]`.
    Inventory(PathBuf),
}

/// What the user asks.
#[derive(Debug, Clone)]
pub struct Request {
    pub hazard: PathBuf,
    /// One site of the file (index from 0); all when `None`.
    pub site: Option<usize>,
    pub blocks: Blocks,
    pub from: Source,
    /// The fragility's IM; `None`: the hazard's.
    pub im: Option<Im>,
    pub direct: bool,
    /// Where `--direct` reports its progress.
    pub progress: fragility::DirectProgress,
    /// For the probability of overturning within this many years.
    pub years: f64,
    pub beyond: Beyond,
    /// The linearised model's accepted error in η_c, for the α warning.
    pub auto_tol: f64,
    /// The building whose floor the blocks stand on (`--direct` only).
    pub floor: Option<crate::floor::Building>,
}

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
    /// With `mu`: whether the block slides before it rocks (μ < b/h).
    pub slides_first: Option<bool>,
    /// On a floor: the building's modes (`T,ζ,Γφ; …`).
    pub floor: Option<String>,
}

/// A block's fragility, as used.
#[derive(Debug, Clone, Serialize)]
pub struct FragilityInfo {
    /// `paper`, the pipeline file, or `direct`.
    pub source: String,
    /// `lognormal` (from a regression or a study's IM table) or
    /// `empirical` (records, `--direct`).
    pub kind: &'static str,
    /// The IM of the fragility and of the hazard, and its unit.
    pub im: String,
    pub unit: &'static str,
    /// The IM level (in `unit`) at which P(OT) = 0.5; `None` when more than
    /// half the records never overturn the block.
    pub median: Option<f64>,
    pub beta: Option<f64>,
    /// Records run, with `--direct`.
    pub records: Option<usize>,
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
    pub annual_rate: f64,
    /// `None` when the rate is 0.
    pub return_period_years: Option<f64>,
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

#[derive(Debug, thiserror::Error)]
pub enum RiskError {
    #[error(
        "{path} is a hazard in {hazard} ({unit}), and the fragility asked for is in {asked}: \
         give --im {hazard}, or the hazard curves of {asked}",
        path = .path.display()
    )]
    ImMismatch {
        path: PathBuf,
        hazard: String,
        unit: &'static str,
        asked: String,
    },
    #[error("{path}: cannot read")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}:{}: {}", .error.line.map_or("?".to_string(), |l| l.to_string()), .error.message)]
    Hazard { path: PathBuf, error: HazardError },
    #[error("{path}: site {site} has only one IML with a finite, positive rate ({iml} g); the integral needs two")]
    OnePoint {
        path: PathBuf,
        site: usize,
        iml: f64,
    },
    #[error("--site {site}: {path} has {sites} site(s), numbered from 0")]
    NoSuchSite {
        path: PathBuf,
        site: usize,
        sites: usize,
    },
    #[error("--years {0}: give a positive number of years")]
    Years(f64),
    #[error("--auto-tol: {0}")]
    AutoTol(String),
    #[error("{path}:{line}: {message}")]
    Inventory {
        path: PathBuf,
        line: u64,
        message: String,
    },
    #[error("block `{name}`")]
    Block {
        name: String,
        #[source]
        source: FragilityError,
    },
    #[error(transparent)]
    Fragility(#[from] FragilityError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// Reads the hazard file: the curves of the sites asked, with their indices.
pub fn read_hazard(
    path: &Path,
    site: Option<usize>,
) -> Result<Vec<(usize, HazardCurve)>, RiskError> {
    let text = std::fs::read_to_string(path).map_err(|source| RiskError::Read {
        path: path.into(),
        source,
    })?;
    let curves = hazard::parse(&text).map_err(|error| RiskError::Hazard {
        path: path.into(),
        error,
    })?;
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
    let im = hazard_im(&req.hazard, &sites, req.im)?;
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
                floor: a.block.floor.clone(),
                site: s.site as i64,
                lon: s.lon,
                lat: s.lat,
                fragility: a.fragility.source.clone(),
                im: a.fragility.im.clone(),
                unit: a.fragility.unit.to_string(),
                median: a.fragility.median,
                beta: a.fragility.beta,
                annual_rate: s.annual_rate,
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
