//! The sweep's writer: gathers the cases' results into their chunks, adds
//! each chunk in order to the final tables as soon as it is complete, and
//! saves the completed chunks as part files once [`Hold`] allows.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::io;
use std::path::Path;
use std::time::Instant;

use super::cases::{CaseResult, Prepared, Tally};
use super::error::SweepError;
use super::layout::CHUNK_CASES;
use super::parts::part_paths;
use crate::pipeline::Plan;
use crate::tables;
use crate::tables::sweep::{CapacityRow, IdaRow};

/// Environment variable for fault-injection tests: abort the process (as a
/// crash would) once this many chunks are complete (and those due saved).
pub const FAULT_ENV: &str = "ROCKING_FAULT_AFTER_CHUNKS";

/// Environment variable for tests: ask every run to stop, as Ctrl-C does
/// ([`crate::physics::interrupt`]), once this many chunks are complete.
pub const INTERRUPT_ENV: &str = "ROCKING_INTERRUPT_AFTER_CHUNKS";

/// Environment variable for tests: each worker waits this many
/// milliseconds before each case, so that a sweep lasts long enough for a
/// signal sent from outside to find it running, however loaded the machine.
pub const CASE_DELAY_ENV: &str = "ROCKING_CASE_DELAY_MS";

/// How long a sweep runs before it saves its first parts. Saving a chunk
/// (two Parquet files created, encoded, synced and renamed, then deleted at
/// the end) costs the writer thread about 2 ms of CPU, taken from the
/// workers on a machine with as many cores as workers: saving all 165 of
/// the paper sweep's chunks made it 3 % slower (docs/BENCHMARKS.md), and a
/// sweep shorter than this is quicker to redo than to save. The chunks
/// completed before are saved at the first case's result after it, and
/// from then on every chunk as it completes: beyond the unfinished chunks,
/// which a crash always loses, it loses at most this much work.
pub const CHECKPOINT_AFTER: std::time::Duration = std::time::Duration::from_secs(10);

/// The most IDA rows held unsaved (about 130 MB as Arrow arrays): a sweep
/// that completes this many before [`CHECKPOINT_AFTER`] saves them then.
pub const MAX_HELD_ROWS: usize = 1_000_000;

/// Environment variable for tests: hold exactly this many first chunks
/// (instead of [`CHECKPOINT_AFTER`]'s worth) before saving any; `0` saves
/// every chunk as it completes.
pub const HOLD_ENV: &str = "ROCKING_HOLD_CHUNKS";

/// Gathers finished cases into their chunks and adds each chunk, in order,
/// to the final tables as soon as it and every chunk before it are
/// complete (a resumed chunk from its parts); the tables are committed once
/// the last chunk is in, so the sweep's end has no tables left to assemble.
/// A slow case holds back only the writes, not the workers. The completed
/// chunks are saved as parts, in order, once [`Hold`] allows (checked at
/// every case's result; those held first): the saved parts are always the
/// first chunks of the sweep, as a crash leaves them.
pub(super) struct ChunkWriter<'a, R> {
    pub(super) prep: &'a Prepared,
    pub(super) plan: &'a Plan,
    pub(super) parts: &'a Path,
    /// Fault injection: abort once this many chunks are complete (and
    /// those due saved).
    pub(super) fault_after: Option<usize>,
    /// Ctrl-C's stop asked for once this many chunks are complete.
    pub(super) interrupt_after: Option<usize>,
    pub(super) report: &'a R,
    /// The chunks still to add to the final tables, in order.
    pub(super) order: VecDeque<usize>,
    /// Those of them whose parts an earlier run saved.
    pub(super) resumed: BTreeSet<usize>,
    /// The final tables, written as the chunks come in.
    pub(super) ida: tables::Appender<IdaRow>,
    pub(super) cap: tables::Appender<CapacityRow>,
    /// Chunks with some cases in, by index: each case's result in its slot.
    pub(super) pending: BTreeMap<usize, Vec<Option<CaseResult>>>,
    /// When the completed chunks start being saved as parts.
    pub(super) hold: Hold,
    /// Chunks complete but not saved yet, in order.
    pub(super) held: Vec<Held>,
    /// Chunks this run completed.
    pub(super) completed: usize,
    pub(super) tally: Tally,
}

