//! A chart's specification (its series, how each is drawn, its axes) and
//! the unbroken runs of its series that the axes can show.

use super::axes::{keep, Hue, Scale};

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Line,
    Points,
    LinePoints,
    /// A thin light-grey line (one of many, such as every record's IDA curve).
    Faint,
    /// A dashed line (a published curve beside this study's).
    Dashed,
    /// A filled area in a light tint of the colour: the points trace its
    /// outline (a band's lower edge left to right, then its upper edge back).
    Band,
}

/// One series of a [`Chart`].
#[derive(Debug, Clone)]
pub struct Line {
    /// Legend entry; `None` keeps it out of the legend.
    pub name: Option<String>,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// What its colour means (ignored for `Faint`).
    pub hue: Hue,
}

/// A 2-D chart with labelled axes and a legend.
#[derive(Debug, Clone)]
pub struct Chart {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub x_scale: Scale,
    pub y_scale: Scale,
    /// Axis ranges in data units; `None` fits the data.
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    /// The x axis's labelled ticks, when the data has its own (levels that
    /// double); `None` takes [`ticks`](super::ticks) of the axis range.
    pub x_ticks: Option<Vec<f64>>,
    pub lines: Vec<Line>,
}

impl Chart {
    /// Whether its axes can show any point of it ([`render`](super::render)
    /// refuses a chart they cannot: every value 0 on a log axis, say).
    pub fn drawable(&self) -> bool {
        runs(self).iter().any(|(_, r)| !r.is_empty())
    }
}

/// Each line's unbroken runs: what an axis cannot show is dropped, and a
/// dropped point splits its line.
pub(super) fn runs(chart: &Chart) -> Vec<(&Line, Vec<Run>)> {
    chart
        .lines
        .iter()
        .map(|l| {
            let mut runs = vec![Vec::new()];
            for &(x, y) in &l.points {
                if keep(chart.x_scale, x) && keep(chart.y_scale, y) {
                    runs.last_mut().expect("one run").push((x, y));
                } else {
                    runs.push(Vec::new());
                }
            }
            runs.retain(|r| !r.is_empty());
            (l, runs)
        })
        .collect()
}

/// An unbroken stretch of a line.
pub(super) type Run = Vec<(f64, f64)>;
pub(super) type Runs<'a> = [(&'a Line, Vec<Run>)];
