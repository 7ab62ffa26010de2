//! One record's intensity measures as `rocking ims --json` states them
//! (and Python's `record_ims`): its own measures, and with the pair's other
//! horizontal component the RotD50 and RotD100 of PGA, PGV and SA
//! (docs/MODEL.md §14, §18). One function for both doors.

use crate::im::rotd::PairIms;
use crate::im::{RecordIms, RecordImsError};
use crate::pair::{Pair, PairError};

/// What refuses a record's measures.
#[derive(Debug, thiserror::Error)]
pub enum MeasuresError {
    #[error("{0}: a period must be a positive number of seconds")]
    Period(f64),
    #[error(transparent)]
    Record(#[from] RecordImsError),
    #[error(transparent)]
    Pair(#[from] PairError),
}

/// A record's measures and, given the pair's other component, its RotDs.
#[derive(Debug, Clone)]
pub struct Measures {
    pub ims: RecordIms,
    pub rotd: Option<PairIms>,
}

impl Measures {
    /// The measures of `accel` (g) at step `dt` (s), SA also at `periods`
    /// (s), and of the pair with `pair`'s samples and step.
    pub fn of(
        accel: &[f64],
        dt: f64,
        pair: Option<(&[f64], f64)>,
        periods: &[f64],
    ) -> Result<Measures, MeasuresError> {
        if let Some(&bad) = periods.iter().find(|t| !(**t > 0.0 && t.is_finite())) {
            return Err(MeasuresError::Period(bad));
        }
        let ims = RecordIms::try_of_record(accel, dt, periods)?;
        let rotd = match pair {
            Some((b, b_dt)) => {
                let pair = Pair::new(accel.to_vec(), dt, b.to_vec(), b_dt)?;
                Some(PairIms::of_pair(&pair, periods)?)
            }
            None => None,
        };
        Ok(Measures { ims, rotd })
    }

    /// As `--json` prints them: the record's measures (keys sorted), with
    /// `rotd50` and `rotd100` beside them for a pair.
    pub fn json(&self) -> serde_json::Value {
        let mut value = serde_json::to_value(&self.ims).expect("measures serialise");
        if let Some(r) = &self.rotd {
            value["rotd50"] = r.json(|m| m.d50);
            value["rotd100"] = r.json(|m| m.d100);
        }
        value
    }
}
