//! Runs of one block and record at several values of η kept in step: the
//! event loop of [`super::drive`] for `N` runs ([`drive_lanes`]), their
//! eventless intervals crossed together by a stepper's lanes
//! ([`CruiseLanes`]).

use super::event_loop::{Driver, Flow, Outcome};
use crate::physics::step::{Rocking, Stepper};
use crate::physics::{Excitation, RunSpec};

/// Up to `N` runs that differ only in η and the stepper's tolerance (the
/// levels of an IDA, two decisive runs' chaos probes, a refinement run
/// with its probes), kept in step, one lane each of one vector
/// ([`CruiseLanes`]: the exact stepper's and the Taylor stepper's four).
/// While every run crosses the same intervals without an event they go on
/// together; at an interval where some lanes meet an event, the others
/// cross it in their lanes ([`CruiseLanes::cruise_lanes`] says which),
/// and those that met it walk it on their own, then all go on together
/// from the next sample: a lane waits for the others' events one interval
/// at a time, never for long. Where every run is at rest they cross the
/// quiet together ([`quiet_together`]). A run not `present` fills a place
/// and is never run (its outcome means nothing). Each run does the same
/// operations in the same order as it would alone ([`super::drive`]), so
/// its outcome is the same to the bit.
#[inline(always)]
pub(in crate::physics) fn drive_lanes<S: CruiseLanes<N>, const N: usize>(
    exc: &Excitation,
    specs: [&RunSpec; N],
    limits: [f64; N],
    steppers: [&mut S; N],
    present: [bool; N],
) -> [Outcome; N] {
    let mut obs = [(); N];
    let mut pairs = steppers.into_iter().zip(obs.each_mut());
    let mut runs: [Driver<'_, S, ()>; N] = std::array::from_fn(|i| {
        let (stepper, obs) = pairs.next().expect("N steppers");
        Driver::new(exc, specs[i], None, limits[i], stepper, obs)
    });
    let n = exc.psi.len().saturating_sub(1);
    let mut ks = [0usize; N];
    let mut live = present;
    let mut tally = LaneTally::default();
    // Runs that met an event in the interval where the others' lanes left them.
    let mut walk = [false; N];
    loop {
        for i in 0..N {
            if live[i] && ks[i] >= n {
                runs[i].finish();
                live[i] = false;
            }
        }
        let Some(ahead) = (0..N).filter(|&i| live[i]).map(|i| ks[i]).max() else {
            break;
        };
        // A run behind the one ahead (one that met an event in the
        // interval the others crossed) catches up with it on its own.
        if let Some(i) = (0..N).find(|&i| live[i] && ks[i] < ahead) {
            let from = ks[i];
            live[i] = if walk[i] {
                // It met an event in the interval the others crossed in
                // their lanes: no fast path crosses it.
                walk[i] = false;
                runs[i].walk_event(&mut ks[i])
            } else {
                runs[i].advance(&mut ks[i], n, ahead)
            } == Flow::Going;
            tally.alone += (ks[i] - from) as u64;
            continue;
        }
        let first = (0..N).find(|&i| live[i]).expect("one run live");
        let count = live.iter().filter(|&&l| l).count();
        if count == 1 {
            live[first] = runs[first].advance(&mut ks[first], n, n) == Flow::Going;
            continue;
        }
        // Every live run at sample `ahead`.
        let resting = (0..N).all(|i| !live[i] || runs[i].state.is_none());
        if resting && quiet_together(&mut runs, &mut ks, live, ahead, n) {
            continue;
        }
        if S::RESTS_IN_LANES || (0..N).all(|i| !live[i] || runs[i].state.is_some()) {
            let mut lanes: [Option<Lane<'_, S>>; N] = std::array::from_fn(|_| None);
            for ((lane, run), _) in lanes
                .iter_mut()
                .zip(runs.iter_mut())
                .zip(live)
                .filter(|x| x.1)
            {
                let Driver {
                    stepper,
                    state,
                    out,
                    threshold,
                    ..
                } = run;
                *lane = Some(Lane {
                    stepper: &mut **stepper,
                    state,
                    top: &mut out.max_abs_x,
                    threshold: *threshold,
                });
            }
            let next = S::cruise_lanes(lanes, exc, ahead);
            for i in (0..N).filter(|&i| live[i]) {
                let done = (next[i] - ahead) as u64;
                runs[i].out.intervals += done;
                tally.in_lanes += done;
                ks[i] = next[i];
            }
            let low = (0..N).filter(|&i| live[i]).map(|i| ks[i]).min();
            let stuck = (0..N).filter(|&i| live[i] && Some(ks[i]) == low).count();
            if low == Some(n) {
                continue;
            }
            if stuck < count {
                // Those that met an event walk it next, while the others wait.
                for i in (0..N).filter(|&i| live[i]) {
                    walk[i] = Some(ks[i]) == low;
                }
                tally.breaks += 1;
                tally.waits += (count - stuck) as u64;
                continue;
            }
        }
        // Each of them has an event in interval `ahead`, or is at rest:
        // the first walks that interval alone (or skips its quiet), then
        // the others catch up.
        tally.breaks += 1;
        let (from, cap) = (ks[first], ks[first] + 1);
        live[first] = runs[first].advance(&mut ks[first], n, cap) == Flow::Going;
        tally.alone += (ks[first] - from) as u64;
    }
    tally.record();
    runs.map(|r| r.out)
}

