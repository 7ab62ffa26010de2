//! Incremental dynamic analysis: the overturning capacity of one record
//! (pure; MODEL.md §4).
//!
//! A record is run at a sequence of intensity levels of decreasing η
//! (increasing PGA). The capacity `η_c` is the first overturning met as
//! intensity rises: the largest level at which the block overturns, even if
//! it survives at some stronger level later (resurrection; Vamvatsikos &
//! Cornell 2002). It is then refined by bisection between the last surviving
//! level and the first overturning one until the bracket is at most `tol`
//! wide in η; the reported `η_c` is the bracket's overturning end (an
//! intensity at which the block is known to overturn).
//!
//! Default grid ([`ImGrid::default`]): 200 levels log-spaced in η from 1
//! (the uplift threshold of the linearised model: nothing moves at η ≥ 1)
//! down to 10⁻³, ratio 10^(−3/200) ≈ 0.966 between levels (3.4 % steps).

use crate::physics::{simulate, Excitation, Outcome, PhysicsError, RunSpec};

/// Most levels a grid may have: each level is a simulation per record and
/// block, and 10⁵ levels are already 1,000 times the paper's 100–200.
/// Larger counts are refused before anything is allocated.
pub const MAX_LEVELS: usize = 100_000;

/// How the η levels are spaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Spacing {
    /// Equal ratios between levels.
    Log,
    /// Equal differences between levels.
    Linear,
}

/// A grid of intensity levels, from `eta_max` (exclusive) down to `eta_min`
/// (inclusive), `count` levels.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ImGrid {
    pub eta_max: f64,
    pub eta_min: f64,
    pub count: usize,
    pub spacing: Spacing,
}

impl Default for ImGrid {
    fn default() -> Self {
        ImGrid {
            eta_max: 1.0,
            eta_min: 1e-3,
            count: 200,
            spacing: Spacing::Log,
        }
    }
}

impl ImGrid {
    /// The levels, in decreasing η: `level_j` for j = 1..=count, the last
    /// exactly `eta_min`.
    pub fn levels(&self) -> Result<Vec<f64>, PhysicsError> {
        if !(self.eta_max > self.eta_min && self.eta_min > 0.0 && self.eta_max.is_finite()) {
            return Err(PhysicsError::BadInput(format!(
                "IM grid: need η_max > η_min > 0, got η_max = {}, η_min = {}",
                self.eta_max, self.eta_min
            )));
        }
        if self.count == 0 {
            return Err(PhysicsError::BadInput("IM grid: at least one level".into()));
        }
        if self.count > MAX_LEVELS {
            return Err(PhysicsError::BadInput(format!(
                "IM grid: {} levels is more than {MAX_LEVELS} (each is a simulation; the paper used 100–200)",
                self.count
            )));
        }
        let n = self.count as f64;
        Ok((1..=self.count)
            .map(|j| {
                let f = j as f64 / n;
                if j == self.count {
                    return self.eta_min;
                }
                match self.spacing {
                    Spacing::Log => self.eta_max * (self.eta_min / self.eta_max).powf(f),
                    Spacing::Linear => self.eta_max + (self.eta_min - self.eta_max) * f,
                }
            })
            .collect())
    }
}

/// Whether a run was at a grid level or a refinement point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunKind {
    Level,
    Refinement,
}

impl crate::label::Label for RunKind {
    const ALL: &'static [Self] = &[RunKind::Level, RunKind::Refinement];
    fn label(self) -> &'static str {
        match self {
            RunKind::Level => "level",
            RunKind::Refinement => "refinement",
        }
    }
}

/// One run of an IDA.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IdaPoint {
    pub eta: f64,
    pub kind: RunKind,
    pub outcome: Outcome,
}

/// The capacity of one record for one block.
#[derive(Debug, Clone, PartialEq)]
pub struct Capacity {
    /// Largest η known to overturn (within `tol` of the first overturning);
    /// `None` if the block survived every level.
    pub eta_c: Option<f64>,
    /// The bracket after refinement: the smallest η known to survive above
    /// `eta_c` (`eta_max` of the grid if the first level overturned).
    pub eta_survived: f64,
    /// The first grid level that overturned, and the last one that survived
    /// before it (the bracket before refinement).
    pub level_overturned: Option<f64>,
    pub level_survived: f64,
    /// Every run, in the order run.
    pub points: Vec<IdaPoint>,
    /// With [`Trace::AllLevels`]: how many grid levels stronger than the
    /// first overturning the block survived (resurrections).
    pub resurrections: Option<usize>,
}

