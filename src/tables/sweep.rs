//! The sweep's tables: `ida_points` (one row per run) and `capacities` (one
//! row per record × block). Each column is documented on its field
//! (generated into docs/tables.md).

use crate::ida::{CertificationKind, Certified, RunKind};
use crate::physics::{EquationKind, RunSpec};
use crate::table;

table! {
    /// One row per run of the IDA.
    ///
    /// Written by the sweep stage (`rocking sweep`, `rocking run`) in
    /// `outputs/<name>/ida_points.parquet`, or per shard in
    /// `ida_points.shard-K-of-N.parquet`; the example stage writes the `[example]` block's
    /// runs, with the same columns, in `example_ida_points.parquet` (case ids numbering the
    /// records 0, 1, …). Runs stop at a case's first overturning (plus the refinement),
    /// unless the pipeline sets `im.trace_past_first`: under the resurrection rule,
    /// stronger levels change neither the capacity nor the horizontal statistics. The
    /// metadata holds `rocking.sweep.plan_hash`, `rocking.sweep.settings` (the settings
    /// that determine the results) and `rocking.sweep.plan` (the resolved pipeline as JSON,
    /// record paths relative to the pipeline's folder); the sweep's final tables also
    /// hold `rocking.sweep.record_keys` (each record's key, by id: a rerun takes the rows
    /// of the records whose key is unchanged), shard tables `rocking.sweep.shard`, part
    /// files `rocking.sweep.chunk`, and the example's table `rocking.example.settings`.
    pub struct IdaRow = "ida_points" v 2 {
        /// Index of the (record, block) case: records by id, then blocks in pipeline order.
        pub case_id: i64,
        /// The record (its AT2 file stem).
        pub record_id: String,
        /// The block's label (physical blocks); empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// The block's slenderness α (rad) when the nonlinear model ran; empty for the
        /// linearised model.
        pub alpha_rad: Option<f64>,
        /// The run's intensity η = αg/A_g (smaller is stronger shaking).
        pub eta: f64,
        /// A_g in units of αg: 1/η.
        pub pga_scale: f64,
        /// θmax/α; +∞ if the block overturned.
        pub edp: f64,
        /// Whether the block overturned in this run.
        pub overturned: bool,
        /// Impacts during the run.
        pub impacts: i64,
        /// `level` (a grid level) or `refinement` (a bisection run of the capacity).
        pub run_kind: RunKind,
        /// The equation run: `linearized`, `nonlinear` or `slide-rock`.
        pub model: EquationKind,
        /// The slide-rock model's run: the base's largest slide relative to the ground
        /// (m); empty for a rocking model. Version 2 added it.
        pub slide_max_m: Option<f64>,
    }
}

table! {
    /// One row per (record, block): the record's capacity for the block.
    ///
    /// Written by the sweep stage in `outputs/<name>/capacities.parquet` (per shard in
    /// `capacities.shard-K-of-N.parquet`), by the example stage for the `[example]` block
    /// in `example_capacities.parquet` (case ids numbering the records 0, 1, …), by the
    /// tree stage for the example block on each branch of `[tree]` in
    /// `tree_capacities.parquet` (records × branches, `eps` and `model` the branch's), and
    /// by `rocking capacity --out`. Version 4 added `pfa_over_pga` and `slides_first`;
    /// version 3 `integrator`; version 2 the four certification columns before it; the
    /// others are as in version 1. The sweep's metadata is that of `ida_points`
    /// (`rocking.sweep.plan_hash`, `rocking.sweep.settings`, `rocking.sweep.plan`,
    /// `rocking.sweep.record_keys`; `rocking.sweep.shard` in shard tables,
    /// `rocking.sweep.chunk` in part files); the
    /// example's holds `rocking.example.settings`, the tree's `rocking.tree.settings`, that
    /// of `rocking capacity --out` `rocking.capacity.command`.
    pub struct CapacityRow = "capacities" v 4 {
        /// Index of the (record, block) case: records by id, then blocks in pipeline order
        /// (from `rocking capacity --out`: records in path order, then blocks as given).
        pub case_id: i64,
        /// The record (its AT2 file stem).
        pub record_id: String,
        /// The block's label (physical blocks); empty for the p × ε grid.
        pub block: String,
        /// The block's frequency parameter p (1/s).
        pub p: f64,
        /// The block's coefficient of restitution ε.
        pub eps: f64,
        /// The block's slenderness α (rad): in a sweep, when the nonlinear model ran; from
        /// `rocking capacity --out`, whenever the block's dimensions give it. Empty
        /// otherwise.
        pub alpha_rad: Option<f64>,
        /// The equation run: `linearized` or `nonlinear`.
        pub model: EquationKind,
        /// The capacity: the largest η known to overturn, within `im.tol` of the first
        /// overturning met as intensity rises; empty if the block survived every level.
        pub eta_c: Option<f64>,
        /// The bracket's surviving end after refinement (η_c < eta_survived ≤ η_c + tol).
        pub eta_survived: f64,
        /// With `level_overturned`, the grid levels that bracketed the first overturning:
        /// the last level (η) that survived before it (the grid's η_max if the first level
        /// overturned; the strongest level if none did).
        pub level_survived: f64,
        /// The first grid level (η) that overturned; empty if the block survived every
        /// level.
        pub level_overturned: Option<f64>,
        /// Runs spent on this case.
        pub runs: i64,
        /// With `im.trace_past_first`: grid levels stronger than the first overturning at
        /// which the block survived; empty without it.
        pub resurrections: Option<i64>,
        /// Whether the capacity's decisive verdicts were confirmed (see `certification`).
        pub certified: bool,
        /// `exact` (the exact stepper) or `tolerance` (Taylor or DP5: the decisive verdicts
        /// stand at a 100× tighter tolerance), both with no decisive verdict changing when η
        /// moves by 1e-9 (relative); or why not: `chaotic` (one does: neither a tolerance
        /// nor exact stepping decides it), `flips` (a verdict still flips at the tightest
        /// tolerance), `fixed_step` (RK4, benchmarks only).
        pub certification: CertificationKind,
        /// The certification in a sentence, with the tolerances and the η concerned.
        pub certification_note: String,
        /// The integrator: `exact` (the linearised model's stepper), `taylor` or `dp5` (the
        /// nonlinear model's).
        pub integrator: String,
        /// The nonlinear integrator's tolerance of the search reported (Taylor's tail or
        /// DP5's rtol; tighter than the pipeline's when a looser one flipped a verdict);
        /// empty for the exact stepper.
        pub rtol: Option<f64>,
        /// On a building's floor (`[floor]`, `--floor`): the floor motion's peak over the
        /// ground record's, PFA/PGA (dimensionless); every η of the row is then the
        /// floor's, and the ground's is η·PFA/PGA. Empty on the ground.
        pub pfa_over_pga: Option<f64>,
        /// Whether the block slides before it rocks, its `mu` at most b/h (docs/MODEL.md
        /// §17): the row then holds only for a block restrained against sliding. False
        /// when no `mu` is given.
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
