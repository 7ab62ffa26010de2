//! The Zeno hops in closed form: a small hop after an impact, its return to
//! the pivot by a double series or by Newton on its Taylor terms.
//! Derivation: docs/MODEL.md, §3.3.

use super::closed_form::Motion;
use super::stepper::Exact;

/// The largest expansion parameter of a hop solved by its Taylor series:
/// `z = pσ` and the relative change of the forcing over the hop. At 1e-2,
/// the series through y⁽⁸⁾ leaves a remainder below 1e-18 of the motion
/// (its last term kept is 5e-17 of it).
const HOP_Z: f64 = 1e-2;

/// Up to this size of a hop's expansion parameters (`max(z², |bσ/|a||)`),
/// its return time and speed are their series to fifth order in them;
/// above it, two Newton steps from the second-order guess (see
/// [`Exact::hop`]).
const HOP_SERIES: f64 = 2e-3;

impl Exact {
    /// A small hop after an impact, in closed form: from `x = 0` with the
    /// block moving out on pivot `s` against a restoring forcing, the return
    /// to `x = 0` (σ, and the velocity there), when it lies inside the
    /// stretch and its apex provably stays below `max_abs_x` (so nothing
    /// else can happen on the way). `None` leaves the stretch to the
    /// general walk.
    ///
    /// The return time and speed come from the hop's Taylor terms: a
    /// double series in its two small parameters ([`hop_series`]) or two
    /// Newton steps on them ([`hop_newton`]). Derivation: docs/MODEL.md, §3.3.
    ///
    /// About two thirds of the impacts of a sweep are such hops; the general
    /// walk costs several closed-form evaluations, a square root and a
    /// logarithm each.
    #[inline(always)]
    pub(super) fn hop(&self, m: &Motion, s: f64, len: f64, max_abs_x: f64) -> Option<(f64, f64)> {
        let w = s * m.v_a;
        if !(m.x_a == 0.0 && w > 0.0) {
            return None;
        }
        let p2 = self.p * self.p;
        let a = p2 * s * m.u;
        let b = p2 * s * m.g1e;
        if a.is_nan() || a >= 0.0 {
            return None;
        }
        let r = 1.0 / a;
        let sigma0 = -2.0 * w * r;
        let beta = -(b * r) * sigma0;
        let z0 = self.p * sigma0;
        // On the hop ÿ ≤ a(1 − HOP_Z) + p²·y_max, so the apex is below
        // w²/(2|a|)·(1 + 4·HOP_Z) (the p²y part is z²/8 of a): it must stay
        // below max_abs_x.
        if !(z0 <= HOP_Z
            && beta.abs() <= HOP_Z
            && w * w * (1.0 + 4.0 * HOP_Z) < max_abs_x * (-2.0 * a))
        {
            return None;
        }
        let q = z0 * z0;
        let (t, v_ratio) = if q.max(beta.abs()) <= HOP_SERIES {
            hop_series(q, beta)
        } else {
            hop_newton(q, beta)
        };
        let sigma = sigma0 * t;
        if !(sigma > 0.0 && sigma < len) {
            return None;
        }
        Some((sigma, -s * w * v_ratio))
    }
}

/// A hop's return time `T = σ/σ₀` and speed ratio `V` to fifth order in
/// `q` and `β` (docs/MODEL.md, §3.3): `Σ βʲ·Pⱼ(q)`, the `Pⱼ` independent of
/// each other and `β`'s powers paired, so that few operations depend on
/// one another. As `q = z² ≤ HOP_Z² = 1e-4` on a hop, the terms of `q⁴`
/// and `q³β²` and beyond (below 1e-19) are left out.
#[inline(always)]
fn hop_series(q: f64, beta: f64) -> (f64, f64) {
    let t0 = 1.0 + q * (1.0 / 12.0 + q * (1.0 / 80.0 + q * (1.0 / 448.0)));
    let t1 = 1.0 / 3.0 + q * (1.0 / 10.0 + q * (3.0 / 112.0 + q * (1.0 / 144.0)));
    let t2 = 2.0 / 9.0 + q * (7.0 / 60.0 + q * (47.0 / 1050.0));
    let t3 = 5.0 / 27.0 + q * (56.0 / 405.0 + q * (173.0 / 2520.0));
    let t4 = 14.0 / 81.0 + q * (1.0 / 6.0);
    let t5 = 14.0 / 81.0;
    let v1 = -1.0 / 3.0 - q * (1.0 / 20.0 + q * (1.0 / 112.0 + q * (1.0 / 576.0)));
    let v2 = -2.0 / 9.0 - q * (7.0 / 90.0 + q * (47.0 / 2100.0));
    let v3 = -5.0 / 27.0 - q * (14.0 / 135.0 + q * (173.0 / 4200.0));
    let v4 = -14.0 / 81.0 - q * (2.0 / 15.0);
    let v5 = -14.0 / 81.0;
    let b2 = beta * beta;
    let t = t0 + beta * ((t1 + beta * t2) + b2 * ((t3 + beta * t4) + b2 * t5));
    let v = 1.0 + beta * ((v1 + beta * v2) + b2 * ((v3 + beta * v4) + b2 * v5));
    (t, v)
}

