//! Reduce stage: the sweep's runs → fractile curves, capacity fractiles,
//! lognormal checks and overturning fractions (docs/MODEL.md §5).
//!
//! Glue: reads the sweep dataset of a study, groups the cases by block, and
//! calls [`crate::stats`]. Under the resurrection rule a record counts as
//! EDP = +∞ at every level at or beyond its first overturning, so the runs
//! the sweep skipped there are not needed.

use std::path::{Path, PathBuf};

use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use super::sweep::{self, DatasetError};
use crate::pipeline::{BlockSpec, FractileDef, Plan};
use crate::stats;
use crate::tables::reduce::{
    CapacityBandRow, CapacityFractileRow, CapacityResampleRow, HorizontalRow, LognormalRow,
    OverturnFractionRow, VerticalRow,
};
use crate::tables::sweep::{CapacityRow, IdaRow};
use crate::tables::{self, TableError};

pub const QUANTILES: [f64; 3] = [0.16, 0.5, 0.84];
/// EDP levels of the vertical statistics: 0.05, 0.10, …, 1.
pub const EDP_LEVELS: usize = 20;

/// The reduce stage.
pub struct Reduce;

/// Output file names, in writing order.
pub const OUTPUTS: [&str; 5] = [
    "fractiles_horizontal.parquet",
    "fractiles_vertical.parquet",
    "capacity_fractiles.parquet",
    "lognormal.parquet",
    "overturn_fraction.parquet",
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
        let fractile = format!("{:?}", study.plan.fractile);
        match study.plan.uncertainty {
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
        if study.plan.uncertainty.is_some() {
            // The records' pairs, for the bootstrap.
            inputs.push(study.records_table());
        }
        Ok(inputs)
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        let bands = match study.plan.uncertainty {
            Some(_) => &[BANDS, RESAMPLES][..],
            None => &[],
        };
        OUTPUTS.iter().chain(bands).map(|n| study.path(n)).collect()
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx.study)?)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ReduceError {
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("the sweep tables do not match the pipeline: {0}; rerun `rocking sweep`")]
    Mismatch(String),
    #[error(transparent)]
    Records(#[from] super::records::SelectError),
    #[error(
        "[uncertainty] unit = \"pair\" resamples the manifest's pairs, and record {0} has \
         none: give the pipeline a manifest with pairs, or set unit = \"record\""
    )]
    NoPair(String),
}

/// One record's IDA for one block, at the grid levels.
struct RecordIda<'a> {
    cap: &'a CapacityRow,
    /// (η, EDP, overturned) at the grid levels that were run, in order.
    levels: Vec<(f64, f64, bool)>,
    /// Index of the first level that overturned.
    first_over: Option<usize>,
}

impl<'a> RecordIda<'a> {
    /// A case's capacity and its runs (any order of kinds; levels in order).
    fn new(cap: &'a CapacityRow, runs: &[&IdaRow]) -> RecordIda<'a> {
        let levels: Vec<(f64, f64, bool)> = runs
            .iter()
            .filter(|r| sweep::is_level(r))
            .map(|r| (r.eta, r.edp, r.overturned))
            .collect();
        let first_over = levels.iter().position(|l| l.2);
        RecordIda {
            cap,
            levels,
            first_over,
        }
    }
}

/// The plan's grid levels (a plan that resolved has a valid grid).
fn grid_levels(plan: &Plan) -> Result<Vec<f64>, ReduceError> {
    plan.grid
        .levels()
        .map_err(|e| ReduceError::Mismatch(e.to_string()))
}

/// The IDA points of each of `n_cases` cases (case ids 0 … n_cases − 1),
/// in table order.
fn split_by_case(ida: &[IdaRow], n_cases: usize) -> Result<Vec<Vec<&IdaRow>>, ReduceError> {
    let mut by_case: Vec<Vec<&IdaRow>> = vec![Vec::new(); n_cases];
    for r in ida {
        let slot = usize::try_from(r.case_id)
            .ok()
            .and_then(|k| by_case.get_mut(k))
            .ok_or_else(|| {
                ReduceError::Mismatch(format!(
                    "IDA point of case {} beyond the capacities",
                    r.case_id
                ))
            })?;
        slot.push(r);
    }
    Ok(by_case)
}

/// The horizontal fractiles of one block, by the rule the stage applies to
/// every block, from its records' capacities (in record order) and runs
/// (cases numbered 0, 1, … as the capacities): the `example` stage's Fig. 5
/// curves.
pub(super) fn horizontal_of_block(
    plan: &Plan,
    block: &BlockSpec,
    caps: &[CapacityRow],
    ida: &[IdaRow],
) -> Result<Vec<HorizontalRow>, ReduceError> {
    let levels = grid_levels(plan)?;
    let by_case = split_by_case(ida, caps.len())?;
    let records: Vec<RecordIda> = caps
        .iter()
        .zip(&by_case)
        .map(|(c, runs)| RecordIda::new(c, runs))
        .collect();
    check_block(block, &records, levels.len())?;
    let mut out = Tables::default();
    horizontal(plan.fractile, block, &levels, &records, &mut out);
    Ok(out.horizontal)
}

/// Every output table, one row vector each.
#[derive(Default)]
struct Tables {
    horizontal: Vec<HorizontalRow>,
    vertical: Vec<VerticalRow>,
    capacity: Vec<CapacityFractileRow>,
    lognormal: Vec<LognormalRow>,
    fraction: Vec<OverturnFractionRow>,
    /// Blocks where lognormality is not rejected at 5 %, of those tested.
    pass: (usize, usize),
}

fn run(study: &Study) -> Result<Summary, ReduceError> {
    let plan = &study.plan;
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
            format!("{:?}", plan.fractile),
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
                "reduced {n_records} records × {n_blocks} blocks ({:?} fractiles): lognormality of η_c not rejected at 5 % in {kept} of {tested} blocks ({:.0} %)",
                plan.fractile,
                100.0 * kept as f64 / tested.max(1) as f64
            ),
            format!(
                "wrote fractiles_horizontal, fractiles_vertical, capacity_fractiles, lognormal, overturn_fraction{} in {}",
                if bands.is_some() { ", capacity_bands, capacity_resamples" } else { "" },
                study.dir.display()
            ),
        ],
        also_wrote: Vec::new(),
    })
}

