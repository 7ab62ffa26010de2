//! `rocking contents`: FEMA P-58's unanchored bookcases and filing cabinets
//! ([`crate::contents::FEMA_P58`]) beside the tool's own fragility of the
//! same blocks in Peak Floor Velocity: on the ground under each record set,
//! and on the roof of modal buildings over a range of first-mode periods.
//! Each is the block's one fragility ([`super::damage::of_block`], PFV, the
//! paper's fractile fit kept lognormal, as FEMA's rows are), so a row
//! equals `fragility --im pfv --direct --if-not-lognormal lognormal` for
//! that block, records and floor.

use std::path::PathBuf;

use super::damage;
use super::fragility::{self, DirectProgress, FragilityError, Source};
use crate::contents::FEMA_P58;
use crate::damage::{DamageStates, Dispersion, FitChoice, FitMethod, IfNotLognormal};
use crate::floor::{Building, Mode};
use crate::im::Im;
use crate::plot::{self, Chart, Hue, Line, Scale, Style};

/// What to compare.
#[derive(Debug, Clone)]
pub struct Request {
    /// The ground's record sets: a name and its AT2 folder.
    pub sets: Vec<(String, PathBuf)>,
    /// The modal buildings' first-mode periods (s), on the first set.
    pub periods: Vec<f64>,
    /// Their damping ratio and roof Γφ.
    pub zeta: f64,
    pub gamma_phi: f64,
    pub auto_tol: f64,
    pub progress: DirectProgress,
}

/// One item in one scene.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Row {
    pub id: &'static str,
    pub name: &'static str,
    pub b_m: f64,
    pub h_m: f64,
    pub alpha_rad: f64,
    /// `ground` or `roof`.
    pub scene: &'static str,
    /// The record set.
    pub records: String,
    /// The building's first-mode period (s) on a roof; none on the ground.
    pub period_s: Option<f64>,
    /// The tool's median PFV at overturning (m/s) and β.
    pub median_mps: f64,
    pub beta: f64,
    /// Lilliefors' p of the records' capacities (below 0.05 a lognormal
    /// does not fit them; the row still states the lognormal, as FEMA's).
    pub lognormal_p: Option<f64>,
    /// FEMA P-58's median (m/s) and β.
    pub fema_median_mps: f64,
    pub fema_beta: f64,
    /// The tool's median over FEMA's.
    pub ratio: f64,
}

/// "1st", "2nd", "3rd", "4th", ….
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (1, x) if x != 11 => "st",
        (2, x) if x != 12 => "nd",
        (3, x) if x != 13 => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

#[derive(Debug, thiserror::Error)]
pub enum ContentsError {
    #[error("{0}")]
    Repeated(String),
    #[error("--auto-tol {0}: {1}")]
    AutoTol(f64, String),
    #[error("the building of --periods {period} s, --zeta {zeta}, --gamma-phi {gamma_phi}")]
    Building {
        period: f64,
        zeta: f64,
        gamma_phi: f64,
        #[source]
        source: crate::floor::FloorError,
    },
    #[error("--set {name}={}: {why}", folder.display())]
    Set {
        name: String,
        folder: PathBuf,
        why: &'static str,
    },
    #[error("--set {name}={}", folder.display())]
    SetFiles {
        name: String,
        folder: PathBuf,
        #[source]
        source: crate::records::CollectError,
    },
    #[error("--set {name}={}", folder.display())]
    SetRecords {
        name: String,
        folder: PathBuf,
        #[source]
        source: Box<FragilityError>,
    },
    #[error("{id} under {records}")]
    Item {
        id: &'static str,
        records: String,
        #[source]
        source: Box<FragilityError>,
    },
}

