//! One AT2 record read for the solvers (`simulate`, `capacity`, `bench`).

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, OnceLock, PoisonError};

use rayon::prelude::*;

use crate::at2::{self, At2Error};
use crate::floor::Building;
use crate::ida::{run_pair, Batch, Hand};
use crate::physics::{simulate, Excitation, Outcome, PhysicsError, RunSpec, Stop};
use crate::pulse::Pulse;

/// A record ready to run, with what the reports show.
#[derive(Debug, Clone)]
pub struct LoadedRecord {
    /// The file stem.
    pub record_id: String,
    pub npts: usize,
    pub pga_g: f64,
    pub exc: Excitation,
    /// The pulse this excitation is, when it is one (no physical PGA then).
    pub pulse: Option<Pulse>,
    /// On a building's floor: the ground record's peak and the building's
    /// amplification of it (`pga_g` and `exc` are then the floor motion's).
    pub floor: Option<OnFloor>,
}

/// A record run on a building's floor rather than on the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnFloor {
    /// The ground record's PGA (g), unscaled.
    pub ground_pga_g: f64,
    /// The floor motion's peak over the ground's, PFA/PGA, for the record
    /// as recorded (and at any scale: the building is linear).
    pub pfa_over_pga: f64,
    /// The floor motion's samples per record step.
    pub substeps: usize,
}

/// A pulse as a record: its name as the id, sampled at the default step
/// for a block of frequency `p`.
pub fn from_pulse(pulse: &Pulse, p: f64) -> Result<LoadedRecord, PhysicsError> {
    let exc = pulse.excitation_for(p)?;
    Ok(LoadedRecord {
        record_id: pulse.to_string(),
        npts: exc.psi.len(),
        pga_g: f64::NAN,
        exc,
        pulse: Some(*pulse),
        floor: None,
    })
}

#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    #[error("{path}: cannot read")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The parse error's line and text are in the message.
    #[error("{path}:{}: {}", .error.line, .error.kind)]
    Parse { path: PathBuf, error: At2Error },
    #[error("{path}")]
    Samples {
        path: PathBuf,
        #[source]
        source: PhysicsError,
    },
    /// A record and a pulse together, a pulse on a floor, or neither.
    #[error("{0}")]
    Asked(String),
    #[error("{path}: its floor motion")]
    Floor {
        path: PathBuf,
        #[source]
        source: crate::floor::FloorError,
    },
}

/// What shakes the block: the record at `path` (on the floor of `building`
/// when one is given), or `pulse` sampled for the block's `p`.
pub fn excitation(
    path: Option<&Path>,
    pulse: Option<&Pulse>,
    building: Option<&Building>,
    p: f64,
) -> Result<LoadedRecord, RecordError> {
    match (path, pulse, building) {
        (Some(_), Some(_), _) => Err(RecordError::Asked(
            "give a record or a pulse, not both".into(),
        )),
        (None, Some(_), Some(_)) => Err(RecordError::Asked(
            "a floor filters a ground record through a building; a pulse is given as the block's own excitation".into(),
        )),
        (None, Some(pulse), None) => from_pulse(pulse, p).map_err(|source| RecordError::Samples {
            path: PathBuf::from(pulse.to_string()),
            source,
        }),
        (Some(path), None, _) => load_on(path, building),
        (None, None, _) => Err(RecordError::Asked(
            "give a record (--record FILE.AT2) or a pulse (--pulse rect|exp)".into(),
        )),
    }
}

/// Reads one AT2 file: its samples (g) and step (s), unscaled.
pub fn read_samples(path: &Path) -> Result<(Vec<f64>, f64), RecordError> {
    let bytes = std::fs::read(path).map_err(|source| RecordError::Read {
        path: path.into(),
        source,
    })?;
    let parsed = at2::parse(&bytes).map_err(|error| RecordError::Parse {
        path: path.into(),
        error,
    })?;
    Ok((parsed.accel_g, parsed.dt_s))
}

/// Reads and normalises one AT2 file.
pub fn load(path: &Path) -> Result<LoadedRecord, RecordError> {
    load_on(path, None)
}

/// Reads one AT2 file and normalises it, or the motion of the floor of
/// `building` under it.
pub fn load_on(path: &Path, building: Option<&Building>) -> Result<LoadedRecord, RecordError> {
    let (ground, dt_s) = read_samples(path)?;
    let record_id = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    from_samples(record_id, ground, dt_s, building).map_err(|e| match e {
        SampleError::Samples(source) => RecordError::Samples {
            path: path.into(),
            source,
        },
        SampleError::Floor(source) => RecordError::Floor {
            path: path.into(),
            source,
        },
    })
}

