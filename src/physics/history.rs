//! The response history of a run, as the driver reports it: an observer
//! receives a point at every event and every sample; `()` ignores them at no
//! cost.

use crate::label::Label;

/// What happened at a point of the history.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    Start,
    Sample,
    Uplift,
    Impact,
    Rest,
    Overturn,
    RecordEnd,
    /// A block that may slide: its base (flat) or its pivot starts to slip.
    Slip,
    /// The slip stops.
    Stick,
    /// The pivot's normal force reached 0 (the run ends).
    Flight,
}

impl Label for EventKind {
    const ALL: &'static [Self] = &[
        EventKind::Start,
        EventKind::Sample,
        EventKind::Uplift,
        EventKind::Impact,
        EventKind::Rest,
        EventKind::Overturn,
        EventKind::RecordEnd,
        EventKind::Slip,
        EventKind::Stick,
        EventKind::Flight,
    ];
    fn label(self) -> &'static str {
        match self {
            EventKind::Start => "start",
            EventKind::Sample => "sample",
            EventKind::Uplift => "uplift",
            EventKind::Impact => "impact",
            EventKind::Rest => "rest",
            EventKind::Overturn => "overturn",
            EventKind::RecordEnd => "record_end",
            EventKind::Slip => "slip",
            EventKind::Stick => "stick",
            EventKind::Flight => "flight",
        }
    }
}

/// A point of the response history.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HistoryPoint {
    pub t_s: f64,
    pub x: f64,
    pub v: f64,
    /// Pivot: +1, −1, or 0 at rest.
    pub pivot: i8,
    /// ψ̈ at that instant (record normalised to unit peak).
    pub psi: f64,
    /// The base's position relative to the ground (m; 0 for a block that
    /// cannot slide).
    pub u_m: f64,
    /// Its velocity relative to the ground (m/s).
    pub w_mps: f64,
    pub kind: EventKind,
}

/// Receives history points; `()` ignores them at no cost.
pub trait Observer {
    /// Whether it wants a point at every sample (not only at events); when
    /// not, the driver may cross eventless intervals in a tight loop.
    const SAMPLES: bool = true;
    fn point(&mut self, p: HistoryPoint);
}

impl Observer for () {
    const SAMPLES: bool = false;
    #[inline(always)]
    fn point(&mut self, _: HistoryPoint) {}
}

/// Records every event and every `every`-th sample.
pub struct Recorder {
    pub every: usize,
    pub points: Vec<HistoryPoint>,
    samples_seen: usize,
}

impl Recorder {
    pub fn new(every: usize) -> Self {
        Recorder {
            every: every.max(1),
            points: Vec::new(),
            samples_seen: 0,
        }
    }
}

impl Observer for Recorder {
    fn point(&mut self, p: HistoryPoint) {
        if p.kind == EventKind::Sample {
            self.samples_seen += 1;
            if self.samples_seen % self.every != 0 {
                return;
            }
        }
        self.points.push(p);
    }
}
