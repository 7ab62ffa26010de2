//! Incremental dynamic analysis: the overturning capacity of one record
//! (pure; MODEL.md §4).
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
//! Default grid ([`ImGrid::default`]): 200 levels log-spaced in η from 1
//! (the uplift threshold of the linearised model: nothing moves at η ≥ 1)
//! down to 10⁻³, ratio 10^(−3/200) ≈ 0.966 between levels (3.4 % steps).

use crate::physics::{simulate, simulate_pair, Excitation, Outcome, PhysicsError, RunSpec};

/// Most levels a grid may have: each level is a simulation per record and
/// block, and 10⁵ levels are already 1,000 times the paper's 100–200.
/// Larger counts are refused before anything is allocated.
pub const MAX_LEVELS: usize = 100_000;

/// How the η levels are spaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Spacing {
    /// Equal ratios between levels.
    Log,
    /// Equal differences between levels.
    Linear,
}

/// A grid of intensity levels, from `eta_max` (exclusive) down to `eta_min`
/// (inclusive), `count` levels.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ImGrid {
    pub eta_max: f64,
    pub eta_min: f64,
    pub count: usize,
    pub spacing: Spacing,
}

impl Default for ImGrid {
    fn default() -> Self {
        ImGrid {
            eta_max: 1.0,
            eta_min: 1e-3,
            count: 200,
            spacing: Spacing::Log,
        }
    }
}

impl ImGrid {
    /// The levels, in decreasing η: `level_j` for j = 1..=count, the last
    /// exactly `eta_min`.
    pub fn levels(&self) -> Result<Vec<f64>, PhysicsError> {
        if !(self.eta_max > self.eta_min && self.eta_min > 0.0 && self.eta_max.is_finite()) {
            return Err(PhysicsError::BadInput(format!(
                "IM grid: need η_max > η_min > 0, got η_max = {}, η_min = {}",
                self.eta_max, self.eta_min
            )));
        }
        if self.count == 0 {
            return Err(PhysicsError::BadInput("IM grid: at least one level".into()));
        }
        if self.count > MAX_LEVELS {
            return Err(PhysicsError::BadInput(format!(
                "IM grid: {} levels is more than {MAX_LEVELS} (each is a simulation; the paper used 100–200)",
                self.count
            )));
        }
        let n = self.count as f64;
        Ok((1..=self.count)
            .map(|j| {
                let f = j as f64 / n;
                if j == self.count {
                    return self.eta_min;
                }
                match self.spacing {
                    Spacing::Log => self.eta_max * (self.eta_min / self.eta_max).powf(f),
                    Spacing::Linear => self.eta_max + (self.eta_min - self.eta_max) * f,
                }
            })
            .collect())
    }
}

/// Whether a run was at a grid level or a refinement point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunKind {
    Level,
    Refinement,
}

impl crate::label::Label for RunKind {
    const ALL: &'static [Self] = &[RunKind::Level, RunKind::Refinement];
    fn label(self) -> &'static str {
        match self {
            RunKind::Level => "level",
            RunKind::Refinement => "refinement",
        }
    }
}

/// One run of an IDA.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IdaPoint {
    pub eta: f64,
    pub kind: RunKind,
    pub outcome: Outcome,
}

/// The capacity of one record for one block.
#[derive(Debug, Clone, PartialEq)]
pub struct Capacity {
    /// Largest η known to overturn (within `tol` of the first overturning);
    /// `None` if the block survived every level.
    pub eta_c: Option<f64>,
    /// The bracket after refinement: the smallest η known to survive above
    /// `eta_c` (`eta_max` of the grid if the first level overturned).
    pub eta_survived: f64,
    /// The first grid level that overturned, and the last one that survived
    /// before it (the bracket before refinement).
    pub level_overturned: Option<f64>,
    pub level_survived: f64,
    /// Every run, in the order run.
    pub points: Vec<IdaPoint>,
    /// With [`Trace::AllLevels`]: how many grid levels stronger than the
    /// first overturning the block survived (resurrections).
    pub resurrections: Option<usize>,
}

