//! `--direct` over record pairs: the motions an orientation rule runs
//! (each recorded component, or every pair at every angle of the step),
//! which pair each is of, and each pair's RotD measures (docs/MODEL.md §18).

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::error::FragilityError;
use crate::im::rotd::PairIms;
use crate::pair::{self, Orientation, Pair};
use crate::tables::records::RecordRow;

/// Which orientations the records are run at, and whether the fragility's
/// IM is a pair's (RotD50, RotD100).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orient {
    pub orientation: Orientation,
    /// The angle step of `random` and `worst` (°).
    pub step_deg: f64,
    /// The IM is a pair's: each record's pair must be known.
    pub pair_im: bool,
}

impl Default for Orient {
    fn default() -> Self {
        Orient {
            orientation: Orientation::AsRecorded,
            step_deg: pair::ANGLE_STEP_DEG,
            pair_im: false,
        }
    }
}

impl Orient {
    /// Whether the records must come in pairs.
    pub fn needs_pairs(&self) -> bool {
        self.orientation != Orientation::AsRecorded || self.pair_im
    }

    /// The angles each pair is run at (`random`, `worst`).
    pub fn angles(&self) -> Vec<f64> {
        pair::angles(self.step_deg)
    }
}

/// One motion `--direct` runs: a recorded component, or a pair's component
/// at an angle.
pub(super) struct Motion {
    pub id: String,
    pub accel_g: Vec<f64>,
    pub dt_s: f64,
    /// Which pair it is of, when the records come in pairs.
    pub pair: Option<usize>,
}

/// The motions `rows` give under `orient`, how many pairs they are of (0
/// when the records need not come in pairs), and each pair's RotD measures
/// (only for a pair's IM: they cost more than the capacities).
pub(super) fn motions(
    rows: Vec<RecordRow>,
    orient: &Orient,
) -> Result<(Vec<Motion>, usize, Vec<PairIms>), FragilityError> {
    if !orient.needs_pairs() {
        let motions = rows
            .into_iter()
            .map(|r| Motion {
                id: r.record_id,
                accel_g: r.accel_g,
                dt_s: r.dt_s,
                pair: None,
            })
            .collect();
        return Ok((motions, 0, Vec::new()));
    }
    let pairs: Vec<(String, String, Pair)> = crate::records::pair_up(rows)
        .map_err(FragilityError::Pairs)?
        .into_iter()
        .map(|p| (p.a.record_id, p.b.record_id, p.pair))
        .collect();
    let n_pairs = pairs.len();
    let rotd: Vec<PairIms> = match orient.pair_im {
        true => pairs
            .par_iter()
            .map(|(_, _, p)| {
                PairIms::of_pair(p, &[]).map_err(|e| FragilityError::Pairs(format!("{e}")))
            })
            .collect::<Result<_, _>>()?,
        false => Vec::new(),
    };
    let motions = match orient.orientation {
        Orientation::AsRecorded => pairs
            .into_iter()
            .enumerate()
            .flat_map(|(k, (a, b, p))| {
                [(a, p.a), (b, p.b)].map(|(id, accel_g)| Motion {
                    id,
                    accel_g,
                    dt_s: p.dt_s,
                    pair: Some(k),
                })
            })
            .collect(),
        Orientation::Random | Orientation::Worst => {
            let angles = orient.angles();
            pairs
                .iter()
                .enumerate()
                .flat_map(|(k, (a, _, p))| {
                    angles.iter().map(move |&theta| Motion {
                        id: format!("{a}@{theta}"),
                        accel_g: p.rotated(theta),
                        dt_s: p.dt_s,
                        pair: Some(k),
                    })
                })
                .collect()
        }
    };
    Ok((motions, n_pairs, rotd))
}

/// The manifest that pairs the records of the folder `records`: its own
/// `manifest.csv`, or its parent's (the bundled sets' layout).
pub(super) fn manifest_of(records: &Path) -> Option<PathBuf> {
    [
        records.join("manifest.csv"),
        records.join("../manifest.csv"),
    ]
    .into_iter()
    .find(|p| p.is_file())
}
