//! Runs of one block and record at several values of η kept in step: the
//! event loop of [`super::drive`] for two runs ([`drive_pair`]) or `N`
//! ([`drive_lanes`]), their eventless intervals crossed together by a
//! stepper's lanes ([`CruisePair`], [`CruiseLanes`]).

use super::event_loop::{Driver, Flow, Outcome};
use crate::physics::step::{Rocking, Stepper};
use crate::physics::{Excitation, RunSpec};

/// Two runs that differ only in η (the two runs of a chaos probe), kept in
/// step: while both rock through the same eventless intervals they are
/// advanced together, two lanes of one vector ([`CruisePair`]: the exact
/// stepper, the Taylor stepper); every other interval each run walks on
/// its own, and the one behind catches up to the other before they go on
/// together (where one meets an event, the exact stepper's lanes carry the
/// other across that interval, so that only the one walks it). Each run does the same operations in the same order as it
/// would alone ([`super::drive`]), so its outcome is the same to the bit.
#[inline(always)]
pub(in crate::physics) fn drive_pair<S: CruisePair>(
    exc: &Excitation,
    specs: [&RunSpec; 2],
    limits: [f64; 2],
    steppers: [&mut S; 2],
) -> [Outcome; 2] {
    let [stepper_a, stepper_b] = steppers;
    let (mut obs_a, mut obs_b) = ((), ());
    let mut a = Driver::new(exc, specs[0], None, limits[0], stepper_a, &mut obs_a);
    let mut b = Driver::new(exc, specs[1], None, limits[1], stepper_b, &mut obs_b);
    let n = exc.psi.len().saturating_sub(1);
    let (mut ka, mut kb) = (0, 0);
    let (mut live_a, mut live_b) = (true, true);
    loop {
        if live_a && ka >= n {
            a.finish();
            live_a = false;
        }
        if live_b && kb >= n {
            b.finish();
            live_b = false;
        }
        match (live_a, live_b) {
            (false, false) => break,
            (true, false) => live_a = a.advance(&mut ka, n, n) == Flow::Going,
            (false, true) => live_b = b.advance(&mut kb, n, n) == Flow::Going,
            (true, true) if ka < kb => live_a = a.advance(&mut ka, n, kb) == Flow::Going,
            (true, true) if kb < ka => live_b = b.advance(&mut kb, n, ka) == Flow::Going,
            (true, true) => {
                if let (Some(st_a), Some(st_b)) = (a.state.as_mut(), b.state.as_mut()) {
                    let [next_a, next_b] = S::cruise_pair(
                        [&mut *a.stepper, &mut *b.stepper],
                        exc,
                        ka,
                        [st_a, st_b],
                        [&mut a.out.max_abs_x, &mut b.out.max_abs_x],
                    );
                    a.out.intervals += (next_a - ka) as u64;
                    b.out.intervals += (next_b - kb) as u64;
                    (ka, kb) = (next_a, next_b);
                    // Both at the record's end, or one past an interval
                    // the other walks next, on its own.
                    if next_a == n && next_b == n || next_a != next_b {
                        continue;
                    }
                }
                // One of them (or both) has an event in interval `ka`, or
                // is at rest: `a` walks that interval alone (or skips its
                // quiet), then `b` catches up.
                let cap = ka + 1;
                live_a = a.advance(&mut ka, n, cap) == Flow::Going;
            }
        }
    }
    [a.out, b.out]
}

/// A stepper that crosses the eventless whole intervals of two runs of
/// the same block and record at two values of η together
/// ([`drive_pair`]).
pub(in crate::physics) trait CruisePair: Stepper {
    /// [`Stepper::cruise`] for two runs at once, both rocking at sample
    /// `k`: their whole intervals, one lane each, for as long as both are
    /// proved eventless; at the first interval either must leave to
    /// [`Stepper::cruise`] or [`Stepper::rock`], the other may cross it
    /// (or is left there too, to cross it on its own). Returns the sample
    /// each is at. Each lane does what `cruise` does alone, operation for
    /// operation.
    fn cruise_pair(
        steppers: [&mut Self; 2],
        exc: &Excitation,
        k: usize,
        states: [&mut Rocking; 2],
        tops: [&mut f64; 2],
    ) -> [usize; 2];
}

/// Up to `N` runs that differ only in η and the stepper's tolerance (two
/// decisive runs' chaos probes, a refinement run with its probes), kept in
/// step: while two or more of them rock through the same eventless
/// intervals they are advanced together, lanes of one vector
/// ([`CruiseLanes`]: the Taylor stepper's four); every other interval each
/// run walks on its own, and those behind catch up with the one ahead
/// before they go on together. A run not `present` fills a place and is
/// never run (its outcome means nothing). Each run does the same
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
        // A run behind the one ahead catches up with it on its own.
        if let Some(i) = (0..N).find(|&i| live[i] && ks[i] < ahead) {
            live[i] = runs[i].advance(&mut ks[i], n, ahead) == Flow::Going;
            continue;
        }
        let first = (0..N).find(|&i| live[i]).expect("one run live");
        if live.iter().filter(|&&l| l).count() == 1 {
            live[first] = runs[first].advance(&mut ks[first], n, n) == Flow::Going;
            continue;
        }
        // Every live run at sample `ahead`: together while all rock.
        if (0..N).all(|i| !live[i] || runs[i].state.is_some()) {
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
                    ..
                } = run;
                if let Some(state) = state.as_mut() {
                    *lane = Some(Lane {
                        stepper: &mut **stepper,
                        state,
                        top: &mut out.max_abs_x,
                    });
                }
            }
            let next = S::cruise_lanes(lanes, exc, ahead);
            for i in (0..N).filter(|&i| live[i]) {
                runs[i].out.intervals += (next - ahead) as u64;
                ks[i] = next;
            }
            if next == n {
                continue;
            }
        }
        // One of them (or more) has an event in interval `ahead`, or is at
        // rest: the first walks that interval alone (or skips its quiet),
        // then the others catch up.
        let cap = ks[first] + 1;
        live[first] = runs[first].advance(&mut ks[first], n, cap) == Flow::Going;
    }
    runs.map(|r| r.out)
}

/// One run of [`drive_lanes`], as [`CruiseLanes::cruise_lanes`] takes it:
/// its stepper, its state (rocking) and the largest `|x|` it has met.
pub(in crate::physics) struct Lane<'a, S> {
    pub stepper: &'a mut S,
    pub state: &'a mut Rocking,
    pub top: &'a mut f64,
}

/// A stepper that crosses the eventless whole intervals of up to `N` runs
/// of the same block and record at several values of η together
/// ([`drive_lanes`]).
pub(in crate::physics) trait CruiseLanes<const N: usize>: Stepper {
    /// [`Stepper::cruise`] for the runs given (`Some`, two or more, all
    /// rocking at sample `k`) at once: their whole intervals, one lane
    /// each, for as long as all are proved eventless; stops at the first
    /// interval one must leave to [`Stepper::cruise`] or [`Stepper::rock`]
    /// (the others are left there too, and cross it on their own) and
    /// returns it. Each lane does what `cruise` does alone, operation for
    /// operation.
    fn cruise_lanes(runs: [Option<Lane<'_, Self>>; N], exc: &Excitation, k: usize) -> usize
    where
        Self: Sized;
}
