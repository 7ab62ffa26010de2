//! Reduce stage: the sweep's runs → fractile curves, capacity fractiles,
//! lognormal checks and overturning fractions (docs/MODEL.md §5).
//!
//! Glue: reads the sweep dataset of a study, groups the cases by block, and
//! calls [`crate::stats`]. Under the resurrection rule a record counts as
//! EDP = +∞ at every level at or beyond its first overturning, so the runs
//! the sweep skipped there are not needed.

mod block_stats;
mod bootstrap;
mod error;

use std::path::{Path, PathBuf};

pub(super) use block_stats::{horizontal_of_block, split_by_case};
pub use block_stats::{EDP_LEVELS, QUANTILES};
pub use error::ReduceError;

use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use super::sweep::{self, DatasetError};
use crate::tables::reduce::BlockRow;
use crate::tables::sweep::{CapacityRow, IdaRow};
use crate::tables::{self, TableError};
use block_stats::{
    capacity_fractiles, check_block, grid_levels, horizontal, lognormal, vertical, RecordIda,
    Tables,
};
use bootstrap::bands;

/// The reduce stage.
pub struct Reduce;

/// Output file names, in writing order.
pub const OUTPUTS: [&str; 6] = [
    "fractiles_horizontal.parquet",
    "fractiles_vertical.parquet",
    "capacity_fractiles.parquet",
    "lognormal.parquet",
    "overturn_fraction.parquet",
    "blocks.parquet",
];

/// The bootstrap bands, written when the pipeline has `[uncertainty]`.
pub const BANDS: &str = "capacity_bands.parquet";
/// Every bootstrap resample's capacity fractiles (what the fit refits),
/// written with the bands.
pub const RESAMPLES: &str = "capacity_resamples.parquet";

impl Stage for Reduce {
    fn name(&self) -> &'static str {
        "reduce"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        study.plan.pulse_map_skips()
    }

    fn about(&self) -> &'static str {
        "Reduce a pipeline's sweep to fractile curves, capacity fractiles and lognormal checks"
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        let fractile = study
            .plan
            .records_study()
            .map_or(String::new(), |r| format!("{:?}", r.fractile));
        match study.plan.uncertainty() {
            None => serde_json::json!(fractile),
            Some(u) => serde_json::json!({ "fractile": fractile, "uncertainty": u }),
        }
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        let mut inputs = match sweep::dataset(&study.dir) {
            Ok((ida, cap)) => ida.into_iter().chain(cap).collect(),
            // Not there yet: name the tables the sweep writes.
            Err(DatasetError::NoTables(_) | DatasetError::Io { .. }) => vec![
                study.path("ida_points.parquet"),
                study.path("capacities.parquet"),
            ],
            Err(e) => return Err(e.into()),
        };
        if study.plan.uncertainty().is_some() {
            // The records' pairs, for the bootstrap.
            inputs.push(study.records_table());
        }
        Ok(inputs)
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        let bands = match study.plan.uncertainty() {
            Some(_) => &[BANDS, RESAMPLES][..],
            None => &[],
        };
        OUTPUTS.iter().chain(bands).map(|n| study.path(n)).collect()
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx.study)?)
    }
}

fn run(study: &Study) -> Result<Summary, ReduceError> {
    let plan = study.plan.records_study()?;
    let (caps, ida) = load(study)?;
    let n_blocks = plan.blocks.len();
    let n_records = caps.len() / n_blocks;
    let levels = grid_levels(plan)?;
    let by_case = split_by_case(&ida, caps.len())?;
    let mut out = Tables::default();
    // Per block: the records' η_c in record order, and their fractiles.
    let mut per_block: Vec<(Vec<f64>, [f64; 3])> = Vec::with_capacity(n_blocks);
    for (bi, block) in plan.blocks.iter().enumerate() {
        let records: Vec<RecordIda> = (0..n_records)
            .map(|ri| {
                let k = ri * n_blocks + bi;
                RecordIda::new(&caps[k], &by_case[k])
            })
            .collect();
        check_block(block, &records, levels.len())?;
        let h_q = horizontal(plan.fractile, block, &levels, &records, &mut out);
        vertical(plan, block, &records, &mut out);
        let q_eta = capacity_fractiles(plan.fractile, block, &records, &h_q, &mut out);
        lognormal(block, &records, q_eta, &mut out);
        per_block.push((
            records.iter().map(|r| r.cap.eta_c.unwrap_or(0.0)).collect(),
            q_eta,
        ));
    }
    let bands = match plan.uncertainty {
        Some(u) => Some(bands(study, u, &caps, &per_block)?),
        None => None,
    };
    let settings = vec![
        (
            "rocking.reduce.fractile".to_string(),
            plan.fractile.name().to_string(),
        ),
        (
            "rocking.reduce.quantiles".to_string(),
            "0.16,0.5,0.84".to_string(),
        ),
    ];
    let path = |i: usize| study.path(OUTPUTS[i]);
    tables::write(&path(0), &out.horizontal, &settings)?;
    tables::write(&path(1), &out.vertical, &settings)?;
    tables::write(&path(2), &out.capacity, &settings)?;
    tables::write(&path(3), &out.lognormal, &settings)?;
    tables::write(&path(4), &out.fraction, &settings)?;
    tables::write(&path(5), &block_rows(plan), &settings)?;
    if let (Some((band_rows, resample_rows)), Some(u)) = (&bands, plan.uncertainty) {
        let mut meta = settings.clone();
        meta.push((
            "rocking.reduce.uncertainty".to_string(),
            serde_json::json!(u).to_string(),
        ));
        tables::write(&study.path(BANDS), band_rows, &meta)?;
        tables::write(&study.path(RESAMPLES), resample_rows, &meta)?;
    }
    let (kept, tested) = out.pass;
    Ok(Summary {
        lines: vec![
            format!(
                "reduced {n_records} records × {n_blocks} blocks ({} fractiles): {}",
                plan.fractile.name(),
                lognormal_count(kept, tested, n_blocks)
            ),
            format!(
                "wrote fractiles_horizontal, fractiles_vertical, capacity_fractiles, lognormal, overturn_fraction, blocks{} in {}",
                if bands.is_some() { ", capacity_bands, capacity_resamples" } else { "" },
                study.dir.display()
            ),
        ],
        headline: 1,
        also_wrote: Vec::new(),
    })
}

