//! The `records` table: one row per ground-motion record, samples included.
//!
//! Written by `rocking ingest`, read by every later stage. This schema is
//! the columns' single definition, [`COLUMN_DOCS`] their meanings
//! (`docs/tables.md`).

use std::path::Path;
use std::sync::{Arc, OnceLock};

use arrow_array::{ArrayRef, Float64Array, Int64Array, RecordBatch, StringArray};
use arrow_schema::{DataType, Field, Schema};

use super::{read_column, Column, Table, TableError, TableKind};
use crate::manifest::RecordMeta;

/// The table's description, as the tables' reference (`docs/tables.md`) gives it.
pub const DOC: &str = "One row per record.\n\n\
    Written by `rocking ingest` (default `outputs/records.parquet`) and by the ingest stage, \
    for a pipeline that names AT2 files, as `outputs/<name>/records.parquet`; every later \
    stage reads it. Rows are sorted by record id, the samples included. The metadata holds \
    `rocking.ingest.paths` (the paths ingested) and, with a manifest, \
    `rocking.ingest.manifest`. The columns that may be empty, `set` to \
    `lowest_usable_freq_hz`, come from the manifest: they are empty for a record the \
    manifest does not list (and where its row leaves a cell blank).";

/// Each column's name and meaning, in schema order ([`schema`]).
pub const COLUMN_DOCS: &[(&str, &[&str])] = &[
    ("record_id", &["The record's id: its AT2 file stem, e.g. `RSN953_NORTHR_MUL009`; unique."]),
    ("source", &["Path of the AT2 file as given or found."]),
    ("sha256", &["SHA-256 of the file's bytes (lower-case hex)."]),
    ("npts", &["Number of samples."]),
    ("dt_s", &["Time step (s)."]),
    ("pga_g", &["Peak absolute acceleration (g), from the samples."]),
    ("pga_time_s", &["Time of the first sample at the peak (s), sample 0 at t = 0."]),
    ("duration_s", &["Duration `(npts − 1)·dt_s` (s)."]),
    ("header_1", &["The file's first header line."]),
    ("header_2", &["The file's second header line."]),
    ("header_3", &["The file's third header line."]),
    ("header_4", &["The file's fourth header line."]),
    ("header_layout", &["`keyed` (`NPTS=…, DT=…`) or `positional` (`2999 0.01 NPTS, DT`)."]),
    ("set", &["Record set, e.g. `far-field`, `near-field-pulse`, `near-field-no-pulse`; empty for a \
         record the manifest does not list."]),
    ("pair", &["FEMA P695 record (pair) number; empty for a record the manifest does not list."]),
    ("pair_component", &["Component within the pair, `a` or `b`; empty for a record the manifest does not list."]),
    ("rsn", &["PEER record sequence number; empty for a record the manifest does not list."]),
    ("event", &["The earthquake; empty for a record the manifest does not list."]),
    ("year", &["The earthquake's year; empty for a record the manifest does not list."]),
    ("magnitude", &["The earthquake's magnitude; empty for a record the manifest does not list."]),
    ("station", &["Recording station; empty for a record the manifest does not list."]),
    ("component", &["Recorded component; empty for a record the manifest does not list."]),
    ("pga_max_pair_g", &["Peak ground acceleration of the pair as tabulated by FEMA P695 (g); empty for a record \
         the manifest does not list."]),
    ("pgv_max_pair_cm_s", &["Peak ground velocity of the pair as tabulated by FEMA P695 (cm/s); empty for a record the \
         manifest does not list."]),
    ("normalization_factor", &["FEMA P695 normalisation factor of the pair; empty for a record the manifest does not \
         list."]),
    ("site_class", &["NEHRP site class; empty for a record the manifest does not list."]),
    ("vs30_m_s", &["Vs30 (m/s); empty for a record the manifest does not list."]),
    ("fault_type", &["Faulting mechanism; empty for a record the manifest does not list."]),
    ("r_jb_km", &["Joyner–Boore distance (km); empty for a record the manifest does not list."]),
    ("r_rup_km", &["Rupture distance (km); empty for a record the manifest does not list."]),
    ("lowest_usable_freq_hz", &["Lowest usable frequency (Hz); empty for a record the manifest does not list."]),
    ("accel_g", &["The samples, in g."]),
];

pub const KIND: TableKind = TableKind {
    name: "records",
    schema_version: 1,
};

/// One row of the records table.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordRow {
    /// The AT2 file stem; unique within a table.
    pub record_id: String,
    /// Path of the AT2 file as given or found by ingest.
    pub source: String,
    /// SHA-256 of the file's bytes, lower-case hex.
    pub sha256: String,
    pub dt_s: f64,
    pub pga_g: f64,
    pub pga_time_s: f64,
    pub duration_s: f64,
    /// The four header lines.
    pub header: [String; 4],
    /// `keyed` or `positional` (see `at2::HeaderLayout`), or `columns` for
    /// a text file of columns (`columns`; its header lines then say how it
    /// was read).
    pub header_layout: String,
    pub meta: RecordMeta,
    pub accel_g: Vec<f64>,
}

