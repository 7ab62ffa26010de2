//! The event-based fields `risk --gmf DIR` reads: the folder's files
//! found (one calculation), parsed ([`crate::gmf`]), and the effective
//! investigation time from the job or `--eff-years`.

use std::path::{Path, PathBuf};

use super::error::RiskError;
use super::request::EventsAsk;
use crate::gmf::{self, Fields, GmfError};

/// The one file of `DIR` whose name starts with `stem` and ends `.csv`.
fn one_file(dir: &Path, stem: &str) -> Result<PathBuf, RiskError> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|source| RiskError::Read {
            path: dir.into(),
            source,
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with(stem) && n.ends_with(".csv"))
        })
        .collect();
    found.sort();
    match found.len() {
        1 => Ok(found.remove(0)),
        0 => Err(RiskError::Gmf(format!(
            "{}: no {stem}*.csv; --gmf takes the folder `oq run … --exports csv` wrote (gmf-data, \
             events and sitemesh CSVs)",
            dir.display()
        ))),
        _ => Err(RiskError::Gmf(format!(
            "{}: {} files {stem}*.csv (several calculations?); give a folder of one",
            dir.display(),
            found.len()
        ))),
    }
}

fn read(path: &Path) -> Result<String, RiskError> {
    std::fs::read_to_string(path).map_err(|source| RiskError::Read {
        path: path.into(),
        source,
    })
}

/// The fields of the folder and the effective time: the job's (`job.ini`
/// in the folder or its parent) or `--eff-years`, refused when neither.
/// The fields of a folder, the effective time (years) and where it is
/// from, and what the folder's files disagree on without refusing.
pub struct ReadFields {
    pub fields: Fields,
    pub eff_years: f64,
    pub from: String,
    pub warnings: Vec<String>,
}

pub fn read_fields(ask: &EventsAsk) -> Result<ReadFields, RiskError> {
    let dir = &ask.dir;
    let name = |p: &Path| p.display().to_string();
    let gerr = |e: GmfError| RiskError::Gmf(e.to_string());
    let sites_path = one_file(dir, "sitemesh_")?;
    let events_path = one_file(dir, "events_")?;
    let gmf_path = one_file(dir, "gmf-data_")?;
    let sites = gmf::parse_sites(&read(&sites_path)?, &name(&sites_path)).map_err(gerr)?;
    let events_text = read(&events_path)?;
    let events = gmf::parse_events(&events_text, &name(&events_path)).map_err(gerr)?;
    let fields =
        gmf::parse_fields(&read(&gmf_path)?, &name(&gmf_path), sites, events).map_err(gerr)?;
    let (realizations, listed) = realizations(dir, &fields)?;
    let weights_listed = listed.is_some();
    let job = [dir.join("job.ini"), dir.join("../job.ini")]
        .into_iter()
        .find(|p| p.is_file());
    let mut warnings = Vec::new();
    let from_job = match &job {
        Some(p) => {
            let text = read(p)?;
            let in_job = |why| RiskError::Gmf(format!("{}: {why}", name(p)));
            let samples = gmf::samples_of_job(&text).map_err(in_job)?;
            warnings.extend(stale_job(&fields, samples, listed, &name(p), &events_path)?);
            let sets = gmf::event_sets_of_job(&text).map_err(in_job)?;
            let last = gmf::last_event_set(&events_text, &name(&events_path)).map_err(gerr)?;
            if let Some(last) = last.filter(|&l| l as f64 > sets) {
                return Err(RiskError::Gmf(format!(
                    "{}: the events are in event sets up to {last}, but {} says \
                     `ses_per_logic_tree_path = {sets}`: is it this calculation's job? (every \
                     rate would be {}× too high at least)",
                    events_path.display(),
                    name(p),
                    crate::im::level_text(last as f64 / sets)
                )));
            }
            Some((
                gmf::eff_years_of_job(&text, realizations).map_err(in_job)?,
                name(p),
            ))
        }
        None => None,
    };
    let (eff, from) = match (ask.eff_years, from_job) {
        (Some(t), _) if !(t > 0.0 && t.is_finite()) => {
            return Err(RiskError::Gmf(format!(
                "--eff-years {t}: give a positive number of years"
            )))
        }
        (Some(t), Some((j, p))) if (t / j - 1.0).abs() > 1e-9 => {
            return Err(RiskError::Gmf(format!(
                "--eff-years {t}, but {p} says {j} (investigation_time × ses_per_logic_tree_path \
                 × {realizations} realisation(s)): give one"
            )))
        }
        (Some(t), None) => {
            // No job to check it against: the events' years bound it.
            let last = gmf::last_year(&events_text, &name(&events_path)).map_err(gerr)?;
            if let Some(y) = last.filter(|&y| y as f64 > t) {
                return Err(RiskError::Gmf(format!(
                    "--eff-years {t}, but {} has events in year {y}: the effective time \
                     (investigation_time × ses_per_logic_tree_path × {realizations} \
                     realisation(s)) is {y} years or more (every rate would be {}× too high \
                     at least)",
                    events_path.display(),
                    crate::im::level_text(y as f64 / t)
                )));
            }
            (t, "--eff-years".to_string())
        }
        (Some(t), _) => (t, "--eff-years".to_string()),
        (None, Some((j, p))) => (j, p),
        (None, None) => {
            return Err(RiskError::Gmf(format!(
                "{}: the effective investigation time (investigation_time × \
                 ses_per_logic_tree_path × realisations) is not in the exported CSVs, and no \
                 job.ini beside them says it: give --eff-years",
                dir.display()
            )))
        }
    };
    if realizations > 1 && !weights_listed {
        warnings.push(format!(
            "the events are of {realizations} realisations and no realizations_*.csv beside \
             them gives their weights: they are pooled as equally weighted (OpenQuake's \
             sampling), which a full enumeration's unequal weights would not be (export the \
             realisations with the fields to have them checked)"
        ));
    }
    Ok(ReadFields {
        fields,
        eff_years: eff,
        from,
        warnings,
    })
}

