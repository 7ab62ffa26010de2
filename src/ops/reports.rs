//! The JSON objects of `simulate` (one run) and `capacity` (one capacity),
//! defined once: the command line prints them, the Python package returns
//! them, so both give the same fields and the same numbers.

use serde::Serialize;

use super::capacity::NamedSpec;
use crate::floor::Building;
use crate::ida::{Certified, ImGrid, RunKind, Spacing};
use crate::im;
use crate::label::Label;
use crate::physics::{Outcome, RunSpec};
use crate::records::LoadedRecord;

/// Where a block stands and how firmly, as the reports state it.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// The building's modes as `--floor` takes them (`T,ζ,Γφ; …`), on a floor.
    pub floor: Option<String>,
    /// The base's friction coefficient, when given.
    pub mu: Option<f64>,
    /// With `mu`: whether the block slides before it rocks.
    pub slides_first: Option<bool>,
}

/// One run of `simulate`.
#[derive(Debug, Clone, Serialize)]
pub struct SimulateReport {
    pub record_id: String,
    pub p: f64,
    pub eps: f64,
    pub eta: f64,
    pub model: &'static str,
    pub alpha_rad: Option<f64>,
    pub overturn: String,
    pub theta_max_over_alpha: f64,
    pub overturned: bool,
    pub overturn_time_s: Option<f64>,
    pub overturn_after_record: bool,
    pub impacts: u64,
    pub first_uplift_s: Option<f64>,
    pub stop: &'static str,
    /// On a floor: the floor motion's peak over the ground record's, PFA/PGA
    /// (η is then with respect to the floor's peak).
    pub pfa_over_pga: Option<f64>,
    /// The base's friction coefficient, with --mu.
    pub mu: Option<f64>,
    /// With --mu: whether the block slides before it rocks (μ ≤ b/h).
    pub slides_first: Option<bool>,
    /// The slide-rock model's run: the base's slide and the time in each mode.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sliding: Option<Sliding>,
}

/// What a run of the slide-rock model did on its base.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Sliding {
    /// The largest |u| of the base relative to the ground (m).
    pub slide_max_m: f64,
    /// Where the base ends (m, signed; for an overturned block, where it
    /// was as it went over).
    pub slide_residual_m: f64,
    /// How many times the base or the pivot started to slip.
    pub slips: u64,
    /// Seconds of the record at rest, sliding flat, rocking and
    /// slide-rocking (up to the run's stop).
    pub rest_s: f64,
    pub slide_s: f64,
    pub rock_s: f64,
    pub slide_rock_s: f64,
}

impl Sliding {
    /// The sliding part of `out`, for a run of a model that slides.
    pub fn of(spec: &RunSpec, out: &Outcome) -> Option<Sliding> {
        spec.model.equation.friction()?;
        let [rest_s, slide_s, rock_s, slide_rock_s] = out.mode_s;
        Some(Sliding {
            slide_max_m: out.slide_max_m,
            slide_residual_m: out.slide_residual_m,
            slips: out.slips,
            rest_s,
            slide_s,
            rock_s,
            slide_rock_s,
        })
    }
}

impl SimulateReport {
    pub fn new(
        rec: &LoadedRecord,
        spec: &RunSpec,
        alpha_rad: Option<f64>,
        out: &Outcome,
        scene: &Scene,
    ) -> SimulateReport {
        SimulateReport {
            record_id: rec.record_id.clone(),
            p: spec.p,
            eps: spec.eps,
            eta: spec.eta,
            model: spec.model.equation.kind().label(),
            alpha_rad,
            overturn: spec.overturn.to_string(),
            theta_max_over_alpha: out.max_abs_x,
            overturned: out.overturned(),
            overturn_time_s: out.overturn_time_s,
            overturn_after_record: out.overturn_after_record,
            impacts: out.impacts,
            first_uplift_s: out.first_uplift_s,
            stop: out.stop.label(),
            pfa_over_pga: rec.floor.map(|f| f.pfa_over_pga),
            mu: scene.mu,
            slides_first: scene.slides_first,
            sliding: Sliding::of(spec, out),
        }
    }
}

/// The capacity search's settings: the grid of levels and the bracket's
/// tolerance.
#[derive(Debug, Clone, Copy)]
pub struct Search {
    pub grid: ImGrid,
    pub tol: f64,
}

