//! The convergence stage's table: the capacity search at several IM-grid
//! resolutions. Each column is documented on its field (generated into
//! docs/tables.md).

use crate::table;

table! {
    /// One row per block × grid resolution.
    ///
    /// Written by the convergence stage (pipelines with `[convergence] levels`) in
    /// `outputs/<name>/capacity_convergence.parquet`: the capacity search repeated at each
    /// resolution, each compared with the finest (the largest level count). Its metadata
    /// holds `rocking.convergence.levels` (the level counts).
    pub struct ConvergenceRow = "capacity_convergence" v 1 {
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// Number of IM levels of this grid (the same range and spacing as the pipeline's).
        pub levels: i64,
        /// The 16 % capacity fractile over the records at this resolution (a record that
        /// survives every level counts as η_c = 0).
        pub eta_c_q16: f64,
        /// The 50 % capacity fractile over the records at this resolution (a record that
        /// survives every level counts as η_c = 0).
        pub eta_c_q50: f64,
        /// The 84 % capacity fractile over the records at this resolution (a record that
        /// survives every level counts as η_c = 0).
        pub eta_c_q84: f64,
        /// Number of records.
        pub n_records: i64,
        /// Records whose η_c differs from the finest grid's by more than twice `im.tol`.
        pub n_changed: i64,
        /// The mean over the records of |η_c − η_c(finest grid)|.
        pub mean_abs_change: f64,
        /// The largest |η_c − η_c(finest grid)| over the records.
        pub max_abs_change: f64,
    }
}

table! {
    /// One row per record × block × grid resolution: the capacity each search found.
    ///
    /// Written by the convergence stage beside `capacity_convergence.parquet`, in
    /// `outputs/<name>/convergence_capacities.parquet`, records by id, then blocks in
    /// pipeline order, then resolutions as `[convergence] levels` lists them: the values
    /// `capacity_convergence` sums up, for a query of which records' capacities move with
    /// the grid. Its metadata holds `rocking.convergence.levels` and
    /// `rocking.convergence.record_keys` (each record's key, by id: a rerun searches again
    /// only the records whose key changed).
    pub struct ConvergenceCaseRow = "convergence_capacities" v 1 {
        /// The record (its AT2 file stem).
        pub record_id: String,
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// Number of IM levels of this grid (the same range and spacing as the pipeline's).
        pub levels: i64,
        /// The capacity at this resolution (as `capacities.eta_c`); empty if the block
        /// survived every level (counted as 0 in `capacity_convergence`).
        pub eta_c: Option<f64>,
    }
}
