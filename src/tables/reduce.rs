//! The reduce stage's tables (docs/MODEL.md §5). Every one starts with the
//! block (`block` label, empty for the grid, `p`, `eps`); each column is
//! documented on its field (generated into docs/tables.md).

use crate::physics::EquationKind;
use crate::stats::ResampleUnit;
use crate::table;

table! {
    /// One row per block, in the pipeline's order.
    ///
    /// Written by the reduce stage in `outputs/<name>/blocks.parquet`: what every other
    /// table's `p`, `eps` (and `block`) refer to, with their places in the grid to filter
    /// and join on. Filter or join on the indices where p is log-spaced (the paper's
    /// p = 2.1213…); ε and p from a linear range are stored as the decimals the pipeline
    /// states (0.65, not 0.6499999999999999). The metadata holds `rocking.reduce.fractile`
    /// and `rocking.reduce.quantiles`.
    pub struct BlockRow = "blocks" v 1 {
        /// The block's place in the pipeline: a sweep case's `case_id` modulo the number
        /// of blocks.
        pub block_index: i64,
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// The place of `p` among the grid's p values (`[blocks] p`), from 0; empty for
        /// `[[block]]` entries.
        pub p_index: Option<i64>,
        /// The place of `eps` among the grid's ε values, from 0; empty for `[[block]]`
        /// entries.
        pub eps_index: Option<i64>,
        /// The slenderness α (rad) when the block has one (its dimensions, or
        /// `model.alpha`); empty otherwise.
        pub alpha_rad: Option<f64>,
        /// The equation it runs: `linearized` or `nonlinear`.
        pub model: EquationKind,
    }
}

table! {
    /// One row per block × grid level.
    ///
    /// Written by the reduce stage in `outputs/<name>/fractiles_horizontal.parquet`:
    /// horizontal statistics, the EDP fractiles over the records at each grid level. Under
    /// the resurrection rule a record counts as EDP = +∞ at every level at or beyond its
    /// first overturning; an interpolation between order statistics that gives +∞ any
    /// weight is +∞. The example stage writes the `[example]` block's, with the same
    /// columns, in `example_fractiles_horizontal.parquet` (metadata
    /// `rocking.example.settings`). The metadata holds `rocking.reduce.fractile` (the
    /// fractile definition, `[reduce] fractile`) and `rocking.reduce.quantiles`.
    pub struct HorizontalRow = "fractiles_horizontal" v 1 {
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// Index of the grid level (0 = the weakest shaking).
        pub level: i64,
        /// The level's intensity η = αg/A_g.
        pub eta: f64,
        /// The 16 % fractile of θmax/α over the records; +∞ allowed (resurrection rule).
        pub edp_q16: f64,
        /// The 50 % fractile of θmax/α over the records; +∞ allowed (resurrection rule).
        pub edp_q50: f64,
        /// The 84 % fractile of θmax/α over the records; +∞ allowed (resurrection rule).
        pub edp_q84: f64,
        /// Number of records.
        pub n_records: i64,
        /// Records overturned at this or a weaker level.
        pub n_overturned: i64,
    }
}

table! {
    /// One row per block × EDP level e = 0.05, 0.10, …, 1.
    ///
    /// Written by the reduce stage in `outputs/<name>/fractiles_vertical.parquet`:
    /// vertical statistics, the fractiles over the records of the η at which the EDP first
    /// reaches `edp`. Each record's η is its first (largest) η at which its EDP reaches e,
    /// linear between grid levels, the capacity point counting as EDP = 1; 0 if never
    /// reached. The metadata holds `rocking.reduce.fractile` and
    /// `rocking.reduce.quantiles`.
    pub struct VerticalRow = "fractiles_vertical" v 1 {
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// The EDP level e (θmax/α): 0.05, 0.10, …, 1.
        pub edp: f64,
        /// The 16 % fractile over the records of the first (largest) η at which the
        /// record's EDP reaches `edp` (0 for a record that never does).
        pub eta_q16: f64,
        /// The 50 % fractile over the records of the first (largest) η at which the
        /// record's EDP reaches `edp` (0 for a record that never does).
        pub eta_q50: f64,
        /// The 84 % fractile over the records of the first (largest) η at which the
        /// record's EDP reaches `edp` (0 for a record that never does).
        pub eta_q84: f64,
        /// Number of records.
        pub n_records: i64,
        /// Records whose EDP never reaches `edp` (counted as η = 0).
        pub n_not_reached: i64,
    }
}

table! {
    /// One row per block × quantile (0.16, 0.5, 0.84).
    ///
    /// Written by the reduce stage in `outputs/<name>/capacity_fractiles.parquet`: the
    /// fractiles of the records' capacities η_c, what the fit stage regresses. The
    /// metadata holds `rocking.reduce.fractile` (the fractile definition,
    /// `[reduce] fractile`) and `rocking.reduce.quantiles`.
    pub struct CapacityFractileRow = "capacity_fractiles" v 1 {
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// The fractile's probability: 0.16, 0.5 or 0.84.
        pub quantile: f64,
        /// The fractile of the records' η_c (a record that never overturned counts as 0).
        pub eta_c: f64,
        /// The largest grid level (η) at which the EDP fractile of the same quantile is +∞
        /// or ≥ 1: the level at which the k-th least fragile record (the k-th smallest
        /// η_c) first overturned, k = ⌈h⌉ with h the fractile's position, e.g.
        /// ⌈1 + (n − 1)q⌉ for type 7. It
        /// differs from `eta_c`, which interpolates between two records, where those
        /// records lie far apart. Empty if that fractile reaches 1 at no grid level.
        pub eta_c_horizontal: Option<f64>,
        /// Number of records.
        pub n_records: i64,
        /// Records that never overturned within the grid (counted as η_c = 0).
        pub n_censored: i64,
    }
}

