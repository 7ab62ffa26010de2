//! Pulses stage (a `[pulses]` pipeline): every pulse family (β or the
//! rectangle) × ε × f → its walls ([`crate::pulse::wall`]) and its map over
//! the plan's η levels → `pulse_walls.parquet`, `pulse_map.parquet`.
//!
//! Glue: the physics is [`crate::pulse`]; (family, ε, f) points run in
//! parallel and are collected in plan order.

use std::path::PathBuf;

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::stage::{BoxError, Context, Progress, Shard, Stage, Study, Summary};
use crate::label::Label;
use crate::physics::{simulate, PhysicsError, RunSpec};
use crate::pipeline::PulsePlan;
use crate::pulse::{self, Pulse, Shape, WallSearch};
use crate::tables::pulse::{PulseCellRow, PulseWallRow};
use crate::tables::{self, TableError};

/// The pulses stage.
pub struct Pulses;

pub const WALLS: &str = "pulse_walls.parquet";
pub const MAP: &str = "pulse_map.parquet";

impl Stage for Pulses {
    fn name(&self) -> &'static str {
        "pulses"
    }

    fn about(&self) -> &'static str {
        "Map a pulse's safe and overturning areas over f and η, and its walls ([pulses] pipelines)"
    }

    fn not_needed(&self, study: &Study) -> Option<String> {
        study
            .plan
            .pulse_map()
            .is_none()
            .then(|| "the pipeline has no [pulses] map".to_string())
    }

    fn settings(&self, study: &Study) -> serde_json::Value {
        let plan = &study.plan;
        serde_json::json!({
            "pulses": plan.pulse_map(),
            "model": plan.model,
            "solver": plan.solver,
            "overturn": plan.overturn,
        })
    }

    fn inputs(&self, _study: &Study) -> Result<Vec<PathBuf>, BoxError> {
        Ok(Vec::new())
    }

    fn outputs(&self, study: &Study, _shard: Option<Shard>) -> Vec<PathBuf> {
        vec![study.path(WALLS), study.path(MAP)]
    }

    fn run(&self, cx: &Context) -> Result<Summary, BoxError> {
        Ok(run(cx)?)
    }
}

#[derive(Debug, thiserror::Error)]
pub enum PulsesError {
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("the pulse map's model")]
    Model(#[source] PhysicsError),
    #[error("pulse {pulse}, ε = {eps}, f = {f}")]
    Physics {
        pulse: String,
        eps: f64,
        f: f64,
        #[source]
        source: PhysicsError,
    },
}

/// One (family, ε, f) point: its wall row and its map cells.
fn point(
    pp: &PulsePlan,
    shape: Shape,
    eps: f64,
    f: f64,
    base: &RunSpec,
) -> Result<(PulseWallRow, Vec<PulseCellRow>), PhysicsError> {
    let pl = Pulse {
        shape,
        cycle: pp.cycle,
        t_d_s: 1.0,
    };
    let n = pp
        .intervals
        .unwrap_or_else(|| pulse::default_intervals(shape, f));
    let exc = pl.excitation(n)?;
    let spec = RunSpec { p: f, eps, ..*base };
    let w = pulse::wall(&exc, &spec, WallSearch::default())?;
    let closed = pl.closed_form_for(f, &spec);
    let wall = PulseWallRow {
        pulse: shape.name().to_string(),
        beta: shape.beta(),
        cycle: pp.cycle.name().to_string(),
        eps,
        f,
        overturn: spec.overturn.to_string(),
        model: spec.model.equation.kind().label().to_string(),
        alpha_rad: spec.model.equation.alpha(),
        eta_w: w.eta_w,
        eta_w_mode0: w.eta_w_mode0,
        mode: w.mode.map(|m| m as i64),
        closed_form: closed.map(|c| c.eta),
        closed_form_equation: closed.map(|c| c.equation.to_string()),
        closed_form_of: closed.map(|c| c.of.column().to_string()),
        runs: w.runs as i64,
        intervals_per_lobe: n as i64,
    };
    let cells = pp
        .eta
        .iter()
        .map(|&eta| {
            let o = simulate(&exc, &RunSpec { eta, ..spec })?;
            Ok(PulseCellRow {
                pulse: wall.pulse.clone(),
                beta: wall.beta,
                cycle: wall.cycle.clone(),
                eps,
                f,
                eta,
                overturned: o.overturned(),
                impacts: o.impacts as i64,
                max_abs_x: o.max_abs_x,
            })
        })
        .collect::<Result<_, PhysicsError>>()?;
    Ok((wall, cells))
}

fn run(cx: &Context) -> Result<Summary, PulsesError> {
    let study = cx.study;
    let plan = &study.plan;
    let pp = plan.pulse_map().expect("not_needed without [pulses]");
    let (model, _) = plan
        .model
        .resolve(pp.alpha, None, plan.solver, plan.auto_tol)
        .map_err(PulsesError::Model)?;
    let base = RunSpec {
        overturn: plan.overturn,
        ..RunSpec::new(1.0, 0.5, 1.0, model)
    };
    let points: Vec<(Shape, f64, f64)> = pp
        .shapes
        .iter()
        .flat_map(|&s| {
            pp.eps
                .iter()
                .flat_map(move |&e| pp.f.iter().map(move |&f| (s, e, f)))
        })
        .collect();
    let started = std::time::Instant::now();
    let (done, all_runs) = (AtomicU64::new(0), AtomicU64::new(0));
    let total = points.len() as u64;
    let results = points
        .par_iter()
        .map(|&(shape, eps, f)| {
            let r = point(pp, shape, eps, f, &base).map_err(|source| PulsesError::Physics {
                pulse: Pulse {
                    shape,
                    cycle: pp.cycle,
                    t_d_s: 1.0,
                }
                .to_string(),
                eps,
                f,
                source,
            });
            let runs = r
                .as_ref()
                .map_or(0, |(w, c)| w.runs as u64 + c.len() as u64);
            let d = done.fetch_add(1, Ordering::Relaxed) + 1;
            let runs = all_runs.fetch_add(runs, Ordering::Relaxed) + runs;
            cx.reporter.progress(&Progress {
                stage: "pulses",
                done: d,
                total,
                resumed: 0,
                runs,
            });
            r
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut walls = Vec::with_capacity(results.len());
    let mut cells = Vec::new();
    let mut runs = 0i64;
    for (w, c) in results {
        runs += w.runs + c.len() as i64;
        walls.push(w);
        cells.extend(c);
    }
    let meta = vec![(
        "rocking.pulses.settings".to_string(),
        Pulses.settings(study).to_string(),
    )];
    tables::write(&study.path(WALLS), &walls, &meta)?;
    tables::write(&study.path(MAP), &cells, &meta)?;
    let closed: Vec<f64> = walls.iter().filter_map(|w| w.closed_form_gap()).collect();
    let mut lines = vec![format!(
        "mapped {} pulse × ε × f points ({} walls, {} map cells): {runs} runs in {:.1} s",
        walls.len(),
        walls.len(),
        cells.len(),
        started.elapsed().as_secs_f64()
    )];
    if let Some(worst) = closed.iter().cloned().reduce(f64::max) {
        lines.push(format!(
            "walls against the paper's closed form: largest relative difference {worst:.1e} over {} walls",
            closed.len()
        ));
    }
    Ok(Summary {
        lines,
        headline: 0,
        also_wrote: Vec::new(),
    })
}
