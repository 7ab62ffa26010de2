//! The reduce and fit stages' tables: small, flat, all numeric but a few
//! labels. Each table is a list of named columns defined once in its
//! `schema()`; rows are written as [`Value`]s in that order and read back by
//! name, so one definition serves writer, reader and docs.

use std::path::Path;
use std::sync::Arc;

use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, Int64Type};
use arrow_array::{
    Array, ArrayRef, BooleanArray, Float64Array, Int64Array, RecordBatch, StringArray,
};
use arrow_schema::{DataType, Field, Schema};

use super::{read_table, AtomicTableWriter, TableError, TableKind};

/// A cell.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    F(Option<f64>),
    I(Option<i64>),
    S(String),
    B(bool),
}

/// Column types.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ty {
    F,
    /// Nullable float.
    Fn,
    I,
    /// Nullable int.
    In,
    S,
    B,
}

/// A flat table: its identity and its columns.
pub struct Flat {
    pub kind: TableKind,
    pub columns: &'static [(&'static str, Ty)],
}

impl Flat {
    pub fn schema(&self) -> Arc<Schema> {
        Arc::new(Schema::new(
            self.columns
                .iter()
                .map(|&(name, ty)| match ty {
                    Ty::F => Field::new(name, DataType::Float64, false),
                    Ty::Fn => Field::new(name, DataType::Float64, true),
                    Ty::I => Field::new(name, DataType::Int64, false),
                    Ty::In => Field::new(name, DataType::Int64, true),
                    Ty::S => Field::new(name, DataType::Utf8, false),
                    Ty::B => Field::new(name, DataType::Boolean, false),
                })
                .collect::<Vec<_>>(),
        ))
    }

    /// Writes `rows` (each in column order) to `dest`, atomically.
    pub fn write(
        &self,
        dest: &Path,
        rows: &[Vec<Value>],
        settings: &[(String, String)],
    ) -> Result<(), TableError> {
        let mut arrays: Vec<ArrayRef> = Vec::with_capacity(self.columns.len());
        for (k, &(name, ty)) in self.columns.iter().enumerate() {
            let cell = |r: &Vec<Value>| r.get(k).cloned();
            let wrong = || TableError::Column {
                path: dest.into(),
                column: name,
                problem: "value of the wrong type".into(),
            };
            let array: ArrayRef = match ty {
                Ty::F | Ty::Fn => Arc::new(
                    rows.iter()
                        .map(|r| match cell(r) {
                            Some(Value::F(v)) => Ok(v),
                            _ => Err(wrong()),
                        })
                        .collect::<Result<Float64Array, _>>()?,
                ),
                Ty::I | Ty::In => Arc::new(
                    rows.iter()
                        .map(|r| match cell(r) {
                            Some(Value::I(v)) => Ok(v),
                            _ => Err(wrong()),
                        })
                        .collect::<Result<Int64Array, _>>()?,
                ),
                Ty::S => Arc::new(
                    rows.iter()
                        .map(|r| match cell(r) {
                            Some(Value::S(v)) => Ok(Some(v)),
                            _ => Err(wrong()),
                        })
                        .collect::<Result<StringArray, _>>()?,
                ),
                Ty::B => Arc::new(
                    rows.iter()
                        .map(|r| match cell(r) {
                            Some(Value::B(v)) => Ok(Some(v)),
                            _ => Err(wrong()),
                        })
                        .collect::<Result<BooleanArray, _>>()?,
                ),
            };
            arrays.push(array);
        }
        let batch =
            RecordBatch::try_new(self.schema(), arrays).map_err(|source| TableError::Arrow {
                path: dest.into(),
                source,
            })?;
        let mut w = AtomicTableWriter::create(dest, self.kind, self.schema(), settings)?;
        w.write(&batch)?;
        w.commit()
    }

    /// Reads a table back as rows of values in column order.
    pub fn read(&self, path: &Path) -> Result<Vec<Vec<Value>>, TableError> {
        let mut rows = Vec::new();
        for batch in read_table(path, self.kind)?.batches {
            let mut cols: Vec<&ArrayRef> = Vec::new();
            for &(name, _) in self.columns {
                cols.push(
                    batch
                        .column_by_name(name)
                        .ok_or_else(|| TableError::Column {
                            path: path.into(),
                            column: name,
                            problem: "missing".into(),
                        })?,
                );
            }
            for i in 0..batch.num_rows() {
                let mut row = Vec::with_capacity(cols.len());
                for (col, &(name, ty)) in cols.iter().zip(self.columns) {
                    let bad = || TableError::Column {
                        path: path.into(),
                        column: name,
                        problem: "unexpected type".into(),
                    };
                    row.push(match ty {
                        Ty::F | Ty::Fn => {
                            let a = col.as_primitive_opt::<Float64Type>().ok_or_else(bad)?;
                            Value::F(a.is_valid(i).then(|| a.value(i)))
                        }
                        Ty::I | Ty::In => {
                            let a = col.as_primitive_opt::<Int64Type>().ok_or_else(bad)?;
                            Value::I(a.is_valid(i).then(|| a.value(i)))
                        }
                        Ty::S => Value::S(
                            col.as_string_opt::<i32>()
                                .ok_or_else(bad)?
                                .value(i)
                                .to_string(),
                        ),
                        Ty::B => Value::B(col.as_boolean_opt().ok_or_else(bad)?.value(i)),
                    });
                }
                rows.push(row);
            }
        }
        Ok(rows)
    }

