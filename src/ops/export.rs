//! `rocking export`: a block's (or an inventory's) damage-state fragilities
//! written for OpenQuake (NRML, with an exposure and a `classical_damage`
//! job on a hazard file's sites) or pelicun (fragility CSV and metadata).

use std::path::{Path, PathBuf};

use super::damage::{self, DamageFragility};
use super::fragility::{self, FragilityError, Source};
use super::risk::{self, Blocks, InventoryBlock, RiskError};
use crate::block::Block;
use crate::damage::{DamageStates, FitMethod};
use crate::export::{nrml, pelicun, Entry, ExportError, Shape, Site};
use crate::im::Im;
use crate::tables::{atomic_write, TableError};

/// The engine to write for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Nrml,
    Pelicun,
}

impl crate::label::Label for Format {
    const ALL: &'static [Self] = &[Format::Nrml, Format::Pelicun];
    const WHAT: &'static str = "export format";
    fn label(self) -> &'static str {
        match self {
            Format::Nrml => "nrml",
            Format::Pelicun => "pelicun",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Format::Nrml => "OpenQuake's NRML 0.5 fragility model (and exposure and job.ini)",
            Format::Pelicun => "pelicun's fragility CSV and its metadata JSON",
        }
    }
}

crate::deserialize_by_label!(Format);

#[derive(Debug, Clone)]
pub struct Request {
    pub format: Format,
    pub blocks: Blocks,
    pub from: Source,
    pub direct: bool,
    /// Where `--direct` reports its progress.
    pub progress: fragility::DirectProgress,
    pub states: DamageStates,
    pub method: FitMethod,
    /// One β for the states of a block (the default), or each its own.
    pub dispersion: crate::damage::Dispersion,
    /// Where the capacities fail the lognormal check: their curve (the
    /// default; pelicun's multilinear_CDF, OpenQuake's discrete function)
    /// or the lognormal anyway.
    pub if_not_lognormal: crate::damage::IfNotLognormal,
    /// The IM; with `--hazard` it must be the hazard's (the default).
    pub im: Option<Im>,
    /// OpenQuake hazard curves: their sites make the exposure, and the job
    /// runs on them (NRML only).
    pub hazard: Option<PathBuf>,
    /// The risk investigation time of the job (years).
    pub years: f64,
    pub auto_tol: f64,
    /// The building whose floor the blocks stand on (`--direct` only).
    pub floor: Option<crate::floor::Building>,
    pub out: PathBuf,
    /// Which orientations of the records (`--direct`).
    pub orient: fragility::Orient,
}

#[derive(Debug, thiserror::Error)]
pub enum ExportOpError {
    #[error(transparent)]
    Risk(#[from] RiskError),
    #[error("block {name}")]
    Block {
        name: String,
        #[source]
        source: FragilityError,
    },
    #[error(transparent)]
    Fragility(#[from] FragilityError),
    #[error(transparent)]
    Format(#[from] ExportError),
    #[error(
        "--method empirical is the records' own curve, which needs their runs: add --direct, or \
         export a lognormal (--method fractile or mle)"
    )]
    EmpiricalExport,
    #[error(
        "--hazard {}: OpenQuake's job needs its hazard-curve CSV with sites (lon, lat) and an \
         investigation_time; a plain `<im>,annual_rate` file has neither",
        .0.display()
    )]
    PlainHazard(PathBuf),
    #[error("--hazard is for --format nrml (the job's sites); pelicun takes demands, not hazard")]
    HazardForPelicun,
    #[error("--out {}: {why}", path.display())]
    Out { path: PathBuf, why: String },
    #[error(transparent)]
    Lock(#[from] crate::stages::lock::LockError),
    #[error(transparent)]
    Write(#[from] TableError),
}

/// One block as exported: itself, its taxonomy in the files, and its
/// fragilities.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ExportedBlock {
    pub block: risk::BlockInfo,
    /// The block's key in the engines' files ([`taxonomy`]).
    pub taxonomy: String,
    /// What its states are written as: `lognormal`, or `curve` (the
    /// records' own: pelicun's `multilinear_CDF`, OpenQuake's discrete
    /// function).
    pub written_as: &'static str,
    pub fragility: DamageFragility,
}

/// What was written, and the fragilities behind it.
#[derive(Debug)]
pub struct Written {
    pub files: Vec<PathBuf>,
    pub blocks: Vec<ExportedBlock>,
}

