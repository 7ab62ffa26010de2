//! `rocking._core`: the library for Python, the compiled half of the
//! `rocking` package (its Python half, `rocking/__init__.py`, converts
//! arrays and reads tables).
//!
//! A thin skin: keyword arguments land in the library's own request types
//! (`rocking::ask`: [`Block`] wraps a `BlockAsk`; `fragility` and `risk`
//! take a `FragilityAsk`, a `RiskAsk`), deserialised by `pythonize` with
//! unknown keys refused, and resolved by the same `resolve` as the command
//! line's, which does every check; answers come back as the command's JSON
//! objects (dicts, numbers exact) or as tables in Parquet bytes (their
//! Arrow types kept). Records cross as little-endian f64 bytes, exact both
//! ways. Errors become `ValueError`s carrying the library's message and its
//! causes; the long computations release the GIL, and Ctrl-C stops them
//! (`interrupt`).

use std::path::PathBuf;

mod block;
mod convert;
mod interrupt;
use block::Block;
use convert::{ask, ask_error, message, samples, to_py, value_error};
use interrupt::{interruptible, interruptible_once};

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use rocking::ask::{ExportKw, FragilityAsk, RiskAsk, SearchAsk, Spelling};
use rocking::floor::Building;
use rocking::ops::capacity::{self as batch, NamedSpec};
use rocking::ops::reports::{Scene, SimulateReport};
use rocking::physics::RunSpec;
use rocking::records::{self, LoadedRecord};

/// A record from its file, or from its samples and step.
fn load_record(
    path: Option<PathBuf>,
    accel: Option<&Bound<'_, PyBytes>>,
    dt: Option<f64>,
    record_id: Option<String>,
    floor: Option<&Building>,
) -> PyResult<LoadedRecord> {
    match (path, accel, dt) {
        (Some(p), None, _) => records::load_on(&p, floor).map_err(value_error),
        (None, Some(a), Some(dt)) => records::from_samples(
            record_id.unwrap_or_else(|| "record".into()),
            samples(a.as_bytes()),
            dt,
            floor,
        )
        .map_err(value_error),
        _ => Err(PyValueError::new_err(
            "give a record's path, or its samples and dt",
        )),
    }
}

/// Reads a PEER AT2 file: its samples (little-endian f64 bytes, g) and step (s).
#[pyfunction]
fn read_at2(py: Python<'_>, path: PathBuf) -> PyResult<(Py<PyBytes>, f64)> {
    let (accel, dt) = records::read_samples(&path).map_err(value_error)?;
    let bytes: Vec<u8> = accel.iter().flat_map(|a| a.to_le_bytes()).collect();
    Ok((PyBytes::new(py, &bytes).unbind(), dt))
}

/// A record's intensity measures (and with a pair's other component, the
/// pair's RotD50 and RotD100): the object of `rocking ims --json`, by the
/// same function.
#[pyfunction]
#[pyo3(signature = (accel, dt, pair=None, pair_dt=None, periods=Vec::new()))]
fn record_ims(
    py: Python<'_>,
    accel: &Bound<'_, PyBytes>,
    dt: f64,
    pair: Option<&Bound<'_, PyBytes>>,
    pair_dt: Option<f64>,
    periods: Vec<f64>,
) -> PyResult<Py<PyAny>> {
    let a = samples(accel.as_bytes());
    let b = pair.map(|b| samples(b.as_bytes()));
    let with = match (&b, pair_dt) {
        (Some(b), Some(t)) => Some((&b[..], t)),
        (None, _) => None,
        (Some(_), None) => return Err(PyValueError::new_err("pair: give its dt too")),
    };
    let m =
        rocking::ops::record_ims::Measures::of(&a, dt, with, &periods).map_err(|e| match e {
            rocking::ops::record_ims::MeasuresError::Period(t) => {
                PyValueError::new_err(format!("periods: {t} is not a positive number of seconds"))
            }
            e => value_error(e),
        })?;
    to_py(py, &m.json())
}

