//! The fit stage's tables (docs/MODEL.md §6); each column is documented on
//! its field (generated into docs/tables.md).

use super::Label;
use crate::table;

/// Where a row of coefficients comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// This study's step-2 fit.
    Fitted,
    /// The paper's published Eqs. 10–12.
    Paper,
}

impl Label for Source {
    const ALL: &'static [Self] = &[Source::Fitted, Source::Paper];
    fn label(self) -> &'static str {
        match self {
            Source::Fitted => "fitted",
            Source::Paper => "paper",
        }
    }
}

/// Which coefficient of `η_c = a(1 − e^{−bp})^c` a row holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coefficient {
    A,
    B,
    C,
}

impl Label for Coefficient {
    const ALL: &'static [Self] = &[Coefficient::A, Coefficient::B, Coefficient::C];
    fn label(self) -> &'static str {
        match self {
            Coefficient::A => "a",
            Coefficient::B => "b",
            Coefficient::C => "c",
        }
    }
}

/// Which curve a row of `fit_bands` belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BandCurve {
    /// A capacity fractile η_c,q(p) at one ε, from the step-2 laws.
    EtaC,
    /// P(overturn | PGA) of the example block (`fragility::example_block`).
    Fragility,
}

impl Label for BandCurve {
    const ALL: &'static [Self] = &[BandCurve::EtaC, BandCurve::Fragility];
    fn label(self) -> &'static str {
        match self {
            BandCurve::EtaC => "eta_c",
            BandCurve::Fragility => "fragility",
        }
    }
}

table! {
    /// One row per point of a fitted curve, with its bootstrap band (only with `[uncertainty]`).
    ///
    /// Written by the fit stage in `outputs/<name>/fit_bands.parquet` when the pipeline has
    /// `[uncertainty]` (no such table otherwise): every resample of `capacity_resamples`
    /// refitted (step 1 and step 2) and evaluated at the point. The metadata holds
    /// `rocking.fit.bands.step1_converged` (the step-1 fits that converged over all
    /// resamples, "k of n") and `rocking.fit.bands.laws_complete` (the resamples whose
    /// refit gave all three laws, "k of n").
    pub struct FitBandRow = "fit_bands" v 1 {
        /// `eta_c`: a capacity fractile η_c,q(p) along p at one ε, from the step-2 laws,
        /// at 61 log-spaced p over the grid's range; `fragility`: P(overturn | PGA) of the
        /// example block (b = 0.25 m, h = 1 m, Housner's ε) at PGA 0.01, 0.02, …, 1.20 g.
        pub curve: BandCurve,
        /// The fractile (0.16, 0.5 or 0.84) of `eta_c` rows; empty for the fragility.
        pub quantile: Option<f64>,
        /// The frequency parameter p (1/s): the point's on `eta_c` rows, the example
        /// block's on fragility rows.
        pub p: f64,
        /// The coefficient of restitution ε: the curve's on `eta_c` rows, the example
        /// block's on fragility rows.
        pub eps: f64,
        /// The PGA (g) of fragility rows; empty for `eta_c` rows.
        pub pga_g: Option<f64>,
        /// This study's fit at the point (η_c, or the probability of overturning); empty
        /// when its laws are incomplete.
        pub value: Option<f64>,
        /// The band's lower end: the (1 − level)/2 percentile (type 7) over the resamples
        /// whose refit gave all three laws; empty when fewer than two did.
        pub lo: Option<f64>,
        /// The band's upper end: the (1 + level)/2 percentile (type 7) over the resamples
        /// whose refit gave all three laws; empty when fewer than two did.
        pub hi: Option<f64>,
        /// Resamples that entered the band at this point (their refit gave all three laws,
        /// and a finite value there).
        pub used: i64,
        /// The band's two-sided level (e.g. 0.90 for the 5–95 % percentiles).
        pub level: f64,
        /// Number of bootstrap resamples.
        pub resamples: i64,
    }
}

