//! `rocking submit`: a study on Slurm. Ingests the records here (the array
//! tasks all read the records table, so it must exist before they start),
//! writes the two job scripts into `<outputs>/<name>/slurm/`, submits the
//! sweep as an array and the later stages after it (`afterok`), and with
//! `--wait` follows them to the end. The scripts are text made by
//! [`crate::cluster`]; this module runs `sbatch`, `scontrol` and `scancel`.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use crate::cluster::{self, JobRecord, Jobs};
use crate::stages::engine::{self, RunOptions, Target};
use crate::stages::{Reporter, Shard, Study};
use crate::tables::{atomic_write, TableError};

/// What to submit.
#[derive(Debug, Clone)]
pub struct SubmitOptions {
    /// The `--outputs` root as given.
    pub outputs: PathBuf,
    /// Array tasks (shards of the sweep).
    pub shards: usize,
    /// Extra `sbatch` options for both jobs.
    pub sbatch: Vec<String>,
    /// The command line, for the lock of the local ingest.
    pub command: String,
}

/// The submitted jobs.
#[derive(Debug, Clone, PartialEq)]
pub struct Submitted {
    pub sweep_job: u64,
    pub later_job: u64,
    pub shards: usize,
    /// The two scripts written (sweep, later stages).
    pub scripts: [PathBuf; 2],
    /// Where the tasks' logs go.
    pub logs: PathBuf,
}

#[derive(Debug, thiserror::Error)]
pub enum SubmitError {
    #[error("nothing to submit: {0}; it runs in seconds with `rocking run`")]
    NoSweep(String),
    #[error("cannot write the job scripts: {0}")]
    Paths(String),
    #[error(
        "rocking submit needs Slurm's `sbatch` on PATH, and there is none \
         (install Slurm's client commands, or load their module)"
    )]
    NoSbatch,
    #[error("--shards {0}: {1}")]
    Shards(usize, String),
    #[error("cannot find this program's own path (the tasks run the same binary)")]
    OwnPath(#[source] std::io::Error),
    #[error("ingesting the records before submitting")]
    Ingest(#[source] engine::RunError),
    #[error("counting the sweep's chunks")]
    Chunks(#[source] Box<crate::stages::sweep::SweepError>),
    #[error(transparent)]
    Write(#[from] TableError),
    #[error("{path}: cannot create the folder for the job scripts and logs")]
    Folder {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("cannot run `{program}`")]
    Spawn {
        program: String,
        #[source]
        source: std::io::Error,
    },
    #[error("`{command}` failed: {stderr}")]
    Slurm { command: String, stderr: String },
    #[error(transparent)]
    Text(#[from] cluster::SlurmText),
    #[error(
        "sweep task {task} of job {job} ended {state} (exit code {exit_code}); its log: {log}. \
         The later stages (job {later}) were cancelled"
    )]
    TaskFailed {
        job: u64,
        task: String,
        state: String,
        exit_code: String,
        log: String,
        later: u64,
    },
    #[error(
        "the later stages (job {job}) ended {state} (exit code {exit_code}); their log: {log}"
    )]
    LaterFailed {
        job: u64,
        state: String,
        exit_code: String,
        log: String,
    },
    #[error("Slurm no longer knows job {0} (purged before it was seen to finish)")]
    Vanished(u64),
}

/// The first executable `name` on PATH.
fn on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|p| {
            use std::os::unix::fs::PermissionsExt;
            p.metadata()
                .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
        })
}

fn absolute(p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        std::env::current_dir().map_or_else(|_| p.to_path_buf(), |d| d.join(p))
    }
}

