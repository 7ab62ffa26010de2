//! What goes wrong reading or writing a table, naming the file and, where
//! one is at fault, the column.

use std::io;
use std::path::PathBuf;

use arrow_schema::ArrowError;
use parquet::errors::ParquetError;

#[derive(Debug, thiserror::Error)]
pub enum TableError {
    #[error("{path}")]
    Io { path: PathBuf, source: io::Error },
    #[error("{path}")]
    Parquet { path: PathBuf, source: ParquetError },
    #[error("{path}")]
    Arrow { path: PathBuf, source: ArrowError },
    #[error(
        "{path}: this is not a `{expected}` table (its metadata says `{found}`); \
         give the file written by the matching stage"
    )]
    WrongTable {
        path: PathBuf,
        expected: &'static str,
        found: String,
    },
    #[error(
        "{path}: `{table}` schema version {found}, but this build of rocking reads version {expected}; \
         rerun the stage that writes it"
    )]
    SchemaVersion {
        path: PathBuf,
        table: &'static str,
        expected: u32,
        found: String,
    },
    #[error("{path}: column `{column}`: {problem}")]
    Column {
        path: PathBuf,
        column: &'static str,
        problem: String,
    },
}
