//! A figure that could not be drawn, and the mapping of plotters' errors to it.

use std::error::Error;

/// A figure that could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    #[error("{title}: nothing to plot")]
    Empty { title: String },
    #[error("{title}: drawing failed")]
    Draw {
        title: String,
        #[source]
        source: Box<dyn Error + Send + Sync>,
    },
}

/// Maps a plotters error to [`PlotError::Draw`] for the chart `title`.
pub(super) fn draw_err<E: Error + Send + Sync + 'static>(
    title: &str,
) -> impl Fn(E) -> PlotError + '_ {
    move |e| PlotError::Draw {
        title: title.to_string(),
        source: Box::new(e),
    }
}
