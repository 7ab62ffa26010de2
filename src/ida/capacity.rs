//! What a capacity search finds: its runs (grid levels and refinements),
//! the capacity with its brackets, and how far the IDA is traced.

use super::runs::Work;
use crate::physics::Outcome;

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

    /// The runs of the search and the sample intervals they went through
    /// (a certification's own runs are [`super::Certified::extra`]).
    pub fn work(&self) -> Work {
        Work {
            runs: self.points.len(),
            intervals: self.points.iter().map(|q| q.outcome.intervals).sum(),
        }
    }
}
