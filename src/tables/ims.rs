//! The ims stage's tables (docs/MODEL.md §14): the records' intensity
//! measures and each block's capacity dispersion in every IM. Columns are
//! documented in the README.

use crate::table;

table! {
    /// One record's intensity measures, unscaled (SA in `record_spectra`).
    pub struct RecordImRow = "record_ims" v 1 {
        pub record_id: String,
        pub pga_g: f64,
        /// From rest, no baseline correction.
        pub pgv_cm_s: f64,
        pub pgd_cm: f64,
        pub arias_m_s: f64,
        pub cav_g_s: f64,
        pub d5_95_s: f64,
        pub pgv_pga_s: f64,
        pub tm_s: f64,
        pub avgsa_g: f64,
    }
}

table! {
    /// One record's 5 %-damped pseudo-spectral acceleration at one period.
    pub struct SpectrumRow = "record_spectra" v 1 {
        pub record_id: String,
        pub period_s: f64,
        pub sa_g: f64,
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
