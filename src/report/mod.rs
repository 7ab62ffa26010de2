//! The study's report as Markdown (pure): settings, run times, counts,
//! capacity fractiles against the paper's Eq. 10, lognormality, the fitted
//! against the published coefficients, the capacity-convergence finding and
//! which IM predicts overturning, the damage states and the figures. The report stage loads the data, draws the figures, calls
//! [`render`] (or [`render_pulses`] for a pulse map) and writes the text;
//! the tests snapshot [`render`]'s output. [`render_html`] turns that
//! Markdown into one self-contained page, the figures inline.

mod bands;
mod damage;
mod floor;
mod html;
mod ims;
mod orientation;
mod pulses;
mod shared;
mod sliding;
mod study;
mod tree;

pub use html::render_html;
pub use pulses::render_pulses;
pub use study::render;
