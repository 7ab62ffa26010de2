//! Hand-made studies for the figures' tests: a plan from a few lines of
//! pipeline text, no results, and one builder per kind of row with only the
//! columns the figures read set (the others neutral).

use crate::ida::{CertificationKind, RunKind};
use crate::physics::EquationKind;
use crate::pipeline::load_str;
use crate::stats::ResampleUnit;
use crate::study::{PulseData, StudyData};
use crate::tables::convergence::ConvergenceRow;
use crate::tables::pulse::{PulseCellRow, PulseWallRow};
use crate::tables::reduce::{CapacityBandRow, CapacityFractileRow, HorizontalRow, LognormalRow};
use crate::tables::sweep::{CapacityRow, IdaRow};

/// A study of the p × ε grid `ps` × `epss` (p outer, ε inner) with no results yet.
pub fn grid_study(ps: &[f64], epss: &[f64]) -> StudyData {
    let text = format!("[records]\nat2 = [\"r\"]\n[blocks]\np = {ps:?}\neps = {epss:?}\n");
    study(&text)
}

/// A study of named (physical) blocks: not the grid.
pub fn block_study() -> StudyData {
    study(
        "[records]\nat2 = [\"r\"]\n\
         [[block]]\nname = \"vase\"\nb = 0.1\nh = 0.4\neps = 0.8\n",
    )
}

/// A study of two named blocks of their own ε: a vase (b = 0.1, h = 0.4,
/// ε = 0.8) and an urn (b = 0.2, h = 0.5, ε = 0.6).
pub fn two_blocks_study() -> StudyData {
    study(
        "[records]\nat2 = [\"r\"]\n\
         [[block]]\nname = \"vase\"\nb = 0.1\nh = 0.4\neps = 0.8\n\
         [[block]]\nname = \"urn\"\nb = 0.2\nh = 0.5\neps = 0.6\n",
    )
}

/// A study of three named blocks listed in the order `names` (of vase,
/// urn and rack: p = 4.2, 3.7 and 2.7 1/s; urn2 is urn's twin).
pub fn three_blocks_study(names: [&str; 3]) -> StudyData {
    let block = |name: &str| match name {
        "vase" => "[[block]]\nname = \"vase\"\nb = 0.1\nh = 0.4\neps = 0.8\n",
        "urn" => "[[block]]\nname = \"urn\"\nb = 0.2\nh = 0.5\neps = 0.6\n",
        "urn2" => "[[block]]\nname = \"urn2\"\nb = 0.2\nh = 0.5\neps = 0.6\n",
        _ => "[[block]]\nname = \"rack\"\nb = 0.3\nh = 1.0\neps = 0.75\n",
    };
    let blocks: String = names.iter().map(|n| block(n)).collect();
    study(&format!("[records]\nat2 = [\"r\"]\n{blocks}"))
}

/// A study of one named block (b = 0.2, h = 1) on the floor of a
/// one-mode building.
pub fn floor_study() -> StudyData {
    study(
        "[records]\nat2 = [\"r\"]\n[floor]\nmodes = [[0.5, 0.05, 1.3]]\n\
         [[block]]\nname = \"rack\"\nb = 0.2\nh = 1.0\neps = 0.8\nmu = 0.1\n",
    )
}

/// Text records (in g) run through a one-mode building: its ground.
pub fn text_floor_study() -> StudyData {
    study(
        "[records]\ntext = [\"t\"]\nunit = \"g\"\n[floor]\nmodes = [[0.5, 0.05, 1.3]]\n\
         [[block]]\nname = \"rack\"\nb = 0.2\nh = 1.0\neps = 0.8\n",
    )
}

fn study(text: &str) -> StudyData {
    let plan = load_str(text, std::path::Path::new("t.toml")).expect("a valid pipeline");
    StudyData {
        plan,
        pipeline: "t.toml".into(),
        version: "0".into(),
        caps: Vec::new(),
        ida: Vec::new(),
        horizontal: Vec::new(),
        capacity_fractiles: Vec::new(),
        lognormal: Vec::new(),
        fit_step1: Vec::new(),
        laws: Vec::new(),
        convergence: None,
        bands: None,
        fit_bands: None,
        example: None,
        damage: Default::default(),
        efficiency: Vec::new(),
        record_ims: Vec::new(),
        tree_caps: None,
        stage_seconds: Vec::new(),
        stood_on: false,
    }
}

/// A study of the statue (b = 0.2 m, h = 0.9 m, Housner's ε) as its
/// `[example]`, with `tree` its `[[tree.eps]]` and `[[tree.model]]`
/// entries.
pub fn tree_study(tree: &str) -> StudyData {
    study(&format!(
        "[records]\nat2 = [\"r\"]\n[model]\nkind = \"auto\"\n[[block]]\nb = 0.2\nh = 0.9\n\
         eps = \"housner\"\n[example]\nname = \"statue\"\nb = 0.2\nh = 0.9\neps = \"housner\"\n\
         {tree}\n"
    ))
}