/// The schema, defined once.
pub fn schema() -> Arc<Schema> {
    static SCHEMA: OnceLock<Arc<Schema>> = OnceLock::new();
    SCHEMA
        .get_or_init(|| {
            let utf8 = |name: &str, nullable| Field::new(name, DataType::Utf8, nullable);
            let f64 = |name: &str, nullable| Field::new(name, DataType::Float64, nullable);
            let i64 = |name: &str, nullable| Field::new(name, DataType::Int64, nullable);
            Arc::new(Schema::new(vec![
                utf8("record_id", false),
                utf8("source", false),
                utf8("sha256", false),
                i64("npts", false),
                f64("dt_s", false),
                f64("pga_g", false),
                f64("pga_time_s", false),
                f64("duration_s", false),
                utf8("header_1", false),
                utf8("header_2", false),
                utf8("header_3", false),
                utf8("header_4", false),
                utf8("header_layout", false),
                utf8("set", true),
                utf8("pair", true),
                utf8("pair_component", true),
                i64("rsn", true),
                utf8("event", true),
                i64("year", true),
                f64("magnitude", true),
                utf8("station", true),
                utf8("component", true),
                f64("pga_max_pair_g", true),
                f64("pgv_max_pair_cm_s", true),
                f64("normalization_factor", true),
                utf8("site_class", true),
                f64("vs30_m_s", true),
                utf8("fault_type", true),
                f64("r_jb_km", true),
                f64("r_rup_km", true),
                f64("lowest_usable_freq_hz", true),
                <Vec<f64> as Column>::field("accel_g"),
            ]))
        })
        .clone()
}

/// Column `name` of a batch (errors name file and column).
fn col<C: Column>(
    batch: &RecordBatch,
    name: &'static str,
    path: &Path,
) -> Result<Vec<C>, TableError> {
    read_column::<C>(batch, name, path)
}

impl Table for RecordRow {
    const KIND: TableKind = KIND;
    /// A few records' samples at a time: bounds the writer's memory.
    const BATCH_ROWS: usize = 16;
    const DOC: &'static [&'static str] = &[DOC];
    const COLUMN_DOCS: &'static [(&'static str, &'static [&'static str])] = COLUMN_DOCS;

    fn column_values() -> Vec<Option<String>> {
        vec![None; COLUMN_DOCS.len()]
    }

    fn schema() -> Arc<Schema> {
        schema()
    }

    fn to_batch(rows: &[Self]) -> Result<RecordBatch, arrow_schema::ArrowError> {
        to_batch(rows)
    }

    fn from_batch(batch: &RecordBatch, path: &Path) -> Result<Vec<Self>, TableError> {
        let npts = col::<i64>(batch, "npts", path)?;
        let mut record_id = col::<String>(batch, "record_id", path)?.into_iter();
        let mut source = col::<String>(batch, "source", path)?.into_iter();
        let mut sha256 = col::<String>(batch, "sha256", path)?.into_iter();
        let mut dt = col::<f64>(batch, "dt_s", path)?.into_iter();
        let mut pga = col::<f64>(batch, "pga_g", path)?.into_iter();
        let mut pga_t = col::<f64>(batch, "pga_time_s", path)?.into_iter();
        let mut dur = col::<f64>(batch, "duration_s", path)?.into_iter();
        let mut h1 = col::<String>(batch, "header_1", path)?.into_iter();
        let mut h2 = col::<String>(batch, "header_2", path)?.into_iter();
        let mut h3 = col::<String>(batch, "header_3", path)?.into_iter();
        let mut h4 = col::<String>(batch, "header_4", path)?.into_iter();
        let mut layout = col::<String>(batch, "header_layout", path)?.into_iter();
        let s = |name| col::<Option<String>>(batch, name, path).map(Vec::into_iter);
        let f = |name| col::<Option<f64>>(batch, name, path).map(Vec::into_iter);
        let i = |name| col::<Option<i64>>(batch, name, path).map(Vec::into_iter);
        let (mut set, mut pair, mut pair_component) = (s("set")?, s("pair")?, s("pair_component")?);
        let (mut rsn, mut event, mut year, mut magnitude) =
            (i("rsn")?, s("event")?, i("year")?, f("magnitude")?);
        let (mut station, mut component) = (s("station")?, s("component")?);
        let (mut pga_pair, mut pgv_pair, mut norm) = (
            f("pga_max_pair_g")?,
            f("pgv_max_pair_cm_s")?,
            f("normalization_factor")?,
        );
        let (mut site_class, mut vs30, mut fault_type) =
            (s("site_class")?, f("vs30_m_s")?, s("fault_type")?);
        let (mut rjb, mut rrup, mut luf) =
            (f("r_jb_km")?, f("r_rup_km")?, f("lowest_usable_freq_hz")?);
        let accel = col::<Vec<f64>>(batch, "accel_g", path)?;
        let mut rows = Vec::with_capacity(batch.num_rows());
        let next = |it: &mut dyn Iterator<Item = String>| it.next().unwrap_or_default();
        for (accel_g, n) in accel.into_iter().zip(npts) {
            let id = next(&mut record_id);
            if accel_g.len() as i64 != n {
                return Err(TableError::Column {
                    path: path.into(),
                    column: "accel_g",
                    problem: format!("record `{id}` has {} samples but npts = {n}", accel_g.len()),
                });
            }
            rows.push(RecordRow {
                record_id: id,
                source: next(&mut source),
                sha256: next(&mut sha256),
                dt_s: dt.next().unwrap_or_default(),
                pga_g: pga.next().unwrap_or_default(),
                pga_time_s: pga_t.next().unwrap_or_default(),
                duration_s: dur.next().unwrap_or_default(),
                header: [next(&mut h1), next(&mut h2), next(&mut h3), next(&mut h4)],
                header_layout: next(&mut layout),
                meta: RecordMeta {
                    set: set.next().flatten(),
                    pair: pair.next().flatten(),
                    pair_component: pair_component.next().flatten(),
                    rsn: rsn.next().flatten(),
                    event: event.next().flatten(),
                    year: year.next().flatten(),
                    magnitude: magnitude.next().flatten(),
                    station: station.next().flatten(),
                    component: component.next().flatten(),
                    pga_max_pair_g: pga_pair.next().flatten(),
                    pgv_max_pair_cm_s: pgv_pair.next().flatten(),
                    normalization_factor: norm.next().flatten(),
                    site_class: site_class.next().flatten(),
                    vs30_m_s: vs30.next().flatten(),
                    fault_type: fault_type.next().flatten(),
                    r_jb_km: rjb.next().flatten(),
                    r_rup_km: rrup.next().flatten(),
                    lowest_usable_freq_hz: luf.next().flatten(),
                },
                accel_g,
            });
        }
        Ok(rows)
    }
}

