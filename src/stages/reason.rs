//! Why stages run or not, as values: typed stale reasons, the reason a
//! stage runs, why it is skipped, and the events a reporter hears. A leaf
//! of the stage modules (it imports none of them), so the engine, the
//! fingerprints and the stage trait can all use it.

use std::fmt;

/// Why a stage is stale. Each names the file or part concerned.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Stale {
    /// No fingerprint: the stage never succeeded in this folder.
    NeverRun,
    /// Never finished here, but an interrupted run left work a rerun
    /// resumes (what, in words).
    Interrupted(String),
    /// The fingerprint file exists but cannot be read or parsed.
    NoteUnreadable {
        note: String,
        problem: String,
    },
    SettingsChanged,
    /// The other stages' run times it shows (the report) changed: one of
    /// them ran again.
    TimesChanged,
    VersionsChanged,
    /// An input file's bytes differ from when the stage last ran.
    InputChanged(String),
    /// A file it reads now that it did not read then (and the reverse).
    InputNew(String),
    InputGone(String),
    /// An input it needs does not exist yet (an earlier stage has not run).
    InputMissing(String),
    /// Its inputs cannot be listed (a folder of AT2 files is unreadable).
    InputsUnavailable(String),
    OutputMissing(String),
    /// An output was edited or replaced behind the tool's back.
    OutputChanged(String),
    /// An output it writes now is not in its fingerprint (written by an older version).
    OutputNotRecorded(String),
    /// It was run in `n` shards, and these are missing or stale (all of
    /// them, after the settings changed, say).
    ShardsIncomplete {
        n: usize,
        missing: Vec<usize>,
    },
}

impl fmt::Display for Stale {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stale::NeverRun => write!(f, "never run here (no fingerprint)"),
            Stale::Interrupted(what) => write!(f, "never finished here: {what}"),
            Stale::NoteUnreadable { note, problem } => {
                write!(f, "its fingerprint {note} is unreadable ({problem})")
            }
            Stale::SettingsChanged => write!(f, "settings changed"),
            Stale::TimesChanged => write!(
                f,
                "another stage ran again, and the run times it shows changed"
            ),
            Stale::VersionsChanged => write!(f, "the tool changed (its version or its sources)"),
            Stale::InputChanged(n) => write!(f, "input {n} changed"),
            Stale::InputNew(n) => write!(f, "input {n} is new"),
            Stale::InputGone(n) => write!(f, "input {n} is gone"),
            Stale::InputMissing(n) => write!(f, "input {n} does not exist yet"),
            Stale::InputsUnavailable(why) => write!(f, "its inputs cannot be listed: {why}"),
            Stale::OutputMissing(n) => write!(f, "output {n} is missing"),
            Stale::OutputChanged(n) => write!(f, "output {n} was changed since it was written"),
            Stale::OutputNotRecorded(n) => write!(f, "output {n} is not in the fingerprint"),
            Stale::ShardsIncomplete { n, missing } => {
                let list: Vec<String> = missing
                    .iter()
                    .take(10)
                    .map(|k| format!("{k}/{n}"))
                    .collect();
                let more = missing.len().saturating_sub(10);
                write!(
                    f,
                    "it was run in {n} shards and shard{} {}{} {} missing or stale",
                    if missing.len() == 1 { "" } else { "s" },
                    list.join(", "),
                    if more > 0 {
                        format!(" and {more} more")
                    } else {
                        String::new()
                    },
                    if missing.len() == 1 { "is" } else { "are" }
                )
            }
        }
    }
}

/// Why a stage runs.
#[derive(Debug, Clone, PartialEq)]
pub enum Reason {
    Stale(Vec<Stale>),
    /// `--force`.
    Forced,
    /// `--from STAGE` at or before it.
    From(&'static str),
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Reason::Stale(why) => {
                let parts: Vec<String> = why.iter().map(Stale::to_string).collect();
                f.write_str(&parts.join("; "))
            }
            Reason::Forced => f.write_str("forced (--force)"),
            Reason::From(s) => write!(f, "forced (--from {s})"),
        }
    }
}

/// Why a stage does not run.
#[derive(Debug, Clone, PartialEq)]
pub enum Skip {
    Fresh,
    FreshShards(usize),
    NotNeeded(String),
}

impl fmt::Display for Skip {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Skip::Fresh => f.write_str("fresh"),
            Skip::FreshShards(n) => write!(f, "fresh ({n} shards)"),
            Skip::NotNeeded(why) => write!(f, "not needed: {why}"),
        }
    }
}

/// A stage's turn in a run.
#[derive(Debug, Clone, PartialEq)]
pub enum StageEvent {
    /// It runs, for these reasons.
    Running(Reason),
    /// It does not: fresh, or not needed by this pipeline.
    Skipped(Skip),
    /// It finished after `seconds`.
    Done { seconds: f64 },
}
