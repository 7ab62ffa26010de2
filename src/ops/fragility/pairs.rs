//! `--direct` over record pairs: the motions an orientation rule runs
//! (each recorded component, or every pair at every angle of the step),
//! which pair each is of, and each pair's RotD measures (docs/MODEL.md §18).

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::error::FragilityError;
use crate::im::rotd::PairIms;
use crate::pair::{self, Orientation};
use crate::records;
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

/// The records `--direct` runs under `orient`, each with its pair's index
/// when the records come in pairs (recorded components, or every pair's
/// component at every angle, as a study over orientations has them:
/// [`records::rotated_rows`]); how many pairs (0 when the records need not
/// come in pairs); and each pair's RotD measures (only for a pair's IM:
/// they cost more than the capacities).
pub(super) type Motions = (Vec<(RecordRow, Option<usize>)>, usize, Vec<PairIms>);

pub(super) fn motions(rows: Vec<RecordRow>, orient: &Orient) -> Result<Motions, FragilityError> {
    if !orient.needs_pairs() {
        return Ok((rows.into_iter().map(|r| (r, None)).collect(), 0, Vec::new()));
    }
    let pairs = records::pair_up(rows).map_err(FragilityError::Pairs)?;
    let rotd: Vec<PairIms> = match orient.pair_im {
        true => pairs
            .par_iter()
            .map(|p| {
                PairIms::of_pair(&p.pair, &[]).map_err(|e| FragilityError::Pairs(format!("{e}")))
            })
            .collect::<Result<_, _>>()?,
        false => Vec::new(),
    };
    let n_pairs = pairs.len();
    let angles = orient.angles();
    let motions = pairs
        .into_iter()
        .enumerate()
        .flat_map(|(k, p)| {
            let of_pair: Vec<RecordRow> = match orient.orientation {
                Orientation::AsRecorded => vec![p.a, p.b],
                Orientation::Random | Orientation::Worst => {
                    records::rotated_rows(std::slice::from_ref(&p), &angles)
                }
            };
            of_pair.into_iter().map(move |r| (r, Some(k)))
        })
        .collect();
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
