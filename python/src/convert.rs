//! Python's values into the library's requests and its answers back:
//! keyword arguments deserialised (NumPy arrays and scalars, paths read as
//! the values they stand for), refusals in Python's words, answers as the
//! command's JSON objects, records as little-endian f64 bytes.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use pythonize::pythonize;

use rocking::ask::Spelling;

/// The error and its causes, as the command line prints them, on one line,
/// the options named as Python's keywords ([`Spelling::respell`]).
pub(crate) fn message(e: &(dyn std::error::Error + 'static)) -> String {
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
    Spelling::Python.respell(&text)
}

/// A refusal of the ask layer, in Python's words (its own parts already
/// are; an inner message of the library's may name a command-line option).
pub(crate) fn ask_error(e: rocking::ask::AskError) -> PyErr {
    PyValueError::new_err(Spelling::Python.respell(&e.0))
}

pub(crate) fn value_error<E: std::error::Error + 'static>(e: E) -> PyErr {
    PyValueError::new_err(message(&e))
}

/// Keyword arguments into a request type, unknown keys refused; numpy's
/// arrays and scalars, and paths, read as the Python values they stand for.
pub(crate) fn ask<T: serde::de::DeserializeOwned>(
    py: Python<'_>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<T> {
    let plain = PyDict::new(py);
    for (k, v) in kwargs.into_iter().flat_map(|d| d.iter()) {
        plain.set_item(k, plain_value(&v)?)?;
    }
    let mut de = pythonize::Depythonizer::from_object(plain.as_any());
    serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let key = e.path().to_string();
        PyValueError::new_err(keyword_error(&key, &e.into_inner().to_string()))
    })
}

/// A keyword's value refused as Python's conversions word it (a negative
/// count, a float for an integer), in the keyword's words; the library's
/// own refusals, which name their key, as they are.
fn keyword_error(key: &str, why: &str) -> String {
    let key = key.split(['.', '[']).next().unwrap_or(key);
    if key.is_empty() || why.starts_with(key) || why.contains(&format!("`{key}`")) {
        return why.to_string();
    }
    if why.contains("negative int to unsigned") {
        // Some keys take 0, some start at 1: their own checks say which.
        format!("{key}: a whole number (it was negative)")
    } else if why.contains("cannot be interpreted as an integer") {
        // Python's words: "'str' object cannot be …".
        let kind = why.split('\'').nth(1).unwrap_or("float");
        format!("{key}: a whole number (it was a {kind})")
    } else {
        format!("{key}: {why}")
    }
}

/// A keyword's value as pythonize reads it: a numpy array or scalar as its
/// `tolist()` (a list of floats, a float), a path as its text, each item
/// of a list or tuple so too; anything else as it is.
pub(crate) fn plain_value<'py>(v: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    use pyo3::types::{PyList, PyString, PyTuple};
    if v.is_instance_of::<PyString>() {
        return Ok(v.clone());
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items = v
            .try_iter()?
            .map(|item| plain_value(&item?))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(PyList::new(v.py(), items)?.into_any());
    }
    if v.hasattr("__fspath__")? {
        return v.call_method0("__fspath__");
    }
    let numpy = v
        .get_type()
        .module()
        .is_ok_and(|m| m.to_string_lossy().starts_with("numpy"));
    if numpy && v.hasattr("tolist")? {
        return v.call_method0("tolist");
    }
    Ok(v.clone())
}

/// A value as the Python object its JSON would be (dicts, lists, floats).
pub(crate) fn to_py<T: serde::Serialize>(py: Python<'_>, value: &T) -> PyResult<Py<PyAny>> {
    Ok(pythonize(py, value)
        .map_err(|e| PyValueError::new_err(e.to_string()))?
        .unbind())
}

/// Samples from little-endian f64 bytes.
pub(crate) fn samples(bytes: &[u8]) -> Vec<f64> {
    bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}
