//! The ims stage: the records' intensity measures, and each block's
//! capacity dispersion in every IM (docs/MODEL.md §14).
//!
//! Glue: reads the pipeline's records, capacities and blocks, calls
//! [`crate::im`] and writes `record_ims`, `record_spectra` and
//! `im_efficiency` through [`crate::tables::ims`].

use std::collections::BTreeMap;
use std::path::PathBuf;

use rayon::prelude::*;

use super::reduce::{self, ReduceError};
use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use super::{records, sweep};
use crate::im::{efficiency, RecordIms};
use crate::tables::ims::{EfficiencyRow, RecordImRow, SpectrumRow};
use crate::tables::reduce::BlockRow;
use crate::tables::{self, records::RecordRow};

/// The ims stage.
pub struct Ims;

/// Output file names, in writing order.
pub const OUTPUTS: [&str; 3] = [
    "record_ims.parquet",
    "record_spectra.parquet",
    "im_efficiency.parquet",
];

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

fn run(study: &Study) -> Result<Summary, ReduceError> {
    let rows = records::select(&study.plan, &study.records_table())?;
    let ims = record_ims(&rows)?;
    let caps = sweep::read_capacities(&study.dir)?;
    let blocks: Vec<BlockRow> = reduce::read(&study.dir, "blocks.parquet")?;
    let n_blocks = blocks.len();
    if n_blocks == 0 || caps.len() != rows.len() * n_blocks {
        return Err(ReduceError::Mismatch(format!(
            "{} capacities for {} records × {n_blocks} blocks",
            caps.len(),
            rows.len()
        )));
    }
    let mut eff = Vec::new();
    let mut best: BTreeMap<String, usize> = BTreeMap::new();
    for (bi, b) in blocks.iter().enumerate() {
        let eta: Vec<Option<f64>> = (0..rows.len())
            .map(|ri| {
                let c = &caps[ri * n_blocks + bi];
                if c.record_id != rows[ri].record_id {
                    return Err(ReduceError::Mismatch(format!(
                        "capacity {} is of record {}, the records table's is {}",
                        c.case_id, c.record_id, rows[ri].record_id
                    )));
                }
                // On a floor, the ground's η (the IMs are the ground record's).
                Ok(c.eta_c.map(|e| e * c.pfa_over_pga.unwrap_or(1.0)))
            })
            .collect::<Result<_, _>>()?;
        let mut found = efficiency::of_block(&eta, &ims, b.p, b.alpha_rad);
        let mut order: Vec<usize> = (0..found.len())
            .filter(|&i| found[i].slope.is_none())
            .collect();
        order.sort_by(|&i, &j| found[i].beta.total_cmp(&found[j].beta));
        if let Some(&first) = order.first() {
            *best.entry(found[first].im.clone()).or_default() += 1;
        }
        let mut ranks = vec![None; found.len()];
        for (r, &i) in order.iter().enumerate() {
            ranks[i] = Some(r as i64 + 1);
        }
        for (e, rank) in found.drain(..).zip(ranks) {
            eff.push(EfficiencyRow {
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
            });
        }
    }
    let settings = vec![(
        "rocking.ims.damping".to_string(),
        crate::im::SPECTRAL_DAMPING.to_string(),
    )];
    let (im_rows, spectra) = im_rows(&rows, &ims);
    tables::write(&study.path(OUTPUTS[0]), &im_rows, &settings)?;
    tables::write(&study.path(OUTPUTS[1]), &spectra, &settings)?;
    tables::write(&study.path(OUTPUTS[2]), &eff, &settings)?;
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
                "wrote record_ims, record_spectra, im_efficiency in {}",
                study.dir.display()
            ),
        ],
        also_wrote: Vec::new(),
    })
}

/// Every record's IMs, on every core.
pub fn record_ims(rows: &[RecordRow]) -> Result<Vec<RecordIms>, ReduceError> {
    rows.par_iter()
        .map(|r| {
            RecordIms::of_record(&r.accel_g, r.dt_s, &[])
                .ok_or_else(|| ReduceError::NoMotion(r.record_id.clone()))
        })
        .collect()
}

/// The records' IMs as the stage wrote them (`record_ims` and
/// `record_spectra` of the study folder `dir`), by record id.
pub fn read_record_ims(dir: &std::path::Path) -> Result<BTreeMap<String, RecordIms>, ReduceError> {
    let rows: Vec<RecordImRow> = reduce::read(dir, OUTPUTS[0])?;
    let spectra: Vec<SpectrumRow> = reduce::read(dir, OUTPUTS[1])?;
    let mut sa: BTreeMap<&str, Vec<(f64, f64)>> = BTreeMap::new();
    for s in &spectra {
        sa.entry(&s.record_id)
            .or_default()
            .push((s.period_s, s.sa_g));
    }
    Ok(rows
        .into_iter()
        .map(|r| {
            let mut sa_g = sa.remove(r.record_id.as_str()).unwrap_or_default();
            sa_g.sort_by(|a, b| a.0.total_cmp(&b.0));
            let ims = RecordIms {
                pga_g: r.pga_g,
                pgv_cm_s: r.pgv_cm_s,
                pgd_cm: r.pgd_cm,
                arias_m_s: r.arias_m_s,
                cav_g_s: r.cav_g_s,
                d5_95_s: r.d5_95_s,
                pgv_pga_s: r.pgv_pga_s,
                tm_s: r.tm_s,
                avgsa_g: r.avgsa_g,
                sa_g,
            };
            (r.record_id, ims)
        })
        .collect())
}

fn im_rows(rows: &[RecordRow], ims: &[RecordIms]) -> (Vec<RecordImRow>, Vec<SpectrumRow>) {
    let mut spectra = Vec::new();
    let table = rows
        .iter()
        .zip(ims)
        .map(|(r, m)| {
            spectra.extend(m.sa_g.iter().map(|&(t, sa)| SpectrumRow {
                record_id: r.record_id.clone(),
                period_s: t,
                sa_g: sa,
            }));
            RecordImRow {
                record_id: r.record_id.clone(),
                pga_g: m.pga_g,
                pgv_cm_s: m.pgv_cm_s,
                pgd_cm: m.pgd_cm,
                arias_m_s: m.arias_m_s,
                cav_g_s: m.cav_g_s,
                d5_95_s: m.d5_95_s,
                pgv_pga_s: m.pgv_pga_s,
                tm_s: m.tm_s,
                avgsa_g: m.avgsa_g,
            }
        })
        .collect();
    (table, spectra)
}
