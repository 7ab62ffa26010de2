//! Reduce stage: the sweep's runs → fractile curves, capacity fractiles,
//! lognormal checks and overturning fractions (docs/MODEL.md §5).
//!
//! Glue: reads the sweep dataset of a pipeline, groups the cases by block,
//! and calls [`crate::stats`]. Under the resurrection rule a record counts
//! as EDP = +∞ at every level at or beyond its first overturning, so the
//! runs the sweep skipped there are not needed. Reruns only when its inputs
//! (the sweep tables' bytes, the fractile definition, the crate and schema
//! versions) changed: their hash is stored in every output's metadata.

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::pipeline::{FractileDef, Plan};
use crate::stages::sweep::{self, SweepError};
use crate::stats;
use crate::tables::summary::{
    f, fo, i, s, Value, CAPACITY_FRACTILES, HORIZONTAL, LOGNORMAL, OVERTURN_FRACTION, VERTICAL,
};
use crate::tables::sweep::{read_capacities, read_ida, CapacityRow, IdaRow};
use crate::tables::{self, TableError};

pub const QUANTILES: [f64; 3] = [0.16, 0.5, 0.84];
/// EDP levels of the vertical statistics: 0.05, 0.10, …, 1.
pub const EDP_LEVELS: usize = 20;
pub const META_INPUT: &str = "rocking.reduce.input";

#[derive(Debug, thiserror::Error)]
pub enum ReduceError {
    #[error(transparent)]
    Sweep(#[from] SweepError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("the sweep tables do not match the pipeline: {0}; rerun `rocking sweep`")]
    Mismatch(String),
}

#[derive(Debug, Clone)]
pub struct ReduceReport {
    pub dir: PathBuf,
    /// True when the outputs were already up to date and nothing ran.
    pub up_to_date: bool,
    pub blocks: usize,
    pub records: usize,
    /// Blocks where lognormality of η_c is not rejected at 5 %, of those tested.
    pub lognormal_pass: (usize, usize),
    pub fractile: FractileDef,
}

/// Output file names, in writing order.
pub fn outputs(dir: &Path) -> [PathBuf; 5] {
    [
        dir.join("fractiles_horizontal.parquet"),
        dir.join("fractiles_vertical.parquet"),
        dir.join("capacity_fractiles.parquet"),
        dir.join("lognormal.parquet"),
        dir.join("overturn_fraction.parquet"),
    ]
}

/// Hash of the files' bytes and of the strings given.
pub fn fingerprint(files: &[PathBuf], extra: &[&str]) -> Result<String, ReduceError> {
    let mut h = Sha256::new();
    h.update(env!("CARGO_PKG_VERSION"));
    for e in extra {
        h.update(e.as_bytes());
        h.update([0]);
    }
    for path in files {
        let bytes = std::fs::read(path).map_err(|source| ReduceError::Io {
            path: path.clone(),
            source,
        })?;
        h.update(Sha256::digest(&bytes));
    }
    Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
}

/// Whether every file exists and carries `key = value` in its metadata.
pub fn all_current(files: &[PathBuf], key: &str, value: &str) -> bool {
    files.iter().all(|p| {
        p.exists()
            && tables::read_metadata(p)
                .map(|kv| kv.iter().any(|(k, v)| k == key && v == value))
                .unwrap_or(false)
    })
}

/// One record's IDA for one block, at the grid levels.
struct RecordIda<'a> {
    cap: &'a CapacityRow,
    /// (η, EDP, overturned) at the grid levels that were run, in order.
    levels: Vec<(f64, f64, bool)>,
    /// Index of the first level that overturned.
    first_over: Option<usize>,
}

