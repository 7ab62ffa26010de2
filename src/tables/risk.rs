//! The `risk` table of `rocking risk --inventory`: one row per block × site.
//! Each column is documented on its field (generated into docs/tables.md).

use crate::risk::Beyond;
use crate::table;

table! {
    /// One row per block × site: the block's annual rate of overturning at the site.
    ///
    /// Written by `rocking risk --inventory BLOCKS.csv` in `--out` (default
    /// `risk.parquet`): every block of the inventory assessed at every site of the hazard
    /// file. The metadata holds `rocking.risk.hazard` (the hazard file). Version 3 added
    /// `mu`, `slides_first` and `floor`; version 5 `fit`; version 6 the bootstrap band
    /// (`annual_rate_lo`, `annual_rate_hi`).
    pub struct RiskRow = "risk" v 6 {
        /// The block's name in the inventory.
        pub block: String,
        /// The block's half-width b (m).
        pub b_m: f64,
        /// The block's half-height h (m).
        pub h_m: f64,
        /// The block's slenderness α (rad).
        pub alpha_rad: f64,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// Whether ε is Housner's bound (the inventory gave none).
        pub eps_housner: bool,
        /// The base's friction coefficient μ (`--mu`, the inventory's `mu`); empty when not
        /// given.
        pub mu: Option<f64>,
        /// Whether μ is at most b/h: the block slides before it rocks (docs/MODEL.md §17).
        /// With `--direct` its runs are then the slide-rock model's (`model`); from a
        /// regression its rate holds only if it is restrained against sliding. False when
        /// μ is not given.
        pub slides_first: bool,
        /// With `--direct`: the equation the records ran, `linearized`, `nonlinear` or
        /// `slide-rock` (a block with μ under `auto`, docs/MODEL.md §21); empty for a
        /// regression.
        pub model: Option<String>,
        /// With `--floor`, or `--from` a `[floor]` study (both with `--direct`): the
        /// building's modes `T,ζ,Γφ; …`, the block standing on its floor; the IMs stay the
        /// ground's. Empty for a block on the ground.
        pub floor: Option<String>,
        /// Index of the site in the hazard file, from 0.
        pub site: i64,
        /// The site's longitude (degrees; OpenQuake files); empty for a plain hazard CSV.
        pub lon: Option<f64>,
        /// The site's latitude (degrees; OpenQuake files); empty for a plain hazard CSV.
        pub lat: Option<f64>,
        /// Where the fragility comes from: `paper`, the pipeline file, or `direct`.
        pub fragility: String,
        /// How the fragility the rate integrates is made: `regression` (the paper's or a
        /// study's, PGA), `fractile` or `mle` (lognormals of the records' capacities, or of a
        /// study's damage table in another IM), `moments` (a study's IM table, where its
        /// damage states hold no overturning), `empirical` (the records' own curve, `--method
        /// empirical`: no β) or `mixture` (a logic tree's).
        pub fit: String,
        /// The IM of the hazard and the fragility (`pga`, `pgv`, `sa(1.0)`, `avgsa`): every
        /// level of the row is in its unit.
        pub im: String,
        /// The IM's unit: g (PGA, SA, AvgSA) or cm/s (PGV).
        pub unit: String,
        /// The fragility's median, in `unit`: the IML at which the block overturns with
        /// probability 0.5. Empty where undefined (`--direct` with most records never
        /// overturning the block).
        pub median: Option<f64>,
        /// The fragility's dispersion (of ln IM). Empty where undefined (`--direct` with
        /// most records never overturning the block, or the records' own curve, `fit` =
        /// `empirical`).
        pub beta: Option<f64>,
        /// λ_OT, the annual rate of overturning (1/year).
        pub annual_rate: f64,
        /// With `--bootstrap`: the lower end of the rate's 90 % band over resamples of the
        /// records (1/year); empty otherwise.
        pub annual_rate_lo: Option<f64>,
        /// With `--bootstrap`: the band's upper end (1/year).
        pub annual_rate_hi: Option<f64>,
        /// The return period 1/λ_OT (years); empty when the rate is 0.
        pub return_period_years: Option<f64>,
        /// The exposure time T (years, `--years`).
        pub years: f64,
        /// The probability of overturning within `years`, 1 − exp(−λ_OT T) (Poisson
        /// arrivals).
        pub p_overturn_in_years: f64,
        /// The first IML of the part of the hazard curve used (in `unit`).
        pub first_iml: f64,
        /// The last IML of the part of the hazard curve used (in `unit`).
        pub last_iml: f64,
        /// P(OT | first IML): the overturning probability below where the hazard curve
        /// starts.
        pub fragility_at_first_iml: f64,
        /// The share of λ_OT from beyond the last IML.
        pub share_beyond_last_iml: f64,
        /// What the curve does beyond its last IML: `extrapolate` (its last log-log slope
        /// continues) or `stop` (no exceedance is counted).
        pub beyond: Beyond,
        /// Where the regression is stretched for this block, each site whose rate comes
        /// mostly (over half) from beyond the hazard curve's last IML, and a block that
        /// slides first, `; `-separated (the same on each of the block's rows); empty when
        /// there is nothing to say.
        pub warnings: String,
    }
}
