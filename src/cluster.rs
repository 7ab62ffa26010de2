//! Slurm, as text: the job scripts `rocking submit` writes, and what it
//! reads back from `sbatch --parsable` and `scontrol show job -o`. No
//! processes and no files here (`ops::submit` runs them).
//!
//! The sweep is an array of N tasks, task K running the K-th shard
//! (`rocking sweep --shard K/N`; a requeued task resumes from the parts it
//! wrote); the later stages are one job that starts after every task
//! succeeded (`--dependency=afterok:<array>`) and runs `rocking run`, which
//! finds the sweep fresh from its N shard tables.

use std::path::{Path, PathBuf};

/// The array tasks' log, as the sweep script names it (`%A` the array's
/// job id, `%a` the task).
const SWEEP_LOG: &str = "sweep-%A_%a.log";
/// The later stages' log (`%j` its job id).
const LATER_LOG: &str = "after-%j.log";

/// The log the sweep script asks for of task `task` of array `job`, in `logs`.
pub fn sweep_log(logs: &Path, job: u64, task: &str) -> PathBuf {
    logs.join(
        SWEEP_LOG
            .replace("%A", &job.to_string())
            .replace("%a", task),
    )
}

/// The log the later script asks for, job `job`, in `logs`.
pub fn later_log(logs: &Path, job: u64) -> PathBuf {
    logs.join(LATER_LOG.replace("%j", &job.to_string()))
}

/// Everything the two job scripts need, as absolute paths.
#[derive(Debug, Clone, PartialEq)]
pub struct Jobs {
    /// The `rocking` binary the tasks run (the one that submitted them).
    pub binary: PathBuf,
    pub pipeline: PathBuf,
    /// The `--outputs` root.
    pub outputs: PathBuf,
    /// Where the tasks start (the submitting directory).
    pub workdir: PathBuf,
    /// Where Slurm writes the tasks' logs (the study's `slurm/` folder).
    pub logs: PathBuf,
    /// The study's name (the pipeline's `name`), for job names.
    pub name: String,
    pub shards: usize,
    /// Extra `sbatch` options, written as `#SBATCH` lines in both scripts.
    pub sbatch: Vec<String>,
}

/// Quotes `s` for a POSIX shell.
fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

fn quote_path(p: &Path) -> String {
    quote(&p.to_string_lossy())
}

/// A path as one word of a command a message suggests: as it is where it
/// holds only letters, digits and `/._-+,:@=`, else quoted ([`quote`]).
pub fn shell_word(p: &Path) -> String {
    let text = p.to_string_lossy();
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_alphanumeric() || "/._-+,:@=".contains(c));
    if plain {
        text.into_owned()
    } else {
        quote(&text)
    }
}

/// A value of an `#SBATCH` line, as sbatch reads it: in double quotes, a
/// backslash before `"`, `\` and `#` (sbatch ends a directive at an
/// unquoted space and at an unescaped `#`; a path with a space once made
/// an "Invalid directive").
fn directive(value: &str) -> String {
    let mut s = String::with_capacity(value.len() + 2);
    s.push('"');
    for c in value.chars() {
        if matches!(c, '"' | '\\' | '#') {
            s.push('\\');
        }
        s.push(c);
    }
    s.push('"');
    s
}

/// An `--output` file pattern for a log `name` (holding Slurm's `%A`, `%a`
/// or `%j`) in the folder `logs`: a `%` of the folder doubled, so that
/// Slurm does not read it as a replacement symbol.
fn log_pattern(logs: &Path, name: &str) -> String {
    format!("{}/{name}", logs.to_string_lossy().replace('%', "%%"))
}

/// A user's `--sbatch` option as a directive: the value after its first
/// `=` quoted as [`directive`] quotes ours (`--comment=my run`).
fn user_directive(option: &str) -> String {
    match option.split_once('=') {
        Some((key, value)) => format!("{key}={}", directive(value)),
        None => option.to_string(),
    }
}