/// A hop's `T` and `V` by two Newton steps on its Taylor terms through
/// y⁽⁸⁾ (docs/MODEL.md, §3.3), for `max(q, |β|)` up to [`HOP_Z`].
#[inline(always)]
fn hop_newton(q: f64, beta: f64) -> (f64, f64) {
    let c = q * (1.0 / 6.0) + beta * (1.0 / 3.0);
    let q12 = q * (1.0 / 12.0);
    let d1 = c - q12;
    let mut t =
        1.0 + (d1 + d1 * (2.0 * c - 0.25 * q) + c * q * (1.0 / 20.0) - q * q * (1.0 / 360.0));
    for _ in 0..2 {
        let t2 = t * t;
        let u = q * t2;
        let f = (1.0 - t)
            + t2 * (c * (1.0 + u * (1.0 / 20.0 + u * (1.0 / 840.0)))
                - q12 * t * (1.0 + u * (1.0 / 30.0 + u * (1.0 / 1680.0))));
        let df = -1.0 + 2.0 * c * t * (1.0 + u * (1.0 / 10.0 + u * (1.0 / 280.0)))
            - q12 * t2 * (3.0 + u * (1.0 / 6.0 + u * (1.0 / 240.0)));
        t -= f / df;
    }
    let t2 = t * t;
    let u = q * t2;
    let ydot_w = (1.0 - 2.0 * t)
        + (3.0 * c * t2 * (1.0 + u * (1.0 / 12.0 + u * (1.0 / 360.0)))
            - 4.0 * q12 * t2 * t * (1.0 + u * (1.0 / 20.0 + u * (1.0 / 840.0))));
    (t, -ydot_w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::step::{Rocking, Stepper, Stretch, StretchEnd};

    /// A hop solved by its series against the general walk (the closed form,
    /// turning point and safeguarded Newton), from hops near the series'
    /// limit (where a wrong low-order coefficient would show at z² ≈ 1e-6)
    /// down to the rest tolerance.
    #[test]
    fn hops_by_series_match_the_general_walk() {
        let mut solved = 0;
        for p in [0.5, 2.0, 8.0] {
            for eta in [0.2, 0.6] {
                for s in [1.0, -1.0] {
                    for g_rel in [-0.9, 0.0, 0.7] {
                        for g1 in [0.0, 0.3, -2.0] {
                            for w_rel in [2e-3, 4e-4, 1e-5, 1e-9] {
                                let (g_a, w) = (s * g_rel * eta, w_rel * p);
                                let lin = Exact::new(p, eta, 0.02, 1.0);
                                let m = Motion {
                                    p,
                                    x_a: 0.0,
                                    v_a: s * w,
                                    u: (g_a - s * eta) / eta,
                                    g1e: g1 / eta,
                                };
                                let Some((sigma, v)) = lin.hop(&m, s, 0.015, 1.0) else {
                                    continue;
                                };
                                solved += 1;
                                let mut st = Rocking {
                                    x: 0.0,
                                    v: s * w,
                                    s,
                                };
                                // max |x| = 0: the series refuses, the general walk runs.
                                let stretch = Stretch {
                                    tau0: 0.005,
                                    len: 0.015,
                                    g_a,
                                    g1,
                                };
                                let StretchEnd::Impact {
                                    sigma: s_ref,
                                    v: v_ref,
                                } = lin.clone().rock(stretch, &mut st, &mut 0.0)
                                else {
                                    panic!("no impact: p {p} η {eta} g {g_a} g1 {g1} w {w}");
                                };
                                let case = format!("p {p} η {eta} s {s} g {g_a} g1 {g1} w {w}");
                                assert!(
                                    (sigma / s_ref - 1.0).abs() < 1e-13,
                                    "{case}: σ {sigma} vs {s_ref}"
                                );
                                assert!(
                                    (v / v_ref - 1.0).abs() < 1e-13,
                                    "{case}: v {v} vs {v_ref}"
                                );
                            }
                        }
                    }
                }
            }
        }
        assert!(solved > 100, "only {solved} hops solved by series");
    }

    /// Hops against the closed-form solution of `ÿ = p²y + a + bσ` from
    /// `y = 0, ẏ = w`, `y = (w/p)·sinh pσ + (a/p²)(cosh pσ − 1) + (b/p³)(sinh pσ − pσ)`,
    /// whose return to `y = 0` and speed there were solved with mpmath at
    /// 40 digits (an independent method): to a few ulps, by the series
    /// (`e` up to [`HOP_SERIES`], near its edge with both `q` and `β` of
    /// either sign) and by Newton, on both pivots.
    #[test]
    #[allow(clippy::excessive_precision)] // mpmath's 20 digits, as printed
    fn hops_match_the_closed_form_to_rounding() {
        // p, s, v_a, u, g1e; then σ and v at the return (mpmath).
        let cases: [(f64, f64, f64, f64, f64, f64, f64); 5] = [
            (
                2.0,
                1.0,
                0.004,
                -0.75,
                0.5,
                0.002_668_255_123_772_262_9,
                -0.003_997_626_805_991_231_4,
            ),
            (
                2.0,
                -1.0,
                -0.007,
                0.75,
                -1.0,
                0.004_676_420_170_177_663_6,
                0.006_985_420_750_850_105_4,
            ),
            (
                0.5,
                1.0,
                1e-9,
                -0.9,
                -3.0,
                8.888_888_801_097_395_8e-9,
                -1.000_000_009_876_543_1e-9,
            ),
            (
                8.0,
                -1.0,
                -0.02,
                0.6,
                5.0,
                0.001_038_675_868_378_032,
                0.020_057_538_470_295_825,
            ),
            // q = 9.0e-5, β = −1.9e-3: the series' fifth-order terms count.
            (
                8.0,
                1.0,
                0.0228,
                -0.6,
                -0.96,
                0.001_186_757_778_592_257_873_6,
                -0.022_814_421_933_150_636_78,
            ),
        ];
        let mut newton = 0;
        for (p, s, v_a, u, g1e, sigma_ref, v_ref) in cases {
            let lin = Exact::new(p, 0.5, 0.02, 1.0);
            let m = Motion {
                p,
                x_a: 0.0,
                v_a,
                u,
                g1e,
            };
            let (sigma, v) = lin.hop(&m, s, 0.02, 1.0).expect("a hop");
            assert!(
                (sigma / sigma_ref - 1.0).abs() < 1e-15,
                "p {p}: σ {sigma} vs {sigma_ref}"
            );
            assert!((v / v_ref - 1.0).abs() < 2e-15, "p {p}: v {v} vs {v_ref}");
            let sigma0 = 2.0 * v_a.abs() / (p * p * u.abs());
            let e = (p * sigma0).powi(2).max((g1e / u * sigma0).abs());
            newton += usize::from(e > HOP_SERIES);
        }
        assert_eq!(newton, 2, "both branches are exercised");
    }

    /// The hop's two solutions, the double series and Newton on the Taylor
    /// terms (derived separately), agree to rounding wherever the series
    /// is used (`q ≤ HOP_Z²`, `|β| ≤ HOP_SERIES`): a fifth-order
    /// coefficient wrong by 10 % would show at its edges (0.17·β⁵ = 5e-15
    /// there).
    #[test]
    fn hop_series_agrees_with_newton_where_it_is_used() {
        let steps = [-1.0, -0.7, -0.3, -1e-2, 0.0, 1e-3, 0.2, 0.5, 0.9, 1.0];
        for fq in steps.iter().map(|f: &f64| f.abs()) {
            for fb in steps {
                let (q, beta) = (fq * HOP_Z * HOP_Z, fb * HOP_SERIES);
                let (t, v) = hop_series(q, beta);
                let (t_n, v_n) = hop_newton(q, beta);
                assert!((t - t_n).abs() <= 4e-16, "q {q} β {beta}: T {t} vs {t_n}");
                assert!((v - v_n).abs() <= 4e-16, "q {q} β {beta}: V {v} vs {v_n}");
            }
        }
    }
}
