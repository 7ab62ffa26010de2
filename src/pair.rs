//! A record pair: two orthogonal horizontal components of one station, and
//! the component in any direction between them (pure; docs/MODEL.md §18).
//!
//! A planar block whose rocking plane makes the angle θ with component a
//! (towards b) feels `a(θ, t) = a(t) cos θ + b(t) sin θ`. The two
//! components are given at one sample step; the shorter is taken as 0 after
//! its end (as a record is still after its last sample), and the rotated
//! component is as long as the components that enter it: at θ = 0° it is
//! component a itself, at 90° component b itself, bit for bit.

/// Two orthogonal horizontal components at one sample step.
#[derive(Debug, Clone, PartialEq)]
pub struct Pair {
    /// Component a (g).
    pub a: Vec<f64>,
    /// Component b (g), 90° from a.
    pub b: Vec<f64>,
    /// The sample step of both (s).
    pub dt_s: f64,
}

/// Why two records are not a pair.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PairError {
    #[error(
        "the components' sample steps differ ({a} s and {b} s): a pair is two components \
         recorded together; resample one to the other's step first"
    )]
    Step { a: f64, b: f64 },
    #[error("a component has no samples")]
    Empty,
    #[error(
        "the two components are one motion (every sample equal): a pair is the two horizontal \
         components of a recording, 90° apart (…000 and …090, say); give the other one"
    )]
    Same,
}

/// Relative difference of two steps taken as one (the AT2 headers' DT is
/// written to a few digits).
const SAME_STEP: f64 = 1e-9;

impl Pair {
    /// Components `a` and `b` sampled at `dt_a` and `dt_b` (s): refused
    /// when the steps differ.
    pub fn new(a: Vec<f64>, dt_a: f64, b: Vec<f64>, dt_b: f64) -> Result<Pair, PairError> {
        if a.is_empty() || b.is_empty() {
            return Err(PairError::Empty);
        }
        if (dt_a - dt_b).abs() > SAME_STEP * dt_a.abs().max(dt_b.abs()) {
            return Err(PairError::Step { a: dt_a, b: dt_b });
        }
        // One file given twice: its RotD would be the component's peak
        // scaled by √2 at 45°, read as a pair's.
        let n = a.len().min(b.len());
        let rest_zero = |v: &[f64]| v[n..].iter().all(|&x| x == 0.0);
        if a[..n] == b[..n] && rest_zero(&a) && rest_zero(&b) {
            return Err(PairError::Same);
        }
        Ok(Pair { a, b, dt_s: dt_a })
    }

    /// The samples of both components, the shorter padded with zeros to
    /// the longer's length.
    pub fn padded(&self) -> (Vec<f64>, Vec<f64>) {
        let n = self.a.len().max(self.b.len());
        let pad = |v: &[f64]| {
            let mut v = v.to_vec();
            v.resize(n, 0.0);
            v
        };
        (pad(&self.a), pad(&self.b))
    }

    /// The component at `theta_deg` from a towards b: `a cos θ + b sin θ`,
    /// with cos and sin exact at multiples of 90° (θ = 0° gives a, 90° b,
    /// 180° −a, 270° −b, bit for bit).
    pub fn rotated(&self, theta_deg: f64) -> Vec<f64> {
        let (c, s) = cos_sin_deg(theta_deg);
        let take = |v: &[f64], k: f64| -> Vec<f64> { v.iter().map(|x| k * x).collect() };
        match (c, s) {
            (_, 0.0) => take(&self.a, c),
            (0.0, _) => take(&self.b, s),
            _ => {
                let (a, b) = self.padded();
                a.iter().zip(&b).map(|(x, y)| c * x + s * y).collect()
            }
        }
    }
}

/// The name of a pair's component at `theta_deg`, `<a>@<θ>` (`a` the id of
/// the pair's first component): `capacity --pair`'s, `--direct`'s and a
/// study's records.
pub fn angled_id(a: &str, theta_deg: f64) -> String {
    format!("{a}@{theta_deg}")
}

/// The first component's id and the angle of an [`angled_id`]; `None` for
/// a record that is not a pair's component at an angle.
pub fn split_angled_id(id: &str) -> Option<(&str, f64)> {
    let (a, theta) = id.rsplit_once('@')?;
    Some((a, theta.parse().ok()?))
}

/// cos θ and sin θ of an angle in degrees, exact (0 and ±1) at multiples
/// of 90°, and those of θ + 180° the exact negation of θ's.
pub fn cos_sin_deg(theta_deg: f64) -> (f64, f64) {
    let r = theta_deg.rem_euclid(360.0);
    if r >= 180.0 {
        // θ + 180° is θ's negation exactly: its component is −(a cos θ + b sin θ).
        let (c, s) = cos_sin_deg(r - 180.0);
        return (-c, -s);
    }
    if r == 0.0 {
        (1.0, 0.0)
    } else if r == 90.0 {
        (0.0, 1.0)
    } else {
        let (s, c) = r.to_radians().sin_cos();
        (c, s)
    }
}

/// The angles of a range over [0°, 180°) every `step_deg`: 0, step, …,
/// below 180 (θ + 180° is θ's mirror image, which a symmetric block does
/// not tell apart).
pub fn angles(step_deg: f64) -> Vec<f64> {
    let n = (180.0 / step_deg).ceil() as usize;
    (0..n)
        .map(|k| k as f64 * step_deg)
        .filter(|&t| t < 180.0)
        .collect()
}

