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
    // Where the study's outputs are looked for: said first, since a relative
    // --outputs (the default) depends on the directory status runs in.
    let dir = std::path::absolute(&study.dir).unwrap_or_else(|_| study.dir.clone());
    println!("outputs of `{}`: {}", study.plan.name, dir.display());
    if !study.dir.exists() {
        println!(
            "(nothing there yet{}: run `rocking run {}`, or pass --outputs DIR where it ran)",
            if args.pipeline.outputs.is_relative() {
                "; --outputs is relative to the current directory"
            } else {
                ""
            },
            args.pipeline.pipeline.display()
        );
    }
    if let Some(who) = rocking::stages::lock::holder(&study.dir) {
        println!(
            "running now: {who} holds the study; the stages below are as its last finished \
             stage left them"
        );
    }
    for (stage, fresh) in engine::status(&study) {
        println!("{stage:<12} {fresh}");
    }
    Ok(())
}
