//! The study's figures, as chart specifications built from its results (pure).
//!
//! [`FIGURES`] lists one function per figure (or per family of figures),
//! in the order the report shows them. Each takes the loaded
//! [`StudyData`] and returns its figures, none when the study cannot have
//! them (a fit figure without a fit, say). Adding a figure is one function
//! in the file of its topic and one line in the list.
//!
//! Numbering follows the source paper: Fig. 5 (every record's IDA curve with
//! the 16/50/84 % fractiles), Fig. 6 (median IDA curves across p), Fig. 7
//! (horizontal against vertical capacity fractiles), Fig. 8 (capacity
//! curves), Fig. 9 (lognormal probability plots), Figs. 10–11 (the
//! regression against the data), then a fragility curve and the capacity
//! convergence study.

mod bands;
mod capacity;
mod convergence;
pub mod damage;
mod figure;
pub mod floor;
mod fragility;
mod ida;
pub mod ims;
mod lognormal;
pub mod orientation;
mod pulse;
mod regression;
mod shared;
pub mod tree;

pub use convergence::{convergence_levels, ConvergenceLevel};
pub use figure::{Figure, FigureFn, PulseFigureFn};
pub use shared::PAPER_EQ;

use crate::study::{PulseData, StudyData};

/// Every figure, in report order.
pub const FIGURES: &[FigureFn] = &[
    ida::ida_curves,
    ida::median_ida_across_p,
    capacity::horizontal_vs_vertical,
    capacity::capacity_curves,
    floor::floor_capacities,
    orientation::orientation_capacity,
    bands::capacity_bands,
    regression::regressions,
    regression::regression_coefficients,
    lognormal::lognormal_plots,
    fragility::fragility_example,
    tree::tree_fragility,
    tree::tree_tornado,
    damage::damage_states,
    ims::im_efficiency,
    convergence::convergence_share,
    convergence::convergence_mean,
];

/// All figures of a study.
pub fn all(d: &StudyData) -> Vec<Figure> {
    FIGURES.iter().flat_map(|f| f(d)).collect()
}

/// Every figure of a pulse map (`[pulses]` pipelines), in report order:
/// the paper's Fig. 2 (waveforms), Fig. 3 (walls: safe above, overturning
/// below) and Fig. 4 (the areas of each mode).
pub const PULSE_FIGURES: &[PulseFigureFn] = &[
    pulse::pulse_waveforms,
    pulse::pulse_walls,
    pulse::pulse_modes,
];

/// All figures of a pulse map.
pub fn all_pulse(d: &PulseData) -> Vec<Figure> {
    PULSE_FIGURES.iter().flat_map(|f| f(d)).collect()
}

#[cfg(test)]
pub(crate) mod fixture;

#[cfg(test)]
mod tests {
    use super::fixture::grid_study;
    use super::*;

    /// A grid study with no results draws what needs no results, in the
    /// report's order: Fig. 5, Fig. 6, Fig. 7, Fig. 8, the coefficients
    /// (the paper's), the fragility (the paper's); none of the bands, the
    /// regression, the lognormal plots or the convergence study.
    #[test]
    fn the_registry_draws_in_report_order() {
        let files: Vec<String> = all(&grid_study(&[1.0, 2.0], &[0.5, 0.9]))
            .into_iter()
            .map(|f| f.file)
            .collect();
        assert_eq!(
            files,
            [
                "fig05_ida_curves.svg",
                "fig06_median_ida_across_p.svg",
                "fig07_horizontal_vs_vertical.svg",
                "fig08_capacity_curves.svg",
                "regression_coefficient_a.svg",
                "regression_coefficient_b.svg",
                "regression_coefficient_c.svg",
                "fragility_example.svg",
            ]
        );
    }
}
