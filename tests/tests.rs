//! Integration tests, one binary (ripgrep's layout): each module below tests
//! one command or stage end to end through the `rocking` binary or the
//! library's public API.
//!
//! - `ingest`: the records table from the bundled FEMA P695 files, checked
//!   against the manifest and the files; bad input and atomic output.
//! - `util`: helpers (running the binary, an independent AT2 reader).

mod ingest;
mod util;
