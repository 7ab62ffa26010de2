//! Cell types of the tables: how one Rust type becomes one Arrow column and
//! back. Every table row is a struct whose fields are [`Column`]s; the
//! [`table!`](crate::table) macro turns such a struct into its schema, its
//! batch builder and its reader, so a table is defined once.
//!
//! Closed sets stored as text (run kinds, model names, fit stop reasons)
//! implement [`Label`]: they are written as their label and read back as
//! the enum, and an unknown label is an error that lists the valid ones.

use std::path::Path;
use std::sync::Arc;

use arrow_array::builder::{Float64Builder, ListBuilder};
use arrow_array::cast::AsArray;
use arrow_array::types::{Float64Type, Int64Type, Int8Type};
use arrow_array::{
    Array, ArrayRef, BooleanArray, Float64Array, Int64Array, Int8Array, RecordBatch, StringArray,
};
use arrow_schema::{DataType, Field};

use crate::label::Label;

use super::error::TableError;

/// A type that is stored as one column.
pub trait Column: Sized {
    /// The Arrow field of a column of this type named `name`.
    fn field(name: &str) -> Field;
    /// Builds the column from the values of every row, in order.
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef
    where
        Self: 'a;
    /// Reads a column back. `Err` says what is wrong (a type this build
    /// does not expect, a null where none is allowed, an unknown label).
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String>;
    /// The values a text column may hold, for the reference
    /// (`docs/tables.md`): a closed set's labels; `None` for any.
    fn values() -> Option<String> {
        None
    }
}

fn wrong_type(array: &ArrayRef, expected: &str) -> String {
    format!("holds {}, expected {expected}", array.data_type())
}

fn no_nulls(array: &ArrayRef) -> Result<(), String> {
    match array.null_count() {
        0 => Ok(()),
        n => Err(format!(
            "holds {n} empty value(s) in a column that allows none"
        )),
    }
}

impl Column for f64 {
    fn field(name: &str) -> Field {
        Field::new(name, DataType::Float64, false)
    }
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
        Arc::new(values.map(|v| Some(*v)).collect::<Float64Array>())
    }
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
        let a = array
            .as_primitive_opt::<Float64Type>()
            .ok_or_else(|| wrong_type(array, "float64"))?;
        no_nulls(array)?;
        Ok(a.values().to_vec())
    }
}

impl Column for Option<f64> {
    fn field(name: &str) -> Field {
        Field::new(name, DataType::Float64, true)
    }
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
        Arc::new(values.copied().collect::<Float64Array>())
    }
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
        let a = array
            .as_primitive_opt::<Float64Type>()
            .ok_or_else(|| wrong_type(array, "float64"))?;
        Ok(a.iter().collect())
    }
}

impl Column for i64 {
    fn field(name: &str) -> Field {
        Field::new(name, DataType::Int64, false)
    }
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
        Arc::new(values.map(|v| Some(*v)).collect::<Int64Array>())
    }
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
        let a = array
            .as_primitive_opt::<Int64Type>()
            .ok_or_else(|| wrong_type(array, "int64"))?;
        no_nulls(array)?;
        Ok(a.values().to_vec())
    }
}

impl Column for Option<i64> {
    fn field(name: &str) -> Field {
        Field::new(name, DataType::Int64, true)
    }
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
        Arc::new(values.copied().collect::<Int64Array>())
    }
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
        let a = array
            .as_primitive_opt::<Int64Type>()
            .ok_or_else(|| wrong_type(array, "int64"))?;
        Ok(a.iter().collect())
    }
}

impl Column for i8 {
    fn field(name: &str) -> Field {
        Field::new(name, DataType::Int8, false)
    }
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
        Arc::new(values.map(|v| Some(*v)).collect::<Int8Array>())
    }
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
        let a = array
            .as_primitive_opt::<Int8Type>()
            .ok_or_else(|| wrong_type(array, "int8"))?;
        no_nulls(array)?;
        Ok(a.values().to_vec())
    }
}

