//! The accuracy studies of `rocking-bench`: how η_c of the nonlinear model
//! moves with DP5's tolerance ([`tolerance_table`], with its
//! [`rocking::ida::HARD_CASES`]), and whether rounding can flip the exact stepper's
//! decisive verdicts ([`rounding_table`]). Both run in parallel (they are
//! about answers, not timings) and return a Markdown section.

mod hard_cases;
mod rounding;
mod tolerance;

pub use rounding::rounding_table;
pub use tolerance::tolerance_table;