/// Computes every block's fragilities and writes the engine's files.
pub fn export(req: &Request) -> Result<Written, ExportOpError> {
    crate::physics::check_auto_tol(req.auto_tol).map_err(FragilityError::AutoTol)?;
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
        Blocks::Inventory(path) => risk::read_inventory(path)?,
    };
    let (laws, records) = fragility::laws_and_records(
        &req.from,
        req.direct,
        &req.progress,
        entries.len(),
        req.floor.as_ref(),
        fragility::Orient {
            pair_im: req.im.is_some_and(|im| im.pair()),
            ..req.orient
        },
    )?;
    let mut blocks = Vec::with_capacity(entries.len());
    let mut export = Vec::with_capacity(entries.len());
    for e in entries {
        let in_block = |source| ExportOpError::Block {
            name: e.name.clone(),
            source,
        };
        let block = fragility::block(e.b_m, e.h_m, e.eps).map_err(in_block)?;
        let mut f = damage::of_block(
            &block,
            &req.states,
            im,
            &laws,
            records.as_ref(),
            crate::ops::fragility::RunModel::auto(req.auto_tol),
            crate::damage::FitChoice {
                method: req.method,
                dispersion: req.dispersion,
                if_not_lognormal: req.if_not_lognormal,
            },
        )
        .map_err(in_block)?;
        let info = risk::block_info(&e, &block, req.floor.as_ref());
        let entry = entry(&info, &f, im, &block, req.floor.as_ref())?;
        f.warnings.extend(damage::crossings(&f, f.method));
        f.warnings
            .extend(hazard.iter().flat_map(|h| h.warnings.iter().cloned()));
        if let (Some(mu), Some(true)) = (info.mu, info.slides_first) {
            f.warnings
                .push(crate::block::sliding_warning(mu, info.alpha_rad));
        }
        blocks.push(ExportedBlock {
            block: info,
            taxonomy: entry.id.clone(),
            written_as: match entry.states {
                Shape::Lognormal(_) => "lognormal",
                Shape::Curve(_) => "curve",
            },
            fragility: f,
        });
        export.push(entry);
    }
    let source = blocks.first().map_or("", |b| b.fragility.source.as_str());
    let floor = records.as_ref().and_then(|r| r.floor());
    let files = write_files(req, hazard.as_ref(), &export, im, source, floor)?;
    Ok(Written { files, blocks })
}

/// What the exported fragilities are, as the engines' files say: the
/// blocks' scene (a floor, facing any direction, a pair's component), the
/// states, the fit and where the capacities came from.
fn description(
    req: &Request,
    im: Im,
    source: &str,
    floor: Option<&crate::floor::Building>,
) -> String {
    let floor = floor.map_or(String::new(), |b| {
        format!(" on the floor of a building of modes T,zeta,Gamma-phi = {b} (IMs of the ground)")
    });
    // Facing any direction, and the component the IM is of.
    let facing = match req.orient.orientation {
        crate::pair::Orientation::AsRecorded => String::new(),
        o => format!(
            " facing {} direction of the records' pairs (every {} degrees)",
            if o == crate::pair::Orientation::Random {
                "any"
            } else {
                "the worst"
            },
            req.orient.step_deg
        ),
    };
    let component = if im.pair() {
        format!(" in {}", im.short())
    } else {
        String::new()
    };
    format!(
        "Damage states of free-standing rigid blocks{floor}{facing}{component} ({}), {} fit, \
         from {} (rocking {})",
        req.states
            .states()
            .iter()
            .map(|s| format!("{}: {}", s.name, s.describe()))
            .collect::<Vec<_>>()
            .join("; "),
        req.method.name(),
        source,
        env!("CARGO_PKG_VERSION")
    )
}

