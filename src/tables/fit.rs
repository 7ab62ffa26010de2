//! The fit stage's tables (docs/MODEL.md §6); columns are documented in the
//! README.

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
    /// One point of a fitted curve with its bootstrap band: every resample
    /// of `capacity_resamples` refitted (step 1 and step 2) and evaluated
    /// there.
    pub struct FitBandRow = "fit_bands" v 1 {
        pub curve: BandCurve,
        /// The fractile (eta_c rows); null for the fragility.
        pub quantile: Option<f64>,
        pub p: f64,
        pub eps: f64,
        /// PGA in g (fragility rows); null for eta_c.
        pub pga_g: Option<f64>,
        /// This study's fit at the point (null when its laws are incomplete).
        pub value: Option<f64>,
        /// The percentile band over the resamples whose refit gave all
        /// three laws (null when fewer than two did).
        pub lo: Option<f64>,
        pub hi: Option<f64>,
        /// Resamples that entered the band at this point.
        pub used: i64,
        pub level: f64,
        pub resamples: i64,
    }
}

table! {
    /// One step-1 fit (one ε, one fractile).
    pub struct FitStep1Row = "fit_step1" v 1 {
        pub eps: f64,
        pub quantile: f64,
        pub a: Option<f64>,
        pub b: Option<f64>,
        pub c: Option<f64>,
        pub rms: Option<f64>,
        pub iterations: i64,
        pub stop: crate::fit::Stop,
        pub converged: bool,
    }
}

table! {
    /// One step-2 polynomial: c0 + c1 ε (+ c2 ε²).
    pub struct FitCoefficientRow = "fit_coefficients" v 1 {
        pub source: Source,
        pub quantile: f64,
        pub coefficient: Coefficient,
        pub c0: Option<f64>,
        pub c1: Option<f64>,
        pub c2: Option<f64>,
    }
}

table! {
    /// Data against step 1, step 2 and the paper at one (p, ε, fractile).
    pub struct FitComparisonRow = "fit_comparison" v 1 {
        pub p: f64,
        pub eps: f64,
        pub quantile: f64,
        pub eta_c_data: f64,
        pub eta_c_step1: Option<f64>,
        pub eta_c_fit: Option<f64>,
        pub eta_c_paper: f64,
    }
}
