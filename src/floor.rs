//! A block on a building's floor: the floor's absolute acceleration from a
//! ground record, through a linear building given by a few modes (pure;
//! docs/MODEL.md §16).
//!
//! Mode k of the building (period T_k, damping ratio ζ_k, and Γφ_k, its
//! participation factor times its shape at the floor) responds to the
//! ground as the oscillator `D̈ + 2ζωḊ + ω²D = −a_g` of [`crate::sdof`],
//! scaled by Γφ_k. The floor's absolute acceleration is the ground's plus
//! the modes' relative accelerations,
//!
//! ```text
//! a_f(t) = a_g(t) + Σ_k Γφ_k · D̈_k(t),   D̈_k = −a_g − 2ζ_k ω_k Ḋ_k − ω_k² D_k,
//! ```
//!
//! each D_k stepped exactly for the piecewise-linear record. The building
//! is linear, so a ground record scaled by λ gives the floor motion scaled
//! by λ: the IDA runs on the floor motion unchanged.

use std::fmt;
use std::str::FromStr;

use crate::sdof::{self, SdofError};

/// Sub-samples per shortest modal period at least: the floor motion is
/// sampled at the record's step cut into n equal parts, n the smallest
/// integer with Δt/n ≤ T_min/40 (at most [`MAX_SUBSTEPS`]). Taken as linear
/// between its samples, as every record is, a harmonic of period T sampled
/// every h is then off by at most 1 − cos(πh/T) ≤ 0.31 % of its amplitude.
pub const SAMPLES_PER_PERIOD: f64 = 40.0;

/// After the record the ground is still but the building rings on: the
/// floor motion goes on until the slowest-decaying mode that moves the
/// floor (Γφ ≠ 0) has decayed to this share of its amplitude, e^(−ζωt).
pub const RING_DOWN: f64 = 0.01;

/// The longest the free vibration after the record is followed (s): an
/// undamped or barely damped mode is cut there.
pub const MAX_RING_S: f64 = 60.0;

/// The most sub-samples a record step is cut into (modes shorter than 16
/// record steps over 40 are sampled more coarsely; they respond almost
/// quasi-statically and carry little of the floor's motion).
pub const MAX_SUBSTEPS: usize = 16;

/// One mode of a linear building, as seen at the floor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mode {
    /// Natural period (s), positive.
    pub period_s: f64,
    /// Damping ratio, in [0, 1).
    pub zeta: f64,
    /// The mode's participation factor times its shape at the floor, Γφ
    /// (dimensionless, any sign: a higher mode's is often negative).
    pub gamma_phi: f64,
}

/// The modal periods accepted (s): beyond them the floor's response is
/// the ground's (a rigid building) or nothing, and the arithmetic only
/// adds noise (a period of 1e20 s once gave PFA/PGA = 30,383, one of
/// 1e-200 s a NaN blamed on the record).
pub const PERIOD_RANGE_S: (f64, f64) = (1e-3, 100.0);

/// The largest |Γφ| accepted.
pub const GAMMA_PHI_MAX: f64 = 10.0;

/// A linear building seen at one floor: one or a few modes, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct Building {
    modes: Vec<Mode>,
}

/// Why a building or its floor motion cannot be had.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FloorError {
    #[error("a floor needs at least one mode (T, ζ, Γφ)")]
    NoModes,
    #[error(
        "mode {mode}: period T = {} s: a building's modal period lies within {}–{} s",
        crate::decimal::shortest(*period),
        PERIOD_RANGE_S.0,
        PERIOD_RANGE_S.1
    )]
    Period { mode: usize, period: f64 },
    #[error("mode {mode}: damping ratio ζ = {} must be in [0, 1)", crate::decimal::shortest(*zeta))]
    Damping { mode: usize, zeta: f64 },
    #[error(
        "mode {mode}: Γφ = {}: a mode's participation factor times its shape at a floor \
         is of order 1 (1.2–1.6 at a roof in the first mode); |Γφ| ≤ {GAMMA_PHI_MAX} is accepted",
        crate::decimal::shortest(*gamma_phi)
    )]
    GammaPhi { mode: usize, gamma_phi: f64 },
    #[error(
        "mode {mode} repeats mode {of} (T, ζ, Γφ all equal): each mode once (a repeated mode is \
         summed twice, doubling its share of the floor's motion)"
    )]
    Repeated { mode: usize, of: usize },
    #[error("`{0}`: a mode is T,ZETA,GAMMA_PHI (period in s, damping ratio, participation × shape at the floor), e.g. 0.5,0.05,1.3")]
    Syntax(String),
    #[error(transparent)]
    Step(#[from] SdofError),
}

