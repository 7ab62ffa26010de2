//! `rocking export`: a block's (or an inventory's) damage-state fragilities
//! written for OpenQuake (NRML, with an exposure and a `classical_damage`
//! job on a hazard file's sites) or pelicun (fragility CSV and metadata).
//!
//! - `request`: what is asked and answered, and every refusal;
//! - `blocks`: each block's entries (a logic tree's branches or mean);
//! - `files`: the files written as one consistent set.

mod blocks;
mod files;
mod request;

use std::path::Path;

use crate::damage::FitMethod;
use crate::export::{pelicun, Site};
use crate::im::Im;
use crate::ops::fragility::{self, FragilityError};
use crate::ops::risk::{self, Blocks, InventoryBlock, RiskError};
pub use blocks::taxonomy;
use files::write_files;
pub use request::{
    BranchExport, ExportOpError, ExportedBlock, Format, Request, TreeExport, Written,
};
use request::{Entries, HazardSites};

/// Computes every block's fragilities and writes the engine's files. A
/// folder `--out` made for an export that then fails is taken away again:
/// nothing is left of it.
pub fn export(req: &Request) -> Result<Written, ExportOpError> {
    let made = !req.out.exists();
    let result = export_into(req);
    if result.is_err() && made {
        // Empty once the lock is gone (`remove_dir` takes only an empty one).
        let _ = std::fs::remove_dir(&req.out);
    }
    result
}

fn export_into(req: &Request) -> Result<Written, ExportOpError> {
    crate::physics::check_auto_tol(req.auto_tol).map_err(FragilityError::AutoTol)?;
    risk::check_years(req.years)?;
    if req.method == FitMethod::Empirical && !req.direct {
        return Err(ExportOpError::EmpiricalExport);
    }
    let hazard = match (&req.hazard, req.format) {
        (Some(_), Format::Pelicun) => return Err(ExportOpError::HazardForPelicun),
        (Some(path), Format::Nrml) => Some(read_sites(path, req.im)?),
        (None, _) => None,
    };
    let im = hazard.as_ref().map_or(req.im.unwrap_or(Im::Pga), |h| h.im);
    // The engine must take the IM before the records are run.
    match req.format {
        Format::Nrml => crate::export::openquake_imt(im).map(drop)?,
        Format::Pelicun => pelicun::demand(im).map(drop)?,
    }
    check_out(&req.out, req)?;
    // One export at a time into a folder.
    let _lock = crate::stages::lock::Lock::take(
        &req.out,
        crate::stages::lock::Scope::Exclusive,
        "rocking export",
    )?;
    let entries = match &req.blocks {
        Blocks::One { b_m, h_m, eps, mu } => vec![InventoryBlock {
            name: format!("b{b_m}_h{h_m}"),
            b_m: *b_m,
            h_m: *h_m,
            eps: *eps,
            mu: *mu,
            line: 0,
        }],
        Blocks::Inventory(path) => {
            let entries = risk::read_inventory(path)?;
            same_taxonomy(path, &entries)?;
            entries
        }
    };
    let (laws, records) = fragility::laws_and_records(
        &req.from,
        req.direct,
        &req.progress,
        entries.len() * req.tree.as_ref().map_or(1, |t| t.paths().len()),
        req.floor.as_ref(),
        fragility::Orient {
            pair_im: req.im.is_some_and(|im| im.pair()),
            ..req.orient
        },
    )?;
    let mut written = Entries::default();
    let mut blocks = Vec::with_capacity(entries.len());
    for e in entries {
        let in_block = |source| ExportOpError::Block {
            name: e.name.clone(),
            source,
        };
        let at = blocks::Asked {
            req,
            im,
            laws: &laws,
            records: records.as_ref(),
        };
        let mut b = blocks::of_block(&at, &e, &mut written).map_err(|err| match err {
            blocks::Refused::Fragility(f) => in_block(f),
            blocks::Refused::Export(x) => *x,
        })?;
        b.fragility
            .warnings
            .extend(hazard.iter().flat_map(|h| h.warnings.iter().cloned()));
        if req.format == Format::Pelicun {
            let entry = written.functions.iter().find(|f| f.id == b.taxonomy);
            b.fragility
                .warnings
                .extend(entry.and_then(|f| uncut_in_pelicun(f, im.unit())));
        }
        if let Some(h) = &hazard {
            // The block's function, or with a tree its first branch's (the
            // branches share the block's uplift level).
            let branch = format!("{}_b1", b.taxonomy);
            let cut = written
                .functions
                .iter()
                .find(|f| f.id == b.taxonomy || f.id == branch)
                .and_then(|f| f.no_damage_limit);
            b.fragility.warnings.extend(beyond_the_curve(&b, h, cut));
            b.fragility.warnings.extend(coarse_sum(&b, h, cut));
            b.fragility.warnings.extend(read_as_certain(&b, h, cut));
        }
        blocks.push(b);
    }
    let source = blocks.first().map_or("", |b| b.fragility.source.as_str());
    let floor = records.as_ref().and_then(|r| r.floor());
    let files = write_files(req, hazard.as_ref(), &written, im, source, floor)?;
    Ok(Written { files, blocks })
}