table! {
    /// One row per block × quantile (0.16, 0.5, 0.84); only with `[uncertainty]`.
    ///
    /// Written by the reduce stage in `outputs/<name>/capacity_bands.parquet` when the
    /// pipeline has `[uncertainty]` (no such table otherwise): a percentile bootstrap band
    /// of each capacity fractile, the block's percentiles of `capacity_resamples`. The
    /// metadata holds `rocking.reduce.fractile`, `rocking.reduce.quantiles` and
    /// `rocking.reduce.uncertainty` (the `[uncertainty]` settings, the seed included).
    pub struct CapacityBandRow = "capacity_bands" v 1 {
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// The fractile's probability: 0.16, 0.5 or 0.84.
        pub quantile: f64,
        /// The point estimate, as in `capacity_fractiles`: the fractile of the records'
        /// η_c (a record that never overturned counts as 0).
        pub eta_c: f64,
        /// The band's lower end: the (1 − level)/2 percentile (type 7) of the fractile over
        /// the resamples.
        pub lo: f64,
        /// The band's upper end: the (1 + level)/2 percentile (type 7) of the fractile over
        /// the resamples.
        pub hi: f64,
        /// The band's two-sided level (e.g. 0.90 for the 5–95 % percentiles).
        pub level: f64,
        /// Number of bootstrap resamples.
        pub resamples: i64,
        /// What a resample draws with replacement: `pair` (the manifest's record pairs) or
        /// `record`.
        pub unit: ResampleUnit,
    }
}

table! {
    /// One row per resample × block × quantile (0.16, 0.5, 0.84); only with `[uncertainty]`.
    ///
    /// Written by the reduce stage in `outputs/<name>/capacity_resamples.parquet` when the
    /// pipeline has `[uncertainty]` (no such table otherwise): each bootstrap resample's
    /// capacity fractiles. A resample is one draw of whole units (pairs or records) applied
    /// to every block. The bands of `capacity_bands` are each block's percentiles of this
    /// table; the fit stage refits it resample by resample. The metadata holds
    /// `rocking.reduce.fractile`, `rocking.reduce.quantiles` and
    /// `rocking.reduce.uncertainty` (the settings, the seed included).
    pub struct CapacityResampleRow = "capacity_resamples" v 1 {
        /// The resample: 0, 1, …, resamples − 1; resample r draws its units from stream r
        /// of the seed, and its one draw applies to every block.
        pub resample: i64,
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// The fractile's probability: 0.16, 0.5 or 0.84.
        pub quantile: f64,
        /// The fractile of the η_c of that resample's records (a record that never
        /// overturned counts as 0).
        pub eta_c: f64,
    }
}

table! {
    /// One row per block.
    ///
    /// Written by the reduce stage in `outputs/<name>/lognormal.parquet`: whether the
    /// block's capacities η_c are lognormal (Lilliefors test of ln η_c over the records
    /// that overturned), with two estimates of the median and β. The p-value is the
    /// Dallal & Wilkinson (1986) approximation, and above 0.1 Stephens' (1974) modified
    /// statistic with the fits of R's `nortest::lillie.test`. The metadata holds
    /// `rocking.reduce.fractile` and `rocking.reduce.quantiles`.
    pub struct LognormalRow = "lognormal" v 1 {
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// Records that overturned within the grid: the η_c values tested.
        pub n: i64,
        /// exp of the mean of ln η_c; empty with fewer than two values.
        pub median_sample: Option<f64>,
        /// The sample standard deviation of ln η_c (divided by n − 1; the likelihood's β of
        /// `--method mle` divides by n); empty with fewer than two values.
        pub beta_sample: Option<f64>,
        /// η_c,50, the 50 % capacity fractile; empty where it is 0 (too many records never
        /// overturned).
        pub median_fractile: Option<f64>,
        /// (ln η_c,84 − ln η_c,16)/2; empty where either fractile is 0.
        pub beta_fractile: Option<f64>,
        /// The Lilliefors statistic D of ln η_c; empty when untested (fewer than five
        /// values, or all equal).
        pub lilliefors_d: Option<f64>,
        /// The Lilliefors p-value; empty when untested (fewer than five values, or all
        /// equal).
        pub p_value: Option<f64>,
        /// The critical value of D at 5 % for `n` values; empty with fewer than five.
        pub critical_d_5pct: Option<f64>,
        /// Whether lognormality is rejected at 5 % (p-value below 0.05); false when
        /// untested.
        pub rejected_5pct: bool,
    }
}

table! {
    /// One row per block × grid level.
    ///
    /// Written by the reduce stage in `outputs/<name>/overturn_fraction.parquet`: the
    /// share of records overturned at each grid level, plainly and under the resurrection
    /// rule. The metadata holds `rocking.reduce.fractile` and `rocking.reduce.quantiles`.
    pub struct OverturnFractionRow = "overturn_fraction" v 1 {
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// Index of the grid level (0 = the weakest shaking).
        pub level: i64,
        /// The level's intensity η = αg/A_g.
        pub eta: f64,
        /// Share of records whose run at this level overturned; empty where some record
        /// was not run at this level.
        pub fraction_plain: Option<f64>,
        /// Share of records overturned at this or a weaker level (resurrection rule).
        pub fraction_resurrection: f64,
    }
}
