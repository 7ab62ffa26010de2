//! The damage stage's tables (docs/MODEL.md §15): each record's capacity for
//! each limit state, and each state's lognormal in every IM. Each column is
//! documented on its field (generated into docs/tables.md).

use crate::damage::FitMethod;
use crate::table;

table! {
    /// One row per block × record × limit state.
    ///
    /// Written by the damage stage in `outputs/<name>/state_capacities.parquet`: each
    /// record's capacity for each of the pipeline's `[damage] states` (default
    /// `rocking=0.1,large_rocking=0.5,overturned=overturned`; docs/MODEL.md §15). With
    /// `[example]`, `example_state_capacities.parquet` holds the same of the example block
    /// (`block_index` 0). The metadata holds `rocking.damage.states`.
    pub struct StateCapacityRow = "state_capacities" v 1 {
        /// The block's row in `blocks.parquet` (0 for the example block).
        pub block_index: i64,
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// The record (its AT2 file stem).
        pub record_id: String,
        /// The state's name (`[damage] states`), lightest first.
        pub state: String,
        /// Where the record reaches the state: η = αg/PGA of the first crossing as
        /// intensity rises (interpolated in 1/η between the runs around it; η_c for
        /// overturning). Where it does not: the η of its strongest run (the capacity lies
        /// beyond it). On a building's floor, the floor motion's η, as in `capacities`.
        pub eta: f64,
        /// Whether the record reaches the state within its runs.
        pub reached: bool,
    }
}

table! {
    /// One row per block × limit state × IM × method: the state's lognormal fragility.
    ///
    /// Written by the damage stage in `outputs/<name>/damage_states.parquet`: each of the
    /// pipeline's `[damage] states` (default
    /// `rocking=0.1,large_rocking=0.5,overturned=overturned`; docs/MODEL.md §15) fitted in
    /// every IM a capacity is stated in, by the paper's fractiles and by censored maximum
    /// likelihood. On a building's floor the IMs are the ground record's. With `[example]`,
    /// `example_damage_states.parquet` holds the same of the example block (`block_index`
    /// 0). The metadata holds `rocking.damage.states`.
    pub struct DamageStateRow = "damage_states" v 2 {
        /// The block's row in `blocks.parquet` (0 for the example block).
        pub block_index: i64,
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// The state's name (`[damage] states`), lightest first.
        pub state: String,
        /// The state's criterion: `θmax/α ≥ x` (e.g. `θmax/α ≥ 0.1`) or `overturned`.
        pub criterion: String,
        /// The criterion's θmax/α threshold x; empty for overturning.
        pub threshold: Option<f64>,
        /// The IM: `pga`, `pgv`, `pgd`, `avgsa`, `arias`, `cav`, or `sa(T)` with T the
        /// period in s (e.g. `sa(1.0)`); over text records (a structural model's floor
        /// motions, no `[floor]`) the floor's `pfa`, `pfv` or `fsa(T)`.
        pub im: String,
        /// The IM's unit: g (PGA, SA, AvgSA, PFA, FSA), cm/s (PGV, PFV), cm (PGD), m/s
        /// (Arias intensity) or g·s (CAV).
        pub unit: String,
        /// `fractile` (the paper's 16/50/84 % fractiles, records not reaching the state at
        /// +∞) or `mle` (censored maximum likelihood, records not reaching the state
        /// censored at their strongest run).
        pub method: FitMethod,
        /// Number of records.
        pub n_records: i64,
        /// Records that reach the state within their runs.
        pub n_reached: i64,
        /// The median capacity, in `unit`; empty for a block without α, or without a fit.
        pub median: Option<f64>,
        /// The median in the IM's dimensionless form (named in `dimensionless`); empty
        /// without a fit, or for an IM without one (`arias`, `cav`).
        pub median_dimensionless: Option<f64>,
        /// The name of the IM's dimensionless form (`PGA/(αg)`, `p·PGV/(αg)`,
        /// `p²·PGD/(αg)`, `SA/(αg)`, `AvgSA/(αg)`); empty for an IM without one.
        pub dimensionless: Option<String>,
        /// The dispersion β, the standard deviation of ln capacity; empty without a fit
        /// (the 84 % fractile beyond the runs, or fewer than two records reaching the
        /// state).
        pub beta: Option<f64>,
        /// Lilliefors' p of the logarithms of the records' capacities in this IM (the
        /// same in both methods' rows); below 0.05 the lognormal is rejected, and
        /// `fragility --direct` gives the records' own curve there. Empty where some
        /// record does not reach the state, or fewer than 5 records do.
        pub lognormal_p: Option<f64>,
    }
}
