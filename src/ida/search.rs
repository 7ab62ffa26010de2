//! The capacity search of one record (MODEL.md §4).
//!
//! A record is run at a sequence of intensity levels of decreasing η
//! (increasing PGA). The capacity `η_c` is the first overturning met as
//! intensity rises: the largest level at which the block overturns, even if
//! it survives at some stronger level later (resurrection; Vamvatsikos &
//! Cornell 2002). It is then refined by bisection between the last surviving
//! level and the first overturning one until the bracket is at most `tol`
//! wide in η; the reported `η_c` is the bracket's overturning end (an
//! intensity at which the block is known to overturn).
//!
//! Without a [`super::Batch`], the grid levels are run two at a time, each
//! with the next, in step ([`Runs::run_ahead`]): where both runs rock
//! through the same eventless intervals, the Taylor stepper builds their
//! two series in the lanes of one vector, at about 0.7 of the price of
//! each alone (`rocking-bench --sections certified`). The outcomes are the
//! ones each run has alone, to the bit, so the capacity is too; the level
//! after the first overturning is run in vain (and not counted in
//! [`super::Work`]). In a certified search each refinement run, decisive,
//! goes with its two chaos probes at the checking tolerance
//! ([`Runs::run_ahead`]; counted when the certification asks for them).

use super::capacity::{Capacity, IdaPoint, RunKind, Trace};
use super::decisive::{decisive_runs, probes};
use super::grid::ImGrid;
use super::runs::Runs;
use crate::physics::{Excitation, Model, PhysicsError, RunSpec};

/// Traces the IDA of one record up to its first overturning and refines it.
/// `run.eta` is ignored (set per level).
pub fn capacity(
    exc: &Excitation,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
) -> Result<Capacity, PhysicsError> {
    capacity_traced(exc, run, grid, tol, Trace::StopAtFirst)
}

/// [`capacity`], optionally running every level past the first overturning.
pub fn capacity_traced(
    exc: &Excitation,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
    trace: Trace,
) -> Result<Capacity, PhysicsError> {
    capacity_in(&mut Runs::new(exc), run, grid, tol, trace)
}

/// [`capacity_traced`] through `runs`: outcomes it already holds are not
/// simulated again.
pub fn capacity_in(
    runs: &mut Runs,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
    trace: Trace,
) -> Result<Capacity, PhysicsError> {
    search(runs, run, grid, tol, trace, Ahead::Nothing)
}

/// What a search runs ahead of need for the certification after it: the
/// chaos probes of its decisive runs ([`chaos_probe`]'s), which wait in
/// [`Runs`] until asked for.
///
/// [`chaos_probe`]: super::decisive::chaos_probe
#[derive(Debug, Clone, Copy)]
pub(super) enum Ahead {
    Nothing,
    /// With a batch, the probes for a check with the search's own spec,
    /// run by the other workers while the bisection goes on
    /// ([`Batch::alongside`](super::Batch::alongside)).
    ProbesAlongside,
    /// Without a batch, each refinement run in step with its two probes
    /// for a check with this model ([`Runs::run_ahead`]).
    ProbesInStep(Model),
}

/// [`capacity_in`], running `ahead` what the certification after it asks for.
pub(super) fn search(
    runs: &mut Runs,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
    trace: Trace,
    ahead: Ahead,
) -> Result<Capacity, PhysicsError> {
    if !(tol > 0.0 && tol.is_finite()) {
        return Err(PhysicsError::BadInput(format!(
            "capacity tolerance {tol} must be positive"
        )));
    }
    let levels = grid.levels()?;
    let mut points = Vec::new();
    let spec = |eta: f64| RunSpec { eta, ..*run };
    let mut survived = grid.eta_max;
    if runs.batch.is_some() {
        let all: Vec<RunSpec> = levels.iter().map(|&e| spec(e)).collect();
        runs.scan(&all);
    }
    for (j, &eta) in levels.iter().enumerate() {
        if runs.batch.is_none() {
            if let Some(&next) = levels.get(j + 1) {
                // Alone, this level and the next in step (the second is
                // run in vain if this one overturns). Not four: two thirds
                // of a search's time go to walking events (bench/profile.py),
                // which lanes do not share, and four levels in lanes, with
                // lane-local events and resting runs in lanes, were slower
                // than pairs for both steppers (commit de1139d: the paper
                // sweep 7.78 s against 7.52 s; the Taylor certified search
                // 3.9-4.1 ms against 3.6-3.7 ms).
                runs.run_ahead(&[spec(eta), spec(next)]);
            }
        }
        let outcome = runs.outcome(&spec(eta))?;
        points.push(IdaPoint {
            eta,
            kind: RunKind::Level,
            outcome,
        });
        if !outcome.overturned() {
            survived = eta;
            continue;
        }
        let (level_survived, level_overturned) = (survived, eta);
        let mut over = eta;
        refine(
            runs,
            run,
            grid,
            tol,
            ahead,
            [&mut survived, &mut over],
            &mut points,
        )?;
        let resurrections = match trace {
            Trace::StopAtFirst => None,
            Trace::AllLevels => Some(levels_past(runs, run, &levels[j + 1..], &mut points)?),
        };
        return Ok(Capacity {
            eta_c: Some(over),
            eta_survived: survived,
            level_overturned: Some(level_overturned),
            level_survived,
            points,
            resurrections,
        });
    }
    Ok(Capacity {
        eta_c: None,
        eta_survived: survived,
        level_overturned: None,
        level_survived: survived,
        points,
        resurrections: match trace {
            Trace::StopAtFirst => None,
            Trace::AllLevels => Some(0),
        },
    })
}

