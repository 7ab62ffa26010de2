//! One writer per study folder: every command that writes into
//! `<outputs>/<name>/` holds a lock there while it works.
//!
//! - An **exclusive** lock (`.lock`) for `run` and the stage commands; a
//!   **shard** lock (`.lock.shard-K-of-N`) for one shard of a sharded sweep,
//!   so the N shards of a batch array can write side by side. An exclusive
//!   lock refuses every other lock; shard locks refuse an exclusive one and
//!   the same shard twice.
//! - A lock file holds its owner as JSON: pid, host, the process's start
//!   time (so a reused pid is not mistaken for the owner), the command. It
//!   is created whole, by hard-linking a file already written, so it never
//!   exists empty.
//! - A lock is **live** when its owner is running: on this host, that pid
//!   running, started at the recorded time, under the process name the
//!   owner recorded. Anything else (the process is gone, the pid now
//!   belongs to another program, the file is garbage or empty) is stale and
//!   taken over. A lock from another host (a cluster's shared folder)
//!   cannot be checked that way: its owner touches it every
//!   [`HEARTBEAT`], and it is obeyed until it has gone [`REMOTE_TTL`]
//!   without a touch (the node died, the job was killed), then taken over;
//!   at once by the same batch job and task (a requeued Slurm array task
//!   takes over the lock its killed run left on another node).
//! - Shard locks of different shard counts refuse each other (their chunks
//!   overlap).
//! - Released on drop, only while it still holds our owner.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use serde::{Deserialize, Serialize};

use super::stage::Shard;

/// Who holds a lock.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Owner {
    pub pid: u32,
    pub host: String,
    /// Start time of the process in clock ticks since boot (/proc/PID/stat),
    /// 0 where unknown.
    pub started_ticks: u64,
    /// Wall-clock start of the lock (Unix seconds), for messages.
    pub since_unix_s: u64,
    /// The command, e.g. `rocking sweep pipelines/paper.toml`.
    pub command: String,
    /// The owner's process name (/proc/PID/comm): a live pid under another
    /// name is another program.
    #[serde(default)]
    pub process: String,
    /// The batch job (Slurm array job and task, or job) the owner ran in, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub job: Option<String>,
}

/// How often a lock's owner touches it (its modification time).
pub const HEARTBEAT: Duration = Duration::from_secs(30);

/// How long a lock from another host is obeyed without a touch.
pub const REMOTE_TTL: Duration = Duration::from_secs(600);

#[derive(Debug, thiserror::Error)]
pub enum LockError {
    #[error(
        "{dir} is in use: {owner} holds {}; wait for it to finish, or remove that file if \
         the process is gone",
        .lock.display()
    )]
    Held {
        dir: PathBuf,
        lock: PathBuf,
        owner: Box<Owner>,
    },
    #[error("{path}: cannot take the lock")]
    Io {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
}

impl std::fmt::Display for Owner {
    /// `` `rocking run …` (pid N on HOST, for S s) ``.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "`{}` (pid {} on {}, for {})",
            self.command,
            self.pid,
            self.host,
            age(self.since_unix_s)
        )
    }
}

fn age(since: u64) -> String {
    let now = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(since, |d| d.as_secs());
    format!("{} s", now.saturating_sub(since))
}

/// Which lock to take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scope {
    Exclusive,
    Shard(Shard),
}

/// A lock held until dropped.
#[derive(Debug)]
pub struct Lock {
    path: PathBuf,
    mine: Vec<u8>,
    /// Dropping it stops the heartbeat thread.
    heartbeat: Option<(mpsc::Sender<()>, std::thread::JoinHandle<()>)>,
}

const EXCLUSIVE: &str = ".lock";
const SHARD_PREFIX: &str = ".lock.shard-";

impl Lock {
    /// Takes the lock of `scope` in `dir` (created if needed) for `command`.
    pub fn take(dir: &Path, scope: Scope, command: &str) -> Result<Lock, LockError> {
        let io_err = |path: &Path| {
            let path = path.to_path_buf();
            move |source| LockError::Io { path, source }
        };
        fs::create_dir_all(dir).map_err(io_err(dir))?;
        let path = match scope {
            Scope::Exclusive => dir.join(EXCLUSIVE),
            Scope::Shard(s) => dir.join(format!("{SHARD_PREFIX}{}-of-{}", s.k, s.n)),
        };
        let owner = Owner::me(command);
        let mine = serde_json::to_vec(&owner).expect("an owner serialises");
        let tmp = dir.join(format!(".lock.tmp-{}-{}", owner.pid, nanos()));
        fs::write(&tmp, &mine).map_err(io_err(&tmp))?;
        let result = claim(&path, &tmp, &mine, dir);
        let _ = fs::remove_file(&tmp);
        let lock = result?;
        // Exclusive against every shard, and a shard against the exclusive
        // lock: whoever sees the other after taking its own steps back (at
        // worst both do, and both say so).
        let conflict = match scope {
            Scope::Exclusive => live_locks(dir, |n| n.starts_with(SHARD_PREFIX)),
            Scope::Shard(s) => {
                let same_count = format!("-of-{}", s.n);
                live_locks(dir, |n| {
                    n == EXCLUSIVE || (n.starts_with(SHARD_PREFIX) && !n.ends_with(&same_count))
                })
            }
        };
        if let Some((other, owner)) = conflict {
            drop(lock);
            return Err(LockError::Held {
                dir: dir.into(),
                lock: other,
                owner: Box::new(owner),
            });
        }
        Ok(lock.beating())
    }

