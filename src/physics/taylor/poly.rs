//! Polynomials on a step, in its own time τ ∈ [0, 1]: evaluation, sums,
//! roots (safeguarded Newton), and the turning points of a velocity
//! polynomial, every one of them, proven by bounds on Taylor shifts.

/// The most turning points kept in one step (a physical step has one or
/// two; more would be rounding noise about a double root).
pub(super) const MAX_TURNS: usize = 8;

/// `Σ c_k t^k` by Horner's rule on its even and odd terms at once (in
/// `t²`, joined at the end): half of Horner's chain of dependent products
/// and sums, which is what an evaluation's time is on these short
/// polynomials; rounded, as Horner's, within a few ulps of `Σ |c_k| t^k`.
#[inline]
pub(super) fn poly(c: &[f64], t: f64) -> f64 {
    let t2 = t * t;
    let pairs = c.chunks_exact(2);
    // An odd count: the last term is the even part's highest.
    let mut even = pairs.remainder().first().copied().unwrap_or(0.0);
    let mut odd = 0.0;
    for pair in pairs.rev() {
        even = even * t2 + pair[0];
        odd = odd * t2 + pair[1];
    }
    even + odd * t
}

/// `Σ c_k t^k`, its derivative and `Σ |c_k| t^k` (for `t ≥ 0`), each as
/// [`poly`] evaluates it.
#[inline]
fn poly_d(c: &[f64], t: f64) -> (f64, f64, f64) {
    let t2 = t * t;
    let pairs = c.chunks_exact(2);
    let top = pairs.remainder().first().copied().unwrap_or(0.0);
    let (mut even, mut odd, mut m_even, mut m_odd) = (top, 0.0, top.abs(), 0.0);
    // The derivative's terms k c_k t^{k−1}: odd powers from even k.
    let n = c.len();
    let (mut d_even, mut d_odd) = if n % 2 == 1 && n > 1 {
        (0.0, (n - 1) as f64 * top)
    } else {
        (0.0, 0.0)
    };
    for (i, pair) in pairs.enumerate().rev() {
        let k = 2 * i;
        even = even * t2 + pair[0];
        odd = odd * t2 + pair[1];
        m_even = m_even * t2 + pair[0].abs();
        m_odd = m_odd * t2 + pair[1].abs();
        // k c_k t^{k−1} (odd power, k even, none for k = 0) and
        // (k+1) c_{k+1} t^k (even power).
        d_even = d_even * t2 + (k + 1) as f64 * pair[1];
        if k > 0 {
            d_odd = d_odd * t2 + k as f64 * pair[0];
        }
    }
    (even + odd * t, d_even + d_odd * t, m_even + m_odd * t)
}

/// The root of the polynomial `c` in `(lo, hi]`, where `c(lo)` and `f_hi`
/// (its value at `hi` as the caller found it, the value that decided there
/// is an event: not evaluated again) have opposite signs (or `f_hi = 0`,
/// the root `hi`): Newton's method from the first root
/// of the quadratic Taylor model at `lo` (the start that matters where `lo`
/// is a turning point and the root nearly double), kept inside the bracket
/// (which every step narrows; bisection when Newton leaves it), until the
/// value is below the rounding of its evaluation or a step moves it, or
/// the next step is foretold to move it, by at most `last_step` (relative;
/// a few ulps for an event's time).
pub(super) fn root(c: &[f64], lo: f64, hi: f64, f_hi: f64) -> f64 {
    root_to(c, lo, hi, f_hi, 4.0 * f64::EPSILON)
}

/// A turning point of the velocity polynomial `v` in `(lo, hi]`, as
/// [`root`] finds it, but done once a Newton step moves it by 1e-6 or less
/// (relative): the step after it would move it by about the square of
/// that, and the position there, all a turning point is used for besides
/// splitting the step, is stationary: an error δ in τ moves it by
/// `Y''δ²/2`, far below its rounding.
fn turn(v: &[f64], lo: f64, hi: f64, f_hi: f64) -> f64 {
    root_to(v, lo, hi, f_hi, 1e-6)
}

