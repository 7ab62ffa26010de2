//! The ims stage: the records' intensity measures, and each block's
//! capacity dispersion in every IM (docs/MODEL.md §14).
//!
//! Glue: reads the pipeline's records, capacities and blocks, calls
//! [`crate::im`] and writes `record_ims` and
//! `im_efficiency` through [`crate::tables::ims`].

use std::collections::BTreeMap;
use std::path::PathBuf;

use rayon::prelude::*;

use super::reduce::{self, ReduceError};
use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use super::sweep;
use crate::im::{efficiency, Im, RecordIms, Rotated};
use crate::records;
use crate::records::SelectError;
use crate::tables::ims::{EfficiencyRow, RecordImRow};
use crate::tables::reduce::BlockRow;
use crate::tables::TableError;
use crate::tables::{self, records::RecordRow};

/// The ims stage.
pub struct Ims;

/// The records' measures.
pub const RECORD_IMS: &str = "record_ims.parquet";
/// Each block's capacity dispersion in every IM.
pub const IM_EFFICIENCY: &str = "im_efficiency.parquet";
/// Output file names, in writing order.
pub const OUTPUTS: [&str; 2] = [RECORD_IMS, IM_EFFICIENCY];

impl Stage for Ims {
    fn name(&self) -> &'static str {
        "ims"
    }

    fn about(&self) -> &'static str {
        "The records' intensity measures, and each block's capacity dispersion in every IM"
    }

    fn has_command(&self) -> bool {
        // `rocking ims` is the one-record command.
        false
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        study.plan.pulse_map_skips()
    }

    fn settings(&self, _study: &Study) -> serde_json::Value {
        serde_json::json!({
            "periods_s": crate::im::PERIODS_S,
            "avgsa_periods_s": crate::im::AVGSA_PERIODS_S,
            "damping": crate::im::SPECTRAL_DAMPING,
        })
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        let caps = match sweep::dataset(&study.dir) {
            Ok((_, cap)) => cap,
            Err(_) => vec![study.path("capacities.parquet")],
        };
        let mut inputs = vec![study.records_table(), study.path("blocks.parquet")];
        inputs.extend(caps);
        Ok(inputs)
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        OUTPUTS.iter().map(|n| study.path(n)).collect()
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx.study)?)
    }
}

