//! A rigid block: its geometry and restitution, defined once (pure;
//! docs/MODEL.md §1).
//!
//! A rectangular block of half-width `b` and half-height `h` (m) rocks with
//! slenderness `α = atan(b/h)`, semi-diagonal `R = √(b² + h²)` and frequency
//! parameter `p = √(3g/(4R))`. Its coefficient of restitution ε is a value
//! in (0, 1] or Housner's bound for a rectangle, `1 − 1.5 sin²α`. Pipelines,
//! `fragility`, `risk`, `simulate` and `capacity` all take a block from here.

use std::fmt;
use std::str::FromStr;

/// Standard gravity (m/s²).
pub const G: f64 = 9.80665;

/// The semi-diagonal R (m) of a block of frequency parameter `p` (1/s):
/// [`Block::p`] undone, R = 3g/(4p²).
pub fn r_of_p(p: f64) -> f64 {
    3.0 * G / (4.0 * p * p)
}

/// A real block: half-width and half-height (m), restitution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Block {
    pub b_m: f64,
    pub h_m: f64,
    pub eps: f64,
}

/// The coefficient of restitution as a user gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Restitution {
    /// A value in (0, 1].
    Value(f64),
    /// Housner's bound for a rectangle, `1 − 1.5 sin²α`.
    Housner,
}

/// A block that cannot be built, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BlockError {
    #[error(
        "b = {} m and h = {} m must be positive and finite",
        crate::decimal::shortest(*b),
        crate::decimal::shortest(*h)
    )]
    Size { b: f64, h: f64 },
    #[error("ε = {}; ε must be in (0, 1]", crate::decimal::shortest(*.0))]
    Eps(f64),
    #[error(
        "Housner's ε = 1 − 1.5 sin²α = {eps:.4} is not positive for b/h = {ratio} \
         (α = {alpha:.4} rad): give ε"
    )]
    HousnerEps { eps: f64, ratio: f64, alpha: f64 },
    #[error("`{0}`: give a number in (0, 1] or `housner`")]
    Restitution(String),
    #[error(
        "friction coefficient μ = {} must be in (0, {max}]: above it the sliding pivot's \
         equations lose uniqueness (Painlevé), and such a base never lets a block slide",
        crate::decimal::shortest(*.0),
        max = MU_MAX
    )]
    Mu(f64),
}

impl Block {
    /// A block from its half-width and half-height (m) and its restitution,
    /// checked: positive finite sizes, ε in (0, 1] (Housner's bound is
    /// refused where it is not positive, for blocks stockier than b/h ≈ 1.2).
    pub fn new(b_m: f64, h_m: f64, eps: Restitution) -> Result<Block, BlockError> {
        if !(b_m > 0.0 && h_m > 0.0 && b_m.is_finite() && h_m.is_finite()) {
            return Err(BlockError::Size { b: b_m, h: h_m });
        }
        let eps = match eps {
            Restitution::Value(e) => check_eps(e)?,
            Restitution::Housner => {
                let e = Block::housner_eps(b_m, h_m);
                if e.is_nan() || e <= 0.0 {
                    return Err(BlockError::HousnerEps {
                        eps: e,
                        ratio: b_m / h_m,
                        alpha: (b_m / h_m).atan(),
                    });
                }
                e
            }
        };
        Ok(Block { b_m, h_m, eps })
    }

    /// A block from its full width and height (m): `b = width/2`, `h = height/2`.
    pub fn from_full(width_m: f64, height_m: f64, eps: Restitution) -> Result<Block, BlockError> {
        Block::new(width_m / 2.0, height_m / 2.0, eps)
    }

    /// Slenderness `α = atan(b/h)` (rad).
    pub fn alpha(&self) -> f64 {
        (self.b_m / self.h_m).atan()
    }

    /// Semi-diagonal `R = √(b² + h²)` (m).
    pub fn r_m(&self) -> f64 {
        self.b_m.hypot(self.h_m)
    }

    /// Frequency parameter `p = √(3g/(4R))` (1/s).
    pub fn p(&self) -> f64 {
        (3.0 * G / (4.0 * self.r_m())).sqrt()
    }

    /// The block of frequency parameter `p` (1/s) and slenderness
    /// `alpha_rad`: [`Block::p`] and [`Block::alpha`] undone, R = 3g/(4p²).
    pub fn of_p_alpha(p: f64, alpha_rad: f64, eps: Restitution) -> Result<Block, BlockError> {
        let r_m = r_of_p(p);
        Block::new(r_m * alpha_rad.sin(), r_m * alpha_rad.cos(), eps)
    }

