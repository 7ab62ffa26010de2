//! Certification of a capacity: its decisive verdicts probed for chaos at a
//! tighter tolerance, and rerun there (the search redone if one flips)
//! where a probe disagrees.

use super::capacity::{Capacity, Trace};
use super::decisive::{chaos_probe, decisive_runs, CHAOS_PROBE};
use super::grid::ImGrid;
use super::runs::{Runs, Work};
use super::search::{search, Ahead};
use crate::physics::{Excitation, PhysicsError, RunSpec};

/// How a capacity's decisive verdicts were checked.
#[derive(Debug, Clone, PartialEq)]
pub enum Certification {
    /// Searched at `rtol`, and every decisive verdict stands at
    /// `checked_rtol` = rtol/[`TIGHTEN`]: the runs with η moved by
    /// ±[`CHAOS_PROBE`] there give it (where one did not, the run itself
    /// gave it there, and the next search tighter was certified so);
    /// `searches` > 1 when looser searches had to be redone.
    Tolerance {
        rtol: f64,
        checked_rtol: f64,
        searches: u32,
    },
    /// The exact stepper: no tolerance to tighten, and no decisive verdict
    /// changes when η moves by [`CHAOS_PROBE`]; rounding, which `rocking
    /// bench` measures, flips no verdict of such capacities.
    Exact,
    /// A fixed-step integrator (RK4, benchmarks only): nothing to tighten.
    FixedStep,
    /// The verdict at `eta` still flips when the tolerance is tightened to
    /// `rtol`, the tightest tried.
    Failed { rtol: f64, eta: f64 },
    /// The verdicts agree at the tighter tolerance (DP5, `rtol` the
    /// checking one) or are exact (the exact stepper, `rtol` = `None`), but
    /// the one at `eta` changes when η moves by [`CHAOS_PROBE`] (relative):
    /// the motion is chaotic there, and neither a tolerance nor exact
    /// stepping decides the verdict; η_c is one edge of a chaotic band.
    Chaotic { rtol: Option<f64>, eta: f64 },
}

impl Certification {
    pub fn certified(&self) -> bool {
        matches!(self, Certification::Tolerance { .. } | Certification::Exact)
    }

    /// The outcome without its numbers.
    pub fn kind(&self) -> CertificationKind {
        match self {
            Certification::Tolerance { .. } => CertificationKind::Tolerance,
            Certification::Exact => CertificationKind::Exact,
            Certification::FixedStep => CertificationKind::FixedStep,
            Certification::Failed { .. } => CertificationKind::Flips,
            Certification::Chaotic { .. } => CertificationKind::Chaotic,
        }
    }
}

impl std::fmt::Display for Certification {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Certification::Tolerance {
                rtol,
                checked_rtol,
                searches,
            } => {
                write!(f, "rtol {rtol:e}; decisive runs agree at {checked_rtol:e}")?;
                if *searches > 1 {
                    write!(
                        f,
                        " (searched {searches} times: looser tolerances flipped a verdict)"
                    )?;
                }
                Ok(())
            }
            Certification::Exact => write!(
                f,
                "exact stepper; decisive verdicts unchanged when η moves by {CHAOS_PROBE:e}"
            ),
            Certification::FixedStep => write!(f, "not certified: fixed-step integrator"),
            Certification::Failed { rtol, eta } => write!(
                f,
                "not certified: the verdict at η = {eta} still flips at rtol {rtol:e}"
            ),
            Certification::Chaotic { rtol, eta } => {
                write!(
                    f,
                    "not certified: chaotic: the verdict at η = {eta} changes when η moves by \
                     {CHAOS_PROBE:e} (relative)"
                )?;
                match rtol {
                    Some(rtol) => write!(f, ", at rtol {rtol:e}"),
                    None => write!(f, ", with the exact stepper"),
                }
            }
        }
    }
}

/// The outcome of a certification, as the capacities table stores it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CertificationKind {
    /// The exact stepper, decisive verdicts not chaotic.
    Exact,
    /// Taylor or DP5: the decisive verdicts stand at a 100× tighter tolerance.
    Tolerance,
    /// A verdict changes when η moves by 1e-9: decided by no tolerance
    /// nor by exact stepping.
    Chaotic,
    /// A verdict still flips at the tightest tolerance.
    Flips,
    /// RK4 (benchmarks only).
    FixedStep,
}

impl crate::label::Label for CertificationKind {
    const ALL: &'static [Self] = &[
        CertificationKind::Exact,
        CertificationKind::Tolerance,
        CertificationKind::Chaotic,
        CertificationKind::Flips,
        CertificationKind::FixedStep,
    ];
    fn label(self) -> &'static str {
        match self {
            CertificationKind::Exact => "exact",
            CertificationKind::Tolerance => "tolerance",
            CertificationKind::Chaotic => "chaotic",
            CertificationKind::Flips => "flips",
            CertificationKind::FixedStep => "fixed_step",
        }
    }
}

