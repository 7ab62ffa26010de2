//! Why the reduce stage fails.

use crate::stages::sweep::DatasetError;
use crate::tables::TableError;

#[derive(Debug, thiserror::Error)]
pub enum ReduceError {
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("the sweep tables do not match the pipeline: {0}; rerun `rocking sweep`")]
    Mismatch(String),
    #[error(transparent)]
    Records(#[from] crate::records::SelectError),
    #[error(
        "[uncertainty] unit = \"pair\" resamples the manifest's pairs, and record {0} has \
         none: give the pipeline a manifest with pairs, or set unit = \"record\""
    )]
    NoPair(String),
    #[error("record {0} has no motion (every sample is 0)")]
    NoMotion(String),
    #[error(transparent)]
    NotRecords(#[from] crate::pipeline::NotRecords),
}