/// One capacity of `capacity`.
#[derive(Debug, Clone, Serialize)]
pub struct CapacityReport {
    pub record_id: String,
    /// A pair's component at this angle from component a (°), with --pair.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub angle_deg: Option<f64>,
    /// The block's name: `b<b>xh<h>` for one given by its dimensions, else empty.
    pub block: String,
    pub p: f64,
    pub eps: f64,
    pub model: &'static str,
    pub alpha_rad: Option<f64>,
    pub overturn: String,
    /// With respect to the peak of the motion the block feels: the
    /// record's PGA, or on a floor the floor motion's peak (PFA).
    pub eta_c: Option<f64>,
    /// A_g at the capacity in units of αg (= 1/η_c).
    pub pga_scale_c: Option<f64>,
    /// The ground's PGA at the capacity (g), when α is known: α/η_c, or on
    /// a floor α/η_c over `pfa_over_pga` (the PGA `simulate --pga` and the
    /// hazard are in).
    pub pga_c_g: Option<f64>,
    /// On a floor: the floor motion's peak at the capacity (g), α/η_c.
    pub pfa_c_g: Option<f64>,
    /// On a floor: the building's modes as --floor takes them.
    pub floor: Option<String>,
    /// On a floor: the floor motion's peak over the ground record's,
    /// PFA/PGA, as recorded (the same at every scale).
    pub pfa_over_pga: Option<f64>,
    /// The base's friction coefficient, with --mu.
    pub mu: Option<f64>,
    /// With --mu: whether the block slides before it rocks (μ ≤ b/h).
    pub slides_first: Option<bool>,
    pub eta_survived: f64,
    pub level_survived: f64,
    pub level_overturned: Option<f64>,
    pub runs: usize,
    pub refinement_runs: usize,
    /// Whether the decisive verdicts were confirmed, and how.
    pub certified: bool,
    pub certification: String,
    /// The integrator: exact (linearised), taylor or dp5 (nonlinear).
    pub integrator: &'static str,
    /// The nonlinear integrator's tolerance of the search reported.
    pub rtol: Option<f64>,
    /// Runs spent on the certification (checks and searches redone).
    pub certification_runs: usize,
    pub tol: f64,
    pub levels: usize,
    pub eta_min: f64,
    pub spacing: &'static str,
}

impl CapacityReport {
    pub fn new(
        rec: &LoadedRecord,
        block: &NamedSpec,
        certified: &Certified,
        search: &Search,
        scene: &Scene,
    ) -> CapacityReport {
        let (spec, cap) = (&block.spec, &certified.capacity);
        // The peak of the motion the block stands on at the capacity.
        let peak_c_g = cap
            .eta_c
            .zip(block.alpha_rad)
            .map(|(e, a)| im::pga_of_eta(e, a));
        let on_floor = rec.floor;
        let pga_c_g = match on_floor {
            Some(f) => peak_c_g.map(|peak| peak / f.pfa_over_pga),
            None => peak_c_g,
        };
        CapacityReport {
            record_id: rec.record_id.clone(),
            angle_deg: rec.angle_deg,
            block: block.name.clone(),
            p: spec.p,
            eps: spec.eps,
            model: spec.model.equation.kind().label(),
            alpha_rad: block.alpha_rad,
            overturn: spec.overturn.to_string(),
            eta_c: cap.eta_c,
            pga_scale_c: cap.eta_c.map(|e| 1.0 / e),
            pga_c_g,
            pfa_c_g: on_floor.and(peak_c_g),
            floor: on_floor.and(scene.floor.clone()),
            pfa_over_pga: on_floor.map(|f| f.pfa_over_pga),
            mu: scene.mu,
            slides_first: scene.slides_first,
            eta_survived: cap.eta_survived,
            level_survived: cap.level_survived,
            level_overturned: cap.level_overturned,
            runs: cap.runs(),
            refinement_runs: refinement_runs(certified),
            certified: certified.certification.certified(),
            certification: certified.certification.to_string(),
            integrator: certified.model.integrator.name(),
            rtol: certified.model.integrator.tol(),
            certification_runs: certified.extra.runs,
            tol: search.tol,
            levels: search.grid.count,
            eta_min: search.grid.eta_min,
            spacing: match search.grid.spacing {
                Spacing::Log => "log",
                Spacing::Linear => "linear",
            },
        }
    }
}

/// The batch's capacities as `capacity --json` states each, in case order.
pub fn capacity_reports(
    records: &[LoadedRecord],
    blocks: &[NamedSpec],
    results: &[Certified],
    search: &Search,
    building: Option<&Building>,
) -> Vec<CapacityReport> {
    results
        .iter()
        .enumerate()
        .map(|(case, c)| {
            let (rec, b) = (&records[case / blocks.len()], &blocks[case % blocks.len()]);
            let scene = Scene {
                floor: building.map(|b| b.to_string()),
                mu: b.mu,
                slides_first: b.slides_first,
            };
            CapacityReport::new(rec, b, c, search, &scene)
        })
        .collect()
}

/// The runs of a search that refined its bracket by bisection.
pub fn refinement_runs(certified: &Certified) -> usize {
    let points = &certified.capacity.points;
    points
        .iter()
        .filter(|q| q.kind == RunKind::Refinement)
        .count()
}
