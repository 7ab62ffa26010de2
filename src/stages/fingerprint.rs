//! Stage fingerprints (cargo's design): named hashes of a stage's settings,
//! of each input file's bytes and of the versions, never file times. After a
//! stage succeeds, its fingerprint and the hashes of what it wrote are saved
//! in `<study>/.fingerprints/<stage>.json` (`<stage>.shard-K-of-N.json` for
//! one shard), with the reason it ran and how long it took. A stage is
//! fresh when that note exists, parses, has the same parts, and its outputs
//! are there unchanged; otherwise every difference is a typed [`Stale`]
//! reason.
//!
//! Files are named relative to the study's folder or the pipeline's
//! ([`Study::name_of`]), so a copied output folder stays fresh.
//!
//! The engine asks one question before a stage runs ([`freshness`]: fresh,
//! or every reason it is not) and makes one call after it succeeds
//! ([`save`]); the notes, their paths and their comparison stay in here.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;
use std::fs;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::reason::Reason;
pub use super::reason::Stale;
use super::stage::{BoxError, Shard, Stage, Study};
use crate::{hash, tables};

/// The saved note of a stage that succeeded.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Note {
    pub stage: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<String>,
    /// Part name → hash: `settings`, `versions`, `input <file>`.
    pub parts: BTreeMap<String, String>,
    /// Output file → hash of its bytes when the stage finished.
    pub outputs: BTreeMap<String, String>,
    pub seconds: f64,
    /// Why it last ran, as shown then.
    pub reason: String,
}

/// Whether a stage must run, and why.
#[derive(Debug, Clone, PartialEq)]
pub enum Freshness {
    Fresh,
    /// Fresh as a complete set of N shards.
    FreshShards(usize),
    Stale(Vec<Stale>),
    /// Fresh itself, but it reads from this stage, which is stale: it will
    /// run once that one has (shown by `status`).
    Waits(&'static str),
    /// The pipeline does not need this stage (why).
    NotNeeded(String),
}

impl fmt::Display for Freshness {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Freshness::Fresh => f.write_str("fresh"),
            Freshness::FreshShards(n) => write!(f, "fresh ({n} shards)"),
            Freshness::Stale(why) => write!(f, "stale: {}", Reason::Stale(why.clone())),
            Freshness::Waits(on) => {
                write!(f, "stale: it reads `{on}`'s outputs, which will change")
            }
            Freshness::NotNeeded(why) => write!(f, "not needed: {why}"),
        }
    }
}

/// Is `stage` fresh? (Runs nothing.) The whole stage (`shard` None): not
/// needed when the pipeline does not need it, else fresh by its own note or
/// as a complete set of shards, else stale with every reason. One shard: by
/// that shard's own note alone (fresh or stale).
pub fn freshness(stage: &dyn Stage, study: &Study, shard: Option<Shard>) -> Freshness {
    if let Some(shard) = shard {
        return freshness_of_shard(stage, study, shard);
    }
    if let Some(why) = stage.not_needed(study) {
        return Freshness::NotNeeded(why);
    }
    let now = match parts(stage, study) {
        Ok(p) => p,
        Err(why) => return Freshness::Stale(why),
    };
    let whole = note_path(study, stage.name(), None);
    let why = match read_note(study, &whole) {
        Ok(note) => {
            let declared = stage.outputs(study, None);
            let why = compare(&now, &note, study, &declared);
            if why.is_empty() {
                return Freshness::Fresh;
            }
            why
        }
        Err(Stale::NeverRun) => match stage.interrupted(study) {
            Some(what) => vec![Stale::Interrupted(what)],
            None => vec![Stale::NeverRun],
        },
        Err(why) => vec![why],
    };
    if stage.shardable() {
        match shard_state(stage, study, &now) {
            Shards::None => {}
            Shards::Complete(n) => return Freshness::FreshShards(n),
            Shards::Incomplete {
                n,
                missing,
                why: of_shards,
            } => {
                // Run in shards, not here: the shards' reasons, not "never
                // run here".
                let mut why = match why[..] {
                    [Stale::NeverRun | Stale::Interrupted(_)] => Vec::new(),
                    _ => why,
                };
                for w in of_shards {
                    if !why.contains(&w) {
                        why.push(w);
                    }
                }
                why.push(Stale::ShardsIncomplete { n, missing });
                return Freshness::Stale(why);
            }
        }
    }
    Freshness::Stale(why)
}