/// Bootstrap bands of every block's capacity fractiles. Resample `r` draws
/// whole units (pairs from the records table, or records) with replacement
/// from stream `r` of the seed and applies the one draw to every block;
/// resamples run in parallel and are collected in order, so the bytes do not
/// depend on the threads. Returns the bands and every resample's fractiles.
fn bands(
    study: &Study,
    u: crate::pipeline::Uncertainty,
    caps: &[CapacityRow],
    per_block: &[(Vec<f64>, [f64; 3])],
) -> Result<(Vec<CapacityBandRow>, Vec<CapacityResampleRow>), ReduceError> {
    use rayon::prelude::*;
    let plan = &study.plan;
    let def = plan.fractile;
    let units = stats::Units::new(&unit_of(study, u.unit, caps, per_block)?);
    // estimates[r][block] = the block's three fractiles in resample r.
    let estimates: Vec<Vec<[f64; 3]>> = (0..u.resamples as u64)
        .into_par_iter()
        .map_init(
            || (Vec::new(), Vec::new()),
            |(draw, pooled): &mut (Vec<usize>, Vec<f64>), r| {
                let mut rng = stats::SplitMix64::stream(u.seed, r);
                units.draw(&mut rng, draw);
                per_block
                    .iter()
                    .map(|(etas, _)| {
                        let mut q = [0.0; 3];
                        stats::fractiles_of_draw(etas, draw, &QUANTILES, def, pooled, &mut q)
                            .expect("every unit holds records");
                        q
                    })
                    .collect()
            },
        )
        .collect();
    let mut band_rows = Vec::with_capacity(3 * per_block.len());
    let mut column = Vec::with_capacity(estimates.len());
    for (bi, (block, (_, q_eta))) in plan.blocks.iter().zip(per_block).enumerate() {
        for (qi, &quantile) in QUANTILES.iter().enumerate() {
            column.clear();
            column.extend(estimates.iter().map(|e| e[bi][qi]));
            let (lo, hi) = stats::percentile_band(&mut column, u.level)
                .ok_or_else(|| ReduceError::Mismatch("a NaN capacity".into()))?;
            band_rows.push(CapacityBandRow {
                block: block.name.clone(),
                p: block.p,
                eps: block.eps,
                quantile,
                eta_c: q_eta[qi],
                lo,
                hi,
                level: u.level,
                resamples: u.resamples as i64,
                unit: u.unit,
            });
        }
    }
    let mut resample_rows = Vec::with_capacity(estimates.len() * 3 * per_block.len());
    for (r, est) in estimates.iter().enumerate() {
        for (block, q) in plan.blocks.iter().zip(est) {
            for (&quantile, &eta_c) in QUANTILES.iter().zip(q) {
                resample_rows.push(CapacityResampleRow {
                    resample: r as i64,
                    block: block.name.clone(),
                    p: block.p,
                    eps: block.eps,
                    quantile,
                    eta_c,
                });
            }
        }
    }
    Ok((band_rows, resample_rows))
}

