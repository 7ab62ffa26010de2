//! The sweep's files on disk besides its final tables: the part files that
//! hold completed chunks (their paths, and the check that a part holds what
//! its chunk should before it is reused), the temporaries a killed run
//! leaves, and the clean-up once the final tables are in place.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use super::error::SweepError;
use super::layout::{final_names, SweepMeta};
use crate::stages::stage::{Shard, Study};
use crate::tables::sweep::{CapacityRow, IdaRow};
use crate::tables::{self, TableError};

/// Once the final tables are in place: removes this run's parts, and the
/// tables the new ones supersede (shards after an unsharded run and the
/// reverse); returns the names of the superseded tables it removed (their
/// temporaries not counted).
pub(super) fn clean_up(
    study: &Study,
    mine: &[usize],
    shard: Option<Shard>,
) -> Result<Vec<String>, SweepError> {
    let parts = study.path("parts");
    for &c in mine {
        let (ida_part, cap_part) = part_paths(&parts, c);
        let _ = fs::remove_file(ida_part);
        let _ = fs::remove_file(cap_part);
    }
    // Only if empty (other shards may still write here).
    let _ = fs::remove_dir(&parts);
    // The tables this run supersedes, and the temporaries a killed run left
    // of them: after an unsharded run every shard's; after a shard of N,
    // the unsharded tables and the shards of another count (a re-sharded
    // sweep). The lock refuses every other writer of those names.
    let (ida, cap) = final_names(None);
    let superseded = |table: &str| {
        let a_shard = table.contains(".shard-") && table.ends_with(".parquet");
        match shard {
            None => a_shard,
            Some(done) => {
                table == ida
                    || table == cap
                    || a_shard && !table.ends_with(&format!("-of-{}.parquet", done.n))
            }
        }
    };
    let removed = remove_where(&study.dir, |name| {
        superseded(crate::tables::temporary_of(name).map_or(name, |(table, _pid)| table))
    })?;
    Ok(removed
        .into_iter()
        .filter(|name| crate::tables::temporary_of(name).is_none())
        .collect())
}

/// How many chunks have a capacity part in `parts` (none without the
/// folder): what an interrupted sweep saved, checked only when resumed.
pub(super) fn saved_chunks(parts: &Path) -> usize {
    let Ok(entries) = fs::read_dir(parts) else {
        return 0;
    };
    entries
        .filter_map(|e| e.ok())
        .filter(|e| {
            let name = e.file_name();
            let name = name.to_string_lossy();
            name.starts_with("cap-") && name.ends_with(".parquet")
        })
        .count()
}

pub(super) fn part_paths(parts: &Path, c: usize) -> (PathBuf, PathBuf) {
    (
        parts.join(format!("ida-{c:06}.parquet")),
        parts.join(format!("cap-{c:06}.parquet")),
    )
}

/// Why a part cannot be reused.
pub(super) enum PartProblem {
    Absent,
    /// From another plan (the settings changed): recomputed silently.
    Stale,
    /// Current plan, wrong content (copied over, truncated): recomputed and
    /// logged, naming the part file at fault.
    Corrupt(std::path::PathBuf, String),
}

/// Trusts a chunk's parts by what they hold: the current plan's hash, this
/// chunk's index, one capacity per case of the chunk in order, and exactly
/// the runs each capacity counts.
pub(super) fn verify_part(
    ida_part: &Path,
    cap_part: &Path,
    hash: &str,
    chunk: usize,
    cases: std::ops::Range<usize>,
) -> Result<(), PartProblem> {
    if !(ida_part.exists() && cap_part.exists()) {
        return Err(PartProblem::Absent);
    }
    for p in [ida_part, cap_part] {
        let meta = SweepMeta::read(p)
            .map_err(|e| PartProblem::Corrupt(p.into(), format!("unreadable: {e}")))?;
        if meta.plan_hash.as_deref() != Some(hash) {
            return Err(PartProblem::Stale);
        }
        if meta.chunk != Some(chunk.to_string()) {
            return Err(PartProblem::Corrupt(
                p.into(),
                format!(
                    "its metadata says chunk {}",
                    meta.chunk.as_deref().unwrap_or("(none)")
                ),
            ));
        }
    }
    let corrupt = |p: &Path, e: TableError| PartProblem::Corrupt(p.into(), e.to_string());
    let caps: Vec<CapacityRow> = tables::read(cap_part).map_err(|e| corrupt(cap_part, e))?;
    let expected: Vec<i64> = cases.map(|c| c as i64).collect();
    let got: Vec<i64> = caps.iter().map(|c| c.case_id).collect();
    if got != expected {
        return Err(PartProblem::Corrupt(
            cap_part.into(),
            format!(
                "it holds cases {}, expected {}",
                span(&got),
                span(&expected)
            ),
        ));
    }
    let ida: Vec<IdaRow> = tables::read(ida_part).map_err(|e| corrupt(ida_part, e))?;
    let mut counts = vec![0i64; caps.len()];
    for r in &ida {
        let k = r.case_id - expected[0];
        if k < 0 || k as usize >= counts.len() {
            return Err(PartProblem::Corrupt(
                ida_part.into(),
                format!("its IDA points include case {}", r.case_id),
            ));
        }
        counts[k as usize] += 1;
    }
    if let Some((c, n)) = caps.iter().zip(&counts).find(|(c, n)| c.runs != **n) {
        return Err(PartProblem::Corrupt(
            ida_part.into(),
            format!(
                "case {} counts {} runs but has {n} IDA points",
                c.case_id, c.runs
            ),
        ));
    }
    Ok(())
}

fn span(ids: &[i64]) -> String {
    match (ids.first(), ids.last()) {
        (Some(a), Some(b)) => format!("{a}–{b}"),
        _ => "none".into(),
    }
}

/// Removes the files of `dir` whose names `stale` picks; returns the names
/// of those removed, sorted.
pub(super) fn remove_where(
    dir: &Path,
    stale: impl Fn(&str) -> bool,
) -> Result<Vec<String>, SweepError> {
    let entries = fs::read_dir(dir).map_err(|source| SweepError::Io {
        path: dir.into(),
        source,
    })?;
    let mut removed = Vec::new();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if stale(&name) && fs::remove_file(e.path()).is_ok() {
            removed.push(name);
        }
    }
    removed.sort();
    Ok(removed)
}

/// Removes temporary files left by a killed run (`.ida-000042.parquet.tmp-PID`),
/// only for this shard's chunks: other shards may be writing beside it.
pub(super) fn remove_stale_temporaries(dir: &Path, mine: &[usize]) -> Result<(), SweepError> {
    let mine: BTreeSet<usize> = mine.iter().copied().collect();
    remove_where(dir, |name| {
        // The writer's PID ends the name: a live writer's file is not stale.
        let Some(part) = crate::tables::orphaned_temporary(name) else {
            return false;
        };
        let chunk = part
            .strip_prefix("ida-")
            .or_else(|| part.strip_prefix("cap-"))
            .and_then(|r| r.split('.').next())
            .and_then(|c| c.parse::<usize>().ok());
        chunk.is_some_and(|c| mine.contains(&c))
    })
    .map(drop)
}