impl Building {
    /// A building from its modes (numbered from 1 in messages), each
    /// checked: T in [`PERIOD_RANGE_S`], ζ in [0, 1), |Γφ| ≤ [`GAMMA_PHI_MAX`].
    pub fn new(modes: Vec<Mode>) -> Result<Building, FloorError> {
        if modes.is_empty() {
            return Err(FloorError::NoModes);
        }
        for (i, m) in modes.iter().enumerate() {
            let mode = i + 1;
            if !(PERIOD_RANGE_S.0..=PERIOD_RANGE_S.1).contains(&m.period_s) {
                return Err(FloorError::Period {
                    mode,
                    period: m.period_s,
                });
            }
            if !(0.0..1.0).contains(&m.zeta) {
                return Err(FloorError::Damping { mode, zeta: m.zeta });
            }
            if m.gamma_phi.is_nan() || m.gamma_phi.abs() > GAMMA_PHI_MAX {
                return Err(FloorError::GammaPhi {
                    mode,
                    gamma_phi: m.gamma_phi,
                });
            }
            if let Some(j) = modes[..i].iter().position(|o| o == m) {
                return Err(FloorError::Repeated { mode, of: j + 1 });
            }
        }
        Ok(Building { modes })
    }

    pub fn modes(&self) -> &[Mode] {
        &self.modes
    }

    /// Whether the floor moves as the ground does (every Γφ is 0: a node
    /// of every mode).
    pub fn moves_as_ground(&self) -> bool {
        self.modes.iter().all(|m| m.gamma_phi == 0.0)
    }

    /// Sub-samples per record step for a record sampled every `dt_s`.
    pub fn substeps(&self, dt_s: f64) -> usize {
        let t_min = self
            .modes
            .iter()
            .map(|m| m.period_s)
            .fold(f64::INFINITY, f64::min);
        let n = (dt_s * SAMPLES_PER_PERIOD / t_min).ceil();
        if n.is_finite() && n >= 1.0 {
            (n as usize).min(MAX_SUBSTEPS)
        } else {
            1
        }
    }

    /// How long the floor moves on after the record (s): until every mode
    /// with Γφ ≠ 0 has decayed to [`RING_DOWN`] (at most [`MAX_RING_S`]).
    pub fn ring_s(&self) -> f64 {
        self.modes
            .iter()
            .filter(|m| m.gamma_phi != 0.0)
            .map(|m| {
                let decay = m.zeta * std::f64::consts::TAU / m.period_s;
                (-RING_DOWN.ln() / decay).min(MAX_RING_S)
            })
            .fold(0.0, f64::max)
    }