/// Why the ims stage fails.
#[derive(Debug, thiserror::Error)]
pub enum ImsError {
    /// The sweep's tables, read as reduce reads them.
    #[error(transparent)]
    Sweep(#[from] ReduceError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error(transparent)]
    Records(#[from] SelectError),
    #[error(transparent)]
    NotRecords(#[from] crate::pipeline::NotRecords),
    #[error("the ims stage's inputs disagree: {0}; rerun `rocking run`")]
    Mismatch(String),
    #[error("{0}: the table is not the ims stage's (rerun `rocking run`)")]
    RecordIms(String),
    #[error("record {0} has no motion (every sample is 0)")]
    NoMotion(String),
    #[error("record {0}: its floor motion: {1}")]
    Floor(String, String),
}

fn run(study: &Study) -> Result<Summary, ImsError> {
    let rows = records::select(&study.plan, &study.records_table())?;
    let mut ims = record_ims(&rows)?;
    let turned = study.plan.records_study()?.random_orientation.is_some();
    if turned {
        // Each motion's pair's RotD, unscaled: the hazard's component.
        with_pair_ims(study, &rows, &mut ims)?;
    }
    let floor = study.plan.records_study()?.floor.as_ref();
    let felt = floor.map(|b| felt_ims(b, &rows)).transpose()?;
    // Text records are the motions the blocks stand on: their measures are
    // the floor's, named so (PFA, PFV, FSA(T)), and ranked among themselves.
    let stood_on = study.stood_on();
    let floors = Im::floor_measures();
    let caps = sweep::read_capacities(&study.dir).map_err(ReduceError::from)?;
    let blocks: Vec<BlockRow> = reduce::read(&study.dir, "blocks.parquet")?;
    let n_blocks = blocks.len();
    if n_blocks == 0 || caps.len() != rows.len() * n_blocks {
        return Err(ImsError::Mismatch(format!(
            "{} capacities for {} records × {n_blocks} blocks",
            caps.len(),
            rows.len()
        )));
    }
    let mut eff = Vec::new();
    let mut best: BTreeMap<String, usize> = BTreeMap::new();
    for (bi, b) in blocks.iter().enumerate() {
        let eta = ground_eta(&caps, &rows, n_blocks, bi)?;
        let mut found = if stood_on {
            efficiency::of_measures(&eta, &ims, &floors, b.p, b.alpha_rad)
        } else {
            efficiency::of_block(&eta, &ims, b.p, b.alpha_rad)
        };
        let mut ranks = ranks(&found);
        if let Some(first) = ranks.iter().position(|&r| r == Some(1)) {
            *best.entry(found[first].im.clone()).or_default() += 1;
        }
        if turned {
            let demands =
                efficiency::of_measures(&eta, &ims, &Im::pair_measures(), b.p, b.alpha_rad);
            ranks.extend(demands.iter().map(|_| None));
            found.extend(demands);
        }
        if let Some(felt) = &felt {
            // The floor's demands, in the floor motion's own η.
            let on_floor: Vec<Option<f64>> = (0..rows.len())
                .map(|ri| caps[ri * n_blocks + bi].eta_c)
                .collect();
            let demands = efficiency::of_measures(&on_floor, felt, &floors, b.p, b.alpha_rad);
            ranks.extend(demands.iter().map(|_| None));
            found.extend(demands);
        }
        eff.extend(
            found
                .drain(..)
                .zip(ranks)
                .map(|(e, rank)| efficiency_row(b, e, rank)),
        );
    }
    let settings = vec![(
        "rocking.ims.damping".to_string(),
        crate::im::SPECTRAL_DAMPING.to_string(),
    )];
    let mut im_table = match stood_on {
        false => im_rows(&rows, &ims),
        true => stood_on_rows(&rows, &ims),
    };
    if let Some(felt) = &felt {
        im_table.extend(floor_rows(&rows, felt));
    }
    tables::write(&study.path(RECORD_IMS), &im_table, &settings)?;
    tables::write(&study.path(IM_EFFICIENCY), &eff, &settings)?;
    let mut ranking: Vec<(String, usize)> = best.into_iter().collect();
    ranking.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let ranking: Vec<String> = ranking
        .iter()
        .map(|(im, n)| format!("{im} in {n}"))
        .collect();
    Ok(Summary {
        lines: vec![
            format!(
                "IMs of {} records; the IM of smallest capacity dispersion β: {} of {n_blocks} blocks",
                rows.len(),
                ranking.join(", ")
            ),
            format!(
                "wrote record_ims, im_efficiency in {}",
                study.dir.display()
            ),
        ],
        headline: 0,
        also_wrote: Vec::new(),
    })
}

/// Each measure's rank by β among `found` (1: the smallest), the vector's
/// (which has a slope) none.
fn ranks(found: &[efficiency::Efficiency]) -> Vec<Option<i64>> {
    let mut order: Vec<usize> = (0..found.len())
        .filter(|&i| found[i].slope.is_none())
        .collect();
    order.sort_by(|&i, &j| found[i].beta.total_cmp(&found[j].beta));
    let mut ranks = vec![None; found.len()];
    for (r, &i) in order.iter().enumerate() {
        ranks[i] = Some(r as i64 + 1);
    }
    ranks
}

/// Block `bi`'s η_c under each record (`None`: never overturned), checked
/// to be of the records in order; on a floor the ground's η (the IMs are
/// the ground record's).
fn ground_eta(
    caps: &[crate::tables::sweep::CapacityRow],
    rows: &[RecordRow],
    n_blocks: usize,
    bi: usize,
) -> Result<Vec<Option<f64>>, ImsError> {
    (0..rows.len())
        .map(|ri| {
            let c = &caps[ri * n_blocks + bi];
            if c.record_id != rows[ri].record_id {
                return Err(ImsError::Mismatch(format!(
                    "capacity {} is of record {}, the records table's is {}",
                    c.case_id, c.record_id, rows[ri].record_id
                )));
            }
            Ok(c.eta_c.map(|e| e * c.pfa_over_pga.unwrap_or(1.0)))
        })
        .collect()
}

/// One block's row of one IM.
fn efficiency_row(b: &BlockRow, e: efficiency::Efficiency, rank: Option<i64>) -> EfficiencyRow {
    EfficiencyRow {
        block_index: b.block_index,
        block: b.block.clone(),
        p: b.p,
        eps: b.eps,
        im: e.im,
        unit: e.unit.to_string(),
        n: e.n as i64,
        median: e.median,
        median_dimensionless: e.median_dimensionless.map(|(v, _)| v),
        dimensionless: e.median_dimensionless.map(|(_, n)| n.to_string()),
        beta: e.beta,
        lilliefors_p: e.lilliefors_p,
        rank,
        slope: e.slope,
    }
}

/// Every record's IMs, on every core.
pub fn record_ims(rows: &[RecordRow]) -> Result<Vec<RecordIms>, ImsError> {
    rows.par_iter()
        .map(|r| {
            RecordIms::of_record(&r.accel_g, r.dt_s, &[])
                .ok_or_else(|| ImsError::NoMotion(r.record_id.clone()))
        })
        .collect()
}

/// The IMs of each record's floor motion through `building` (the motion
/// the blocks feel, whose PGA is the PFA), on every core.
fn felt_ims(
    building: &crate::floor::Building,
    rows: &[RecordRow],
) -> Result<Vec<RecordIms>, ImsError> {
    rows.par_iter()
        .map(|r| {
            let f = building
                .floor_motion(&r.accel_g, r.dt_s)
                .map_err(|e| ImsError::Floor(r.record_id.clone(), e.to_string()))?;
            RecordIms::of_record(&f.accel_g, f.dt_s, &[])
                .ok_or_else(|| ImsError::NoMotion(r.record_id.clone()))
        })
        .collect()
}

/// One row per record × floor demand (PFA, PFV, FSA(T)), records in order.
fn floor_rows(rows: &[RecordRow], felt: &[RecordIms]) -> Vec<RecordImRow> {
    let demands = Im::floor_measures();
    rows.iter()
        .zip(felt)
        .flat_map(|(r, m)| {
            demands.iter().filter_map(move |&im| {
                Some(RecordImRow {
                    record_id: r.record_id.clone(),
                    im: im.name(),
                    unit: im.unit().to_string(),
                    period_s: match im {
                        Im::Fsa(t) => Some(t),
                        _ => None,
                    },
                    value: m.value(im)?,
                })
            })
        })
        .collect()
}

/// Text records' rows, records in order: the floor's demands, then the
/// measures that name no ground (Arias, CAV, D5–95, Tm: the records'
/// properties).
fn stood_on_rows(rows: &[RecordRow], ims: &[RecordIms]) -> Vec<RecordImRow> {
    (0..rows.len())
        .flat_map(|k| {
            let (r, m) = (&rows[k..=k], &ims[k..=k]);
            let any = im_rows(r, m).into_iter();
            let any = any.filter(|r| r.im.parse().is_ok_and(|im: Im| im.of_any_motion()));
            floor_rows(r, m).into_iter().chain(any)
        })
        .collect()
}

/// The records' IMs as the stage wrote them (`record_ims` of the study
/// folder `dir`), by record id: the records' own measures, which for a
/// study whose blocks stand on its records (`stood_on`: text records, whose
/// rows are the floor's PFA, PFV and FSA(T)) are its floor rows.
pub fn read_record_ims(
    dir: &std::path::Path,
    stood_on: bool,
) -> Result<BTreeMap<String, RecordIms>, ImsError> {
    let rows: Vec<RecordImRow> = reduce::read(dir, RECORD_IMS)?;
    let mut values: BTreeMap<String, Vec<(Im, f64)>> = BTreeMap::new();
    for r in rows {
        let im = r
            .im
            .parse::<Im>()
            .map_err(|e| ImsError::RecordIms(format!("record_ims: record {}: {e}", r.record_id)))?;
        if im.floor() != stood_on {
            // A floor study's floor demands are of the floor motion, not
            // the record; text records' are the records' own.
            continue;
        }
        values
            .entry(r.record_id)
            .or_default()
            .push((im.of_motion(), r.value));
    }
    values
        .into_iter()
        .map(|(id, v)| {
            let ims = RecordIms::from_values(v).ok_or_else(|| {
                let peak = if stood_on { "PFA" } else { "PGA" };
                ImsError::RecordIms(format!("record_ims: record {id} has no {peak}"))
            })?;
            Ok((id, ims))
        })
        .collect()
}

/// Adds to each motion's measures its pair's RotD50 and RotD100 (a study
/// over orientations: the motions are the pairs' rotated components).
fn with_pair_ims(study: &Study, rows: &[RecordRow], ims: &mut [RecordIms]) -> Result<(), ImsError> {
    let pairs = records::select_pairs(&study.plan, &study.records_table())?;
    let rotd: Vec<crate::im::rotd::PairIms> = pairs
        .par_iter()
        .map(|p| {
            crate::im::rotd::PairIms::of_pair(&p.pair, &[])
                .map_err(|_| ImsError::NoMotion(p.a.record_id.clone()))
        })
        .collect::<Result<_, _>>()?;
    let key = |r: &RecordRow| (r.meta.set.clone(), r.meta.pair.clone());
    for (r, m) in rows.iter().zip(ims.iter_mut()) {
        let k = pairs
            .iter()
            .position(|p| key(&p.a) == key(r))
            .ok_or_else(|| ImsError::Mismatch(format!("record {} is of no pair", r.record_id)))?;
        m.extend(rotd[k].values());
    }
    Ok(())
}

/// One row per record × measure, records in order.
fn im_rows(rows: &[RecordRow], ims: &[RecordIms]) -> Vec<RecordImRow> {
    rows.iter()
        .zip(ims)
        .flat_map(|(r, m)| {
            m.iter().map(|(im, value)| RecordImRow {
                record_id: r.record_id.clone(),
                im: im.name(),
                unit: im.unit().to_string(),
                period_s: match im {
                    Im::Sa(t) | Im::RotD50(Rotated::Sa(t)) | Im::RotD100(Rotated::Sa(t)) => Some(t),
                    _ => None,
                },
                value,
            })
        })
        .collect()
}
