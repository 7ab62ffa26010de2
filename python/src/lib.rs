//! `rocking._core`: the library's commands for Python, the compiled half of
//! the `rocking` package (its Python half, `rocking/__init__.py`, checks the
//! arguments, converts arrays and builds the tables).
//!
//! Every function calls the same library code as the command line and
//! returns the same JSON the command prints with `--json`, so a number
//! crosses to Python exactly (serde's shortest round-trip text, read back
//! by Python's correctly rounded `float`). Records cross as little-endian
//! f64 bytes, exact both ways. Errors become `ValueError`s carrying the
//! library's message and its causes (a bad AT2 file names its line); the
//! long computations release the GIL.

use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use serde::Deserialize;

use rocking::block::{Block, Restitution};
use rocking::floor::{Building, Mode};
use rocking::ida::{ImGrid, Spacing};
use rocking::ops::capacity::{self as batch, Asked, NamedSpec};
use rocking::ops::record::{self, LoadedRecord};
use rocking::ops::reports::{CapacityReport, Scene, Search, SimulateReport};
use rocking::physics::{ModelChoice, NonlinearIntegrator, Overturn, RunSpec, Solver};

/// The error and its causes, as the command line prints them, on one line.
fn message(e: &(dyn std::error::Error + 'static)) -> String {
    let mut text = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        let next = c.to_string();
        if !text.contains(&next) {
            text.push_str(": ");
            text.push_str(&next);
        }
        cause = c.source();
    }
    text
}

fn value_error<E: std::error::Error + 'static>(e: E) -> PyErr {
    PyValueError::new_err(message(&e))
}

fn json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(value_error)
}

/// Samples from little-endian f64 bytes.
fn samples(bytes: &[u8]) -> Vec<f64> {
    bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}

/// A block as Python gives it (JSON from `rocking.__init__`): by p and ε,
/// or by its half sizes, with the model and how to run it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct BlockIn {
    p: Option<f64>,
    b: Option<f64>,
    h: Option<f64>,
    /// A number or "housner".
    eps: serde_json::Value,
    alpha: Option<f64>,
    model: String,
    integrator: String,
    rtol: Option<f64>,
    auto_tol: f64,
    overturn: String,
    mu: Option<f64>,
}

/// The block asked for, its model resolved, with why; and whether it
/// slides first (when `mu` is given).
fn block(text: &str) -> PyResult<(NamedSpec, String, Scene)> {
    let b: BlockIn = serde_json::from_str(text).map_err(value_error)?;
    let model = match b.model.as_str() {
        "linearized" | "linearised" => ModelChoice::Linearized,
        "nonlinear" => ModelChoice::Nonlinear,
        "auto" => ModelChoice::Auto,
        other => {
            return Err(PyValueError::new_err(format!(
                "model = {other:?}; valid: \"linearized\", \"nonlinear\", \"auto\""
            )))
        }
    };
    let integrator = match b.integrator.as_str() {
        "taylor" => NonlinearIntegrator::Taylor,
        "dp5" => NonlinearIntegrator::Dp5,
        other => {
            return Err(PyValueError::new_err(format!(
                "integrator = {other:?}; valid: \"taylor\", \"dp5\""
            )))
        }
    };
    let solver =
        Solver::new(integrator, b.rtol).map_err(|e| PyValueError::new_err(format!("rtol: {e}")))?;
    let overturn: Overturn = b
        .overturn
        .parse()
        .map_err(|e: rocking::physics::PhysicsError| {
            PyValueError::new_err(format!("overturn: {}", message(&e)))
        })?;
    let eps: Restitution = match &b.eps {
        serde_json::Value::Number(n) => Restitution::Value(n.as_f64().unwrap_or(f64::NAN)),
        serde_json::Value::String(s) => s.parse().map_err(value_error)?,
        other => {
            return Err(PyValueError::new_err(format!(
                "eps = {other}: give a number in (0, 1] or \"housner\""
            )))
        }
    };
    let asked = Asked {
        model,
        solver,
        auto_tol: b.auto_tol,
        overturn,
    };
    let (named, why) =
        match (b.p, b.b, b.h) {
            (Some(p), None, None) => {
                let Restitution::Value(e) = eps else {
                    return Err(PyValueError::new_err(
                    "eps=\"housner\" needs the block's dimensions (b and h, or width and height)",
                ));
                };
                NamedSpec::ask(String::new(), p, e, b.alpha, &asked).map_err(value_error)?
            }
            (None, Some(bm), Some(hm)) => {
                if b.alpha.is_some() {
                    return Err(PyValueError::new_err(
                        "alpha comes from b and h; give one or the other",
                    ));
                }
                let blk = Block::new(bm, hm, eps).map_err(value_error)?;
                let name = format!("b{bm}xh{hm}");
                NamedSpec::ask(name, blk.p(), blk.eps, Some(blk.alpha()), &asked)
                    .map_err(value_error)?
            }
            _ => return Err(PyValueError::new_err(
                "give the block by p (and eps), or by its half sizes b and h (or width and height)",
            )),
        };
    let slides_first = match (b.mu, named.alpha_rad) {
        (None, _) => None,
        (Some(mu), Some(alpha)) => {
            rocking::block::check_mu(mu).map_err(|e| PyValueError::new_err(format!("mu: {e}")))?;
            Some(rocking::block::slides_first(mu, alpha))
        }
        (Some(_), None) => {
            return Err(PyValueError::new_err(
                "mu is compared with the block's b/h: give b and h (or width and height) or alpha",
            ))
        }
    };
    let scene = Scene {
        floor: None,
        mu: b.mu,
        slides_first,
    };
    Ok((named, why, scene))
}

