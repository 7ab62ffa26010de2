//! The export's files written into its folder, as one consistent set: the
//! engine's files, and the list of them that the next export replaces.

use std::path::{Path, PathBuf};

use super::request::{Entries, ExportOpError, Format, HazardSites, Request};
use crate::export::{nrml, pelicun};
use crate::im::Im;
use crate::tables::{atomic_write, atomic_write_all};

/// Writes the engine's files into `req.out`, and says which.
pub(super) fn write_files(
    req: &Request,
    hazard: Option<&HazardSites>,
    entries: &Entries,
    im: Im,
    source: &str,
    floor: Option<&crate::floor::Building>,
) -> Result<Vec<PathBuf>, ExportOpError> {
    let names: Vec<String> = req.states.states().iter().map(|s| s.name.clone()).collect();
    let description = description(req, im, source, floor, &entries.functions);
    std::fs::create_dir_all(&req.out).map_err(|e| ExportOpError::Out {
        path: req.out.clone(),
        why: e.to_string(),
    })?;
    let earlier = earlier_export(&req.out);
    // Every file rendered, then every target checked, then written: a
    // folder holding a file no export wrote gets nothing at all.
    let mut planned: Vec<(&str, String)> = Vec::new();
    match req.format {
        Format::Nrml => {
            planned.push((
                nrml::FRAGILITY_FILE,
                nrml::fragility_model(&entries.functions, &names, im, &description)?,
            ));
            // A tree's branches are weighted per taxonomy, job or not.
            let mapping = !entries.mapping.is_empty();
            if mapping {
                planned.push((
                    nrml::TAXONOMY_MAPPING_FILE,
                    nrml::taxonomy_mapping(&entries.mapping),
                ));
            }
            if let Some(h) = hazard {
                let (xml, csv) = nrml::exposure_model(&entries.exposure, &h.sites)?;
                planned.push((nrml::EXPOSURE_FILE, xml));
                planned.push((nrml::ASSETS_FILE, csv));
                planned.push((nrml::HAZARD_FILE, h.text.clone()));
                planned.push((
                    nrml::JOB_FILE,
                    nrml::job_ini(req.years, h.investigation_time, mapping),
                ));
            }
        }
        Format::Pelicun => {
            let states: Vec<(String, String)> = req
                .states
                .states()
                .iter()
                .map(|s| (s.name.clone(), s.describe()))
                .collect();
            planned.push((
                pelicun::CSV_FILE,
                pelicun::fragility_csv(&entries.functions, names.len(), im)?,
            ));
            planned.push((
                pelicun::JSON_FILE,
                pelicun::metadata_json(&entries.functions, &states, &description)?,
            ));
        }
    }
    if let Some((name, _)) = planned
        .iter()
        .find(|(name, _)| req.out.join(name).exists() && !earlier.iter().any(|e| e == name))
    {
        return Err(ExportOpError::Out {
            path: req.out.clone(),
            why: format!("it holds {name}, which no export wrote; export into a folder of its own"),
        });
    }
    let files = write_set(&req.out, &earlier, &planned)?;
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

/// Writes `planned` into `out` as one set ([`atomic_write_all`]), the list
/// of the folder's files first holding them beside the `earlier` export's,
/// so that an export stopped while writing can be redone there.
fn write_set(
    out: &Path,
    earlier: &[String],
    planned: &[(&str, String)],
) -> Result<Vec<PathBuf>, ExportOpError> {
    let listed: Vec<&str> = earlier
        .iter()
        .map(String::as_str)
        .chain(planned.iter().map(|(name, _)| *name))
        .collect();
    atomic_write(&out.join(MANIFEST), listed.join("\n").as_bytes())?;
    let files: Vec<PathBuf> = planned.iter().map(|(name, _)| out.join(name)).collect();
    let set: Vec<(&Path, &[u8])> = files
        .iter()
        .zip(planned)
        .map(|(path, (_, text))| (path.as_path(), text.as_bytes()))
        .collect();
    atomic_write_all(&set)?;
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

/// What the exported fragilities are, as the engines' files say: the
/// blocks' scene (a floor, facing any direction, a pair's component), the
/// states, the fit (the functions written as the records' own curves
/// named where the fit asked for is a lognormal) and where the capacities
/// came from.
fn description(
    req: &Request,
    im: Im,
    source: &str,
    floor: Option<&crate::floor::Building>,
    functions: &[crate::export::Entry],
) -> String {
    let curves: Vec<&str> = functions
        .iter()
        .filter(|f| matches!(f.states, crate::export::Shape::Curve(_)))
        .map(|f| f.id.as_str())
        .collect();
    let fit = match (req.method, curves.is_empty()) {
        (crate::damage::FitMethod::Empirical, _) | (_, true) => {
            format!("{} fit", req.method.name())
        }
        (m, false) if curves.len() == functions.len() => format!(
            "the records' own curves (their capacities fail the lognormal check of the {} fit)",
            m.name()
        ),
        (m, false) => format!(
            "{} fit, the records' own curves for {} (their capacities fail the lognormal check)",
            m.name(),
            curves.join(", ")
        ),
    };
    let floor = floor.map_or(String::new(), |b| {
        // PFA, PFV and FSA are the floor's motion's; the others the ground's.
        let whose = if im.floor() {
            "the floor's motion"
        } else {
            "the ground"
        };
        format!(" on the floor of a building of modes T,zeta,Gamma-phi = {b} (IMs of {whose})")
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
        "Damage states of free-standing rigid blocks{floor}{facing}{component} ({}), {fit}, \
         from {} (rocking {})",
        req.states
            .states()
            .iter()
            .map(|s| format!("{}: {}", s.name, s.describe()))
            .collect::<Vec<_>>()
            .join("; "),
        source,
        env!("CARGO_PKG_VERSION")
    )
}