/// Each record's resampling unit (records in case order): its pair's
/// number (pairs numbered in order of first appearance), or its own.
fn unit_of(
    study: &Study,
    unit: crate::pipeline::ResampleUnit,
    caps: &[CapacityRow],
    per_block: &[(Vec<f64>, [f64; 3])],
) -> Result<Vec<usize>, ReduceError> {
    use crate::pipeline::ResampleUnit;
    let plan = &study.plan;
    let n_blocks = plan.blocks.len();
    let n_records = per_block.first().map_or(0, |b| b.0.len());
    if unit == ResampleUnit::Record {
        return Ok((0..n_records).collect());
    }
    // Case k = ri·n_blocks + bi.
    let rows = super::records::select(plan, &study.records_table())?;
    let pair_of: std::collections::HashMap<&str, &str> = rows
        .iter()
        .filter_map(|r| Some((r.record_id.as_str(), r.meta.pair.as_deref()?)))
        .collect();
    let mut pairs: Vec<&str> = Vec::new();
    (0..n_records)
        .map(|ri| {
            let id = caps[ri * n_blocks].record_id.as_str();
            let pair = *pair_of
                .get(id)
                .ok_or_else(|| ReduceError::NoPair(id.to_string()))?;
            Ok(match pairs.iter().position(|p| *p == pair) {
                Some(i) => i,
                None => {
                    pairs.push(pair);
                    pairs.len() - 1
                }
            })
        })
        .collect()
}

