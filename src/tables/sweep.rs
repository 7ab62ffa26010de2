//! The sweep's tables: `ida_points` (one row per run) and `capacities` (one
//! row per record × block). Columns are documented in the README.

use crate::ida::{CertificationKind, Certified, RunKind};
use crate::physics::{EquationKind, RunSpec};
use crate::table;

table! {
    /// One run of the IDA.
    pub struct IdaRow = "ida_points" v 1 {
        /// Index of the (record, block) case in the plan's order.
        pub case_id: i64,
        pub record_id: String,
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub alpha_rad: Option<f64>,
        pub eta: f64,
        /// A_g in units of αg: 1/η.
        pub pga_scale: f64,
        /// θmax/α, +∞ once overturned.
        pub edp: f64,
        pub overturned: bool,
        pub impacts: i64,
        pub run_kind: RunKind,
        pub model: EquationKind,
    }
}

table! {
    /// The capacity of one record for one block.
    pub struct CapacityRow = "capacities" v 4 {
        pub case_id: i64,
        pub record_id: String,
        pub block: String,
        pub p: f64,
        pub eps: f64,
        pub alpha_rad: Option<f64>,
        pub model: EquationKind,
        /// Largest η known to overturn; empty if it survived every level.
        pub eta_c: Option<f64>,
        pub eta_survived: f64,
        pub level_survived: f64,
        pub level_overturned: Option<f64>,
        pub runs: i64,
        /// Levels stronger than the first overturning that survived (only
        /// when the pipeline traces past the first overturning).
        pub resurrections: Option<i64>,
        /// Whether the decisive verdicts were confirmed (`ida::Certification`).
        pub certified: bool,
        /// How: `exact`, `tolerance`, or why not: `chaotic`, `flips`, `fixed_step`.
        pub certification: CertificationKind,
        /// The same in a sentence, with the tolerances and the η concerned.
        pub certification_note: String,
        /// The integrator: `exact` (linearised), `taylor` or `dp5` (nonlinear).
        pub integrator: String,
        /// The nonlinear integrator's tolerance of the search reported
        /// (tighter than the pipeline's when a looser one flipped a
        /// verdict); empty for the exact stepper.
        pub rtol: Option<f64>,
        /// On a building's floor (`[floor]`, `--floor`): the floor motion's
        /// peak over the ground record's, PFA/PGA. η is then the floor's;
        /// the ground's is η·PFA/PGA. Empty on the ground.
        pub pfa_over_pga: Option<f64>,
        /// Whether the block slides before it rocks (its μ below b/h): the
        /// row then holds only for a block restrained against sliding.
        pub slides_first: bool,
    }
}

impl CapacityRow {
    /// The row of case `case_id`: the record, the block (its name, its run
    /// specification and the α the table shows), and its certified capacity.
    pub fn of(
        case_id: usize,
        record_id: &str,
        block: &str,
        spec: &RunSpec,
        alpha_rad: Option<f64>,
        certified: &Certified,
    ) -> CapacityRow {
        let cap = &certified.capacity;
        CapacityRow {
            case_id: case_id as i64,
            record_id: record_id.to_string(),
            block: block.to_string(),
            p: spec.p,
            eps: spec.eps,
            alpha_rad,
            model: spec.model.equation.kind(),
            eta_c: cap.eta_c,
            eta_survived: cap.eta_survived,
            level_survived: cap.level_survived,
            level_overturned: cap.level_overturned,
            runs: cap.points.len() as i64,
            resurrections: cap.resurrections.map(|r| r as i64),
            certified: certified.certification.certified(),
            certification: certified.certification.kind(),
            certification_note: certified.certification.to_string(),
            integrator: certified.model.integrator.name().to_string(),
            rtol: certified.model.integrator.tol(),
            pfa_over_pga: None,
            slides_first: false,
        }
    }
}