/// The pipeline's blocks as rows; a grid's (unnamed blocks) with the
/// indices of their p and ε among the grid's values.
fn block_rows(plan: &crate::pipeline::RecordsPlan) -> Vec<BlockRow> {
    let (blocks, grid) = (&plan.blocks, plan.is_grid());
    let distinct = |f: fn(&crate::pipeline::BlockSpec) -> f64| {
        let mut v: Vec<f64> = Vec::new();
        for b in blocks {
            if !v.contains(&f(b)) {
                v.push(f(b));
            }
        }
        v
    };
    let (ps, es) = (distinct(|b| b.p), distinct(|b| b.eps));
    let index = |v: &[f64], x: f64| {
        grid.then(|| v.iter().position(|&y| y == x).map(|i| i as i64))
            .flatten()
    };
    blocks
        .iter()
        .enumerate()
        .map(|(i, b)| BlockRow {
            block_index: i as i64,
            block: b.name.clone(),
            p: b.p,
            eps: b.eps,
            p_index: index(&ps, b.p),
            eps_index: index(&es, b.eps),
            alpha_rad: b.alpha_rad,
            model: b.run.model.equation.kind(),
        })
        .collect()
}

/// The sweep's capacities and IDA points, in case order, checked to be of
/// this pipeline's settings (a leftover from an edit is refused).
pub(super) fn load(study: &Study) -> Result<(Vec<CapacityRow>, Vec<IdaRow>), ReduceError> {
    let plan = &study.plan;
    let (ida_files, cap_files) = sweep::dataset(&study.dir)?;
    for f in &cap_files {
        let made = sweep::SweepMeta::read(f)?.settings;
        if made.as_deref() != Some(plan.sweep_settings().as_str()) {
            return Err(ReduceError::Mismatch(format!(
                "{} was made with other settings than the pipeline's",
                f.display()
            )));
        }
    }
    let mut caps: Vec<CapacityRow> = tables::read_all(&cap_files)?;
    caps.sort_by_key(|c| c.case_id);
    let mut ida: Vec<IdaRow> = tables::read_all(&ida_files)?;
    ida.sort_by_key(|r| r.case_id);
    let n_blocks = plan.blocks().len();
    if caps.len() % n_blocks != 0 {
        return Err(ReduceError::Mismatch(format!(
            "{} capacities for {n_blocks} blocks",
            caps.len()
        )));
    }
    if let Some((k, c)) = caps
        .iter()
        .enumerate()
        .find(|(k, c)| c.case_id != *k as i64)
    {
        return Err(ReduceError::Mismatch(format!(
            "capacity {k} has case id {} (case ids must be 0, 1, 2, … once each)",
            c.case_id
        )));
    }
    Ok((caps, ida))
}

/// Reads a reduce table of a study folder (for fit, the report and tests).
pub fn read<T: tables::Table>(dir: &Path, file: &str) -> Result<Vec<T>, TableError> {
    tables::read(&dir.join(file))
}

/// How many blocks' η_c passed the lognormal check, of those it could test.
fn lognormal_count(kept: usize, tested: usize, n_blocks: usize) -> String {
    let why = "fewer than five of their records overturn them, or all at one level";
    if tested == 0 {
        return format!("lognormality of η_c untested in every block ({why})");
    }
    let untested = match n_blocks.saturating_sub(tested) {
        0 => String::new(),
        k => format!("; {k} untested ({why})"),
    };
    format!(
        "lognormality of η_c not rejected at 5 % in {kept} of {tested} blocks ({:.0} %){untested}",
        100.0 * kept as f64 / tested as f64
    )
}