/// A job.ini that is not the fields' calculation's (edited or copied after
/// the run) sets the effective time, and every rate, by its samples:
/// refused where the events name a realisation past the job's samples,
/// warned of where the realisations listed are not as many as it samples
/// (OpenQuake lists one per sample, each of weight 1/S).
fn stale_job(
    fields: &Fields,
    samples: Option<f64>,
    listed: Option<(usize, String)>,
    job: &str,
    events: &Path,
) -> Result<Option<String>, RiskError> {
    let Some(s) = samples else {
        return Ok(None);
    };
    if let Some(r) = fields.events.iter().map(|e| e.1).max() {
        if f64::from(r) >= s {
            return Err(RiskError::Gmf(format!(
                "{}: the events name realisation {r}, but {job} samples {s} \
                 (`number_of_logic_tree_samples`, realisations 0 to {}): is it this \
                 calculation's job?",
                events.display(),
                s - 1.0
            )));
        }
    }
    Ok(listed.filter(|(r, _)| *r as f64 != s).map(|(r, file)| {
        format!(
            "{job} samples {s} realisations (`number_of_logic_tree_samples`), but {file} lists \
             {r}: the rates divide by the job's {s}; is the job.ini this calculation's?"
        )
    }))
}

/// The number of realisations whose events are pooled: the rows of
/// `realizations_*.csv` when the folder has it, refused when their weights
/// differ (pooling their events is then not their weighted mean, which
/// OpenQuake itself refuses to collect), else those the events name.
fn realizations(
    dir: &Path,
    fields: &Fields,
) -> Result<(usize, Option<(usize, String)>), RiskError> {
    let found = one_file(dir, "realizations_").ok();
    if let Some(path) = found {
        let w = gmf::parse_weights(&read(&path)?, &path.display().to_string())
            .map_err(|e| RiskError::Gmf(e.to_string()))?;
        if w.iter().any(|x| (x / w[0] - 1.0).abs() > 1e-6) {
            return Err(RiskError::Gmf(format!(
                "{}: the realisations have unequal weights ({}): their events cannot be pooled \
                 into one rate; run with `number_of_logic_tree_samples` (equal weights) or one \
                 realisation",
                path.display(),
                w.iter()
                    .map(|x| x.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        if let Some(r) = fields
            .events
            .iter()
            .map(|e| e.1)
            .find(|&r| r as usize >= w.len())
        {
            return Err(RiskError::Gmf(format!(
                "{}: the events name realisation {r}, but it lists {} (0 to {}): are they of one \
                 calculation?",
                path.display(),
                w.len(),
                w.len().saturating_sub(1)
            )));
        }
        return Ok((w.len().max(1), Some((w.len(), path.display().to_string()))));
    }
    let mut r: Vec<u32> = fields.events.iter().map(|e| e.1).collect();
    r.sort_unstable();
    r.dedup();
    Ok((r.len().max(1), None))
}
