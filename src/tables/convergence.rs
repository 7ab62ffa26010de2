//! The convergence stage's table: the capacity search at several IM-grid
//! resolutions; columns are documented in the README.

use crate::table;

table! {
    /// One block at one grid resolution.
    pub struct ConvergenceRow = "capacity_convergence" v 1 {
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub levels: i64,
        pub eta_c_q16: f64,
        pub eta_c_q50: f64,
        pub eta_c_q84: f64,
        pub n_records: i64,
        /// Records whose η_c differs from the finest grid's by more than 2·tol.
        pub n_changed: i64,
        pub mean_abs_change: f64,
        pub max_abs_change: f64,
    }
}
