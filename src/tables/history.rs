//! The `history` table of `rocking simulate --history`: the response at every
//! event and at a chosen rate of samples, as Parquet or CSV (by extension).

use std::fmt::Write as _;
use std::path::Path;

use super::{atomic_write, Label, Table, TableError};
use crate::physics::{EventKind, HistoryPoint};
use crate::table;

table! {
    /// One row per event or kept sample of the response history.
    ///
    /// Written by `rocking simulate --history FILE` as Parquet (`.parquet`) or CSV
    /// (`.csv`, the same columns): the motion at every event and at every
    /// `--history-every`-th sample. A run that settles for good or overturns ends there.
    /// The Parquet metadata holds `rocking.simulate.record` (the record) and
    /// `rocking.simulate.spec` (the run's specification).
    pub struct HistoryRow = "history" v 2 {
        /// Time from the first sample (s).
        pub t_s: f64,
        /// The rotation θ/α, signed.
        pub x: f64,
        /// dx/dt (1/s).
        pub v_per_s: f64,
        /// The pivot: +1 or −1 while rocking, 0 at rest.
        pub pivot: i8,
        /// ψ̈, the record normalised to unit peak, at that instant.
        pub psi: f64,
        /// The base's position relative to the ground (m; 0 for a model that does not
        /// slide), positive along the inertial force of a positive record value (against
        /// the record's own axis: a positive pulse leaves the block behind at u > 0), the
        /// axis on which pivot +1 lies (docs/MODEL.md §21).
        pub slide_m: f64,
        /// The base's velocity relative to the ground (m/s), on the same axis.
        pub slide_velocity_m_per_s: f64,
        /// What the row is: `sample` (a kept sample) or an event: `start`, `uplift`,
        /// `impact` (the state after it; one row for each impact the run counts),
        /// `rest` (the block settles: after the `impact` row of an impact too slow
        /// to rebound, or alone where a lift dies out), `overturn`, `record_end`,
        /// and for the
        /// slide-rock model `slip` (the base or the pivot starts to slip), `stick` (it
        /// stops) and `flight` (the pivot's normal force reached 0).
        pub event: EventKind,
    }
}

impl From<&HistoryPoint> for HistoryRow {
    fn from(p: &HistoryPoint) -> Self {
        HistoryRow {
            t_s: p.t_s,
            x: p.x,
            v_per_s: p.v,
            pivot: p.pivot,
            psi: p.psi,
            slide_m: p.u_m,
            slide_velocity_m_per_s: p.w_mps,
            event: p.kind,
        }
    }
}

/// A history table's settings: the record it ran (its path, or its id) and
/// the run's specification.
pub fn settings(record: &str, spec: &crate::physics::RunSpec) -> Vec<(String, String)> {
    vec![
        ("rocking.simulate.record".to_string(), record.to_string()),
        ("rocking.simulate.spec".to_string(), format!("{spec:?}")),
    ]
}

/// The points as the bytes of the Parquet file [`write`] writes (for a
/// front end that hands the table on in memory: Python).
pub fn to_bytes(
    points: &[HistoryPoint],
    settings: &[(String, String)],
) -> Result<Vec<u8>, TableError> {
    let rows: Vec<HistoryRow> = points.iter().map(HistoryRow::from).collect();
    super::to_bytes(&rows, settings)
}

/// Writes the points to `dest`: Parquet for `.parquet`, CSV for `.csv` (same
/// columns, the header from the same schema).
pub fn write(
    dest: &Path,
    points: &[HistoryPoint],
    settings: &[(String, String)],
) -> Result<(), TableError> {
    let rows: Vec<HistoryRow> = points.iter().map(HistoryRow::from).collect();
    let ext = dest.extension().map(|e| e.to_ascii_lowercase());
    match ext.as_ref().and_then(|e| e.to_str()) {
        Some("parquet") => super::write(dest, &rows, settings),
        Some("csv") => {
            let schema = HistoryRow::schema();
            let header: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
            let mut text = header.join(",");
            text.push('\n');
            for r in &rows {
                // `{:?}` prints the shortest decimal that reads back to the
                // same f64, always as a float (`0.0`, `1e-7`): a bare `0`
                // made readers that guess types take a column for integers.
                let _ = writeln!(
                    text,
                    "{:?},{:?},{:?},{},{:?},{:?},{:?},{}",
                    r.t_s,
                    r.x,
                    r.v_per_s,
                    r.pivot,
                    r.psi,
                    r.slide_m,
                    r.slide_velocity_m_per_s,
                    r.event.label()
                );
            }
            atomic_write(dest, text.as_bytes())
        }
        _ => Err(TableError::Io {
            path: dest.into(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "a history file must end in .parquet or .csv",
            ),
        }),
    }
}
