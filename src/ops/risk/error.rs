//! Every refusal of `risk`.

use std::path::PathBuf;

use crate::hazard::HazardError;
use crate::ops::fragility::FragilityError;
use crate::plot::PlotError;
use crate::tables::TableError;

#[derive(Debug, thiserror::Error)]
pub enum RiskError {
    #[error("{0}")]
    Gmf(String),
    #[error("--component rotd50: the hazard's {0} has no RotD50 (RotD is of PGA, PGV and SA(T))")]
    Component(String),
    #[error(
        "{path} is a hazard in {hazard} ({unit}), and the fragility asked for is in {asked}: \
         give --im {hazard}, or the hazard curves of {asked}",
        path = .path.display()
    )]
    ImMismatch {
        path: PathBuf,
        hazard: String,
        unit: &'static str,
        asked: String,
    },
    #[error("{path}: cannot read")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}:{}: {}", .error.line.map_or("?".to_string(), |l| l.to_string()), .error.message)]
    Hazard { path: PathBuf, error: HazardError },
    #[error("{path}: site {site} has only one IML with a finite, positive rate ({iml} g); the integral needs two")]
    OnePoint {
        path: PathBuf,
        site: usize,
        iml: f64,
    },
    #[error("--site {site}: {path} has {sites} site(s), numbered from 0")]
    NoSuchSite {
        path: PathBuf,
        site: usize,
        sites: usize,
    },
    #[error("--years {0}: give a positive number of years")]
    Years(f64),
    #[error("--auto-tol: {0}")]
    AutoTol(String),
    #[error("{path}:{line}: {message}")]
    Inventory {
        path: PathBuf,
        line: u64,
        message: String,
    },
    #[error("block `{name}`")]
    Block {
        name: String,
        #[source]
        source: FragilityError,
    },
    #[error(transparent)]
    Fragility(#[from] FragilityError),
    #[error(transparent)]
    Table(#[from] TableError),
    #[error(transparent)]
    Plot(#[from] PlotError),
}

/// The investigation time of a risk answer or an exported job, checked
/// once for `risk`, `risk --gmf` and `export`: a positive, finite number
/// of years.
pub fn check_years(years: f64) -> Result<(), RiskError> {
    if years > 0.0 && years.is_finite() {
        Ok(())
    } else {
        Err(RiskError::Years(years))
    }
}
