//! Reading a study folder's sweep tables as one dataset: the unsharded
//! tables or all N shards of one plan (never a mix), their capacities and IDA
//! points in case order.

use std::collections::BTreeSet;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use super::layout::{final_names, SweepMeta};
use crate::ida::RunKind;
use crate::stages::stage::Shard;
use crate::tables::sweep::{CapacityRow, IdaRow};
use crate::tables::{self, TableError};

/// A folder's sweep tables cannot be read as one dataset.
#[derive(Debug, thiserror::Error)]
pub enum DatasetError {
    #[error("{0}: no sweep tables (run `rocking sweep` first)")]
    NoTables(PathBuf),
    #[error(
        "{dir}: holds both the unsharded sweep tables (ida_points.parquet, capacities.parquet) and \
         {shards} shard table(s) (*.shard-K-of-N.parquet); they are two versions of the same sweep: \
         remove one set"
    )]
    Mixed { dir: PathBuf, shards: usize },
    #[error("{dir}: shard tables of different shard counts ({counts}); remove the stale ones")]
    ShardCounts { dir: PathBuf, counts: String },
    #[error("{dir}: shards {missing} of the sweep are missing; run them with `rocking sweep … --shard K/{n}`")]
    MissingShards {
        dir: PathBuf,
        missing: String,
        n: usize,
    },
    #[error("{dir}: the shards come from different plans; rerun the stale ones")]
    ShardPlans { dir: PathBuf },
    #[error("{dir}: only one of ida_points.parquet and capacities.parquet is there; rerun `rocking sweep`")]
    HalfTables { dir: PathBuf },
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("{path}")]
    Io {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
}

/// The sweep tables of a study folder, as one dataset: the unsharded tables,
/// or all N shards (every one required, all from the same plan), never a mix.
/// Returns (ida_points files, capacities files).
pub fn dataset(dir: &Path) -> Result<(Vec<PathBuf>, Vec<PathBuf>), DatasetError> {
    let entries = fs::read_dir(dir).map_err(|source| DatasetError::Io {
        path: dir.into(),
        source,
    })?;
    let mut shard_files = 0;
    let mut counts = BTreeSet::new();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name
            .strip_prefix("capacities.shard-")
            .or_else(|| name.strip_prefix("ida_points.shard-"))
            .and_then(|r| r.strip_suffix(".parquet"))
        else {
            continue;
        };
        shard_files += 1;
        if let Some(n) = rest
            .split_once("-of-")
            .and_then(|(_, n)| n.parse::<usize>().ok())
        {
            counts.insert(n);
        }
    }
    let (ida, cap) = final_names(None);
    let (ida, cap) = (dir.join(ida), dir.join(cap));
    match (ida.exists(), cap.exists(), shard_files) {
        (true, true, 0) => return Ok((vec![ida], vec![cap])),
        (true, _, s) | (_, true, s) if s > 0 => {
            return Err(DatasetError::Mixed {
                dir: dir.into(),
                shards: s,
            })
        }
        (true, false, _) | (false, true, _) => {
            return Err(DatasetError::HalfTables { dir: dir.into() })
        }
        _ => {}
    }
    let n = match counts.len() {
        0 => return Err(DatasetError::NoTables(dir.into())),
        1 => *counts.iter().next().expect("one"),
        _ => {
            return Err(DatasetError::ShardCounts {
                dir: dir.into(),
                counts: counts
                    .iter()
                    .map(|n| format!("of {n}"))
                    .collect::<Vec<_>>()
                    .join(", "),
            })
        }
    };
    let mut idas = Vec::new();
    let mut caps = Vec::new();
    let mut missing = Vec::new();
    let mut hashes = BTreeSet::new();
    // Shards are looked for up to N, but never more than ten past the ones
    // that exist: a file name claiming a huge N must not make this loop long.
    let mut k = 0;
    while k < n && missing.len() < 10 {
        k += 1;
        let (i, c) = final_names(Some(Shard { k, n }));
        let (i, c) = (dir.join(i), dir.join(c));
        if !(i.exists() && c.exists()) {
            missing.push(format!("{k}/{n}"));
            continue;
        }
        hashes.insert(SweepMeta::read(&c)?.plan_hash.unwrap_or_default());
        idas.push(i);
        caps.push(c);
    }
    if !missing.is_empty() {
        if k < n {
            missing.push("…".into());
        }
        return Err(DatasetError::MissingShards {
            dir: dir.into(),
            missing: missing.join(", "),
            n,
        });
    }
    if hashes.len() > 1 {
        return Err(DatasetError::ShardPlans { dir: dir.into() });
    }
    Ok((idas, caps))
}

/// Capacities of a dataset, in case order (shards interleaved back).
pub fn read_capacities(dir: &Path) -> Result<Vec<CapacityRow>, DatasetError> {
    let (_, caps) = dataset(dir)?;
    let mut rows: Vec<CapacityRow> = tables::read_all(&caps)?;
    rows.sort_by_key(|r| r.case_id);
    Ok(rows)
}

/// IDA points of a dataset, in case order (run order within a case).
pub fn read_ida(dir: &Path) -> Result<Vec<IdaRow>, DatasetError> {
    let (idas, _) = dataset(dir)?;
    let mut rows: Vec<IdaRow> = tables::read_all(&idas)?;
    rows.sort_by_key(|r| r.case_id); // stable: keeps run order within a case
    Ok(rows)
}

/// Runs kinds written by the sweep, for readers that filter grid levels.
pub fn is_level(r: &IdaRow) -> bool {
    r.run_kind == RunKind::Level
}
