//! One record ready to run ([`LoadedRecord`]): an AT2 file read and
//! normalised, samples given as values, or a pulse sampled for a block;
//! on a building's floor, the floor's motion under it.

use std::path::{Path, PathBuf};

use crate::at2::{self, At2Error};
use crate::floor::Building;
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
    /// On a building's floor: the ground record's peak and the building's
    /// amplification of it (`pga_g` and `exc` are then the floor motion's).
    pub floor: Option<OnFloor>,
    /// A pair's component at this angle from component a (°), when the
    /// record is one ([`pair_at`]).
    pub angle_deg: Option<f64>,
}

/// A record run on a building's floor rather than on the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnFloor {
    /// The ground record's PGA (g), unscaled.
    pub ground_pga_g: f64,
    /// The floor motion's peak over the ground's, PFA/PGA, for the record
    /// as recorded (and at any scale: the building is linear).
    pub pfa_over_pga: f64,
    /// The floor motion's samples per record step.
    pub substeps: usize,
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
        floor: None,
        angle_deg: None,
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
    /// The parse error's line and text are in the message, and where the
    /// file is named as text (`.txt`, `.out`, …) which reader takes it.
    #[error("{path}:{}: {}{}", .error.line, .error.kind, text_hint(.path))]
    Parse { path: PathBuf, error: At2Error },
    #[error("{path}")]
    Samples {
        path: PathBuf,
        #[source]
        source: PhysicsError,
    },
    /// A record and a pulse together, a pulse on a floor, or neither.
    #[error("{0}")]
    Asked(String),
    #[error("{} and {}", a.display(), b.display())]
    Pair {
        a: PathBuf,
        b: PathBuf,
        #[source]
        source: crate::pair::PairError,
    },
    #[error("{path}: its floor motion")]
    Floor {
        path: PathBuf,
        #[source]
        source: crate::floor::FloorError,
    },
}

/// What shakes the block: the record at `path` (on the floor of `building`
/// when one is given), or `pulse` sampled for the block's `p`.
pub fn excitation(
    path: Option<&Path>,
    pulse: Option<&Pulse>,
    building: Option<&Building>,
    p: f64,
) -> Result<LoadedRecord, RecordError> {
    match (path, pulse, building) {
        (Some(_), Some(_), _) => Err(RecordError::Asked(
            "give a record or a pulse, not both".into(),
        )),
        (None, Some(_), Some(_)) => Err(RecordError::Asked(
            "a floor filters a ground record through a building; a pulse is given as the block's own excitation".into(),
        )),
        (None, Some(pulse), None) => from_pulse(pulse, p).map_err(|source| RecordError::Samples {
            path: PathBuf::from(pulse.to_string()),
            source,
        }),
        (Some(path), None, _) => load_on(path, building),
        (None, None, _) => Err(RecordError::Asked(
            "give a record (--record FILE.AT2) or a pulse (--pulse rect|exp)".into(),
        )),
    }
}

/// For a text motion file given where an AT2 file is read: what reads it.
fn text_hint(path: &Path) -> &'static str {
    if super::discover::has_extension(path, super::TEXT_EXTENSIONS) {
        " (a text motion file? this command reads AT2 files; text records are read by \
         fragility, risk and export with --records-unit, or a pipeline's `[records] text`)"
    } else {
        ""
    }
}

/// Reads one AT2 file: its samples (g) and step (s), unscaled.
pub fn read_samples(path: &Path) -> Result<(Vec<f64>, f64), RecordError> {
    let bytes = std::fs::read(path).map_err(|source| RecordError::Read {
        path: path.into(),
        source,
    })?;
    let parsed = at2::parse(&bytes).map_err(|error| RecordError::Parse {
        path: path.into(),
        error,
    })?;
    Ok((parsed.accel_g, parsed.dt_s))
}

/// Reads and normalises one AT2 file.
pub fn load(path: &Path) -> Result<LoadedRecord, RecordError> {
    load_on(path, None)
}

/// Reads one AT2 file and normalises it, or the motion of the floor of
/// `building` under it.
pub fn load_on(path: &Path, building: Option<&Building>) -> Result<LoadedRecord, RecordError> {
    let (ground, dt_s) = read_samples(path)?;
    let record_id = super::collect::record_id(path);
    from_samples(record_id, ground, dt_s, building).map_err(|e| e.of(path))
}

/// Why samples cannot be a record.
#[derive(Debug, thiserror::Error)]
pub enum SampleError {
    #[error("{0}")]
    Motion(String),
    #[error(transparent)]
    Samples(PhysicsError),
    #[error("its floor motion")]
    Floor(#[source] crate::floor::FloorError),
}

impl SampleError {
    /// The error of the record read from `path`.
    fn of(self, path: &Path) -> RecordError {
        match self {
            SampleError::Motion(why) => RecordError::Samples {
                path: path.into(),
                source: PhysicsError::BadInput(why),
            },
            SampleError::Samples(source) => RecordError::Samples {
                path: path.into(),
                source,
            },
            SampleError::Floor(source) => RecordError::Floor {
                path: path.into(),
                source,
            },
        }
    }
}

/// A ground record given by its samples (g) and step (s), named
/// `record_id`, normalised; or the motion of the floor of `building` under it.
pub fn from_samples(
    record_id: String,
    ground: Vec<f64>,
    ground_dt_s: f64,
    building: Option<&Building>,
) -> Result<LoadedRecord, SampleError> {
    crate::motion::check(&ground, ground_dt_s).map_err(SampleError::Motion)?;
    let peak = |a: &[f64], dt| crate::motion::peak(a, dt).map_or(0.0, |p| p.pga_g);
    let (accel_g, dt_s, floor) = match building {
        None => (ground, ground_dt_s, None),
        Some(b) => {
            let f = b
                .floor_motion(&ground, ground_dt_s)
                .map_err(SampleError::Floor)?;
            let on = OnFloor {
                ground_pga_g: peak(&ground, ground_dt_s),
                pfa_over_pga: f.pfa_over_pga,
                substeps: f.substeps,
            };
            (f.accel_g, f.dt_s, Some(on))
        }
    };
    let pga_g = peak(&accel_g, dt_s);
    let npts = accel_g.len();
    let exc = Excitation::from_samples(accel_g, dt_s).map_err(SampleError::Samples)?;
    Ok(LoadedRecord {
        record_id,
        npts,
        pga_g,
        exc,
        pulse: None,
        floor,
        angle_deg: None,
    })
}

/// The component of the pair of AT2 files `a` and `b` (b 90° from a) at
/// each of `angles_deg`, each a record named `<a's stem>@<θ>` (on the floor
/// of `building` when one is given).
pub fn pair_at(
    a: &Path,
    b: &Path,
    angles_deg: &[f64],
    building: Option<&Building>,
) -> Result<Vec<LoadedRecord>, RecordError> {
    let (xa, dt_a) = read_samples(a)?;
    let (xb, dt_b) = read_samples(b)?;
    let pair = crate::pair::Pair::new(xa, dt_a, xb, dt_b).map_err(|source| RecordError::Pair {
        a: a.into(),
        b: b.into(),
        source,
    })?;
    let stem = super::collect::record_id(a);
    angles_deg
        .iter()
        .map(|&theta| {
            let id = crate::pair::angled_id(&stem, theta);
            let mut rec =
                from_samples(id, pair.rotated(theta), pair.dt_s, building).map_err(|e| e.of(a))?;
            rec.angle_deg = Some(theta);
            Ok(rec)
        })
        .collect()
}
