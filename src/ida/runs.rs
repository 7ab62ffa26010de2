//! The simulations of one record, remembered (and run ahead of need by a
//! [`Batch`] of workers), and the work they counted.

use std::hash::BuildHasherDefault;

use crate::physics::{simulate, simulate_in_step, Excitation, Outcome, PhysicsError, RunSpec};

/// The simulations of one record, remembered: a search or check that asks
/// for a run already done (the same η and model) gets its outcome without
/// simulating again. Runs are deterministic, so sharing changes nothing but
/// the time; nested IM grids (100, 200, 400 … log-spaced levels between the
/// same ends) share their common levels bit for bit.
///
/// With a [`Batch`] (from [`Runs::with_batch`]) a search also asks for
/// runs ahead of need, several at once: the grid levels up to the first
/// overturning (scanned by all workers together, [`Runs::scan`]), and
/// every chaos probe. The outcomes are the same, so the capacity and its
/// certification are too, and so is the work counted (runs are counted
/// when asked for); only the time changes, and at most one level per
/// other worker past the first overturning is run in vain.
pub struct Runs<'a> {
    pub(super) exc: &'a Excitation,
    memo: Memo,
    /// Runs done ahead of need by [`Runs::run_ahead`], not yet asked for:
    /// counted in [`Runs::work`] (and checked for the event cap) when they
    /// are, so the work reported is the same as if each ran when asked.
    ahead: Memo,
    done: Work,
    pub(super) batch: Option<&'a dyn Batch>,
}

/// Runs simulations of one record together: what a caller with spare cores
/// lends one capacity search (the `capacity` command runs them in
/// parallel, [`crate::ops::pool::capacity_certified_parallel`]).
pub trait Batch: Sync {
    /// [`simulate`]'s result for each spec, in order.
    fn each(&self, exc: &Excitation, specs: &[RunSpec]) -> Vec<Result<Outcome, PhysicsError>>;

    /// The specs in order, each worker taking the next one as soon as it is
    /// free (no worker waits for another), none taken past the first known
    /// to overturn or to end without a verdict (an error, the event cap):
    /// [`simulate`]'s result for each spec run, `None` for the others. Those
    /// run past the first overturning are the runs that were under way when
    /// it was found: at most one per other worker.
    fn until_overturned(
        &self,
        exc: &Excitation,
        specs: &[RunSpec],
    ) -> Vec<Option<Result<Outcome, PhysicsError>>>;