/// One run at `eta` (or at the record's `pga` after scaling, g): the object
/// of `rocking simulate --json`.
#[pyfunction]
#[pyo3(signature = (block, eta=None, pga=None, path=None, accel=None, dt=None, record_id=None, history=None))]
#[allow(clippy::too_many_arguments)]
fn simulate(
    py: Python<'_>,
    block: &Block,
    eta: Option<f64>,
    pga: Option<f64>,
    path: Option<PathBuf>,
    accel: Option<&Bound<'_, PyBytes>>,
    dt: Option<f64>,
    record_id: Option<String>,
    history: Option<usize>,
) -> PyResult<(Py<PyAny>, Option<Py<PyBytes>>)> {
    let named = &block.one()?.named;
    let building = block.building()?;
    let shown = path.as_ref().map(|p| p.display().to_string());
    let rec = load_record(path, accel, dt, record_id, building.as_ref())?;
    let amplification = rec.floor.map_or(1.0, |f| f.pfa_over_pga);
    let eta =
        rocking::ask::excitation::eta(Spelling::Python, eta, pga, named.alpha_rad, amplification)
            .map_err(ask_error)?;
    let spec = RunSpec { eta, ..named.spec };
    spec.validate().map_err(value_error)?;
    // With `history`: every event and every `history`-th sample, as
    // `simulate --history FILE --history-every N` writes them.
    let (out, points) = interruptible(py, || match history {
        Some(every) => {
            let mut recorder = rocking::physics::Recorder::new(every);
            rocking::physics::simulate_observed(&rec.exc, &spec, &mut recorder)
                .map(|o| (o, Some(recorder.points)))
        }
        None => rocking::physics::simulate(&rec.exc, &spec).map(|o| (o, None)),
    })?
    .map_err(value_error)?;
    let table = match points {
        Some(points) => {
            let record = shown.unwrap_or_else(|| rec.record_id.clone());
            let settings = rocking::tables::history::settings(&record, &spec);
            let bytes =
                rocking::tables::history::to_bytes(&points, &settings).map_err(value_error)?;
            Some(PyBytes::new(py, &bytes).unbind())
        }
        None => None,
    };
    let scene = Scene {
        floor: None,
        mu: named.mu,
        slides_first: named.slides_first,
    };
    let report = to_py(
        py,
        &SimulateReport::new(&rec, &spec, named.alpha_rad, &out, &scene),
    )?;
    Ok((report, table))
}

