"""Overturning of free-standing rigid blocks under earthquake records.

The Python door to ``rocking``: the same library, and the same numbers, as
the command line (``rocking simulate|capacity|fragility|risk … --json``),
with records as NumPy arrays and tables as polars DataFrames.

>>> import rocking
>>> acc, dt = rocking.read_at2("records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2")
>>> rocking.capacity(acc, dt, p=2.0, eps=0.7)["eta_c"]   # doctest: +SKIP

Units: accelerations in g, times in s, lengths (b, h) in m, p in 1/s.
η = αg/PGA is the dimensionless intensity (smaller is stronger shaking).
Errors are ``ValueError`` with the library's message.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
import warnings
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _core

__all__ = [
    "read_at2",
    "simulate",
    "capacity",
    "capacities",
    "fragility",
    "risk",
    "run",
    "load",
    "__version__",
]

__version__: str = _core.version()

PathLike = Union[str, "os.PathLike[str]"]
Record = Union[PathLike, np.ndarray, Sequence[float]]
Mode = Tuple[float, float, float]


def read_at2(path: PathLike) -> Tuple[np.ndarray, float]:
    """Read a PEER AT2 record.

    Returns its acceleration samples (g) as a 1-D float64 array and its time
    step (s). A malformed file raises ``ValueError`` naming its line.
    """
    data, dt = _core.read_at2(os.fspath(path))
    return np.frombuffer(data, dtype="<f8").copy(), dt


def _samples(acc: Any, dt: Any, what: str = "the record") -> Tuple[bytes, float]:
    """A record as little-endian f64 bytes, checked: 1-D, finite, dt > 0."""
    a = np.asarray(acc, dtype=np.float64)
    if a.ndim != 1:
        raise ValueError(f"{what} must be a 1-D array of accelerations (g); got shape {a.shape}")
    if a.size < 2:
        raise ValueError(f"{what} needs at least 2 samples; got {a.size}")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise ValueError(f"{what} holds a non-finite sample {a[bad[0]]} at index {bad[0]}")
    if dt is None:
        raise ValueError(f"{what} is an array: give its time step dt (s)")
    dt = float(dt)
    if not (dt > 0 and math.isfinite(dt)):
        raise ValueError(f"dt = {dt}: the time step must be positive and finite (s)")
    return np.ascontiguousarray(a, dtype="<f8").tobytes(), dt


def _is_path(x: Any) -> bool:
    return isinstance(x, (str, os.PathLike))


def _block(
    p: Optional[float],
    eps: Union[float, str],
    b: Optional[float],
    h: Optional[float],
    width: Optional[float],
    height: Optional[float],
    alpha: Optional[float],
    model: str,
    integrator: str,
    rtol: Optional[float],
    auto_tol: float,
    overturn: str,
    mu: Optional[float],
) -> str:
    """A block as JSON for ``_core``: by p, by half sizes b, h, or by full sizes."""
    if width is not None or height is not None:
        if width is None or height is None or b is not None or h is not None:
            raise ValueError("give the block's full width and height together, or b and h")
        b, h = width / 2.0, height / 2.0
    if isinstance(eps, str):
        eps_v: Union[float, str] = eps
    else:
        eps_v = float(eps)
    return json.dumps(
        {
            "p": None if p is None else float(p),
            "b": None if b is None else float(b),
            "h": None if h is None else float(h),
            "eps": eps_v,
            "alpha": None if alpha is None else float(alpha),
            "model": model,
            "integrator": integrator,
            "rtol": None if rtol is None else float(rtol),
            "auto_tol": float(auto_tol),
            "overturn": overturn,
            "mu": None if mu is None else float(mu),
        }
    )


def _floor(floor: Optional[Iterable[Mode]]) -> Optional[List[Mode]]:
    if floor is None:
        return None
    modes = [tuple(float(v) for v in m) for m in floor]
    for i, m in enumerate(modes):
        if len(m) != 3:
            raise ValueError(f"floor mode {i + 1} has {len(m)} numbers; a mode is (T, zeta, gamma_phi)")
    return modes  # type: ignore[return-value]


def _warn_sliding(report: Dict[str, Any]) -> Dict[str, Any]:
    """Warn, as the command line does, of a block that slides before it rocks."""
    if report.get("slides_first"):
        warnings.warn(
            f"the block slides before it rocks: friction mu = {report.get('mu')} is below b/h "
            "(Ishiyama 1982; Shenton 1996); the rocking results hold only if it is restrained "
            "against sliding",
            stacklevel=3,
        )
    return report


def _record_args(record: Record, dt: Optional[float], record_id: Optional[str]) -> Dict[str, Any]:
    if _is_path(record):
        if dt is not None:
            raise ValueError("dt comes from the AT2 file; give it only with an array")
        return {"path": os.fspath(record)}
    data, step = _samples(record, dt)
    return {"accel": data, "dt": step, "record_id": record_id or "record"}


def simulate(
    record: Record,
    dt: Optional[float] = None,
    *,
    eta: Optional[float] = None,
    pga: Optional[float] = None,
    p: Optional[float] = None,
    eps: Union[float, str],
    b: Optional[float] = None,
    h: Optional[float] = None,
    width: Optional[float] = None,
    height: Optional[float] = None,
    alpha: Optional[float] = None,
    model: str = "linearized",
    integrator: str = "taylor",
    rtol: Optional[float] = None,
    auto_tol: float = 0.01,
    overturn: str = "static",
    floor: Optional[Iterable[Mode]] = None,
    mu: Optional[float] = None,
    record_id: Optional[str] = None,
) -> Dict[str, Any]:
    """Run one record at one intensity: ``rocking simulate --json``.

    ``record`` is an AT2 path, or an array of accelerations (g) with ``dt``
    (s). The intensity is ``eta`` (η = αg/PGA) or ``pga`` (the record's PGA
    after scaling, g; on a floor, the ground's). The block is ``p`` and
    ``eps``, or its half sizes ``b``, ``h`` (or full ``width``, ``height``,
    m) and ``eps`` (a number in (0, 1] or ``"housner"``). ``model`` is
    ``linearized``, ``nonlinear`` (needs α) or ``auto``; ``integrator``
    ``taylor`` or ``dp5`` with ``rtol``; ``overturn`` ``static``,
    ``cap:<c>``, ``on-side`` or ``escape``. ``floor``: the building's modes
    ``[(T, zeta, gamma_phi), …]`` whose floor the block stands on. ``mu``:
    the base's friction coefficient (a block with μ < b/h slides first,
    flagged ``slides_first``).

    Returns the command's JSON object as a dict (θmax/α, overturning and
    its time, impacts, first uplift, …).
    """
    block = _block(p, eps, b, h, width, height, alpha, model, integrator, rtol, auto_tol, overturn, mu)
    text = _core.simulate(block, eta=eta, pga=pga, floor=_floor(floor), **_record_args(record, dt, record_id))
    return _warn_sliding(json.loads(text))


def _search(levels: int, eta_min: float, spacing: str, tol: float) -> Dict[str, Any]:
    return {"levels": int(levels), "eta_min": float(eta_min), "spacing": spacing, "tol": float(tol)}


def capacity(
    record: Record,
    dt: Optional[float] = None,
    *,
    p: Optional[float] = None,
    eps: Union[float, str],
    b: Optional[float] = None,
    h: Optional[float] = None,
    width: Optional[float] = None,
    height: Optional[float] = None,
    alpha: Optional[float] = None,
    model: str = "linearized",
    integrator: str = "taylor",
    rtol: Optional[float] = None,
    auto_tol: float = 0.01,
    overturn: str = "static",
    floor: Optional[Iterable[Mode]] = None,
    mu: Optional[float] = None,
    tol: float = 1e-4,
    levels: int = 200,
    eta_min: float = 1e-3,
    spacing: str = "log",
    record_id: Optional[str] = None,
) -> Dict[str, Any]:
    """The certified overturning capacity η_c of one record: ``rocking capacity --json``.

    Arguments as :func:`simulate` (without the intensity), and the search:
    ``levels`` intensity levels from η = 1 down to ``eta_min`` (``log`` or
    ``linear`` ``spacing``), refined by bisection to ``tol`` in η.

    Returns the command's JSON object as a dict: ``eta_c`` (``None`` when
    the block survives every level), ``pga_c_g``, the bracket, the runs,
    the certification, and on a floor ``pfa_over_pga`` and ``ground_pga_c_g``.
    """
    block = _block(p, eps, b, h, width, height, alpha, model, integrator, rtol, auto_tol, overturn, mu)
    paths, arrays = _records([record] if _is_path(record) else [(record_id or "record", record, dt)])
    text = _core.capacities([block], paths, arrays, floor=_floor(floor), **_search(levels, eta_min, spacing, tol))
    return _warn_sliding(json.loads(text)[0])


def _records(records: Any) -> Tuple[List[str], List[Tuple[str, bytes, float]]]:
    """Paths (files or folders of AT2 records), or (id, array, dt) triples, or a dict id → (array, dt)."""
    if _is_path(records):
        records = [records]
    if isinstance(records, dict):
        records = [(k, v[0], v[1]) for k, v in records.items()]
    paths: List[str] = []
    arrays: List[Tuple[str, bytes, float]] = []
    for r in records:
        if _is_path(r):
            paths.append(os.fspath(r))
        elif isinstance(r, tuple) and len(r) == 3:
            rid, acc, step = r
            data, step = _samples(acc, step, f"record {rid!r}")
            arrays.append((str(rid), data, step))
        else:
            raise ValueError(
                "records: give AT2 paths or folders, (record_id, accelerations, dt) triples, "
                "or a dict record_id -> (accelerations, dt)"
            )
    if paths and arrays:
        raise ValueError("records: give paths or arrays, not both")
    return paths, arrays


def capacities(
    records: Any,
    blocks: Sequence[Dict[str, Any]],
    *,
    floor: Optional[Iterable[Mode]] = None,
    tol: float = 1e-4,
    levels: int = 200,
    eta_min: float = 1e-3,
    spacing: str = "log",
) -> "polars.DataFrame":  # noqa: F821
    """The certified capacity of every record × block, on every core, the GIL released.

    ``records``: AT2 files or folders (searched for ``*.AT2``, in path order,
    as ``rocking capacity --record`` takes them), or ``(record_id,
    accelerations, dt)`` triples, or a dict ``record_id -> (accelerations,
    dt)``. ``blocks``: dicts of :func:`capacity`'s block arguments (``p``,
    ``eps``, ``b``, ``h``, ``width``, ``height``, ``alpha``, ``model``,
    ``integrator``, ``rtol``, ``auto_tol``, ``overturn``, ``mu``).

    Returns a polars DataFrame, one row per record × block (records outer),
    with the columns of ``rocking capacity --json``. polars rather than
    pyarrow: it is the analysts' tool of this project's Parquet outputs, and
    its frames hand over to pandas or pyarrow with ``to_pandas()``/``to_arrow()``.
    """
    import polars as pl

    allowed = {"p", "eps", "b", "h", "width", "height", "alpha", "model", "integrator", "rtol", "auto_tol", "overturn", "mu"}
    specs = []
    for i, blk in enumerate(blocks):
        unknown = set(blk) - allowed
        if unknown:
            raise ValueError(f"blocks[{i}]: unknown key(s) {sorted(unknown)}; valid: {sorted(allowed)}")
        if "eps" not in blk:
            raise ValueError(f"blocks[{i}] needs eps")
        kw = {
            "p": None, "b": None, "h": None, "width": None, "height": None, "alpha": None,
            "model": "linearized", "integrator": "taylor", "rtol": None, "auto_tol": 0.01,
            "overturn": "static", "mu": None,
        }
        kw.update(blk)
        specs.append(
            _block(kw["p"], kw["eps"], kw["b"], kw["h"], kw["width"], kw["height"], kw["alpha"],
                   kw["model"], kw["integrator"], kw["rtol"], kw["auto_tol"], kw["overturn"], kw["mu"])
        )
    if not specs:
        raise ValueError("blocks: give at least one block")
    paths, arrays = _records(records)
    text = _core.capacities(specs, paths, arrays, floor=_floor(floor), **_search(levels, eta_min, spacing, tol))
    return pl.DataFrame(json.loads(text), infer_schema_length=None)


def _source(source: PathLike) -> str:
    return source if source == "paper" else os.fspath(source)


def fragility(
    b: float,
    h: float,
    *,
    eps: Union[float, str] = "housner",
    pga: Optional[Sequence[float]] = None,
    im: str = "pga",
    at: Optional[Sequence[float]] = None,
    source: PathLike = "paper",
    outputs: PathLike = "outputs",
    records: Optional[PathLike] = None,
    direct: bool = False,
    auto_tol: float = 0.01,
    floor: Optional[Iterable[Mode]] = None,
    mu: Optional[float] = None,
    states: Optional[str] = None,
    method: str = "fractile",
) -> Dict[str, Any]:
    """P(overturn | IM) of a block of half sizes b, h (m): ``rocking fragility --json``.

    Levels in PGA (``pga``, g) or in ``im`` (``pgv``, ``sa(1.0)``, …) at
    ``at``. ``source``: ``"paper"`` (the published regression) or a pipeline
    file whose study to use (under ``outputs``). ``direct``: also run the
    block through ``records`` (a folder; default the bundled far-field
    set). ``states``: damage states (``"rocking=0.1,overturned=overturned"``)
    fitted by ``method`` (``fractile`` or ``mle``), as ``--states``.
    """
    if pga is not None:
        if at is not None or im != "pga":
            raise ValueError("give pga, or im and at, not both")
        levels = list(pga)
    elif at is not None:
        levels = list(at)
    else:
        raise ValueError("give the levels: pga=[…] (g), or im=… and at=[…]")
    text = _core.fragility(
        float(b), float(h), str(eps), im, [float(x) for x in levels], _source(source), os.fspath(outputs),
        None if records is None else os.fspath(records), bool(direct), float(auto_tol),
        floor=_floor(floor), mu=mu, states=states, method=method,
    )
    return json.loads(text)


_HAZARD_COLUMNS = {"pga": "pga_g", "pgv": "pgv_cm_s", "avgsa": "avgsa_g"}


def _hazard_file(levels: Any, rates: Any, im: str, folder: str) -> str:
    """A plain hazard CSV ``<im column>,annual_rate`` from arrays."""
    x = np.asarray(levels, dtype=np.float64)
    y = np.asarray(rates, dtype=np.float64)
    if x.ndim != 1 or y.ndim != 1 or x.size != y.size or x.size < 2:
        raise ValueError("hazard: give levels and annual rates as 1-D arrays of the same length (at least 2)")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ValueError("hazard: levels and rates must be finite")
    key = im.lower()
    column = _HAZARD_COLUMNS.get(key) or (f"{key}_g" if key.startswith("sa(") else None)
    if column is None:
        raise ValueError(f"hazard im = {im!r}: a hazard curve is in pga, pgv, sa(T) or avgsa")
    path = os.path.join(folder, "hazard.csv")
    with open(path, "w", encoding="utf-8") as f:
        f.write(f"{column},annual_rate\n")
        for a, r in zip(x, y):
            f.write(f"{float(a)!r},{float(r)!r}\n")
    return path


def risk(
    hazard: Union[PathLike, Tuple[Any, Any]],
    *,
    b: Optional[float] = None,
    h: Optional[float] = None,
    eps: Union[float, str] = "housner",
    inventory: Optional[PathLike] = None,
    site: Optional[int] = None,
    im: Optional[str] = None,
    hazard_im: str = "pga",
    source: PathLike = "paper",
    outputs: PathLike = "outputs",
    records: Optional[PathLike] = None,
    direct: bool = False,
    years: float = 50.0,
    beyond: str = "extrapolate",
    auto_tol: float = 0.01,
    floor: Optional[Iterable[Mode]] = None,
    mu: Optional[float] = None,
    states: Optional[str] = None,
    method: str = "fractile",
) -> Union[Dict[str, Any], List[Dict[str, Any]]]:
    """The annual rate of overturning at a site: ``rocking risk --json``.

    ``hazard``: an OpenQuake hazard-curve CSV or a plain ``pga_g,annual_rate``
    CSV, or arrays ``(levels, annual_rates)`` in ``hazard_im`` (``pga`` in g,
    ``pgv`` in cm/s, ``sa(T)``, ``avgsa``). One block (``b``, ``h``,
    ``eps``, ``mu``) gives a dict, an ``inventory`` CSV a list of dicts.
    """
    with tempfile.TemporaryDirectory(prefix="rocking-hazard-") as tmp:
        if isinstance(hazard, tuple):
            path = _hazard_file(hazard[0], hazard[1], hazard_im, tmp)
        else:
            path = os.fspath(hazard)
        text = _core.risk(
            path, b, h, str(eps), None if inventory is None else os.fspath(inventory), site, im,
            _source(source), os.fspath(outputs), None if records is None else os.fspath(records),
            bool(direct), float(years), beyond, float(auto_tol),
            floor=_floor(floor), mu=mu, states=states, method=method,
        )
    return json.loads(text)


def run(pipeline: PathLike, outputs: PathLike = "outputs", *, force: bool = False) -> List[Dict[str, Any]]:
    """Run a pipeline as ``rocking run`` does (stale stages only; every stage with ``force``).

    Returns one dict per stage: ``stage``, ``ran``, ``seconds``, ``why``.
    The tables are then in ``outputs/<name>/``: :func:`load` reads them.
    """
    text, _ = _core.run(os.fspath(pipeline), os.fspath(outputs), force)
    return json.loads(text)


def load(pipeline: PathLike, outputs: PathLike = "outputs") -> Dict[str, "polars.DataFrame"]:  # noqa: F821
    """A study's tables as polars DataFrames, by name (``capacities``, ``capacity_fractiles``, …).

    Sharded tables (``name.shard-K-of-N.parquet``) are read together as one.
    Columns are documented in the README's "Tables".
    """
    import polars as pl

    folder = Path(_core.study_dir(os.fspath(pipeline), os.fspath(outputs)))
    if not folder.is_dir():
        raise ValueError(f"{folder}: no study here yet; run the pipeline first (rocking.run)")
    tables: Dict[str, List[Path]] = {}
    for f in sorted(folder.glob("*.parquet")):
        name = f.name[: -len(".parquet")].split(".shard-")[0]
        tables.setdefault(name, []).append(f)
    return {name: pl.concat([pl.read_parquet(f) for f in files]) for name, files in tables.items()}
