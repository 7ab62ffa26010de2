//! The slide-rock mode's stepper: a block on one pivot whose pivot slips
//! (docs/MODEL.md §21), advanced by Dormand–Prince 5(4) with error control
//! over the state `(x, v, u, w)` until the stretch ends or its first event:
//! the impact (`x = 0`), the overturning limit, the slip's stop (`w = 0`)
//! or the normal force reaching 0 (the block would fly). Events are
//! located by bisection on the step's length, each trial a step of the same
//! formula from the step's start, to the last bits of time.

use super::friction::Contact;
use super::step::{Rocking, Stretch};

/// A block on a slipping pivot: the rocking state, the base's position `u`
/// (m) and velocity `w` (m/s), and the direction the pivot slips (±1; `w`
/// is 0 or of its sign).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slipping {
    pub st: Rocking,
    pub u: f64,
    pub w: f64,
    pub dir: f64,
}

/// How a slide-rock stretch ended (offsets from the stretch's start).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SlideRockEnd {
    End,
    /// `x` reached 0: the state is at the impact, before its map.
    Impact {
        sigma: f64,
    },
    Overturn {
        sigma: f64,
    },
    /// The slip stopped (`w = 0`).
    Stick {
        sigma: f64,
    },
    /// The normal force reached 0: the block would leave the base.
    Flight {
        sigma: f64,
    },
}

/// The stepper; one per run.
pub struct SlideRock {
    contact: Contact,
    limit: f64,
    rtol: f64,
    /// Scales of the four components' absolute errors.
    atol: [f64; 4],
    /// The last accepted step's length (s).
    h: f64,
    /// Steps taken (accepted and rejected), for benchmarks.
    pub steps: u64,
}

type Y = [f64; 4];

const C: [f64; 6] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0];
const A: [[f64; 5]; 6] = [
    [0.0; 5],
    [0.2, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
    ],
];
const B: [f64; 6] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
];
/// The fifth-order weights less the fourth's (the seventh stage's −1/40 apart).
const E: [f64; 6] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
];
const E7: f64 = -1.0 / 40.0;

impl SlideRock {
    /// The stepper for `contact`, stopping at `|x| = limit`, at relative
    /// tolerance `rtol` per step; `p` (1/s) sets the time scale.
    pub fn new(contact: Contact, p: f64, limit: f64, rtol: f64) -> Self {
        let size = contact.r * contact.alpha;
        SlideRock {
            contact,
            limit,
            rtol,
            atol: [rtol, rtol * p, rtol * size, rtol * size * p],
            h: 0.05 / p,
            steps: 0,
        }
    }

    fn rhs(&self, s: f64, dir: f64, psi: f64, y: &Y) -> (Y, f64) {
        let (xdd, wdd, n) = self.contact.slide_rock_accel(s, dir, y[0], y[1], psi);
        ([y[1], xdd, y[3], wdd], n)
    }

    /// One step of length `h` from `y` at offset `sigma` (the forcing
    /// `g_a + g1 σ` from the stretch's start), whose derivative there is
    /// `k1`: the fifth-order solution, the scaled error, and the derivative
    /// and normal force at the solution (the next step's first stage).
    #[allow(clippy::too_many_arguments)]
    fn step(&self, s: f64, dir: f64, st: &Stretch, sigma: f64, y: &Y, k1: &Y, h: f64) -> Step {
        let mut k = [[0.0; 4]; 6];
        k[0] = *k1;
        for i in 1..6 {
            let mut yi = *y;
            for (j, kj) in k.iter().enumerate().take(i) {
                for c in 0..4 {
                    yi[c] += h * A[i][j] * kj[c];
                }
            }
            let psi = st.g_a + st.g1 * (sigma + C[i] * h);
            k[i] = self.rhs(s, dir, psi, &yi).0;
        }
        let mut out = *y;
        for (i, ki) in k.iter().enumerate() {
            for c in 0..4 {
                out[c] += h * B[i] * ki[c];
            }
        }
        let (k7, n) = self.rhs(s, dir, st.g_a + st.g1 * (sigma + h), &out);
        let mut err: f64 = 0.0;
        for c in 0..4 {
            let mut e = E7 * k7[c];
            for (i, ki) in k.iter().enumerate() {
                e += E[i] * ki[c];
            }
            let scale = self.atol[c] + self.rtol * y[c].abs().max(out[c].abs());
            err = err.max((h * e).abs() / scale);
        }
        Step {
            y: out,
            err,
            dy: k7,
            n,
        }
    }