    /// The floor's absolute acceleration under the ground record `accel`
    /// (g, sampled every `dt_s`, the building at rest at its first sample),
    /// in g, sampled every `dt_s / n` with n = [`Building::substeps`], and
    /// on after the record (the ground still) for [`Building::ring_s`].
    pub fn floor_motion(&self, accel: &[f64], dt_s: f64) -> Result<FloorMotion, FloorError> {
        let n = self.substeps(dt_s);
        let ring = if accel.is_empty() {
            0
        } else {
            (self.ring_s() / dt_s).ceil() as usize
        };
        let still = std::iter::repeat_n(0.0, ring);
        let ground: Vec<f64> = accel.iter().copied().chain(still).collect();
        let accel = &ground[..];
        let h = dt_s / n as f64;
        let steps = self
            .modes
            .iter()
            .map(|m| sdof::Step::new(m.period_s, m.zeta, h))
            .collect::<Result<Vec<_>, _>>()?;
        let omegas: Vec<(f64, f64)> = self
            .modes
            .iter()
            .map(|m| {
                let w = std::f64::consts::TAU / m.period_s;
                (2.0 * m.zeta * w, w * w)
            })
            .collect();
        let floor = |ground: f64, states: &[(f64, f64)]| {
            let mut a = ground;
            for ((m, &(c, k)), &(u, v)) in self.modes.iter().zip(&omegas).zip(states) {
                a += m.gamma_phi * (-ground - c * v - k * u);
            }
            a
        };
        let mut states = vec![(0.0, 0.0); self.modes.len()];
        let mut out = Vec::with_capacity((accel.len().saturating_sub(1)) * n + 1);
        if let Some(&first) = accel.first() {
            out.push(floor(first, &states));
        }
        for w in accel.windows(2) {
            let slope = (w[1] - w[0]) / n as f64;
            for j in 0..n {
                let a0 = w[0] + slope * j as f64;
                let a1 = if j + 1 == n { w[1] } else { a0 + slope };
                for (s, step) in states.iter_mut().zip(&steps) {
                    *s = step.advance(*s, a0, a1);
                }
                out.push(floor(a1, &states));
            }
        }
        let peak = |a: &[f64]| a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let ground_peak = peak(accel);
        Ok(FloorMotion {
            // A record of zeros moves no floor: its amplification is taken as 1.
            pfa_over_pga: if ground_peak > 0.0 {
                peak(&out) / ground_peak
            } else {
                1.0
            },
            accel_g: out,
            dt_s: h,
            substeps: n,
        })
    }
}

/// A floor's absolute acceleration history.
#[derive(Debug, Clone, PartialEq)]
pub struct FloorMotion {
    /// Samples (g), the first at the record's first, the last after the
    /// building's ring-down.
    pub accel_g: Vec<f64>,
    /// The floor's peak over the ground record's, PFA/PGA (1 for a record
    /// of zeros): the same at every scale of the record.
    pub pfa_over_pga: f64,
    /// Its step (s): the record's over `substeps`.
    pub dt_s: f64,
    pub substeps: usize,
}

impl FromStr for Mode {
    type Err = FloorError;

    /// `T,ZETA,GAMMA_PHI`, e.g. `0.5,0.05,1.3`; the values are checked by
    /// [`Building::new`].
    fn from_str(s: &str) -> Result<Mode, FloorError> {
        let parts: Vec<&str> = s.split(',').map(str::trim).collect();
        let [t, z, g] = parts[..] else {
            return Err(FloorError::Syntax(s.to_string()));
        };
        let num = |x: &str| {
            x.parse::<f64>()
                .map_err(|_| FloorError::Syntax(s.to_string()))
        };
        Ok(Mode {
            period_s: num(t)?,
            zeta: num(z)?,
            gamma_phi: num(g)?,
        })
    }
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{}", self.period_s, self.zeta, self.gamma_phi)
    }
}

impl fmt::Display for Building {
    /// The modes as `--floor` takes them, separated by `; `.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, m) in self.modes.iter().enumerate() {
            if i > 0 {
                f.write_str("; ")?;
            }
            write!(f, "{m}")?;
        }
        Ok(())
    }
}