/// The sweep's capacities and IDA points, in case order, checked to be of
/// this pipeline's settings (a leftover from an edit is refused).
fn load(study: &Study) -> Result<(Vec<CapacityRow>, Vec<IdaRow>), ReduceError> {
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
    let n_blocks = plan.blocks.len();
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

fn check_block(
    block: &BlockSpec,
    records: &[RecordIda],
    n_levels: usize,
) -> Result<(), ReduceError> {
    for r in records {
        if r.cap.p != block.p || r.cap.eps != block.eps {
            return Err(ReduceError::Mismatch(format!(
                "case {} is p = {}, ε = {} in the tables but p = {}, ε = {} in the pipeline",
                r.cap.case_id, r.cap.p, r.cap.eps, block.p, block.eps
            )));
        }
        let needed = r.first_over.map_or(n_levels, |f| f + 1);
        if r.levels.len() < needed {
            return Err(ReduceError::Mismatch(format!(
                "case {} has too few level runs",
                r.cap.case_id
            )));
        }
    }
    Ok(())
}

fn fractiles(sorted: &[f64], def: FractileDef) -> [f64; 3] {
    QUANTILES.map(|q| stats::fractile(sorted, q, def).expect("at least one record"))
}

/// Horizontal statistics (EDP given η, +∞ at and beyond a record's first
/// overturning) and overturning fractions; returns each level's η and EDP
/// fractiles for the capacity's horizontal counterpart.
fn horizontal(
    def: FractileDef,
    block: &BlockSpec,
    levels: &[f64],
    records: &[RecordIda],
    out: &mut Tables,
) -> Vec<(f64, [f64; 3])> {
    let n_records = records.len();
    let mut h_q = Vec::with_capacity(levels.len());
    for (j, &eta) in levels.iter().enumerate() {
        let mut edp: Vec<f64> = records
            .iter()
            .map(|r| {
                if r.first_over.is_some_and(|fo| j >= fo) {
                    f64::INFINITY
                } else {
                    r.levels[j].1
                }
            })
            .collect();
        edp.sort_by(|a, b| a.total_cmp(b));
        let n_over = edp.iter().filter(|e| e.is_infinite()).count();
        let q = fractiles(&edp, def);
        out.horizontal.push(HorizontalRow {
            block: block.name.clone(),
            p: block.p,
            eps: block.eps,
            level: j as i64,
            eta,
            edp_q16: q[0],
            edp_q50: q[1],
            edp_q84: q[2],
            n_records: n_records as i64,
            n_overturned: n_over as i64,
        });
        h_q.push((eta, q));
        // Plain fraction: needs a run of every record at this level.
        let plain: Option<usize> = records
            .iter()
            .map(|r| r.levels.get(j).map(|l| usize::from(l.2)))
            .sum::<Option<usize>>();
        out.fraction.push(OverturnFractionRow {
            block: block.name.clone(),
            p: block.p,
            eps: block.eps,
            level: j as i64,
            eta,
            fraction_plain: plain.map(|c| c as f64 / n_records as f64),
            fraction_resurrection: n_over as f64 / n_records as f64,
        });
    }
    h_q
}

/// Vertical statistics: the first (largest) η at which each record's EDP reaches e.
fn vertical(plan: &Plan, block: &BlockSpec, records: &[RecordIda], out: &mut Tables) {
    for k in 1..=EDP_LEVELS {
        let e = k as f64 / EDP_LEVELS as f64;
        let mut etas = Vec::with_capacity(records.len());
        let mut not_reached = 0;
        for r in records {
            match first_eta_reaching(r, plan.grid.eta_max, e) {
                Some(eta) => etas.push(eta),
                None => {
                    etas.push(0.0);
                    not_reached += 1;
                }
            }
        }
        etas.sort_by(|a, b| a.total_cmp(b));
        let q = fractiles(&etas, plan.fractile);
        out.vertical.push(VerticalRow {
            block: block.name.clone(),
            p: block.p,
            eps: block.eps,
            edp: e,
            eta_q16: q[0],
            eta_q50: q[1],
            eta_q84: q[2],
            n_records: records.len() as i64,
            n_not_reached: not_reached,
        });
    }
}

/// Capacity fractiles of η_c over the records (a record that never
/// overturned counts as η_c = 0, stronger than any level), and the
/// horizontal counterpart: the largest level whose EDP fractile is ≥ 1.
fn capacity_fractiles(
    def: FractileDef,
    block: &BlockSpec,
    records: &[RecordIda],
    h_q: &[(f64, [f64; 3])],
    out: &mut Tables,
) -> [f64; 3] {
    let mut eta_c: Vec<f64> = records.iter().map(|r| r.cap.eta_c.unwrap_or(0.0)).collect();
    let censored = records.iter().filter(|r| r.cap.eta_c.is_none()).count();
    eta_c.sort_by(|a, b| a.total_cmp(b));
    let q_eta = fractiles(&eta_c, def);
    for (qi, &q) in QUANTILES.iter().enumerate() {
        let horiz = h_q
            .iter()
            .find(|(_, hq)| hq[qi] >= 1.0)
            .map(|(eta, _)| *eta);
        out.capacity.push(CapacityFractileRow {
            block: block.name.clone(),
            p: block.p,
            eps: block.eps,
            quantile: q,
            eta_c: q_eta[qi],
            eta_c_horizontal: horiz,
            n_records: records.len() as i64,
            n_censored: censored as i64,
        });
    }
    q_eta
}

/// Lognormality of η_c (Lilliefors) and the two estimates of median and β.
fn lognormal(block: &BlockSpec, records: &[RecordIda], q_eta: [f64; 3], out: &mut Tables) {
    let logs: Vec<f64> = records
        .iter()
        .filter_map(|r| r.cap.eta_c)
        .map(f64::ln)
        .collect();
    let test = stats::lilliefors(&logs);
    let (mean, sd) = if logs.len() >= 2 {
        stats::mean_sd(&logs)
    } else {
        (f64::NAN, f64::NAN)
    };
    let ok = |v: f64| (v.is_finite() && v > 0.0).then_some(v);
    let beta_fr = match (ok(q_eta[0]), ok(q_eta[2])) {
        (Some(a), Some(b)) => Some(0.5 * (b.ln() - a.ln())),
        _ => None,
    };
    let rejected = test.is_some_and(|t| t.p_value < 0.05);
    if test.is_some() {
        out.pass.1 += 1;
        out.pass.0 += usize::from(!rejected);
    }
    out.lognormal.push(LognormalRow {
        block: block.name.clone(),
        p: block.p,
        eps: block.eps,
        n: logs.len() as i64,
        median_sample: mean.is_finite().then(|| mean.exp()),
        beta_sample: sd.is_finite().then_some(sd),
        median_fractile: ok(q_eta[1]),
        beta_fractile: beta_fr,
        lilliefors_d: test.map(|t| t.d),
        p_value: test.map(|t| t.p_value),
        critical_d_5pct: (logs.len() >= 5)
            .then(|| stats::lilliefors_critical_value(logs.len(), 0.05)),
        rejected_5pct: rejected,
    });
}

/// The first (largest) η at which the record's IDA curve reaches EDP `e`,
/// interpolating linearly between grid levels; the curve starts at
/// (η_max, 0) and ends at (η_c, 1) if the record overturns.
fn first_eta_reaching(r: &RecordIda, eta_max: f64, e: f64) -> Option<f64> {
    // Nothing moves at η ≥ 1 (the uplift threshold of either model), so a grid
    // that starts there starts at EDP = 0; one that starts lower starts at its
    // first level.
    let mut prev = (eta_max >= 1.0).then_some((eta_max, 0.0));
    let end = r.first_over.unwrap_or(r.levels.len());
    let tail = r.cap.eta_c.map(|c| (c, 1.0));
    for point in r.levels[..end].iter().map(|l| (l.0, l.1)).chain(tail) {
        if point.1 >= e {
            return Some(match prev {
                Some(prev) => prev.0 + (e - prev.1) / (point.1 - prev.1) * (point.0 - prev.0),
                None => point.0,
            });
        }
        prev = Some(point);
    }
    None
}

/// Reads a reduce table of a study folder (for fit, the report and tests).
pub fn read<T: tables::Table>(dir: &Path, file: &str) -> Result<Vec<T>, TableError> {
    tables::read(&dir.join(file))
}
