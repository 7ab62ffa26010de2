//! The series of one Taylor step, order by order: the recurrences of the
//! module's header, the constants of a step multiplied out beforehand, the
//! first orders each their own straight code, the tail tested as the series
//! grows ([`Taylor::series`]).

use super::poly::sum;
use super::{Ends, Step, Taylor, INV, LEN, MAX_ORDER, MIN_ORDER};

impl Taylor {
    /// Builds the series of a step of length `h` from `y0`, `ẏ0 = w0`, `sin
    /// u0 = e0`, `cos u0 = d0` on pivot `s` under `g_a + g1·σ`, order by
    /// order until its tail is below the tolerance; returns the degree `n`
    /// of V (Y's is n + 1), or `None` if the tail is still above the
    /// tolerance at [`MAX_ORDER`]. On success [`Taylor::ends`] holds the
    /// series' sums (its values at τ = 1) and `Σ_{j≥1} |V_j|`.
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
        let h2 = h * h;
        let k_sin = h2 * self.p2_over_alpha;
        let f = s * h2 * self.p2_over_eta;
        let a = self.alpha;
        let v0 = h * w0;
        (self.y[0], self.v[0], self.e[0], self.d[0]) = (y0, v0, e0, d0);
        let c = Consts {
            f0: f * g_a,
            f1: f * g1 * h,
            k_sin,
            a,
            a_v0: a * v0,
            a_e0: a * e0,
            a_d0: a * d0,
            tol: self.tol,
            tol_e: self.tol_sin_cos(),
        };
        // The newest coefficients stay in registers; the convolutions read
        // from memory only the ones stored an order or more before. The
        // coefficients fall geometrically: V's largest is among its first
        // three.
        let mut g = Grow {
            vk: v0,
            ek: e0,
            dk: d0,
            d_prev: 0.0,
            scale_v: v0.abs(),
            tol_v: 0.0,
        };
        // The orders nearly every step needs, each its own straight code
        // (its convolutions unrolled); the rare longer series in a loop.
        macro_rules! unrolled {
            ($($k:literal)*) => {$(
                if self.order($k, &c, &mut g) {
                    return Some($k + 1);
                }
            )*};
        }
        unrolled!(0 1 2 3 4 5 6 7 8);
        for k in 9..MAX_ORDER {
            if self.order(k, &c, &mut g) {
                return Some(k + 1);
            }
        }
        None
    }

    /// Order `k + 1` of the series [`Taylor::series`] grows: its
    /// coefficients stored and the newest values in `g` moved on; true when
    /// the tail is below the tolerance there ([`Taylor::ends`] then set from
    /// the stored coefficients, [`ends`], and the series done).
    ///
    /// Each order depends on the one before through a product and two
    /// sums (the constants multiplied out beforehand, the convolutions'
    /// older terms summed first): the chain of orders is what bounds the
    /// step's time, the rest runs beside it.
    #[inline(always)]
    fn order(&mut self, k: usize, c: &Consts, g: &mut Grow) -> bool {
        let (m, inv) = (k + 1, INV[k + 1]);
        let (y, v, e, d) = (&mut self.y, &mut self.v, &mut self.e, &mut self.d);
        // Off the chain: what does not depend on order k.
        let (c0, cs, t1) = (c.f0 * inv, c.k_sin * inv, (c.f1 * inv) * g.d_prev);
        let (se, sd) = convolutions(&d[..], &e[..], &v[..], k, 0.0);
        let ai = c.a * inv;
        let (se, sd) = (ai * se, ai * sd);
        let (cv, cd, ce) = (c.a_v0 * inv, c.a_d0 * inv, c.a_e0 * inv);
        // On the chain: order k's values, each through a product and two sums.
        let (vk, ek, dk) = (g.vk, g.ek, g.dk);
        let vm = (c0 * dk + t1) - cs * ek;
        let ym = vk * inv;
        let (em, dm) = if k > 0 {
            (-(se + cv * dk) - cd * vk, (sd + cv * ek) + ce * vk)
        } else {
            (-(cd * vk), ce * vk)
        };
        (y[m], v[m], e[m], d[m]) = (ym, vm, em, dm);
        if m <= 2 {
            g.scale_v = g.scale_v.max(vm.abs());
            g.tol_v = c.tol * g.scale_v;
        } else if m >= MIN_ORDER
            && vm.abs() + vk.abs() <= g.tol_v
            && em.abs() + ek.abs() <= c.tol_e
            && dm.abs() + dk.abs() <= c.tol_e
        {
            y[m + 1] = vm * INV[m + 1];
            let [y_end, v_end, e_end, d_end, abs_v_tail] =
                ends(&y[..], &v[..], &e[..], &d[..], m, 0.0, f64::abs);
            self.ends = Ends {
                y: y_end,
                v: v_end,
                e: e_end,
                d: d_end,
                abs_v_tail,
            };
            return true;
        }
        (g.vk, g.ek, g.d_prev, g.dk) = (vm, em, dk, dm);
        false
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

/// A step's constants, as every order of its series uses them.
pub(super) struct Consts {
    f0: f64,
    f1: f64,
    k_sin: f64,
    a: f64,
    a_v0: f64,
    a_e0: f64,
    a_d0: f64,
    tol: f64,
    tol_e: f64,
}

/// A series as it grows: the newest coefficients (`d_prev` the one before
/// `dk`), V's scale and `tol` times it (set by order 2).
pub(super) struct Grow {
    vk: f64,
    ek: f64,
    dk: f64,
    d_prev: f64,
    scale_v: f64,
    tol_v: f64,
}