/// OpenQuake's job counts nothing beyond the hazard's last IML, where
/// `risk` by default continues the curve (`--beyond extrapolate`): where
/// that part is 1 % or more of a block's rate of its heaviest state at a
/// site, the two answers differ by it, and the warning says so and how to
/// get OpenQuake's from `risk`. The share is `risk`'s own
/// ([`crate::risk::assess_above`]).
fn beyond_the_curve(b: &ExportedBlock, h: &HazardSites, cut: Option<f64>) -> Option<String> {
    let f = &b.fragility;
    let parts = heaviest(b)?;
    let shares: Vec<_> = h
        .curves
        .iter()
        .map(|(k, c)| {
            let r = site_risk(&parts, c, cut, crate::risk::Beyond::Extrapolate);
            (*k, r.share_beyond_last_iml, r.last_iml)
        })
        .collect();
    let (site, share, last) = *shares.iter().max_by(|a, b| a.1.total_cmp(&b.1))?;
    (share >= 0.01).then(|| {
        format!(
            "OpenQuake's job counts nothing beyond the hazard's last IML ({last} {}): at site \
             {site}, {:.1} % of the rate of `{}` that `risk` gives by default comes from beyond \
             it{} (`risk --beyond stop` leaves it out, as the job does)",
            h.im.unit(),
            100.0 * share,
            f.states.last().map_or("", |s| s.name.as_str()),
            others(shares.iter().map(|s| s.1), shares.len())
        )
    })
}

/// OpenQuake's job sums the hazard at its IMLs by a midpoint rule
/// ([`crate::export::reading::midpoint_rate`]), where `risk` integrates
/// the log-log curve between them: on a coarse curve (the 14 IMLs of a
/// typical hazard export) the job's rate of a block's heaviest state
/// differs from `risk --beyond stop`'s by several per cent. Where it
/// differs by 1 % or more at a site, the warning gives both rates and what
/// brings them together.
fn coarse_sum(b: &ExportedBlock, h: &HazardSites, cut: Option<f64>) -> Option<String> {
    let f = &b.fragility;
    let parts = heaviest(b)?;
    let gaps: Vec<_> = h
        .curves
        .iter()
        .filter_map(|(k, c)| {
            let job: f64 = parts
                .iter()
                .map(|(w, frag)| {
                    let p = |x| crate::ops::damage::probability_above(frag, x, cut);
                    w * crate::export::reading::midpoint_rate(c, p)
                })
                .sum();
            let ours = site_risk(&parts, c, cut, crate::risk::Beyond::Stop).annual_rate;
            // The job's IMLs: the file's, those of poe 1 and a closing 0 too.
            let imls = c.infinite.len() + c.iml.len() + usize::from(c.ends_at.is_some());
            (ours > 0.0).then(|| (*k, job / ours - 1.0, job, ours, imls))
        })
        .collect();
    let &(site, gap, job, ours, imls) =
        gaps.iter().max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
    (gap.abs() >= 0.01).then(|| {
        format!(
            "OpenQuake's job sums the hazard at its {imls} IMLs by a midpoint rule, where `risk` \
             integrates the curve between them: at site {site} the job counts {job:.3e}/yr of \
             `{}`, {:.1} % {} the {ours:.3e}/yr of `risk --beyond stop`{} (give the hazard at \
             more IMLs: the gap falls with the square of their spacing, to 0.1 % at about 20 \
             per factor of 2)",
            f.states.last().map_or("", |s| s.name.as_str()),
            100.0 * gap.abs(),
            if gap > 0.0 { "above" } else { "below" },
            others(gaps.iter().map(|g| g.1.abs()), gaps.len())
        )
    })
}