/// Builds one batch from rows, columns in schema order.
pub fn to_batch(rows: &[RecordRow]) -> Result<RecordBatch, arrow_schema::ArrowError> {
    fn strs<'a>(rows: &'a [RecordRow], f: impl Fn(&'a RecordRow) -> Option<&'a str>) -> ArrayRef {
        Arc::new(rows.iter().map(f).collect::<StringArray>())
    }
    fn reals(rows: &[RecordRow], f: impl Fn(&RecordRow) -> Option<f64>) -> ArrayRef {
        Arc::new(rows.iter().map(f).collect::<Float64Array>())
    }
    fn ints(rows: &[RecordRow], f: impl Fn(&RecordRow) -> Option<i64>) -> ArrayRef {
        Arc::new(rows.iter().map(f).collect::<Int64Array>())
    }
    let columns: Vec<ArrayRef> = vec![
        strs(rows, |r| Some(&r.record_id)),
        strs(rows, |r| Some(&r.source)),
        strs(rows, |r| Some(&r.sha256)),
        ints(rows, |r| Some(r.accel_g.len() as i64)),
        reals(rows, |r| Some(r.dt_s)),
        reals(rows, |r| Some(r.pga_g)),
        reals(rows, |r| Some(r.pga_time_s)),
        reals(rows, |r| Some(r.duration_s)),
        strs(rows, |r| Some(&r.header[0])),
        strs(rows, |r| Some(&r.header[1])),
        strs(rows, |r| Some(&r.header[2])),
        strs(rows, |r| Some(&r.header[3])),
        strs(rows, |r| Some(&r.header_layout)),
        strs(rows, |r| r.meta.set.as_deref()),
        strs(rows, |r| r.meta.pair.as_deref()),
        strs(rows, |r| r.meta.pair_component.as_deref()),
        ints(rows, |r| r.meta.rsn),
        strs(rows, |r| r.meta.event.as_deref()),
        ints(rows, |r| r.meta.year),
        reals(rows, |r| r.meta.magnitude),
        strs(rows, |r| r.meta.station.as_deref()),
        strs(rows, |r| r.meta.component.as_deref()),
        reals(rows, |r| r.meta.pga_max_pair_g),
        reals(rows, |r| r.meta.pgv_max_pair_cm_s),
        reals(rows, |r| r.meta.normalization_factor),
        strs(rows, |r| r.meta.site_class.as_deref()),
        reals(rows, |r| r.meta.vs30_m_s),
        strs(rows, |r| r.meta.fault_type.as_deref()),
        reals(rows, |r| r.meta.r_jb_km),
        reals(rows, |r| r.meta.r_rup_km),
        reals(rows, |r| r.meta.lowest_usable_freq_hz),
        <Vec<f64> as Column>::build(rows.iter().map(|r| &r.accel_g)),
    ];
    RecordBatch::try_new(schema(), columns)
}

/// Writes `rows` to `dest` atomically, with `settings` in the metadata.
pub fn write(
    dest: &Path,
    rows: &[RecordRow],
    settings: &[(String, String)],
) -> Result<(), TableError> {
    super::write(dest, rows, settings)
}

/// Reads a records table written by `rocking ingest`.
pub fn read(path: &Path) -> Result<Vec<RecordRow>, TableError> {
    super::read(path)
}
