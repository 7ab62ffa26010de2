//! The assessment: the hazard read, each block's fragility built, the
//! integral at each site.

use std::path::Path;

use super::answer::{site_info, Assessment, BlockInfo, FragilityInfo, SiteInfo};
use super::error::RiskError;
use super::inventory::{entries, InventoryBlock};
use super::request::{Hazard, Request};
use crate::block::{Block, Restitution};
use crate::damage::{DamageStates, Dispersion, FitChoice};
use crate::hazard::{self, HazardCurve};
use crate::im::Im;
use crate::label::Label;
use crate::ops::damage;
use crate::ops::fragility::{self, DirectRecords, FragilityError, Laws, RunModel};
use crate::risk::{self, Fragility};

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
        Hazard::Events(e) => {
            return Err(RiskError::Gmf(format!(
                "{}: ground-motion fields, not hazard curves: their risk is `assess_events`'s",
                e.dir.display()
            )))
        }
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

/// The fragility of a block in terms of `im` (the block's one fragility,
/// [`damage::of_block`], by `method`), how to describe it, and the
/// regression's warnings for it.
fn fragility_of(
    block: &Block,
    laws: &Laws,
    im: Im,
    direct: Option<&DirectRecords>,
    model: RunModel,
    fit: FitChoice,
) -> Result<(Fragility, FragilityInfo, damage::DamageFragility), FragilityError> {
    let f = damage::of_block(
        block,
        &DamageStates::overturning(),
        im,
        laws,
        direct,
        model,
        fit,
    )?;
    let (fragility, info) = stated(&f, im)?;
    Ok((fragility, info, f))
}

/// The overturning fragility of `f` (its one state, by its method) and
/// what the answers say of it.
pub(super) fn stated(
    f: &damage::DamageFragility,
    im: Im,
) -> Result<(Fragility, FragilityInfo), FragilityError> {
    let method = f.method;
    let state = &f.states[0];
    let fragility = state
        .fragility(method)
        .ok_or_else(|| damage::no_fit(f, state, method))?;
    let (median, beta) = state.median_beta(method);
    let info = FragilityInfo {
        source: f.source.clone(),
        fit: state.fit_name(method),
        im: im.name(),
        unit: im.unit(),
        median,
        beta,
        lognormal_p: state.lognormal_p,
        records: f.records,
        records_folder: f.records_folder.clone(),
        equation: f.equation,
        model: f.model.clone(),
        tree: None,
        bootstrap: None,
    };
    Ok((fragility, info))
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
    /// Of the hazard file, for every block ([`hazard_warnings`]).
    pub warnings: Vec<String>,
}

/// Where a hazard's curves look like another unit than their IM's, are
/// in AvgSA, whose periods a file does not state, or are not the mean
/// hazard ([`crate::hazard::statistic_note`]).
pub fn hazard_warnings(sites: &[(usize, HazardCurve)]) -> Vec<String> {
    let mut out: Vec<String> = sites
        .iter()
        .filter_map(|(k, c)| {
            crate::hazard::plausibility(c).map(|w| match sites.len() {
                1 => w,
                _ => format!("site {k}: {w}"),
            })
        })
        .collect();
    // One AvgSA note for the file, not one per site.
    if out.len() > 1 && out.iter().all(|w| w.contains("AvgSA: a hazard file")) {
        let first = out[0]
            .split_once(": ")
            .map_or(out[0].clone(), |(_, w)| w.to_string());
        out = vec![first];
    }
    // One file, one statistic: said once.
    out.extend(
        sites
            .first()
            .and_then(|(_, c)| crate::hazard::statistic_note(c)),
    );
    out
}