/// ", and 1 % or more at N other sites of M" where a warning that names
/// its worst site holds at others too; nothing where it does not.
fn others(shares: impl Iterator<Item = f64>, sites: usize) -> String {
    match shares.filter(|&s| s >= 0.01).count() {
        0 | 1 => String::new(),
        2 => format!(", and 1 % or more at 1 other site of {sites}"),
        n => format!(", and 1 % or more at {} other sites of {sites}", n - 1),
    }
}

/// OpenQuake's job reads poes within 6e-8 of 1 as 1 and counts them at a
/// rate of 36.74/T ([`crate::export::reading`]), where `risk` reads the
/// curve as written: where the rate those IMLs add to the job's count of a
/// block's heaviest state is 1 % or more of `risk`'s rate at a site, the
/// warning says so and by how much.
fn read_as_certain(b: &ExportedBlock, h: &HazardSites, cut: Option<f64>) -> Option<String> {
    let f = &b.fragility;
    let parts = heaviest(b)?;
    let shares: Vec<_> = h
        .curves
        .iter()
        .filter_map(|(k, c)| {
            let mut excess = 0.0;
            let mut edge = None;
            for (w, frag) in &parts {
                let p = |x| crate::ops::damage::probability_above(frag, x, cut);
                let s = crate::export::reading::saturated(c, h.investigation_time, p)?;
                excess += w * s.excess_rate;
                edge = Some(s);
            }
            let s = crate::export::reading::Saturated {
                excess_rate: excess,
                ..edge?
            };
            Some((
                *k,
                excess / site_risk(&parts, c, cut, crate::risk::Beyond::Extrapolate).annual_rate,
                s,
            ))
        })
        .collect();
    let (site, share, s) = *shares.iter().max_by(|a, b| a.1.total_cmp(&b.1))?;
    (share >= 0.01).then(|| {
        format!(
            "OpenQuake's job reads the hazard's poes in single precision: at site {site} its \
             first {} IMLs (to {} {}) read as poe = 1, which it counts at a rate of {:.3}/yr: \
             that adds {:.3e}/yr to the rate of `{}` the job counts, {:.1} % of `risk`'s rate{} \
             (give the job a curve whose poes fall below 1 - 6e-8 where the fragility is still \
             near 0)",
            s.imls,
            crate::im::level_text(s.up_to),
            h.im.unit(),
            s.certain_rate,
            s.excess_rate,
            f.states.last().map_or("", |s| s.name.as_str()),
            100.0 * share,
            others(shares.iter().map(|s| s.1), h.curves.len()),
        )
    })
}

/// pelicun's lognormal has no lower limit where the block's states have
/// one (its uplift level, OpenQuake's noDamageLimit): at that level the
/// lightest state's lognormal already gives P, which pelicun counts below
/// it and `risk`, `fragility` and OpenQuake's job do not. Said where that P
/// is 1 % or more. (A truncated capacity, pelicun's `TruncateLower`, would
/// renormalise the rest of the curve rather than hold it at 0 below.)
fn uncut_in_pelicun(f: &crate::export::Entry, unit: &str) -> Option<String> {
    let cut = f.no_damage_limit?;
    let crate::export::Shape::Lognormal(states) = &f.states else {
        return None;
    };
    let p = states.first()?.cdf(cut);
    (p >= 0.01).then(|| {
        format!(
            "pelicun's lognormal has no lower limit: at the uplift level {} {unit}, below which \
             `risk`, `fragility` and OpenQuake's job count 0, the lightest state's already \
             gives P = {:.1} %, which pelicun counts at smaller demands too",
            crate::im::level_text(cut),
            100.0 * p
        )
    })
}