    /// Starts touching the lock every [`HEARTBEAT`] until dropped.
    fn beating(mut self) -> Lock {
        let (stop, stopped) = mpsc::channel::<()>();
        let path = self.path.clone();
        let thread = std::thread::spawn(move || {
            while let Err(mpsc::RecvTimeoutError::Timeout) = stopped.recv_timeout(HEARTBEAT) {
                if let Ok(f) = fs::File::options().append(true).open(&path) {
                    let _ = f.set_modified(SystemTime::now());
                }
            }
        });
        self.heartbeat = Some((stop, thread));
        self
    }
}

/// Links `tmp` (holding `mine`) at `path`, taking over a stale lock there.
fn claim(path: &Path, tmp: &Path, mine: &[u8], dir: &Path) -> Result<Lock, LockError> {
    for _ in 0..4 {
        match fs::hard_link(tmp, path) {
            Ok(()) => {
                return Ok(Lock {
                    path: path.into(),
                    mine: mine.to_vec(),
                    heartbeat: None,
                })
            }
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                let held = fs::read(path).unwrap_or_default();
                if let Some(owner) = live_owner(&held, modified(path)) {
                    return Err(LockError::Held {
                        dir: dir.into(),
                        lock: path.into(),
                        owner: Box::new(owner),
                    });
                }
                take_over(path, &held);
            }
            Err(source) => {
                return Err(LockError::Io {
                    path: path.into(),
                    source,
                })
            }
        }
    }
    // Lost every race: someone else keeps taking it.
    let held = fs::read(path).unwrap_or_default();
    Err(LockError::Held {
        dir: dir.into(),
        lock: path.into(),
        owner: Box::new(parse_owner(&held).unwrap_or_else(Owner::unknown)),
    })
}

/// Removes the stale lock at `path` whose bytes were `stale`: it is renamed
/// aside first (atomic), and put back if what was renamed is not the stale
/// lock but a fresh one another process took meanwhile. Three processes
/// racing for one stale lock in the same microseconds can still both end up
/// holding it (B renames A's fresh lock aside, C links its own, B's put-back
/// fails); OS file locks would close that, at the price of shared
/// filesystems where they are not reliable.
fn take_over(path: &Path, stale: &[u8]) {
    let aside = path.with_file_name(format!(".lock.stale-{}-{}", std::process::id(), nanos()));
    if fs::rename(path, &aside).is_err() {
        return; // gone already: retry the link
    }
    if fs::read(&aside).is_ok_and(|b| b == stale) {
        let _ = fs::remove_file(&aside);
    } else {
        let _ = fs::hard_link(&aside, path);
        let _ = fs::remove_file(&aside);
    }
}

impl Drop for Lock {
    fn drop(&mut self) {
        if let Some((stop, thread)) = self.heartbeat.take() {
            drop(stop);
            let _ = thread.join();
        }
        if fs::read(&self.path).is_ok_and(|b| b == self.mine) {
            let _ = fs::remove_file(&self.path);
        }
    }
}

/// Who holds `dir` now, if a live process does (its exclusive lock or a
/// shard's), in words: `rocking run … (pid N on HOST, for S s)`.
pub fn holder(dir: &Path) -> Option<String> {
    let (_, owner) = live_locks(dir, |n| n == EXCLUSIVE || n.starts_with(SHARD_PREFIX))?;
    Some(owner.to_string())
}

/// The first live lock in `dir` whose file name passes `which`, other than ours.
fn live_locks(dir: &Path, which: impl Fn(&str) -> bool) -> Option<(PathBuf, Owner)> {
    let (me, here) = (std::process::id(), hostname());
    fs::read_dir(dir).ok()?.flatten().find_map(|e| {
        let name = e.file_name().to_string_lossy().into_owned();
        if !which(&name) {
            return None;
        }
        let owner = live_owner(&fs::read(e.path()).ok()?, modified(&e.path()))?;
        (owner.pid != me || owner.host != here).then(|| (e.path(), owner))
    })
}

/// How long ago a file was last modified (zero if unknown or in the future).
fn modified(path: &Path) -> Duration {
    fs::metadata(path)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| SystemTime::now().duration_since(t).ok())
        .unwrap_or_default()
}

fn parse_owner(bytes: &[u8]) -> Option<Owner> {
    serde_json::from_slice(bytes).ok()
}

