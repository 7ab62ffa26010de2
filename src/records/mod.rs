//! The records a run, a command or a study shakes its blocks with (reads
//! files; no figures, no tables written):
//!
//! - [`discover`]: the files a list of paths names (AT2 or text);
//! - [`collect`]: the AT2 files a list of paths names, read, checked
//!   against a manifest, record ids unique (the ingest stage, a pipeline
//!   reading AT2 files, `capacity --record`, `--direct`);
//! - [`load`]: one record ready to run (a file, samples, a pulse), on the
//!   ground or a building's floor;
//! - [`select`]: the records a pipeline selects (its table or its files,
//!   filtered by set and id), and the motion its blocks feel under each.

pub mod collect;
pub mod discover;
pub mod load;
pub mod pairs;
pub mod select;

pub use collect::{
    collect, collect_as, BadFile, CollectError, Collected, OnBad, Problem, PIPELINE_HINT,
    TEXT_LAYOUT,
};
pub use discover::{discover, discover_text, TEXT_EXTENSIONS};
pub use load::{
    excitation, from_pulse, from_samples, load, load_on, pair_at, read_samples, LoadedRecord,
    OnFloor, RecordError, SampleError,
};
pub use pairs::{pair_up, rotated_rows, RowPair};
pub use select::{felt, of_plan, rows_if_table, select, select_pairs, stood_on, SelectError};