/// A pulse map of the `[pulses]` keys `pulses` (shape, β, cycle, ε) over
/// f = 0.5, 1, 2 and η = 1, 0.5, 0.1, with no results yet.
pub fn pulse_study(pulses: &str) -> PulseData {
    let text = format!(
        "[model]\nkind = \"linearized\"\n[pulses]\n{pulses}\n\
         f = [0.5, 1.0, 2.0]\neta = [1.0, 0.5, 0.1]\n"
    );
    let plan = load_str(&text, std::path::Path::new("t.toml")).expect("a valid pulse map");
    PulseData {
        plan,
        pipeline: "t.toml".into(),
        version: "0".into(),
        walls: Vec::new(),
        cells: Vec::new(),
        stage_seconds: Vec::new(),
    }
}

/// A capacity of case `case_id` (record `case_id / blocks`, block `case_id % blocks`).
pub fn cap(case_id: i64, eta_c: Option<f64>) -> CapacityRow {
    CapacityRow {
        case_id,
        record_id: format!("r{case_id}"),
        block: String::new(),
        p: 0.0,
        eps: 0.0,
        alpha_rad: None,
        model: EquationKind::Linearized,
        eta_c,
        eta_survived: 0.0,
        level_survived: 0.0,
        level_overturned: None,
        runs: 0,
        resurrections: None,
        certified: true,
        certification: CertificationKind::Exact,
        certification_note: String::new(),
        integrator: "exact".into(),
        rtol: None,
        pfa_over_pga: None,
        slides_first: false,
    }
}

/// A run of the IDA of case `case_id` at a grid level.
pub fn run(case_id: i64, pga_scale: f64, edp: f64, overturned: bool) -> IdaRow {
    IdaRow {
        case_id,
        record_id: format!("r{case_id}"),
        block: String::new(),
        p: 0.0,
        eps: 0.0,
        alpha_rad: None,
        eta: 1.0 / pga_scale,
        pga_scale,
        edp,
        overturned,
        impacts: 0,
        run_kind: RunKind::Level,
        model: EquationKind::Linearized,
        slide_max_m: None,
    }
}

/// One level of a block's horizontal fractiles: EDP at 16, 50 and 84 %.
pub fn horizontal(p: f64, eps: f64, eta: f64, edp: [f64; 3]) -> HorizontalRow {
    HorizontalRow {
        block: String::new(),
        p,
        eps,
        level: 0,
        eta,
        edp_q16: edp[0],
        edp_q50: edp[1],
        edp_q84: edp[2],
        n_records: 1,
        n_overturned: 0,
    }
}

/// A capacity fractile of block (p, ε).
pub fn fractile(p: f64, eps: f64, quantile: f64, eta_c: f64) -> CapacityFractileRow {
    CapacityFractileRow {
        block: String::new(),
        p,
        eps,
        quantile,
        eta_c,
        eta_c_horizontal: None,
        n_records: 1,
        n_censored: 0,
    }
}

/// A bootstrap band of a capacity fractile of block (p, ε).
pub fn band(p: f64, eps: f64, quantile: f64, eta_c: f64, lo: f64, hi: f64) -> CapacityBandRow {
    CapacityBandRow {
        block: String::new(),
        p,
        eps,
        quantile,
        eta_c,
        lo,
        hi,
        level: 0.9,
        resamples: 100,
        unit: ResampleUnit::Pair,
    }
}

/// The Lilliefors test of block (p, ε).
pub fn lognormal(p: f64, eps: f64, p_value: Option<f64>) -> LognormalRow {
    LognormalRow {
        block: String::new(),
        p,
        eps,
        n: 0,
        median_sample: None,
        beta_sample: None,
        median_fractile: None,
        beta_fractile: None,
        lilliefors_d: None,
        p_value,
        critical_d_5pct: None,
        rejected_5pct: false,
    }
}

/// A block's capacity at one grid resolution against the finest grid's.
pub fn level(
    levels: i64,
    n_changed: i64,
    n_records: i64,
    mean_abs: f64,
    q50: f64,
) -> ConvergenceRow {
    ConvergenceRow {
        block: String::new(),
        p: 0.0,
        eps: 0.0,
        levels,
        eta_c_q16: 0.0,
        eta_c_q50: q50,
        eta_c_q84: 0.0,
        n_records,
        n_changed,
        mean_abs_change: mean_abs,
        max_abs_change: mean_abs,
    }
}

/// A wall of family (β, ε) at f, with its closed form (`of`: the wall it gives).
pub fn wall(
    beta: Option<f64>,
    eps: f64,
    f: f64,
    eta_w: Option<f64>,
    closed: Option<(f64, &str, &str)>,
) -> PulseWallRow {
    PulseWallRow {
        pulse: if beta.is_some() { "exp" } else { "rect" }.into(),
        beta,
        cycle: "half".into(),
        eps,
        f,
        overturn: "escape".into(),
        model: "linearized".into(),
        alpha_rad: None,
        eta_w,
        eta_w_mode0: eta_w,
        mode: Some(0),
        closed_form: closed.map(|c| c.0),
        closed_form_equation: closed.map(|c| c.1.to_string()),
        closed_form_of: closed.map(|c| c.2.to_string()),
        runs: 1,
        intervals_per_lobe: 1,
    }
}

/// A point of the map of family (β, ε).
pub fn cell(
    beta: Option<f64>,
    eps: f64,
    f: f64,
    eta: f64,
    overturned: bool,
    impacts: i64,
) -> PulseCellRow {
    PulseCellRow {
        pulse: if beta.is_some() { "exp" } else { "rect" }.into(),
        beta,
        cycle: "half".into(),
        eps,
        f,
        eta,
        overturned,
        impacts,
        max_abs_x: 0.0,
    }
}
