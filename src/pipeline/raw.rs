//! The pipeline file as written: one struct per section, with
//! `deny_unknown_fields` so that a misspelt key is an error that names it,
//! and the defaults of every key (documented in `pipelines/README.md`).

use serde::Deserialize;

use crate::ida::Spacing;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawPipeline {
    pub name: Option<String>,
    pub description: Option<String>,
    pub records: Option<RawRecords>,
    /// A pulse map instead of a records study.
    pub pulses: Option<RawPulses>,
    #[serde(default)]
    pub model: RawModel,
    #[serde(default)]
    pub blocks: RawBlocks,
    #[serde(default)]
    pub block: Vec<RawBlock>,
    #[serde(default)]
    pub im: RawIm,
    #[serde(default)]
    pub reduce: RawReduce,
    pub convergence: Option<RawConvergence>,
    pub uncertainty: Option<RawUncertainty>,
    pub example: Option<RawExample>,
    pub damage: Option<RawDamage>,
    /// A logic tree over the example block: the keys of a tree file.
    pub tree: Option<toml::Value>,
    pub floor: Option<RawFloor>,
}

/// `[floor]`: the blocks stand on a floor of a linear building, given by
/// that floor's modes `[T (s), ζ, Γφ]` as `--floor` takes them, or by the
/// building's modes `[T (s), ζ, Γ, φ1, …, φn]` and the floor's `level`, as
/// `--building` and `--level` take them.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawFloor {
    #[serde(default)]
    pub modes: Vec<Vec<f64>>,
    #[serde(default)]
    pub building: Vec<crate::building::ShapedMode>,
    pub level: Option<usize>,
}

/// `[damage]`: the limit states the damage stage fits, as `--states`
/// writes them (`rocking=0.1,large_rocking=0.5,overturned=overturned`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawDamage {
    pub states: String,
}

/// `[example]`: the block the report's Fig. 5 draws, run over the records
/// by the `example` stage even when it is not one of the study's blocks:
/// `p` and `eps` (dimensionless, α from `model.alpha`), or a physical
/// block's `b`, `h` and `eps` as in `[[block]]`, with its `mu` (and
/// `mu_k`) where it slides.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawExample {
    pub name: Option<String>,
    pub p: Option<f64>,
    pub b: Option<f64>,
    pub h: Option<f64>,
    pub eps: toml::Value,
    /// As a `[[block]]`'s: the base's static and kinetic friction.
    pub mu: Option<f64>,
    pub mu_k: Option<f64>,
}

/// `[pulses]`: a pulse map (safe and overturning areas over f and η, and
/// the walls), the paper's Figs. 2–4.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawPulses {
    /// `rect` or `exp`.
    pub shape: String,
    /// The exponential pulse's shape parameters (one family per β).
    pub beta: Option<Vec<f64>>,
    /// `half` or `full`.
    #[serde(default = "default_cycle")]
    pub cycle: String,
    /// f = p·t_d values (a list or a range).
    pub f: RawValues,
    /// The map's η levels (a list or a range).
    pub eta: RawValues,
    /// Coefficients of restitution (one family per ε).
    pub eps: RawValues,
    /// Intervals per lobe (even); by default enough for the shape.
    pub intervals: Option<usize>,
}

fn default_cycle() -> String {
    "half".into()
}

/// Bootstrap bands of the capacity fractiles.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawUncertainty {
    #[serde(default = "default_resamples")]
    pub resamples: usize,
    #[serde(default = "default_level")]
    pub level: f64,
    #[serde(default = "default_unit")]
    pub unit: String,
    #[serde(default)]
    pub seed: u64,
}

