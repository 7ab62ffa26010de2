//! `Block`: a block (or a grid of blocks) and how to run it, as Python
//! holds it: the library's `BlockAsk`, checked when made, kept with the
//! keywords it was made of.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use rocking::ask::{AskedBlock, BlockAsk, Spelling};
use rocking::floor::Building;

use crate::convert::{ask, ask_error, plain_value, to_py};

/// A block (or a grid of blocks) and how to run it: the library's
/// `BlockAsk`, checked when made.
#[pyclass(frozen, module = "rocking._core")]
pub(crate) struct Block {
    pub(crate) ask: BlockAsk,
    pub(crate) blocks: Vec<AskedBlock>,
    /// The keywords it was made of, for its repr and for pickling.
    kwargs: Py<PyDict>,
}

#[pymethods]
impl Block {
    #[new]
    #[pyo3(signature = (**kwargs))]
    fn new(py: Python<'_>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Block> {
        let ask: BlockAsk = ask(py, kwargs)?;
        let blocks = ask.resolve(Spelling::Python).map_err(ask_error)?;
        ask.building(Spelling::Python).map_err(ask_error)?;
        // Fresh values (lists for arrays and lists), not the caller's
        // objects: a list changed after the block is made changes neither
        // its repr nor its pickle.
        let kept = PyDict::new(py);
        for (k, v) in kwargs.into_iter().flat_map(|d| d.iter()) {
            kept.set_item(k, plain_value(&v)?)?;
        }
        Ok(Block {
            ask,
            blocks,
            kwargs: kept.unbind(),
        })
    }

    /// Equal when made of the same block options, however spelt (one
    /// number or a list of one, a NumPy scalar or a float).
    fn __eq__(&self, other: PyRef<'_, Self>) -> bool {
        self.ask == other.ask
    }

    /// Consistent with `==` (a dict's key, a set's member).
    fn __hash__(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        format!("{:?}", self.ask).hash(&mut h);
        h.finish()
    }

    /// Pickled (and copied) as its keywords, made again on loading.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (Py<PyDict>,))> {
        let make = py.import("rocking")?.getattr("_block_from")?;
        Ok((make, (self.kwargs.clone_ref(py),)))
    }

    /// Each block it stands for: `name`, `p` (1/s), `eps`, `alpha_rad`
    /// (None for a block given by p alone), `mu` and `slides_first`.
    #[getter]
    fn blocks(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let rows: Vec<serde_json::Value> = self
            .blocks
            .iter()
            .map(|b| {
                let n = &b.named;
                serde_json::json!({
                    "name": n.name, "p": n.spec.p, "eps": n.spec.eps,
                    "alpha_rad": n.alpha_rad, "mu": n.mu, "slides_first": n.slides_first,
                })
            })
            .collect();
        to_py(py, &rows)
    }

    /// How many blocks it stands for (p × ε, or each size × ε).
    fn __len__(&self) -> usize {
        self.blocks.len()
    }

    /// Why each block runs with its model.
    #[getter]
    fn why(&self) -> Vec<String> {
        self.blocks.iter().map(|b| b.why.clone()).collect()
    }

    /// What the library says of a block: one that slides before it rocks,
    /// or of sizes in another unit.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        AskedBlock::warnings_of(&self.blocks)
            .iter()
            .map(|w| Spelling::Python.respell(w))
            .collect()
    }

    /// As it was made: `Block(b=0.2, h=0.9, eps=0.85)`.
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let mut parts = Vec::new();
        for (k, v) in self.kwargs.bind(py).iter() {
            parts.push(format!("{}={}", k.str()?, v.repr()?));
        }
        Ok(format!("Block({})", parts.join(", ")))
    }
}

impl Block {
    pub(crate) fn one(&self) -> PyResult<&AskedBlock> {
        match &self.blocks[..] {
            [one] => Ok(one),
            many => Err(PyValueError::new_err(format!(
                "{} blocks given; this runs one (give one value to each block option)",
                many.len()
            ))),
        }
    }

    pub(crate) fn building(&self) -> PyResult<Option<Building>> {
        self.ask.building(Spelling::Python).map_err(ask_error)
    }
}