/// The sets, checked before anything runs: each name once, each a folder.
/// A set's records refused as `contents` words it: bad files straight
/// under the set (no `--direct` between them: the command has none), their
/// hint naming `--set`, not `--records`.
fn set_records(name: &str, folder: &std::path::Path, e: FragilityError) -> ContentsError {
    use crate::records::CollectError;
    match e {
        FragilityError::Ingest(CollectError::BadFiles { files, .. }) => ContentsError::SetFiles {
            name: name.to_string(),
            folder: folder.into(),
            source: CollectError::BadFiles {
                files,
                hint: "fix them, or give --set a folder of good AT2 files",
            },
        },
        FragilityError::Ingest(source) => ContentsError::SetFiles {
            name: name.to_string(),
            folder: folder.into(),
            source,
        },
        other => ContentsError::SetRecords {
            name: name.to_string(),
            folder: folder.into(),
            source: Box::new(other),
        },
    }
}

fn check_sets(sets: &[(String, PathBuf)]) -> Result<(), ContentsError> {
    for (k, (name, folder)) in sets.iter().enumerate() {
        let set = |why| ContentsError::Set {
            name: name.clone(),
            folder: folder.clone(),
            why,
        };
        if sets[..k].iter().any(|(other, _)| other == name) {
            return Err(set("the name is given to another set too"));
        }
        if !folder.is_dir() {
            return Err(set("not a folder (give NAME=FOLDER of AT2 records)"));
        }
    }
    Ok(())
}

/// Where the items stand: `ground` or `roof`, the record set, and the
/// roof's building with its period.
type Scene<'a> = (
    &'static str,
    &'a (String, PathBuf),
    Option<&'a (f64, Building)>,
);

/// The modal buildings of `req.periods`, each with its period (s). A
/// period given twice is refused (it ran twice: one column in the table,
/// two rows per item in the JSON).
fn roofs(req: &Request) -> Result<Vec<(f64, Building)>, ContentsError> {
    if let Some((i, t)) = req
        .periods
        .iter()
        .enumerate()
        .find(|&(i, t)| req.periods[..i].contains(t))
    {
        return Err(ContentsError::Repeated(format!(
            "--periods: {t} s is given twice (the {} and an earlier one); give each period once",
            ordinal(i + 1)
        )));
    }
    req.periods
        .iter()
        .map(|&t| {
            Building::new(vec![Mode {
                period_s: t,
                zeta: req.zeta,
                gamma_phi: req.gamma_phi,
            }])
            .map(|b| (t, b))
            .map_err(|source| ContentsError::Building {
                period: t,
                zeta: req.zeta,
                gamma_phi: req.gamma_phi,
                source,
            })
        })
        .collect()
}

/// Every item in every scene, and what the fits warn of.
#[derive(Debug, Clone)]
pub struct Comparison {
    pub rows: Vec<Row>,
    /// Each warning once, with the scene it is of and the items it is of
    /// (all nine, or those named): one record's capacities have no
    /// dispersion, and a row's β = 0 is that, not a certainty.
    pub warnings: Vec<String>,
}