/// A building from its modes `[[T, ζ, Γφ], …]`; `None` for none.
fn building(modes: Option<Vec<(f64, f64, f64)>>) -> PyResult<Option<Building>> {
    let Some(modes) = modes else { return Ok(None) };
    let modes = modes
        .into_iter()
        .map(|(period_s, zeta, gamma_phi)| Mode {
            period_s,
            zeta,
            gamma_phi,
        })
        .collect();
    Building::new(modes)
        .map(Some)
        .map_err(|e| PyValueError::new_err(format!("floor: {}", message(&e))))
}

/// A record from its file, or from its samples and step.
enum RecordIn {
    Path(PathBuf),
    Samples {
        id: String,
        accel: Vec<f64>,
        dt: f64,
    },
}

impl RecordIn {
    fn from_py(
        path: Option<PathBuf>,
        accel: Option<&Bound<'_, PyBytes>>,
        dt: Option<f64>,
        record_id: Option<String>,
    ) -> PyResult<RecordIn> {
        match (path, accel, dt) {
            (Some(p), None, _) => Ok(RecordIn::Path(p)),
            (None, Some(a), Some(dt)) => Ok(RecordIn::Samples {
                id: record_id.unwrap_or_else(|| "record".into()),
                accel: samples(a.as_bytes()),
                dt,
            }),
            _ => Err(PyValueError::new_err(
                "give a record's path, or its samples and dt",
            )),
        }
    }

    fn load(self, floor: Option<&Building>) -> PyResult<LoadedRecord> {
        match self {
            RecordIn::Path(p) => record::load_on(&p, floor).map_err(value_error),
            RecordIn::Samples { id, accel, dt } => {
                record::from_samples(id, accel, dt, floor).map_err(value_error)
            }
        }
    }
}

fn floor_text(b: Option<&Building>) -> Option<String> {
    b.map(|b| b.to_string())
}

/// Reads a PEER AT2 file: its samples (little-endian f64 bytes, g) and step (s).
#[pyfunction]
fn read_at2(py: Python<'_>, path: PathBuf) -> PyResult<(Py<PyBytes>, f64)> {
    let (accel, dt) = record::read_samples(&path).map_err(value_error)?;
    let bytes: Vec<u8> = accel.iter().flat_map(|a| a.to_le_bytes()).collect();
    Ok((PyBytes::new(py, &bytes).unbind(), dt))
}

