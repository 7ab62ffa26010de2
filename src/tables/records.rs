//! The `records` table: one row per ground-motion record, samples included.
//!
//! Written by `rocking ingest`, read by every later stage. Column meanings are
//! documented in `outputs/README.md`; this schema is their single definition.

use std::path::Path;
use std::sync::{Arc, OnceLock};

use arrow_array::builder::{Float64Builder, ListBuilder};
use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, Int64Type};
use arrow_array::{Array, ArrayRef, Float64Array, Int64Array, RecordBatch, StringArray};
use arrow_schema::{DataType, Field, Schema};

use super::{read_table, AtomicTableWriter, TableError, TableKind};
use crate::manifest::RecordMeta;

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
    /// `keyed` or `positional` (see `at2::HeaderLayout`).
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
                Field::new(
                    "accel_g",
                    DataType::List(Arc::new(Field::new("item", DataType::Float64, false))),
                    false,
                ),
            ]))
        })
        .clone()
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
    let mut accel = ListBuilder::new(Float64Builder::new()).with_field(Arc::new(Field::new(
        "item",
        DataType::Float64,
        false,
    )));
    for r in rows {
        accel.values().append_slice(&r.accel_g);
        accel.append(true);
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
        Arc::new(accel.finish()),
    ];
    RecordBatch::try_new(schema(), columns)
}

/// Rows per batch (and so per row group) when writing: bounds memory to a
/// few records' samples at a time.
pub const ROWS_PER_BATCH: usize = 16;

/// Writes `rows` to `dest` atomically, with `settings` in the metadata.
pub fn write(
    dest: &Path,
    rows: &[RecordRow],
    settings: &[(String, String)],
) -> Result<(), TableError> {
    let mut writer = AtomicTableWriter::create(dest, KIND, schema(), settings)?;
    for chunk in rows.chunks(ROWS_PER_BATCH) {
        let batch = to_batch(chunk).map_err(|source| TableError::Arrow {
            path: dest.to_path_buf(),
            source,
        })?;
        writer.write(&batch)?;
    }
    writer.commit()
}

/// Reads a records table written by `rocking ingest`.
pub fn read(path: &Path) -> Result<Vec<RecordRow>, TableError> {
    let contents = read_table(path, KIND)?;
    let mut rows = Vec::new();
    for batch in &contents.batches {
        let col = |name: &'static str| -> Result<&ArrayRef, TableError> {
            batch
                .column_by_name(name)
                .ok_or_else(|| TableError::Column {
                    path: path.into(),
                    column: name,
                    problem: "missing".into(),
                })
        };
        let bad_type = |name: &'static str| TableError::Column {
            path: path.into(),
            column: name,
            problem: "unexpected type".into(),
        };
        let s = |name: &'static str| -> Result<&StringArray, TableError> {
            col(name)?
                .as_string_opt::<i32>()
                .ok_or_else(|| bad_type(name))
        };
        let f = |name: &'static str| -> Result<&Float64Array, TableError> {
            col(name)?
                .as_primitive_opt::<Float64Type>()
                .ok_or_else(|| bad_type(name))
        };
        let i = |name: &'static str| -> Result<&Int64Array, TableError> {
            col(name)?
                .as_primitive_opt::<Int64Type>()
                .ok_or_else(|| bad_type(name))
        };
        let opt_s = |a: &StringArray, k: usize| a.is_valid(k).then(|| a.value(k).to_string());
        let opt_f = |a: &Float64Array, k: usize| a.is_valid(k).then(|| a.value(k));
        let opt_i = |a: &Int64Array, k: usize| a.is_valid(k).then(|| a.value(k));

        let (record_id, source, sha256) = (s("record_id")?, s("source")?, s("sha256")?);
        let npts = i("npts")?;
        let (dt, pga, pga_t, dur) = (f("dt_s")?, f("pga_g")?, f("pga_time_s")?, f("duration_s")?);
        let headers = [
            s("header_1")?,
            s("header_2")?,
            s("header_3")?,
            s("header_4")?,
        ];
        let layout = s("header_layout")?;
        let (set, pair, pair_component) = (s("set")?, s("pair")?, s("pair_component")?);
        let (rsn, event, year, magnitude) = (i("rsn")?, s("event")?, i("year")?, f("magnitude")?);
        let (station, component) = (s("station")?, s("component")?);
        let (pga_pair, pgv_pair, norm) = (
            f("pga_max_pair_g")?,
            f("pgv_max_pair_cm_s")?,
            f("normalization_factor")?,
        );
        let (site_class, vs30, fault_type) = (s("site_class")?, f("vs30_m_s")?, s("fault_type")?);
        let (rjb, rrup, luf) = (f("r_jb_km")?, f("r_rup_km")?, f("lowest_usable_freq_hz")?);
        let accel = col("accel_g")?
            .as_list_opt::<i32>()
            .ok_or_else(|| bad_type("accel_g"))?;

        for k in 0..batch.num_rows() {
            let samples = accel.value(k);
            let samples = samples
                .as_primitive_opt::<Float64Type>()
                .ok_or_else(|| bad_type("accel_g"))?;
            let accel_g = samples.values().to_vec();
            if accel_g.len() as i64 != npts.value(k) {
                return Err(TableError::Column {
                    path: path.into(),
                    column: "accel_g",
                    problem: format!(
                        "record `{}` has {} samples but npts = {}",
                        record_id.value(k),
                        accel_g.len(),
                        npts.value(k)
                    ),
                });
            }
            rows.push(RecordRow {
                record_id: record_id.value(k).to_string(),
                source: source.value(k).to_string(),
                sha256: sha256.value(k).to_string(),
                dt_s: dt.value(k),
                pga_g: pga.value(k),
                pga_time_s: pga_t.value(k),
                duration_s: dur.value(k),
                header: headers.map(|h| h.value(k).to_string()),
                header_layout: layout.value(k).to_string(),
                meta: RecordMeta {
                    set: opt_s(set, k),
                    pair: opt_s(pair, k),
                    pair_component: opt_s(pair_component, k),
                    rsn: opt_i(rsn, k),
                    event: opt_s(event, k),
                    year: opt_i(year, k),
                    magnitude: opt_f(magnitude, k),
                    station: opt_s(station, k),
                    component: opt_s(component, k),
                    pga_max_pair_g: opt_f(pga_pair, k),
                    pgv_max_pair_cm_s: opt_f(pgv_pair, k),
                    normalization_factor: opt_f(norm, k),
                    site_class: opt_s(site_class, k),
                    vs30_m_s: opt_f(vs30, k),
                    fault_type: opt_s(fault_type, k),
                    r_jb_km: opt_f(rjb, k),
                    r_rup_km: opt_f(rrup, k),
                    lowest_usable_freq_hz: opt_f(luf, k),
                },
                accel_g,
            });
        }
    }
    Ok(rows)
}
