//! The sweep's tables: `ida_points` (one row per run) and `capacities` (one
//! row per record × block). Schemas defined once here; the columns are
//! documented in the README.

use std::path::Path;
use std::sync::{Arc, OnceLock};

use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, Int64Type};
use arrow_array::{
    Array, ArrayRef, BooleanArray, Float64Array, Int64Array, RecordBatch, StringArray,
};
use arrow_schema::{DataType, Field, Schema};

use super::{read_table, TableError, TableKind};

pub const IDA_KIND: TableKind = TableKind {
    name: "ida_points",
    schema_version: 1,
};
pub const CAPACITY_KIND: TableKind = TableKind {
    name: "capacities",
    schema_version: 1,
};

/// One run of the IDA.
#[derive(Debug, Clone, PartialEq)]
pub struct IdaRow {
    /// Index of the (record, block) case in the plan's order.
    pub case_id: i64,
    pub record_id: String,
    pub block: String,
    pub p: f64,
    pub eps: f64,
    pub alpha_rad: Option<f64>,
    pub eta: f64,
    /// A_g in units of αg: 1/η.
    pub pga_scale: f64,
    /// θmax/α, +∞ once overturned.
    pub edp: f64,
    pub overturned: bool,
    pub impacts: i64,
    /// `level` or `refinement`.
    pub run_kind: String,
    pub model: String,
}

/// The capacity of one record for one block.
#[derive(Debug, Clone, PartialEq)]
pub struct CapacityRow {
    pub case_id: i64,
    pub record_id: String,
    pub block: String,
    pub p: f64,
    pub eps: f64,
    pub alpha_rad: Option<f64>,
    pub model: String,
    /// Largest η known to overturn; null if it survived every level.
    pub eta_c: Option<f64>,
    pub eta_survived: f64,
    pub level_survived: f64,
    pub level_overturned: Option<f64>,
    pub runs: i64,
    /// Levels stronger than the first overturning that survived (only when
    /// the pipeline traces past the first overturning).
    pub resurrections: Option<i64>,
}

fn f(name: &str, nullable: bool) -> Field {
    Field::new(name, DataType::Float64, nullable)
}
fn i(name: &str, nullable: bool) -> Field {
    Field::new(name, DataType::Int64, nullable)
}
fn s(name: &str) -> Field {
    Field::new(name, DataType::Utf8, false)
}

pub fn ida_schema() -> Arc<Schema> {
    static SCHEMA: OnceLock<Arc<Schema>> = OnceLock::new();
    SCHEMA
        .get_or_init(|| {
            Arc::new(Schema::new(vec![
                i("case_id", false),
                s("record_id"),
                s("block"),
                f("p", false),
                f("eps", false),
                f("alpha_rad", true),
                f("eta", false),
                f("pga_scale", false),
                f("edp", false),
                Field::new("overturned", DataType::Boolean, false),
                i("impacts", false),
                s("run_kind"),
                s("model"),
            ]))
        })
        .clone()
}

pub fn capacity_schema() -> Arc<Schema> {
    static SCHEMA: OnceLock<Arc<Schema>> = OnceLock::new();
    SCHEMA
        .get_or_init(|| {
            Arc::new(Schema::new(vec![
                i("case_id", false),
                s("record_id"),
                s("block"),
                f("p", false),
                f("eps", false),
                f("alpha_rad", true),
                s("model"),
                f("eta_c", true),
                f("eta_survived", false),
                f("level_survived", false),
                f("level_overturned", true),
                i("runs", false),
                i("resurrections", true),
            ]))
        })
        .clone()
}

fn strs<T>(rows: &[T], g: impl Fn(&T) -> &str) -> ArrayRef {
    Arc::new(rows.iter().map(|r| Some(g(r))).collect::<StringArray>())
}
fn reals<T>(rows: &[T], g: impl Fn(&T) -> Option<f64>) -> ArrayRef {
    Arc::new(rows.iter().map(g).collect::<Float64Array>())
}
fn ints<T>(rows: &[T], g: impl Fn(&T) -> Option<i64>) -> ArrayRef {
    Arc::new(rows.iter().map(g).collect::<Int64Array>())
}

pub fn ida_batch(rows: &[IdaRow]) -> Result<RecordBatch, arrow_schema::ArrowError> {
    RecordBatch::try_new(
        ida_schema(),
        vec![
            ints(rows, |r| Some(r.case_id)),
            strs(rows, |r| &r.record_id),
            strs(rows, |r| &r.block),
            reals(rows, |r| Some(r.p)),
            reals(rows, |r| Some(r.eps)),
            reals(rows, |r| r.alpha_rad),
            reals(rows, |r| Some(r.eta)),
            reals(rows, |r| Some(r.pga_scale)),
            reals(rows, |r| Some(r.edp)),
            Arc::new(
                rows.iter()
                    .map(|r| Some(r.overturned))
                    .collect::<BooleanArray>(),
            ),
            ints(rows, |r| Some(r.impacts)),
            strs(rows, |r| &r.run_kind),
            strs(rows, |r| &r.model),
        ],
    )
}