/// Runs a Slurm command; its standard output, or its standard error as the error.
fn slurm(program: &Path, args: &[&str]) -> Result<String, SubmitError> {
    let out = Command::new(program)
        .args(args)
        .output()
        .map_err(|source| SubmitError::Spawn {
            program: program.display().to_string(),
            source,
        })?;
    if !out.status.success() {
        return Err(SubmitError::Slurm {
            // As a shell would take it back: each word quoted where it must be.
            command: std::iter::once(program)
                .chain(args.iter().map(Path::new))
                .map(cluster::shell_word)
                .collect::<Vec<_>>()
                .join(" "),
            stderr: String::from_utf8_lossy(&out.stderr).trim().to_string(),
        });
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// A Slurm client command: on PATH, else beside `sbatch`.
fn client(name: &str, sbatch: &Path) -> PathBuf {
    on_path(name).unwrap_or_else(|| sbatch.with_file_name(name))
}

/// Ingests here, writes the scripts, submits both jobs.
pub fn submit(
    study: &Study,
    opts: &SubmitOptions,
    reporter: &dyn Reporter,
) -> Result<Submitted, SubmitError> {
    format!("1/{}", opts.shards)
        .parse::<Shard>()
        .map_err(|e| SubmitError::Shards(opts.shards, e))?;
    if let Some(why) = study.plan.pulse_map_skips() {
        return Err(SubmitError::NoSweep(why));
    }
    let sbatch = on_path("sbatch").ok_or(SubmitError::NoSbatch)?;
    let binary = std::env::current_exe()
        .and_then(|p| p.canonicalize())
        .map_err(SubmitError::OwnPath)?;
    engine::run(
        study,
        &RunOptions {
            target: Target::Through(&crate::stages::ingest::Ingest),
            command: opts.command.clone(),
            ..RunOptions::default()
        },
        reporter,
    )
    .map_err(SubmitError::Ingest)?;
    // Every task of an array of more shards than the sweep has chunks
    // refuses its shard, and the later stages never run.
    let chunks = crate::stages::sweep::chunks(study).map_err(|e| SubmitError::Chunks(e.into()))?;
    if opts.shards > chunks {
        return Err(SubmitError::Shards(
            opts.shards,
            format!(
                "the sweep has {chunks} chunk(s) of {} cases, so at most {chunks} array tasks \
                 have work: give --shards {chunks} or fewer",
                crate::stages::sweep::CHUNK_CASES
            ),
        ));
    }
    let logs = absolute(&study.dir.join("slurm"));
    std::fs::create_dir_all(&logs).map_err(|source| SubmitError::Folder {
        path: logs.clone(),
        source,
    })?;
    let jobs = Jobs {
        binary,
        pipeline: absolute(&study.pipeline),
        outputs: absolute(&opts.outputs),
        workdir: std::env::current_dir().map_err(SubmitError::OwnPath)?,
        logs: logs.clone(),
        name: study.plan.name.clone(),
        shards: opts.shards,
        sbatch: opts.sbatch.clone(),
    };
    if let Some(why) = jobs.unwritable() {
        return Err(SubmitError::Paths(why));
    }
    let sweep_script = logs.join("sweep.sbatch");
    let later_script = logs.join("after.sbatch");
    atomic_write(&sweep_script, jobs.sweep_script().as_bytes())?;
    atomic_write(&later_script, jobs.later_script().as_bytes())?;
    // Nothing submitted: no scripts left behind (the records table is a
    // complete stage's, fingerprinted, and the next run reuses it).
    let unwritten = |e: SubmitError| {
        for s in [&sweep_script, &later_script] {
            let _ = std::fs::remove_file(s);
        }
        let _ = std::fs::remove_dir(&logs); // only if empty
        e
    };
    let sweep_job = slurm(&sbatch, &["--parsable", &sweep_script.to_string_lossy()])
        .and_then(|out| Ok(cluster::job_id(&out)?))
        .map_err(unwritten)?;
    let dependency = format!("--dependency=afterok:{sweep_job}");
    let later = slurm(
        &sbatch,
        &["--parsable", &dependency, &later_script.to_string_lossy()],
    )
    .and_then(|out| Ok(cluster::job_id(&out)?));
    let later_job = match later {
        Ok(id) => id,
        Err(e) => {
            // No array without its later stages: cancel it, then say why.
            let _ = slurm(&client("scancel", &sbatch), &[&sweep_job.to_string()]);
            return Err(unwritten(e));
        }
    };
    Ok(Submitted {
        sweep_job,
        later_job,
        shards: opts.shards,
        scripts: [sweep_script, later_script],
        logs,
    })
}

/// A job's log: the one Slurm names where it is on disk, else the one the
/// script asked for (`scontrol -o` separates its fields by spaces, so a log
/// path with a space comes back cut).
fn log_of(r: &JobRecord, asked: PathBuf) -> String {
    match &r.stdout {
        Some(named) if Path::new(named).is_file() => named.clone(),
        _ => asked.to_string_lossy().into_owned(),
    }
}

/// The records of job `id` (every task of an array).
fn records(scontrol: &Path, id: u64) -> Result<Vec<JobRecord>, SubmitError> {
    match slurm(scontrol, &["show", "job", "-o", &id.to_string()]) {
        Ok(text) => Ok(cluster::job_records(&text)),
        Err(SubmitError::Slurm { stderr, .. }) if stderr.contains("Invalid job id") => {
            Err(SubmitError::Vanished(id))
        }
        Err(e) => Err(e),
    }
}

/// Where the sweep's array stands, from Slurm; fails naming the first
/// failed task and its log (and cancels the later stages, which can then
/// never start). An array Slurm forgot before every task was seen done
/// succeeded if the later job (which starts only after every task did) has
/// left its wait.
fn array_progress(
    sub: &Submitted,
    scontrol: &Path,
    scancel: &Path,
) -> Result<cluster::ArrayState, SubmitError> {
    let tasks = match records(scontrol, sub.sweep_job) {
        Ok(tasks) => tasks,
        Err(SubmitError::Vanished(id)) => {
            let later = records(scontrol, sub.later_job)?;
            if later.first().is_none_or(|r| r.state == "PENDING") {
                return Err(SubmitError::Vanished(id));
            }
            return Ok(cluster::ArrayState {
                done: sub.shards,
                ..Default::default()
            });
        }
        Err(e) => return Err(e),
    };
    let st = cluster::array_state(&tasks, sub.shards);
    if let Some(bad) = st.failed.first() {
        let _ = slurm(scancel, &[&sub.later_job.to_string()]);
        let task = bad.array_task.clone().unwrap_or_else(|| "?".into());
        return Err(SubmitError::TaskFailed {
            job: sub.sweep_job,
            log: log_of(bad, cluster::sweep_log(&sub.logs, sub.sweep_job, &task)),
            task,
            state: bad.state.clone(),
            exit_code: bad.exit_code.clone(),
            later: sub.later_job,
        });
    }
    Ok(st)
}

/// Follows the jobs to the end, polling every `poll`; `say` hears each
/// change. Fails naming the first failed task and its log (and cancels the
/// later stages, which can then never start), or the later job's failure.
pub fn wait(sub: &Submitted, poll: Duration, mut say: impl FnMut(&str)) -> Result<(), SubmitError> {
    let sbatch = on_path("sbatch").ok_or(SubmitError::NoSbatch)?;
    let (scontrol, scancel) = (client("scontrol", &sbatch), client("scancel", &sbatch));
    let mut last = String::new();
    // Once every task is seen done the array is not asked about again:
    // Slurm forgets a finished job after its MinJobAge (300 s by default),
    // while the later stages may run on.
    let mut swept = false;
    loop {
        let st = match swept {
            true => cluster::ArrayState {
                done: sub.shards,
                ..Default::default()
            },
            false => array_progress(sub, &scontrol, &scancel)?,
        };
        swept = st.done == sub.shards;
        let later = records(&scontrol, sub.later_job)?;
        let now = match later.first() {
            Some(r) if r.succeeded() => {
                say(&format!(
                    "later stages (job {}) completed; all done",
                    sub.later_job
                ));
                return Ok(());
            }
            Some(r) if r.finished() => {
                return Err(SubmitError::LaterFailed {
                    job: sub.later_job,
                    state: r.state.clone(),
                    exit_code: r.exit_code.clone(),
                    log: log_of(r, cluster::later_log(&sub.logs, sub.later_job)),
                })
            }
            Some(r) => format!(
                "sweep (job {}): {} of {} tasks done, {} running; later stages (job {}): {}",
                sub.sweep_job,
                st.done,
                sub.shards,
                st.running,
                sub.later_job,
                r.state.to_lowercase()
            ),
            None => return Err(SubmitError::Vanished(sub.later_job)),
        };
        if now != last {
            say(&now);
            last = now;
        }
        std::thread::sleep(poll);
    }
}
