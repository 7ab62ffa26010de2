//! The damage stage: each record's capacity for each limit state of
//! `[damage]` (default `rocking=0.1,large_rocking=0.5,overturned`), and
//! each state's lognormal in every IM, by the paper's fractiles and by
//! censored maximum likelihood (docs/MODEL.md §15).
//!
//! Glue: reads the sweep's runs and capacities and the records' IMs (the
//! ims stage's tables), calls [`crate::damage`], and writes
//! `state_capacities` and `damage_states` through
//! [`crate::tables::damage`]; with `[example]` the same two tables of the
//! report's example block (`example_…`).

use std::collections::BTreeMap;
use std::path::PathBuf;

use rayon::prelude::*;

use super::ims::ImsError;
use super::reduce::{self, ReduceError};
use super::stage::{BoxError, Context, Shard, Stage, Study, Summary};
use super::{example, ims, sweep};
use crate::damage::{self, DamageStates, FitMethod, StateCapacity};
use crate::im::{self, Im, RecordIms};
use crate::pipeline::BlockSpec;
use crate::stats::FractileDef;
use crate::tables;
use crate::tables::damage::{DamageStateRow, StateCapacityRow};
use crate::tables::sweep::{CapacityRow, IdaRow};

/// The damage stage.
pub struct Damage;

/// Every record's capacity for every state of every block.
pub const CAPACITIES: &str = "state_capacities.parquet";
/// Every state's lognormal of every block in every IM, both methods.
pub const STATES: &str = "damage_states.parquet";
/// The same two of the example block (with `[example]`).
pub const EXAMPLE_CAPACITIES: &str = "example_state_capacities.parquet";
pub const EXAMPLE_STATES: &str = "example_damage_states.parquet";

impl Stage for Damage {
    fn name(&self) -> &'static str {
        "damage"
    }

    fn about(&self) -> &'static str {
        "Each record's capacity for each limit state ([damage]), and each state's lognormal in every IM"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        study.plan.pulse_map_skips()
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        match study.plan.records_study() {
            Ok(r) => serde_json::json!({
                "states": r.damage.text(),
                "fractile": r.fractile.name(),
            }),
            Err(_) => serde_json::Value::Null,
        }
    }

    fn inputs(&self, study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        let mut inputs = match sweep::dataset(&study.dir) {
            Ok((ida, cap)) => ida.into_iter().chain(cap).collect(),
            Err(_) => vec![
                study.path("ida_points.parquet"),
                study.path("capacities.parquet"),
            ],
        };
        inputs.push(study.records_table());
        inputs.push(study.path(ims::RECORD_IMS));
        if study.plan.example().is_some() {
            inputs.extend([example::IDA, example::CAPACITIES].map(|n| study.path(n)));
        }
        Ok(inputs)
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        let mut out = vec![study.path(CAPACITIES), study.path(STATES)];
        if study.plan.example().is_some() {
            out.extend([EXAMPLE_CAPACITIES, EXAMPLE_STATES].map(|n| study.path(n)));
        }
        out
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx.study)?)
    }
}