pub fn capacity_batch(rows: &[CapacityRow]) -> Result<RecordBatch, arrow_schema::ArrowError> {
    RecordBatch::try_new(
        capacity_schema(),
        vec![
            ints(rows, |r| Some(r.case_id)),
            strs(rows, |r| &r.record_id),
            strs(rows, |r| &r.block),
            reals(rows, |r| Some(r.p)),
            reals(rows, |r| Some(r.eps)),
            reals(rows, |r| r.alpha_rad),
            strs(rows, |r| &r.model),
            reals(rows, |r| r.eta_c),
            reals(rows, |r| Some(r.eta_survived)),
            reals(rows, |r| Some(r.level_survived)),
            reals(rows, |r| r.level_overturned),
            ints(rows, |r| Some(r.runs)),
            ints(rows, |r| r.resurrections),
        ],
    )
}

/// Column accessors for a batch read back, with errors naming file and column.
struct Cols<'a> {
    batch: &'a RecordBatch,
    path: &'a Path,
}

impl<'a> Cols<'a> {
    fn col(&self, name: &'static str) -> Result<&'a ArrayRef, TableError> {
        self.batch
            .column_by_name(name)
            .ok_or_else(|| TableError::Column {
                path: self.path.into(),
                column: name,
                problem: "missing".into(),
            })
    }
    fn bad(&self, name: &'static str) -> TableError {
        TableError::Column {
            path: self.path.into(),
            column: name,
            problem: "unexpected type".into(),
        }
    }
    fn f(&self, name: &'static str) -> Result<&'a Float64Array, TableError> {
        self.col(name)?
            .as_primitive_opt::<Float64Type>()
            .ok_or_else(|| self.bad(name))
    }
    fn i(&self, name: &'static str) -> Result<&'a Int64Array, TableError> {
        self.col(name)?
            .as_primitive_opt::<Int64Type>()
            .ok_or_else(|| self.bad(name))
    }
    fn s(&self, name: &'static str) -> Result<&'a StringArray, TableError> {
        self.col(name)?
            .as_string_opt::<i32>()
            .ok_or_else(|| self.bad(name))
    }
    fn b(&self, name: &'static str) -> Result<&'a BooleanArray, TableError> {
        self.col(name)?
            .as_boolean_opt()
            .ok_or_else(|| self.bad(name))
    }
}

fn opt(a: &Float64Array, k: usize) -> Option<f64> {
    a.is_valid(k).then(|| a.value(k))
}

/// Reads IDA points from one or more files (a dataset), in file order.
pub fn read_ida(paths: &[impl AsRef<Path>]) -> Result<Vec<IdaRow>, TableError> {
    let mut rows = Vec::new();
    for path in paths {
        let path = path.as_ref();
        for batch in read_table(path, IDA_KIND)?.batches {
            let c = Cols {
                batch: &batch,
                path,
            };
            let (case, rec, block) = (c.i("case_id")?, c.s("record_id")?, c.s("block")?);
            let (p, eps, alpha, eta) = (c.f("p")?, c.f("eps")?, c.f("alpha_rad")?, c.f("eta")?);
            let (scale, edp, over, imp) = (
                c.f("pga_scale")?,
                c.f("edp")?,
                c.b("overturned")?,
                c.i("impacts")?,
            );
            let (kind, model) = (c.s("run_kind")?, c.s("model")?);
            for k in 0..batch.num_rows() {
                rows.push(IdaRow {
                    case_id: case.value(k),
                    record_id: rec.value(k).to_string(),
                    block: block.value(k).to_string(),
                    p: p.value(k),
                    eps: eps.value(k),
                    alpha_rad: opt(alpha, k),
                    eta: eta.value(k),
                    pga_scale: scale.value(k),
                    edp: edp.value(k),
                    overturned: over.value(k),
                    impacts: imp.value(k),
                    run_kind: kind.value(k).to_string(),
                    model: model.value(k).to_string(),
                });
            }
        }
    }
    Ok(rows)
}

/// Reads capacities from one or more files (a dataset), in file order.
pub fn read_capacities(paths: &[impl AsRef<Path>]) -> Result<Vec<CapacityRow>, TableError> {
    let mut rows = Vec::new();
    for path in paths {
        let path = path.as_ref();
        for batch in read_table(path, CAPACITY_KIND)?.batches {
            let c = Cols {
                batch: &batch,
                path,
            };
            let (case, rec, block) = (c.i("case_id")?, c.s("record_id")?, c.s("block")?);
            let (p, eps, alpha, model) = (c.f("p")?, c.f("eps")?, c.f("alpha_rad")?, c.s("model")?);
            let (eta_c, top, ls, lo) = (
                c.f("eta_c")?,
                c.f("eta_survived")?,
                c.f("level_survived")?,
                c.f("level_overturned")?,
            );
            let (runs, res) = (c.i("runs")?, c.i("resurrections")?);
            for k in 0..batch.num_rows() {
                rows.push(CapacityRow {
                    case_id: case.value(k),
                    record_id: rec.value(k).to_string(),
                    block: block.value(k).to_string(),
                    p: p.value(k),
                    eps: eps.value(k),
                    alpha_rad: opt(alpha, k),
                    model: model.value(k).to_string(),
                    eta_c: opt(eta_c, k),
                    eta_survived: top.value(k),
                    level_survived: ls.value(k),
                    level_overturned: opt(lo, k),
                    runs: runs.value(k),
                    resurrections: res.is_valid(k).then(|| res.value(k)),
                });
            }
        }
    }
    Ok(rows)
}
