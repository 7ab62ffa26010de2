//! Where a block's capacities come from ([`LawAsk`]): the paper's
//! regression or a pipeline's study, the records `direct` runs (a folder
//! of AT2 files, or a structural model's text motions) and the
//! orientations they run at.

use std::path::PathBuf;

use serde::Deserialize;

use super::spelling::{AskError, Spelling};
use crate::columns::{AccelUnit, TextRecords};
use crate::ops::fragility::{self, Source};
use crate::pair::Orientation;

/// Where a pipeline's studies are, unless `outputs` says.
pub const DEFAULT_OUTPUTS: &str = "outputs";

/// Where the capacities come from: `paper` (the published regression) or
/// a pipeline file whose study is under `outputs`; `records` for `direct`
/// with the paper (default: the bundled far-field set).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LawAsk {
    pub source: String,
    pub outputs: Option<PathBuf>,
    pub records: Option<PathBuf>,
    /// The records are text columns in this unit (a structural model's
    /// floor motions), not AT2 files.
    pub records_unit: Option<AccelUnit>,
    /// Their value column (1 = the first after time; with `records_unit`).
    pub records_column: Option<usize>,
    /// They are relative to the ground: its motions, as run, in this folder.
    pub records_ground: Option<PathBuf>,
    /// Which orientations of the records `direct` runs (pairs for random and worst).
    pub orientation: Orientation,
    /// The angle step of the random and worst orientations (°).
    pub angle_step: f64,
}

impl Default for LawAsk {
    fn default() -> Self {
        LawAsk {
            source: "paper".into(),
            outputs: None,
            records: None,
            records_unit: None,
            records_column: None,
            records_ground: None,
            orientation: Orientation::AsRecorded,
            angle_step: crate::pair::ANGLE_STEP_DEG,
        }
    }
}

impl LawAsk {
    /// The orientations `direct` runs the records at, checked.
    pub fn orient(&self, direct: bool, sp: Spelling) -> Result<fragility::Orient, AskError> {
        super::check_angle_step(self.angle_step, sp)?;
        if self.angle_step != crate::pair::ANGLE_STEP_DEG
            && self.orientation == Orientation::AsRecorded
        {
            return Err(AskError(format!(
                "{} is the step of {} or {}: the records run as recorded without either",
                sp.set_number("angle_step", self.angle_step),
                sp.set("orientation", "random"),
                sp.set("orientation", "worst")
            )));
        }
        // Without the runs the records were ignored, and the capacities
        // the paper's regression's (or a study's) without a word.
        if let Some(records) = self.records.as_ref().filter(|_| !direct) {
            return Err(AskError(format!(
                "{}: records are run with {}; add it (without it the capacities are the \
                 paper's regression's, or a study's with {})",
                sp.set("records", &records.display().to_string()),
                sp.key("direct"),
                sp.key("from")
            )));
        }
        let text_keys = [
            ("records_unit", self.records_unit.is_some()),
            ("records_column", self.records_column.is_some()),
            ("records_ground", self.records_ground.is_some()),
        ];
        if let Some((key, _)) = text_keys.iter().find(|(_, given)| *given && !direct) {
            return Err(AskError(format!(
                "{} says how {} runs text records: add it (without it no record is read)",
                sp.key(key),
                sp.key("direct")
            )));
        }
        if self.orientation != Orientation::AsRecorded && !direct {
            return Err(AskError(format!(
                "{} runs the records' pairs at every angle: add {}",
                sp.set("orientation", crate::label::Label::label(self.orientation)),
                sp.key("direct")
            )));
        }
        Ok(fragility::Orient {
            orientation: self.orientation,
            step_deg: self.angle_step,
            pair_im: false,
        })
    }

    pub fn resolve(&self, sp: Spelling) -> Result<Source, AskError> {
        let text = match (self.records_unit, self.records_column) {
            (Some(unit), column) => Some(TextRecords {
                unit,
                column: column.unwrap_or(1),
                ground: self.records_ground.clone(),
            }),
            (None, _) if self.records_column.is_some() || self.records_ground.is_some() => {
                let key = if self.records_column.is_some() {
                    "records_column"
                } else {
                    "records_ground"
                };
                return Err(AskError(format!(
                    "{} is for text records: give their unit with {}",
                    sp.key(key),
                    sp.key("records_unit")
                )));
            }
            (None, _) => None,
        };
        if let Some(t) = &text {
            if self.source != "paper" {
                return Err(AskError(format!(
                    "{} reads the text files of {}; a pipeline's records are its own",
                    sp.key("records_unit"),
                    sp.key("records")
                )));
            }
            if t.column == 0 {
                return Err(AskError(format!(
                    "{}: value columns are counted from 1 (the first after time)",
                    sp.set("records_column", "0")
                )));
            }
        }
        // The regression reads no study: a folder given for one is a
        // `from` forgotten.
        if let (Some(outputs), "paper") = (&self.outputs, self.source.as_str()) {
            return Err(AskError(format!(
                "{} is where a pipeline's study is read, with {}; the paper's regression \
                 reads nothing there",
                sp.set("outputs", &outputs.display().to_string()),
                sp.set("from", "PIPELINE.toml")
            )));
        }
        Ok(Source::named(
            &self.source,
            self.outputs
                .clone()
                .unwrap_or_else(|| PathBuf::from(DEFAULT_OUTPUTS)),
            self.records.clone(),
            text,
        ))
    }
}
