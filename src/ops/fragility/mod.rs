//! `rocking fragility`: the probability that a real block overturns at given
//! levels of an IM. The fragility is the block's one fragility
//! ([`super::damage::of_block`], the overturning state): in PGA from the
//! paper's regression or a pipeline's fit, in another IM from a study's IM
//! table, or from the records' own capacities (`--direct`), by the fit
//! asked (the fractiles by default); with `--direct` also the share of
//! records the block overturns under.
//!
//! - `request`: what is asked, checked, and the records and laws it needs;
//! - `assess`: the answer;
//! - `direct`: `--direct`'s records and the progress of their searches;
//! - `pairs`: the motions an orientation rule runs over record pairs;
//! - `laws`: where the capacities come from (the paper, a study's fit, IM
//!   and damage tables), checked to be the pipeline's as it stands;
//! - `error`: every refusal.

mod assess;
mod direct;
mod error;
mod laws;
mod model;
mod pairs;
mod request;

pub use assess::{assess, Assessment, Point};
pub use direct::{DirectProgress, DirectRecords};
pub use error::FragilityError;
pub use laws::{default_records, laws, Laws, Source};
pub use model::RunModel;
pub use pairs::Orient;
pub use request::{
    alpha_warning, block, check, laws_and_records, model_warning, warnings, Request,
};