/// What the shard notes of a sharded stage say.
enum Shards {
    /// No shard notes at all.
    None,
    /// Every shard of N is fresh.
    Complete(usize),
    /// Some shards of N, or none, are fresh; these are not (missing, or
    /// stale for `why`: the first stale shard's reasons).
    Incomplete {
        n: usize,
        missing: Vec<usize>,
        why: Vec<Stale>,
    },
}

fn shard_state(stage: &dyn Stage, study: &Study, now: &BTreeMap<String, String>) -> Shards {
    let notes = shard_notes(study, stage.name());
    let Some(n) = current_count(&notes) else {
        return Shards::None;
    };
    let mut fresh = BTreeSet::new();
    let mut why = Vec::new();
    for (s, path) in notes.iter().filter(|(s, _)| s.n == n) {
        let stale = match read_note(study, path) {
            Ok(note) => compare(now, &note, study, &stage.outputs(study, Some(*s))),
            Err(e) => vec![e],
        };
        if stale.is_empty() {
            fresh.insert(s.k);
        } else if why.is_empty() {
            why = stale;
        }
    }
    match fresh.len() {
        k if k == n => Shards::Complete(n),
        _ => Shards::Incomplete {
            n,
            // N is bounded by the number of chunks.
            missing: (1..=n).filter(|k| !fresh.contains(k)).collect(),
            why,
        },
    }
}

/// Fresh when the shard's own note is, else stale with why not.
fn freshness_of_shard(stage: &dyn Stage, study: &Study, shard: Shard) -> Freshness {
    let now = match parts(stage, study) {
        Ok(p) => p,
        Err(why) => return Freshness::Stale(why),
    };
    let path = note_path(study, stage.name(), Some(shard));
    match read_note(study, &path) {
        Ok(note) => {
            let why = compare(&now, &note, study, &stage.outputs(study, Some(shard)));
            if why.is_empty() {
                Freshness::Fresh
            } else {
                Freshness::Stale(why)
            }
        }
        Err(why) => Freshness::Stale(vec![why]),
    }
}

/// Saves the note of `stage` (or of one shard of it) after it succeeded:
/// its parts, its inputs hashed again now that they are final, the hashes
/// of what it wrote (its declared outputs and `also_wrote`), how long it
/// took and why it ran. `Err` is why the note could not be saved.
pub fn save(
    stage: &dyn Stage,
    study: &Study,
    shard: Option<Shard>,
    also_wrote: &[PathBuf],
    seconds: f64,
    reason: &Reason,
) -> Result<(), BoxError> {
    let name = stage.name();
    let parts = parts(stage, study).map_err(|why| Reason::Stale(why).to_string())?;
    let mut written = stage.outputs(study, shard);
    written.extend(also_wrote.iter().cloned());
    let outputs = hash_outputs(study, &written)?;
    if shard.is_none() {
        retire(study, &note_path(study, name, None), &outputs);
    }
    let note = Note {
        stage: name.into(),
        shard: shard.map(|s| s.to_string()),
        parts,
        outputs,
        seconds,
        reason: reason.to_string(),
    };
    let path = note_path(study, name, shard);
    let text = serde_json::to_string_pretty(&note).expect("a note serialises");
    tables::atomic_write(&path, text.as_bytes())?;
    // A whole run supersedes shard notes, and a shard the whole run's note.
    match shard {
        None => {
            for (_, p) in shard_notes(study, name) {
                let _ = std::fs::remove_file(p);
            }
        }
        Some(done) => {
            let _ = std::fs::remove_file(note_path(study, name, None));
            for (other, p) in shard_notes(study, name) {
                if other.n != done.n {
                    let _ = std::fs::remove_file(p);
                }
            }
        }
    }
    Ok(())
}

/// Removes the files the stage's last run wrote (its note at `note`) that
/// this run did not (`now`): a table of a section since taken out of the
/// pipeline (`[uncertainty]`'s bands, `[example]`'s damage tables), which
/// would otherwise stay beside the study's, to be read as its own. Only a
/// file still as the stage wrote it, inside the study's folder; a file
/// changed since is left alone, as [`forget`] leaves it.
fn retire(study: &Study, note: &Path, now: &BTreeMap<String, String>) {
    let Ok(before) = read_note(study, note) else {
        return;
    };
    for name in before.outputs.keys().filter(|n| !now.contains_key(*n)) {
        let rel = Path::new(name);
        let inside = rel.is_relative()
            && rel
                .components()
                .all(|c| matches!(c, std::path::Component::Normal(_)));
        let file = study.dir.join(rel);
        if inside && as_written(study, &before, &file) {
            let _ = fs::remove_file(&file);
        }
    }
}

