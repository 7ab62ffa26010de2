//! `rocking export`: a block's (or an inventory's) damage-state fragilities
//! written for OpenQuake (NRML, with an exposure and a `classical_damage`
//! job on a hazard file's sites) or pelicun (fragility CSV and metadata).
//!
//! - `request`: what is asked and answered, and every refusal;
//! - `blocks`: each block's entries (a logic tree's branches or mean);
//! - `files`: the files written as one consistent set;
//! - `agreement`: where OpenQuake's job on the files and `risk` differ.

mod agreement;
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
            let said = agreement::warnings(&b, h, cut);
            b.fragility.warnings.extend(said);
        }
        blocks.push(b);
    }
    let source = blocks.first().map_or("", |b| b.fragility.source.as_str());
    let floor = records.as_ref().and_then(|r| r.floor());
    let files = write_files(req, hazard.as_ref(), &written, im, source, floor)?;
    Ok(Written { files, blocks })
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
