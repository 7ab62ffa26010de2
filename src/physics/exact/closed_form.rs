//! The closed form of the linearised equation on one pivot over a stretch
//! with linear forcing ([`Motion`]), the functions of `z = pσ` it needs
//! ([`Coeffs`], [`cosh_m1`], [`sinhc_m1`]) and its turning points.
//! Derivation: docs/MODEL.md, §3.1–3.2.

use crate::physics::lanes::Lane;

/// `cosh z − 1`, without cancellation: `z²/2 · (1 + z²/12 + …)`, its
/// Taylor series to z¹⁴ for |z| < 0.5 (to z⁶ below |z| = 0.01, where the
/// first dropped term is below 2⁻⁵³ of the sum), `2 sinh²(z/2)` above.
/// The bracket is a polynomial in z² with reciprocal constants: no division
/// on the events' path.
#[inline(always)]
pub fn cosh_m1(z: f64) -> f64 {
    let z2 = z * z;
    if z2 < 1e-4 {
        0.5 * z2 * (1.0 + z2 * (1.0 / 12.0 + z2 * (1.0 / 360.0)))
    } else if z2 < 0.25 {
        0.5 * z2
            * (1.0
                + z2 * (1.0 / 12.0
                    + z2 * (1.0 / 360.0
                        + z2 * (1.0 / 20_160.0
                            + z2 * (1.0 / 1_814_400.0
                                + z2 * (1.0 / 239_500_800.0 + z2 * (1.0 / 43_589_145_600.0)))))))
    } else {
        let h = (0.5 * z).sinh();
        2.0 * h * h
    }
}

/// `sinh(z)/z − 1`: `z²/6 · (1 + z²/20 + …)`, its Taylor series to z¹⁴ for
/// |z| < 0.5 (to z⁶ below |z| = 0.01; the first dropped term is below 2⁻⁵³
/// of the sum), directly above. One division (z²/6, exactly rounded), off
/// the polynomial's dependency chain.
#[inline(always)]
pub fn sinhc_m1(z: f64) -> f64 {
    let z2 = z * z;
    if z2 < 1e-4 {
        z2 / 6.0 * (1.0 + z2 * (1.0 / 20.0 + z2 * (1.0 / 840.0)))
    } else if z2 < 0.25 {
        z2 / 6.0
            * (1.0
                + z2 * (1.0 / 20.0
                    + z2 * (1.0 / 840.0
                        + z2 * (1.0 / 60_480.0
                            + z2 * (1.0 / 6_652_800.0
                                + z2 * (1.0 / 1_037_836_800.0 + z2 * (1.0 / 217_945_728_000.0)))))))
    } else {
        z.sinh() / z - 1.0
    }
}

/// The functions of `z = pσ` the step needs (in every lane of `T`: one
/// stretch's for runs in step).
#[derive(Debug, Clone, Copy)]
pub(super) struct Coeffs<T = f64> {
    pub(super) sigma: T,
    pub(super) sinh: T,
    /// cosh z − 1
    pub(super) c: T,
    /// σ·sinh(z)/z = sinh(z)/p
    pub(super) s_sigma: T,
    /// σ·(sinh(z)/z − 1)
    pub(super) s1_sigma: T,
}

impl Coeffs {
    /// The same coefficients in every lane of `T`.
    #[inline(always)]
    pub(super) fn splat<T: Lane>(&self) -> Coeffs<T> {
        Coeffs {
            sigma: T::splat(self.sigma),
            sinh: T::splat(self.sinh),
            c: T::splat(self.c),
            s_sigma: T::splat(self.s_sigma),
            s1_sigma: T::splat(self.s1_sigma),
        }
    }

    #[inline(always)]
    pub(super) fn new(p: f64, sigma: f64) -> Self {
        // Below |z| = 0.5 (every sample interval up to p·dt = 0.5) these are
        // polynomials: no transcendental call in the hot loop.
        let z = p * sigma;
        let s1 = sinhc_m1(z);
        Coeffs {
            sigma,
            sinh: z + z * s1,
            c: cosh_m1(z),
            s_sigma: sigma + sigma * s1,
            s1_sigma: sigma * s1,
        }
    }
}