/// [`Prepared`] for `req`, for [`assess`] and `states::assess_states`.
pub(super) fn prepare(req: &Request) -> Result<Prepared, RiskError> {
    super::check_years(req.years)?;
    crate::physics::check_auto_tol(req.auto_tol).map_err(RiskError::AutoTol)?;
    let sites = read_hazard(&req.hazard, req.site)?;
    let entries = entries(&req.blocks)?;
    let im = hazard_im(&req.hazard.name(), &sites, req.im)?;
    let (im, component_warning) = in_component(im, req)?;
    let (laws, records) = fragility::laws_and_records(
        &req.from,
        req.direct,
        &req.progress,
        entries.len() * req.tree.as_ref().map_or(1, |t| t.paths().len()),
        req.floor.as_ref(),
        fragility::Orient {
            pair_im: im.pair(),
            ..req.orient
        },
    )?;
    let mut warnings = hazard_warnings(&sites);
    warnings.extend(component_warning);
    if req.orient.orientation != crate::pair::Orientation::AsRecorded && !im.pair() {
        if let Some(r) = im.rotd50() {
            warnings.push(format!(
                "the fragility is over the block's orientations but in the rotated component's \
                 own {}, while a hazard from ground-motion models (NGA-West2 and after) is in \
                 RotD50: give --im {} to state it in the hazard's component",
                im.short(),
                r.name()
            ));
        }
    }
    Ok(Prepared {
        warnings,
        sites,
        im,
        entries,
        laws,
        records,
    })
}

/// Assesses every block asked at every site asked.
pub fn assess(req: &Request) -> Result<Vec<Assessment>, RiskError> {
    let p = prepare(req)?;
    p.entries.iter().map(|e| assess_block(req, &p, e)).collect()
}

/// One block at every site: its fragility (each branch's with a tree),
/// its rates, and with `--bootstrap` their bands.
fn assess_block(req: &Request, p: &Prepared, e: &InventoryBlock) -> Result<Assessment, RiskError> {
    let (sites, im, records) = (&p.sites, p.im, p.records.as_ref());
    let in_block = |source| RiskError::Block {
        name: e.name.clone(),
        source,
    };
    let block = fragility::block(e.b_m, e.h_m, e.eps).map_err(in_block)?;
    let floor = records.and_then(|r| r.floor());
    let fit = FitChoice {
        dispersion: Dispersion::Each,
        ..req.fit()
    };
    // Each path of the tree (one without), its block and its runs' model.
    let paths = match &req.tree {
        Some(tree) => tree.paths(),
        None => vec![crate::tree::TreePath::plain()],
    };
    let mut branches = Vec::with_capacity(paths.len());
    let base = fragility::RunModel::of_command(req.auto_tol, records);
    for path in paths {
        let (eps, model) =
            crate::ops::tree::branch(&path, e.b_m, e.h_m, e.eps, base).map_err(in_block)?;
        let b = fragility::block(e.b_m, e.h_m, eps).map_err(in_block)?;
        let model = model.on(e.mu);
        let (frag, info, whole) =
            fragility_of(&b, &p.laws, im, records, model, fit).map_err(in_block)?;
        let cut = damage::zero_below(&b, im, floor, whole.slides_on_mu).unwrap_or(0.0);
        let risks = sites
            .iter()
            .map(|(_, c)| risk::assess_above(c, &frag, req.beyond, cut))
            .collect();
        branches.push(super::tree::Branch {
            path,
            eps: b.eps,
            frag,
            info,
            warnings: whole.warnings.clone(),
            risks,
            whole,
            cut,
        });
    }
    // A branch run rocking (a tree's model branch) on a base it slides on.
    let unmodelled = branches
        .iter()
        .find_map(|b| b.whole.unmodelled_sliding(e.mu, block.alpha()));
    let resampled: Vec<super::bootstrap::Resampled> = branches
        .iter()
        .map(|b| super::bootstrap::Resampled {
            weight: b.path.weight,
            fragility: &b.whole,
            cut: b.cut,
        })
        .collect();
    let bands = match (req.bootstrap, records) {
        (Some(boot), Some(r)) => Some(super::bootstrap::bands(
            boot,
            r.units(),
            &resampled,
            sites,
            req.beyond,
        )),
        _ => None,
    };
    drop(resampled);
    let (mut info, mut warnings, mut site_infos) = match &req.tree {
        Some(tree) => super::tree::combine(tree, branches, sites, req.years),
        None => {
            let b = branches.into_iter().next().expect("one branch");
            let infos = sites
                .iter()
                .zip(&b.risks)
                .map(|((k, c), r)| site_info(*k, c, r, req.years))
                .collect();
            (b.info, b.warnings, infos)
        }
    };
    if let Some(bands) = bands {
        with_bands(bands, &mut info, &mut warnings, &mut site_infos);
    }
    warnings.extend(p.warnings.iter().cloned());
    warnings.extend(site_infos.iter().flat_map(|s| tails(s, im.unit(), None)));
    let assessed = block_info(e, &block, floor);
    warnings.extend(unmodelled);
    Ok(Assessment {
        block: assessed,
        fragility: info,
        years: req.years,
        beyond: req.beyond.label(),
        sites: site_infos,
        warnings,
    })
}

