//! The previous sweep's rows for the records it ran as they are now: a
//! rerun after records were added, removed or edited computes only the
//! cases of the records whose key ([`RecordKeys`]) is new. A case's rows depend
//! on nothing but its record's motion, its block and the settings, all in
//! the key, so the rows taken are the ones a computation would give, to
//! the bit (only the case's number moves, with the records before it).
//!
//! Taken only from the unsharded tables of the last unsharded sweep, as
//! that sweep wrote them (their hashes in its fingerprint), and never when
//! the stage is forced (`--force`, `--from`): then everything is computed.
//! The rows taken are held in memory until written (about 200 bytes an
//! IDA row), so tables of more than [`MAX_TAKEN_ROWS`] are not read.
//!
//! [`RecordKeys`]: super::layout::RecordKeys

use std::collections::{BTreeMap, BTreeSet};

use super::cases::{CaseResult, Prepared};
use super::layout::{final_names, RecordKeys, META_RECORD_KEYS};
use crate::stages::fingerprint;
use crate::stages::stage::Context;
use crate::tables::sweep::{CapacityRow, IdaRow};
use crate::tables::{self, TableError};

/// The most IDA rows a rerun takes from the previous table (about 1 GB
/// held): past them, every case is computed, as before the rows were
/// taken, with the sweep's bounded memory.
pub(super) const MAX_TAKEN_ROWS: usize = 5_000_000;

/// Why the previous tables were not read.
pub(super) enum NotTaken {
    Unreadable(TableError),
    TooLarge(usize),
}

impl From<TableError> for NotTaken {
    fn from(e: TableError) -> Self {
        NotTaken::Unreadable(e)
    }
}

/// The results of the cases among `todo` that the previous sweep's tables
/// hold for an unchanged record, by case, and how many records they are;
/// empty where nothing can be taken. `Err` says why tables that looked
/// reusable were not read (the cases are then computed).
pub(super) fn previous(
    cx: &Context,
    prep: &Prepared,
    todo: &[usize],
) -> Result<(Vec<(usize, CaseResult)>, usize), NotTaken> {
    let study = cx.study;
    if cx.shard.is_some() || cx.forced || !fingerprint::outputs_as_written(study, &super::Sweep) {
        return Ok((Vec::new(), 0));
    }
    let (ida_name, cap_name) = final_names(None);
    let (ida_path, cap_path) = (study.path(&ida_name), study.path(&cap_name));
    let Some(keys) = RecordKeys::written(&cap_path, META_RECORD_KEYS)? else {
        return Ok((Vec::new(), 0));
    };
    let n_blocks = prep.blocks.len();
    let wanted: BTreeSet<usize> = todo.iter().copied().collect();
    let unchanged: Vec<usize> = (0..prep.records.len())
        .filter(|&ri| keys.get(&prep.records[ri].record_id) == Some(&prep.record_keys[ri]))
        .filter(|&ri| (0..n_blocks).any(|bi| wanted.contains(&(ri * n_blocks + bi))))
        .collect();
    if unchanged.is_empty() {
        return Ok((Vec::new(), 0));
    }
    let rows = tables::row_count(&ida_path)?;
    if rows > MAX_TAKEN_ROWS {
        return Err(NotTaken::TooLarge(rows));
    }
    let caps: Vec<CapacityRow> = tables::read(&cap_path)?;
    let mut ida_by_case: BTreeMap<i64, Vec<IdaRow>> = BTreeMap::new();
    for row in tables::read::<IdaRow>(&ida_path)? {
        ida_by_case.entry(row.case_id).or_default().push(row);
    }
    let mut caps_by_record: BTreeMap<&str, Vec<&CapacityRow>> = BTreeMap::new();
    for row in &caps {
        caps_by_record.entry(&row.record_id).or_default().push(row);
    }
    let (mut taken, mut records) = (Vec::new(), 0);
    for ri in unchanged {
        let id = prep.records[ri].record_id.as_str();
        let Some(old) = caps_by_record.get(id) else {
            continue;
        };
        // The same blocks in the same order (the key holds the settings,
        // blocks among them): checked again on the rows themselves.
        let same =
            old.len() == n_blocks && old.iter().zip(&prep.blocks).all(|(r, b)| r.block == b.name);
        if !same {
            continue;
        }
        let mut results = Vec::new();
        for (bi, cap) in old.iter().enumerate() {
            let case = ri * n_blocks + bi;
            let mut ida = ida_by_case.remove(&cap.case_id).unwrap_or_default();
            if ida.len() as i64 != cap.runs {
                // Not the runs its capacity counts: the record is computed.
                results.clear();
                break;
            }
            if !wanted.contains(&case) {
                continue;
            }
            for row in &mut ida {
                row.case_id = case as i64;
            }
            let capacity = CapacityRow {
                case_id: case as i64,
                ..(*cap).clone()
            };
            results.push((
                case,
                CaseResult {
                    ida,
                    capacity,
                    check_runs: 0,
                    intervals: 0,
                    reused: true,
                },
            ));
        }
        if !results.is_empty() {
            records += 1;
            taken.extend(results);
        }
    }
    Ok((taken, records))
}
