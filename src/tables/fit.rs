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