/// Writes the engine's files into `req.out`, and says which.
fn write_files(
    req: &Request,
    hazard: Option<&HazardSites>,
    export: &[Entry],
    im: Im,
    source: &str,
    floor: Option<&crate::floor::Building>,
) -> Result<Vec<PathBuf>, ExportOpError> {
    let names: Vec<String> = req.states.states().iter().map(|s| s.name.clone()).collect();
    let description = description(req, im, source, floor);
    std::fs::create_dir_all(&req.out).map_err(|e| ExportOpError::Out {
        path: req.out.clone(),
        why: e.to_string(),
    })?;
    let earlier = earlier_export(&req.out);
    let mut files = Vec::new();
    let mut put = |name: &str, text: &str| -> Result<(), ExportOpError> {
        let path = req.out.join(name);
        if path.exists() && !earlier.iter().any(|e| e == name) {
            return Err(ExportOpError::Out {
                path: req.out.clone(),
                why: format!(
                    "it holds {name}, which no export wrote; export into a folder of its own"
                ),
            });
        }
        atomic_write(&path, text.as_bytes())?;
        files.push(path);
        Ok(())
    };
    match req.format {
        Format::Nrml => {
            put(
                nrml::FRAGILITY_FILE,
                &nrml::fragility_model(export, &names, im, &description)?,
            )?;
            if let Some(h) = hazard {
                let (xml, csv) = nrml::exposure_model(export, &h.sites)?;
                put(nrml::EXPOSURE_FILE, &xml)?;
                put(nrml::ASSETS_FILE, &csv)?;
                put(nrml::HAZARD_FILE, &h.text)?;
                put(
                    nrml::JOB_FILE,
                    &nrml::job_ini(req.years, h.investigation_time),
                )?;
            }
        }
        Format::Pelicun => {
            let states: Vec<(String, String)> = req
                .states
                .states()
                .iter()
                .map(|s| (s.name.clone(), s.describe()))
                .collect();
            put(
                pelicun::CSV_FILE,
                &pelicun::fragility_csv(export, names.len(), im)?,
            )?;
            put(
                pelicun::JSON_FILE,
                &pelicun::metadata_json(export, &states, &description)?,
            )?;
        }
    }
    // The earlier export's files this one did not write are stale (another
    // format, or a job without --hazard now): removed, so that the folder
    // is one consistent set; then the list of this one's.
    for name in &earlier {
        if !files
            .iter()
            .any(|f| f.file_name().is_some_and(|n| n == name.as_str()))
        {
            let _ = std::fs::remove_file(req.out.join(name));
        }
    }
    let names: Vec<String> = files
        .iter()
        .filter_map(|f| f.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    atomic_write(&req.out.join(MANIFEST), names.join("\n").as_bytes())?;
    Ok(files)
}

/// The list of the files the last export into a folder wrote.
const MANIFEST: &str = ".rocking-export";

/// The files an earlier export wrote into `out` (none without its list).
fn earlier_export(out: &Path) -> Vec<String> {
    std::fs::read_to_string(out.join(MANIFEST))
        .map(|t| {
            t.lines()
                .map(str::trim)
                // Only bare file names: the list never points elsewhere.
                .filter(|n| !n.is_empty() && !n.contains(['/', '\\']) && !n.starts_with('.'))
                .map(String::from)
                .collect()
        })
        .unwrap_or_default()
}

/// The block's entry: its states' functions by the fit its fragility is
/// made by (the records' curves, or a lognormal each).
fn entry(
    e: &risk::BlockInfo,
    f: &DamageFragility,
    im: Im,
    block: &Block,
    floor: Option<&crate::floor::Building>,
) -> Result<Entry, ExportOpError> {
    let method = f.method;
    let refuse = |source| ExportOpError::Block {
        name: e.name.clone(),
        source,
    };
    let states = if method == FitMethod::Empirical {
        let curves = f
            .states
            .iter()
            .map(|s| match s.fragility(method) {
                Some(crate::risk::Fragility::Curve(c)) if c.complete() => Ok(c),
                Some(_) => Err(refuse(FragilityError::CurveShort {
                    state: s.name.clone(),
                    reached: s.reached.unwrap_or(0),
                    records: f.records.unwrap_or(0),
                })),
                None => Err(refuse(damage::no_fit(f, s, method))),
            })
            .collect::<Result<Vec<_>, _>>()?;
        Shape::Curve(curves)
    } else {
        Shape::Lognormal(lognormals(e, f)?)
    };
    let slides = match (e.mu, e.slides_first) {
        (Some(mu), Some(true)) => format!(
            "; slides before it rocks (μ = {mu} < b/h = {:.4}): these fragilities assume it \
             does not",
            e.b_m / e.h_m
        ),
        _ => String::new(),
    };
    Ok(Entry {
        id: taxonomy(&e.name),
        description: format!(
            "{}: half-width {} m, half-height {} m, α = {:.4} rad, p = {:.4} 1/s, ε = {:.4}{slides}",
            e.name, e.b_m, e.h_m, e.alpha_rad, e.p, e.eps
        ),
        // The level below which no state is reached, as `risk` cuts it.
        no_damage_limit: damage::zero_below(block, im, floor),
        states,
    })
}

/// The block's states' lognormals by its fit, each with a spread.
fn lognormals(
    e: &risk::BlockInfo,
    f: &DamageFragility,
) -> Result<Vec<crate::damage::Lognormal>, ExportOpError> {
    let method = f.method;
    f.states
        .iter()
        .map(|s| {
            let refuse = |source| ExportOpError::Block {
                name: e.name.clone(),
                source,
            };
            let l = s
                .by(method)
                .ok_or_else(|| refuse(damage::no_fit(f, s, method)))?;
            if l.beta > 0.0 && l.beta.is_finite() {
                Ok(l)
            } else {
                Err(refuse(FragilityError::NoSpread {
                    state: s.name.clone(),
                    beta: l.beta,
                    reached: s.reached,
                }))
            }
        })
        .collect()
}

/// The block's name as a taxonomy the engines read as one key: every
/// character but letters, digits, `_`, `-` and `.` becomes `_`.
pub fn taxonomy(name: &str) -> String {
    name.trim()
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// An OpenQuake hazard file: its text, IM, sites and investigation time.
struct HazardSites {
    text: String,
    im: Im,
    sites: Vec<Site>,
    investigation_time: f64,
    /// Of its curves' units ([`risk::hazard_warnings`]).
    warnings: Vec<String>,
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
    Ok(HazardSites {
        warnings: risk::hazard_warnings(&curves),
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