    /// The events' functions at `y` with normal force `n` (each positive
    /// while nothing happens): the height over the impact, under the limit,
    /// the slip, the normal force.
    fn events(&self, s: f64, dir: f64, y: &Y, n: f64) -> [f64; 4] {
        [s * y[0], self.limit - s * y[0], dir * y[3], n]
    }

    /// Advances `state` over `stretch` or to its first event; raises
    /// `max_abs_x` to every extremum passed.
    pub fn advance(
        &mut self,
        stretch: Stretch,
        state: &mut Slipping,
        max_abs_x: &mut f64,
    ) -> SlideRockEnd {
        let (s, dir) = (state.st.s, state.dir);
        let mut y: Y = [state.st.x, state.st.v, state.u, state.w];
        if s * y[0] <= 0.0 && s * y[1] < 0.0 {
            // On the impact already (past it within rounding: a slip that
            // stopped at x ≈ 0 starts again there) and moving into it: the
            // impact is now. Located, it was at the start's rounding, where
            // the slip's stop came first: stop and slip alternated at one
            // instant without end.
            y[0] = 0.0;
            self.store(state, &y);
            return SlideRockEnd::Impact { sigma: 0.0 };
        }
        let mut k1 = self.rhs(s, dir, stretch.g_a, &y).0;
        let mut sigma = 0.0;
        while sigma < stretch.len {
            let h = self.h.min(stretch.len - sigma);
            let next = self.step(s, dir, &stretch, sigma, &y, &k1, h);
            self.steps += 1;
            let err = next.err;
            let accepted = err <= 1.0;
            if !accepted && h > 1e-14 {
                let shrink = if err.is_finite() {
                    (0.9 * err.powf(-0.2)).clamp(0.1, 0.9)
                } else {
                    0.1
                };
                self.h = h * shrink;
                continue;
            }
            let from = From {
                s,
                dir,
                st: &stretch,
                sigma,
                y: &y,
                k1: &k1,
            };
            let ev = self.events(s, dir, &next.y, next.n);
            if let Some(i) = ev.iter().position(|&e| e < 0.0) {
                let (at, mut y_at) = self.locate(&from, h, i, ev[i]);
                *max_abs_x = max_abs_x.max(self.top(&from, at - sigma, &y_at));
                let end = match i {
                    0 => {
                        y_at[0] = 0.0;
                        SlideRockEnd::Impact { sigma: at }
                    }
                    1 => {
                        y_at[0] = s * self.limit;
                        *max_abs_x = max_abs_x.max(self.limit);
                        SlideRockEnd::Overturn { sigma: at }
                    }
                    2 => {
                        y_at[3] = 0.0;
                        SlideRockEnd::Stick { sigma: at }
                    }
                    _ => SlideRockEnd::Flight { sigma: at },
                };
                self.store(state, &y_at);
                return end;
            }
            *max_abs_x = max_abs_x.max(self.top(&from, h, &next.y));
            y = next.y;
            k1 = next.dy;
            sigma += h;
            self.h = if err > 0.0 {
                h * (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            } else {
                h * 5.0
            };
        }
        self.store(state, &y);
        SlideRockEnd::End
    }

    fn store(&self, state: &mut Slipping, y: &Y) {
        state.st.x = y[0];
        state.st.v = y[1];
        state.u = y[2];
        state.w = y[3];
    }

    /// The state a step of length `len` from `from` reaches.
    fn reach(&self, from: &From, len: f64) -> Step {
        self.step(from.s, from.dir, from.st, from.sigma, from.y, from.k1, len)
    }

    /// Where in `(0, h]` of the step from `from` event `i` (negative, `e`,
    /// at `h`) happens, and the state there (its function just below 0),
    /// by [`first_negative`] on the step's length; if another event comes
    /// first there, that one's. The offset is from the stretch's start.
    fn locate(&self, from: &From, h: f64, i: usize, e: f64) -> (f64, Y) {
        let (s, dir) = (from.s, from.dir);
        let n0 = self
            .rhs(s, dir, from.st.g_a + from.st.g1 * from.sigma, from.y)
            .1;
        let at_zero = self.events(s, dir, from.y, n0)[i];
        let (mut at, mut y_at) = first_negative(
            (0.0, at_zero.max(0.0)),
            (h, e),
            self.reach(from, h).y,
            1e-15 * (from.sigma + h),
            |len| {
                let next = self.reach(from, len);
                (self.events(s, dir, &next.y, next.n)[i], next.y)
            },
        );
        // Another event passed before this one: locate it instead.
        let step = self.reach(from, at);
        let ev = self.events(s, dir, &step.y, step.n);
        if let Some(j) = ev.iter().position(|&x| x < 0.0).filter(|&j| j != i) {
            (at, y_at) = self.locate(from, at, j, ev[j]);
            return (at, y_at);
        }
        (from.sigma + at, y_at)
    }

    /// The largest `|x|` over a step of length `h` from `from` to `end`:
    /// its ends, and where the velocity turns if it turns inside.
    fn top(&self, from: &From, h: f64, end: &Y) -> f64 {
        let (s, y) = (from.s, from.y);
        let mut top = y[0].abs().max(end[0].abs());
        if s * y[1] > 0.0 && s * end[1] < 0.0 {
            let (_, turn) = first_negative(
                (0.0, s * y[1]),
                (h, s * end[1]),
                *end,
                1e-15 * (from.sigma + h),
                |len| {
                    let at = self.reach(from, len).y;
                    (s * at[1], at)
                },
            );
            top = top.max(turn[0].abs());
        }
        top
    }
}

/// One step's result.
struct Step {
    y: Y,
    err: f64,
    /// The derivative and the normal force at `y`.
    dy: Y,
    n: f64,
}

/// Where a step starts.
struct From<'a> {
    s: f64,
    dir: f64,
    st: &'a Stretch,
    sigma: f64,
    y: &'a Y,
    k1: &'a Y,
}

