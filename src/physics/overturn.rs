//! When a block counts as overturned ([`Overturn`]), and the proof that a
//! linearised block escapes ([`escape_proven`]; docs/MODEL.md §10).

use std::fmt;

use super::error::PhysicsError;
use super::step::Rocking;

/// When a block counts as overturned.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Overturn {
    /// `|x| ≥ 1`: θ reaches α, the static stability limit (the paper's choice).
    Static,
    /// `|x| ≥ cap` for a cap above 1.
    Cap(f64),
    /// Nonlinear model only: the block lies on its side, `θ = π/2`.
    OnSide,
    /// True overturning: the block never comes back (MODEL.md §10). The
    /// nonlinear model: θ reaches π/2, as [`Overturn::OnSide`]. The
    /// linearised model has no such angle: nothing is decided while the
    /// ground moves unless a bound proves the escape (the growing mode
    /// outruns the largest forcing still to come, [`escape_proven`]), and
    /// after the excitation the free motion's energy decides.
    Escape,
}

/// Whether a linearised block on pivot `s` at `(x, v)` escapes for sure
/// whatever the forcing does from now on, given a bound `m_over_eta` on
/// `|ψ̈|/η` for the rest of the excitation. With `y = s·x`, `w = s·ẋ`, the
/// growing mode `u = y − 1 + w/p` obeys `u̇ = p(u + sψ̈/η) ≥ p(u − M/η)`,
/// so `u > M/η` keeps growing; the other mode `y − 1 − w/p` stays within
/// `M/η` of its free decay, which keeps `y ≥ min(y₀, 1) > 0`: no impact,
/// and `y → ∞`. (Proof in MODEL.md §10.) A relative margin of 1e-9 covers
/// the rounding of `u`.
pub fn escape_proven(p: f64, st: Rocking, m_over_eta: f64) -> bool {
    let (y, w) = (st.s * st.x, st.s * st.v);
    let u = y - 1.0 + w / p;
    y > 0.0 && u > m_over_eta * (1.0 + 1e-9) + 1e-9 * (y.abs() + 1.0)
}

impl Overturn {
    /// The `|x|` at which the run stops, for a block of slenderness `alpha_rad`.
    pub fn limit(self, alpha_rad: Option<f64>) -> Result<f64, PhysicsError> {
        match self {
            Overturn::Static => Ok(1.0),
            // Past θ = π/2 the block lies on its side: no state of the
            // nonlinear model reaches the cap (cap:100 at α = 0.2 reported
            // θmax/α = 100, 20 rad, "overturned no").
            Overturn::Cap(c) if alpha_rad.is_some_and(|a| c * a > std::f64::consts::FRAC_PI_2) => {
                let a = alpha_rad.unwrap_or(1.0);
                Err(PhysicsError::BadInput(format!(
                    "overturning cap {} is past the block's side: c·α = {} rad > π/2; the \
                     nonlinear model's largest cap is π/(2α) = {:.4} (`on-side`)",
                    crate::decimal::shortest(c),
                    crate::decimal::level_text(c * a),
                    std::f64::consts::FRAC_PI_2 / a
                )))
            }
            Overturn::Cap(c) if c.is_finite() && c >= 1.0 => Ok(c),
            Overturn::Cap(c) => Err(PhysicsError::BadInput(format!(
                "overturning cap {} must be a finite number ≥ 1 (in units of α)",
                crate::decimal::shortest(c)
            ))),
            Overturn::OnSide => match alpha_rad {
                Some(a) => Ok(std::f64::consts::FRAC_PI_2 / a),
                None => Err(PhysicsError::BadInput(
                    "the `on-side` criterion (θ = π/2) needs the nonlinear model and α".into(),
                )),
            },
            // Linearised: the first |x| at which the driver tries to prove
            // the escape (it doubles after each try that fails).
            Overturn::Escape => Ok(alpha_rad.map_or(1.0, |a| std::f64::consts::FRAC_PI_2 / a)),
        }
    }

    /// Whether runs under this criterion stop only on a proof of escape
    /// (the linearised model under [`Overturn::Escape`]) rather than at
    /// the limit.
    pub fn needs_escape_proof(self, alpha_rad: Option<f64>) -> bool {
        self == Overturn::Escape && alpha_rad.is_none()
    }
}

impl std::str::FromStr for Overturn {
    type Err = PhysicsError;

    /// `static`, `cap:<c>` (c ≥ 1), `on-side` or `escape`.
    fn from_str(text: &str) -> Result<Self, PhysicsError> {
        let bad = || {
            PhysicsError::BadInput(format!(
                "unknown overturning criterion `{text}`; valid: static, cap:<c> (c ≥ 1, in units of α), on-side, escape"
            ))
        };
        match text {
            "static" => Ok(Overturn::Static),
            "on-side" => Ok(Overturn::OnSide),
            "escape" => Ok(Overturn::Escape),
            _ => {
                let c = text
                    .strip_prefix("cap:")
                    .ok_or_else(bad)?
                    .parse::<f64>()
                    .map_err(|_| bad())?;
                Overturn::Cap(c).limit(None).map(|_| Overturn::Cap(c))
            }
        }
    }
}

impl fmt::Display for Overturn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Overturn::Static => write!(f, "static"),
            Overturn::Cap(c) => write!(f, "cap:{c}"),
            Overturn::OnSide => write!(f, "on-side"),
            Overturn::Escape => write!(f, "escape"),
        }
    }
}

crate::deserialize_by_from_str!(Overturn);

#[cfg(test)]
mod tests {
    use super::Overturn;
    use std::f64::consts::FRAC_PI_2;

    /// A cap is in units of α: the linearised model has no side to lie on
    /// and takes any cap ≥ 1; the nonlinear one takes caps up to π/(2α),
    /// where the block lies on its side, and refuses beyond.
    #[test]
    fn a_cap_past_the_side_is_refused_for_the_nonlinear_model() {
        assert_eq!(Overturn::Cap(100.0).limit(None).unwrap(), 100.0);
        let alpha = 0.2;
        let side = FRAC_PI_2 / alpha;
        assert_eq!(Overturn::Cap(7.5).limit(Some(alpha)).unwrap(), 7.5);
        assert_eq!(Overturn::Cap(side).limit(Some(alpha)).unwrap(), side);
        let e = Overturn::Cap(100.0)
            .limit(Some(alpha))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("past the block's side") && e.contains("7.8540"),
            "{e}"
        );
        assert!(Overturn::Cap(side * (1.0 + 1e-15))
            .limit(Some(alpha))
            .is_err());
    }
}