/// Removes the whole stage's note: one left from when the pipeline needed
/// the stage is not this study's. So are the stage's outputs the note
/// records that are still as it wrote them (a file changed since is left
/// alone): another pipeline of the same name writing into the folder, or
/// the pipeline without the stage's section, left its tables beside the
/// study's, to be read as the study's.
pub fn forget(study: &Study, stage: &dyn Stage) {
    let path = note_path(study, stage.name(), None);
    if let Ok(note) = read_note(study, &path) {
        for file in stage.outputs(study, None) {
            if as_written(study, &note, &file) {
                let _ = fs::remove_file(&file);
            }
        }
    }
    let _ = std::fs::remove_file(path);
}

/// Whether every output of `stage`'s last unsharded run is still as it
/// wrote it (each file's hash the one its note recorded): tables the stage
/// may take rows from again. No note, an output missing or changed: no.
pub fn outputs_as_written(study: &Study, stage: &dyn Stage) -> bool {
    let Ok(note) = read_note(study, &note_path(study, stage.name(), None)) else {
        return false;
    };
    (stage.outputs(study, None).iter()).all(|file| as_written(study, &note, file))
}

/// Whether `file` is as the stage whose `note` this is wrote it: its hash
/// the one the note recorded.
fn as_written(study: &Study, note: &Note, file: &Path) -> bool {
    let recorded = note.outputs.get(&study.name_of(file));
    recorded.is_some_and(|h| hash::file_sha256(file).is_ok_and(|now| &now == h))
}

/// The version part: the tool's version, which is raised with any change of
/// a table's schema (ARCHITECTURE.md, "How to add a table"), and a hash of
/// its sources (`build.rs`): the physics can change within a version, and
/// a study made by another build is computed again.
fn versions() -> String {
    format!("rocking {}", crate::BUILD)
}

/// Where a stage's note lives.
fn note_path(study: &Study, stage: &str, shard: Option<Shard>) -> PathBuf {
    let file = match shard {
        None => format!("{stage}.json"),
        Some(s) => format!("{stage}.{}.json", s.tag()),
    };
    study.dir.join(crate::outpath::STUDY_MARK).join(file)
}

/// Reads a note; `Err` is why the stage counts as stale.
fn read_note(study: &Study, path: &Path) -> Result<Note, Stale> {
    let text = match fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(Stale::NeverRun),
        Err(e) => {
            return Err(Stale::NoteUnreadable {
                note: study.name_of(path),
                problem: e.to_string(),
            })
        }
    };
    serde_json::from_str(&text).map_err(|e| Stale::NoteUnreadable {
        note: study.name_of(path),
        problem: e.to_string(),
    })
}

/// The key of a stage's settings that holds the other stages' run times
/// it shows (the report's table of them): fingerprinted on its own.
pub const TIMES: &str = "times";

/// The fingerprint parts of `stage` as things stand, or why it cannot run yet.
fn parts(stage: &dyn Stage, study: &Study) -> Result<BTreeMap<String, String>, Vec<Stale>> {
    let mut p = BTreeMap::new();
    p.insert("versions".to_string(), versions());
    let mut settings = stage.settings(study);
    // The other stages' run times a stage prints (the report's) are a part
    // of their own, so that a rerun for them says so, not "settings".
    if let Some(times) = settings.as_object_mut().and_then(|o| o.remove(TIMES)) {
        p.insert(
            TIMES.to_string(),
            hash::sha256_hex(times.to_string().as_bytes()),
        );
    }
    if !settings.is_null() {
        p.insert(
            "settings".to_string(),
            hash::sha256_hex(settings.to_string().as_bytes()),
        );
    }
    let inputs = stage
        .inputs(study)
        .map_err(|e| vec![Stale::InputsUnavailable(e.to_string())])?;
    let mut missing = Vec::new();
    for f in inputs {
        let name = study.name_of(&f);
        match hash::file_sha256(&f) {
            Ok(h) => {
                p.insert(format!("input {name}"), h);
            }
            Err(_) => missing.push(Stale::InputMissing(name)),
        }
    }
    if missing.is_empty() {
        Ok(p)
    } else {
        Err(missing)
    }
}