/// How far to trace a record's IDA.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Trace {
    /// Stop at the first overturning (and refine): all the capacity and the
    /// horizontal statistics under the resurrection rule need.
    StopAtFirst,
    /// Also run every stronger level, to count resurrections.
    AllLevels,
}

impl Capacity {
    pub fn runs(&self) -> usize {
        self.points.len()
    }
}

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
/// certification are too; only the time changes, and at most one level
/// per other worker past the first overturning is run in vain.
pub struct Runs<'a> {
    exc: &'a Excitation,
    memo: std::collections::HashMap<[u64; 8], Outcome>,
    /// Runs done ahead of need by [`Runs::pair_ahead`], not yet asked for:
    /// counted in [`Runs::work`] (and checked for the event cap) when they
    /// are, so the work reported is the same as if each ran when asked.
    ahead: std::collections::HashMap<[u64; 8], Outcome>,
    done: Work,
    batch: Option<&'a dyn Batch>,
}

/// Runs simulations of one record together: what a caller with spare cores
/// lends one capacity search (the `capacity` command runs them in
/// parallel, [`crate::ops::record::capacity_certified_parallel`]).
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
/// where [`simulate_pair`] can, else one after the other. Each result is
/// [`simulate`]'s for that spec alone.
pub fn run_pair(exc: &Excitation, pair: &[RunSpec; 2]) -> [Result<Outcome, PhysicsError>; 2] {
    match simulate_pair(exc, pair.each_ref()) {
        Some(outs) => outs.map(Ok),
        None => pair.each_ref().map(|s| simulate(exc, s)),
    }
}

impl<'a> Runs<'a> {
    pub fn new(exc: &'a Excitation) -> Self {
        Runs {
            exc,
            memo: std::collections::HashMap::new(),
            ahead: std::collections::HashMap::new(),
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
    /// [`Runs::outcome`] to run again and report if it is ever needed. Those
    /// already run ahead of need are taken as they are, and counted now as
    /// the batch's runs are.
    pub fn prefetch(&mut self, specs: &[RunSpec]) {
        let Some(batch) = self.batch else {
            return;
        };
        let (mut keys, mut missing) = (Vec::new(), Vec::new());
        for s in specs {
            let key = run_key(s);
            if self.memo.contains_key(&key) || keys.contains(&key) {
                continue;
            }
            match self.ahead.remove(&key) {
                Some(out) => {
                    let _ = self.remember(s, out);
                }
                None => {
                    keys.push(key);
                    missing.push(*s);
                }
            }
        }
        if missing.len() < 2 {
            return;
        }
        for (spec, out) in missing.iter().zip(batch.each(self.exc, &missing)) {
            if let Ok(out) = out {
                let _ = self.remember(spec, out);
            }
        }
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
            match self.memo.get(&run_key(s)) {
                Some(out) if out.overturned() => break,
                Some(_) => {}
                None => missing.push(*s),
            }
        }
        if missing.len() < 2 {
            return;
        }
        for (spec, out) in missing
            .iter()
            .zip(batch.until_overturned(self.exc, &missing))
        {
            if let Some(Ok(out)) = out {
                let _ = self.remember(spec, out);
            }
        }
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

    /// Runs two specs that differ in η alone (a chaos probe's two runs)
    /// together, in step, when neither is known yet and they can be
    /// ([`simulate_pair`]: about the price of one where they rock alike).
    /// Their outcomes wait until asked for ([`Runs::outcome`]).
    pub fn pair_ahead(&mut self, specs: &[RunSpec; 2]) {
        let keys = specs.each_ref().map(run_key);
        if keys[0] == keys[1]
            || keys
                .iter()
                .any(|k| self.memo.contains_key(k) || self.ahead.contains_key(k))
        {
            return;
        }
        if let Some(outs) = simulate_pair(self.exc, specs.each_ref()) {
            self.ahead.extend(keys.into_iter().zip(outs));
        }
    }

    /// Keeps outcomes run ahead of need (by [`Batch::alongside`]) until they
    /// are asked for, as [`Runs::pair_ahead`] does; failures are dropped, to
    /// be run again and reported if they are ever asked for.
    fn keep_ahead(&mut self, outs: Vec<(RunSpec, Result<Outcome, PhysicsError>)>) {
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
            return Err(PhysicsError::BadInput(format!(
                "the run at η = {} hit the limit of {} events without a verdict",
                spec.eta,
                crate::physics::MAX_EVENTS
            )));
        }
        self.done.runs += 1;
        self.done.intervals += out.intervals;
        self.memo.insert(run_key(spec), out);
        Ok(out)
    }
}

/// Every number that defines a run, as bits.
fn run_key(spec: &RunSpec) -> [u64; 8] {
    use crate::physics::{Equation, Integrator, Overturn};
    let (integrator, param) = match spec.model.integrator {
        Integrator::Exact => (0, 0),
        Integrator::Dp5 { rtol } => (1, rtol.to_bits()),
        Integrator::Rk4 { substeps } => (2, u64::from(substeps)),
    };
    let alpha = match spec.model.equation {
        Equation::Linearized => u64::MAX,
        Equation::Nonlinear { alpha_rad } => alpha_rad.to_bits(),
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
    ]
}

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
    search(runs, run, grid, tol, trace, false)
}