/// The motion on one stretch, evaluable at any σ; written once for any
/// number of runs in step (`T` a [`Lane`]: `f64` for one run).
#[derive(Debug, Clone, Copy)]
pub(super) struct Motion<T = f64> {
    pub(super) p: T,
    pub(super) x_a: T,
    pub(super) v_a: T,
    /// u = x_a − s + g_a/η
    pub(super) u: T,
    /// g1/η
    pub(super) g1e: T,
}

impl<T: Lane> Motion<T> {
    /// The motion on pivot `s` from `(x, v)` under the forcing `g_a + g1·σ`,
    /// for a block of frequency parameter `p` at `s·η` and `1/η`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(p: T, s_eta: T, inv_eta: T, x: T, v: T, g_a: T, g1: T) -> Motion<T> {
        Motion {
            p,
            x_a: x,
            v_a: v,
            u: x + (g_a - s_eta) * inv_eta,
            g1e: g1 * inv_eta,
        }
    }

    /// `(x, v)` at the end of a stretch of `c.sigma`.
    #[inline(always)]
    pub(super) fn at(&self, c: &Coeffs<T>) -> (T, T) {
        let x = self.x_a + self.u * c.c + self.v_a * c.s_sigma + self.g1e * c.s1_sigma;
        let v = self.v_a + self.p * self.u * c.sinh + (self.v_a + self.g1e) * c.c;
        (x, v)
    }
}

impl Motion {
    /// The size of the largest term of x(σ): the scale of its rounding error.
    #[inline(always)]
    pub(super) fn scale(&self, c: &Coeffs) -> f64 {
        self.x_a.abs()
            + (self.u * c.c).abs()
            + (self.v_a * c.s_sigma).abs()
            + (self.g1e * c.s1_sigma).abs()
    }

    /// Acceleration at σ given x(σ): p²(x − s + ψ̈(σ)/η).
    #[inline(always)]
    pub(super) fn acc(&self, x: f64, sigma: f64) -> f64 {
        self.p * self.p * (x - self.x_a + self.u + self.g1e * sigma)
    }