fn root_to(c: &[f64], mut lo: f64, mut hi: f64, f_hi: f64, last_step: f64) -> f64 {
    if f_hi == 0.0 {
        return hi;
    }
    let up = f_hi > 0.0;
    let mut t = quadratic_start(c, lo).map_or(f64::NAN, |d| lo + d);
    if !(t > lo && t < hi) {
        let f_lo = poly(c, lo);
        t = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        if !(t > lo && t < hi) {
            t = 0.5 * (lo + hi);
        }
    }
    // The last Newton step (NaN after a bisection): where steps shrink
    // quadratically, `e_{k+1} ≈ δ_k³/δ_{k−1}²` foretells the next one.
    let mut last = f64::NAN;
    for _ in 0..100 {
        let (f, df, m) = poly_d(c, t);
        // Below the rounding of its evaluation, f is zero.
        if f.abs() <= 4.0 * c.len() as f64 * f64::EPSILON * m {
            return t;
        }
        if (f > 0.0) == up {
            hi = t;
        } else {
            lo = t;
        }
        let mut next = t - f / df;
        let mut step = (next - t).abs();
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
            step = f64::NAN;
        }
        let done = last_step * next.abs();
        if step <= done
            || step * step * step <= done * last * last
            || hi - lo <= 4.0 * f64::EPSILON * hi
        {
            return next;
        }
        (t, last) = (next, step);
    }
    t
}

/// The smallest positive root `δ` of `c(t) + c'(t) δ + c''(t) δ²/2`, the
/// polynomial's quadratic model at `t`, if it has one.
#[inline]
fn quadratic_start(c: &[f64], t: f64) -> Option<f64> {
    let (mut p, mut dp, mut ddp) = (0.0, 0.0, 0.0);
    if t == 0.0 {
        // What the loop below gives at t = 0, to the bit: the step's start,
        // where nearly every root is sought from.
        let at = |k: usize| c.get(k).copied().unwrap_or(0.0);
        (p, dp, ddp) = (at(0), at(1), at(2));
    } else {
        for &ck in c.iter().rev() {
            ddp = ddp * t + dp;
            dp = dp * t + p;
            p = p * t + ck;
        }
    }
    let (a, b, q) = (ddp, dp, p); // q + b δ + a δ² (a is c''/2)
    let disc = b * b - 4.0 * a * q;
    if a == 0.0 || disc < 0.0 {
        return (b != 0.0 && -q / b > 0.0).then(|| -q / b);
    }
    // The two roots without cancellation.
    let r = -0.5 * (b + b.signum() * disc.sqrt());
    let (d1, d2) = (r / a, if r != 0.0 { q / r } else { f64::NAN });
    // The smaller positive one (NaN and zeros are neither).
    match (d1 > 0.0, d2 > 0.0) {
        (true, true) => Some(if d2 < d1 { d2 } else { d1 }),
        (true, false) => Some(d1),
        (false, true) => Some(d2),
        (false, false) => None,
    }
}

/// `Σ c_k`, smallest terms first.
#[inline]
pub(super) fn sum(c: &[f64]) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ck| acc + ck)
}