/// Which orientations of the records a fragility is over.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Orientation {
    /// Each recorded component as it was recorded: the paper's.
    #[default]
    AsRecorded,
    /// The block's plane uniform over [0°, 180°): every pair at every
    /// angle of the step, each the same weight.
    Random,
    /// Each pair at its worst angle: the smallest capacity over the angles.
    Worst,
}

impl crate::label::Label for Orientation {
    const ALL: &'static [Self] = &[
        Orientation::AsRecorded,
        Orientation::Random,
        Orientation::Worst,
    ];
    const WHAT: &'static str = "orientation";
    fn label(self) -> &'static str {
        match self {
            Orientation::AsRecorded => "as-recorded",
            Orientation::Random => "random",
            Orientation::Worst => "worst",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Orientation::AsRecorded => "each recorded component as recorded (the paper's)",
            Orientation::Random => {
                "the block facing any direction: every pair at every --angle-step over \
                 [0°, 180°), equally weighted"
            }
            Orientation::Worst => "each pair at the angle of its smallest capacity",
        }
    }
    fn aliases(self) -> &'static [&'static str] {
        match self {
            Orientation::AsRecorded => &["as_recorded"],
            _ => &[],
        }
    }
}

crate::deserialize_by_label!(Orientation);

/// Which component of a record pair a hazard curve is of: the recorded
/// one, or RotD50, the ground-motion models' (NGA-West2 and after).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Component {
    AsRecorded,
    #[serde(rename = "rotd50")]
    RotD50,
}

impl crate::label::Label for Component {
    const ALL: &'static [Self] = &[Component::AsRecorded, Component::RotD50];
    const WHAT: &'static str = "component";
    fn label(self) -> &'static str {
        match self {
            Component::AsRecorded => "as-recorded",
            Component::RotD50 => "rotd50",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Component::AsRecorded => "the hazard is of a recorded component, as the fragility",
            Component::RotD50 => {
                "the hazard is RotD50 (the ground-motion models'): with --direct the fragility \
                 is stated in RotD50 of the hazard's measure; without, the mismatch is warned of"
            }
        }
    }
}

crate::deserialize_by_label!(Component);

/// The angle step (°) of the random and worst orientations when none is
/// asked: for the two blocks of the angle study the random-orientation
/// fragility's median and β at 10° lie within 0.8 % of those at 1° (at
/// 15°, up to 1.8 % and 4.2 %), for 18 angles a pair (docs/BENCHMARKS.md,
/// the `orientations` section).
pub const ANGLE_STEP_DEG: f64 = 10.0;

/// The angle steps (°) a pair may be run at, by every door: finer than a
/// degree is finer than a pair's RotD (180 angles), and every motion is
/// held at once (1e-9° asked for 1.8e11 motions, 0.01° for about 80 GB).
pub const ANGLE_STEPS_DEG: std::ops::RangeInclusive<f64> = 1.0..=180.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_axes_give_the_components_themselves() {
        let p = Pair::new(vec![0.1, -0.0, 0.3], 0.01, vec![0.2, 0.5], 0.01).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&p.rotated(0.0)), bits(&p.a));
        assert_eq!(bits(&p.rotated(360.0)), bits(&p.a));
        assert_eq!(bits(&p.rotated(90.0)), bits(&p.b));
        assert_eq!(p.rotated(180.0), vec![-0.1, 0.0, -0.3]);
        assert_eq!(p.rotated(-90.0), vec![-0.2, -0.5]);
        let minus: Vec<f64> = p.rotated(37.5).iter().map(|x| -x).collect();
        assert_eq!(p.rotated(217.5), minus);
        // Between the axes both enter, b zero after its end.
        let r = p.rotated(45.0);
        let h = std::f64::consts::FRAC_1_SQRT_2;
        assert_eq!(r.len(), 3);
        assert!((r[0] - h * 0.3).abs() < 1e-15 && (r[2] - h * 0.3).abs() < 1e-15);
        assert!((r[1] - h * 0.5).abs() < 1e-15);
    }

    /// One file given as both components (`ims --record A --pair A`) gave
    /// a RotD100 PGA √2 times the component's without a word; it is
    /// refused. Components that differ anywhere are a pair.
    #[test]
    fn one_motion_twice_is_not_a_pair() {
        let a = vec![0.1, -0.2, 0.3];
        let e = Pair::new(a.clone(), 0.01, a.clone(), 0.01).unwrap_err();
        assert!(matches!(e, PairError::Same), "{e}");
        assert!(e.to_string().contains("one motion"), "{e}");
        // Padded with a zero it is the same motion still.
        assert!(Pair::new(a.clone(), 0.01, vec![0.1, -0.2, 0.3, 0.0], 0.01).is_err());
        assert!(Pair::new(a.clone(), 0.01, vec![0.1, -0.2, 0.3, 0.1], 0.01).is_ok());
        assert!(Pair::new(a, 0.01, vec![-0.1, 0.2, -0.3], 0.01).is_ok());
    }

    #[test]
    fn a_pair_is_recorded_at_one_step() {
        assert_eq!(
            Pair::new(vec![0.1], 0.01, vec![0.1], 0.005),
            Err(PairError::Step { a: 0.01, b: 0.005 })
        );
        assert!(Pair::new(vec![0.1], 0.01, vec![0.2], 0.01 * (1.0 + 1e-12)).is_ok());
        assert_eq!(
            Pair::new(vec![], 0.01, vec![0.1], 0.01),
            Err(PairError::Empty)
        );
        assert_eq!(angles(30.0), vec![0.0, 30.0, 60.0, 90.0, 120.0, 150.0]);
        assert_eq!(angles(1.0).len(), 180);
        assert_eq!(angles(7.0).last(), Some(&175.0));
    }
}
