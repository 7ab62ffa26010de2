//! The Zeno hops of the exact stepper in closed form: a small hop after an
//! impact returns to the pivot as `ÿ = p²y + a + bσ` says
//! ([`crate::physics::hop`]). Derivation: docs/MODEL.md, §3.3.

use super::closed_form::Motion;
use super::stepper::Exact;
use crate::physics::hop::hop_return;

impl Exact {
    /// A small hop after an impact, in closed form: from `x = 0` with the
    /// block moving out on pivot `s` against a restoring forcing, the return
    /// to `x = 0` (σ, and the velocity there), when it lies inside the
    /// stretch and its apex provably stays below `max_abs_x` (so nothing
    /// else can happen on the way). `None` leaves the stretch to the
    /// general walk. The return is that of `ÿ = p²y + a + bσ`
    /// ([`hop_return`]), which is this equation's motion.
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
        let hop = hop_return(self.p, w, p2 * s * m.u, p2 * s * m.g1e, len, max_abs_x)?;
        Some((hop.sigma, -s * w * hop.v_ratio))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::hop::HOP_SERIES;
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
}