/// The heaviest state's fragility of a block with its weight 1, or of each
/// branch of its tree with the branch's weight: the rate `risk --tree`
/// gives is their weighted sum, and so are its parts.
fn heaviest(b: &ExportedBlock) -> Option<Vec<(f64, crate::risk::Fragility)>> {
    let of = |f: &crate::ops::damage::DamageFragility| f.states.last()?.fragility(f.method);
    match &b.tree {
        None => Some(vec![(1.0, of(&b.fragility)?)]),
        Some(t) => t
            .branches
            .iter()
            .map(|br| Some((br.weight, of(&br.fragility)?)))
            .collect(),
    }
}

/// `risk`'s answer at a site for `parts` (with `beyond` as its tail, the
/// export's cut): one block's, or a tree's mixture of its branches' as `risk --tree`
/// states it ([`crate::risk::mixed`]).
fn site_risk(
    parts: &[(f64, crate::risk::Fragility)],
    c: &crate::hazard::HazardCurve,
    cut: Option<f64>,
    beyond: crate::risk::Beyond,
) -> crate::risk::SiteRisk {
    let one = |f| crate::risk::assess_above(c, f, beyond, cut.unwrap_or(0.0));
    match parts {
        [(_, f)] => one(f),
        _ => crate::risk::mixed(&parts.iter().map(|(w, f)| (*w, one(f))).collect::<Vec<_>>()),
    }
}

fn read_sites(path: &Path, asked: Option<Im>) -> Result<HazardSites, ExportOpError> {
    let curves = risk::read_hazard(&risk::Hazard::File(path.into()), None)?;
    let im = risk::hazard_im(path, &curves, asked)?;
    let text = std::fs::read_to_string(path).map_err(|source| RiskError::Read {
        path: path.into(),
        source,
    })?;
    let investigation_time = crate::hazard::investigation_time(&text)
        .ok_or_else(|| ExportOpError::PlainHazard(path.into()))?;
    let sites = curves
        .iter()
        .map(|(_, c)| match (c.lon, c.lat) {
            (Some(lon), Some(lat)) => Ok(Site { lon, lat }),
            _ => Err(ExportOpError::PlainHazard(path.into())),
        })
        .collect::<Result<Vec<_>, _>>()?;
    // As OpenQuake's job reads it (its own exports' site ids dropped).
    let text = crate::hazard::openquake_input(&text)
        .ok_or_else(|| ExportOpError::PlainHazard(path.into()))?;
    Ok(HazardSites {
        warnings: risk::hazard_warnings(&curves),
        curves,
        text,
        im,
        sites,
        investigation_time,
    })
}

/// `--out` is a folder that holds none of the command's inputs.
fn check_out(out: &Path, req: &Request) -> Result<(), ExportOpError> {
    if out.is_file() {
        return Err(ExportOpError::Out {
            path: out.into(),
            why: "a file, not a folder".into(),
        });
    }
    crate::outpath::check_folder("--out", out)?;
    let resolved = |p: &Path| std::fs::canonicalize(p).ok();
    let inputs: Vec<&Path> = [req.hazard.as_deref()]
        .into_iter()
        .chain([match &req.blocks {
            Blocks::Inventory(p) => Some(p.as_path()),
            Blocks::One { .. } => None,
        }])
        .flatten()
        .collect();
    for input in inputs {
        let dir = resolved(input).and_then(|p| p.parent().map(Path::to_path_buf));
        if dir.is_some() && dir == resolved(out) {
            return Err(ExportOpError::Out {
                path: out.into(),
                why: format!(
                    "it holds {}, an input of this command; write the export to a folder of its own",
                    input.display()
                ),
            });
        }
    }
    Ok(())
}

/// Two blocks of an inventory whose names make one taxonomy (`marble
/// statue` and `marble_statue`), refused naming both lines before anything
/// runs: the engines would read one block's curves as the other's.
fn same_taxonomy(path: &std::path::Path, entries: &[InventoryBlock]) -> Result<(), ExportOpError> {
    let mut firsts: std::collections::HashMap<String, &InventoryBlock> = Default::default();
    for e in entries {
        let key = taxonomy(&e.name);
        if let Some(first) = firsts.get(&key) {
            return Err(ExportOpError::SameTaxonomy {
                path: path.to_path_buf(),
                line: e.line,
                name: e.name.clone(),
                first: first.name.clone(),
                first_line: first.line,
                taxonomy: key,
            });
        }
        firsts.insert(key, e);
    }
    Ok(())
}