/// How far to trace a record's IDA.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Trace {
    /// Stop at the first overturning (and refine): all the capacity and the
    /// horizontal statistics under the resurrection rule need.
    StopAtFirst,
    /// Also run every stronger level, to count resurrections.
    AllLevels,
}

impl Capacity {
    pub fn runs(&self) -> usize {
        self.points.len()
    }
}

/// Traces the IDA of one record up to its first overturning and refines it.
/// `run.eta` is ignored (set per level).
pub fn capacity(
    exc: &Excitation,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
) -> Result<Capacity, PhysicsError> {
    capacity_traced(exc, run, grid, tol, Trace::StopAtFirst)
}

/// [`capacity`], optionally running every level past the first overturning.
pub fn capacity_traced(
    exc: &Excitation,
    run: &RunSpec,
    grid: &ImGrid,
    tol: f64,
    trace: Trace,
) -> Result<Capacity, PhysicsError> {
    if !(tol > 0.0 && tol.is_finite()) {
        return Err(PhysicsError::BadInput(format!(
            "capacity tolerance {tol} must be positive"
        )));
    }
    let levels = grid.levels()?;
    let mut points = Vec::new();
    // A run stopped by the event cap has no verdict: refuse it rather than
    // count it as surviving.
    let at = |eta: f64| {
        let out = simulate(exc, &RunSpec { eta, ..*run })?;
        if out.stop == crate::physics::Stop::EventLimit {
            return Err(PhysicsError::BadInput(format!(
                "the run at η = {eta} hit the limit of {} events without a verdict",
                crate::physics::MAX_EVENTS
            )));
        }
        Ok(out)
    };
    let mut survived = grid.eta_max;
    for (j, &eta) in levels.iter().enumerate() {
        let outcome = at(eta)?;
        points.push(IdaPoint {
            eta,
            kind: RunKind::Level,
            outcome,
        });
        if !outcome.overturned() {
            survived = eta;
            continue;
        }
        let (level_survived, level_overturned) = (survived, eta);
        let mut over = eta;
        while survived - over > tol {
            let mid = 0.5 * (survived + over);
            if mid <= over || mid >= survived {
                break;
            }
            let outcome = at(mid)?;
            points.push(IdaPoint {
                eta: mid,
                kind: RunKind::Refinement,
                outcome,
            });
            if outcome.overturned() {
                over = mid;
            } else {
                survived = mid;
            }
        }
        let resurrections = match trace {
            Trace::StopAtFirst => None,
            Trace::AllLevels => {
                let mut survived_after = 0;
                for &eta in &levels[j + 1..] {
                    let outcome = at(eta)?;
                    points.push(IdaPoint {
                        eta,
                        kind: RunKind::Level,
                        outcome,
                    });
                    survived_after += usize::from(!outcome.overturned());
                }
                Some(survived_after)
            }
        };
        return Ok(Capacity {
            eta_c: Some(over),
            eta_survived: survived,
            level_overturned: Some(level_overturned),
            level_survived,
            points,
            resurrections,
        });
    }
    Ok(Capacity {
        eta_c: None,
        eta_survived: survived,
        level_overturned: None,
        level_survived: survived,
        points,
        resurrections: match trace {
            Trace::StopAtFirst => None,
            Trace::AllLevels => Some(0),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_grid_has_equal_ratios_and_exact_ends() {
        let g = ImGrid::default().levels().unwrap();
        assert_eq!(g.len(), 200);
        assert_eq!(*g.last().unwrap(), 1e-3);
        let r = 10f64.powf(-3.0 / 200.0);
        for w in g.windows(2) {
            assert!((w[1] / w[0] - r).abs() < 1e-12);
        }
        assert!((g[0] - r).abs() < 1e-15);
        let lin = ImGrid {
            eta_max: 1.0,
            eta_min: 0.1,
            count: 9,
            spacing: Spacing::Linear,
        }
        .levels()
        .unwrap();
        assert!((lin[0] - 0.9).abs() < 1e-15 && lin[8] == 0.1);
        assert!(ImGrid {
            eta_min: 2.0,
            ..ImGrid::default()
        }
        .levels()
        .is_err());
    }
}