    /// The PGA (g) at which the block lifts off on the ground, `b/h = tan α`:
    /// below it nothing moves (the inertia force m·a cannot tip it about a
    /// corner against m·g, docs/MODEL.md §1).
    pub fn uplift_pga_g(&self) -> f64 {
        self.b_m / self.h_m
    }

    /// Housner's upper bound of ε for a rectangle, 1 − 1.5 sin²α.
    pub fn housner_eps(b_m: f64, h_m: f64) -> f64 {
        housner_eps_of_alpha((b_m / h_m).atan())
    }
}

/// Housner's 1 − 1.5 sin²α of a rectangle of slenderness α (rad).
pub fn housner_eps_of_alpha(alpha: f64) -> f64 {
    1.0 - 1.5 * alpha.sin().powi(2)
}

/// `eps` when it is in (0, 1].
pub fn check_eps(eps: f64) -> Result<f64, BlockError> {
    if eps > 0.0 && eps <= 1.0 {
        Ok(eps)
    } else {
        Err(BlockError::Eps(eps))
    }
}

/// The largest friction coefficient the models take: below 4/3 the
/// slide-rock mode's `1/3 + k s sin φ` stays positive at every angle
/// (`5/6 − ½√(1 + μ²) > 0`), so its accelerations are unique (no Painlevé
/// paradox; docs/MODEL.md §21).
pub const MU_MAX: f64 = 1.3;

/// `mu` when it is a friction coefficient the models take: in (0, [`MU_MAX`]].
pub fn check_mu(mu: f64) -> Result<f64, BlockError> {
    if mu > 0.0 && mu <= MU_MAX {
        Ok(mu)
    } else {
        Err(BlockError::Mu(mu))
    }
}

/// Whether a block of slenderness `alpha_rad` on a base of static friction
/// coefficient `mu` slides before it rocks under horizontal ground shaking
/// (docs/MODEL.md §17): uplift needs a horizontal inertia force of m·g·b/h
/// (moments about the corner), while the base can transmit at most μ·m·g
/// before it slips, so the block slides first when μ < b/h = tan α
/// (Ishiyama 1982, EESD 10(5); Shenton 1996, J. Eng. Mech. 122(7)). Then
/// the rocking model, which assumes no sliding, does not apply.
///
/// At μ = b/h both thresholds are crossed together, and the block slides:
/// once lifted it needs more friction than tan α at once (the rotation's
/// inertia adds to the demand), so its pivot slips, and a slip at
/// μₖ = tan α does not tip it (the resultant passes through the corner).
/// So a tie slides, as every μ below it does. A μ within [`TIE_REL`] of
/// tan α is that tie (b/h given as μ, and tan α of the block's own α,
/// differ by rounding).
pub fn slides_first(mu: f64, alpha_rad: f64) -> bool {
    let tan = alpha_rad.tan();
    mu < tan || ties(mu, tan)
}

/// How close (relative) a friction coefficient and tan α are to count as
/// equal: 16 machine epsilons, a few times the rounding of tan(atan(b/h)).
const TIE_REL: f64 = 16.0 * f64::EPSILON;

/// Whether `mu` is `tan_alpha` within rounding ([`TIE_REL`]).
fn ties(mu: f64, tan_alpha: f64) -> bool {
    (mu - tan_alpha).abs() <= TIE_REL * tan_alpha
}

/// The largest half size (m) of a free-standing object the tool expects: a
/// block 20 m tall is a building, and more likely a size given in cm.
pub const LARGEST_HALF_SIZE_M: f64 = 10.0;

/// What every command says of a block larger than [`LARGEST_HALF_SIZE_M`]:
/// an inventory in cm (`statue,20,90`) ran as a 90 m block without a word.
pub fn size_warning(block: &Block) -> Option<String> {
    (block.b_m.max(block.h_m) > LARGEST_HALF_SIZE_M).then(|| {
        let m = crate::decimal::level_text;
        format!(
            "half-width {} m, half-height {} m: a block {} m tall is a building's size; sizes \
             are in metres (were they given in cm?)",
            m(block.b_m),
            m(block.h_m),
            m(2.0 * block.h_m)
        )
    })
}

/// What every command says of a block that slides before it rocks.
pub fn sliding_warning(mu: f64, alpha_rad: f64) -> String {
    format!(
        "the block slides before it rocks: friction μ = {mu} does not exceed b/h = tan α = {:.4} \
         (Ishiyama 1982; Shenton 1996); the rocking results assume it does not slide, so \
         they hold only if it is restrained against sliding",
        alpha_rad.tan()
    )
}

impl FromStr for Restitution {
    type Err = BlockError;