impl Jobs {
    /// Why these paths cannot be written into the scripts, if they cannot:
    /// a control character (a line break ends a directive, and the rest
    /// would run as a shell line), or a backslash in the logs' folder
    /// (Slurm then takes `%A_%a` literally, and every task writes one log).
    pub fn unwritable(&self) -> Option<String> {
        let paths = [
            &self.binary,
            &self.pipeline,
            &self.outputs,
            &self.workdir,
            &self.logs,
        ];
        if let Some(p) = paths
            .iter()
            .find(|p| p.to_string_lossy().chars().any(char::is_control))
        {
            return Some(format!(
                "{:?} holds a control character (a line break, say), which a job script \
                 cannot carry",
                p.to_string_lossy()
            ));
        }
        self.logs.to_string_lossy().contains('\\').then(|| {
            format!(
                "the logs' folder {} holds a backslash, which makes Slurm write every task's \
                 log to one file: give --outputs a path without one",
                self.logs.display()
            )
        })
    }

    fn header(&self, what: &str, lines: &[String]) -> String {
        let mut s = String::from("#!/bin/sh\n");
        for l in lines {
            s.push_str(&format!("#SBATCH {l}\n"));
        }
        for extra in &self.sbatch {
            s.push_str(&format!("#SBATCH {}\n", user_directive(extra)));
        }
        s.push_str(&format!(
            "# Written by `rocking submit` for the study `{}`: {what}.\n\
             # Submit it again by hand with sbatch if needed (docs/guide.md, \"Running on a cluster\").\n",
            self.name
        ));
        s
    }

    /// The array job: task K of N sweeps the K-th shard.
    pub fn sweep_script(&self) -> String {
        let lines = [
            format!(
                "--job-name={}",
                directive(&format!("rocking-{}-sweep", self.name))
            ),
            format!("--array=1-{}", self.shards),
            format!(
                "--output={}",
                directive(&log_pattern(&self.logs, SWEEP_LOG))
            ),
            "--requeue".to_string(),
            format!("--chdir={}", directive(&self.workdir.to_string_lossy())),
        ];
        let mut s = self.header(
            &format!(
                "the sweep as {} array tasks; task K runs shard K/{} with one thread per CPU \
                 Slurm gives it, and a requeued task resumes from the parts it wrote",
                self.shards, self.shards
            ),
            &lines,
        );
        s.push_str(&format!(
            "exec {} sweep {} --outputs {} --shard \"${{SLURM_ARRAY_TASK_ID}}/{}\" \
             --threads \"${{SLURM_CPUS_PER_TASK:-1}}\"\n",
            quote_path(&self.binary),
            quote_path(&self.pipeline),
            quote_path(&self.outputs),
            self.shards
        ));
        s
    }

    /// The job of the later stages, run once the array has succeeded.
    pub fn later_script(&self) -> String {
        let lines = [
            format!(
                "--job-name={}",
                directive(&format!("rocking-{}-after", self.name))
            ),
            format!(
                "--output={}",
                directive(&log_pattern(&self.logs, LATER_LOG))
            ),
            format!("--chdir={}", directive(&self.workdir.to_string_lossy())),
        ];
        let mut s = self.header(
            "the stages after the sweep (rocking run finds the sweep fresh from its shards)",
            &lines,
        );
        s.push_str(&format!(
            "exec {} run {} --outputs {} --threads \"${{SLURM_CPUS_PER_TASK:-1}}\"\n",
            quote_path(&self.binary),
            quote_path(&self.pipeline),
            quote_path(&self.outputs)
        ));
        s
    }
}

/// Something Slurm said that is not what was expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SlurmText {
    #[error("sbatch printed `{0}`, not a job id")]
    NoJobId(String),
}

/// The job id in `sbatch --parsable`'s output (`ID` or `ID;CLUSTER`).
pub fn job_id(sbatch_stdout: &str) -> Result<u64, SlurmText> {
    let line = sbatch_stdout.trim();
    line.split(';')
        .next()
        .and_then(|id| id.trim().parse().ok())
        .ok_or_else(|| SlurmText::NoJobId(line.to_string()))
}

