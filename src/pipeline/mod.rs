//! Pipeline files: TOML in, a typed plan out (pure: text in, values out).
//!
//! Two layers (ripgrep's LowArgs/HiArgs): [`RawPipeline`] mirrors the file
//! with `deny_unknown_fields`, so a misspelt key is an error that names it;
//! [`resolve`] checks every value and builds the [`Plan`] the stages see:
//! paths resolved against the pipeline file's folder, grids expanded into
//! lists, the model and overturning criterion typed. Every key is documented
//! in `pipelines/README.md`.

//! - [`raw`]: the file's sections as written;
//! - [`checks`]: checkers both study kinds use;
//! - [`plan`]: the resolved [`Plan`] and its limits;
//! - [`resolve`]: the checkers that turn the one into the other;
//! - [`pulse_map`]: the same for a pulse map's `[pulses]`.

mod checks;
mod plan;
mod pulse_map;
mod raw;
mod resolve;
mod tree;

pub use crate::ida::MAX_LEVELS;
pub use plan::*;
pub use raw::*;
pub use resolve::{load_str, resolve};
