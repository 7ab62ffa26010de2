//! What `rocking-bench` is asked and how it fails: its options, the
//! sections of BENCHMARKS.md it can rewrite, and its errors.

use std::path::PathBuf;

use rocking::physics::PhysicsError;
use rocking::plot::PlotError;
use rocking::records::RecordError;
use rocking::tables::TableError;

/// What to measure and where to write it.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Folder of the bundled records (with far-field/ inside).
    pub records: PathBuf,
    /// Where BENCHMARKS.md and the plot are written.
    pub out_dir: PathBuf,
    /// Repetitions per timing (the median is reported).
    pub reps: usize,
    /// Fewer cases and settings: a smoke run, not for the record.
    pub quick: bool,
    /// The sections to measure and rewrite (the others are left as they are).
    pub sections: Vec<Section>,
    /// The `rocking` executable whose `capacity` command the `calls`
    /// section times as a new process per call (the running one).
    pub exe: PathBuf,
}

/// The generated sections of BENCHMARKS.md.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Section {
    /// Every solver's speed against its error, and the plot.
    Solvers,
    /// The linearisation error against α (the basis of `--model auto`).
    Linearisation,
    /// How much the overturning criterion moves η_c.
    Criteria,
    /// η_c of the nonlinear model against DP5's tolerance, and certification.
    Tolerance,
    /// Whether rounding can flip the exact stepper's decisive verdicts.
    Rounding,
    /// `rocking capacity` per call, process start included.
    Calls,
    /// A certified nonlinear capacity against the linearised one.
    Certified,
    /// The random-orientation fragility against the angle step.
    Orientations,
    /// The slide-rock model against the nonlinear rocking model.
    Sliding,
    /// The sweep's cost per sample interval against the exact step's floor.
    Floor,
}

impl rocking::label::Label for Section {
    const ALL: &'static [Self] = &[
        Section::Solvers,
        Section::Linearisation,
        Section::Criteria,
        Section::Tolerance,
        Section::Rounding,
        Section::Calls,
        Section::Certified,
        Section::Orientations,
        Section::Sliding,
        Section::Floor,
    ];
    fn label(self) -> &'static str {
        match self {
            Section::Solvers => "solvers",
            Section::Linearisation => "linearisation",
            Section::Criteria => "criteria",
            Section::Tolerance => "tolerance",
            Section::Rounding => "rounding",
            Section::Calls => "calls",
            Section::Certified => "certified",
            Section::Orientations => "orientations",
            Section::Sliding => "sliding",
            Section::Floor => "floor",
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A fragility the section asks for, refused or failed.
    #[error("{0}")]
    Ask(String),
    #[error(transparent)]
    Record(#[from] RecordError),
    #[error("a benchmark run")]
    Physics(#[from] PhysicsError),
    #[error(transparent)]
    Plot(#[from] PlotError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("--reps {0}: give 1 to {MAX_REPS} repetitions")]
    Reps(usize),
    #[error("`{command}` failed ({status}): {stderr}")]
    Call {
        command: String,
        status: String,
        stderr: String,
    },
    #[error("`{command}`: cannot start")]
    Spawn {
        command: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: cannot list")]
    List {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// Most repetitions per timing: the median of a thousand is already steady.
pub const MAX_REPS: usize = 1000;
