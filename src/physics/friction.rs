//! A rigid block on a rigid base with Coulomb friction (docs/MODEL.md §21):
//! the contact forces of each mode, the accelerations of the mode where the
//! pivot slips, the mode a block takes from rest, and the flat slide over a
//! stretch in closed form. Pure mechanics, no integrator.
//!
//! Coordinates: the rocking state `x = θ/α` on pivot `s` as the rocking
//! model has it, the base's position `u` (m, relative to the ground; the
//! base's centre, so an impact does not move it) and its velocity `w`
//! (m/s). The ground's inertial force per mass is `a = A·ψ̈` with
//! `A = αg/η` (m/s²), in the direction that tips the block onto `s = +1`.
//! With `φ = α(1 − s x)` the angle of the line from the pivot to the centre
//! from the vertical, `R = 3g/(4p²)`, and per unit mass (Shenton 1996):
//!
//! ```text
//! rock (pivot held):   θ̈ = p²(−s sin φ + (a/g) cos φ)
//!                      F = R s sin φ θ̇² + R cos φ θ̈ − a   (friction on the block, +X)
//!                      N = g − R cos φ θ̇² + s R sin φ θ̈
//! slide-rock (pivot slips towards σ, F = −μₖσN):
//!                      k = s sin φ − μₖσ cos φ
//!                      θ̈ = −k (g − R cos φ θ̇²) / (R (1/3 + k s sin φ))
//!                      ẅ = a − μₖσN − R (s sin φ θ̇² + cos φ θ̈)
//! slide (flat):        ẇ = a − μₖσg
//! ```

use super::PhysicsError;
pub use crate::block::{G, MU_MAX};

/// Coulomb friction of the base: static `mu_s`, kinetic `mu_k ≤ mu_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Friction {
    pub mu_s: f64,
    pub mu_k: f64,
}

impl Friction {
    /// One coefficient for both.
    pub fn new(mu: f64) -> Friction {
        Friction { mu_s: mu, mu_k: mu }
    }

    /// Checks `0 < μₖ ≤ μₛ ≤` [`MU_MAX`].
    pub fn validate(self) -> Result<(), PhysicsError> {
        let Friction { mu_s, mu_k } = self;
        if !(mu_s > 0.0 && mu_s <= MU_MAX) {
            return Err(PhysicsError::BadInput(format!(
                "static friction μ = {mu_s} must be in (0, {MU_MAX}]: above it the sliding \
                 pivot's equations lose uniqueness (Painlevé), and such a base never lets a \
                 block slide"
            )));
        }
        if !(mu_k > 0.0 && mu_k <= mu_s) {
            return Err(PhysicsError::BadInput(format!(
                "kinetic friction μₖ = {mu_k} must be in (0, μₛ = {mu_s}]"
            )));
        }
        Ok(())
    }
}

/// The mode a block takes when it leaves rest (or when a slip stops and the
/// forcing is still beyond rest).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Onset {
    /// Flat, the base slipping towards `dir` (±1).
    Slide { dir: f64 },
    /// On pivot `s`, held by friction.
    Rock { s: f64 },
    /// On pivot `s`, the pivot slipping towards `dir`.
    SlideRock { s: f64, dir: f64 },
}

/// The block's mechanics at one intensity: geometry, gravity, friction and
/// the forcing's scale.
#[derive(Debug, Clone, Copy)]
pub struct Contact {
    pub friction: Friction,
    pub alpha: f64,
    /// R (m): the half-diagonal, `3g/(4p²)`.
    pub r: f64,
    /// A = αg/η (m/s²): the ground's acceleration at ψ̈ = 1.
    pub a_scale: f64,
    p2: f64,
}

/// Forces per unit mass at the pivot (m/s²): friction `f` (on the block,
/// +X) and the normal force `n`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Forces {
    pub f: f64,
    pub n: f64,
}