/// A block as assessed: its geometry, and whether it slides first.
/// What the answers say of a block: its sizes, groups and sliding check.
pub fn block_info(
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

/// The fragility's IM for a hazard in `im` of the component the request
/// says: RotD50 of it with `--direct` (the records' pairs give it), else
/// `im` with a warning of the mismatch.
fn in_component(im: Im, req: &Request) -> Result<(Im, Option<String>), RiskError> {
    use crate::pair::Component;
    if req.component != Some(Component::RotD50) || im.pair() {
        return Ok((im, None));
    }
    let rotd = im.rotd50().ok_or_else(|| RiskError::Component(im.name()))?;
    if req.direct {
        return Ok((rotd, None));
    }
    Ok((
        im,
        Some(format!(
            "the hazard is RotD50 (--component rotd50) and the fragility is of the recorded \
             components' {}: a mismatch in the IM's definition, which the risk integral \
             amplifies; add --direct to state the fragility in {} over the records' pairs",
            im.short(),
            rotd.short()
        )),
    ))
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
        // The hazard's measure declared RotD50 (the ground-motion models' component).
        Some(a) if im.rotd50() == Some(a) => Ok(a),
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
/// A site whose rate leans on the hazard curve's ends: more than half of it
/// from beyond the last IML (an extrapolation), or a fragility already
/// above 1 % at the first IML (the events below the curve are not counted:
/// the rate is a lower bound). `state` names a damage state.
pub(super) fn tails(s: &SiteInfo, unit: &str, state: Option<&str>) -> Vec<String> {
    let what = state.map_or(String::new(), |n| format!("`{n}`: "));
    let mut out = Vec::new();
    if s.share_beyond_last_iml > 0.5 {
        out.push(format!(
            "site {}: {what}{:.0} % of the rate comes from beyond the hazard curve's last IML \
             ({} {unit}), where its last slope is extrapolated; the rate and return period are \
             an extrapolation (compare --beyond stop)",
            s.site,
            100.0 * s.share_beyond_last_iml,
            crate::im::level_text(s.last_iml)
        ));
    }
    if s.fragility_at_first_iml > 0.01 {
        out.push(format!(
            "site {}: {what}P = {:.1} % already at the hazard curve's first IML ({} {unit}): \
             the events below it are not counted, so the rate is a lower bound; give a curve \
             that starts lower",
            s.site,
            100.0 * s.fragility_at_first_iml,
            crate::im::level_text(s.first_iml)
        ));
    }
    out
}

/// The bootstrap's bands on the answer, and a warning where some
/// resamples had no fit.
fn with_bands(
    (boot, site_bands): (super::BootstrapInfo, Vec<Option<[f64; 2]>>),
    info: &mut FragilityInfo,
    warnings: &mut Vec<String>,
    sites: &mut [SiteInfo],
) {
    if boot.fitted < boot.resamples {
        warnings.push(format!(
            "{} of {} resamples have no fit in some branch (too few of their records overturn \
             the block for the fit asked): the bands are of the {} others",
            boot.resamples - boot.fitted,
            boot.resamples,
            boot.fitted
        ));
    }
    for (s, band) in sites.iter_mut().zip(site_bands) {
        s.annual_rate_band = band;
    }
    info.bootstrap = Some(boot);
}
