//! Bootstrap bands of the capacity fractiles: whole units (the manifest's
//! pairs, or records) resampled with replacement, one draw for every block.

use super::block_stats::QUANTILES;
use super::error::ReduceError;
use crate::stages::stage::Study;
use crate::stats;
use crate::tables::reduce::{CapacityBandRow, CapacityResampleRow};
use crate::tables::sweep::CapacityRow;

/// Bootstrap bands of every block's capacity fractiles. Resample `r` draws
/// whole units (pairs from the records table, or records) with replacement
/// from stream `r` of the seed and applies the one draw to every block;
/// resamples run in parallel and are collected in order, so the bytes do not
/// depend on the threads. Returns the bands and every resample's fractiles.
pub(super) fn bands(
    study: &Study,
    u: crate::pipeline::Uncertainty,
    caps: &[CapacityRow],
    per_block: &[(Vec<f64>, [f64; 3])],
) -> Result<(Vec<CapacityBandRow>, Vec<CapacityResampleRow>), ReduceError> {
    use rayon::prelude::*;
    let plan = study.plan.records_study()?;
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
    unit: crate::stats::ResampleUnit,
    caps: &[CapacityRow],
    per_block: &[(Vec<f64>, [f64; 3])],
) -> Result<Vec<usize>, ReduceError> {
    use crate::stats::ResampleUnit;
    let plan = &study.plan;
    let n_blocks = plan.blocks().len();
    let n_records = per_block.first().map_or(0, |b| b.0.len());
    if unit == ResampleUnit::Record {
        return Ok((0..n_records).collect());
    }
    // Case k = ri·n_blocks + bi.
    let rows = crate::records::select(plan, &study.records_table())?;
    let pair_of: std::collections::HashMap<&str, &str> = rows
        .iter()
        .filter_map(|r| Some((r.record_id.as_str(), r.meta.pair.as_deref()?)))
        .collect();
    let pairs = (0..n_records)
        .map(|ri| {
            let id = caps[ri * n_blocks].record_id.as_str();
            pair_of
                .get(id)
                .copied()
                .ok_or_else(|| ReduceError::NoPair(id.to_string()))
        })
        .collect::<Result<Vec<&str>, _>>()?;
    Ok(crate::stats::numbered_by_first(&pairs))
}