/// A completed chunk's rows, as added to the final tables.
pub(super) struct Held {
    chunk: usize,
    ida: tables::Batches<IdaRow>,
    cap: tables::Batches<CapacityRow>,
}

/// When a sweep starts saving the chunks it completes as parts.
#[derive(Debug, Clone, Copy)]
pub(super) enum Hold {
    /// At this instant, or once [`MAX_HELD_ROWS`] IDA rows are held.
    Until(Instant),
    /// Once more than this many chunks are complete ([`HOLD_ENV`]).
    Chunks(usize),
}

impl Hold {
    /// Whether the held chunks are saved now, with `completed` chunks
    /// complete and `held_rows` IDA rows held.
    fn due(self, completed: usize, held_rows: usize, now: Instant) -> bool {
        match self {
            Hold::Until(t) => held_rows >= MAX_HELD_ROWS || now >= t,
            Hold::Chunks(n) => completed > n,
        }
    }
}

impl<R: Fn(&Tally)> ChunkWriter<'_, R> {
    /// Takes one case's result, adds the chunks it completes to the final
    /// tables, and saves the held chunks as parts if that is due (also
    /// while a slow case holds the next chunk back).
    pub(super) fn take(&mut self, case: usize, result: CaseResult) -> Result<(), SweepError> {
        self.slot(case, result);
        self.flush()?;
        self.checkpoint()
    }

    /// Puts one case's result in its chunk's slot.
    fn slot(&mut self, case: usize, result: CaseResult) {
        let c = case / CHUNK_CASES;
        let range = self.prep.chunk_cases(c);
        self.pending
            .entry(c)
            .or_insert_with(|| range.clone().map(|_| None).collect())[case - range.start] =
            Some(result);
    }

    /// Saves the held chunks as parts, in order, if [`Hold`] says so.
    fn checkpoint(&mut self) -> Result<(), SweepError> {
        let held_rows = self.held.iter().map(|h| h.ida.rows()).sum();
        if self.held.is_empty() || !self.hold.due(self.completed, held_rows, Instant::now()) {
            return Ok(());
        }
        self.save_held()
    }

    /// The sweep's end at a case's `error` (Ctrl-C's among them): the
    /// results still coming (`rest`, as the workers stop) are taken, and
    /// every chunk complete, in order or beyond a gap, is saved as parts
    /// now, whatever [`Hold`] says, so that a rerun resumes from them (it
    /// trusts each part by its content); `error` is returned (a failure to
    /// save is the lesser news, and leaves what any failure leaves: whole
    /// parts or none).
    pub(super) fn keep_completed(
        mut self,
        error: SweepError,
        rest: impl Iterator<Item = (usize, Result<CaseResult, SweepError>)>,
    ) -> SweepError {
        for (case, result) in rest {
            if let Ok(r) = result {
                self.slot(case, r);
            }
        }
        let _ = self.flush();
        let complete: Vec<usize> = (self.pending.iter())
            .filter(|(_, slots)| slots.iter().all(Option::is_some))
            .map(|(&c, _)| c)
            .collect();
        for c in complete {
            let results = self.pending.remove(&c).into_iter().flatten().flatten();
            if self.save(c, results).is_err() {
                return error;
            }
        }
        let _ = self.save_held();
        error
    }

    /// Saves every held chunk as parts, in order.
    fn save_held(&mut self) -> Result<(), SweepError> {
        for h in self.held.drain(..) {
            let (ida_part, cap_part) = part_paths(self.parts, h.chunk);
            let meta = self.prep.metadata(self.plan, Some(h.chunk), None);
            tables::write_batches(&ida_part, &h.ida, &meta)?;
            tables::write_batches(&cap_part, &h.cap, &meta)?;
        }
        Ok(())
    }

    /// Adds the chunks at the front of the order that are complete (or
    /// were resumed) to the final tables, holding the new ones to be saved
    /// as parts.
    fn flush(&mut self) -> Result<(), SweepError> {
        while let Some(&c) = self.order.front() {
            if self.resumed.contains(&c) {
                let (ida_part, cap_part) = part_paths(self.parts, c);
                self.ida.table(&ida_part)?;
                self.cap.table(&cap_part)?;
            } else {
                let complete = self
                    .pending
                    .get(&c)
                    .is_some_and(|slots| slots.iter().all(Option::is_some));
                if !complete {
                    break;
                }
                let results = self.pending.remove(&c).into_iter().flatten().flatten();
                self.save(c, results)?;
            }
            self.order.pop_front();
        }
        Ok(())
    }

    /// Commits the final tables once every chunk is in.
    pub(super) fn finish(mut self) -> Result<Tally, SweepError> {
        self.flush()?;
        if let Some(c) = self.order.front() {
            // Only reached when a worker stopped early, which reports its own error.
            return Err(SweepError::Io {
                path: self.parts.to_path_buf(),
                source: io::Error::other(format!("chunk {c} was never completed")),
            });
        }
        self.ida.commit()?;
        self.cap.commit()?;
        Ok(self.tally)
    }

    /// Adds chunk `c`, from its cases' results in case order, to the final
    /// tables, and saves it as parts with the chunks held before it once
    /// [`Hold`] allows; else holds it.
    fn save(
        &mut self,
        c: usize,
        results: impl Iterator<Item = CaseResult>,
    ) -> Result<(), SweepError> {
        let mut ida_rows = Vec::new();
        let mut cap_rows = Vec::with_capacity(CHUNK_CASES);
        for r in results {
            if r.reused {
                self.tally.cases_reused += 1;
            } else {
                self.tally.runs += r.ida.len() as u64;
                self.tally.check_runs += r.check_runs as u64;
                self.tally.intervals += r.intervals;
            }
            ida_rows.extend(r.ida);
            cap_rows.push(r.capacity);
        }
        let ida = self.ida.rows_as_read(&ida_rows)?;
        let cap = self.cap.rows_as_read(&cap_rows)?;
        self.held.push(Held { chunk: c, ida, cap });
        self.completed += 1;
        self.checkpoint()?;
        self.tally.cases_done += cap_rows.len();
        (self.report)(&self.tally);
        if self.fault_after.is_some_and(|n| self.completed >= n) {
            // Fault injection for the resume tests: die as a crash would.
            std::process::abort();
        }
        if self.interrupt_after.is_some_and(|n| self.completed >= n) {
            crate::physics::interrupt::request();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn held_chunks_are_due_at_the_instant_or_the_row_limit_or_past_the_count() {
        let t0 = Instant::now();
        let until = Hold::Until(t0 + Duration::from_secs(10));
        // Before the instant, only the row limit makes saving due.
        assert!(!until.due(500, MAX_HELD_ROWS - 1, t0));
        assert!(until.due(1, MAX_HELD_ROWS, t0));
        // From the instant on, whatever is held.
        assert!(until.due(1, 0, t0 + Duration::from_secs(10)));
        assert!(!until.due(1, 0, t0 + Duration::from_millis(9_999)));
        // Holding two chunks: the third is the first saved, with both.
        let two = Hold::Chunks(2);
        assert!(!two.due(1, MAX_HELD_ROWS, t0));
        assert!(!two.due(2, 0, t0));
        assert!(two.due(3, 0, t0));
        assert!(Hold::Chunks(0).due(1, 0, t0));
    }
}