/// Every item in every scene.
pub fn compare(req: &Request) -> Result<Comparison, ContentsError> {
    // Every set and building checked before anything runs.
    check_sets(&req.sets)?;
    // Checked before any run: it was refused inside the first item's runs,
    // under an option (`--direct`) the command does not have.
    crate::physics::check_auto_tol(req.auto_tol)
        .map_err(|e| ContentsError::AutoTol(req.auto_tol, e))?;
    let roofs = roofs(req)?;
    let mut scenes: Vec<Scene> = req.sets.iter().map(|s| ("ground", s, None)).collect();
    if let Some(first) = req.sets.first() {
        scenes.extend(roofs.iter().map(|roof| ("roof", first, Some(roof))));
    }
    let fit = FitChoice {
        method: FitMethod::Fractile,
        dispersion: Dispersion::Each,
        if_not_lognormal: IfNotLognormal::Lognormal,
    };
    let mut rows = Vec::new();
    let mut warnings = Vec::new();
    for (scene, (name, folder), roof) in scenes {
        // Each warning of this scene, with the items it is of.
        let mut said: Vec<(String, Vec<&str>)> = Vec::new();
        let (period, building) = (roof.map(|r| r.0), roof.map(|r| &r.1));
        let from = Source::Paper {
            records: folder.clone(),
            text: None,
        };
        let (laws, records) = fragility::laws_and_records(
            &from,
            true,
            &req.progress,
            FEMA_P58.len(),
            building,
            fragility::Orient::default(),
        )
        .map_err(|source| set_records(name, folder, source))?;
        for c in &FEMA_P58 {
            let in_item = |source| ContentsError::Item {
                id: c.id,
                records: name.clone(),
                source: Box::new(source),
            };
            let block = fragility::block(c.b_m(), c.h_m(), crate::block::Restitution::Housner)
                .map_err(in_item)?;
            let f = damage::of_block(
                &block,
                &DamageStates::overturning(),
                Im::Pfv,
                &laws,
                records.as_ref(),
                crate::ops::fragility::RunModel::auto(req.auto_tol),
                fit,
            )
            .map_err(in_item)?;
            for w in &f.warnings {
                match said.iter_mut().find(|(text, _)| text == w) {
                    Some((_, ids)) => ids.push(c.id),
                    None => said.push((w.clone(), vec![c.id])),
                }
            }
            let state = &f.states[0];
            let (median, beta) = state.median_beta(FitMethod::Fractile);
            let median_mps = median.unwrap_or(f64::INFINITY) / 100.0;
            rows.push(Row {
                id: c.id,
                name: c.name,
                b_m: c.b_m(),
                h_m: c.h_m(),
                alpha_rad: block.alpha(),
                scene,
                records: name.clone(),
                period_s: period,
                median_mps,
                beta: beta.unwrap_or(f64::NAN),
                lognormal_p: state.lognormal_p,
                fema_median_mps: c.median_mps,
                fema_beta: c.beta,
                ratio: median_mps / c.median_mps,
            });
        }
        warnings.extend(each_once(said, period, name));
    }
    Ok(Comparison { rows, warnings })
}

/// A scene's warnings, each once with the place and the items it is of.
fn each_once(said: Vec<(String, Vec<&str>)>, period: Option<f64>, name: &str) -> Vec<String> {
    let place = match period {
        None => format!("on the ground under {name}"),
        Some(t) => format!("on the roof of T = {t} s under {name}"),
    };
    said.into_iter()
        .map(|(text, ids)| {
            let of = match ids.len() == FEMA_P58.len() {
                true => "every item".to_string(),
                false => ids.join(", "),
            };
            format!("{place} ({of}): {text}")
        })
        .collect()
}

/// The ratio of the tool's median to FEMA's for each item against the
/// building's period, the ground of the first set at T = 0 (a building
/// infinitely stiff moves as the ground), FEMA's own at 1 (SVG).
pub fn chart(rows: &[Row], first_set: &str) -> Result<String, plot::PlotError> {
    let n = FEMA_P58.len();
    let mut lines: Vec<Line> = FEMA_P58
        .iter()
        .enumerate()
        .map(|(k, c)| Line {
            name: Some(format!(
                "{} ({})",
                c.id.trim_start_matches("E.20.22."),
                c.name
            )),
            points: rows
                .iter()
                .filter(|r| r.id == c.id && (r.scene == "roof" || r.records == first_set))
                .map(|r| (r.period_s.unwrap_or(0.0), r.ratio))
                .collect(),
            style: Style::LinePoints,
            hue: Hue::Ramp(k as f64 / (n - 1).max(1) as f64),
        })
        .collect();
    let t_max = rows.iter().filter_map(|r| r.period_s).fold(0.0, f64::max);
    lines.push(Line {
        name: Some("FEMA P-58's median".into()),
        points: vec![(0.0, 1.0), (t_max.max(0.1), 1.0)],
        style: Style::Dashed,
        hue: Hue::Ink,
    });
    plot::render(&Chart {
        title: format!(
            "FEMA P-58 contents: the tool's median PFV at overturning over FEMA's ({first_set})"
        ),
        x_desc: "first-mode period of the building, roof (s); 0: the ground".into(),
        y_desc: "median PFV, the tool's / FEMA P-58's".into(),
        x_scale: Scale::Linear,
        y_scale: Scale::Linear,
        x_range: None,
        y_range: None,
        x_ticks: None,
        lines,
    })
}
