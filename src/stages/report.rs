//! Report stage: load the study's tables (I/O) → draw the figures and render
//! `report.md` (pure: [`crate::figures`], [`crate::report`]) → write them.

use std::path::{Path, PathBuf};

use super::damage;
use super::fingerprint;
use super::fit;
use super::reduce::OUTPUTS as REDUCE_OUTPUTS;
use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use super::sweep::{self, DatasetError};
use crate::figures;
use crate::plot::{self, PlotError};
use crate::study::{DamageData, ExampleData, FitBands, PulseData, StudyData};
use crate::tables::{self, TableError};

/// The report stage.
pub struct Report;

/// The report as one page, figures inline.
pub const HTML: &str = "report.html";

impl Stage for Report {
    fn name(&self) -> &'static str {
        "report"
    }

    fn about(&self) -> &'static str {
        "Draw the study's figures (SVG) and write report.md and report.html (one page, the figures inline)"
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        // The run times of the other stages appear in the report.
        let times: std::collections::BTreeMap<String, String> =
            fingerprint::seconds_in_folder(study)
                .into_iter()
                .filter(|(name, _)| name != self.name())
                .map(|(name, s)| (name, format!("{s:.3}")))
                .collect();
        serde_json::json!({
            "plan": study.plan.portable_json(),
            "pipeline": pipeline_name(&study.pipeline),
            fingerprint::TIMES: times,
        })
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        if study.plan.pulse_map().is_some() {
            return Ok(vec![
                study.path(super::pulses::WALLS),
                study.path(super::pulses::MAP),
            ]);
        }
        let mut inputs = match sweep::dataset(&study.dir) {
            Ok((ida, cap)) => ida.into_iter().chain(cap).collect(),
            Err(DatasetError::NoTables(_) | DatasetError::Io { .. }) => vec![
                study.path("ida_points.parquet"),
                study.path("capacities.parquet"),
            ],
            Err(e) => return Err(e.into()),
        };
        inputs.extend(REDUCE_OUTPUTS.iter().map(|n| study.path(n)));
        inputs.push(study.path(super::ims::IM_EFFICIENCY));
        if study
            .plan
            .records_study()
            .is_ok_and(|r| r.random_orientation.is_some())
        {
            inputs.push(study.path(super::ims::RECORD_IMS));
        }
        inputs.extend([damage::STATES, damage::CAPACITIES].map(|n| study.path(n)));
        if fit::not_applicable(&study.plan).is_none() {
            inputs.extend(fit::OUTPUTS.iter().map(|n| study.path(n)));
        }
        if study.plan.example().is_some() {
            inputs.extend(super::example::OUTPUTS.iter().map(|n| study.path(n)));
            let example = [damage::EXAMPLE_STATES, damage::EXAMPLE_CAPACITIES];
            inputs.extend(example.map(|n| study.path(n)));
        }
        if study.plan.tree().is_some() {
            inputs.push(study.path(super::tree::CAPACITIES));
        }
        if !study.plan.convergence().is_empty() {
            inputs.push(study.path("capacity_convergence.parquet"));
        }
        if study.plan.uncertainty().is_some() {
            inputs.push(study.path(super::reduce::BANDS));
            if fit::not_applicable(&study.plan).is_none() {
                inputs.push(study.path(fit::BANDS));
            }
        }
        Ok(inputs)
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        vec![study.path("report.md"), study.path(HTML)]
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx)?)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error(transparent)]
    Fit(#[from] fit::FitError),
    #[error("{0}: no `{1}` in its metadata (\"k of n\"); rerun `rocking fit --force`")]
    Meta(PathBuf, String),
    #[error("figure {file}")]
    Plot {
        file: String,
        #[source]
        source: PlotError,
    },
}

fn pipeline_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Reads every table the figures and the report need.
pub fn load(
    study: &Study,
    stage_seconds: &[(&str, Option<f64>)],
) -> Result<StudyData, ReportError> {
    let dir = &study.dir;
    let plan = &study.plan;
    let read_fit = fit::not_applicable(plan).is_none();
    Ok(StudyData {
        plan: plan.clone(),
        pipeline: pipeline_name(&study.pipeline),
        version: crate::BUILD.to_string(),
        caps: sweep::read_capacities(dir)?,
        ida: sweep::read_ida(dir)?,
        horizontal: tables::read(&dir.join("fractiles_horizontal.parquet"))?,
        capacity_fractiles: tables::read(&dir.join("capacity_fractiles.parquet"))?,
        lognormal: tables::read(&dir.join("lognormal.parquet"))?,
        fit_step1: if read_fit {
            tables::read(&dir.join("fit_step1.parquet"))?
        } else {
            Vec::new()
        },
        laws: if read_fit {
            fit::read_laws(dir, &study.pipeline.display().to_string())?
        } else {
            Vec::new()
        },
        convergence: if plan.convergence().is_empty() {
            None
        } else {
            Some(tables::read(&dir.join("capacity_convergence.parquet"))?)
        },
        bands: match plan.uncertainty() {
            Some(_) => Some(tables::read(&dir.join(super::reduce::BANDS))?),
            None => None,
        },
        fit_bands: match plan.uncertainty() {
            Some(_) if read_fit => Some(read_fit_bands(&dir.join(fit::BANDS))?),
            _ => None,
        },
        example: match plan.example() {
            Some(block) => {
                use super::example::{CAPACITIES, HORIZONTAL, IDA};
                Some(ExampleData {
                    block: block.clone(),
                    ida: tables::read(&dir.join(IDA))?,
                    caps: tables::read(&dir.join(CAPACITIES))?,
                    horizontal: tables::read(&dir.join(HORIZONTAL))?,
                    damage: read_damage(dir, damage::EXAMPLE_STATES, damage::EXAMPLE_CAPACITIES)?,
                })
            }
            None => None,
        },
        efficiency: tables::read(&dir.join(super::ims::IM_EFFICIENCY))?,
        record_ims: match plan.records_study().map(|r| r.random_orientation) {
            Ok(Some(_)) => tables::read(&dir.join(super::ims::RECORD_IMS))?,
            _ => Vec::new(),
        },
        damage: read_damage(dir, damage::STATES, damage::CAPACITIES)?,
        tree_caps: match plan.tree() {
            Some(_) => Some(tables::read(&dir.join(super::tree::CAPACITIES))?),
            None => None,
        },
        stage_seconds: other_stages(study, stage_seconds),
        stood_on: study.stood_on(),
    })
}