/// Every root of the polynomial `v` in (0, 1) where it changes sign, in
/// increasing order (at most [`MAX_TURNS`]), each to a few ulps.
///
/// On an interval of centre m and half-width r with `v(m + d) = Σ c_j d^j`,
/// there is no root if `|c_0| > Σ_{j≥1} |c_j| r^j`, and at most one (then
/// located if the signs at the ends differ) if `|c_1| > Σ_{j≥2} j |c_j|
/// r^{j−1}`, for `v` is then monotone. The whole step is tried with the
/// coefficients as they are (about τ = 0, where the first test settles
/// nearly every step); an interval that passes neither test is halved, down
/// to 2⁻²⁰ of a step (and [`MAX_HALVES`] intervals in all), where a sign
/// change at the ends decides. A root at τ = 0 (a step from rest) is
/// divided out first; a polynomial that is not finite has none.
pub(super) fn turning_points(v: &[f64], out: &mut Turns) {
    // A step from rest starts at a root of V (τ = 0, not inside the step):
    // its roots in (0, 1) are those of V/τ.
    let mut v = v;
    while v.len() > 1 && v[0] == 0.0 {
        v = &v[1..];
    }
    if !v.iter().all(|c| c.is_finite()) {
        return;
    }
    let tail = |from: usize, weight: fn(usize) -> f64| {
        v[from..]
            .iter()
            .enumerate()
            .map(|(i, c)| weight(i + from) * c.abs())
            .sum::<f64>()
    };
    if v[0].abs() > tail(1, |_| 1.0) {
        return;
    }
    if v.len() < 2 || v[1].abs() > tail(2, |j| j as f64) {
        crossing(v, 0.0, 1.0, poly(v, 0.0), poly(v, 1.0), out);
        return;
    }
    let mut budget = MAX_HALVES;
    halves(v, 0.0, 1.0, poly(v, 0.0), poly(v, 1.0), 0, &mut budget, out);
}

/// The most intervals [`turning_points`] examines in one step: each root
/// needs about 20 on its way down, and a step has one or two.
const MAX_HALVES: u32 = 256;

/// The turning points found so far, in order.
#[derive(Default)]
pub(super) struct Turns {
    pub at: [f64; MAX_TURNS],
    pub len: usize,
}

impl Turns {
    fn push(&mut self, t: f64) {
        if self.len < MAX_TURNS {
            self.at[self.len] = t;
            self.len += 1;
        }
    }

    pub fn as_slice(&self) -> &[f64] {
        &self.at[..self.len]
    }
}

/// A root in (a, b) if `v` changes sign between the ends.
fn crossing(v: &[f64], a: f64, b: f64, va: f64, vb: f64, out: &mut Turns) {
    if (va > 0.0 && vb < 0.0) || (va < 0.0 && vb > 0.0) {
        let t = turn(v, a, b, vb);
        if t > a && t < b {
            out.push(t);
        }
    }
}

/// [`turning_points`] on [a, b] by the tests on its Taylor shift, halving.
#[allow(clippy::too_many_arguments)]
fn halves(
    v: &[f64],
    a: f64,
    b: f64,
    va: f64,
    vb: f64,
    depth: u32,
    budget: &mut u32,
    out: &mut Turns,
) {
    *budget = budget.saturating_sub(1);
    let (m, r) = (0.5 * (a + b), 0.5 * (b - a));
    let mut c = [0.0; 32];
    let c = shifted(v, m, &mut c[..v.len()]);
    let (mut tail0, mut tail1, mut rj) = (0.0, 0.0, 1.0);
    for (j, cj) in c.iter().enumerate().skip(1) {
        // rj = r^{j−1}
        tail0 += cj.abs() * rj * r;
        if j >= 2 {
            tail1 += j as f64 * cj.abs() * rj;
        }
        rj *= r;
    }
    if c[0].abs() > tail0 {
        return;
    }
    if c[1].abs() > tail1 || depth >= 20 || *budget == 0 {
        crossing(v, a, b, va, vb, out);
        return;
    }
    let vm = c[0];
    halves(v, a, m, va, vm, depth + 1, budget, out);
    if vm == 0.0 && m > a {
        out.push(m);
    }
    halves(v, m, b, vm, vb, depth + 1, budget, out);
}

/// The coefficients of `v(m + d)` in powers of d (repeated synthetic division).
fn shifted<'a>(v: &[f64], m: f64, c: &'a mut [f64]) -> &'a [f64] {
    c.copy_from_slice(v);
    let n = c.len();
    for i in 0..n {
        for k in (i..n - 1).rev() {
            c[k] += m * c[k + 1];
        }
    }
    c
}