/// One run at `eta` (or at the record's `pga` after scaling, g): the JSON of
/// `rocking simulate --json`.
#[pyfunction]
#[pyo3(signature = (block_json, eta=None, pga=None, path=None, accel=None, dt=None, record_id=None, floor=None))]
#[allow(clippy::too_many_arguments)]
fn simulate(
    py: Python<'_>,
    block_json: &str,
    eta: Option<f64>,
    pga: Option<f64>,
    path: Option<PathBuf>,
    accel: Option<&Bound<'_, PyBytes>>,
    dt: Option<f64>,
    record_id: Option<String>,
    floor: Option<Vec<(f64, f64, f64)>>,
) -> PyResult<String> {
    let (named, _, scene) = block(block_json)?;
    let building = building(floor)?;
    let rec = RecordIn::from_py(path, accel, dt, record_id)?.load(building.as_ref())?;
    let amplification = rec.floor.map_or(1.0, |f| f.pfa_over_pga);
    let eta =
        match (eta, pga, named.alpha_rad) {
            (Some(eta), None, _) => eta,
            (None, Some(pga), Some(alpha)) if pga > 0.0 && pga.is_finite() => {
                rocking::im::eta_of_pga(pga * amplification, alpha)
            }
            (None, Some(pga), Some(_)) => {
                return Err(PyValueError::new_err(format!(
                    "pga = {pga}: a PGA must be positive (g)"
                )))
            }
            (None, Some(_), None) => return Err(PyValueError::new_err(
                "pga needs the block's slenderness α: give b and h (or width and height) or alpha",
            )),
            _ => return Err(PyValueError::new_err("give eta or pga, one of them")),
        };
    let spec = RunSpec { eta, ..named.spec };
    spec.validate().map_err(value_error)?;
    let out = py
        .detach(|| rocking::physics::simulate(&rec.exc, &spec))
        .map_err(value_error)?;
    json(&SimulateReport::new(
        &rec,
        &spec,
        named.alpha_rad,
        &out,
        &scene,
    ))
}

/// The search's settings, checked.
fn search(levels: usize, eta_min: f64, spacing: &str, tol: f64) -> PyResult<Search> {
    let spacing = match spacing {
        "log" => Spacing::Log,
        "linear" => Spacing::Linear,
        other => {
            return Err(PyValueError::new_err(format!(
                "spacing = {other:?}; valid: \"log\", \"linear\""
            )))
        }
    };
    let grid = ImGrid {
        eta_max: 1.0,
        eta_min,
        count: levels,
        spacing,
    };
    grid.levels().map_err(value_error)?;
    Ok(Search { grid, tol })
}

