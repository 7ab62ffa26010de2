//! The `risk` table of `rocking risk --inventory`: one row per block × site.
//! Columns are documented in the README.

use crate::risk::Beyond;
use crate::table;

table! {
    /// The annual rate of overturning of one block at one site.
    pub struct RiskRow = "risk" v 3 {
        /// The block's name in the inventory.
        pub block: String,
        pub b_m: f64,
        pub h_m: f64,
        pub alpha_rad: f64,
        pub p: f64,
        pub eps: f64,
        /// Whether ε is Housner's bound (the inventory gave none).
        pub eps_housner: bool,
        /// The base's friction coefficient, when given (`--mu`, the inventory's `mu`).
        pub mu: Option<f64>,
        /// Whether the block slides before it rocks (μ < b/h): its rocking
        /// results then hold only if it is restrained against sliding.
        /// False when μ is not given.
        pub slides_first: bool,
        /// The building's modes `T,ζ,Γφ; …` when the block stands on a
        /// floor (`--floor`); the IMs are still the ground's.
        pub floor: Option<String>,
        /// Index of the site in the hazard file, from 0.
        pub site: i64,
        pub lon: Option<f64>,
        pub lat: Option<f64>,
        /// `paper`, the pipeline file, or `direct`.
        pub fragility: String,
        /// The IM of the hazard and the fragility (`pga`, `pgv`, `sa(1.0)`,
        /// `avgsa`), and its unit: every IML of the row is in it.
        pub im: String,
        pub unit: String,
        /// The IML at which the block overturns with probability 0.5.
        pub median: Option<f64>,
        /// Dispersion (ln) of the fragility.
        pub beta: Option<f64>,
        /// λ_OT (1/year).
        pub annual_rate: f64,
        /// 1/λ_OT; empty when the rate is 0.
        pub return_period_years: Option<f64>,
        pub years: f64,
        /// 1 − exp(−λ_OT · years).
        pub p_overturn_in_years: f64,
        pub first_iml: f64,
        pub last_iml: f64,
        /// P(OT | first IML): overturning probability below where the hazard starts.
        pub fragility_at_first_iml: f64,
        /// Share of λ_OT from beyond the last IML.
        pub share_beyond_last_iml: f64,
        pub beyond: Beyond,
        /// Where the regression is stretched for this block, `; `-separated.
        pub warnings: String,
    }
}
