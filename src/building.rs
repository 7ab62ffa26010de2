//! A linear building with its floors (pure): each mode's period, damping,
//! participation factor Γ and its shape φ at every floor, lowest floor
//! first. A floor's motion takes Γφ of each mode ([`crate::floor::Mode`]),
//! so one building gives every floor's modes, and a block on floor k is
//! the one-floor case with Γφ = Γ·φ_k (`--building … --level k` is
//! `--floor T,ζ,Γ·φ_k` for each mode).

use std::fmt;
use std::str::FromStr;

use crate::floor::Mode;

/// One mode with its shape at every floor.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapedMode {
    /// Period (s).
    pub period_s: f64,
    /// Damping ratio.
    pub zeta: f64,
    /// Participation factor Γ (with the shape's normalisation).
    pub gamma: f64,
    /// The shape's value at each floor, lowest first.
    pub shape: Vec<f64>,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BuildingError {
    #[error(
        "`{0}`: a building's mode is T,ZETA,GAMMA,PHI1,…,PHIn (period in s, damping ratio, \
         participation factor, the shape at each floor, lowest first), e.g. \
         0.5,0.05,1.3,0.33,0.67,1"
    )]
    Syntax(String),
    #[error("mode {mode} has its shape at {got} floors, mode 1 at {want}: give every mode's at each floor")]
    Floors {
        mode: usize,
        got: usize,
        want: usize,
    },
    #[error("level {level}: the building has floors 1–{floors}")]
    Level { level: usize, floors: usize },
    #[error("a level picks a floor of a building: give the building")]
    Alone,
    #[error("the building has floors 1–{0}: give the block's level")]
    NoLevel(usize),
    #[error("a floor's modes and a building both place the block: give one")]
    Both,
}

impl ShapedMode {
    /// From `[T, ζ, Γ, φ1, …, φn]`.
    fn of_values(values: &[f64], text: impl FnOnce() -> String) -> Result<Self, BuildingError> {
        if values.len() < 4 {
            return Err(BuildingError::Syntax(text()));
        }
        Ok(ShapedMode {
            period_s: values[0],
            zeta: values[1],
            gamma: values[2],
            shape: values[3..].to_vec(),
        })
    }
}

impl FromStr for ShapedMode {
    type Err = BuildingError;

    fn from_str(s: &str) -> Result<ShapedMode, BuildingError> {
        let values: Vec<f64> = s
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| BuildingError::Syntax(s.to_string()))?;
        ShapedMode::of_values(&values, || s.to_string())
    }
}

/// A mode as `[T, ζ, Γ, φ1, …, φn]` or as the text `T,ZETA,GAMMA,PHI1,…`.
impl<'de> serde::Deserialize<'de> for ShapedMode {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Given {
            Numbers(Vec<f64>),
            Text(String),
        }
        match Given::deserialize(d)? {
            Given::Numbers(v) => ShapedMode::of_values(&v, || format!("{v:?}")),
            Given::Text(t) => t.parse(),
        }
        .map_err(serde::de::Error::custom)
    }
}

impl fmt::Display for ShapedMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{}", self.period_s, self.zeta, self.gamma)?;
        for v in &self.shape {
            write!(f, ",{v}")?;
        }
        Ok(())
    }
}

/// How many floors the modes describe (each mode's shape at every floor).
pub fn floors(modes: &[ShapedMode]) -> Result<usize, BuildingError> {
    let want = modes.first().map_or(0, |m| m.shape.len());
    for (i, m) in modes.iter().enumerate() {
        if m.shape.len() != want {
            return Err(BuildingError::Floors {
                mode: i + 1,
                got: m.shape.len(),
                want,
            });
        }
    }
    Ok(want)
}

/// The modes of floor `level` (1 = the lowest floor the shapes give):
/// Γφ = Γ·φ_level for each mode. The modes' values are checked where they
/// become a floor ([`crate::floor::Building::new`]).
pub fn at_level(modes: &[ShapedMode], level: usize) -> Result<Vec<Mode>, BuildingError> {
    let n = floors(modes)?;
    if level == 0 || level > n {
        return Err(BuildingError::Level { level, floors: n });
    }
    Ok(modes
        .iter()
        .map(|m| Mode {
            period_s: m.period_s,
            zeta: m.zeta,
            gamma_phi: m.gamma * m.shape[level - 1],
        })
        .collect())
}

/// The floor a block stands on, from `--floor` modes or a `--building`
/// and its `--level` (one of the two).
pub fn floor_modes(
    floor: &[Mode],
    building: &[ShapedMode],
    level: Option<usize>,
) -> Result<Vec<Mode>, BuildingError> {
    match (floor.is_empty(), building.is_empty(), level) {
        (_, true, Some(_)) => Err(BuildingError::Alone),
        (false, false, _) => Err(BuildingError::Both),
        (true, false, None) => Err(BuildingError::NoLevel(floors(building)?)),
        (true, false, Some(k)) => at_level(building, k),
        (_, true, None) => Ok(floor.to_vec()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A three-storey shear building's first two modes (hand-worked shapes
    /// normalised to 1 at the roof): floor 2 of mode 1 takes Γφ = 1.25 ×
    /// 0.8 = 1.0, of mode 2 −0.35 × −0.5 = 0.175.
    #[test]
    fn a_level_takes_each_modes_share_at_that_floor() {
        let modes: Vec<ShapedMode> = ["0.5,0.05,1.25,0.45,0.8,1", "0.18,0.05,-0.35,1,-0.5,-1"]
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        assert_eq!(floors(&modes), Ok(3));
        let two = at_level(&modes, 2).unwrap();
        assert_eq!(two[0].gamma_phi, 1.25 * 0.8);
        assert_eq!(two[1].gamma_phi, -0.35 * -0.5);
        assert_eq!((two[0].period_s, two[1].zeta), (0.5, 0.05));
        assert_eq!(modes[0].to_string(), "0.5,0.05,1.25,0.45,0.8,1");
        assert_eq!(
            at_level(&modes, 4),
            Err(BuildingError::Level {
                level: 4,
                floors: 3
            })
        );
        let uneven = vec![modes[0].clone(), "0.2,0.05,1,1".parse().unwrap()];
        assert!(matches!(
            at_level(&uneven, 1),
            Err(BuildingError::Floors {
                mode: 2,
                got: 1,
                want: 3
            })
        ));
        assert!("0.5,0.05,1.3".parse::<ShapedMode>().is_err());
        // One of --floor or --building with --level.
        let floor = vec!["0.5,0.05,1.3".parse().unwrap()];
        assert_eq!(floor_modes(&floor, &[], None).unwrap(), floor);
        assert_eq!(floor_modes(&[], &modes, Some(2)).unwrap(), two);
        assert_eq!(
            floor_modes(&floor, &modes, Some(2)),
            Err(BuildingError::Both)
        );
        assert_eq!(floor_modes(&[], &[], Some(2)), Err(BuildingError::Alone));
        assert!(floor_modes(&[], &modes, None).is_err());
    }
}