pub fn run(plan: &Plan, outputs_root: &Path, force: bool) -> Result<ReduceReport, ReduceError> {
    let dir = outputs_root.join(&plan.name);
    let (ida_files, cap_files) = sweep::dataset(&dir)?;
    let inputs: Vec<PathBuf> = ida_files.iter().chain(&cap_files).cloned().collect();
    let fractile_name = format!("{:?}", plan.fractile);
    let schema_tag = "fractiles_horizontal/1 fractiles_vertical/1 capacity_fractiles/1 lognormal/1 overturn_fraction/1";
    let input_hash = fingerprint(&inputs, &[&fractile_name, schema_tag])?;
    let outs = outputs(&dir);
    let n_blocks = plan.blocks.len();
    if !force && all_current(&outs, META_INPUT, &input_hash) {
        return Ok(ReduceReport {
            dir,
            up_to_date: true,
            blocks: n_blocks,
            records: 0,
            lognormal_pass: (0, 0),
            fractile: plan.fractile,
        });
    }

    // The sweep must be of this pipeline's settings (a leftover from an edit is refused).
    for f in &cap_files {
        let kv = tables::read_metadata(f)?;
        let made = kv
            .iter()
            .find(|(k, _)| k == sweep::META_SETTINGS)
            .map(|(_, v)| v.as_str());
        if made != Some(plan.sweep_settings().as_str()) {
            return Err(ReduceError::Mismatch(format!(
                "{} was made with other settings than the pipeline's",
                f.display()
            )));
        }
    }
    let mut caps = read_capacities(&cap_files)?;
    caps.sort_by_key(|c| c.case_id);
    let mut ida = read_ida(&ida_files)?;
    ida.sort_by_key(|r| r.case_id);
    if caps.len() % n_blocks != 0 {
        return Err(ReduceError::Mismatch(format!(
            "{} capacities for {n_blocks} blocks",
            caps.len()
        )));
    }
    let n_records = caps.len() / n_blocks;
    let levels = plan
        .grid
        .levels()
        .map_err(|e| ReduceError::Mismatch(e.to_string()))?;

    // Split the IDA points by case.
    let mut by_case: Vec<Vec<&IdaRow>> = vec![Vec::new(); caps.len()];
    for r in &ida {
        let k = r.case_id as usize;
        if k >= by_case.len() {
            return Err(ReduceError::Mismatch(format!(
                "IDA point of case {k} beyond the capacities"
            )));
        }
        by_case[k].push(r);
    }

    let def = plan.fractile;
    let (mut horizontal, mut vertical, mut cap_fr, mut lognormal, mut fraction) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut pass = (0, 0);
    for (bi, block) in plan.blocks.iter().enumerate() {
        let records: Vec<RecordIda> = (0..n_records)
            .map(|ri| {
                let k = ri * n_blocks + bi;
                let cap = &caps[k];
                let levels_run: Vec<(f64, f64, bool)> = by_case[k]
                    .iter()
                    .filter(|r| r.run_kind == "level")
                    .map(|r| (r.eta, r.edp, r.overturned))
                    .collect();
                let first_over = levels_run.iter().position(|l| l.2);
                RecordIda {
                    cap,
                    levels: levels_run,
                    first_over,
                }
            })
            .collect();
        for r in &records {
            if r.cap.p != block.p || r.cap.eps != block.eps {
                return Err(ReduceError::Mismatch(format!(
                    "case {} is p = {}, ε = {} in the tables but p = {}, ε = {} in the pipeline",
                    r.cap.case_id, r.cap.p, r.cap.eps, block.p, block.eps
                )));
            }
            let needed = r.first_over.map_or(levels.len(), |f| f + 1);
            if r.levels.len() < needed {
                return Err(ReduceError::Mismatch(format!(
                    "case {} has too few level runs",
                    r.cap.case_id
                )));
            }
        }
        let key = |v: &mut Vec<Value>| {
            v.push(s(&block.name));
            v.push(f(block.p));
            v.push(f(block.eps));
        };

        // Horizontal: EDP given η, +∞ at and beyond a record's first overturning.
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
            let q: Vec<f64> = QUANTILES
                .iter()
                .map(|&q| stats::fractile(&edp, q, def).expect("records"))
                .collect();
            let mut row = Vec::new();
            key(&mut row);
            row.extend([
                i(j as i64),
                f(eta),
                f(q[0]),
                f(q[1]),
                f(q[2]),
                i(n_records as i64),
                i(n_over as i64),
            ]);
            horizontal.push(row);
            h_q.push((eta, q));

            // Overturning fractions: plain needs a run of every record at this level.
            let plain: Option<usize> = records
                .iter()
                .map(|r| r.levels.get(j).map(|l| usize::from(l.2)))
                .sum::<Option<usize>>();
            let mut row = Vec::new();
            key(&mut row);
            row.extend([
                i(j as i64),
                f(eta),
                fo(plain.map(|c| c as f64 / n_records as f64)),
                f(n_over as f64 / n_records as f64),
            ]);
            fraction.push(row);
        }

        // Vertical: the first (largest) η at which each record's EDP reaches e.
        for k in 1..=EDP_LEVELS {
            let e = k as f64 / EDP_LEVELS as f64;
            let mut etas = Vec::with_capacity(n_records);
            let mut not_reached = 0;
            for r in &records {
                match first_eta_reaching(r, plan.grid.eta_max, e) {
                    Some(eta) => etas.push(eta),
                    None => {
                        etas.push(0.0);
                        not_reached += 1;
                    }
                }
            }
            etas.sort_by(|a, b| a.total_cmp(b));
            let q: Vec<f64> = QUANTILES
                .iter()
                .map(|&q| stats::fractile(&etas, q, def).expect("records"))
                .collect();
            let mut row = Vec::new();
            key(&mut row);
            row.extend([
                f(e),
                f(q[0]),
                f(q[1]),
                f(q[2]),
                i(n_records as i64),
                i(not_reached),
            ]);
            vertical.push(row);
        }

        // Capacity fractiles: of η_c over the records (a record that never
        // overturned counts as η_c = 0, stronger than any level), and the
        // horizontal counterpart: the largest level whose EDP fractile is ≥ 1.
        let mut eta_c: Vec<f64> = records.iter().map(|r| r.cap.eta_c.unwrap_or(0.0)).collect();
        let censored = records.iter().filter(|r| r.cap.eta_c.is_none()).count();
        eta_c.sort_by(|a, b| a.total_cmp(b));
        let mut q_eta = [0.0; 3];
        for (qi, &q) in QUANTILES.iter().enumerate() {
            let v = stats::fractile(&eta_c, q, def).expect("records");
            q_eta[qi] = v;
            let horiz = h_q
                .iter()
                .find(|(_, hq)| hq[qi] >= 1.0)
                .map(|(eta, _)| *eta);
            let mut row = Vec::new();
            key(&mut row);
            row.extend([
                f(q),
                f(v),
                fo(horiz),
                i(n_records as i64),
                i(censored as i64),
            ]);
            cap_fr.push(row);
        }

        // Lognormality of η_c.
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
        if let Some(_t) = test {
            pass.1 += 1;
            pass.0 += usize::from(!rejected);
        }
        let mut row = Vec::new();
        key(&mut row);
        row.extend([
            i(logs.len() as i64),
            fo(mean.is_finite().then(|| mean.exp())),
            fo(sd.is_finite().then_some(sd)),
            fo(ok(q_eta[1])),
            fo(beta_fr),
            fo(test.map(|t| t.d)),
            fo(test.map(|t| t.p_value)),
            fo((logs.len() >= 5).then(|| stats::lilliefors_critical_value(logs.len(), 0.05))),
            Value::B(rejected),
        ]);
        lognormal.push(row);
    }

    let settings = vec![
        (META_INPUT.to_string(), input_hash),
        ("rocking.reduce.fractile".to_string(), fractile_name),
        (
            "rocking.reduce.quantiles".to_string(),
            "0.16,0.5,0.84".to_string(),
        ),
    ];
    HORIZONTAL.write(&outs[0], &horizontal, &settings)?;
    VERTICAL.write(&outs[1], &vertical, &settings)?;
    CAPACITY_FRACTILES.write(&outs[2], &cap_fr, &settings)?;
    LOGNORMAL.write(&outs[3], &lognormal, &settings)?;
    OVERTURN_FRACTION.write(&outs[4], &fraction, &settings)?;
    Ok(ReduceReport {
        dir,
        up_to_date: false,
        blocks: n_blocks,
        records: n_records,
        lognormal_pass: pass,
        fractile: def,
    })
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