    /// `housner`, or a number (checked later, with the block).
    fn from_str(text: &str) -> Result<Self, BlockError> {
        let text = text.trim();
        if text.eq_ignore_ascii_case("housner") {
            return Ok(Restitution::Housner);
        }
        text.parse::<f64>()
            .map(Restitution::Value)
            .map_err(|_| BlockError::Restitution(text.to_string()))
    }
}

impl fmt::Display for Restitution {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Restitution::Value(e) => write!(f, "{e}"),
            Restitution::Housner => f.write_str("housner"),
        }
    }
}

/// A number in (0, 1] (checked with the block) or `"housner"`.
impl<'de> serde::Deserialize<'de> for Restitution {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Given {
            Number(f64),
            Text(String),
        }
        // serde's own message ("did not match any variant of untagged
        // enum Given") names neither the key nor what it takes.
        let given = Given::deserialize(d).map_err(|_| {
            serde::de::Error::custom(
                "eps: give a number in (0, 1] or \"housner\" (one block's; a list is a \
                 logic tree's, `tree`)",
            )
        })?;
        match given {
            Given::Number(e) => Ok(Restitution::Value(e)),
            Given::Text(t) => t.parse().map_err(serde::de::Error::custom),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two blocks of b/h = 0.4: μ = 0.2 slides first (a base slipping at
    /// 0.2 g cannot give the 0.4 g uplift needs), μ = 0.6 rocks; so does
    /// μ = 0.5 at b/h a part in 1e12 below it (the tie is some 1e-15).
    #[test]
    fn a_block_slides_first_when_friction_is_below_its_aspect_ratio() {
        let block = Block::new(0.4, 1.0, Restitution::Value(0.9)).unwrap();
        assert!(slides_first(0.2, block.alpha()));
        assert!(!slides_first(0.6, block.alpha()));
        assert!(!slides_first(
            0.5,
            Block::new(0.5, 1.0, Restitution::Value(0.9))
                .unwrap()
                .alpha()
                - 1e-12
        ));
        assert!(sliding_warning(0.2, block.alpha()).contains("b/h = tan α = 0.4000"));
        assert_eq!(check_mu(0.3), Ok(0.3));
        assert_eq!(check_mu(-0.1), Err(BlockError::Mu(-0.1)));
        // The one range of every door, the slide-rock model's (Friction::validate).
        assert_eq!(check_mu(1.3), Ok(1.3));
        assert!(check_mu(0.0).is_err() && check_mu(5.0).is_err());
        assert!(check_mu(f64::NAN).is_err());
    }

    #[test]
    fn geometry_by_hand() {
        // b = 0.2 m, h = 1 m: R = √1.04 m, p = √(3g/(4R)), α = atan 0.2.
        let b = Block::new(0.2, 1.0, Restitution::Value(0.8)).unwrap();
        assert!((b.r_m() - 1.04f64.sqrt()).abs() < 1e-15);
        assert!((b.p() - (3.0 * 9.80665 / (4.0 * 1.04f64.sqrt())).sqrt()).abs() < 1e-12);
        assert!((b.alpha() - 0.197_395_559_849_880_75).abs() < 1e-15);
        // Full dimensions are twice the half ones.
        assert_eq!(
            Block::from_full(0.4, 2.0, Restitution::Value(0.8)).unwrap(),
            b
        );
    }

    #[test]
    fn housner_bound_and_its_limits() {
        // sin²(atan x) = x²/(1 + x²): at b/h = 0.25, 1 − 1.5·(1/17).
        let b = Block::new(0.25, 1.0, Restitution::Housner).unwrap();
        assert!((b.eps - (1.0 - 1.5 / 17.0)).abs() < 1e-15);
        // Not positive from sin²α ≥ 2/3, i.e. b/h ≥ √2.
        assert!(matches!(
            Block::new(1.5, 1.0, Restitution::Housner),
            Err(BlockError::HousnerEps { .. })
        ));
        assert_eq!(
            Block::new(0.2, 1.0, Restitution::Value(1.2)),
            Err(BlockError::Eps(1.2))
        );
        assert!(matches!(
            Block::new(-0.2, 1.0, Restitution::Value(0.8)),
            Err(BlockError::Size { .. })
        ));
        assert!(Block::new(f64::NAN, 1.0, Restitution::Value(0.8)).is_err());
    }

    #[test]
    fn restitution_reads_a_number_or_housner() {
        assert_eq!("housner".parse(), Ok(Restitution::Housner));
        assert_eq!("0.7".parse(), Ok(Restitution::Value(0.7)));
        assert!("elastic".parse::<Restitution>().is_err());
        assert_eq!(Restitution::Housner.to_string(), "housner");
    }
}
