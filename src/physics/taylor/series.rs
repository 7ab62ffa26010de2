//! The series of a Taylor step, order by order, written once for any
//! number of lanes ([`build`]; the lone run's [`Taylor::series`] is its
//! one-lane case, the runs in step of `pair` its two- and four-lane ones):
//! the recurrences of the module's header, the constants of a step
//! multiplied out beforehand, the first orders each their own straight
//! code, the tail tested as the series grows.

use super::poly::sum;
use super::{Ends, Step, Taylor, INV, LEN, MAX_ORDER, MIN_ORDER};
use crate::physics::lanes::Lanes;

impl Taylor {
    /// Builds the series of a step of length `h` from `y0`, `ẏ0 = w0`, `sin
    /// u0 = e0`, `cos u0 = d0` on pivot `s` under `g_a + g1·σ`, order by
    /// order until its tail is below the tolerance; returns the degree `n`
    /// of V (Y's is n + 1), or `None` if the tail is still above the
    /// tolerance at [`MAX_ORDER`]. On success [`Taylor::ends`] holds the
    /// series' sums (its values at τ = 1) and `Σ_{j≥1} |V_j|`. The one-lane
    /// case of [`build`].
    #[inline(always)]
    pub(super) fn series(&mut self, from: Step) -> Option<usize> {
        let Step {
            s,
            y0,
            w0,
            e0,
            d0,
            h,
            g_a,
            g1,
        } = from;
        self.built = None;
        let c = Shared {
            p2_over_alpha: self.p2_over_alpha,
            alpha: self.alpha,
            p2_over_eta: self.p2_over_eta,
            tol: self.tol,
            tol_e: self.tol_sin_cos(),
        };
        let coeffs = Coefficients {
            y: &mut self.y,
            v: &mut self.v,
            e: &mut self.e,
            d: &mut self.d,
        };
        let ([n], [ends]) = build::<f64, 1>(coeffs, &c, [s, y0, w0, e0, d0], h, g_a, g1);
        if n.is_some() {
            self.ends = ends;
        }
        n
    }

    /// The series just built, not converged, taken as it is to
    /// [`MAX_ORDER`] (a state that is not finite): its degree.
    pub(super) fn as_it_is(&mut self) -> usize {
        self.y[MAX_ORDER + 1] = self.v[MAX_ORDER] * INV[MAX_ORDER + 1];
        self.ends = Ends {
            y: sum(&self.y),
            v: sum(&self.v[..LEN - 1]),
            e: sum(&self.e[..LEN - 1]),
            d: sum(&self.d[..LEN - 1]),
            abs_v_tail: f64::INFINITY,
        };
        MAX_ORDER
    }
}

/// `Σ_{j=1}^{k−1} D_j V_{k−j}` and `Σ E_j V_{k−j}` (order k's convolutions
/// without their terms in `D_0`, `E_0`, `V_0`), for [`Taylor::series`] and
/// the pair's lanes alike. Summed from the inside out: the terms pair as
/// `(j, k − j)`, and a pair needs order `max(j, k − j)`, so the oldest
/// terms are summed first and the two of the newest stored order (j = 1, k
/// − 1) last, not first: the sum then waits for that order by a product
/// and two sums only, and the chain of orders stays three operations an
/// order.
#[inline(always)]
pub(super) fn convolutions<T>(d: &[T], e: &[T], v: &[T], k: usize, zero: T) -> (T, T)
where
    T: Copy + std::ops::Add<Output = T> + std::ops::Mul<Output = T>,
{
    let (mut se, mut sd) = (zero, zero);
    if k < 2 {
        return (se, sd);
    }
    let (mut lo, mut hi) = (k / 2, k - k / 2);
    if lo == hi {
        (se, sd) = (d[lo] * v[lo], e[lo] * v[lo]);
        (lo, hi) = (lo - 1, hi + 1);
    }
    while lo >= 1 {
        se = se + (d[lo] * v[hi] + d[hi] * v[lo]);
        sd = sd + (e[lo] * v[hi] + e[hi] * v[lo]);
        (lo, hi) = (lo - 1, hi + 1);
    }
    (se, sd)
}

/// A series' sums at τ = 1 (Y to degree m + 1, V, E, D to m) and `Σ_{j≥1}
/// |V_j|`, for [`Taylor::series`] and the pair's lanes alike: the terms
/// past the first summed from the first order up (each far below the
/// first, so summed in any order they round as one sum), after the series
/// is done rather than as it grows, which keeps the registers for the
/// chain of orders.
#[inline(always)]
pub(super) fn ends<T>(
    y: &[T],
    v: &[T],
    e: &[T],
    d: &[T],
    m: usize,
    zero: T,
    abs: impl Fn(T) -> T,
) -> [T; 5]
where
    T: Copy + std::ops::Add<Output = T>,
{
    let (mut ty, mut tv, mut te, mut td, mut abs_v) = (zero, zero, zero, zero, zero);
    for j in 1..=m {
        ty = ty + y[j];
        tv = tv + v[j];
        te = te + e[j];
        td = td + d[j];
        abs_v = abs_v + abs(v[j]);
    }
    [
        y[0] + (ty + y[m + 1]),
        v[0] + tv,
        e[0] + te,
        d[0] + td,
        abs_v,
    ]
}

/// What the steps of the lanes share (the same `p` and α), as a series
/// uses it, and what each lane has of its own (η, the tolerance: a run and
/// its chaos probes at a tighter one go together).
pub(super) struct Shared<T> {
    pub(super) p2_over_alpha: f64,
    pub(super) alpha: f64,
    pub(super) p2_over_eta: T,
    pub(super) tol: T,
    pub(super) tol_e: T,
}

