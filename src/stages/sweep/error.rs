//! Why a sweep fails.

use std::io;
use std::path::PathBuf;

use super::dataset::DatasetError;
use super::layout::CHUNK_CASES;
use crate::physics::PhysicsError;
use crate::records::SelectError;
use crate::stages::stage::Shard;
use crate::tables::TableError;

#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error(transparent)]
    Records(#[from] SelectError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error("record {record}")]
    Record {
        record: String,
        #[source]
        source: PhysicsError,
    },
    #[error("{path}")]
    Io {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error(transparent)]
    Dataset(#[from] DatasetError),
    #[error(
        "--shard {shard}: the sweep has {chunks} chunk(s) of {CHUNK_CASES} cases, so at most \
         {chunks} shards have work; give N ≤ {chunks}"
    )]
    TooManyShards { shard: Shard, chunks: usize },
}