/// One record of `scontrol show job -o`: a job, one task of an array, or
/// the array's tasks still pending together.
#[derive(Debug, Clone, PartialEq)]
pub struct JobRecord {
    pub job_id: u64,
    /// `ArrayTaskId`: a number, or a range such as `2-3` while pending.
    pub array_task: Option<String>,
    pub state: String,
    pub reason: String,
    pub exit_code: String,
    pub stdout: Option<String>,
}

impl JobRecord {
    /// Whether the job is over (whatever its outcome).
    pub fn finished(&self) -> bool {
        !matches!(
            self.state.as_str(),
            "PENDING"
                | "RUNNING"
                | "CONFIGURING"
                | "COMPLETING"
                | "REQUEUED"
                | "REQUEUE_FED"
                | "REQUEUE_HOLD"
                | "RESIZING"
                | "SUSPENDED"
                | "STAGE_OUT"
                | "SIGNALING"
        )
    }

    pub fn succeeded(&self) -> bool {
        self.state == "COMPLETED"
    }
}

/// Parses `scontrol show job -o` (one job per line, `Key=Value` fields).
pub fn job_records(text: &str) -> Vec<JobRecord> {
    text.lines()
        .filter(|l| l.contains("JobId="))
        .filter_map(|line| {
            let field = |key: &str| {
                line.split_whitespace()
                    .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
                    .map(str::to_string)
            };
            Some(JobRecord {
                job_id: field("JobId")?.parse().ok()?,
                array_task: field("ArrayTaskId"),
                state: field("JobState")?,
                reason: field("Reason").unwrap_or_default(),
                exit_code: field("ExitCode").unwrap_or_default(),
                stdout: field("StdOut"),
            })
        })
        .collect()
}

/// Where an array stands: tasks done, tasks over but failed, tasks left.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ArrayState {
    pub done: usize,
    pub failed: Vec<JobRecord>,
    pub running: usize,
}

/// Sums the records of an array job of `tasks` tasks (pending ranges count
/// as as many tasks as they span).
pub fn array_state(records: &[JobRecord], tasks: usize) -> ArrayState {
    let mut st = ArrayState::default();
    for r in records {
        if r.succeeded() {
            st.done += 1;
        } else if r.finished() {
            st.failed.push(r.clone());
        } else if r.state == "RUNNING" || r.state == "COMPLETING" {
            st.running += 1;
        }
    }
    st.done = st.done.min(tasks);
    st
}

#[cfg(test)]
mod tests {
    use super::*;

    fn jobs() -> Jobs {
        Jobs {
            binary: "/opt/rocking/bin/rocking".into(),
            pipeline: "/home/a b/paper.toml".into(),
            outputs: "/scratch/it's/outputs".into(),
            workdir: "/home/a b".into(),
            logs: "/scratch/it's/outputs/paper/slurm".into(),
            name: "paper".into(),
            shards: 10,
            sbatch: vec!["--partition=debug".into(), "--cpus-per-task=8".into()],
        }
    }

