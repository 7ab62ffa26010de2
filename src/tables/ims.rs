//! The ims stage's tables (docs/MODEL.md §14): the records' intensity
//! measures and each block's capacity dispersion in every IM. Columns are
//! documented in the README.

use crate::table;

table! {
    /// One measure of one record, unscaled (docs/MODEL.md §14): every
    /// measure of `Im::record_measures` (the capacity measures, the record's
    /// properties, SA at each period), records in order.
    pub struct RecordImRow = "record_ims" v 2 {
        pub record_id: String,
        /// `pga`, `pgv`, `pgd`, `avgsa`, `arias`, `cav`, `d5_95`, `pgv_pga`,
        /// `tm`, `sa(T)`.
        pub im: String,
        pub unit: String,
        /// SA's period (s); null for the other measures.
        pub period_s: Option<f64>,
        /// In `unit`; PGV and PGD from rest, no baseline correction.
        pub value: f64,
    }
}

table! {
    /// One IM's capacity dispersion for one block.
    pub struct EfficiencyRow = "im_efficiency" v 1 {
        /// The block's row in `blocks.parquet`.
        pub block_index: i64,
        pub block: String,
        pub p: f64,
        pub eps: f64,
        /// `pga`, `pgv`, `pgd`, `sa(T)`, `avgsa`, `arias`, `cav`, or
        /// `pga | pgv/pga` (PGA given PGV/PGA).
        pub im: String,
        pub unit: String,
        /// Records that overturn the block within the grid.
        pub n: i64,
        /// exp(mean ln IM_c), in `unit`; null for a block without α.
        pub median: Option<f64>,
        /// The median in the IM's dimensionless form (`dimensionless`).
        pub median_dimensionless: Option<f64>,
        pub dimensionless: Option<String>,
        /// Standard deviation of ln IM_c (of the residuals for the vector).
        pub beta: f64,
        pub lilliefors_p: Option<f64>,
        /// 1 for the scalar IM with the smallest β of the block; null for the vector.
        pub rank: Option<i64>,
        /// The vector's d ln PGA_c / d ln(PGV/PGA).
        pub slope: Option<f64>,
    }
}
