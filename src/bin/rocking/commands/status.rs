//! `rocking status`: each stage as fresh, stale (and why) or not needed.

use rocking::stages::engine;

use super::args::PipelineArgs;

/// Show each stage of a pipeline as fresh or stale, and why, without running anything.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(flatten)]
    pipeline: PipelineArgs,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let study = args.pipeline.study()?;
    for (stage, fresh) in engine::status(&study) {
        println!("{stage:<12} {fresh}");
    }
    Ok(())
}