/// Refines the bracket `[over, survived]` of the first overturning (its
/// ends the first grid level that overturned and the last that survived
/// before it) by [`bisect`]; with [`Ahead::ProbesAlongside`] and a batch,
/// the chaos probes of the decisive runs are handed to the other workers
/// meanwhile, those known before the bisection first.
fn refine(
    runs: &mut Runs,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
    ahead: Ahead,
    [survived, over]: [&mut f64; 2],
    points: &mut Vec<IdaPoint>,
) -> Result<(), PhysicsError> {
    let (level_survived, level_overturned) = (*survived, *over);
    match (runs.batch, ahead) {
        (None, Ahead::ProbesInStep(model)) => bisect(
            runs,
            run,
            tol,
            Some(model),
            [survived, over],
            points,
            &|_| {},
        )?,
        (None, _) | (Some(_), Ahead::Nothing | Ahead::ProbesInStep(_)) => {
            bisect(runs, run, tol, None, [survived, over], points, &|_| {})?
        }
        (Some(batch), Ahead::ProbesAlongside) => {
            // The decisive runs known before the bisection: the bracket
            // and the near misses (those of a capacity refined no further).
            let known = decisive_runs(
                &Capacity {
                    eta_c: Some(*over),
                    eta_survived: *survived,
                    level_overturned: Some(level_overturned),
                    level_survived,
                    points: points.clone(),
                    resurrections: None,
                },
                grid,
            );
            let mut bisected = Ok(());
            let outs = batch.alongside(runs.exc, &mut |hand| {
                for &(eta, _) in &known {
                    hand(probes(run, eta));
                }
                let each = |eta| hand(probes(run, eta));
                let bracket = [&mut *survived, &mut *over];
                bisected = bisect(runs, run, tol, None, bracket, points, &each);
            });
            runs.keep_ahead(outs);
            bisected?;
        }
    }
    Ok(())
}

/// Runs and records the grid `levels` past the first overturning (for
/// [`Trace::AllLevels`]): how many of them the block survived.
fn levels_past(
    runs: &mut Runs,
    run: &RunSpec,
    levels: &[f64],
    points: &mut Vec<IdaPoint>,
) -> Result<usize, PhysicsError> {
    let spec = |eta: f64| RunSpec { eta, ..*run };
    let rest: Vec<RunSpec> = levels.iter().map(|&e| spec(e)).collect();
    runs.prefetch(&rest);
    let mut survived_after = 0;
    for &eta in levels {
        let outcome = runs.outcome(&spec(eta))?;
        points.push(IdaPoint {
            eta,
            kind: RunKind::Level,
            outcome,
        });
        survived_after += usize::from(!outcome.overturned());
    }
    Ok(survived_after)
}

/// Bisects the bracket `[over, survived]` of `run`'s η down to `tol`,
/// recording each refinement run and calling `refined` with its η; with
/// `probe_with`, each refinement run in step with its chaos probes for a
/// check with that model.
fn bisect(
    runs: &mut Runs,
    run: &RunSpec,
    tol: f64,
    probe_with: Option<Model>,
    [survived, over]: [&mut f64; 2],
    points: &mut Vec<IdaPoint>,
    refined: &dyn Fn(f64),
) -> Result<(), PhysicsError> {
    while *survived - *over > tol {
        let mid = 0.5 * (*survived + *over);
        if mid <= *over || mid >= *survived {
            break;
        }
        let spec = RunSpec { eta: mid, ..*run };
        if let Some(model) = probe_with {
            // With its chaos probes, in step: the certification asks for them.
            let [up, down] = probes(&RunSpec { model, ..spec }, mid);
            runs.run_ahead(&[spec, up, down]);
        }
        let outcome = runs.outcome(&spec)?;
        points.push(IdaPoint {
            eta: mid,
            kind: RunKind::Refinement,
            outcome,
        });
        refined(mid);
        if outcome.overturned() {
            *over = mid;
        } else {
            *survived = mid;
        }
    }
    Ok(())
}
