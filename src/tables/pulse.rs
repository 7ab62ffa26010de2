//! The pulse map's tables (`[pulses]` pipelines): one row per wall, one per
//! map cell. Columns are documented in the README.

use crate::pulse::WallKind;
use crate::table;

table! {
    /// The walls of one pulse (shape, β, cycle) for one block (ε) at one f.
    pub struct PulseWallRow = "pulse_walls" v 1 {
        /// `rect` or `exp`.
        pub pulse: String,
        /// The exponential pulse's β; empty for `rect`.
        pub beta: Option<f64>,
        /// `half` or `full`.
        pub cycle: String,
        pub eps: f64,
        /// f = p·t_d (t_d = 1 s).
        pub f: f64,
        /// The overturning criterion (`escape`, `static`, …).
        pub overturn: String,
        /// `linearized` or `nonlinear`.
        pub model: String,
        pub alpha_rad: Option<f64>,
        /// The largest η at which the block overturns; empty: none above η = 1e-5.
        pub eta_w: Option<f64>,
        /// The largest η at which it overturns with no impact (Mode 0).
        pub eta_w_mode0: Option<f64>,
        /// Impacts before overturning just below `eta_w`.
        pub mode: Option<i64>,
        /// The paper's closed form where one applies (linearised model).
        pub closed_form: Option<f64>,
        /// `Eq. 3`, `Eq. 5` or `Eq. 6`.
        pub closed_form_equation: Option<String>,
        /// Which wall it gives: `eta_w` or `eta_w_mode0`.
        pub closed_form_of: Option<String>,
        /// Simulations the wall search ran.
        pub runs: i64,
        pub intervals_per_lobe: i64,
    }
}

impl PulseWallRow {
    /// Which wall its closed form gives (`closed_form_of`), if it has one.
    pub fn closed_form_kind(&self) -> Option<WallKind> {
        let of = self.closed_form_of.as_deref()?;
        [WallKind::Any, WallKind::Mode0]
            .into_iter()
            .find(|k| k.column() == of)
    }

    /// The simulated wall its closed form gives, if any.
    pub fn closed_form_wall(&self) -> Option<f64> {
        self.closed_form?;
        match self.closed_form_kind()? {
            WallKind::Any => self.eta_w,
            WallKind::Mode0 => self.eta_w_mode0,
        }
    }

    /// |simulated − closed form| / closed form, where both exist.
    pub fn closed_form_gap(&self) -> Option<f64> {
        let c = self.closed_form?;
        Some((self.closed_form_wall()? - c).abs() / c)
    }
}

table! {
    /// One point of the map: one pulse and block at one (f, η).
    pub struct PulseCellRow = "pulse_map" v 1 {
        pub pulse: String,
        pub beta: Option<f64>,
        pub cycle: String,
        pub eps: f64,
        pub f: f64,
        pub eta: f64,
        pub overturned: bool,
        /// Impacts before overturning (its mode) or over the whole run.
        pub impacts: i64,
        /// θmax/α (infinite when it overturned under `escape`).
        pub max_abs_x: f64,
    }
}
