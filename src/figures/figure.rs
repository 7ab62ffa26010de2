//! What a figure is: a file name, the chart and a caption, and the shape of
//! a function that draws figures from a study or from a pulse map.

use crate::plot::Chart;
use crate::study::{PulseData, StudyData};

/// A figure: its file name (without folder), the chart, and a caption.
pub struct Figure {
    pub file: String,
    pub chart: Chart,
    pub caption: String,
}

/// A function drawing one figure or a family of figures.
pub type FigureFn = fn(&StudyData) -> Vec<Figure>;

/// A function drawing one figure or a family of figures of a pulse map.
pub type PulseFigureFn = fn(&PulseData) -> Vec<Figure>;