    /// The number in `row` under `col` (NaN if empty or not a number).
    pub fn get(&self, row: &[Value], col: &str) -> f64 {
        row[self.col(col)].f().unwrap_or(f64::NAN)
    }

    /// Index of a column by name (panics on a name not in the schema: a bug).
    pub fn col(&self, name: &str) -> usize {
        self.columns
            .iter()
            .position(|(n, _)| *n == name)
            .unwrap_or_else(|| panic!("no column {name}"))
    }
}

impl Value {
    pub fn f(&self) -> Option<f64> {
        match self {
            Value::F(v) => *v,
            Value::I(v) => v.map(|x| x as f64),
            _ => None,
        }
    }
    pub fn s(&self) -> &str {
        match self {
            Value::S(s) => s,
            _ => "",
        }
    }
}

/// Shorthands for building rows.
pub fn f(v: f64) -> Value {
    Value::F(Some(v))
}
pub fn fo(v: Option<f64>) -> Value {
    Value::F(v)
}
pub fn i(v: i64) -> Value {
    Value::I(Some(v))
}
pub fn s(v: &str) -> Value {
    Value::S(v.to_string())
}

const fn kind(name: &'static str) -> TableKind {
    TableKind {
        name,
        schema_version: 1,
    }
}

pub const HORIZONTAL: Flat = Flat {
    kind: kind("fractiles_horizontal"),
    columns: &[
        ("block", Ty::S),
        ("p", Ty::F),
        ("eps", Ty::F),
        ("level", Ty::I),
        ("eta", Ty::F),
        ("edp_q16", Ty::F),
        ("edp_q50", Ty::F),
        ("edp_q84", Ty::F),
        ("n_records", Ty::I),
        ("n_overturned", Ty::I),
    ],
};

pub const VERTICAL: Flat = Flat {
    kind: kind("fractiles_vertical"),
    columns: &[
        ("block", Ty::S),
        ("p", Ty::F),
        ("eps", Ty::F),
        ("edp", Ty::F),
        ("eta_q16", Ty::F),
        ("eta_q50", Ty::F),
        ("eta_q84", Ty::F),
        ("n_records", Ty::I),
        ("n_not_reached", Ty::I),
    ],
};

pub const CAPACITY_FRACTILES: Flat = Flat {
    kind: kind("capacity_fractiles"),
    columns: &[
        ("block", Ty::S),
        ("p", Ty::F),
        ("eps", Ty::F),
        ("quantile", Ty::F),
        ("eta_c", Ty::F),
        ("eta_c_horizontal", Ty::Fn),
        ("n_records", Ty::I),
        ("n_censored", Ty::I),
    ],
};

pub const LOGNORMAL: Flat = Flat {
    kind: kind("lognormal"),
    columns: &[
        ("block", Ty::S),
        ("p", Ty::F),
        ("eps", Ty::F),
        ("n", Ty::I),
        ("median_sample", Ty::Fn),
        ("beta_sample", Ty::Fn),
        ("median_fractile", Ty::Fn),
        ("beta_fractile", Ty::Fn),
        ("lilliefors_d", Ty::Fn),
        ("p_value", Ty::Fn),
        ("critical_d_5pct", Ty::Fn),
        ("rejected_5pct", Ty::B),
    ],
};

pub const OVERTURN_FRACTION: Flat = Flat {
    kind: kind("overturn_fraction"),
    columns: &[
        ("block", Ty::S),
        ("p", Ty::F),
        ("eps", Ty::F),
        ("level", Ty::I),
        ("eta", Ty::F),
        ("fraction_plain", Ty::Fn),
        ("fraction_resurrection", Ty::F),
    ],
};

pub const FIT_STEP1: Flat = Flat {
    kind: kind("fit_step1"),
    columns: &[
        ("eps", Ty::F),
        ("quantile", Ty::F),
        ("a", Ty::Fn),
        ("b", Ty::Fn),
        ("c", Ty::Fn),
        ("rms", Ty::Fn),
        ("iterations", Ty::I),
        ("stop", Ty::S),
        ("converged", Ty::B),
    ],
};

pub const FIT_COEFFICIENTS: Flat = Flat {
    kind: kind("fit_coefficients"),
    columns: &[
        ("source", Ty::S),
        ("quantile", Ty::F),
        ("coefficient", Ty::S),
        ("c0", Ty::Fn),
        ("c1", Ty::Fn),
        ("c2", Ty::Fn),
    ],
};

pub const FIT_COMPARISON: Flat = Flat {
    kind: kind("fit_comparison"),
    columns: &[
        ("p", Ty::F),
        ("eps", Ty::F),
        ("quantile", Ty::F),
        ("eta_c_data", Ty::F),
        ("eta_c_step1", Ty::Fn),
        ("eta_c_fit", Ty::Fn),
        ("eta_c_paper", Ty::F),
    ],
};

pub const CONVERGENCE: Flat = Flat {
    kind: kind("capacity_convergence"),
    columns: &[
        ("block", Ty::S),
        ("p", Ty::F),
        ("eps", Ty::F),
        ("levels", Ty::I),
        ("eta_c_q16", Ty::F),
        ("eta_c_q50", Ty::F),
        ("eta_c_q84", Ty::F),
        ("n_records", Ty::I),
        ("n_changed", Ty::I),
        ("mean_abs_change", Ty::F),
        ("max_abs_change", Ty::F),
    ],
};