/// Why samples cannot be a record.
#[derive(Debug, thiserror::Error)]
pub enum SampleError {
    #[error(transparent)]
    Samples(PhysicsError),
    #[error("its floor motion")]
    Floor(#[source] crate::floor::FloorError),
}

/// A ground record given by its samples (g) and step (s), named
/// `record_id`, normalised; or the motion of the floor of `building` under it.
pub fn from_samples(
    record_id: String,
    ground: Vec<f64>,
    ground_dt_s: f64,
    building: Option<&Building>,
) -> Result<LoadedRecord, SampleError> {
    let peak = |a: &[f64], dt| crate::motion::peak(a, dt).map_or(0.0, |p| p.pga_g);
    let (accel_g, dt_s, floor) = match building {
        None => (ground, ground_dt_s, None),
        Some(b) => {
            let f = b
                .floor_motion(&ground, ground_dt_s)
                .map_err(SampleError::Floor)?;
            let on = OnFloor {
                ground_pga_g: peak(&ground, ground_dt_s),
                pfa_over_pga: f.pfa_over_pga,
                substeps: f.substeps,
            };
            (f.accel_g, f.dt_s, Some(on))
        }
    };
    let pga_g = peak(&accel_g, dt_s);
    let npts = accel_g.len();
    let exc = Excitation::from_samples(accel_g, dt_s).map_err(SampleError::Samples)?;
    Ok(LoadedRecord {
        record_id,
        npts,
        pga_g,
        exc,
        pulse: None,
        floor,
    })
}

/// [`crate::ida::capacity_certified`] of one record with every core of the
/// rayon pool: the workers scan the grid levels together, each taking the
/// next level as soon as it is free; while this worker bisects, the others
/// run the exact stepper's chaos probes of the decisive runs known so far,
/// two runs in step; the probes still missing then run at once
/// ([`crate::ida::Runs::with_batch`]). The capacity and its certification
/// are those of the sequential search (the runs are the same, only run
/// ahead of need); at most `threads − 1` levels past the first overturning
/// run in vain. For one capacity at a time, as the `capacity` command; a
/// sweep already keeps the cores busy with cases.
pub fn capacity_certified_parallel(
    exc: &Excitation,
    spec: &RunSpec,
    grid: &crate::ida::ImGrid,
    tol: f64,
    trace: crate::ida::Trace,
) -> Result<crate::ida::Certified, PhysicsError> {
    // The whole search runs on a worker of the pool: a batch started there
    // shares its runs with the other workers at once, where one started
    // from outside the pool would wait for a sleeping worker every time.
    rayon::scope(|_| {
        let mut runs = crate::ida::Runs::with_batch(exc, &Pool);
        crate::ida::capacity_certified_in(&mut runs, spec, grid, tol, trace)
    })
}

/// The workers of the rayon pool it is called in, as a [`Batch`].
struct Pool;

impl Batch for Pool {
    fn each(&self, exc: &Excitation, specs: &[RunSpec]) -> Vec<Result<Outcome, PhysicsError>> {
        specs.par_iter().map(|s| simulate(exc, s)).collect()
    }

    fn until_overturned(
        &self,
        exc: &Excitation,
        specs: &[RunSpec],
    ) -> Vec<Option<Result<Outcome, PhysicsError>>> {
        let next = AtomicUsize::new(0);
        // The first index known to overturn (or fail): none is taken past it.
        let first_over = AtomicUsize::new(usize::MAX);
        let slots: Vec<OnceLock<Result<Outcome, PhysicsError>>> =
            specs.iter().map(|_| OnceLock::new()).collect();
        (0..rayon::current_num_threads())
            .into_par_iter()
            .for_each(|_| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= specs.len() || i > first_over.load(Ordering::Acquire) {
                    break;
                }
                let out = simulate(exc, &specs[i]);
                if out
                    .as_ref()
                    .map_or(true, |o| o.overturned() || o.stop == Stop::EventLimit)
                {
                    first_over.fetch_min(i, Ordering::AcqRel);
                }
                let _ = slots[i].set(out);
            });
        slots.into_iter().map(OnceLock::into_inner).collect()
    }

