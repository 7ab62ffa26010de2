//! The intensity levels of an IDA: a grid of η values from `eta_max` down
//! to `eta_min`, log- or linearly spaced.
//!
//! Default grid ([`ImGrid::default`]): 200 levels log-spaced in η from 1
//! (the uplift threshold of the linearised model: nothing moves at η ≥ 1)
//! down to 10⁻³, ratio 10^(−3/200) ≈ 0.966 between levels (3.4 % steps).

use crate::physics::PhysicsError;

/// Most levels a grid may have: each level is a simulation per record and
/// block, and 10⁵ levels are already 1,000 times the paper's 100–200.
/// Larger counts are refused before anything is allocated.
pub const MAX_LEVELS: usize = 100_000;

/// How the η levels are spaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Spacing {
    /// Equal ratios between levels.
    Log,
    /// Equal differences between levels.
    Linear,
}

impl crate::label::Label for Spacing {
    const ALL: &'static [Self] = &[Spacing::Log, Spacing::Linear];
    const WHAT: &'static str = "spacing";
    fn label(self) -> &'static str {
        match self {
            Spacing::Log => "log",
            Spacing::Linear => "linear",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Spacing::Log => "equal ratios between levels",
            Spacing::Linear => "equal differences between levels",
        }
    }
}

crate::deserialize_by_label!(Spacing);

/// A grid of intensity levels, from `eta_max` (exclusive) down to `eta_min`
/// (inclusive), `count` levels.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ImGrid {
    pub eta_max: f64,
    pub eta_min: f64,
    pub count: usize,
    pub spacing: Spacing,
}

/// The search's default tolerance in η: a capacity refined between two
/// levels until they are this close (`rocking capacity --tol`).
pub const DEFAULT_TOL: f64 = 1e-4;

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
        if self.eta_min < crate::physics::ETA_MIN {
            return Err(PhysicsError::BadInput(format!(
                "IM grid: η_min = {:e} is below {:e}, where no run goes",
                self.eta_min,
                crate::physics::ETA_MIN
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

    /// Whether `tol` (Δη) can be a capacity's refinement on this grid:
    /// below its whole span η_max − η_min. One as wide (10 for 1e-4, say)
    /// is no refinement but a slip, refused; one wider than the grid's
    /// gaps merely leaves the levels' own bracket (a grid finer than the
    /// paper's 1e-4 needs none).
    pub fn check_tol(&self, tol: f64) -> Result<(), PhysicsError> {
        let span = self.eta_max - self.eta_min;
        if tol >= span {
            return Err(PhysicsError::BadInput(format!(
                "a refinement of Δη = {} is as wide as the grid itself (η from {} to {}): give \
                 the width a capacity is refined to (the paper's is 1e-4)",
                crate::decimal::shortest(tol),
                crate::decimal::shortest(self.eta_min),
                crate::decimal::shortest(self.eta_max),
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Δη as wide as the grid (10, or 0.999 for η from 0.001 to 1) is a
    /// slip and refused; a coarse one (0.05) leaves the levels' bracket,
    /// and the paper's 1e-4 on a grid finer than it is no error (it was
    /// refused on 10,000 linear levels).
    #[test]
    fn a_refinement_as_wide_as_the_grid_is_refused() {
        let g = ImGrid::default();
        for tol in [1e-4, 0.05, 0.5] {
            assert!(g.check_tol(tol).is_ok(), "{tol}");
        }
        for tol in [0.999, 10.0] {
            let e = g.check_tol(tol).unwrap_err().to_string();
            assert!(e.contains("as wide as the grid itself"), "{tol}: {e}");
        }
        let fine = ImGrid {
            count: 10_000,
            spacing: Spacing::Linear,
            ..ImGrid::default()
        };
        assert!(fine.check_tol(1e-4).is_ok());
    }

    #[test]
    fn a_grid_below_the_smallest_eta_is_refused() {
        let grid = |eta_min| ImGrid {
            eta_min,
            ..ImGrid::default()
        };
        assert!(grid(1e-12).levels().is_ok());
        let e = grid(1e-13).levels().unwrap_err().to_string();
        assert!(e.contains("η_min = 1e-13 is below 1e-12"), "{e}");
    }

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