/// The first point of `(lo, hi]` where `f` turns negative, given `f(lo) ≥
/// 0 > f(hi)` and what `eval` gives at `hi`: the Illinois variant of
/// regula falsi (superlinear on a smooth `f`, never leaving the bracket),
/// until the bracket is below `floor` or 100 evaluations; returns the
/// bracket's negative end and what `eval` gave there.
pub(super) fn first_negative<T>(
    (mut lo, mut f_lo): (f64, f64),
    (mut hi, mut f_hi): (f64, f64),
    mut at_hi: T,
    floor: f64,
    mut eval: impl FnMut(f64) -> (f64, T),
) -> (f64, T) {
    let mut last = 0i8;
    for k in 0..100 {
        if hi - lo <= floor {
            break;
        }
        // Every fourth trial halves the bracket, so that a flat side never
        // stalls it.
        let mut x = if k % 4 == 3 {
            0.5 * (lo + hi)
        } else {
            hi - f_hi * (hi - lo) / (f_hi - f_lo)
        };
        if !(x > lo && x < hi) {
            x = 0.5 * (lo + hi);
            if !(x > lo && x < hi) {
                break;
            }
        }
        let (fx, tx) = eval(x);
        if fx < 0.0 {
            (hi, f_hi, at_hi) = (x, fx, tx);
            if last == -1 {
                f_lo *= 0.5;
            }
            last = -1;
        } else {
            (lo, f_lo) = (x, fx);
            if last == 1 {
                f_hi *= 0.5;
            }
            last = 1;
        }
    }
    (hi, at_hi)
}