table! {
    /// One row per ε × quantile: a step-1 fit.
    ///
    /// Written by the fit stage in `outputs/<name>/fit_step1.parquet` (a p × ε grid of at
    /// least 3 × 3): `η_c,q(p) = a(1 − e^{−bp})^c` fitted to each ε's capacity fractiles
    /// of `capacity_fractiles` (those above 0) by Levenberg–Marquardt on ln a, ln b, ln c
    /// from nine starting points (docs/MODEL.md §6).
    pub struct FitStep1Row = "fit_step1" v 1 {
        /// The coefficient of restitution ε.
        pub eps: f64,
        /// The fractile: 0.16, 0.5 or 0.84.
        pub quantile: f64,
        /// The fitted coefficient a (the curve's limit as p grows); empty when no fit
        /// could be made (`bad_data`).
        pub a: Option<f64>,
        /// The fitted coefficient b (s); empty when no fit could be made (`bad_data`).
        pub b: Option<f64>,
        /// The fitted exponent c; empty when no fit could be made (`bad_data`).
        pub c: Option<f64>,
        /// The root-mean-square residual of η_c; empty when no fit could be made
        /// (`bad_data`).
        pub rms: Option<f64>,
        /// Iterations of the solver run kept.
        pub iterations: i64,
        /// Why the solver stopped: `cost_converged`, `step_converged` or
        /// `gradient_converged` (converged); `max_iterations` (500 without meeting a
        /// criterion), `stalled` (no step lowered the cost), `diverged` (a parameter left
        /// the sane range), `unbounded` (the curve collapsed to a constant, b and c not
        /// identified), `bad_data` (fewer than 3 finite positive points).
        pub stop: crate::fit::Stop,
        /// Whether the fit converged (`stop` is one of the three converged reasons); only
        /// converged fits enter step 2.
        pub converged: bool,
    }
}

table! {
    /// One row per source × quantile × coefficient: a step-2 polynomial in ε.
    ///
    /// Written by the fit stage in `outputs/<name>/fit_coefficients.parquet`: step 2 fits
    /// a(ε) linear and b(ε), c(ε) quadratic over each fractile's converged step-1 fits,
    /// a = c0 + c1 ε and b, c = c0 + c1 ε + c2 ε²; the paper's published Eqs. 10–12 beside
    /// them.
    pub struct FitCoefficientRow = "fit_coefficients" v 1 {
        /// `fitted` (this study's step-2 fit) or `paper` (the paper's published
        /// Eqs. 10–12).
        pub source: Source,
        /// The fractile: 0.16, 0.5 or 0.84.
        pub quantile: f64,
        /// Which coefficient of `η_c = a(1 − e^{−bp})^c` the row holds: `a`, `b` or `c`.
        pub coefficient: Coefficient,
        /// The polynomial's constant term; empty when step 2 could not fit it (too few
        /// converged step-1 fits).
        pub c0: Option<f64>,
        /// The coefficient of ε; empty when step 2 could not fit the polynomial.
        pub c1: Option<f64>,
        /// The coefficient of ε²; empty for `a` (linear in ε), or when step 2 could not fit
        /// the polynomial.
        pub c2: Option<f64>,
    }
}

table! {
    /// One row per p × ε × quantile: the data against step 1, step 2 and the paper.
    ///
    /// Written by the fit stage in `outputs/<name>/fit_comparison.parquet`, over the
    /// pipeline's grid.
    pub struct FitComparisonRow = "fit_comparison" v 1 {
        /// The frequency parameter p (1/s).
        pub p: f64,
        /// The coefficient of restitution ε.
        pub eps: f64,
        /// The fractile: 0.16, 0.5 or 0.84.
        pub quantile: f64,
        /// The capacity fractile of the data (`capacity_fractiles`' `eta_c`).
        pub eta_c_data: f64,
        /// The step-1 curve of this ε and fractile at p; empty where that fit did not
        /// converge.
        pub eta_c_step1: Option<f64>,
        /// The step-2 law at (p, ε); empty where step 2 gave no law for the fractile.
        pub eta_c_fit: Option<f64>,
        /// The paper's published law (Eqs. 10–12) at (p, ε).
        pub eta_c_paper: f64,
    }
}