impl Forces {
    /// `μ n − |f|`: how far the friction is from slipping (< 0: it slips;
    /// a negative `n` counts as slipping too).
    pub fn margin(self, mu: f64) -> f64 {
        mu * self.n - self.f.abs()
    }
}

impl Contact {
    pub fn new(p: f64, eta: f64, alpha: f64, friction: Friction) -> Contact {
        Contact {
            friction,
            alpha,
            r: crate::block::r_of_p(p),
            a_scale: alpha * G / eta,
            p2: p * p,
        }
    }

    /// Whether a flat block slides rather than tips while its base slips:
    /// the base's friction `μₖ g` keeps the resultant within the base
    /// (`μₖ ≤ tan α`, the tie within rounding as in
    /// [`crate::block::slides_first`]: at equality it passes through the
    /// corner, and tips nothing).
    pub fn slides_flat(&self) -> bool {
        crate::block::slides_first(self.friction.mu_k, self.alpha)
    }

    /// Whether a block at rest slides before it rocks (`μₛ ≤ tan α`, [`crate::block::slides_first`]).
    pub fn slides_first(&self) -> bool {
        crate::block::slides_first(self.friction.mu_s, self.alpha)
    }

    /// The forces on pivot `s` held by friction, at `(x, v)` under forcing `psi`.
    #[inline]
    pub fn rock_forces(&self, s: f64, x: f64, v: f64, psi: f64) -> Forces {
        let a = self.a_scale * psi;
        let (sn, c) = (self.alpha * (1.0 - s * x)).sin_cos();
        let th_d = self.alpha * v;
        let th_dd = self.p2 * (-s * sn + (a / G) * c);
        let r = self.r;
        Forces {
            f: r * s * sn * th_d * th_d + r * c * th_dd - a,
            n: G - r * c * th_d * th_d + s * r * sn * th_dd,
        }
    }

    /// The slide-rock mode's accelerations at `(x, v)` on pivot `s`, the
    /// pivot slipping towards `dir`, under forcing `psi`: `(ẍ, ẇ, N/m)`.
    #[inline]
    pub fn slide_rock_accel(&self, s: f64, dir: f64, x: f64, v: f64, psi: f64) -> (f64, f64, f64) {
        let a = self.a_scale * psi;
        let mu = self.friction.mu_k;
        let (sn, c) = (self.alpha * (1.0 - s * x)).sin_cos();
        let th_d = self.alpha * v;
        let r = self.r;
        let k = s * sn - mu * dir * c;
        let centripetal = G - r * c * th_d * th_d;
        let th_dd = -k * centripetal / (r * (1.0 / 3.0 + k * s * sn));
        let n = centripetal + s * r * sn * th_dd;
        let w_dd = a - mu * dir * n - r * (s * sn * th_d * th_d + c * th_dd);
        (th_dd / self.alpha, w_dd, n)
    }

    /// The mode a block at rest takes under forcing `psi` beyond rest's
    /// threshold: a block that slides first slides (its flat slide keeps
    /// the resultant within the base); else it lifts onto the pivot the
    /// forcing pushes it to (`side`), held there if the friction it then
    /// needs is within `μₛN`, else slipping against that friction (Shenton
    /// 1996).
    pub fn onset(&self, psi: f64, side: f64) -> Onset {
        let dir = side;
        if self.slides_first() {
            return Onset::Slide { dir };
        }
        let s = dir;
        let forces = self.rock_forces(s, 0.0, 0.0, psi);
        if forces.margin(self.friction.mu_s) >= 0.0 {
            return Onset::Rock { s };
        }
        let slip = -forces.f.signum();
        // Slipping, it must also tip (with μₖ up to tan α it need not): else
        // it slides flat.
        let (xdd, _, _) = self.slide_rock_accel(s, slip, 0.0, 0.0, psi);
        if s * xdd > 0.0 || !self.slides_flat() {
            Onset::SlideRock { s, dir: slip }
        } else {
            Onset::Slide { dir }
        }
    }