    /// Calls `search` on this worker while the other workers run the pairs
    /// of specs it hands to its argument, in the order handed, each pair by
    /// [`run_pair`]; once `search` returns, this worker joins them until
    /// every pair handed is run. Returns [`simulate`]'s result for each spec
    /// handed. For work that is sequential by nature (a bisection) and
    /// whose later needs are known early (the chaos probes of its decisive
    /// runs): the other workers would idle otherwise.
    fn alongside(
        &self,
        exc: &Excitation,
        search: &mut (dyn FnMut(&Hand<'_>) + Send),
    ) -> Vec<(RunSpec, Result<Outcome, PhysicsError>)>;
}

/// What a search given to [`Batch::alongside`] hands its pairs to.
pub type Hand<'a> = dyn Fn([RunSpec; 2]) + 'a;

/// Two runs that differ in η alone (a chaos probe's pair): together, in step,
/// where [`simulate_in_step`] can, else one after the other. Each result is
/// [`simulate`]'s for that spec alone.
pub fn run_pair(exc: &Excitation, pair: &[RunSpec; 2]) -> [Result<Outcome, PhysicsError>; 2] {
    match simulate_in_step(exc, pair)[..] {
        [a, b] => [Ok(a), Ok(b)],
        _ => pair.each_ref().map(|s| simulate(exc, s)),
    }
}

impl<'a> Runs<'a> {
    pub fn new(exc: &'a Excitation) -> Self {
        Runs {
            exc,
            memo: Memo::default(),
            ahead: Memo::default(),
            done: Work::default(),
            batch: None,
        }
    }

    /// Runs that ask `batch` for runs ahead of need ([`Runs::scan`],
    /// [`Runs::prefetch`]).
    pub fn with_batch(exc: &'a Excitation, batch: &'a dyn Batch) -> Self {
        Runs {
            batch: Some(batch),
            ..Runs::new(exc)
        }
    }

    /// Runs the specs not yet in memory together, when there is a batch and
    /// more than one is missing; a run that fails is left for
    /// [`Runs::outcome`] to run again and report if it is ever needed. The
    /// outcomes wait, as [`Runs::run_ahead`]'s do, until asked for: a
    /// certification that stops at its first chaotic verdict counts the
    /// runs it asked for, with a batch or without.
    pub fn prefetch(&mut self, specs: &[RunSpec]) {
        let Some(batch) = self.batch else {
            return;
        };
        let (mut keys, mut missing) = (Vec::new(), Vec::new());
        for s in specs {
            let key = run_key(s);
            if self.memo.contains_key(&key) || self.ahead.contains_key(&key) || keys.contains(&key)
            {
                continue;
            }
            keys.push(key);
            missing.push(*s);
        }
        if missing.len() < 2 {
            return;
        }
        let outs = batch.each(self.exc, &missing);
        self.keep_ahead(missing.into_iter().zip(outs).collect());
    }

    /// Runs the grid levels `specs` (in the order a search meets them) that
    /// are not yet in memory, when there is a batch, up to the first level
    /// known to overturn: all workers at once, each taking the next level
    /// as soon as it is free ([`Batch::until_overturned`]).
    pub fn scan(&mut self, specs: &[RunSpec]) {
        let Some(batch) = self.batch else {
            return;
        };
        let mut missing = Vec::new();
        for s in specs {
            let key = run_key(s);
            match self.memo.get(&key).or_else(|| self.ahead.get(&key)) {
                Some(out) if out.overturned() => break,
                Some(_) => {}
                None => missing.push(*s),
            }
        }
        if missing.len() < 2 {
            return;
        }
        // Kept ahead of need: counted when the search asks for them, so the
        // levels run in vain past the first overturning are not.
        let outs = batch.until_overturned(self.exc, &missing);
        let ran = missing
            .into_iter()
            .zip(outs)
            .filter_map(|(spec, out)| Some((spec, out?)))
            .collect();
        self.keep_ahead(ran);
    }

    /// The simulations done so far (outcomes found in memory excluded).
    pub fn work(&self) -> Work {
        self.done
    }

    /// The outcome of one run. A run stopped by the event cap has no verdict:
    /// it is refused rather than counted as surviving.
    pub fn outcome(&mut self, spec: &RunSpec) -> Result<Outcome, PhysicsError> {
        let key = run_key(spec);
        if let Some(out) = self.memo.get(&key) {
            return Ok(*out);
        }
        let out = match self.ahead.remove(&key) {
            Some(out) => out,
            None => simulate(self.exc, spec)?,
        };
        self.remember(spec, out)
    }

    /// Runs specs that differ in η alone (a chaos probe's two runs, two
    /// grid levels; for the Taylor stepper, in the tolerance too: a run
    /// with its probes, two runs' probes) ahead of need, together, in step,
    /// when the first is not known yet: as many of those not known as the
    /// physics keeps in step ([`simulate_in_step`]), the set at about the
    /// price of one run where its runs rock alike; the others are left to
    /// be run when asked for. The outcomes wait until asked for
    /// ([`Runs::outcome`]).
    pub fn run_ahead(&mut self, specs: &[RunSpec]) {
        let known = |k: &[u64; 10]| self.memo.contains_key(k) || self.ahead.contains_key(k);
        if specs.first().is_none_or(|first| known(&run_key(first))) {
            return;
        }
        let (mut todo, mut keys) = (
            Vec::with_capacity(specs.len()),
            Vec::with_capacity(specs.len()),
        );
        for spec in specs {
            let key = run_key(spec);
            if !known(&key) && !keys.contains(&key) {
                todo.push(*spec);
                keys.push(key);
            }
        }
        let outs = simulate_in_step(self.exc, &todo);
        self.ahead.extend(keys.into_iter().zip(outs));
    }

    /// Keeps outcomes run ahead of need (by [`Batch::alongside`],
    /// [`Runs::prefetch`], [`Runs::scan`]) until they are asked for, as
    /// [`Runs::run_ahead`] does; failures are dropped, to be run again and
    /// reported if they are ever asked for.
    pub(super) fn keep_ahead(&mut self, outs: Vec<(RunSpec, Result<Outcome, PhysicsError>)>) {
        for (spec, out) in outs {
            let key = run_key(&spec);
            if let (Ok(out), false) = (out, self.memo.contains_key(&key)) {
                self.ahead.insert(key, out);
            }
        }
    }

    /// Counts and keeps a run's outcome; a run stopped by the event cap is
    /// refused.
    fn remember(&mut self, spec: &RunSpec, out: Outcome) -> Result<Outcome, PhysicsError> {
        if out.stop == crate::physics::Stop::EventLimit {
            // At ε = 1 no impact loses energy: a block that barely lifts
            // hops for ever, each hop the shorter the larger p; a real
            // run can then reach the cap, which is no fault of the tool.
            // (A model that slides has its own guard on events at one
            // instant, which is a fault.)
            let rocks_only = spec.model.equation.friction().is_none();
            let why = if spec.eps >= 1.0 && rocks_only {
                format!(
                    "ε = 1 loses no energy at an impact, so a block that barely lifts keeps \
                     hopping, each hop the shorter the larger p (here {} 1/s); give ε < 1, as \
                     every real impact loses energy",
                    crate::im::level_text(spec.p)
                )
            } else {
                "a fault of the tool: please report the record and the block".to_string()
            };
            return Err(PhysicsError::BadInput(format!(
                "the run at η = {} hit the limit of {} events, or of events at one instant, \
                 without a verdict ({why})",
                spec.eta,
                crate::physics::MAX_EVENTS
            )));
        }
        if out.stop == crate::physics::Stop::Flight {
            return Err(PhysicsError::BadInput(format!(
                "the run at η = {}: the block's pivot lost contact (its normal force reached 0), \
                 so the block would leave the base, which the slide-rock model does not follow",
                spec.eta
            )));
        }
        self.done.runs += 1;
        self.done.intervals += out.intervals;
        self.memo.insert(run_key(spec), out);
        Ok(out)
    }
}

/// Outcomes by their run's key ([`run_key`]). Never iterated, so the
/// hasher decides only the time of a lookup.
type Memo = std::collections::HashMap<[u64; 10], Outcome, BuildHasherDefault<KeyHasher>>;

/// The hash of a run's key, a word at a time by a multiply and a rotate
/// (as rustc's FxHash): the default SipHash spent about 1.5 % of a sweep
/// hashing 80 bytes per lookup. The keys are a program's own numbers, not
/// an adversary's, so a keyed hash buys nothing here.
#[derive(Default)]
struct KeyHasher(u64);

impl std::hash::Hasher for KeyHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    fn write_u64(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// Every number that defines a run, as bits.
fn run_key(spec: &RunSpec) -> [u64; 10] {
    use crate::physics::{Equation, Integrator, Overturn};
    let (integrator, param) = match spec.model.integrator {
        Integrator::Exact => (0, 0),
        Integrator::Dp5 { rtol } => (1, rtol.to_bits()),
        Integrator::Rk4 { substeps } => (2, u64::from(substeps)),
        Integrator::Taylor { tol } => (3, tol.to_bits()),
    };
    let (alpha, mu) = match spec.model.equation {
        Equation::Linearized => (u64::MAX, [u64::MAX; 2]),
        Equation::Nonlinear { alpha_rad } => (alpha_rad.to_bits(), [u64::MAX; 2]),
        Equation::SlideRock {
            alpha_rad,
            friction,
        } => (
            alpha_rad.to_bits(),
            [friction.mu_s.to_bits(), friction.mu_k.to_bits()],
        ),
    };
    let overturn = match spec.overturn {
        Overturn::Static => 0,
        Overturn::Cap(c) => c.to_bits(),
        Overturn::OnSide => u64::MAX,
        Overturn::Escape => u64::MAX - 1,
    };
    [
        spec.eta.to_bits(),
        spec.p.to_bits(),
        spec.eps.to_bits(),
        spec.rest_tol.to_bits(),
        integrator,
        param,
        alpha,
        overturn,
        mu[0],
        mu[1],
    ]
}

/// Simulations done, and the sample intervals they integrated.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Work {
    pub runs: usize,
    pub intervals: u64,
}

impl Work {
    /// The work done since `earlier`.
    pub fn since(self, earlier: Work) -> Work {
        Work {
            runs: self.runs - earlier.runs,
            intervals: self.intervals - earlier.intervals,
        }
    }
}