/// Where a series' coefficients (in τ) go: Y to degree n + 1, V, E, D to n.
pub(super) struct Coefficients<'c, T> {
    pub(super) y: &'c mut [T; LEN],
    pub(super) v: &'c mut [T; LEN],
    pub(super) e: &'c mut [T; LEN],
    pub(super) d: &'c mut [T; LEN],
}

/// The series of `N` steps over the same stretch of length `h` under
/// `g_a + g1·σ` (one lane each, each from its own `[s, y0, w0, e0, d0]`: its
/// pivot, `y`, `ẏ`, `sin u`, `cos u`), order by order as the module's
/// recurrences grow them, until every lane's tail is below its tolerance
/// (or [`MAX_ORDER`]): each lane's degree (`None` where its tail is still
/// above it) and sums. The orders nearly every step needs are each their
/// own straight code (their convolutions unrolled), the rare longer series
/// a loop. A lane done an order or more before the others keeps its own
/// last term of Y: that order's.
///
/// Each order depends on the one before through a product and two sums
/// (the constants multiplied out beforehand, the convolutions' older terms
/// summed first): the chain of orders is what bounds the step's time, the
/// rest runs beside it, and lanes share the chain.
#[inline(always)]
pub(super) fn build<T: Lanes<N>, const N: usize>(
    co: Coefficients<'_, T>,
    c: &Shared<T>,
    [s, y0, w0, e0, d0]: [T; 5],
    h: f64,
    g_a: f64,
    g1: f64,
) -> ([Option<usize>; N], [Ends; N]) {
    let zero = T::splat(0.0);
    let h2 = h * h;
    let k_sin = T::splat(h2 * c.p2_over_alpha);
    let f = (s * T::splat(h2)) * c.p2_over_eta;
    let (f0, f1) = (f * T::splat(g_a), (f * T::splat(g1)) * T::splat(h));
    let a = c.alpha;
    let (tol, tol_e) = (c.tol, c.tol_e);
    let Coefficients { y, v, e, d } = co;
    let v0 = T::splat(h) * w0;
    y[0] = y0;
    v[0] = v0;
    e[0] = e0;
    d[0] = d0;
    let fa = T::splat(a);
    let (a_v0, a_e0, a_d0) = (fa * v0, fa * e0, fa * d0);
    // The newest coefficients stay in registers; the convolutions read from
    // memory only the ones stored an order or more before. The
    // coefficients fall geometrically: V's largest is among its first three.
    let (mut vk, mut ek, mut dk, mut d_prev) = (v0, e0, d0, zero);
    let (mut scale_v, mut tol_v) = (v0.abs(), zero);
    let mut n = [None; N];
    let mut sums = [Ends::default(); N];
    macro_rules! order {
        ($k:expr) => {{
            let k: usize = $k;
            let m = k + 1;
            let inv = T::splat(INV[m]);
            // Off the chain: what does not depend on order k.
            let (c0, cs, t1) = (f0 * inv, k_sin * inv, (f1 * inv) * d_prev);
            let (se, sd) = convolutions(&d[..], &e[..], &v[..], k, zero);
            let ai = T::splat(a * INV[m]);
            let (se, sd) = (ai * se, ai * sd);
            let (cv, cd, ce) = (a_v0 * inv, a_d0 * inv, a_e0 * inv);
            // On the chain: order k's values, each through a product and two sums.
            let vm = (c0 * dk + t1) - cs * ek;
            let ym = vk * inv;
            let (em, dm) = if k > 0 {
                (-(se + cv * dk) - cd * vk, (sd + cv * ek) + ce * vk)
            } else {
                (-(cd * vk), ce * vk)
            };
            (y[m], v[m], e[m], d[m]) = (ym, vm, em, dm);
            if m <= 2 {
                scale_v = scale_v.max(vm.abs());
                tol_v = tol * scale_v;
            } else if m >= MIN_ORDER {
                let tails = (
                    vm.abs() + vk.abs(),
                    em.abs() + ek.abs(),
                    dm.abs() + dk.abs(),
                );
                let bits = tails.0.le3(tol_v, tails.1, tol_e, tails.2, tol_e);
                if bits != 0 {
                    // Y's last term, as the next order's `ym` would be.
                    y[m + 1] = vm * T::splat(INV[m + 1]);
                    let [ye, ve, ee, de, ae] =
                        ends(&y[..], &v[..], &e[..], &d[..], m, zero, T::abs);
                    let [ye, ve, ee, de, ae] = [
                        ye.to_lanes(),
                        ve.to_lanes(),
                        ee.to_lanes(),
                        de.to_lanes(),
                        ae.to_lanes(),
                    ];
                    for lane in 0..N {
                        if bits & (1 << lane) != 0 && n[lane].is_none() {
                            n[lane] = Some(m);
                            sums[lane] = Ends {
                                y: ye[lane],
                                v: ve[lane],
                                e: ee[lane],
                                d: de[lane],
                                abs_v_tail: ae[lane],
                            };
                        }
                    }
                    if n.iter().all(Option::is_some) {
                        return (n, sums);
                    }
                }
            }
            (vk, ek, d_prev, dk) = (vm, em, dk, dm);
        }};
    }
    order!(0);
    order!(1);
    order!(2);
    order!(3);
    order!(4);
    order!(5);
    order!(6);
    order!(7);
    order!(8);
    for k in 9..MAX_ORDER {
        order!(k);
    }
    (n, sums)
}