fn default_resamples() -> usize {
    1000
}
fn default_level() -> f64 {
    0.90
}
fn default_unit() -> String {
    "pair".into()
}
/// Repeat the capacity search at several grid resolutions.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawConvergence {
    pub levels: Vec<usize>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawRecords {
    /// A records table written by `rocking ingest`.
    pub table: Option<String>,
    /// Or AT2 files/folders, read directly.
    pub at2: Option<Vec<String>>,
    /// Or text files/folders of columns (a structural model's floor
    /// motions), read with `unit`, `column` and, for relative
    /// accelerations, the `ground` motions' folder.
    pub text: Option<Vec<String>>,
    pub unit: Option<String>,
    pub column: Option<usize>,
    pub ground: Option<String>,
    pub manifest: Option<String>,
    #[serde(default)]
    pub sets: Vec<String>,
    #[serde(default)]
    pub ids: Vec<String>,
    /// `as-recorded` (default) or `random`: every pair at every angle.
    pub orientation: Option<String>,
    /// The angle step of `random` (°).
    pub angle_step: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawModel {
    #[serde(default = "default_kind")]
    pub kind: String,
    pub alpha: Option<f64>,
    /// The nonlinear equation's integrator: `taylor` (default) or `dp5`.
    pub integrator: Option<String>,
    /// Its tolerance; the integrator's default when absent.
    pub rtol: Option<f64>,
    #[serde(default = "default_auto_tol")]
    pub auto_tol: f64,
    /// `static` by default (`escape` for a pulse map).
    pub overturn: Option<String>,
}

fn default_kind() -> String {
    "linearized".into()
}
fn default_auto_tol() -> f64 {
    0.01
}
impl Default for RawModel {
    fn default() -> Self {
        RawModel {
            kind: default_kind(),
            alpha: None,
            integrator: None,
            rtol: None,
            auto_tol: default_auto_tol(),
            overturn: None,
        }
    }
}

/// A list of values, or a range with a count.
#[derive(Debug, Clone)]
pub enum RawValues {
    List(Vec<f64>),
    Range(RawRange),
}

/// By the value's shape, so that a bad range says what is wrong with it
/// (an untagged enum said only "data did not match any variant").
impl<'de> Deserialize<'de> for RawValues {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        match toml::Value::deserialize(d)? {
            toml::Value::Array(items) => items
                .into_iter()
                .map(|v| match v {
                    toml::Value::Float(x) => Ok(x),
                    toml::Value::Integer(i) => Ok(i as f64),
                    other => Err(D::Error::custom(format!(
                        "a list of numbers holds a {}; give numbers",
                        other.type_str()
                    ))),
                })
                .collect::<Result<_, _>>()
                .map(RawValues::List),
            toml::Value::Table(t) => toml::Value::Table(t)
                .try_into::<RawRange>()
                .map(RawValues::Range)
                .map_err(|e| {
                    D::Error::custom(format!(
                        "a range {{ from, to, count, spacing = \"linear\" | \"log\" }} with count \
                         a whole number ≥ 1: {}",
                        e.message()
                    ))
                }),
            other => Err(D::Error::custom(format!(
                "a {} where a list of numbers or a range {{ from, to, count }} goes",
                other.type_str()
            ))),
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawRange {
    pub from: f64,
    pub to: f64,
    pub count: usize,
    #[serde(default = "default_linear")]
    pub spacing: Spacing,
}

fn default_linear() -> Spacing {
    Spacing::Linear
}

/// The dimensionless grid of the paper: every p with every ε.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBlocks {
    pub p: Option<RawValues>,
    pub eps: Option<RawValues>,
}

/// A physical block: half-width b and half-height h (m), and ε (a number or
/// "housner" for Housner's bound 1 − 1.5 sin²α).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawBlock {
    pub name: Option<String>,
    pub b: f64,
    pub h: f64,
    pub eps: toml::Value,
    /// The base's static friction coefficient, when known.
    pub mu: Option<f64>,
    /// Its kinetic friction coefficient (≤ mu; mu when not given).
    pub mu_k: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawIm {
    #[serde(default = "default_log")]
    pub spacing: Spacing,
    #[serde(default = "default_count")]
    pub count: usize,
    #[serde(default = "default_eta_max")]
    pub eta_max: f64,
    #[serde(default = "default_eta_min")]
    pub eta_min: f64,
    #[serde(default = "default_tol")]
    pub tol: f64,
    #[serde(default)]
    pub trace_past_first: bool,
}

fn default_log() -> Spacing {
    Spacing::Log
}
fn default_count() -> usize {
    200
}
fn default_eta_max() -> f64 {
    1.0
}
fn default_eta_min() -> f64 {
    1e-3
}
pub(super) fn default_tol() -> f64 {
    1e-4
}

impl Default for RawIm {
    fn default() -> Self {
        RawIm {
            spacing: default_log(),
            count: default_count(),
            eta_max: default_eta_max(),
            eta_min: default_eta_min(),
            tol: default_tol(),
            trace_past_first: false,
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawReduce {
    #[serde(default = "default_fractile")]
    pub fractile: String,
}

pub(super) fn default_fractile() -> String {
    "type7".into()
}

impl Default for RawReduce {
    fn default() -> Self {
        RawReduce {
            fractile: default_fractile(),
        }
    }
}
