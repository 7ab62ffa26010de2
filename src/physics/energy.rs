//! Free rocking after the record ends, settled from energy (MODEL.md §3).
//!
//! With the ground still, energy is conserved between impacts and lost only
//! at them. With `y = s·x` (the angle on the current pivot, in units of α)
//! and `w = s·ẋ`, define the *distance below the crest* `D`:
//!
//! ```text
//! linearised:  D = ½ [ (1 − y)² − (w/p)² ]
//! nonlinear:   D = [ 2 sin²(α(1 − y)/2) − ½ (α w / p)² ] / α²
//! ```
//!
//! `D > 0`: the swing turns back before the crest `y = 1`; `D < 0`: it passes
//! the crest and the block overturns. The fate is settled by the current
//! swing and at most the next one. Derivation: docs/MODEL.md, §3.4.

use super::step::Rocking;

/// What the free motion after the record still holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fate {
    /// The largest |x| still to come (0 if none beyond the current position).
    pub max_abs_x: f64,
    /// Whether the block passes the crest |x| = 1 (and so overturns).
    pub passes_crest: bool,
    /// Impacts on the way to passing it (0, or 1 after heading back).
    pub impacts: u64,
}

/// The shape of the potential: how `D` is made from an angle gap and a speed.
trait Potential {
    /// `D` for angle gap `g = 1 − y` and speed `w`.
    fn d(&self, gap: f64, w: f64) -> f64;
    /// The gap `1 − y_max` at which the potential term equals `d ≥ 0`.
    fn gap_at(&self, d: f64) -> f64;
    /// Speed² at `y = 0` for a given `D`.
    fn speed2_at_pivot(&self, d: f64) -> f64;
}

struct LinearPotential {
    p: f64,
}

impl Potential for LinearPotential {
    fn d(&self, gap: f64, w: f64) -> f64 {
        let r = w / self.p;
        0.5 * (gap - r) * (gap + r)
    }
    fn gap_at(&self, d: f64) -> f64 {
        (2.0 * d).sqrt()
    }
    fn speed2_at_pivot(&self, d: f64) -> f64 {
        // D = ½ (1 − w²/p²)  ⇒  w² = p² (1 − 2D)
        self.p * self.p * (1.0 - 2.0 * d)
    }
}

struct NonlinearPotential {
    p: f64,
    alpha: f64,
}

impl NonlinearPotential {
    fn hav(&self, gap: f64) -> f64 {
        // 2 sin²(α g / 2) / α²
        let s = (0.5 * self.alpha * gap).sin();
        2.0 * s * s / (self.alpha * self.alpha)
    }
}

impl Potential for NonlinearPotential {
    fn d(&self, gap: f64, w: f64) -> f64 {
        let r = w / self.p;
        self.hav(gap) - 0.5 * r * r
    }
    fn gap_at(&self, d: f64) -> f64 {
        // 2 sin²(α g/2)/α² = d  ⇒  g = (2/α) asin(α sqrt(d/2))
        (2.0 / self.alpha) * (self.alpha * (0.5 * d).sqrt()).min(1.0).asin()
    }
    fn speed2_at_pivot(&self, d: f64) -> f64 {
        // d = hav(1) − ½ w²/p²
        2.0 * self.p * self.p * (self.hav(1.0) - d)
    }
}

fn fate(pot: &impl Potential, st: Rocking, eps: f64) -> Fate {
    let y = st.s * st.x;
    let w = st.s * st.v;
    let d = pot.d(1.0 - y, w);
    if y > 1.0 {
        // Past the crest (possible under a cap above 1): it falls away unless
        // it heads back with enough speed to climb over the crest again.
        if !(w < 0.0 && d < 0.0) {
            return Fate {
                max_abs_x: f64::INFINITY,
                passes_crest: true,
                impacts: 0,
            };
        }
    } else if w > 0.0 {
        // Still swinging out: this swing is the highest still to come.
        if d < 0.0 {
            return Fate {
                max_abs_x: f64::INFINITY,
                passes_crest: true,
                impacts: 0,
            };
        }
        return Fate {
            max_abs_x: 1.0 - pot.gap_at(d),
            passes_crest: false,
            impacts: 0,
        };
    }
    // Heading back: impact, then one swing on the other pivot at ε times the speed.
    let w_impact2 = pot.speed2_at_pivot(d).max(0.0);
    let w_after = eps * w_impact2.sqrt();
    let d_after = pot.d(1.0, w_after);
    if d_after < 0.0 {
        return Fate {
            max_abs_x: f64::INFINITY,
            passes_crest: true,
            impacts: 1,
        };
    }
    Fate {
        max_abs_x: 1.0 - pot.gap_at(d_after),
        passes_crest: false,
        impacts: 0,
    }
}

/// Fate of the linearised model's free rocking.
pub fn linear_fate(p: f64, st: Rocking, eps: f64) -> Fate {
    fate(&LinearPotential { p }, st, eps)
}

