//! `rocking risk`: the annual rate of overturning of a block (or of every
//! block of an inventory) at the sites of a hazard file, with its
//! deaggregation by PGA. The integral is [`crate::risk`]'s; this module reads
//! the files, builds each block's fragility (the paper's regression, a
//! pipeline's fit, or `--direct` capacities under the records), says where
//! the regression is stretched, and writes the table and the figures.

mod answer;
mod assess;
mod bootstrap;
mod charts;
mod error;
mod events;
mod fields;
mod inventory;
mod request;
mod states;
mod table;
mod tree;

pub use answer::{Assessment, BinInfo, BlockInfo, BranchRate, FragilityInfo, SiteInfo};
pub use assess::{assess, block_info, hazard_im, hazard_warnings, read_hazard};
pub use bootstrap::{draws, Bootstrap, BootstrapInfo, BAND_LEVEL};
pub use charts::{deaggregation_chart, ranking_chart};
pub use error::{check_years, RiskError};
pub use events::{assess_events, Counts, EventSite, EventsAssessment, EventsBlock, RETURN_PERIODS};
pub use fields::read_fields;
pub use inventory::{read_inventory, InventoryBlock};
pub use request::{Blocks, EventsAsk, Hazard, Request};
pub use states::{assess_states, StateRisk, StatesAssessment, StatesSite};
pub use table::{rows, write_table};