    /// Where a pivot's slip that has just stopped goes on, on pivot `s` at
    /// `(x, v)` under `psi`: held (`None`), or slipping again towards the
    /// returned direction.
    pub fn after_stick(&self, s: f64, x: f64, v: f64, psi: f64) -> Option<f64> {
        let forces = self.rock_forces(s, x, v, psi);
        (forces.margin(self.friction.mu_s) < 0.0).then_some(-forces.f.signum())
    }

    /// The flat slide over `len` seconds from base velocity `w` (m/s,
    /// towards `dir`) under `ψ̈ = g_a + g1 σ`: where the slip stops, if it
    /// does within `len` (`Some(σ)`), and the base's displacement and
    /// velocity at the end or the stop. Exact: ẇ is linear in σ.
    pub fn slide(&self, w: f64, dir: f64, g_a: f64, g1: f64, len: f64) -> FlatSlide {
        let friction = self.friction.mu_k * G;
        let mut c0 = self.a_scale * g_a - friction * dir;
        // A slip that starts where the forcing reaches the friction (rest's
        // threshold, or a stop) has no acceleration at its start but the
        // rounding's: it is 0, and the forcing's slope decides.
        if w == 0.0 && c0.abs() <= 1e-12 * friction {
            c0 = 0.0;
        }
        let c1 = self.a_scale * g1;
        // dir·w(σ) = dir·w + dir·c0 σ + dir·c1 σ²/2: its first root in (0, len].
        let stop = first_root(dir * w, dir * c0, dir * c1 / 2.0, len);
        let at = stop.unwrap_or(len);
        let du = w * at + c0 * at * at / 2.0 + c1 * at * at * at / 6.0;
        let w_end = if stop.is_some() {
            0.0
        } else {
            w + c0 * at + c1 * at * at / 2.0
        };
        FlatSlide { stop, du, w: w_end }
    }
}

/// A flat slide over a stretch ([`Contact::slide`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlatSlide {
    /// Where the slip stops, from the stretch's start (s).
    pub stop: Option<f64>,
    /// The base's displacement over the slide (m).
    pub du: f64,
    /// The base's velocity at its end (m/s; 0 where it stopped).
    pub w: f64,
}

