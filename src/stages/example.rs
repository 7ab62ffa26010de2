//! Example stage (a pipeline with `[example]`): the IDA of the report's
//! Fig. 5 block over every record, whether or not the block is one of the
//! study's, and its horizontal fractiles → `example_ida_points.parquet`,
//! `example_capacities.parquet`, `example_fractiles_horizontal.parquet`.
//!
//! Glue: each record's capacity is the sweep's ([`super::sweep::run_case`]:
//! the same certified search, grid and tolerance), and the fractiles are
//! the reduce stage's ([`super::reduce::horizontal_of_block`]: the same
//! definition and resurrection rule). Cases are numbered by record, 0, 1, …
//! The grid, the fit and every other table are left alone.

use std::path::PathBuf;
use std::time::Instant;

use super::reduce::{self, ReduceError};
use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use super::sweep::{self, SweepError};
use crate::pipeline::{BlockSpec, Plan};
use crate::tables::{self, TableError};

/// The example stage.
pub struct Example;

/// The example block's runs (the columns of `ida_points`).
pub const IDA: &str = "example_ida_points.parquet";
/// Its capacities, one per record (the columns of `capacities`).
pub const CAPACITIES: &str = "example_capacities.parquet";
/// Its horizontal fractiles (the columns of `fractiles_horizontal`).
pub const HORIZONTAL: &str = "example_fractiles_horizontal.parquet";
/// Every output of the stage.
pub const OUTPUTS: [&str; 3] = [IDA, CAPACITIES, HORIZONTAL];

/// Metadata key of every output: [`settings`] as JSON.
pub const META_SETTINGS: &str = "rocking.example.settings";

/// What the example's tables depend on: the sweep's settings with the
/// example block in place of the study's, and the fractile definition.
pub fn settings(plan: &Plan) -> serde_json::Value {
    let mut s = plan.sweep_settings_json();
    s["blocks"] = serde_json::json!([plan.example()]);
    if let Ok(r) = plan.records_study() {
        s["fractile"] = serde_json::json!(format!("{:?}", r.fractile));
    }
    s
}

impl Stage for Example {
    fn name(&self) -> &'static str {
        "example"
    }

    fn about(&self) -> &'static str {
        "Run the report's example block ([example], Fig. 5) over the records, even off the grid"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        if let Some(why) = study.plan.pulse_map_skips() {
            return Some(why);
        }
        study
            .plan
            .example()
            .is_none()
            .then(|| "the pipeline has no [example] block".to_string())
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        settings(&study.plan)
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        Ok(vec![study.records_table()])
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        OUTPUTS.iter().map(|n| study.path(n)).collect()
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx)?)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ExampleError {
    #[error("[example] block")]
    Sweep(#[source] SweepError),
    #[error(transparent)]
    Reduce(#[from] ReduceError),
    #[error(transparent)]
    Table(#[from] TableError),
}

fn run(cx: &Context) -> Result<Summary, ExampleError> {
    let started = Instant::now();
    let study = cx.study;
    let plan = &study.plan;
    let block: &BlockSpec = plan
        .example()
        .expect("not_needed skips a plan without [example]");
    let results = sweep::run_blocks(cx, "example", std::slice::from_ref(block))
        .map_err(ExampleError::Sweep)?;
    let mut ida = Vec::new();
    let mut caps = Vec::with_capacity(results.len());
    for r in results {
        ida.extend(r.ida);
        caps.push(r.capacity);
    }
    let horizontal = reduce::horizontal_of_block(plan, block, &caps, &ida)?;
    let meta = vec![(META_SETTINGS.to_string(), settings(plan).to_string())];
    tables::write(&study.path(IDA), &ida, &meta)?;
    tables::write(&study.path(CAPACITIES), &caps, &meta)?;
    tables::write(&study.path(HORIZONTAL), &horizontal, &meta)?;
    let overturned = caps.iter().filter(|c| c.eta_c.is_some()).count();
    let on_grid = plan.blocks().iter().any(|b| b == block);
    Ok(Summary {
        lines: vec![
            format!(
                "example block p = {:.4} 1/s, ε = {:.2}{}: {} records, {} runs, {overturned} \
                 overturned within the grid, in {:.2} s",
                block.p,
                block.eps,
                if on_grid {
                    " (also a block of the grid)"
                } else {
                    " (not on the grid)"
                },
                caps.len(),
                ida.len(),
                started.elapsed().as_secs_f64()
            ),
            format!(
                "wrote {} in {}",
                OUTPUTS.map(|n| n.trim_end_matches(".parquet")).join(", "),
                study.dir.display()
            ),
        ],
        headline: 0,
        also_wrote: Vec::new(),
    })
}