/// Fate of the nonlinear model's free rocking.
pub fn nonlinear_fate(p: f64, alpha: f64, st: Rocking, eps: f64) -> Fate {
    fate(&NonlinearPotential { p, alpha }, st, eps)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Housner's free-rocking amplitude after an impact with speed v:
    /// 1 − sqrt(1 − (v/p)²) (MODEL.md §9).
    #[test]
    fn amplitude_after_impact_matches_closed_form() {
        let p = 2.0;
        for v in [0.1, 0.7, 1.5, 1.99] {
            for eps in [0.5, 0.9, 1.0] {
                // Heading back to the pivot at x = 0 with speed v (on pivot +1, so v < 0).
                let f = linear_fate(
                    p,
                    Rocking {
                        x: 0.0,
                        v: -v,
                        s: 1.0,
                    },
                    eps,
                );
                let expected = 1.0 - (1.0 - (eps * v / p).powi(2)).sqrt();
                assert!((f.max_abs_x - expected).abs() < 1e-15, "{v} {eps}");
                assert!(!f.passes_crest);
                // Swinging out from the pivot at speed v: the same without ε.
                let f = linear_fate(p, Rocking { x: 0.0, v, s: 1.0 }, eps);
                assert!((f.max_abs_x - (1.0 - (1.0 - (v / p).powi(2)).sqrt())).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn crest_is_passed_exactly_when_energy_says_so() {
        let p = 3.0;
        // Released at rest: never passes.
        let f = linear_fate(
            p,
            Rocking {
                x: -0.8,
                v: 0.0,
                s: -1.0,
            },
            1.0,
        );
        assert!(!f.passes_crest);
        assert!(
            (f.max_abs_x - 0.8).abs() < 1e-15,
            "elastic: the next swing is as high"
        );
        // Leaving the pivot at v/p just above and below 1.
        assert!(
            linear_fate(
                p,
                Rocking {
                    x: 0.0,
                    v: p * (1.0 + 1e-12),
                    s: 1.0
                },
                0.5
            )
            .passes_crest
        );
        assert!(
            !linear_fate(
                p,
                Rocking {
                    x: 0.0,
                    v: p * (1.0 - 1e-12),
                    s: 1.0
                },
                0.5
            )
            .passes_crest
        );
        // Heading in fast: overturns on the other side only if ε keeps enough speed.
        let st = Rocking {
            x: 0.5,
            v: -1.5 * p,
            s: 1.0,
        };
        // w² at pivot = p²(1 − (0.25 − 2.25)) = 3p², so ε·sqrt(3) vs 1.
        assert!(linear_fate(p, st, 0.6).passes_crest);
        assert!(!linear_fate(p, st, 0.57).passes_crest);
    }

    #[test]
    fn past_the_crest_it_falls_unless_heading_back_fast_enough() {
        let p = 2.0;
        // y = 1.3: linear free motion y − 1 = 0.3 cosh + (w/p) sinh escapes iff w/p > −0.3.
        let at = |r: f64, eps: f64| {
            linear_fate(
                p,
                Rocking {
                    x: 1.3,
                    v: r * p,
                    s: 1.0,
                },
                eps,
            )
        };
        assert!(at(0.5, 0.5).passes_crest);
        assert!(at(-0.29, 0.5).passes_crest);
        // Heading back at w/p = −0.31 it climbs over the crest and reaches the
        // pivot with (w/p)² = 1 − (0.09 − 0.0961) = 1.0061: elastic, the next
        // swing passes the crest on the other side; at ε = 0.99 it does not
        // ((0.99)²·1.0061 < 1) and peaks at 1 − sqrt(1 − 0.9801·1.0061).
        assert!(at(-0.31, 1.0).passes_crest);
        let back = at(-0.31, 0.99);
        assert!(!back.passes_crest);
        assert!((back.max_abs_x - (1.0 - (1.0 - 0.9801 * 1.0061f64).sqrt())).abs() < 1e-12);
    }

    #[test]
    fn nonlinear_tends_to_linear_as_alpha_vanishes() {
        let p = 1.5;
        let st = Rocking {
            x: -0.3,
            v: -0.9,
            s: -1.0,
        };
        let lin = linear_fate(p, st, 0.8).max_abs_x;
        let mut last_err = f64::INFINITY;
        for alpha in [0.2, 0.1, 0.05, 0.025, 0.0125] {
            let err = (nonlinear_fate(p, alpha, st, 0.8).max_abs_x - lin).abs();
            assert!(err < last_err, "error shrinks with α");
            last_err = err;
        }
        // Second order in α: the cosine's next term.
        assert!(last_err < 1e-4, "{last_err}");
    }

    #[test]
    fn nonlinear_crest_from_exact_energy() {
        // Leaving the pivot, the crest is reached iff ½w² ≥ (p²/α²)(1 − cos α).
        let (p, alpha) = (2.0, 0.3f64);
        let w_crit = (2.0 * p * p / (alpha * alpha) * (1.0 - alpha.cos())).sqrt();
        let at = |w: f64| {
            nonlinear_fate(
                p,
                alpha,
                Rocking {
                    x: 0.0,
                    v: w,
                    s: 1.0,
                },
                1.0,
            )
        };
        assert!(at(w_crit * (1.0 + 1e-10)).passes_crest);
        assert!(!at(w_crit * (1.0 - 1e-10)).passes_crest);
    }
}