/// The first `σ ∈ (0, len]` where `c0 + c1 σ + c2 σ²` (positive just after
/// 0, or 0 at 0 and rising) reaches 0; `None` if it stays positive. A start
/// at 0 that falls at once stops at 0.
fn first_root(c0: f64, c1: f64, c2: f64, len: f64) -> Option<f64> {
    if c0 <= 0.0 && (c1 < 0.0 || (c1 == 0.0 && c2 <= 0.0)) {
        return Some(0.0);
    }
    let f = |s: f64| c0 + s * (c1 + s * c2);
    // Roots of the quadratic (or the line), smallest positive first.
    let mut roots = [f64::NAN; 2];
    if c2 == 0.0 {
        if c1 != 0.0 {
            roots[0] = -c0 / c1;
        }
    } else {
        // A touch of the axis (a double root) rounds either way: within
        // rounding of 0 it is one.
        let disc = c1 * c1 - 4.0 * c2 * c0;
        let disc = if disc < 0.0 && disc >= -1e-12 * c1 * c1 {
            0.0
        } else {
            disc
        };
        if disc >= 0.0 {
            // The stable pair: q = −(c1 + sgn(c1)√disc)/2, roots q/c2 and c0/q.
            let sign = if c1 >= 0.0 { 1.0 } else { -1.0 };
            let q = -0.5 * (c1 + sign * disc.sqrt());
            roots = [q / c2, if q != 0.0 { c0 / q } else { f64::NAN }];
        }
    }
    let mut best: Option<f64> = None;
    for r in roots {
        if r > 0.0 && r <= len && best.is_none_or(|b| r < b) {
            best = Some(r);
        }
    }
    // At the far end a root rounded just past `len` still stops the slip
    // if the velocity has turned there.
    if best.is_none() && f(len) <= 0.0 {
        best = Some(len);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_root_is_the_smallest_positive_one() {
        // (1 − σ)(2 − σ) = 2 − 3σ + σ²: first root 1.
        assert_eq!(first_root(2.0, -3.0, 1.0, 5.0), Some(1.0));
        assert_eq!(first_root(2.0, -3.0, 1.0, 0.5), None);
        // 1 − 2σ: 0.5.
        assert_eq!(first_root(1.0, -2.0, 0.0, 1.0), Some(0.5));
        // Rising from 0: no root.
        assert_eq!(first_root(0.0, 1.0, 0.0, 1.0), None);
        // Falling from 0: stops at once.
        assert_eq!(first_root(0.0, -1.0, 0.0, 1.0), Some(0.0));
    }

    #[test]
    fn the_rock_forces_at_uplift_ask_tan_alpha() {
        // At uplift (x = 0, v = 0, a = g tan α) the pivot carries the weight
        // and the inertial force: F/N = tan α.
        let alpha = 0.3f64;
        let eta = 1.0;
        let c = Contact::new(2.0, eta, alpha, Friction::new(0.5));
        let psi = G * alpha.tan() / c.a_scale;
        let f = c.rock_forces(1.0, 0.0, 0.0, psi);
        assert!((f.f.abs() / f.n - alpha.tan()).abs() < 1e-14);
        assert!((f.n - G).abs() < 1e-12);
    }

    #[test]
    fn a_block_lifted_at_mu_equal_to_b_over_h_needs_more_than_mu() {
        // Why a tie slides (MODEL.md §17): just past rest's threshold, by
        // δ = a − g tan α, the lifted block asks F/N = tan α + δ/(4g) to
        // first order (R θ̈ = ¾ δ cos α from Eq. 7 with R p² = ¾ g), so a
        // pivot with μₛ = tan α slips at once.
        let alpha = 0.25f64;
        let c = Contact::new(2.0, 1.0, alpha, Friction::new(alpha.tan()));
        for delta in [1e-4, 1e-3, 1e-2] {
            let psi = (G * alpha.tan() + delta) / c.a_scale;
            let f = c.rock_forces(1.0, 0.0, 0.0, psi);
            let excess = f.f.abs() / f.n - alpha.tan();
            let first_order = delta / (4.0 * G);
            assert!(
                (excess - first_order).abs() < 2.0 * first_order * delta / G,
                "δ = {delta}: {excess} against {first_order}"
            );
            assert!(f.margin(alpha.tan()) < 0.0);
        }
    }

    #[test]
    fn at_mu_equal_to_b_over_h_the_block_slides_flat() {
        // μ = b/h as a user gives it, an ulp either side, tan α of the
        // block's own α: each is the tie, which slides first (its slip does
        // not tip it). A part in 1e9 above b/h rocks first.
        for (b, h) in [(0.2, 0.9), (0.25, 1.0), (0.3, 0.7), (0.1, 1.3)] {
            let alpha = f64::atan(b / h);
            let ratio: f64 = b / h;
            for mu in [ratio, ratio.next_up(), ratio.next_down(), alpha.tan()] {
                assert!(
                    crate::block::slides_first(mu, alpha),
                    "μ = {mu}, b/h = {b}/{h}"
                );
                let c = Contact::new(2.0, 0.3, alpha, Friction::new(mu));
                assert!(c.slides_flat(), "μₖ = {mu}");
                let psi = 0.3 * alpha.tan() / alpha;
                for side in [1.0, -1.0] {
                    assert_eq!(c.onset(side * psi, side), Onset::Slide { dir: side });
                }
            }
            let above = ratio * (1.0 + 1e-9);
            assert!(!crate::block::slides_first(above, alpha));
            let c = Contact::new(2.0, 0.3, alpha, Friction::new(above));
            assert!(!c.slides_flat());
            // At rest's threshold the demand is tan α, within μ: held.
            let psi = 0.3 * alpha.tan() / alpha;
            assert_eq!(c.onset(psi, 1.0), Onset::Rock { s: 1.0 });
        }
    }
}
