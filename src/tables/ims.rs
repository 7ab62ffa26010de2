//! The ims stage's tables (docs/MODEL.md §14): the records' intensity
//! measures and each block's capacity dispersion in every IM. Each column is
//! documented on its field (generated into docs/tables.md).

use crate::table;

table! {
    /// One row per record × measure.
    ///
    /// Written by the ims stage in `outputs/<name>/record_ims.parquet`: every measure of
    /// every record, unscaled, records in order (definitions: docs/MODEL.md §14). The
    /// measures are those of `Im::record_measures`: the capacity measures, the record's
    /// properties, then SA at each period. PGV and PGD come from exact integration from
    /// rest, with no baseline correction; SA is the pseudo-spectral acceleration at 5 %
    /// damping at the periods 0.05–4 s; AvgSA is the geometric mean of SA over 0.1–2 s. The
    /// metadata holds `rocking.ims.damping` (0.05). On a building's floor (`[floor]`) the
    /// measures are the ground record's (the hazard's), followed by the floor demands `pfa`,
    /// `pfv` and `fsa(T)` of the record's floor motion (the motion the blocks feel). In a
    /// study over orientations (`orientation = "random"`) each record is a pair's component
    /// at an angle, and its pair's `rotd50_*` and `rotd100_*` measures follow. Version
    /// 2 is this long format; version 1
    /// had one row per record, one column per measure, and SA in a table of its own
    /// (`record_spectra`).
    pub struct RecordImRow = "record_ims" v 2 {
        /// The record (its AT2 file stem).
        pub record_id: String,
        /// The measure: `pga`, `pgv`, `pgd`, `avgsa`, `arias`, `cav`, `d5_95`, `pgv_pga`,
        /// `tm`, `sa(T)` with T the period in s (e.g. `sa(1.0)`), and on a floor `pfa`, `pfv`,
        /// `fsa(T)`, and over orientations `rotd50_pga`, `rotd50_pgv`, `rotd50_sa(T)`,
        /// `rotd100_…`. `pga` is the peak
        /// ground acceleration, `pgv` and `pgd` the peak ground velocity and displacement,
        /// `avgsa` the geometric mean of SA over 0.1–2 s, `arias` the Arias intensity,
        /// `cav` the cumulative absolute velocity, `d5_95` the 5–95 % significant duration,
        /// `pgv_pga` PGV/PGA, `tm` the mean period (Rathje et al. 1998), `sa(T)` the
        /// pseudo-spectral acceleration at 5 % damping at period T; `pfa`, `pfv` and `fsa(T)`
        /// the same peak acceleration, peak velocity and SA(T) of the floor motion. Text
        /// records (a structural model's floor motions, no `[floor]`) are the floor's
        /// motions: their rows are `pfa`, `pfv` and `fsa(T)`, and the measures that name no
        /// ground, `arias`, `cav`, `d5_95` and `tm`.
        pub im: String,
        /// The measure's unit: g (PGA, SA, AvgSA, PFA, FSA), cm/s (PGV, PFV), cm (PGD), m/s
        /// (Arias intensity), g·s (CAV) or s (D5–95, PGV/PGA, Tm).
        pub unit: String,
        /// SA's (or FSA's, or a RotD of SA's) period (s); empty for the other measures.
        pub period_s: Option<f64>,
        /// The measure's value, in `unit`.
        pub value: f64,
    }
}

table! {
    /// One row per block × IM.
    ///
    /// Written by the ims stage in `outputs/<name>/im_efficiency.parquet`: how well each IM
    /// predicts the block's overturning, by the dispersion of its capacities IM_c over the
    /// records that overturn the block (IM_c is the record's IM when scaled to the block's
    /// capacity η_c; on a building's floor, the ground record's). The IMs are `pga`, `pgv`,
    /// `pgd`, `avgsa`, `arias`, `cav`, `sa(T)` at each period, and the vector
    /// `pga | pgv/pga`; on a building's floor (`[floor]`) they are followed by the floor
    /// demands `pfa`, `pfv` and `fsa(T)`, the block's capacity stated in its floor motion's
    /// own measures (FEMA P-58's PFA and PFV); in a study over orientations by a pair's
    /// RotD50 and RotD100 (`rotd50_pga`, …: the hazard's component). Over text records (a
    /// structural model's floor motions, no `[floor]`) the IMs are the floor's `pfa`, `pfv`
    /// and `fsa(T)` only, ranked among themselves. A block with fewer
    /// than three capacities has no rows; the vector
    /// needs four. The metadata holds `rocking.ims.damping` (0.05).
    pub struct EfficiencyRow = "im_efficiency" v 1 {
        /// The block's row in `blocks.parquet`.
        pub block_index: i64,
        /// The block's label; empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// `pga`, `pgv`, `pgd`, `sa(T)`, `avgsa`, `arias`, `cav`, `pga | pgv/pga` (PGA
        /// given PGV/PGA), on a floor `pfa`, `pfv`, `fsa(T)`, and over orientations
        /// `rotd50_pga`, `rotd50_pgv`, `rotd50_sa(T)`, `rotd100_…`.
        pub im: String,
        /// The IM's unit: g (PGA, SA, AvgSA, PFA, FSA, and the vector), cm/s (PGV, PFV), cm
        /// (PGD), m/s (Arias intensity) or g·s (CAV).
        pub unit: String,
        /// Records that overturn the block within the grid (the others are left out).
        pub n: i64,
        /// exp(mean ln IM_c), in `unit`; empty for a block without α (the linearised
        /// grid) and for the vector.
        pub median: Option<f64>,
        /// The median in the IM's dimensionless form (named in `dimensionless`); empty for
        /// an IM without one (`arias`, `cav`, the vector).
        pub median_dimensionless: Option<f64>,
        /// The name of the IM's dimensionless form: `PGA/(αg)`, `p·PGV/(αg)`,
        /// `p²·PGD/(αg)`, `SA/(αg)` or `AvgSA/(αg)`; empty for an IM without one.
        pub dimensionless: Option<String>,
        /// The sample standard deviation of ln IM_c (n − 1); for the vector, of the
        /// residuals of ln PGA_c on ln(PGV/PGA) (n − 2).
        pub beta: f64,
        /// The Lilliefors p-value of ln IM_c (of the residuals for the vector); empty when
        /// untested (fewer than five records, or no spread).
        pub lilliefors_p: Option<f64>,
        /// The scalar ground IM's rank by β within the block: 1 for the smallest β; empty
        /// for the vector, the floor demands and a pair's measures.
        pub rank: Option<i64>,
        /// The vector's d ln PGA_c / d ln(PGV/PGA); empty for the scalar IMs.
        pub slope: Option<f64>,
    }
}