    /// A directive's value as sbatch reads it (its `_get_argument`: a
    /// double quote toggles quoting, a backslash takes the next character
    /// as it is, an unescaped `#` starts a comment), escaped by hand.
    #[test]
    fn directives_quote_spaces_and_escape_what_sbatch_reads() {
        assert_eq!(directive("/a b/x-%A.log"), r#""/a b/x-%A.log""#);
        assert_eq!(directive(r##"/it's "#1" \x"##), r##""/it's \"\#1\" \\x""##);
        assert_eq!(
            sweep_log(Path::new("/l"), 10, "3"),
            Path::new("/l/sweep-10_3.log")
        );
        assert_eq!(
            later_log(Path::new("/l o"), 11),
            Path::new("/l o/after-11.log")
        );
        // A % of the folder is doubled (Slurm's %x would be the job name).
        assert_eq!(
            log_pattern(Path::new("/a%x"), SWEEP_LOG),
            "/a%%x/sweep-%A_%a.log"
        );
        assert_eq!(user_directive("--comment=my run"), r#"--comment="my run""#);
        assert_eq!(user_directive("--exclusive"), "--exclusive");
        let mut bad = jobs();
        assert_eq!(bad.unwritable(), None);
        bad.logs = "/s/a\\b".into();
        assert!(bad.unwritable().unwrap().contains("backslash"));
        bad.logs = "/s/a".into();
        bad.outputs = "/s/a\nb".into();
        assert!(bad.unwritable().unwrap().contains("control character"));
    }

    /// The scripts as a shell reads them: every path one word, the shard
    /// from the task id, the user's options as directives.
    #[test]
    fn scripts_quote_paths_and_carry_the_options() {
        let s = jobs().sweep_script();
        assert!(s.starts_with("#!/bin/sh\n"));
        assert!(s.contains("#SBATCH --array=1-10\n"));
        // The user's values quoted as ours (sbatch strips the quotes).
        assert!(s.contains("#SBATCH --partition=\"debug\"\n#SBATCH --cpus-per-task=\"8\"\n"));
        // Directives' values in double quotes (sbatch split them at a space).
        assert!(
            s.contains("#SBATCH --output=\"/scratch/it's/outputs/paper/slurm/sweep-%A_%a.log\"\n")
        );
        assert!(s.contains("#SBATCH --chdir=\"/home/a b\"\n"));
        assert!(s.contains("#SBATCH --job-name=\"rocking-paper-sweep\"\n"));
        assert!(s.contains(
            "exec '/opt/rocking/bin/rocking' sweep '/home/a b/paper.toml' \
             --outputs '/scratch/it'\\''s/outputs' --shard \"${SLURM_ARRAY_TASK_ID}/10\""
        ));
        // Every #SBATCH line comes before the first command (sbatch stops
        // reading directives there).
        let first_cmd = s.lines().position(|l| l.starts_with("exec")).unwrap();
        assert!(s.lines().skip(first_cmd).all(|l| !l.starts_with("#SBATCH")));
        let l = jobs().later_script();
        assert!(l.contains("exec '/opt/rocking/bin/rocking' run '/home/a b/paper.toml'"));
        assert!(!l.contains("--array"));
    }

    #[test]
    fn job_ids_and_records_are_read_from_slurms_text() {
        assert_eq!(job_id("1234\n"), Ok(1234));
        assert_eq!(job_id("77;cluster2"), Ok(77));
        assert!(job_id("sbatch: error: Batch job submission failed").is_err());
        // As printed by Slurm 22.05 (abridged) for an array of 3: task 3 done,
        // task 2 failed, task 1 still pending as a range.
        let text = "JobId=12 ArrayJobId=10 ArrayTaskId=3 JobName=x JobState=COMPLETED Reason=None ExitCode=0:0 StdOut=/l/sweep-10_3.log\n\
                    JobId=11 ArrayJobId=10 ArrayTaskId=2 JobName=x JobState=FAILED Reason=NonZeroExitCode ExitCode=1:0 StdOut=/l/sweep-10_2.log\n\
                    JobId=10 ArrayJobId=10 ArrayTaskId=1 JobName=x JobState=PENDING Reason=Priority ExitCode=0:0 StdOut=/l/sweep-10_1.log\n";
        let recs = job_records(text);
        assert_eq!(recs.len(), 3);
        assert_eq!(recs[1].array_task.as_deref(), Some("2"));
        assert_eq!(recs[1].stdout.as_deref(), Some("/l/sweep-10_2.log"));
        let st = array_state(&recs, 3);
        assert_eq!((st.done, st.running, st.failed.len()), (1, 0, 1));
        assert_eq!(st.failed[0].exit_code, "1:0");
        assert!(!recs[2].finished() && recs[0].finished() && recs[1].finished());
    }
}
