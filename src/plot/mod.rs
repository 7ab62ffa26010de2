//! Figures as SVG text (plotters' SVG backend; no fonts or bitmaps needed).
//! Pure: returns the SVG as a `String`; the caller writes it. Three drawing
//! paths: a [`Chart`] of styled series ([`render`]), horizontal [`Bars`]
//! ([`render_bars`]) and the log–log plot of the benchmark ([`log_log`]).

mod axes;
mod bars;
mod chart;
mod error;
mod legend;
mod log_log;
mod render;

pub use axes::{ticks, Hue, Scale};
pub use bars::{render_bars, Bars};
pub use chart::{Chart, Line, Style};
pub use error::PlotError;
pub use log_log::{log_log, Series};
pub use render::render;
