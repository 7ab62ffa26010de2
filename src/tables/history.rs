//! The `history` table of `rocking simulate --history`: the response at every
//! event and at a chosen rate of samples, as Parquet or CSV (by extension).

use std::fmt::Write as _;
use std::path::Path;
use std::sync::{Arc, OnceLock};

use arrow_array::{ArrayRef, Float64Array, Int8Array, RecordBatch, StringArray};
use arrow_schema::{DataType, Field, Schema};

use super::{atomic_write, AtomicTableWriter, TableError, TableKind};
use crate::physics::HistoryPoint;

pub const KIND: TableKind = TableKind {
    name: "history",
    schema_version: 1,
};

/// The schema, defined once; the CSV header uses the same names.
pub fn schema() -> Arc<Schema> {
    static SCHEMA: OnceLock<Arc<Schema>> = OnceLock::new();
    SCHEMA
        .get_or_init(|| {
            Arc::new(Schema::new(vec![
                Field::new("t_s", DataType::Float64, false),
                Field::new("x", DataType::Float64, false),
                Field::new("v_per_s", DataType::Float64, false),
                Field::new("pivot", DataType::Int8, false),
                Field::new("psi", DataType::Float64, false),
                Field::new("event", DataType::Utf8, false),
            ]))
        })
        .clone()
}

/// Writes the points to `dest`: Parquet for `.parquet`, CSV for `.csv`.
pub fn write(
    dest: &Path,
    points: &[HistoryPoint],
    settings: &[(String, String)],
) -> Result<(), TableError> {
    let ext = dest.extension().map(|e| e.to_ascii_lowercase());
    match ext.as_ref().and_then(|e| e.to_str()) {
        Some("parquet") => {
            let columns: Vec<ArrayRef> = vec![
                Arc::new(points.iter().map(|p| p.t_s).collect::<Float64Array>()),
                Arc::new(points.iter().map(|p| p.x).collect::<Float64Array>()),
                Arc::new(points.iter().map(|p| p.v).collect::<Float64Array>()),
                Arc::new(points.iter().map(|p| p.pivot).collect::<Int8Array>()),
                Arc::new(points.iter().map(|p| p.psi).collect::<Float64Array>()),
                Arc::new(
                    points
                        .iter()
                        .map(|p| Some(p.kind.as_str()))
                        .collect::<StringArray>(),
                ),
            ];
            let batch =
                RecordBatch::try_new(schema(), columns).map_err(|source| TableError::Arrow {
                    path: dest.into(),
                    source,
                })?;
            let mut w = AtomicTableWriter::create(dest, KIND, schema(), settings)?;
            w.write(&batch)?;
            w.commit()
        }
        Some("csv") => {
            let schema = schema();
            let header: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
            let mut text = header.join(",");
            text.push('\n');
            for p in points {
                // `{}` prints the shortest decimal that reads back to the same f64.
                let _ = writeln!(
                    text,
                    "{},{},{},{},{},{}",
                    p.t_s,
                    p.x,
                    p.v,
                    p.pivot,
                    p.psi,
                    p.kind.as_str()
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