/// The certified capacity of every record × block, records outer, on every
/// core of the pool, the GIL released. `paths` are AT2 files or folders
/// (sorted as the command sorts them); `arrays` are (id, samples, dt).
/// `table`: the rows of the `capacities` table as Parquet bytes (as
/// `rocking capacity --out` writes it); else the objects of `rocking
/// capacity --json`, one per capacity.
#[pyfunction]
#[pyo3(signature = (blocks, paths, arrays, table, pair=None, angles=Vec::new(), **search))]
#[allow(clippy::too_many_arguments)]
fn capacities(
    py: Python<'_>,
    blocks: Vec<PyRef<'_, Block>>,
    paths: Vec<PathBuf>,
    arrays: Vec<(String, Bound<'_, PyBytes>, f64)>,
    table: bool,
    pair: Option<PathBuf>,
    angles: Vec<f64>,
    search: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<PyAny>> {
    let search = ask::<SearchAsk>(py, search)?
        .resolve(Spelling::Python)
        .map_err(ask_error)?;
    let named: Vec<NamedSpec> = blocks
        .iter()
        .flat_map(|b| b.blocks.iter().map(|a| a.named.clone()))
        .collect();
    // The records run once, on the floor the blocks stand on: one for all.
    let buildings = blocks
        .iter()
        .map(|b| b.building())
        .collect::<PyResult<Vec<_>>>()?;
    if buildings.windows(2).any(|w| w[0] != w[1]) {
        return Err(PyValueError::new_err(
            "blocks: every block of a batch stands on the same floor (or all on the ground)",
        ));
    }
    let building = buildings.into_iter().next().flatten();
    let arrays: Vec<(String, Vec<f64>, f64)> = arrays
        .iter()
        .map(|(id, a, dt)| (id.clone(), samples(a.as_bytes()), *dt))
        .collect();
    rocking::ask::check_angles(&angles, Spelling::Python).map_err(ask_error)?;
    let (records, found) = interruptible(py, || -> Result<_, String> {
        let mut records = match (&pair, &paths[..]) {
            // The pair's component at each angle (`capacity --pair --angle`).
            (Some(b), [a]) => {
                records::pair_at(a, b, &angles, building.as_ref()).map_err(|e| message(&e))?
            }
            (Some(_), _) => return Err("pair: give one record, the pair's first component".into()),
            (None, []) => Vec::new(),
            (None, _) => batch::load_records(&paths, building.as_ref()).map_err(|e| message(&e))?,
        };
        for (id, accel, dt) in arrays.iter().cloned() {
            records.push(
                records::from_samples(id, accel, dt, building.as_ref()).map_err(|e| message(&e))?,
            );
        }
        let found = batch::capacities(&records, &named, &search.grid, search.tol, &|_| {})
            .map_err(|e| message(&e))?;
        Ok((records, found))
    })?
    .map_err(PyValueError::new_err)?;
    if table {
        let rows = batch::rows(&records, &named, &found);
        let bytes = rocking::tables::to_bytes(&rows, &[]).map_err(value_error)?;
        return Ok(PyBytes::new(py, &bytes).into_any().unbind());
    }
    let reports = rocking::ops::reports::capacity_reports(
        &records,
        &named,
        &found,
        &search,
        building.as_ref(),
    );
    to_py(py, &reports)
}

/// P(state | IM) of a real block: the object of `rocking fragility --json`
/// (with `states`, of `rocking fragility --states … --json`).
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn fragility(py: Python<'_>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Py<PyAny>> {
    let (req, states) = ask::<FragilityAsk>(py, kwargs)?
        .resolve(Spelling::Python, Default::default())
        .map_err(ask_error)?;
    let answer = interruptible(py, || match &states.states {
        Some(s) => rocking::ops::damage::assess(&req, s, states.method)
            .map(|a| serde_json::to_value(a).expect("an assessment serialises"))
            .map_err(|e| message(&e)),
        None => rocking::ops::fragility::assess(&req)
            .map(|a| serde_json::to_value(a).expect("an assessment serialises"))
            .map_err(|e| message(&e)),
    })?;
    let mut answer = answer.map_err(PyValueError::new_err)?;
    Spelling::Python.respell_warnings(&mut answer);
    to_py(py, &answer)
}

/// The annual rate of overturning (or of each damage state) at a hazard's
/// sites: the object of `rocking risk --json` for one block, the list for
/// an inventory. `hazard` is a file, or `{"im", "levels", "rates"}`.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn risk(py: Python<'_>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Py<PyAny>> {
    use rocking::ops::risk::{self, Blocks};
    let (req, states) = ask::<RiskAsk>(py, kwargs)?
        .resolve(Spelling::Python, Default::default())
        .map_err(ask_error)?;
    let one = matches!(req.blocks, Blocks::One { .. });
    let answer = interruptible(py, || -> Result<serde_json::Value, String> {
        // Event-based fields: one answer over every block.
        if let risk::Hazard::Events(e) = &req.hazard {
            let a = risk::assess_events(&req, e).map_err(|e| message(&e))?;
            return serde_json::to_value(a).map_err(|e| e.to_string());
        }
        let all = match &states.states {
            Some(s) => serde_json::to_value(
                risk::assess_states(&req, s, states.method).map_err(|e| message(&e))?,
            ),
            None => serde_json::to_value(risk::assess(&req).map_err(|e| message(&e))?),
        }
        .map_err(|e| e.to_string())?;
        Ok(if one { all[0].clone() } else { all })
    })?;
    let mut answer = answer.map_err(PyValueError::new_err)?;
    Spelling::Python.respell_warnings(&mut answer);
    to_py(py, &answer)
}

/// A block's (or an inventory's) fragilities written for OpenQuake or
/// pelicun into `out`: `{"files": [...], "blocks": [...]}`, the blocks as
/// `rocking export --json` prints them.
#[pyfunction]
#[pyo3(signature = (**kwargs))]
fn export(py: Python<'_>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Py<PyAny>> {
    let (req, _) = ask::<ExportKw>(py, kwargs)?
        .ask(Spelling::Python)
        .and_then(|a| a.resolve(Spelling::Python, Default::default()))
        .map_err(ask_error)?;
    let answer = interruptible(py, || -> Result<serde_json::Value, String> {
        let written = rocking::ops::export::export(&req).map_err(|e| message(&e))?;
        let files: Vec<String> = written
            .files
            .iter()
            .map(|f| f.display().to_string())
            .collect();
        Ok(serde_json::json!({ "files": files, "blocks": written.blocks }))
    })?;
    let mut answer = answer.map_err(PyValueError::new_err)?;
    Spelling::Python.respell_warnings(&mut answer);
    to_py(py, &answer)
}

/// Runs a pipeline's stale stages (every stage with `force`, `from_` and
/// every later one, through `to`) on `threads` workers, the GIL released,
/// as `rocking run` does: `[{"stage", "ran", "seconds", "why"}]`, and the
/// study's folder.
#[pyfunction]
#[pyo3(signature = (pipeline, outputs, force=false, from_=None, to=None, threads=None))]
fn run(
    py: Python<'_>,
    pipeline: PathBuf,
    outputs: PathBuf,
    force: bool,
    from_: Option<String>,
    to: Option<String>,
    threads: Option<usize>,
) -> PyResult<(Py<PyAny>, String)> {
    use rocking::stages::engine::{self, Outcome, RunOptions};
    let stage = |key: &str, name: Option<String>| -> PyResult<_> {
        name.map(|n| {
            engine::find(&n).ok_or_else(|| {
                PyValueError::new_err(format!(
                    "{key}: unknown stage `{n}`; valid: {}",
                    engine::names()
                ))
            })
        })
        .transpose()
    };
    let (from, to) = (stage("from_", from_)?, stage("to", to)?);
    let study = rocking::stages::Study::load(&pipeline, &outputs).map_err(value_error)?;
    let opts = RunOptions::run(to, from, force, threads, "rocking.run (Python)".into());
    let results = interruptible_once(py, || engine::run(&study, &opts, &rocking::stages::Silent))?
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
    Ok((to_py(py, &rows)?, study.dir.display().to_string()))
}

/// The folder a pipeline's tables go to under `outputs`.
#[pyfunction]
fn study_dir(pipeline: PathBuf, outputs: PathBuf) -> PyResult<String> {
    let study = rocking::stages::Study::load(&pipeline, &outputs).map_err(value_error)?;
    Ok(study.dir.display().to_string())
}

/// Every intensity measure a record has, with what each answers: its name,
/// key, unit, and whether a capacity, a hazard curve, OpenQuake and pelicun
/// may be in it. The same enum the command line and the tables derive from.
#[pyfunction]
fn ims(py: Python<'_>) -> PyResult<Py<PyAny>> {
    let kinds = rocking::im::Im::kinds();
    let floor = kinds.into_iter().filter(|im| im.floor());
    let pair = kinds.into_iter().filter(|im| im.pair());
    let all: Vec<serde_json::Value> = rocking::im::Im::record_measures()
        .into_iter()
        .chain(floor)
        .chain(pair)
        .map(|im| {
            serde_json::json!({
                "name": im.name(),
                "key": im.key(),
                "unit": im.unit(),
                "scales": im.scales(),
                "hazard": im.hazard(),
                "floor": im.floor(),
                "pair": im.pair(),
                "openquake": im.openquake(),
                "pelicun": im.pelicun().map(|(name, _)| name),
            })
        })
        .collect();
    to_py(py, &all)
}

/// The library's version.
#[pyfunction]
fn version() -> &'static str {
    rocking::VERSION
}

/// The build, as `rocking --version` and a study's notes name it: the
/// version and a hash of the library's sources.
#[pyfunction]
fn build() -> &'static str {
    rocking::BUILD
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Block>()?;
    m.add_function(wrap_pyfunction!(read_at2, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(capacities, m)?)?;
    m.add_function(wrap_pyfunction!(fragility, m)?)?;
    m.add_function(wrap_pyfunction!(risk, m)?)?;
    m.add_function(wrap_pyfunction!(export, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(study_dir, m)?)?;
    m.add_function(wrap_pyfunction!(ims, m)?)?;
    m.add_function(wrap_pyfunction!(record_ims, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    m.add_function(wrap_pyfunction!(build, m)?)?;
    Ok(())
}
