//! `rocking submit`: the study on Slurm (an array for the sweep, one job
//! for the later stages), optionally followed to the end.

use std::time::Duration;

use rocking::ops::submit::{self, SubmitOptions};

use super::args::PipelineArgs;
use crate::reporter::Terminal;

/// A count of shards: 1 or more (0 was read as the shard `1/0`).
fn shard_count(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(0) => Err("the sweep runs as 1 shard or more".into()),
        Ok(n) => Ok(n),
        Err(_) => Err(format!("`{text}` is not a count of shards (1, 2, …)")),
    }
}

/// Run a study on Slurm: the sweep as an array of --shards tasks, the later
/// stages as one job after it.
///
/// Ingests the records here, writes the job scripts into
/// <outputs>/<name>/slurm/ (sweep.sbatch, after.sbatch; kept and readable
/// once submitted, the tasks' logs beside them; a submission sbatch refuses
/// leaves none, and its error says why), submits the sweep with `sbatch
/// --array=1-N` (task K runs `rocking sweep --shard K/N` with one thread per
/// CPU Slurm gives it; a requeued task resumes from the parts it wrote) and
/// `rocking run` with `--dependency=afterok:<array>`, and prints both job
/// ids. The tasks run this same binary, from this directory; the outputs
/// must be on a filesystem the nodes share. With --wait it follows the jobs
/// and exits non-zero naming a failed task and its log.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pipeline: PipelineArgs,
    /// Array tasks: the sweep's shards, 1 or more and at most its chunks of 32
    /// cases (a task without a chunk would have no work: refused).
    #[arg(long, value_name = "N", value_parser = shard_count)]
    shards: usize,
    /// Follow the jobs until they end; fail naming a failed task and its log.
    #[arg(long)]
    wait: bool,
    /// An sbatch option for both jobs (repeatable), e.g. --sbatch=--partition=long
    /// --sbatch=--cpus-per-task=8 --sbatch=--time=01:00:00.
    #[arg(long, value_name = "ARG", allow_hyphen_values = true)]
    sbatch: Vec<String>,
    /// Seconds between checks while waiting.
    #[arg(long, value_name = "S", default_value_t = 5.0, hide = true)]
    poll: f64,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let study = args.pipeline.study()?;
    let sub = submit::submit(
        &study,
        &SubmitOptions {
            outputs: args.pipeline.outputs.clone(),
            shards: args.shards,
            sbatch: args.sbatch,
            command: super::run::command_line(),
        },
        &Terminal::new(),
    )?;
    println!(
        "submitted the sweep as job {} ({} array tasks) and the later stages as job {} (after it)",
        sub.sweep_job, sub.shards, sub.later_job
    );
    println!(
        "scripts: {} and {}; logs in {}",
        sub.scripts[0].display(),
        sub.scripts[1].display(),
        sub.logs.display()
    );
    if args.wait {
        let poll = Duration::from_secs_f64(args.poll.clamp(0.2, 600.0));
        submit::wait(&sub, poll, |line| eprintln!("{line}"))?;
        println!("done: report in {}", study.path("report.md").display());
    }
    Ok(())
}
