//! The reduce stage's tables (docs/MODEL.md §5). Every one starts with the
//! block (`block` label, empty for the grid, `p`, `eps`); columns are
//! documented in the README.

use crate::physics::EquationKind;
use crate::stats::ResampleUnit;
use crate::table;

table! {
    /// The pipeline's blocks, one row each, in the pipeline's order: what
    /// every other table's `p`, `eps` (and `block`) refer to, with their
    /// places in the grid to filter and join on.
    pub struct BlockRow = "blocks" v 1 {
        /// The block's place in the pipeline (a sweep case's `case_id`
        /// modulo the number of blocks).
        pub block_index: i64,
        pub block: String,
        pub p: f64,
        pub eps: f64,
        /// The index of `p` among the grid's p values (`[blocks] p`, from 0);
        /// null for `[[block]]` entries.
        pub p_index: Option<i64>,
        /// The index of `eps` among the grid's ε values; null for `[[block]]`.
        pub eps_index: Option<i64>,
        /// Slenderness α (rad) when the block has one (dimensions, or `model.alpha`).
        pub alpha_rad: Option<f64>,
        /// The equation it runs.
        pub model: EquationKind,
    }
}

table! {
    /// Horizontal statistics: EDP fractiles at one grid level of one block.
    pub struct HorizontalRow = "fractiles_horizontal" v 1 {
        pub block: String,
        pub p: f64,
        pub eps: f64,
        /// Index of the grid level (0 = weakest shaking).
        pub level: i64,
        pub eta: f64,
        /// θmax/α fractiles; +∞ under the resurrection rule.
        pub edp_q16: f64,
        pub edp_q50: f64,
        pub edp_q84: f64,
        pub n_records: i64,
        /// Records overturned at this or a weaker level.
        pub n_overturned: i64,
    }
}

table! {
    /// Vertical statistics: η fractiles at which the EDP first reaches `edp`.
    pub struct VerticalRow = "fractiles_vertical" v 1 {
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub edp: f64,
        pub eta_q16: f64,
        pub eta_q50: f64,
        pub eta_q84: f64,
        pub n_records: i64,
        pub n_not_reached: i64,
    }
}

table! {
    /// A capacity fractile of one block.
    pub struct CapacityFractileRow = "capacity_fractiles" v 1 {
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub quantile: f64,
        /// Fractile of the records' η_c (a record that never overturned counts as 0).
        pub eta_c: f64,
        /// The largest grid level at which that EDP fractile is +∞ or ≥ 1.
        pub eta_c_horizontal: Option<f64>,
        pub n_records: i64,
        pub n_censored: i64,
    }
}

table! {
    /// A percentile bootstrap band of one capacity fractile of one block
    /// (pipeline key `[uncertainty]`).
    pub struct CapacityBandRow = "capacity_bands" v 1 {
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub quantile: f64,
        /// The point estimate, as in capacity_fractiles.
        pub eta_c: f64,
        /// The band: the (1 − level)/2 and (1 + level)/2 percentiles of the
        /// fractile over the resamples.
        pub lo: f64,
        pub hi: f64,
        pub level: f64,
        pub resamples: i64,
        pub unit: ResampleUnit,
    }
}

table! {
    /// One bootstrap resample's capacity fractile of one block. A resample
    /// is one draw of whole units (pairs or records) applied to every block,
    /// so the fit stage can refit each resample's whole grid.
    pub struct CapacityResampleRow = "capacity_resamples" v 1 {
        /// 0, 1, …, resamples − 1; resample r draws from stream r of the seed.
        pub resample: i64,
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub quantile: f64,
        pub eta_c: f64,
    }
}

table! {
    /// Lognormality of one block's η_c (Lilliefors).
    pub struct LognormalRow = "lognormal" v 1 {
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub n: i64,
        pub median_sample: Option<f64>,
        pub beta_sample: Option<f64>,
        pub median_fractile: Option<f64>,
        pub beta_fractile: Option<f64>,
        pub lilliefors_d: Option<f64>,
        pub p_value: Option<f64>,
        pub critical_d_5pct: Option<f64>,
        pub rejected_5pct: bool,
    }
}

table! {
    /// Share of records overturned at one grid level of one block.
    pub struct OverturnFractionRow = "overturn_fraction" v 1 {
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub level: i64,
        pub eta: f64,
        /// Empty where some record was not run at this level.
        pub fraction_plain: Option<f64>,
        pub fraction_resurrection: f64,
    }
}
