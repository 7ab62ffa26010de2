//! One AT2 record read for the solvers (`simulate`, `capacity`, `bench`).

use std::path::{Path, PathBuf};

use crate::at2::{self, At2Error};
use crate::physics::{Excitation, PhysicsError};
use crate::pulse::Pulse;

/// A record ready to run, with what the reports show.
#[derive(Debug, Clone)]
pub struct LoadedRecord {
    /// The file stem.
    pub record_id: String,
    pub npts: usize,
    pub pga_g: f64,
    pub exc: Excitation,
    /// The pulse this excitation is, when it is one (no physical PGA then).
    pub pulse: Option<Pulse>,
}

/// A pulse as a record: its name as the id, sampled at the default step
/// for a block of frequency `p`.
pub fn from_pulse(pulse: &Pulse, p: f64) -> Result<LoadedRecord, PhysicsError> {
    let exc = pulse.excitation_for(p)?;
    Ok(LoadedRecord {
        record_id: pulse.to_string(),
        npts: exc.psi.len(),
        pga_g: f64::NAN,
        exc,
        pulse: Some(*pulse),
    })
}

#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    #[error("{path}: cannot read")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The parse error's line and text are in the message.
    #[error("{path}:{}: {}", .error.line, .error.kind)]
    Parse { path: PathBuf, error: At2Error },
    #[error("{path}")]
    Samples {
        path: PathBuf,
        #[source]
        source: PhysicsError,
    },
}

/// Reads and normalises one AT2 file.
pub fn load(path: &Path) -> Result<LoadedRecord, RecordError> {
    let bytes = std::fs::read(path).map_err(|source| RecordError::Read {
        path: path.into(),
        source,
    })?;
    let parsed = at2::parse(&bytes).map_err(|error| RecordError::Parse {
        path: path.into(),
        error,
    })?;
    let pga_g = crate::motion::peak(&parsed.accel_g, parsed.dt_s).map_or(0.0, |p| p.pga_g);
    let exc =
        Excitation::new(&parsed.accel_g, parsed.dt_s).map_err(|source| RecordError::Samples {
            path: path.into(),
            source,
        })?;
    Ok(LoadedRecord {
        record_id: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        npts: parsed.accel_g.len(),
        pga_g,
        exc,
        pulse: None,
    })
}

/// [`crate::ida::capacity_certified`] of one record with every core of the
/// rayon pool: the search runs the next `threads` grid levels at once and
/// all the chaos probes at once ([`crate::ida::Runs::with_batch`]). The
/// capacity and its certification are those of the sequential search (the
/// runs are the same, only run ahead of need); at most `threads − 1` levels
/// past the first overturning run in vain. For one capacity at a time, as
/// the `capacity` command; a sweep already keeps the cores busy with cases.
pub fn capacity_certified_parallel(
    exc: &Excitation,
    spec: &crate::physics::RunSpec,
    grid: &crate::ida::ImGrid,
    tol: f64,
    trace: crate::ida::Trace,
) -> Result<crate::ida::Certified, PhysicsError> {
    use rayon::prelude::*;
    let batch = |exc: &Excitation, specs: &[crate::physics::RunSpec]| {
        specs
            .par_iter()
            .map(|s| crate::physics::simulate(exc, s))
            .collect::<Vec<_>>()
    };
    let width = rayon::current_num_threads();
    // The whole search runs on a worker of the pool: a batch started there
    // shares its runs with the other workers at once, where one started
    // from outside the pool would wait for a sleeping worker every time.
    rayon::scope(|_| {
        let mut runs = crate::ida::Runs::with_batch(exc, &batch, width);
        crate::ida::capacity_certified_in(&mut runs, spec, grid, tol, trace)
    })
}
