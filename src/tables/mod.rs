//! The one module that reads and writes Parquet.
//!
//! Every table the tool writes has its schema defined once, in a submodule
//! here, and that schema is used by its writer, its reader and the docs.
//! Every file carries key-value metadata: `rocking.table`,
//! `rocking.schema_version`, `rocking.crate_version`, plus whatever settings the
//! writing stage adds. Files are written to a temporary sibling, closed and
//! then renamed into place, so a crash or an error never leaves a
//! half-written table under the final name.
//!
//! Tables are typed: a table is a row struct defined once with the
//! [`table!`](crate::table) macro (or, for the records table, by hand), which
//! gives its schema, its writer and its reader. Code reads rows as structs and
//! never looks a column up by a string. [`write`] and [`read`] work for every
//! [`Table`].
//!
//! Architecture invariant: nothing outside `tables` imports `parquet` or
//! opens a Parquet file.

pub mod column;
pub mod convergence;
pub mod damage;
mod error;
mod file;
pub mod fit;
pub mod history;
pub mod ims;
pub mod pulse;
pub mod records;
pub mod reduce;
pub mod reference;
pub mod risk;
pub mod sweep;
mod table;

pub use crate::label::Label;
pub use column::{read_column, Column};
pub use error::TableError;
pub use file::{
    atomic_write, atomic_write_all, orphaned_temporary, read, read_all, read_metadata, read_table,
    row_count, temporary_of, to_bytes, write, write_batches, Appender, AtomicTableWriter, Batches,
    TableContents, META_CRATE_VERSION, META_SCHEMA_VERSION, META_TABLE, READ_BATCH_ROWS,
};
pub use table::{Table, TableKind, ROW_GROUP_ROWS};