/// [`capacity_in`]; with `probe_early` and a batch, the chaos probes of the
/// decisive runs ([`chaos_probe`]'s, for a check with the search's own
/// spec) are run by the other workers while the bisection goes on
/// ([`Batch::alongside`]), and wait in [`Runs`] until asked for.
fn search(
    runs: &mut Runs,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
    trace: Trace,
    probe_early: bool,
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
        match runs.batch.filter(|_| probe_early) {
            None => bisect(
                runs,
                run,
                tol,
                [&mut survived, &mut over],
                &mut points,
                &|_| {},
            )?,
            Some(batch) => {
                // The decisive runs known before the bisection: the bracket
                // and the near misses (those of a capacity refined no further).
                let known = decisive_runs(
                    &Capacity {
                        eta_c: Some(over),
                        eta_survived: survived,
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
                    bisected = bisect(
                        runs,
                        run,
                        tol,
                        [&mut survived, &mut over],
                        &mut points,
                        &each,
                    );
                });
                runs.keep_ahead(outs);
                bisected?;
            }
        }
        let resurrections = match trace {
            Trace::StopAtFirst => None,
            Trace::AllLevels => {
                let rest: Vec<RunSpec> = levels[j + 1..].iter().map(|&e| spec(e)).collect();
                runs.prefetch(&rest);
                let mut survived_after = 0;
                for &eta in &levels[j + 1..] {
                    let outcome = runs.outcome(&spec(eta))?;
                    points.push(IdaPoint {
                        eta,
                        kind: RunKind::Level,
                        outcome,
                    });
                    survived_after += usize::from(!outcome.overturned());
                }
                Some(survived_after)
            }
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

/// Bisects the bracket `[over, survived]` of `run`'s η down to `tol`,
/// recording each refinement run and calling `refined` with its η.
fn bisect(
    runs: &mut Runs,
    run: &RunSpec,
    tol: f64,
    [survived, over]: [&mut f64; 2],
    points: &mut Vec<IdaPoint>,
    refined: &dyn Fn(f64),
) -> Result<(), PhysicsError> {
    while *survived - *over > tol {
        let mid = 0.5 * (*survived + *over);
        if mid <= *over || mid >= *survived {
            break;
        }
        let outcome = runs.outcome(&RunSpec { eta: mid, ..*run })?;
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

/// How a capacity's decisive verdicts were checked.
#[derive(Debug, Clone, PartialEq)]
pub enum Certification {
    /// Searched at `rtol` and the decisive runs gave the same verdicts at
    /// `checked_rtol` = rtol/[`TIGHTEN`]; `searches` > 1 when looser
    /// searches had to be redone.
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
    /// DP5: the decisive verdicts agree at a 100× tighter tolerance.
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

/// The tightest tolerance a check may use: below it DP5's error estimate
/// is rounding noise.
pub const TIGHTEST_RTOL: f64 = 1e-14;

/// How far (relative) the chaos probe moves η: far below any meaning (the
/// grid's steps are 3.4 %), about the size of the integration errors a
/// tolerance allows.
pub const CHAOS_PROBE: f64 = 1e-9;

/// The two runs that probe the run of `check` at `eta`: η moved by
/// ±[`CHAOS_PROBE`].
fn probes(check: &RunSpec, eta: f64) -> [RunSpec; 2] {
    [eta * (1.0 + CHAOS_PROBE), eta * (1.0 - CHAOS_PROBE)].map(|eta| RunSpec { eta, ..*check })
}

/// The first decisive run whose verdict changes when η moves by
/// ±[`CHAOS_PROBE`], if any.
fn chaos_probe(
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
    for (eta, overturned, pair) in decisive {
        runs.pair_ahead(&pair);
        for spec in &pair {
            if runs.outcome(spec)?.overturned() != overturned {
                return Ok(Some(eta));
            }
        }
    }
    Ok(None)
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

/// [`capacity_traced`], certified: for a tolerance-controlled integrator the
/// decisive runs ([`decisive_runs`]) are rerun at a [`TIGHTEN`]× tighter
/// tolerance; if a verdict flips, the whole search is redone at that
/// tolerance and checked again, down to [`TIGHTEST_RTOL`]. Once they agree,
/// every decisive run is probed for chaos (η moved by ±[`CHAOS_PROBE`] at
/// the tighter tolerance). The exact stepper has no tolerance: its decisive
/// runs are only probed for chaos. RK4 is not certified.
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
    let Integrator::Dp5 { rtol: asked } = run.model.integrator else {
        // The exact stepper's probes are run with the search's own spec:
        // with a batch, they can start while the bisection runs.
        let exact = run.model.integrator == Integrator::Exact;
        let capacity = search(runs, run, grid, tol, trace, exact)?;
        let searched = runs.work();
        let certification = match run.model.integrator {
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
    let with_rtol = |rtol: f64| RunSpec {
        model: crate::physics::Model {
            integrator: Integrator::Dp5 { rtol },
            ..run.model
        },
        ..*run
    };
    let (mut rtol, mut searches) = (asked, 0u32);
    loop {
        searches += 1;
        let spec = with_rtol(rtol);
        let before = runs.work();
        let capacity = capacity_in(runs, &spec, grid, tol, trace)?;
        let search = runs.work().since(before);
        let checked_rtol = (rtol / TIGHTEN).max(TIGHTEST_RTOL);
        let check = with_rtol(checked_rtol);
        let mut flipped = None;
        for (eta, overturned) in decisive_runs(&capacity, grid) {
            if runs.outcome(&RunSpec { eta, ..check })?.overturned() != overturned {
                flipped = Some(eta);
                break;
            }
        }
        let chaos = match flipped {
            Some(_) => None,
            None => chaos_probe(runs, &check, &capacity, grid)?,
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
            (Some(eta), _) if rtol / (TIGHTEN * TIGHTEN) < TIGHTEST_RTOL => Certification::Failed {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_grid_has_equal_ratios_and_exact_ends() {
        let g = ImGrid::default().levels().unwrap();
        assert_eq!(g.len(), 200);
        assert_eq!(*g.last().unwrap(), 1e-3);
        let r = 10f64.powf(-3.0 / 200.0);
        for w in g.windows(2) {
            assert!((w[1] / w[0] - r).abs() < 1e-12);
        }
        assert!((g[0] - r).abs() < 1e-15);
        let lin = ImGrid {
            eta_max: 1.0,
            eta_min: 0.1,
            count: 9,
            spacing: Spacing::Linear,
        }
        .levels()
        .unwrap();
        assert!((lin[0] - 0.9).abs() < 1e-15 && lin[8] == 0.1);
        assert!(ImGrid {
            eta_min: 2.0,
            ..ImGrid::default()
        }
        .levels()
        .is_err());
    }
}