/// The owner of a lock's bytes if it is live; `age` is the time since the
/// lock file was last touched.
fn live_owner(bytes: &[u8], age: Duration) -> Option<Owner> {
    let owner = match parse_owner(bytes) {
        Some(o) => o,
        // A bare pid: the lock of an older version of this tool.
        None => {
            let pid = std::str::from_utf8(bytes)
                .ok()?
                .trim()
                .parse::<u32>()
                .ok()?;
            Owner {
                pid,
                host: hostname(),
                started_ticks: 0,
                since_unix_s: 0,
                command: "rocking (an older version)".into(),
                process: my_comm(),
                job: None,
            }
        }
    };
    if owner.host != hostname() {
        // Another machine's process (a cluster's shared folder): obey it
        // while it keeps the lock fresh, unless it is an earlier run of this
        // very batch task (requeued after its node or time ran out).
        let same_task = owner.job.is_some() && owner.job == batch_job();
        return (age < REMOTE_TTL && !same_task).then_some(owner);
    }
    if !Path::new("/proc/self/stat").exists() {
        return Some(owner); // no way to check here: obey it
    }
    let stat = fs::read_to_string(format!("/proc/{}/stat", owner.pid)).ok()?;
    if owner.started_ticks != 0 && start_ticks(&stat) != Some(owner.started_ticks) {
        return None; // the pid was reused
    }
    if matches!(process_state(&stat), Some('Z' | 'X' | 'x')) {
        return None; // killed, not yet reaped: it runs no more
    }
    let comm = fs::read_to_string(format!("/proc/{}/comm", owner.pid)).ok()?;
    let expected = if owner.process.is_empty() {
        my_comm()
    } else {
        owner.process.clone()
    };
    (comm.trim() == expected).then_some(owner)
}

impl Owner {
    fn me(command: &str) -> Owner {
        let stat = fs::read_to_string("/proc/self/stat").unwrap_or_default();
        Owner {
            pid: std::process::id(),
            host: hostname(),
            started_ticks: start_ticks(&stat).unwrap_or(0),
            since_unix_s: SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
            command: command.to_string(),
            process: my_comm(),
            job: batch_job(),
        }
    }

    fn unknown() -> Owner {
        Owner {
            pid: 0,
            host: "?".into(),
            started_ticks: 0,
            since_unix_s: 0,
            command: "?".into(),
            process: String::new(),
            job: None,
        }
    }
}

/// Field 22 of /proc/PID/stat (start time in clock ticks); the process name
/// in field 2 may hold spaces and parentheses, so fields are counted after
/// its last `)`.
/// The process's state in /proc/PID/stat (`R`, `S`, `Z` for a zombie, …).
fn process_state(stat: &str) -> Option<char> {
    stat[stat.rfind(')')? + 1..]
        .split_whitespace()
        .next()?
        .chars()
        .next()
}

fn start_ticks(stat: &str) -> Option<u64> {
    let rest = &stat[stat.rfind(')')? + 1..];
    rest.split_whitespace().nth(19)?.parse().ok()
}

/// The Slurm job this process runs in: `ARRAYJOB_TASK` for an array task
/// (the same across requeues), else the job id; `None` outside Slurm.
fn batch_job() -> Option<String> {
    let var = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
    match (var("SLURM_ARRAY_JOB_ID"), var("SLURM_ARRAY_TASK_ID")) {
        (Some(job), Some(task)) => Some(format!("slurm {job}_{task}")),
        _ => var("SLURM_JOB_ID").map(|j| format!("slurm {j}")),
    }
}

fn my_comm() -> String {
    fs::read_to_string("/proc/self/comm")
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|_| "rocking".into())
}

fn hostname() -> String {
    fs::read_to_string("/proc/sys/kernel/hostname")
        .or_else(|_| fs::read_to_string("/etc/hostname"))
        .map(|s| s.trim().to_string())
        .unwrap_or_else(|_| "localhost".into())
}

fn nanos() -> u128 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn start_time_is_read_after_the_process_name() {
        // A process name with a space and a parenthesis.
        let stat = "42 (a b) c) S 1 42 42 0 -1 4194560 100 0 0 0 1 2 0 0 20 0 1 0 98765 1000 10";
        assert_eq!(start_ticks(stat), Some(98765));
        let me = fs::read_to_string("/proc/self/stat").unwrap();
        assert!(start_ticks(&me).unwrap() > 0);
        assert_eq!(process_state(stat), Some('S'));
    }

    /// A lock whose owner was killed but not yet reaped (a zombie: its pid,
    /// start time and name still in /proc) was obeyed; it runs no more.
    #[test]
    fn a_zombies_lock_is_stale() {
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let stat_path = format!("/proc/{}/stat", child.id());
        let mut stat = String::new();
        for _ in 0..500 {
            stat = fs::read_to_string(&stat_path).unwrap();
            if process_state(&stat) == Some('Z') {
                break;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        assert_eq!(process_state(&stat), Some('Z'), "{stat}");
        let owner = Owner {
            pid: child.id(),
            host: hostname(),
            started_ticks: start_ticks(&stat).unwrap(),
            since_unix_s: 0,
            command: "rocking run".into(),
            process: "true".into(),
            job: None,
        };
        let bytes = serde_json::to_vec(&owner).unwrap();
        assert_eq!(live_owner(&bytes, Duration::ZERO), None);
        child.wait().unwrap();
    }
}
