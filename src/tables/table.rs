//! What a table is ([`Table`]: its identity, schema, batch builder and
//! reader) and the [`table!`](crate::table) macro that derives all of it
//! from one list of fields.

use std::path::Path;
use std::sync::Arc;

use arrow_array::RecordBatch;
use arrow_schema::{ArrowError, Schema};

use super::error::TableError;

/// Rows per row group: bounds the writer's buffer (a million-run sweep is
/// streamed, never held whole).
pub const ROW_GROUP_ROWS: usize = 65_536;

/// Identity of a table: its name and schema version.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TableKind {
    pub name: &'static str,
    pub schema_version: u32,
}

/// A table: its rows are `Self`. Implemented by the [`table!`](crate::table)
/// macro from one list of fields, so schema, writer and reader cannot
/// disagree.
pub trait Table: Sized {
    const KIND: TableKind;
    /// The row type's doc comment, line by line: what a row is, where the
    /// table is written (`docs/tables.md`).
    const DOC: &'static [&'static str];
    /// Each column's name and doc comment, in order.
    const COLUMN_DOCS: &'static [(&'static str, &'static [&'static str])];
    /// The labels each column may hold where it is a closed set's, in
    /// order ([`super::Column::values`]).
    fn column_values() -> Vec<Option<String>>;
    /// Rows per batch (and so at most per row group) when writing.
    const BATCH_ROWS: usize = ROW_GROUP_ROWS;
    fn schema() -> Arc<Schema>;
    fn to_batch(rows: &[Self]) -> Result<RecordBatch, ArrowError>;
    /// The rows of one batch read back; errors name the file and the column.
    fn from_batch(batch: &RecordBatch, path: &Path) -> Result<Vec<Self>, TableError>;
}

/// Defines a table's row type and, from the same field list, its schema,
/// batch builder, reader and reference ([`Table`]). Field names are the
/// column names, in order; field types are [`Column`]s; the doc comments
/// of the struct and of each field (the only attributes allowed) are the
/// table's documentation (`docs/tables.md`, [`super::reference`]).
///
/// ```ignore
/// table! {
///     /// One row per block × quantile.
///     pub struct CapacityFractileRow = "capacity_fractiles" v1 {
///         pub block: String,
///         pub eta_c: f64,
///         pub eta_c_horizontal: Option<f64>,
///     }
/// }
/// ```
#[macro_export]
macro_rules! table {
    (
        $(#[doc = $doc:literal])*
        pub struct $name:ident = $table:literal v $version:literal {
            $( $(#[doc = $fdoc:literal])* pub $field:ident : $ty:ty, )*
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Debug, Clone, PartialEq)]
        pub struct $name {
            $( $(#[doc = $fdoc])* pub $field: $ty, )*
        }

        impl $crate::tables::Table for $name {
            const KIND: $crate::tables::TableKind = $crate::tables::TableKind {
                name: $table,
                schema_version: $version,
            };
            const DOC: &'static [&'static str] = &[$($doc),*];
            const COLUMN_DOCS: &'static [(&'static str, &'static [&'static str])] =
                &[$( (stringify!($field), &[$($fdoc),*]) ),*];

            fn column_values() -> Vec<Option<String>> {
                vec![ $( <$ty as $crate::tables::Column>::values(), )* ]
            }

            fn schema() -> ::std::sync::Arc<::arrow_schema::Schema> {
                static SCHEMA: ::std::sync::OnceLock<::std::sync::Arc<::arrow_schema::Schema>> =
                    ::std::sync::OnceLock::new();
                SCHEMA
                    .get_or_init(|| {
                        ::std::sync::Arc::new(::arrow_schema::Schema::new(vec![
                            $( <$ty as $crate::tables::Column>::field(stringify!($field)), )*
                        ]))
                    })
                    .clone()
            }

            fn to_batch(
                rows: &[Self],
            ) -> Result<::arrow_array::RecordBatch, ::arrow_schema::ArrowError> {
                ::arrow_array::RecordBatch::try_new(
                    Self::schema(),
                    vec![ $( <$ty as $crate::tables::Column>::build(rows.iter().map(|r| &r.$field)), )* ],
                )
            }

            fn from_batch(
                batch: &::arrow_array::RecordBatch,
                path: &::std::path::Path,
            ) -> Result<Vec<Self>, $crate::tables::TableError> {
                $( let mut $field = $crate::tables::read_column::<$ty>(batch, stringify!($field), path)?
                    .into_iter(); )*
                let mut rows = Vec::with_capacity(batch.num_rows());
                for _ in 0..batch.num_rows() {
                    rows.push($name {
                        $( $field: $field.next().expect("a column holds one value per row"), )*
                    });
                }
                Ok(rows)
            }
        }
    };
}