impl Column for bool {
    fn field(name: &str) -> Field {
        Field::new(name, DataType::Boolean, false)
    }
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
        Arc::new(values.map(|v| Some(*v)).collect::<BooleanArray>())
    }
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
        let a = array
            .as_boolean_opt()
            .ok_or_else(|| wrong_type(array, "boolean"))?;
        no_nulls(array)?;
        Ok(a.values().iter().collect())
    }
}

impl Column for String {
    fn field(name: &str) -> Field {
        Field::new(name, DataType::Utf8, false)
    }
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
        Arc::new(values.map(|v| Some(v.as_str())).collect::<StringArray>())
    }
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
        let a = array
            .as_string_opt::<i32>()
            .ok_or_else(|| wrong_type(array, "utf8"))?;
        no_nulls(array)?;
        Ok(a.iter()
            .map(|v| v.unwrap_or_default().to_string())
            .collect())
    }
}

impl Column for Option<String> {
    fn field(name: &str) -> Field {
        Field::new(name, DataType::Utf8, true)
    }
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
        Arc::new(values.map(|v| v.as_deref()).collect::<StringArray>())
    }
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
        let a = array
            .as_string_opt::<i32>()
            .ok_or_else(|| wrong_type(array, "utf8"))?;
        Ok(a.iter().map(|v| v.map(str::to_string)).collect())
    }
}

/// A list of floats per row (the samples of a record).
impl Column for Vec<f64> {
    fn field(name: &str) -> Field {
        Field::new(
            name,
            DataType::List(Arc::new(Field::new("item", DataType::Float64, false))),
            false,
        )
    }
    fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
        let mut list = ListBuilder::new(Float64Builder::new()).with_field(Arc::new(Field::new(
            "item",
            DataType::Float64,
            false,
        )));
        for v in values {
            list.values().append_slice(v);
            list.append(true);
        }
        Arc::new(list.finish())
    }
    fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
        let lists = array
            .as_list_opt::<i32>()
            .ok_or_else(|| wrong_type(array, "list<float64>"))?;
        no_nulls(array)?;
        (0..lists.len())
            .map(|k| {
                let item = lists.value(k);
                item.as_primitive_opt::<Float64Type>()
                    .map(|a| a.values().to_vec())
                    .ok_or_else(|| wrong_type(&item, "float64 items"))
            })
            .collect()
    }
}

/// Implements [`Column`] (text) for [`Label`] types.
macro_rules! label_columns {
    ($($t:ty),* $(,)?) => {$(
        impl Column for $t {
            fn field(name: &str) -> Field {
                Field::new(name, DataType::Utf8, false)
            }
            fn build<'a>(values: impl Iterator<Item = &'a Self>) -> ArrayRef {
                Arc::new(values.map(|v| Some(v.label())).collect::<StringArray>())
            }
            fn read(array: &ArrayRef) -> Result<Vec<Self>, String> {
                let a = array
                    .as_string_opt::<i32>()
                    .ok_or_else(|| wrong_type(array, "utf8"))?;
                no_nulls(array)?;
                a.iter()
                    .map(|v| {
                        let text = v.unwrap_or_default();
                        <$t as Label>::from_label(text).ok_or_else(|| {
                            format!("unknown value `{text}`; valid: {}", <$t as Label>::labels())
                        })
                    })
                    .collect()
            }
            fn values() -> Option<String> {
                Some(<$t as Label>::labels())
            }
        }
    )*};
}

label_columns!(
    crate::ida::RunKind,
    crate::ida::CertificationKind,
    crate::physics::EquationKind,
    crate::physics::EventKind,
    crate::fit::Stop,
    super::fit::Source,
    super::fit::Coefficient,
    super::fit::BandCurve,
    crate::risk::Beyond,
    crate::stats::ResampleUnit,
    crate::damage::FitMethod,
);

/// One column of a batch as values of type `C`; errors name file and column.
pub fn read_column<C: Column>(
    batch: &RecordBatch,
    name: &'static str,
    path: &Path,
) -> Result<Vec<C>, TableError> {
    let array: &ArrayRef = batch
        .column_by_name(name)
        .ok_or_else(|| TableError::Column {
            path: path.into(),
            column: name,
            problem: "missing".into(),
        })?;
    C::read(array).map_err(|problem| TableError::Column {
        path: path.into(),
        column: name,
        problem,
    })
}