/// Every difference between the parts now and a note, and between the
/// outputs it recorded (and those the stage declares) and the files there.
fn compare(
    now: &BTreeMap<String, String>,
    note: &Note,
    study: &Study,
    declared: &[PathBuf],
) -> Vec<Stale> {
    let mut why = Vec::new();
    let input_name = |k: &str| k.strip_prefix("input ").map(str::to_string);
    for (k, v) in now {
        match note.parts.get(k) {
            Some(old) if old == v => {}
            old => why.push(match (k.as_str(), input_name(k), old) {
                ("settings", _, _) => Stale::SettingsChanged,
                (TIMES, _, _) => Stale::TimesChanged,
                ("versions", _, _) => Stale::VersionsChanged,
                (_, Some(n), Some(_)) => Stale::InputChanged(n),
                (_, Some(n), None) => Stale::InputNew(n),
                (_, None, _) => Stale::SettingsChanged,
            }),
        }
    }
    for k in note.parts.keys().filter(|k| !now.contains_key(*k)) {
        why.push(match input_name(k) {
            Some(n) => Stale::InputGone(n),
            None => Stale::SettingsChanged,
        });
    }
    let mut recorded: Vec<(&String, &String)> = note.outputs.iter().collect();
    recorded.sort();
    for (name, h) in recorded {
        let path = study.dir.join(name);
        match hash::file_sha256(&path) {
            Err(_) => why.push(Stale::OutputMissing(name.clone())),
            Ok(now) if &now != h => why.push(Stale::OutputChanged(name.clone())),
            Ok(_) => {}
        }
    }
    for out in declared {
        let name = study.name_of(out);
        if !note.outputs.contains_key(&name) && !why.contains(&Stale::OutputMissing(name.clone())) {
            why.push(if out.exists() {
                Stale::OutputNotRecorded(name)
            } else {
                Stale::OutputMissing(name)
            });
        }
    }
    why
}

/// Hashes of the outputs, named as fingerprints name them.
fn hash_outputs(study: &Study, files: &[PathBuf]) -> std::io::Result<BTreeMap<String, String>> {
    let mut out = BTreeMap::new();
    for f in files {
        let h = hash::file_sha256(f)
            .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", f.display())))?;
        out.insert(study.name_of(f), h);
    }
    Ok(out)
}

/// How long each of `stages` took when it last succeeded here, in their order.
pub fn recorded_seconds(
    study: &Study,
    stages: &[&'static dyn Stage],
) -> Vec<(&'static str, Option<f64>)> {
    let found = seconds_in_folder(study);
    stages
        .iter()
        .map(|s| (s.name(), found.get(s.name()).copied()))
        .collect()
}

/// The count of the set of shards the notes speak for: the largest (a set
/// of another count is superseded once one of the new set finishes).
fn current_count(notes: &[(Shard, PathBuf)]) -> Option<usize> {
    notes.iter().map(|(s, _)| s.n).max()
}

/// Shard notes present for `stage`: (shard, path), in shard order.
fn shard_notes(study: &Study, stage: &str) -> Vec<(Shard, PathBuf)> {
    let dir = study.dir.join(crate::outpath::STUDY_MARK);
    let Ok(entries) = fs::read_dir(&dir) else {
        return Vec::new();
    };
    let prefix = format!("{stage}.shard-");
    let mut found: Vec<(Shard, PathBuf)> = entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let rest = name.strip_prefix(&prefix)?.strip_suffix(".json")?;
            let (k, n) = rest.split_once("-of-")?;
            let shard = Shard {
                k: k.parse().ok()?,
                n: n.parse().ok()?,
            };
            (shard.k >= 1 && shard.k <= shard.n && shard.n <= super::stage::MAX_SHARDS)
                .then(|| (shard, e.path()))
        })
        .collect();
    found.sort_by_key(|(s, _)| (s.n, s.k));
    found
}

/// The seconds of a stage run in shards, summed over its shards (of the
/// current count, [`current_count`]), and that count; `None` without shard
/// notes.
pub fn sharded_seconds(study: &Study, stage: &str) -> Option<(f64, usize)> {
    let notes = shard_notes(study, stage);
    let n = current_count(&notes)?;
    let total = notes
        .iter()
        .filter(|(shard, _)| shard.n == n)
        .filter_map(|(_, path)| read_note(study, path).ok())
        .map(|note| note.seconds)
        .sum();
    Some((total, n))
}

/// Seconds of every whole-stage note in the study's folder, by stage name
/// (for a stage whose output shows the others' run times).
pub fn seconds_in_folder(study: &Study) -> BTreeMap<String, f64> {
    let dir = study.dir.join(crate::outpath::STUDY_MARK);
    let Ok(entries) = fs::read_dir(&dir) else {
        return BTreeMap::new();
    };
    entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            let stage = name.strip_suffix(".json")?;
            if stage.contains('.') {
                return None; // a shard's note
            }
            let note = read_note(study, &e.path()).ok()?;
            Some((stage.to_string(), note.seconds))
        })
        .collect()
}