/// The impact of a hop, if the step (Y's coefficients `y`, its end
/// `y_end`) is one that is proven simple: from the pivot (`Y_0 = 0`) up
/// (`Y_1 > 0`) and back to it or below by the step's end, with `Z = Y/τ`
/// decreasing on [0, 1] (`−Z_1 > Σ_{k≥2} k |Z_k|`, so `Z' < 0` there) and
/// `Z(0) = Y_1` no higher than `top` (the largest `y` met before) and below
/// `limit`. Then Z has one root in (0, 1], the impact; before it `0 < Y =
/// τZ ≤ Z(0)`, so the step neither overturns nor raises `top`: the turning
/// point [`Taylor::event`] would locate changes nothing, and the impact is
/// the root of Z, found from Z's quadratic model at τ = 0 (its first three
/// coefficients, nothing evaluated). Most impacts are such hops: after an
/// impact the block lifts off the other corner and the forcing brings it
/// back within the interval (a Zeno sequence, docs/MODEL.md §3).
#[inline]
pub(super) fn hop(y: &[f64], y_end: f64, top: f64, limit: f64) -> Option<f64> {
    // NaN fails every test, as it should.
    let from_pivot_back = y.len() >= 3 && y[0] == 0.0 && y[1] > 0.0 && y_end <= 0.0;
    if !from_pivot_back {
        return None;
    }
    let z = &y[1..];
    let mut slope_tail = 0.0;
    for (k, zk) in z.iter().enumerate().skip(2) {
        slope_tail += k as f64 * zk.abs();
    }
    // Widened by far more than the rounding of the sum (a few ulps of it).
    let decreasing = -z[1] > slope_tail * (1.0 + 1e-9);
    let low = z[0] * (1.0 + 1e-9) <= top && z[0] < limit;
    (decreasing && low).then(|| root(z, 0.0, 1.0, y_end))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The step that made the one-turning-point rule miss an impact: V > 0 at
    /// both ends of the step, negative between.
    #[test]
    fn two_turning_points_with_one_sign_at_both_ends_are_found() {
        // v(τ) = 3(τ − 0.2)(τ − 0.7) + small: roots near 0.2 and 0.7.
        let v = [0.42, -2.7, 3.0];
        let mut turns = Turns::default();
        turning_points(&v, &mut turns);
        let roots = turns.as_slice();
        assert_eq!(roots.len(), 2, "{roots:?}");
        assert!(
            (roots[0] - 0.2).abs() < 1e-15 && (roots[1] - 0.7).abs() < 1e-15,
            "{roots:?}"
        );
    }

    #[test]
    fn shifts_agree_with_evaluation() {
        let v = [0.3, -1.2, 0.7, 0.25, -0.125];
        let mut buf = [0.0; 5];
        let c = shifted(&v, 0.4, &mut buf);
        for d in [-0.3, 0.0, 0.2, 0.55] {
            assert!((poly(c, d) - poly(&v, 0.4 + d)).abs() < 1e-15);
        }
    }

    #[test]
    fn a_velocity_without_a_root_has_no_turning_point() {
        let mut turns = Turns::default();
        turning_points(&[1.0, -0.4, 0.3], &mut turns);
        assert!(turns.as_slice().is_empty());
        // Near-double root that does not cross: (τ − 0.5)² + 1e-9.
        turning_points(&[0.25 + 1e-9, -1.0, 1.0], &mut turns);
        assert!(turns.as_slice().is_empty(), "{:?}", turns.as_slice());
    }

    #[test]
    fn newton_finds_roots_to_ulps() {
        // (τ − 1/3)(τ + 2) = τ² + 5τ/3 − 2/3
        let r = root(
            &[-2.0 / 3.0, 5.0 / 3.0, 1.0],
            0.0,
            1.0,
            1.0 + 5.0 / 3.0 - 2.0 / 3.0,
        );
        assert!((r - 1.0 / 3.0).abs() <= 2.0 * f64::EPSILON, "{r}");
    }
}