/// How much tighter the check of a search is than the search.
pub const TIGHTEN: f64 = 100.0;

/// A capacity with its certification.
#[derive(Debug, Clone, PartialEq)]
pub struct Certified {
    pub capacity: Capacity,
    pub certification: Certification,
    /// The model of the search reported (its tolerance may be tighter than asked).
    pub model: crate::physics::Model,
    /// Runs spent on checks and on searches that were redone.
    pub extra: Work,
}

/// [`capacity_traced`], certified: for a tolerance-controlled integrator
/// every decisive run ([`decisive_runs`]) is probed for chaos at a
/// [`TIGHTEN`]× tighter tolerance (η moved by ±[`CHAOS_PROBE`]). Where every
/// probe gives its run's verdict, the verdicts stand at that tolerance (and
/// an η step of 1e-9 away): certified. Where one does not, the decisive
/// runs themselves are rerun at that tolerance: if a verdict flips, the
/// whole search is redone at that tolerance and checked again, down to the
/// integrator's tightest ([`crate::physics::Integrator::tightest_tol`]);
/// if none does, the capacity is chaotic. The exact stepper has no
/// tolerance: its decisive runs are only probed for chaos. RK4 is not
/// certified.
///
/// [`capacity_traced`]: super::capacity_traced
pub fn capacity_certified(
    exc: &Excitation,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
    trace: Trace,
) -> Result<Certified, PhysicsError> {
    capacity_certified_in(&mut Runs::new(exc), run, grid, tol, trace)
}

/// [`capacity_certified`] through `runs`, which may already hold some of the
/// runs it needs (another grid's levels, say). `extra` counts the
/// simulations beyond those of the reported search.
pub fn capacity_certified_in(
    runs: &mut Runs,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
    trace: Trace,
) -> Result<Certified, PhysicsError> {
    use crate::physics::Integrator;
    let start = runs.work();
    let integrator = run.model.integrator;
    let Some(asked) = integrator.tol() else {
        // The exact stepper's probes are run with the search's own spec:
        // with a batch, they can start while the bisection runs.
        let ahead = match integrator {
            Integrator::Exact => Ahead::ProbesAlongside,
            _ => Ahead::Nothing,
        };
        let capacity = search(runs, run, grid, tol, trace, ahead)?;
        let searched = runs.work();
        let certification = match integrator {
            Integrator::Exact => match chaos_probe(runs, run, &capacity, grid)? {
                Some(eta) => Certification::Chaotic { rtol: None, eta },
                None => Certification::Exact,
            },
            _ => Certification::FixedStep,
        };
        return Ok(Certified {
            capacity,
            certification,
            model: run.model,
            extra: runs.work().since(searched),
        });
    };
    let tightest = integrator.tightest_tol();
    let with_rtol = |rtol: f64| RunSpec {
        model: crate::physics::Model {
            integrator: integrator.with_tol(rtol),
            ..run.model
        },
        ..*run
    };
    let (mut rtol, mut searches) = (asked, 0u32);
    loop {
        searches += 1;
        let spec = with_rtol(rtol);
        let checked_rtol = (rtol / TIGHTEN).max(tightest);
        let check = with_rtol(checked_rtol);
        let before = runs.work();
        // Alone, the refinement runs go with their probes, in step.
        let ahead = Ahead::ProbesInStep(check.model);
        let capacity = search(runs, &spec, grid, tol, trace, ahead)?;
        let search = runs.work().since(before);
        // The probes, run at the tighter tolerance, check it too: where
        // every one gives its decisive run's verdict, the verdicts stand at
        // that tolerance an η step of 1e-9 away on both sides. Only where
        // one does not are the decisive runs themselves rerun there, to
        // tell a verdict the tolerance flips (search again, tighter) from
        // a chaotic one.
        let (flipped, chaos) = match chaos_probe(runs, &check, &capacity, grid)? {
            None => (None, None),
            Some(chaotic) => {
                let mut flipped = None;
                for (eta, overturned) in decisive_runs(&capacity, grid) {
                    if runs.outcome(&RunSpec { eta, ..check })?.overturned() != overturned {
                        flipped = Some(eta);
                        break;
                    }
                }
                (flipped, flipped.is_none().then_some(chaotic))
            }
        };
        let certification = match (flipped, chaos) {
            (None, Some(eta)) => Certification::Chaotic {
                rtol: Some(checked_rtol),
                eta,
            },
            (None, None) => Certification::Tolerance {
                rtol,
                checked_rtol,
                searches,
            },
            (Some(eta), _) if rtol / (TIGHTEN * TIGHTEN) < tightest => Certification::Failed {
                rtol: checked_rtol,
                eta,
            },
            (Some(_), _) => {
                rtol /= TIGHTEN;
                continue;
            }
        };
        return Ok(Certified {
            capacity,
            certification,
            model: spec.model,
            extra: runs.work().since(start).since(search),
        });
    }
}
