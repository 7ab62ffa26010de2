//! The runs whose verdicts decide a capacity, and the chaos probe of them:
//! each decisive run again with η moved by ±[`CHAOS_PROBE`].

use super::capacity::{Capacity, RunKind};
use super::grid::ImGrid;
use super::runs::Runs;
use crate::physics::{PhysicsError, RunSpec};

/// θmax/α from which a surviving grid level counts as a near miss: a
/// slightly different integration could tip it over, and so move the first
/// overturning to it.
pub const NEAR_MISS: f64 = 0.5;

/// The runs whose verdicts decide a capacity, each with the verdict the
/// search found: the first grid level that overturned and the last that
/// survived before it (the bracket before refinement), every refinement run
/// (each verdict steered the bisection, so a flip anywhere moves η_c, as
/// the surviving midpoints above the final bracket do), and the surviving
/// grid levels before the first overturning that came near overturning
/// (θmax/α ≥ [`NEAR_MISS`]): a flip there moves the first overturning up.
/// η_c and the bracket's surviving end are among them, first.
pub fn decisive_runs(cap: &Capacity, grid: &ImGrid) -> Vec<(f64, bool)> {
    let mut runs: Vec<(f64, bool)> = Vec::with_capacity(8);
    let mut push = |eta: f64, overturned: bool| {
        if !runs.iter().any(|&(e, _)| e == eta) {
            runs.push((eta, overturned));
        }
    };
    if let Some(c) = cap.eta_c {
        push(c, true);
    }
    // At the grid's top the block is known to stand (nothing moves at η ≥ 1).
    if cap.eta_survived < grid.eta_max {
        push(cap.eta_survived, false);
    }
    if let Some(l) = cap.level_overturned {
        push(l, true);
    }
    if cap.level_survived < grid.eta_max {
        push(cap.level_survived, false);
    }
    for q in cap.points.iter().filter(|q| q.kind == RunKind::Refinement) {
        push(q.eta, q.outcome.overturned());
    }
    let before_first = cap
        .points
        .iter()
        .take_while(|q| !(q.kind == RunKind::Level && q.outcome.overturned()));
    for q in before_first {
        if q.kind == RunKind::Level && q.outcome.max_abs_x >= NEAR_MISS {
            push(q.eta, false);
        }
    }
    runs
}

/// How far (relative) the chaos probe moves η: far below any meaning (the
/// grid's steps are 3.4 %), about the size of the integration errors a
/// tolerance allows.
pub const CHAOS_PROBE: f64 = 1e-9;

/// The two runs that probe the run of `check` at `eta`: η moved by
/// ±[`CHAOS_PROBE`].
pub(super) fn probes(check: &RunSpec, eta: f64) -> [RunSpec; 2] {
    [eta * (1.0 + CHAOS_PROBE), eta * (1.0 - CHAOS_PROBE)].map(|eta| RunSpec { eta, ..*check })
}

/// The first decisive run whose verdict changes when η moves by
/// ±[`CHAOS_PROBE`], if any. Each run's two probes are run in step with the
/// next run's two ([`Runs::run_ahead`]: four lanes for the Taylor stepper,
/// a pair otherwise); where a run's probes disagree, the next run's were
/// run in vain.
pub(super) fn chaos_probe(
    runs: &mut Runs,
    check: &RunSpec,
    cap: &Capacity,
    grid: &ImGrid,
) -> Result<Option<f64>, PhysicsError> {
    let decisive: Vec<(f64, bool, [RunSpec; 2])> = decisive_runs(cap, grid)
        .into_iter()
        .map(|(eta, overturned)| (eta, overturned, probes(check, eta)))
        .collect();
    let all: Vec<RunSpec> = decisive.iter().flat_map(|d| d.2).collect();
    runs.prefetch(&all);
    for (i, &(eta, overturned, pair)) in decisive.iter().enumerate() {
        // This run's probes with the next run's, in step.
        let next = decisive.get(i + 1).map_or(&[][..], |d| &d.2[..]);
        runs.run_ahead(&[&pair[..], next].concat());
        for spec in &pair {
            if runs.outcome(spec)?.overturned() != overturned {
                return Ok(Some(eta));
            }
        }
    }
    Ok(None)
}

/// The finest tolerance a search refines to without its certification
/// reading a sharp edge as chaos, for levels up to `eta_max`: 100 chaos
/// probes ([`CHAOS_PROBE`], relative) at the top level. Finer, the
/// bracket's ends sit within a probe of the overturning edge, and a probe
/// crosses it (a pipeline's `tol = 1e-10` left 44 of 44 capacities
/// "chaotic"); at this width it does for about 2 % of the capacities at η =
/// `eta_max`, and fewer below.
fn finest_tol(eta_max: f64) -> f64 {
    100.0 * CHAOS_PROBE * eta_max
}

/// The warning of a tolerance finer than [`finest_tol`]: the capacities
/// are refined to it (a closed form's check may ask 1e-11), but their
/// certification cannot tell a sharp edge from a chaotic band there.
pub fn tol_warning(tol: f64, eta_max: f64) -> Option<String> {
    let finest = finest_tol(eta_max);
    // Within rounding of the limit is on it (1e-7 is 100 × 1e-9 × 1).
    (tol < finest * (1.0 - 1e-12)).then(|| {
        format!(
            "a search tolerance of {tol:e} is finer than {finest:.0e}: certification moves η by \
             {CHAOS_PROBE:e} (relative) to test each decisive verdict, and a bracket this narrow \
             leaves its ends within a probe of the overturning edge, so a capacity whose edge is \
             only sharp may be certified \"chaotic\"; the capacities themselves are refined to it"
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tolerance finer than the chaos probe resolves read every capacity
    /// as chaotic (a pipeline's `tol = 1e-10`: 44 of 44) without a word. It
    /// is warned of by `rocking capacity` and a pipeline's sweep; the
    /// default 1e-4 and 100 probes at the top level are not.
    #[test]
    fn a_tolerance_finer_than_the_probes_resolve_is_warned_of() {
        assert_eq!(finest_tol(1.0), 100.0 * CHAOS_PROBE);
        assert_eq!(tol_warning(1e-7, 1.0), None);
        assert_eq!(tol_warning(crate::ida::DEFAULT_TOL, 1.0), None);
        let w = tol_warning(1e-8, 1.0).unwrap();
        assert!(
            w.contains("finer than 1e-7") && w.contains("chaotic"),
            "{w}"
        );
        assert!(tol_warning(1e-7, 2.0).is_some());
    }
}
