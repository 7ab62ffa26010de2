//! One capacity on every core: the rayon pool's workers as the IDA's
//! [`Batch`] (the grid levels scanned together, the chaos probes' pairs
//! run while the search goes on), for a command that searches one
//! capacity at a time.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, OnceLock, PoisonError};

use rayon::prelude::*;

use crate::ida::{run_pair, Batch, Hand};
use crate::physics::{simulate, Excitation, Outcome, PhysicsError, RunSpec, Stop};

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
                if out.as_ref().map_or(true, |o| {
                    o.overturned() || matches!(o.stop, Stop::EventLimit | Stop::Flight)
                }) {
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