/// A mode as `[T, ζ, Γφ]` or as the text `T,ZETA,GAMMA_PHI`; the values
/// are checked by [`Building::new`].
impl<'de> serde::Deserialize<'de> for Mode {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Given {
            Numbers(f64, f64, f64),
            Text(String),
        }
        let given = Given::deserialize(d).map_err(|_| {
            serde::de::Error::custom(
                "floor: a mode is three numbers [T, ζ, Γφ] (period in s, damping ratio, \
                 participation at the floor) or the text \"T,ZETA,GAMMA_PHI\", and the floor a \
                 list of modes: [[0.5, 0.05, 1.3]]",
            )
        })?;
        match given {
            Given::Numbers(period_s, zeta, gamma_phi) => Ok(Mode {
                period_s,
                zeta,
                gamma_phi,
            }),
            Given::Text(t) => t.parse().map_err(serde::de::Error::custom),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn one(period_s: f64, zeta: f64, gamma_phi: f64) -> Building {
        Building::new(vec![Mode {
            period_s,
            zeta,
            gamma_phi,
        }])
        .unwrap()
    }

    /// Steady state under a ground acceleration A sin Ωt: the mode's relative
    /// acceleration is A r²/(1 − r² + 2iζr) (r = Ω/ω), so the floor's
    /// amplitude is A |1 + Γφ r²/(1 − r² + 2iζr)|; with Γφ = 1 it is the
    /// classical transmissibility √((1 + (2ζr)²)/((1 − r²)² + (2ζr)²)).
    /// Sampled at 1/1000 of the forcing period, the piecewise-linear sine
    /// and the sampled peak each miss by about (π/1000)²/2 = 5e-6: 1e-4.
    #[test]
    fn harmonic_ground_gives_the_steady_state_amplification() {
        let (period, zeta) = (0.5, 0.05);
        let w = TAU / period;
        for gamma_phi in [1.0, 1.3, -0.4] {
            for r in [0.3, 1.0, 2.5] {
                let big_w = r * w;
                let dt = TAU / big_w / 1000.0;
                let settle = (12.0 * 10f64.ln() / (zeta * w) / dt) as usize;
                let n = settle + 3000;
                let ground: Vec<f64> = (0..n).map(|k| (big_w * k as f64 * dt).sin()).collect();
                let b = one(period, zeta, gamma_phi);
                assert_eq!(b.substeps(dt), 1);
                let f = b.floor_motion(&ground, dt).unwrap();
                assert_eq!(f.accel_g.len(), n + (b.ring_s() / dt).ceil() as usize);
                let amplitude = f.accel_g[settle..n]
                    .iter()
                    .fold(0.0f64, |m, a| m.max(a.abs()));
                // 1 + Γφ r²/(1 − r² + 2iζr) = (x + iy)/(d + iy).
                let (d, y) = (1.0 - r * r, 2.0 * zeta * r);
                let x = d + gamma_phi * r * r;
                let exact = ((x * x + y * y) / (d * d + y * y)).sqrt();
                if gamma_phi == 1.0 {
                    let tr = ((1.0 + y * y) / (d * d + y * y)).sqrt();
                    assert!((exact / tr - 1.0).abs() < 1e-14);
                }
                assert!(
                    (amplitude / exact - 1.0).abs() < 1e-4,
                    "Γφ {gamma_phi}, r {r}: {amplitude} vs {exact}"
                );
            }
        }
    }

    /// A record from rest with kinks (slope changes Δs at its samples) through a very
    /// stiff building: each kink starts a transient of relative
    /// acceleration at most |Δs|/ω_d, decaying as e^{−ζωt}; the
    /// quasi-static part −ä_g/ω² is zero between kinks. So |a_f − a_g| ≤
    /// |Γφ| max|Δs| / ω_d / (1 − e^{−ζωΔt}), about 0.2 % of the peak here
    /// at T = 2 ms, and it falls as T does.
    #[test]
    fn a_stiff_building_gives_the_ground_back() {
        let dt = 0.01;
        let ground: Vec<f64> = (0..3000)
            .map(|k| {
                let t = k as f64 * dt;
                0.3 * (5.0 * t).sin() * (-0.1 * t).exp() + 0.1 * (17.0 * t).sin()
            })
            .collect();
        // The record starts from rest at a_g = 0: its first slope is a kink too.
        let max_kink = ground
            .windows(3)
            .map(|w| ((w[2] - w[1]) - (w[1] - w[0])).abs() / dt)
            .fold((ground[1] - ground[0]).abs() / dt, f64::max);
        let mut last = f64::INFINITY;
        for period in [0.02, 0.005, 0.002] {
            let (zeta, gamma_phi) = (0.05, 1.4);
            let b = one(period, zeta, gamma_phi);
            let f = b.floor_motion(&ground, dt).unwrap();
            let n = f.substeps;
            let w = TAU / period;
            let wd = w * (1.0f64 - zeta * zeta).sqrt();
            let bound = gamma_phi * max_kink / wd / (1.0 - (-zeta * w * dt).exp());
            let err = ground
                .iter()
                .enumerate()
                .map(|(i, g)| (f.accel_g[i * n] - g).abs())
                .fold(0.0f64, f64::max);
            assert!(err <= bound, "T {period}: {err} > {bound}");
            assert!(err < last, "T {period}: {err} not below {last}");
            last = err;
        }
        assert!(last < 0.003 * 0.4, "{last}");
    }

    /// Γφ = 0 at the floor (a node of every mode): the floor moves with the
    /// ground, at the record's samples exactly and linearly between them.
    #[test]
    fn a_node_of_every_mode_gives_the_ground() {
        let dt = 0.02;
        let ground: Vec<f64> = (0..500).map(|k| (0.37 * k as f64).sin() * 0.2).collect();
        let b = Building::new(vec![
            Mode {
                period_s: 0.3,
                zeta: 0.05,
                gamma_phi: 0.0,
            },
            Mode {
                period_s: 0.1,
                zeta: 0.02,
                gamma_phi: 0.0,
            },
        ])
        .unwrap();
        let f = b.floor_motion(&ground, dt).unwrap();
        assert_eq!(f.substeps, 8);
        assert_eq!(f.dt_s, dt / 8.0);
        for (i, g) in ground.iter().enumerate() {
            assert_eq!(f.accel_g[i * 8], *g);
        }
        let mid = f.accel_g[4];
        assert!((mid - 0.5 * (ground[0] + ground[1])).abs() < 1e-16);
    }

    /// Two modes superpose: the floor motion of a two-mode building is the
    /// ground plus each one-mode building's contribution (linearity), and
    /// scaling the ground scales the floor motion.
    #[test]
    fn modes_superpose_and_the_floor_scales_with_the_ground() {
        let dt = 0.01;
        let ground: Vec<f64> = (0..800)
            .map(|k| (0.21 * k as f64).sin() * (0.013 * k as f64).cos())
            .collect();
        let m1 = Mode {
            period_s: 1.5,
            zeta: 0.05,
            gamma_phi: 1.3,
        };
        let m2 = Mode {
            period_s: 0.5,
            zeta: 0.05,
            gamma_phi: -0.4,
        };
        let both = Building::new(vec![m1, m2]).unwrap();
        let f = both.floor_motion(&ground, dt).unwrap();
        let f1 = Building::new(vec![m1])
            .unwrap()
            .floor_motion(&ground, dt)
            .unwrap();
        let f2 = Building::new(vec![m2])
            .unwrap()
            .floor_motion(&ground, dt)
            .unwrap();
        assert_eq!((f.substeps, f1.substeps, f2.substeps), (1, 1, 1));
        for (i, g) in ground.iter().enumerate() {
            let sum = f1.accel_g[i] + f2.accel_g[i] - g;
            assert!((f.accel_g[i] - sum).abs() < 1e-13, "{i}");
        }
        let scaled: Vec<f64> = ground.iter().map(|g| 2.5 * g).collect();
        let fs = both.floor_motion(&scaled, dt).unwrap();
        for (a, b) in fs.accel_g.iter().zip(&f.accel_g) {
            assert!((a - 2.5 * b).abs() < 1e-13);
        }
    }

    /// After the record the building rings on, the ground still: the floor
    /// motion lasts ln(1/0.01)/(ζω) longer (by hand: 7.33 s for T = 0.5 s,
    /// ζ = 5 %), and its envelope decays as e^(−ζωt): the peak over the
    /// last period is within a factor 1.5 of 1 % of the peak over the first
    /// period after the record, times e^(ζωT) (one period of decay apart).
    #[test]
    fn the_building_rings_down_after_the_record() {
        let (period, zeta, dt) = (0.5, 0.05, 0.005);
        let w = TAU / period;
        let b = one(period, zeta, 1.3);
        let ring = (100f64).ln() / (zeta * w);
        assert!((b.ring_s() - 7.329).abs() < 1e-3, "{}", b.ring_s());
        let ground: Vec<f64> = (0..2000).map(|k| (9.0 * k as f64 * dt).sin()).collect();
        let f = b.floor_motion(&ground, dt).unwrap();
        let extra = (ring / dt).ceil() as usize;
        assert_eq!(f.accel_g.len(), ground.len() + extra);
        let per = (period / dt) as usize;
        let peak = |a: &[f64]| a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let first = peak(&f.accel_g[ground.len()..ground.len() + per]);
        let last = peak(&f.accel_g[f.accel_g.len() - per..]);
        let expected = first * RING_DOWN * (zeta * w * period).exp();
        assert!(first > 0.1, "the building rings: {first}");
        assert!(
            last < 1.5 * expected && last > expected / 1.5,
            "{last} vs {expected}"
        );
        // A floor at a node of every mode does not ring: no samples added.
        assert_eq!(one(0.5, 0.05, 0.0).ring_s(), 0.0);
        // An undamped mode rings at most MAX_RING_S.
        assert_eq!(one(0.5, 0.0, 1.0).ring_s(), MAX_RING_S);
    }

    #[test]
    fn modes_are_parsed_and_checked() {
        let m: Mode = "0.5, 0.05, 1.3".parse().unwrap();
        assert_eq!(
            m,
            Mode {
                period_s: 0.5,
                zeta: 0.05,
                gamma_phi: 1.3
            }
        );
        assert_eq!(m.to_string(), "0.5,0.05,1.3");
        for bad in ["0.5,0.05", "a,b,c", "0.5,0.05,1,2", ""] {
            assert!(
                matches!(bad.parse::<Mode>(), Err(FloorError::Syntax(_))),
                "{bad}"
            );
        }
        let build = |t, z, g| {
            Building::new(vec![Mode {
                period_s: t,
                zeta: z,
                gamma_phi: g,
            }])
        };
        assert_eq!(
            build(0.0, 0.05, 1.0),
            Err(FloorError::Period {
                mode: 1,
                period: 0.0
            })
        );
        assert_eq!(
            build(0.5, 1.0, 1.0),
            Err(FloorError::Damping { mode: 1, zeta: 1.0 })
        );
        assert!(matches!(
            build(0.5, 0.05, f64::NAN),
            Err(FloorError::GammaPhi { mode: 1, .. })
        ));
        assert_eq!(Building::new(vec![]), Err(FloorError::NoModes));
        assert_eq!(one(0.001, 0.05, 1.0).substeps(0.02), MAX_SUBSTEPS);
        // Once accepted: 1e20 s gave PFA/PGA = 30,383, 1e-200 s a NaN
        // blamed on the record, and Γφ = 1e300 went through.
        for t in [1e20, 1e8, 1e-200, 9e-4] {
            assert!(
                matches!(build(t, 0.05, 1.0), Err(FloorError::Period { .. })),
                "{t}"
            );
        }
        for g in [1e300, -11.0] {
            assert!(
                matches!(build(0.5, 0.05, g), Err(FloorError::GammaPhi { .. })),
                "{g}"
            );
        }
        assert!(build(100.0, 0.05, -10.0).is_ok());
    }
}
