//! Tree stage (a pipeline with `[tree]`): the report's example block on
//! each path of a logic tree over ε and the model, over every record →
//! `tree_capacities.parquet` (the columns of `capacities`, one row per
//! record × branch: the block's `eps` and `model` are the branch's).
//!
//! Glue: each case is the sweep's ([`super::sweep::run_case`]: the same
//! certified search, grid and tolerance) over the branches' blocks as the
//! plan built them; the fragilities, their mixture and the tornado are the
//! report's, from these capacities (docs/MODEL.md §19).

use std::path::PathBuf;
use std::time::Instant;

use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use super::sweep::{self, SweepError};
use crate::pipeline::{BlockSpec, Plan};
use crate::tables::{self, TableError};

/// The tree stage.
pub struct Tree;

/// The branches' capacities (the columns of `capacities`).
pub const CAPACITIES: &str = "tree_capacities.parquet";

/// Metadata key of its output: [`settings`] as JSON.
pub const META_SETTINGS: &str = "rocking.tree.settings";

/// What the capacities depend on: the sweep's settings with the branches'
/// blocks in place of the study's, and the branches.
pub fn settings(plan: &Plan) -> serde_json::Value {
    let mut s = plan.sweep_settings_json();
    if let Some(t) = plan.tree() {
        s["blocks"] = serde_json::json!(t.branches.iter().map(|b| &b.block).collect::<Vec<_>>());
        s["tree"] = serde_json::json!(t.branches);
    }
    s
}

impl Stage for Tree {
    fn name(&self) -> &'static str {
        "tree"
    }

    fn about(&self) -> &'static str {
        "Run the example block on each branch of the logic tree ([tree]: ε, the model) over the records"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        if let Some(why) = study.plan.pulse_map_skips() {
            return Some(why);
        }
        study
            .plan
            .tree()
            .is_none()
            .then(|| "the pipeline has no [tree]".to_string())
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        settings(&study.plan)
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        Ok(vec![study.records_table()])
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        vec![study.path(CAPACITIES)]
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx)?)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum TreeStageError {
    #[error("[tree] branch")]
    Sweep(#[source] SweepError),
    #[error(transparent)]
    Table(#[from] TableError),
}

fn run(cx: &Context) -> Result<Summary, TreeStageError> {
    let started = Instant::now();
    let study = cx.study;
    let plan = &study.plan;
    let tree = plan.tree().expect("not_needed skips a plan without [tree]");
    let blocks: Vec<BlockSpec> = tree.branches.iter().map(|b| b.block.clone()).collect();
    let results = sweep::run_blocks(cx, "tree", &blocks).map_err(TreeStageError::Sweep)?;
    let runs: i64 = results.iter().map(|r| r.capacity.runs).sum();
    let caps: Vec<_> = results.into_iter().map(|r| r.capacity).collect();
    let meta = vec![(META_SETTINGS.to_string(), settings(plan).to_string())];
    tables::write(&study.path(CAPACITIES), &caps, &meta)?;
    Ok(Summary {
        lines: vec![
            format!(
                "example block over {} branches of the tree: {} records × {} branches, {runs} \
                 runs, in {:.2} s",
                blocks.len(),
                caps.len() / blocks.len().max(1),
                blocks.len(),
                started.elapsed().as_secs_f64()
            ),
            format!("wrote tree_capacities in {}", study.dir.display()),
        ],
        headline: 0,
        also_wrote: Vec::new(),
    })
}