    /// Turning points (v = 0) with 0 < σ < len, ascending.
    /// `delta_max = e^{p·len} − 1` bounds δ, so roots outside the stretch
    /// cost no logarithm.
    #[inline(always)]
    pub(super) fn turning_points(&self, len: f64, delta_max: f64) -> ([f64; 2], usize) {
        let b = self.p * self.u + self.v_a;
        let a = b + self.g1e;
        let c = 2.0 * self.v_a;
        let mut roots = [f64::NAN; 2];
        let mut n = 0;
        let mut push = |delta: f64| {
            if delta > 0.0 && delta < delta_max {
                let sigma = delta.ln_1p() / self.p;
                if sigma > 0.0 && sigma < len {
                    roots[n] = sigma;
                    n += 1;
                }
            }
        };
        if a == 0.0 {
            if b != 0.0 {
                push(-c / (2.0 * b));
            }
        } else {
            let disc = b * b - a * c;
            if disc >= 0.0 {
                // a δ² + 2b δ + c = 0, the stable pair of formulas.
                let q = -(b + b.signum() * disc.sqrt());
                if q != 0.0 {
                    push(q / a);
                    push(c / q);
                } else {
                    // b = 0 and disc = 0: c = 0 too, a double root at δ = 0.
                }
            }
        }
        if n == 2 && roots[0] > roots[1] {
            roots.swap(0, 1);
        }
        (roots, n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::exact::Exact;

    #[test]
    fn special_functions_keep_relative_precision() {
        // Against their Taylor series, truncated where the next term is below
        // 1e-17 relative for these z: cosh z − 1 = z²/2 (1 + z²/12 + z⁴/360 + z⁶/20160),
        // sinh z / z − 1 = z²/6 (1 + z²/20 + z⁴/840 + z⁶/60480).
        for z in [1e-12f64, 1e-8, 1e-4, 1e-2] {
            let z2 = z * z;
            let c_ref = z2 / 2.0 * (1.0 + z2 / 12.0 * (1.0 + z2 / 30.0 * (1.0 + z2 / 56.0)));
            let s_ref = z2 / 6.0 * (1.0 + z2 / 20.0 * (1.0 + z2 / 42.0 * (1.0 + z2 / 72.0)));
            assert!((cosh_m1(z) / c_ref - 1.0).abs() < 4e-16, "{z}");
            assert!((sinhc_m1(z) / s_ref - 1.0).abs() < 4e-16, "{z}");
        }
        // The series branch agrees with the direct formula where they meet
        // (the direct one is accurate there: it loses only 1 − 1/1.04 of a digit).
        for z in [0.49999f64, 0.3, 0.1] {
            let direct = z.sinh() / z - 1.0;
            assert!((sinhc_m1(z) - direct).abs() < 1e-14, "{z}");
        }
    }

    /// One step against a fine RK4 integration of the same ODE (an
    /// independent method): the closed form must agree to RK4's own error.
    #[test]
    fn step_matches_numerical_integration() {
        let (p, eta, s) = (2.5, 0.3, -1.0);
        let (x0, v0, g_a, g1) = (-0.2, 0.7, -0.25, 8.0);
        let len = 0.05;
        let lin = Exact::new(p, eta, len, 1.0);
        let m = Motion {
            p,
            x_a: x0,
            v_a: v0,
            u: x0 + (g_a - s * eta) / eta,
            g1e: g1 / eta,
        };
        let (x, v) = m.at(&lin.full);
        let f = |t: f64, x: f64| p * p * (x - s) + p * p / eta * (g_a + g1 * t);
        let (mut xr, mut vr) = (x0, v0);
        let n = 20000;
        let h = len / n as f64;
        for i in 0..n {
            let t = i as f64 * h;
            let (k1x, k1v) = (vr, f(t, xr));
            let (k2x, k2v) = (vr + 0.5 * h * k1v, f(t + 0.5 * h, xr + 0.5 * h * k1x));
            let (k3x, k3v) = (vr + 0.5 * h * k2v, f(t + 0.5 * h, xr + 0.5 * h * k2x));
            let (k4x, k4v) = (vr + h * k3v, f(t + h, xr + h * k3x));
            xr += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            vr += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        }
        // RK4 with h = 2.5e-6 s: truncation ~ (ph)⁴ ≈ 1e-21 per step; rounding dominates (~1e-13).
        assert!((x - xr).abs() < 1e-12, "{x} vs {xr}");
        assert!((v - vr).abs() < 1e-11, "{v} vs {vr}");
    }

    #[test]
    fn tiny_motions_keep_relative_precision() {
        // Just past uplift: x_a = v_a = 0, forcing exactly at the threshold
        // and rising. x(σ) ≈ (g1/η) p² σ³/6 to leading order.
        let (p, eta) = (3.0, 0.5);
        let g1 = 1e-12 / 0.01; // a 1e-12 excess over one 0.01 s interval
        let m = Motion {
            p,
            x_a: 0.0,
            v_a: 0.0,
            u: 0.0,
            g1e: g1 / eta,
        };
        let sigma = 0.01;
        let (x, v) = m.at(&Coeffs::new(p, sigma));
        let z: f64 = p * sigma;
        let x_ref = g1 / eta * sigma * (z.sinh() / z - 1.0); // exact; here z²/6 dominates
        let x_series = g1 / eta * sigma * z * z / 6.0
            * (1.0 + z * z / 20.0 + z.powi(4) / 840.0 + z.powi(6) / 60480.0);
        assert!(x > 0.0);
        assert!(
            (x / x_series - 1.0).abs() < 1e-14,
            "{x} vs {x_series} (naive {x_ref})"
        );
        let v_series =
            g1 / eta * z * z / 2.0 * (1.0 + z * z / 12.0 + z.powi(4) / 360.0 + z.powi(6) / 20160.0);
        assert!((v / v_series - 1.0).abs() < 1e-14, "{v} vs {v_series}");
    }

    #[test]
    fn turning_points_are_where_velocity_vanishes() {
        let (p, eta, s) = (4.0, 0.4, 1.0);
        // Moving out, decelerating: one maximum inside.
        let m = Motion {
            p,
            x_a: 0.1,
            v_a: 0.5,
            u: 0.1 + (0.1 - s * eta) / eta,
            g1e: -3.0 / eta,
        };
        let (t, n) = m.turning_points(1.0, 4.0f64.exp_m1());
        assert_eq!(n, 1);
        let (_, v) = m.at(&Coeffs::new(p, t[0]));
        assert!(v.abs() < 1e-14, "{v}");
    }
}
