//! `rocking capacity` over many records and blocks in one process: every
//! record × block case certified (`ida::capacity_certified`), on every
//! core, results in case order (record outer, block inner, as the sweep).
//!
//! A case's capacity does not depend on how the cases are spread over the
//! workers: a case alone runs its search with the runs ahead of need on
//! every core ([`super::pool::capacity_certified_parallel`]), several
//! cases run one search per worker, and both give the sequential search's
//! result.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::pool;
use crate::ida::{self, Certified, ImGrid, Trace};
use crate::physics::{PhysicsError, RunSpec};
use crate::records::{self as record, LoadedRecord, RecordError};
use crate::tables::sweep::CapacityRow;

/// One block of a batch: its name (empty for a p × ε block), its
/// slenderness when known (from its dimensions or given; the linearised
/// model itself needs none), its run specification at η = 1, and its
/// base's friction with whether it slides first (when μ is given).
#[derive(Debug, Clone)]
pub struct NamedSpec {
    pub name: String,
    pub alpha_rad: Option<f64>,
    pub spec: RunSpec,
    pub mu: Option<f64>,
    pub slides_first: Option<bool>,
}

/// How a block is to be run, as a user asks: the model and its integrator,
/// the linearisation's accepted error and the overturning criterion.
#[derive(Debug, Clone, Copy)]
pub struct Asked {
    pub model: crate::physics::ModelChoice,
    pub solver: crate::physics::Solver,
    pub auto_tol: f64,
    pub overturn: crate::physics::Overturn,
}

impl NamedSpec {
    /// The block `name` (p, ε and α when known, on a base of `friction`
    /// when known) run as `asked`, its model
    /// resolved and its run specification at η = 1 checked; with why that
    /// model.
    pub fn ask(
        name: String,
        p: f64,
        eps: f64,
        alpha_rad: Option<f64>,
        friction: Option<crate::physics::friction::Friction>,
        asked: &Asked,
    ) -> Result<(NamedSpec, String), PhysicsError> {
        let (model, why) =
            asked
                .model
                .resolve(alpha_rad, friction, asked.solver, asked.auto_tol)?;
        let spec = RunSpec {
            overturn: asked.overturn,
            ..RunSpec::new(p, eps, 1.0, model)
        };
        spec.validate()?;
        Ok((
            NamedSpec {
                name,
                alpha_rad,
                spec,
                mu: None,
                slides_first: None,
            },
            why,
        ))
    }
}

/// A case that failed, named.
#[derive(Debug, thiserror::Error)]
pub enum CapacityError {
    #[error(transparent)]
    Discover(#[from] crate::records::CollectError),
    #[error(transparent)]
    Record(#[from] RecordError),
    #[error("record {record}, block {block}")]
    Case {
        record: String,
        block: String,
        #[source]
        source: PhysicsError,
    },
    #[error(transparent)]
    OutPath(#[from] crate::outpath::OutPathError),
    #[error(
        "{} and {}: two records of one id `{id}` (the file stem); record ids must be unique",
        a.display(),
        b.display()
    )]
    SameId { id: String, a: PathBuf, b: PathBuf },
}

/// The records at `paths` (AT2 files, or folders searched recursively for
/// `*.AT2`), sorted by path, each read once; on the floor of `building`
/// when one is given.
pub fn load_records(
    paths: &[PathBuf],
    building: Option<&crate::floor::Building>,
) -> Result<Vec<LoadedRecord>, CapacityError> {
    let files = crate::records::discover(paths).map_err(crate::records::CollectError::from)?;
    // A record's id is its file stem, as in a records table: two files of
    // one stem (in two folders) would be two records of one id.
    let mut seen = std::collections::BTreeMap::new();
    for f in &files {
        let stem = f
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        if let Some(other) = seen.insert(stem.clone(), f) {
            return Err(CapacityError::SameId {
                id: stem,
                a: other.clone(),
                b: f.clone(),
            });
        }
    }
    files
        .par_iter()
        .map(|f| record::load_on(f, building).map_err(CapacityError::from))
        .collect()
}

/// The certified capacity of every record × block, in case order. `done`
/// is called with each case's result, from any worker.
pub fn capacities(
    records: &[LoadedRecord],
    blocks: &[NamedSpec],
    grid: &ImGrid,
    tol: f64,
    done: &(dyn Fn(&Certified) + Sync),
) -> Result<Vec<Certified>, CapacityError> {
    let cases: Vec<(usize, usize)> = (0..records.len())
        .flat_map(|r| (0..blocks.len()).map(move |b| (r, b)))
        .collect();
    let one = |&(r, b): &(usize, usize), alone: bool| {
        let (rec, block) = (&records[r], &blocks[b]);
        let certified = if alone {
            pool::capacity_certified_parallel(&rec.exc, &block.spec, grid, tol, Trace::StopAtFirst)
        } else {
            ida::capacity_certified(&rec.exc, &block.spec, grid, tol, Trace::StopAtFirst)
        };
        if let Ok(c) = &certified {
            done(c);
        }
        certified.map_err(|source| CapacityError::Case {
            record: rec.record_id.clone(),
            block: block_label(block),
            source,
        })
    };
    // Fewer cases than workers: each case in turn on every core; else one
    // case per worker at a time.
    if cases.len() < rayon::current_num_threads() {
        cases.iter().map(|c| one(c, true)).collect()
    } else {
        cases.par_iter().map(|c| one(c, false)).collect()
    }
}

/// The batch's capacities as the `capacities` table's rows (the sweep's
/// schema), in case order: `capacity --out`'s table, and Python's.
pub fn rows(
    records: &[LoadedRecord],
    blocks: &[NamedSpec],
    results: &[Certified],
) -> Vec<CapacityRow> {
    results
        .iter()
        .enumerate()
        .map(|(case, c)| {
            let (rec, b) = (&records[case / blocks.len()], &blocks[case % blocks.len()]);
            CapacityRow {
                pfa_over_pga: rec.floor.map(|f| f.pfa_over_pga),
                slides_first: b.slides_first == Some(true),
                ..CapacityRow::of(case, &rec.record_id, &b.name, &b.spec, b.alpha_rad, c)
            }
        })
        .collect()
}

/// A block as errors name it: its name, or its p and ε.
fn block_label(block: &NamedSpec) -> String {
    if block.name.is_empty() {
        format!(
            "p = {} 1/s, ε = {}",
            crate::decimal::shortest(block.spec.p),
            crate::decimal::shortest(block.spec.eps)
        )
    } else {
        block.name.clone()
    }
}

/// Checks that `out` is a `.parquet` file that is none of `inputs` (nor,
/// through links, resolves to one).
pub fn check_out(out: &Path, inputs: &[PathBuf]) -> Result<(), CapacityError> {
    let inputs: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    Ok(crate::outpath::check("--out", out, "parquet", &inputs)?)
}