/// Runs all at rest at sample `k` cross the quiet together: as far as the
/// one of the lowest uplift threshold stays at rest
/// ([`Excitation::quiet_until`]), where every other is quiet too; a run
/// whose record stays below its threshold from some sample on stops
/// there, as it would alone (at the first sample where the record's
/// suffix maximum is at most its threshold: it is moved there, and stops
/// when it is next advanced). Whether they moved.
#[inline(always)]
fn quiet_together<S: Stepper, const N: usize>(
    runs: &mut [Driver<'_, S, ()>; N],
    ks: &mut [usize; N],
    live: [bool; N],
    k: usize,
    n: usize,
) -> bool {
    let exc = runs[0].exc;
    let lowest = (0..N)
        .filter(|&i| live[i])
        .map(|i| runs[i].threshold)
        .fold(f64::INFINITY, f64::min);
    if (0..N).any(|i| live[i] && exc.suffix_max[k] <= runs[i].threshold)
        || exc.psi[k].abs() > lowest
    {
        return false;
    }
    let until = exc.quiet_until(k, lowest).min(n);
    if until == k {
        return false;
    }
    let suffix = &exc.suffix_max[k + 1..=until];
    for i in (0..N).filter(|&i| live[i]) {
        let threshold = runs[i].threshold;
        let to = k + 1 + suffix.partition_point(|&m| m > threshold);
        let to = to.min(until);
        runs[i].out.intervals += (to - k) as u64;
        ks[i] = to;
    }
    true
}

/// What [`drive_lanes`] did, counted on each thread for `rocking-bench`
/// ([`take_lane_tally`]): how its runs' intervals were crossed, and how
/// often a lane waited for another's event.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LaneTally {
    /// Intervals a run crossed in its lane, together with the others.
    pub in_lanes: u64,
    /// Intervals a run walked or crossed on its own while others waited
    /// or after they stopped.
    pub alone: u64,
    /// Intervals at which some lanes met an event.
    pub breaks: u64,
    /// Lanes that crossed such an interval and waited for those that
    /// walked it.
    pub waits: u64,
}

thread_local! {
    static TALLY: std::cell::Cell<LaneTally> = const {
        std::cell::Cell::new(LaneTally { in_lanes: 0, alone: 0, breaks: 0, waits: 0 })
    };
}

impl LaneTally {
    /// Adds this call's counts to the thread's.
    fn record(self) {
        TALLY.with(|t| {
            let mut all = t.get();
            all.in_lanes += self.in_lanes;
            all.alone += self.alone;
            all.breaks += self.breaks;
            all.waits += self.waits;
            t.set(all);
        });
    }
}

/// The counts of runs in lanes on this thread since the last call (and
/// resets them).
pub fn take_lane_tally() -> LaneTally {
    TALLY.with(|t| t.replace(LaneTally::default()))
}

/// One run of [`drive_lanes`], as [`CruiseLanes::cruise_lanes`] takes it:
/// its stepper, its state (`None`: at rest), the largest `|x|` it has met
/// and its uplift threshold on `|ψ̈|`.
pub(in crate::physics) struct Lane<'a, S> {
    pub stepper: &'a mut S,
    pub state: &'a mut Option<Rocking>,
    pub top: &'a mut f64,
    pub threshold: f64,
}

/// A stepper that crosses the eventless whole intervals of up to `N` runs
/// of the same block and record at several values of η together
/// ([`drive_lanes`]).
pub(in crate::physics) trait CruiseLanes<const N: usize>: Stepper {
    /// Whether [`CruiseLanes::cruise_lanes`] takes runs at rest too (else
    /// every run it is given rocks).
    const RESTS_IN_LANES: bool;

    /// [`Stepper::cruise`] for the runs given (`Some`, two or more, all at
    /// sample `k`) at once: their whole intervals, one lane each, for as
    /// long as all cross them without an event (a rocking run proved
    /// eventless as `cruise` proves it; one at rest, in quiet). At the
    /// first interval some cannot cross so, those that can may cross it
    /// (a stepper that keeps no lane's work leaves them all there). Returns
    /// the sample each run is at; each lane does what `cruise` does alone,
    /// operation for operation.
    fn cruise_lanes(runs: [Option<Lane<'_, Self>>; N], exc: &Excitation, k: usize) -> [usize; N]
    where
        Self: Sized;
}
