//! The damage stage's tables (docs/MODEL.md §15): each record's capacity for
//! each limit state, and each state's lognormal in every IM. Columns are
//! documented in the README.

use crate::damage::FitMethod;
use crate::table;

table! {
    /// One record's capacity for one limit state of one block.
    pub struct StateCapacityRow = "state_capacities" v 1 {
        /// The block's row in `blocks.parquet` (0 for the example block).
        pub block_index: i64,
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub record_id: String,
        /// The state's name (`[damage] states`), lightest first.
        pub state: String,
        /// Where the record reaches the state: η = αg/PGA of the first
        /// crossing as intensity rises (interpolated in 1/η); where it does
        /// not, the η of its strongest run (the capacity lies beyond it).
        pub eta: f64,
        pub reached: bool,
    }
}

table! {
    /// One limit state's lognormal fragility of one block in one IM, by one method.
    pub struct DamageStateRow = "damage_states" v 1 {
        pub block_index: i64,
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub state: String,
        /// `θmax/α ≥ 0.1` or `overturned`.
        pub criterion: String,
        /// The θmax/α threshold; null for overturning.
        pub threshold: Option<f64>,
        /// `pga`, `pgv`, `sa(1.0)`, … as in `im_efficiency`.
        pub im: String,
        pub unit: String,
        /// `fractile` (the paper's 16/50/84 %) or `mle` (censored maximum likelihood).
        pub method: FitMethod,
        pub n_records: i64,
        /// Records that reach the state within their runs.
        pub n_reached: i64,
        /// The median capacity in `unit`; null for a block without α.
        pub median: Option<f64>,
        /// The median in the IM's dimensionless form (`dimensionless`).
        pub median_dimensionless: Option<f64>,
        pub dimensionless: Option<String>,
        /// Dispersion: the standard deviation of ln capacity. Median and β
        /// are null where the method has no fit (too few records reach the state).
        pub beta: Option<f64>,
    }
}