/// Why the damage stage fails.
#[derive(Debug, thiserror::Error)]
pub enum DamageStageError {
    /// The sweep's tables, read as reduce reads them.
    #[error(transparent)]
    Sweep(#[from] ReduceError),
    /// The records' IMs, as the ims stage wrote them.
    #[error(transparent)]
    Ims(#[from] ImsError),
    #[error(transparent)]
    Table(#[from] crate::tables::TableError),
    #[error(transparent)]
    NotRecords(#[from] crate::pipeline::NotRecords),
    #[error("record {0} has no row in record_ims; rerun the ims stage (`rocking run`)")]
    NoIms(String),
}

fn run(study: &Study) -> Result<Summary, DamageStageError> {
    let plan = study.plan.records_study()?;
    let states = &plan.damage;
    let (caps, ida) = reduce::load(study)?;
    let by_case = reduce::split_by_case(&ida, caps.len())?;
    // Text records' measures are the floor's (PFA, PFV, FSA(T)), the
    // states fitted in those.
    let stood_on = study.stood_on();
    let record_ims = ims::read_record_ims(&study.dir, stood_on)?;
    let measures = Im::capacity_measures_of(stood_on);
    let n_blocks = plan.blocks.len();
    let n_records = caps.len() / n_blocks;
    let of = |k: usize| &by_case[k];
    let results: Vec<BlockDamage> = (0..n_blocks)
        .into_par_iter()
        .map(|bi| {
            let cases = (0..n_records).map(|ri| ri * n_blocks + bi);
            let records: Vec<(&CapacityRow, &[&IdaRow])> =
                cases.map(|k| (&caps[k], of(k).as_slice())).collect();
            of_block(
                bi,
                &plan.blocks[bi],
                &records,
                &record_ims,
                (states, &measures),
                plan.fractile,
            )
        })
        .collect::<Result<_, _>>()?;
    let meta = vec![("rocking.damage.states".to_string(), states.text())];
    let (cap_rows, state_rows) = flatten(results);
    tables::write(&study.path(CAPACITIES), &cap_rows, &meta)?;
    tables::write(&study.path(STATES), &state_rows, &meta)?;
    let mut wrote = vec!["state_capacities", "damage_states"];
    if let Some(block) = plan.example.as_ref() {
        let caps: Vec<CapacityRow> = reduce::read(&study.dir, example::CAPACITIES)?;
        let ida: Vec<IdaRow> = reduce::read(&study.dir, example::IDA)?;
        let by_case = reduce::split_by_case(&ida, caps.len())?;
        let records: Vec<(&CapacityRow, &[&IdaRow])> = caps
            .iter()
            .zip(&by_case)
            .map(|(c, r)| (c, r.as_slice()))
            .collect();
        let found = of_block(
            0,
            block,
            &records,
            &record_ims,
            (states, &measures),
            plan.fractile,
        )?;
        let (c, s) = flatten(vec![found]);
        tables::write(&study.path(EXAMPLE_CAPACITIES), &c, &meta)?;
        tables::write(&study.path(EXAMPLE_STATES), &s, &meta)?;
        wrote.extend(["example_state_capacities", "example_damage_states"]);
    }
    let shares: Vec<String> = states
        .states()
        .iter()
        .map(|s| {
            let of_state = cap_rows.iter().filter(|r| r.state == s.name);
            let (n, hit) = of_state.fold((0, 0), |(n, h), r| (n + 1, h + usize::from(r.reached)));
            format!("{} {:.0} %", s.name, 100.0 * hit as f64 / n.max(1) as f64)
        })
        .collect();
    Ok(Summary {
        lines: vec![
            format!(
                "limit states of {n_blocks} blocks × {n_records} records, fitted in {} IMs; \
                 capacities reached within the grid: {}",
                measures.len(),
                shares.join(", ")
            ),
            format!("wrote {} in {}", wrote.join(", "), study.dir.display()),
        ],
        headline: 0,
        also_wrote: Vec::new(),
    })
}

/// One block's rows of both tables.
struct BlockDamage {
    capacities: Vec<StateCapacityRow>,
    states: Vec<DamageStateRow>,
}

fn flatten(blocks: Vec<BlockDamage>) -> (Vec<StateCapacityRow>, Vec<DamageStateRow>) {
    let (mut c, mut s) = (Vec::new(), Vec::new());
    for b in blocks {
        c.extend(b.capacities);
        s.extend(b.states);
    }
    (c, s)
}

/// Lilliefors' p of state `k`'s capacities over the records in an IM
/// (`in_im` of a record's index and η), as `--direct` checks them.
fn lognormal_p_in(
    per_record: &[Vec<StateCapacity>],
    k: usize,
    in_im: &dyn Fn(usize, f64) -> Option<f64>,
) -> Option<f64> {
    let mut caps: Vec<f64> = per_record
        .iter()
        .enumerate()
        .map(|(r, found)| match found[k] {
            StateCapacity::Reached(eta) => in_im(r, eta).unwrap_or(f64::NAN),
            StateCapacity::NotReached(_) => f64::INFINITY,
        })
        .collect();
    caps.sort_by(f64::total_cmp);
    damage::lognormal_p(&caps)
}

/// The states' capacities of one block under each record (its capacity row
/// and runs, in record order), and their fits in each of `measures`. Fits are made at
/// α = 1 and stated in the IM's dimensionless form; a block with α also
/// gets its medians in the IM's unit (ln IM_c shifts by power·ln α).
fn of_block(
    index: usize,
    block: &BlockSpec,
    records: &[(&CapacityRow, &[&IdaRow])],
    record_ims: &BTreeMap<String, RecordIms>,
    (states, measures): (&DamageStates, &[Im]),
    def: FractileDef,
) -> Result<BlockDamage, DamageStageError> {
    let mut ims = Vec::with_capacity(records.len());
    let mut per_record = Vec::with_capacity(records.len());
    let mut capacities = Vec::new();
    for (cap, runs) in records {
        let id = &cap.record_id;
        ims.push(
            record_ims
                .get(id)
                .ok_or_else(|| DamageStageError::NoIms(id.clone()))?,
        );
        let found = damage::capacities(
            states,
            runs.iter().map(|r| damage::StateRun {
                eta: r.eta,
                edp: r.edp,
                slide_m: r.slide_max_m.unwrap_or(0.0),
                overturned: r.overturned,
            }),
            cap.eta_c,
        );
        for (s, c) in states.states().iter().zip(&found) {
            let (eta, reached) = match *c {
                StateCapacity::Reached(e) => (e, true),
                StateCapacity::NotReached(e) => (e, false),
            };
            capacities.push(StateCapacityRow {
                block_index: index as i64,
                block: block.name.clone(),
                p: block.p,
                eps: block.eps,
                record_id: id.clone(),
                state: s.name.clone(),
                eta,
                reached,
            });
        }
        per_record.push(found);
    }
    let amp: Vec<f64> = records
        .iter()
        .map(|(c, _)| c.pfa_over_pga.unwrap_or(1.0))
        .collect();
    let n = states.states().len();
    let mut rows = Vec::new();
    for &im in measures {
        // On a floor, the ground's η (the IMs are the ground record's).
        let at_unit_alpha = |k: usize, eta: f64| im::of_eta(im, eta * amp[k], 1.0, ims[k]);
        let Some(fits) = damage::fit_states(n, &per_record, at_unit_alpha, def) else {
            continue;
        };
        let dimensionless = im.dimensionless(1.0, block.p);
        let power = f64::from(im.power());
        for (k, (s, fit)) in states.states().iter().zip(fits).enumerate() {
            let lognormal_p = lognormal_p_in(&per_record, k, &at_unit_alpha);
            for method in FitMethod::LOGNORMAL {
                let l = match method {
                    FitMethod::Fractile => fit.fractile,
                    FitMethod::MaxLikelihood => fit.mle,
                    FitMethod::Empirical => unreachable!("the table holds lognormals"),
                };
                rows.push(DamageStateRow {
                    block_index: index as i64,
                    block: block.name.clone(),
                    p: block.p,
                    eps: block.eps,
                    state: s.name.clone(),
                    criterion: s.describe(),
                    threshold: s.threshold(),
                    im: im.name(),
                    unit: im.unit().to_string(),
                    method,
                    n_records: records.len() as i64,
                    n_reached: fit.reached as i64,
                    median: l.and_then(|l| Some(l.median * block.alpha_rad?.powf(power))),
                    median_dimensionless: l.and_then(|l| Some(l.median * dimensionless?.0)),
                    dimensionless: dimensionless.map(|d| d.1.to_string()),
                    beta: l.map(|l| l.beta),
                    lognormal_p,
                });
            }
        }
    }
    Ok(BlockDamage {
        capacities,
        states: rows,
    })
}