/// The certified capacity of every record × block, records outer: a JSON
/// array of `rocking capacity --json` objects. `paths` are AT2 files or
/// folders (sorted as the command sorts them); `arrays` are (id, samples,
/// dt). Runs on every core of the pool, the GIL released.
#[pyfunction]
#[pyo3(signature = (blocks_json, paths, arrays, levels, eta_min, spacing, tol, floor=None))]
#[allow(clippy::too_many_arguments)]
fn capacities(
    py: Python<'_>,
    blocks_json: Vec<String>,
    paths: Vec<PathBuf>,
    arrays: Vec<(String, Bound<'_, PyBytes>, f64)>,
    levels: usize,
    eta_min: f64,
    spacing: &str,
    tol: f64,
    floor: Option<Vec<(f64, f64, f64)>>,
) -> PyResult<String> {
    let search = search(levels, eta_min, spacing, tol)?;
    let blocks = blocks_json
        .iter()
        .map(|b| block(b))
        .collect::<PyResult<Vec<_>>>()?;
    let building = building(floor)?;
    let arrays: Vec<(String, Vec<f64>, f64)> = arrays
        .iter()
        .map(|(id, a, dt)| (id.clone(), samples(a.as_bytes()), *dt))
        .collect();
    let named: Vec<NamedSpec> = blocks.iter().map(|b| b.0.clone()).collect();
    let result = py.detach(|| -> Result<_, String> {
        let mut records = if paths.is_empty() {
            Vec::new()
        } else {
            batch::load_records(&paths, building.as_ref()).map_err(|e| message(&e))?
        };
        for (id, accel, dt) in arrays {
            records.push(
                record::from_samples(id, accel, dt, building.as_ref()).map_err(|e| message(&e))?,
            );
        }
        let found = batch::capacities(&records, &named, &search.grid, search.tol, &|_| {})
            .map_err(|e| message(&e))?;
        Ok((records, found))
    });
    let (records, found) = result.map_err(PyValueError::new_err)?;
    let reports: Vec<CapacityReport> = found
        .iter()
        .enumerate()
        .map(|(case, c)| {
            let (r, b) = (case / named.len(), case % named.len());
            let scene = Scene {
                floor: floor_text(building.as_ref()),
                ..blocks[b].2.clone()
            };
            CapacityReport::new(&records[r], &named[b], c, &search, &scene)
        })
        .collect();
    json(&reports)
}

fn damage_states(states: Option<&str>) -> PyResult<Option<rocking::damage::DamageStates>> {
    states
        .map(|s| {
            rocking::damage::DamageStates::parse(s)
                .map_err(|e| PyValueError::new_err(format!("states: {e}")))
        })
        .transpose()
}

fn fit_method(method: &str) -> PyResult<rocking::damage::FitMethod> {
    match method {
        "fractile" => Ok(rocking::damage::FitMethod::Fractile),
        "mle" => Ok(rocking::damage::FitMethod::MaxLikelihood),
        other => Err(PyValueError::new_err(format!(
            "method = {other:?}; valid: \"fractile\", \"mle\""
        ))),
    }
}

fn im(text: &str) -> PyResult<rocking::im::Im> {
    text.parse().map_err(PyValueError::new_err)
}

/// P(overturn | IM) of a real block: the JSON of `rocking fragility --json`
/// (with `states`, of `rocking fragility --states … --json`).
#[pyfunction]
#[pyo3(signature = (b, h, eps, im_name, levels, from_, outputs, records, direct, auto_tol, floor=None, mu=None, states=None, method="fractile"))]
#[allow(clippy::too_many_arguments)]
fn fragility(
    py: Python<'_>,
    b: f64,
    h: f64,
    eps: &str,
    im_name: &str,
    levels: Vec<f64>,
    from_: &str,
    outputs: PathBuf,
    records: Option<PathBuf>,
    direct: bool,
    auto_tol: f64,
    floor: Option<Vec<(f64, f64, f64)>>,
    mu: Option<f64>,
    states: Option<&str>,
    method: &str,
) -> PyResult<String> {
    let req = rocking::ops::fragility::Request {
        b_m: b,
        h_m: h,
        eps: eps.parse().map_err(value_error)?,
        im: im(im_name)?,
        levels,
        from: rocking::ops::fragility::Source::named(from_, outputs, records),
        direct,
        progress: Default::default(),
        auto_tol,
        floor: building(floor)?,
        mu,
    };
    let states = damage_states(states)?;
    let method = fit_method(method)?;
    py.detach(|| match &states {
        Some(s) => rocking::ops::damage::assess(&req, s, method)
            .map_err(|e| message(&e))
            .and_then(|a| serde_json::to_string(&a).map_err(|e| e.to_string())),
        None => rocking::ops::fragility::assess(&req)
            .map_err(|e| message(&e))
            .and_then(|a| serde_json::to_string(&a).map_err(|e| e.to_string())),
    })
    .map_err(PyValueError::new_err)
}

/// The annual rate of overturning at a hazard file's sites: the JSON of
/// `rocking risk --json` (an object for one block, an array for an
/// inventory; with `states`, of `rocking risk --states … --json`).
#[pyfunction]
#[pyo3(signature = (hazard, b, h, eps, inventory, site, im_name, from_, outputs, records, direct, years, beyond, auto_tol, floor=None, mu=None, states=None, method="fractile"))]
#[allow(clippy::too_many_arguments)]
fn risk(
    py: Python<'_>,
    hazard: PathBuf,
    b: Option<f64>,
    h: Option<f64>,
    eps: &str,
    inventory: Option<PathBuf>,
    site: Option<usize>,
    im_name: Option<&str>,
    from_: &str,
    outputs: PathBuf,
    records: Option<PathBuf>,
    direct: bool,
    years: f64,
    beyond: &str,
    auto_tol: f64,
    floor: Option<Vec<(f64, f64, f64)>>,
    mu: Option<f64>,
    states: Option<&str>,
    method: &str,
) -> PyResult<String> {
    use rocking::ops::risk::{self, Blocks};
    let blocks = match (inventory, b, h) {
        (Some(path), None, None) => {
            if mu.is_some() {
                return Err(PyValueError::new_err(
                    "mu is an inventory's column: give it there",
                ));
            }
            Blocks::Inventory(path)
        }
        (None, Some(b_m), Some(h_m)) => Blocks::One {
            b_m,
            h_m,
            eps: eps.parse().map_err(value_error)?,
            mu: mu
                .map(rocking::block::check_mu)
                .transpose()
                .map_err(|e| PyValueError::new_err(format!("mu: {e}")))?,
        },
        _ => {
            return Err(PyValueError::new_err(
                "give one block's b and h, or an inventory, not both",
            ))
        }
    };
    let one = matches!(blocks, Blocks::One { .. });
    let req = risk::Request {
        hazard,
        site,
        blocks,
        from: rocking::ops::fragility::Source::named(from_, outputs, records),
        im: im_name.map(im).transpose()?,
        direct,
        progress: Default::default(),
        years,
        beyond: match beyond {
            "extrapolate" => rocking::risk::Beyond::Extrapolate,
            "stop" => rocking::risk::Beyond::Stop,
            other => {
                return Err(PyValueError::new_err(format!(
                    "beyond = {other:?}; valid: \"extrapolate\", \"stop\""
                )))
            }
        },
        auto_tol,
        floor: building(floor)?,
    };
    let states = damage_states(states)?;
    let method = fit_method(method)?;
    py.detach(|| -> Result<String, String> {
        let text = |v: serde_json::Result<String>| v.map_err(|e| e.to_string());
        match &states {
            Some(s) => {
                let all = risk::assess_states(&req, s, method).map_err(|e| message(&e))?;
                text(if one {
                    serde_json::to_string(&all[0])
                } else {
                    serde_json::to_string(&all)
                })
            }
            None => {
                let all = risk::assess(&req).map_err(|e| message(&e))?;
                text(if one {
                    serde_json::to_string(&all[0])
                } else {
                    serde_json::to_string(&all)
                })
            }
        }
    })
    .map_err(PyValueError::new_err)
}

/// Runs a pipeline's stale stages (every stage with `force`), the GIL
/// released: JSON `[{"stage", "ran", "seconds", "why"}]`, and the study's
/// folder.
#[pyfunction]
#[pyo3(signature = (pipeline, outputs, force=false))]
fn run(
    py: Python<'_>,
    pipeline: PathBuf,
    outputs: PathBuf,
    force: bool,
) -> PyResult<(String, String)> {
    use rocking::stages::engine::{self, Force, Outcome, RunOptions, Target};
    let study = rocking::stages::Study::load(&pipeline, &outputs).map_err(value_error)?;
    let opts = RunOptions {
        target: Target::All,
        force: if force { Force::All } else { Force::Nothing },
        shard: None,
        threads: None,
        command: "rocking.run (Python)".into(),
    };
    let results = py
        .detach(|| engine::run(&study, &opts, &rocking::stages::Silent))
        .map_err(value_error)?;
    let rows: Vec<serde_json::Value> = results
        .iter()
        .map(|r| match &r.outcome {
            Outcome::Ran {
                reason, seconds, ..
            } => serde_json::json!({
                "stage": r.stage, "ran": true, "seconds": seconds, "why": reason.to_string()
            }),
            Outcome::Skipped(skip) => serde_json::json!({
                "stage": r.stage, "ran": false, "seconds": null, "why": skip.to_string()
            }),
        })
        .collect();
    Ok((json(&rows)?, study.dir.display().to_string()))
}

/// The folder a pipeline's tables go to under `outputs`.
#[pyfunction]
fn study_dir(pipeline: PathBuf, outputs: PathBuf) -> PyResult<String> {
    let study = rocking::stages::Study::load(&pipeline, &outputs).map_err(value_error)?;
    Ok(study.dir.display().to_string())
}

/// The library's version.
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(read_at2, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(capacities, m)?)?;
    m.add_function(wrap_pyfunction!(fragility, m)?)?;
    m.add_function(wrap_pyfunction!(risk, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(study_dir, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    Ok(())
}
