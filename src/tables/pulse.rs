//! The pulse map's tables (`[pulses]` pipelines): one row per wall, one per
//! map cell. Each column is documented on its field (generated into
//! docs/tables.md).

use crate::pulse::WallKind;
use crate::table;

table! {
    /// One row per pulse shape (β) × ε × f: the walls of one pulse for one block.
    ///
    /// Written by the pulses stage (`[pulses]` pipelines) in
    /// `outputs/<name>/pulse_walls.parquet`: for each pulse (shape, β, cycle; lobes of
    /// t_d = 1 s) and block (ε) at each f, the walls found by simulation: a log grid of
    /// 500 levels from η = 1 down to 1e-5, then bisection in ln η to 1e-10. The metadata
    /// holds `rocking.pulses.settings` (the `[pulses]` map, the model, the solver and the
    /// overturning criterion, as JSON).
    pub struct PulseWallRow = "pulse_walls" v 1 {
        /// The lobe's shape: `rect` (rectangular) or `exp` (exponential, the paper's Eq. 4).
        pub pulse: String,
        /// The exponential lobe's shape parameter β; empty for `rect`.
        pub beta: Option<f64>,
        /// `half` (one lobe) or `full` (the lobe followed by its negative).
        pub cycle: String,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// f = p·t_d, the block's frequency parameter p (1/s) times the lobe's duration
        /// t_d = 1 s (dimensionless).
        pub f: f64,
        /// The overturning criterion: `static`, `cap:C`, `on-side` or `escape`.
        pub overturn: String,
        /// The equation run: `linearized` or `nonlinear`.
        pub model: String,
        /// The block's slenderness α (rad) for the nonlinear model (`model.alpha`); empty
        /// for the linearised model.
        pub alpha_rad: Option<f64>,
        /// The wall: the largest η at which the block overturns; empty: none above
        /// η = 1e-5.
        pub eta_w: Option<f64>,
        /// The largest η at which it overturns with no impact (Mode 0); empty: none above
        /// η = 1e-5.
        pub eta_w_mode0: Option<f64>,
        /// The mode: impacts before overturning just below `eta_w` (0: Mode 0, 1: Mode 1,
        /// …); empty where `eta_w` is.
        pub mode: Option<i64>,
        /// The paper's closed-form wall where one applies (linearised model only: Eq. 3 for
        /// the rectangular half cycle, Eq. 5 for the exponential one, Eq. 6 for Mode 0 of
        /// the rectangular full cycle under `escape`); empty otherwise.
        pub closed_form: Option<f64>,
        /// The closed form's equation: `Eq. 3`, `Eq. 5` or `Eq. 6`; empty without one.
        pub closed_form_equation: Option<String>,
        /// Which wall the closed form gives: `eta_w` or `eta_w_mode0`; empty without one.
        pub closed_form_of: Option<String>,
        /// Simulations the wall search ran.
        pub runs: i64,
        /// Sample intervals per lobe of the pulse (`[pulses] intervals`, or by default
        /// enough for the shape and f).
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
    /// One row per pulse shape × ε × f × η of the map.
    ///
    /// Written by the pulses stage (`[pulses]` pipelines) in
    /// `outputs/<name>/pulse_map.parquet`: one simulation of one pulse and block at each
    /// (f, η) of the map. The metadata holds `rocking.pulses.settings`, as in
    /// `pulse_walls`.
    pub struct PulseCellRow = "pulse_map" v 1 {
        /// The lobe's shape: `rect` (rectangular) or `exp` (exponential, the paper's Eq. 4).
        pub pulse: String,
        /// The exponential lobe's shape parameter β; empty for `rect`.
        pub beta: Option<f64>,
        /// `half` (one lobe) or `full` (the lobe followed by its negative).
        pub cycle: String,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// f = p·t_d, the block's frequency parameter p (1/s) times the lobe's duration
        /// t_d = 1 s (dimensionless).
        pub f: f64,
        /// The run's intensity η = αg/A_g, one of the map's levels.
        pub eta: f64,
        /// Whether the block overturned.
        pub overturned: bool,
        /// Impacts before overturning (its mode) if it overturned; else over the whole run.
        pub impacts: i64,
        /// θmax/α (infinite when it overturned under `escape`).
        pub max_abs_x: f64,
    }
}