/// A damage table pair of the study folder `dir`.
fn read_damage(dir: &Path, states: &str, capacities: &str) -> Result<DamageData, ReportError> {
    Ok(DamageData {
        states: tables::read(&dir.join(states))?,
        capacities: tables::read(&dir.join(capacities))?,
    })
}

/// `fit_bands.parquet` with its counts ("k of n" in the metadata).
fn read_fit_bands(path: &Path) -> Result<FitBands, ReportError> {
    let meta = tables::read_metadata(path)?;
    let count = |key: &str| -> Result<(usize, usize), ReportError> {
        meta.iter()
            .find(|(k, _)| k == key)
            .and_then(|(_, v)| {
                let (k, n) = v.split_once(" of ")?;
                Some((k.parse().ok()?, n.parse().ok()?))
            })
            .ok_or_else(|| ReportError::Meta(path.to_path_buf(), key.to_string()))
    };
    Ok(FitBands {
        rows: tables::read(path)?,
        step1_converged: count(fit::META_STEP1)?,
        laws_complete: count(fit::META_LAWS)?,
    })
}

/// The other stages' times, for the report; a stage run in shards only
/// (the sweep on a cluster), their sum, named so.
fn other_stages(
    study: &Study,
    stage_seconds: &[(&str, Option<f64>)],
) -> Vec<(String, Option<f64>)> {
    stage_seconds
        .iter()
        .filter(|(name, _)| *name != "report")
        .map(
            |&(name, s)| match (s, fingerprint::sharded_seconds(study, name)) {
                (None, Some((total, n))) => (format!("{name} ({n} shards, summed)"), Some(total)),
                _ => (name.to_string(), s),
            },
        )
        .collect()
}

/// A pulse map's tables.
pub fn load_pulses(
    study: &Study,
    stage_seconds: &[(&str, Option<f64>)],
) -> Result<PulseData, ReportError> {
    Ok(PulseData {
        plan: study.plan.clone(),
        pipeline: pipeline_name(&study.pipeline),
        version: crate::BUILD.to_string(),
        walls: tables::read(&study.path(super::pulses::WALLS))?,
        cells: tables::read(&study.path(super::pulses::MAP))?,
        stage_seconds: other_stages(study, stage_seconds),
    })
}

/// The figures the report wrote last, one file name a line (in `figures/`).
const FIGURE_LIST: &str = ".report-figures";

fn run(cx: &Context) -> Result<Summary, ReportError> {
    let study = cx.study;
    // A figure with no point its axes can show (every capacity fractile 0,
    // on a log axis, when no block overturned) is left out of the report.
    let drawable = |figs: Vec<figures::Figure>| -> Vec<figures::Figure> {
        figs.into_iter().filter(|f| f.chart.drawable()).collect()
    };
    let (figs, md) = if study.plan.pulse_map().is_some() {
        let data = load_pulses(study, &cx.stage_seconds)?;
        let figs = drawable(figures::all_pulse(&data));
        let md = crate::report::render_pulses(&data, &figs);
        (figs, md)
    } else {
        let data = load(study, &cx.stage_seconds)?;
        let figs = drawable(figures::all(&data));
        let md = crate::report::render(&data, &figs);
        (figs, md)
    };
    let fig_dir = study.path("figures");
    let mut written = Vec::new();
    let mut svgs = Vec::new();
    for f in &figs {
        let svg = plot::render(&f.chart).map_err(|source| ReportError::Plot {
            file: f.file.clone(),
            source,
        })?;
        let path = fig_dir.join(&f.file);
        tables::atomic_write(&path, svg.as_bytes())?;
        written.push(path);
        svgs.push((f.file.clone(), svg));
    }
    // Figures of an earlier state of the study that it no longer has (a fit
    // that no longer converges, say) would sit beside the report unlisted:
    // those the report wrote last time (its list) are removed; any other
    // file there, a user's own figure, is left alone.
    let list = fig_dir.join(FIGURE_LIST);
    let earlier = std::fs::read_to_string(&list).unwrap_or_default();
    for name in earlier.lines().map(str::trim) {
        let bare = !name.is_empty() && !name.contains(['/', '\\']) && name.ends_with(".svg");
        if bare && !figs.iter().any(|f| f.file == name) {
            let _ = std::fs::remove_file(fig_dir.join(name));
        }
    }
    let names: Vec<&str> = figs.iter().map(|f| f.file.as_str()).collect();
    tables::atomic_write(&list, names.join("\n").as_bytes())?;
    let report = study.path("report.md");
    tables::atomic_write(&report, md.as_bytes())?;
    let page = crate::report::render_html(&format!("Study {}", study.plan.name), &md, &svgs);
    let html = study.path(HTML);
    tables::atomic_write(&html, page.as_bytes())?;
    Ok(Summary {
        lines: vec![format!(
            "wrote {}, {} (self-contained) and {} figures in {}",
            report.display(),
            html.display(),
            figs.len(),
            fig_dir.display()
        )],
        headline: 0,
        also_wrote: written,
    })
}