    fn alongside(
        &self,
        exc: &Excitation,
        search: &mut (dyn FnMut(&Hand<'_>) + Send),
    ) -> Vec<(RunSpec, Result<Outcome, PhysicsError>)> {
        // The other workers wait for pairs on a condition variable, taking
        // no other work of the pool meanwhile: fit for a pool that runs one
        // search, as the `capacity` command's does.
        let pairs = Pairs::default();
        let others = rayon::current_num_threads().saturating_sub(1);
        rayon::join(
            || {
                // Closed however `search` ends (a panic included), so no
                // other worker waits for pairs that will never come.
                let closing = Closing(&pairs);
                search(&|pair| pairs.hand(pair));
                drop(closing);
                pairs.work(exc);
            },
            || (0..others).into_par_iter().for_each(|_| pairs.work(exc)),
        );
        pairs
            .done
            .into_inner()
            .unwrap_or_else(PoisonError::into_inner)
    }
}

/// The pairs handed to [`Batch::alongside`]'s workers, and their results.
#[derive(Default)]
struct Pairs {
    /// The pairs not yet taken, and whether more may come.
    waiting: Mutex<(VecDeque<[RunSpec; 2]>, bool)>,
    handed: Condvar,
    done: Mutex<Vec<(RunSpec, Result<Outcome, PhysicsError>)>>,
}

impl Pairs {
    fn hand(&self, pair: [RunSpec; 2]) {
        let mut waiting = self.waiting.lock().unwrap_or_else(PoisonError::into_inner);
        waiting.0.push_back(pair);
        self.handed.notify_one();
    }

    fn close(&self) {
        self.waiting
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .1 = true;
        self.handed.notify_all();
    }

    /// Runs the pairs as they are handed, until none is left and none will
    /// come.
    fn work(&self, exc: &Excitation) {
        loop {
            let pair = {
                let mut waiting = self.waiting.lock().unwrap_or_else(PoisonError::into_inner);
                loop {
                    match waiting.0.pop_front() {
                        Some(pair) => break pair,
                        None if waiting.1 => return,
                        None => {
                            waiting = self
                                .handed
                                .wait(waiting)
                                .unwrap_or_else(PoisonError::into_inner)
                        }
                    }
                }
            };
            let outs = run_pair(exc, &pair);
            self.done
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .extend(pair.into_iter().zip(outs));
        }
    }
}

/// Closes [`Pairs`] when dropped.
struct Closing<'a>(&'a Pairs);

impl Drop for Closing<'_> {
    fn drop(&mut self) {
        self.0.close();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ida::ImGrid;
    use crate::physics::Model;

    /// A 15 s decaying sine at 1.3 Hz, sampled at 0.01 s.
    fn decaying_sine() -> Excitation {
        let dt = 0.01;
        let accel: Vec<f64> = (0..1500)
            .map(|i| {
                let t = i as f64 * dt;
                0.4 * (2.0 * std::f64::consts::PI * 1.3 * t).sin() * (-0.2 * t).exp()
            })
            .collect();
        Excitation::new(&accel, dt).unwrap()
    }

    /// The scan's contract ([`Batch::until_overturned`]) with three workers:
    /// every level up to the first overturning is run, each result is the
    /// one `simulate` gives alone, and at most two levels past it (one per
    /// other worker) are run.
    #[test]
    fn the_pools_scan_runs_every_level_up_to_the_first_overturning() {
        let exc = decaying_sine();
        let specs: Vec<RunSpec> = ImGrid::default()
            .levels()
            .unwrap()
            .into_iter()
            .map(|eta| RunSpec::new(2.0, 0.8, eta, Model::LINEARIZED))
            .collect();
        let alone: Vec<Outcome> = specs.iter().map(|s| simulate(&exc, s).unwrap()).collect();
        let first = alone
            .iter()
            .position(Outcome::overturned)
            .expect("a level overturns");
        assert!(first > 10, "the scan covers many levels: {first}");
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        for _ in 0..5 {
            let got = pool.install(|| Pool.until_overturned(&exc, &specs));
            assert_eq!(got.len(), specs.len());
            for (i, (g, a)) in got.iter().zip(&alone).enumerate() {
                match g {
                    Some(r) => assert_eq!(r.as_ref().unwrap(), a, "level {i}"),
                    None => assert!(i > first, "level {i} up to {first} not run"),
                }
            }
            let past = got[first + 1..].iter().filter(|g| g.is_some()).count();
            assert!(past <= 2, "{past} levels run past the first overturning");
        }
    }

    /// [`Batch::alongside`]'s contract, with one worker and three: every
    /// pair handed, before the search's own runs and between them, is run
    /// once, each spec's result the one `simulate` gives alone, while the
    /// search's runs go on; and a search that panics stops the others
    /// instead of leaving them waiting for pairs.
    #[test]
    fn the_pools_workers_run_the_pairs_handed_while_the_search_goes_on() {
        let exc = decaying_sine();
        let spec = |eta: f64| RunSpec::new(2.0, 0.8, eta, Model::LINEARIZED);
        let pair = |eta: f64| [spec(eta * (1.0 + 1e-9)), spec(eta * (1.0 - 1e-9))];
        let etas: Vec<f64> = (0..12).map(|j| 0.9 * 0.93f64.powi(j)).collect();
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut own = Vec::new();
            let got = pool.install(|| {
                Pool.alongside(&exc, &mut |hand| {
                    for &eta in &etas[..4] {
                        hand(pair(eta));
                    }
                    for &eta in &etas[4..] {
                        own.push(simulate(&exc, &spec(eta)).unwrap());
                        hand(pair(eta));
                    }
                })
            });
            assert_eq!(own.len(), 8, "the search ran its own runs");
            let handed: Vec<RunSpec> = etas.iter().flat_map(|&e| pair(e)).collect();
            assert_eq!(got.len(), handed.len(), "{threads} threads");
            for s in &handed {
                let mine: Vec<_> = got.iter().filter(|(g, _)| g == s).collect();
                assert_eq!(mine.len(), 1, "η = {} run once", s.eta);
                assert_eq!(mine[0].1, simulate(&exc, s), "η = {}", s.eta);
            }
            let panicked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                pool.install(|| {
                    Pool.alongside(&exc, &mut |hand| {
                        hand(pair(etas[0]));
                        panic!("the search failed");
                    })
                })
            }));
            assert!(panicked.is_err(), "the panic reaches the caller");
        }
    }
}
