"""Overturning of free-standing rigid blocks under earthquake records.

The Python door to ``rocking``: the same library, and the same numbers, as
the command line (``rocking simulate|capacity|fragility|risk … --json``),
with records as NumPy arrays and tables as polars DataFrames.

>>> import rocking
>>> acc, dt = rocking.read_at2("records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2")
>>> rocking.capacity(acc, dt, p=2.0, eps=0.7)["eta_c"]   # doctest: +SKIP

A thin skin: keyword arguments go, as they are, to the library's request
types, which check them (unknown keywords, bad values and bad combinations
are refused there, with the command line's message, options named as
here). Units: accelerations in g, times in s, lengths (b, h) in m, p in
1/s. η = αg/PGA is the dimensionless intensity (smaller is stronger
shaking). Errors are ``ValueError`` with the library's message.
"""

from __future__ import annotations

import io
import os
import warnings
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _core
from ._core import Block

__all__ = [
    "Block",
    "read_at2",
    "simulate",
    "capacity",
    "capacities",
    "fragility",
    "risk",
    "risk_events",
    "export",
    "run",
    "load",
    "ims",
    "record_ims",
    "__version__",
    "__build__",
]

__version__: str = _core.version()
# The version and a hash of the library's sources: `rocking --version`
# prints the same, and a study's notes (outputs/<name>/.fingerprints/) name it.
__build__: str = _core.build()

PathLike = Union[str, "os.PathLike[str]"]
Record = Union[PathLike, np.ndarray, Sequence[float]]

# The search's keywords (the rest of a capacity's keywords are the block's).
_SEARCH = ("tol", "levels", "eta_min", "spacing")


def _block_from(kw: Dict[str, Any]) -> Block:
    """A Block made again from its keywords (how a Block pickles)."""
    return Block(**kw)


def read_at2(path: PathLike) -> Tuple[np.ndarray, float]:
    """Read a PEER AT2 record.

    Returns its acceleration samples (g) as a 1-D float64 array and its time
    step (s). A malformed file raises ``ValueError`` naming its line.
    """
    data, dt = _core.read_at2(_path(path, "path"))
    return np.frombuffer(data, dtype="<f8").copy(), dt


def _samples(acc: Any, dt: Any, what: str = "the record") -> Tuple[bytes, float]:
    """A record as little-endian f64 bytes (the library checks its values and dt)."""
    a = np.asarray(acc, dtype=np.float64)
    if a.ndim != 1:
        raise ValueError(f"{what} must be a 1-D array of accelerations (g); got shape {a.shape}")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise ValueError(f"{what} holds a non-finite sample {a[bad[0]]} at index {bad[0]}")
    if dt is None:
        raise ValueError(f"{what} is an array: give its time step dt (s)")
    return np.ascontiguousarray(a, dtype="<f8").tobytes(), _number(dt, "dt")


def _number(x: Any, key: str) -> float:
    """``x`` as one real number (a NumPy scalar or a 1-element array too),
    or a ValueError naming the keyword it came as."""
    if isinstance(x, (bool, np.bool_)) or isinstance(x, (str, bytes)):
        raise ValueError(f"{key}: give one number, not {x!r}")
    a = np.asarray(x)
    if a.size != 1 or not np.issubdtype(a.dtype, np.number) or np.iscomplexobj(a):
        raise ValueError(f"{key}: give one number, not {type(x).__name__} {x!r}")
    return float(a.reshape(()))


def _record_id(record_id: Any) -> Optional[str]:
    """An array record's id: a str (or a whole number, written out); not empty."""
    if record_id is None:
        return None
    if isinstance(record_id, (int, np.integer)) and not isinstance(record_id, (bool, np.bool_)):
        record_id = str(int(record_id))
    if not isinstance(record_id, str):
        raise ValueError(f"record_id: give a str, not {type(record_id).__name__}")
    if not record_id.strip():
        raise ValueError("record_id: give a name, not an empty string")
    return record_id


def _file_args(record: Any, dt: Any, record_id: Any) -> None:
    """A record given as a file names itself and carries its own dt: either
    given beside it is refused (each was ignored)."""
    if dt is not None:
        raise ValueError("dt comes from the AT2 file; give it only with an array")
    if record_id is not None:
        raise ValueError(
            "record_id names an array record; a file's id is its name "
            f"({Path(os.fspath(record)).stem})"
        )


def _is_path(x: Any) -> bool:
    return isinstance(x, (str, os.PathLike))


def _path(x: Any, key: str) -> str:
    """``x`` as a path, or a ValueError naming the keyword it came as."""
    if not _is_path(x):
        raise ValueError(f"{key}: give a path (a str or an os.PathLike), not {type(x).__name__}")
    return os.fspath(x)


def _block(block: Any, kw: Dict[str, Any]) -> Block:
    """The block given (a Block, or a dict of its keywords), or one made of
    the block keywords."""
    if block is not None:
        if kw:
            raise ValueError(f"give a Block or its keywords, not both (got {sorted(kw)})")
        if isinstance(block, dict):
            return Block(**block)
        if not isinstance(block, Block):
            raise ValueError(f"block: give a Block or a dict of its keywords, not {type(block).__name__}")
        return block
    return Block(**kw)


def _warn(block: Block) -> None:
    """Warn, as the command line does, of a block that slides before it rocks."""
    for w in block.warnings:
        warnings.warn(w, stacklevel=3)


def _warn_answer(answer: Any) -> Any:
    """Warn, as the command line prints them, of every ``warnings`` list in
    a command's answer (nested ones too: a block's, a site's), each text
    once, attributed to the caller of the public function; the answer keeps
    them. Returns the answer."""
    said: List[str] = []

    def walk(x: Any) -> None:
        if isinstance(x, dict):
            for k, v in x.items():
                if k == "warnings" and isinstance(v, list):
                    said.extend(w for w in v if isinstance(w, str) and w not in said)
                else:
                    walk(v)
        elif isinstance(x, list):
            for v in x:
                if isinstance(v, (dict, list)):
                    walk(v)

    walk(answer)
    for w in said:
        # The public function, then its caller.
        warnings.warn(w, stacklevel=3)
    return answer


def _options(kw: Dict[str, Any]) -> Dict[str, Any]:
    """A command's keywords as the library reads them: ``None`` is a keyword
    not given (its default), and ``states`` may be a list of
    ``name=criterion`` strings as well as the command's comma-separated text."""
    kw = {k: v for k, v in kw.items() if v is not None}
    states = kw.get("states")
    if isinstance(states, (list, tuple)):
        if not all(isinstance(x, str) for x in states):
            raise ValueError('states: give "name=criterion" strings, e.g. ["rocking=0.1", "overturned=overturned"]')
        kw["states"] = ",".join(states)
    return kw


def _record_args(record: Record, dt: Optional[float], record_id: Optional[str]) -> Dict[str, Any]:
    if _is_path(record):
        _file_args(record, dt, record_id)
        return {"path": os.fspath(record)}
    data, step = _samples(record, dt)
    return {"accel": data, "dt": step, "record_id": _record_id(record_id) or "record"}


def simulate(
    record: Record,
    dt: Optional[float] = None,
    *,
    eta: Optional[float] = None,
    pga: Optional[float] = None,
    block: Optional[Block] = None,
    record_id: Optional[str] = None,
    history: Union[bool, int] = False,
    **block_kw: Any,
) -> Dict[str, Any]:
    """Run one record at one intensity: ``rocking simulate --json``.

    ``record`` is an AT2 path, or an array of accelerations (g) with ``dt``
    (s). The intensity is ``eta`` (η = αg/PGA) or ``pga`` (the record's PGA
    after scaling, g; on a floor, the ground's). The block is a
    :class:`Block`, or its keywords here (see :class:`Block`).

    Returns the command's JSON object as a dict (θmax/α, overturning and
    its time, impacts, first uplift, …). With ``history`` (``True``, or
    ``N``: every N-th sample), also ``"history"``: the response at every
    event and every (N-th) sample as a polars DataFrame, the table
    ``simulate --history FILE.parquet --history-every N`` writes (t, x, ẋ,
    pivot, ψ̈, the slide and its velocity, the event; docs/tables.md).
    """
    blk = _block(block, block_kw)
    _warn(blk)
    eta = None if eta is None else _number(eta, "eta")
    pga = None if pga is None else _number(pga, "pga")
    if isinstance(history, (bool, np.bool_)):
        every = 1 if history else None
    elif isinstance(history, (int, np.integer)) and history >= 1:
        every = int(history)
    else:
        raise ValueError(f"history: give True, False or a whole number of samples ≥ 1, not {history!r}")
    answer, table = _core.simulate(blk, eta=eta, pga=pga, history=every,
                                   **_record_args(record, dt, record_id))
    if table is not None:
        import polars as pl

        answer["history"] = pl.read_parquet(io.BytesIO(table))
    return answer


def capacity(
    record: Record,
    dt: Optional[float] = None,
    *,
    block: Optional[Block] = None,
    record_id: Optional[str] = None,
    pair: Optional[PathLike] = None,
    angle: Any = None,
    **kw: Any,
) -> Any:
    """The certified overturning capacity η_c of one record: ``rocking capacity --json``.

    The block as :func:`simulate` takes it, and the search: ``levels``
    intensity levels (200) from η = 1 down to ``eta_min`` (1e-3), ``log`` or
    ``linear`` ``spacing``, refined by bisection to ``tol`` (1e-4) in η.

    Returns the command's JSON object as a dict: ``eta_c`` (``None`` when
    the block survives every level), ``pga_c_g``, the bracket, the runs,
    the certification, and on a floor ``pfa_over_pga`` and ``pfa_c_g`` (the
    floor's peak at the capacity; ``pga_c_g`` is the ground's PGA, as
    ``simulate(pga=…)`` takes it).

    With ``pair`` (the other horizontal component's AT2 file, 90° from
    ``record``) and ``angle`` (degrees, or a list of them): the block
    rocking in the plane at that angle from ``record`` towards ``pair``
    (``rocking capacity --pair --angle``); a list of dicts for a list.

    Block keywords that give several blocks (``p=[1, 2, 5]``), or a folder
    of AT2 records as ``record``, give a list of dicts too, one per block
    (and angle) and record, in the command's order.
    """
    search = {k: kw.pop(k) for k in _SEARCH if k in kw}
    if angle is not None and pair is None:
        # The command line demands --pair with --angle; it was ignored here.
        raise ValueError("angle: give pair too, the other horizontal component's AT2 file")
    blk = _block(block, kw)
    _warn(blk)
    if pair is not None:
        if not _is_path(record) or angle is None:
            raise ValueError("pair: give the record as an AT2 path, and the angle (degrees)")
        # A list, tuple, range or NumPy array of angles, or one angle.
        many = not isinstance(angle, (str, bytes)) and np.ndim(angle) > 0
        if many:
            angles = [_number(a, "angle") for a in np.asarray(angle, dtype=object).ravel()]
        else:
            angles = [_number(angle, "angle")]
        if not angles:
            # An empty list gave an empty list without a word.
            raise ValueError("angle: none given; give an angle in degrees, or a list of them")
        found = _core.capacities([blk], [os.fspath(record)], [], False, pair=_path(pair, "pair"),
                                 angles=angles, **search)
        return found if many or len(blk) > 1 else found[0]
    if _is_path(record):
        _file_args(record, dt, record_id)
        paths, arrays = [os.fspath(record)], []
    else:
        data, step = _samples(record, dt)
        paths, arrays = [], [(_record_id(record_id) or "record", data, step)]
    found = _core.capacities([blk], paths, arrays, False, **search)
    # Several blocks, or a folder of records: every one, as the command
    # prints them (a folder of one record is still a list).
    many = len(blk) > 1 or (_is_path(record) and os.path.isdir(os.fspath(record)))
    return found if many else found[0]


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
    if not paths and not arrays:
        # An empty list gave an empty table without a word.
        raise ValueError("records: none given; give AT2 paths or folders, or arrays")
    return paths, arrays


def capacities(
    records: Any,
    blocks: Sequence[Union[Block, Dict[str, Any]]],
    **search: Any,
) -> "polars.DataFrame":  # noqa: F821
    """The certified capacity of every record × block, on every core, the GIL released.

    ``records``: AT2 files or folders (searched for ``*.AT2``, in path order,
    as ``rocking capacity --record`` takes them), or ``(record_id,
    accelerations, dt)`` triples, or a dict ``record_id -> (accelerations,
    dt)``. ``blocks``: :class:`Block` objects (or dicts of their keywords),
    all on the same floor. ``search``: ``tol``, ``levels``, ``eta_min``,
    ``spacing``, as :func:`capacity`.

    Returns a polars DataFrame, one row per record × block (records outer):
    the ``capacities`` table, its columns typed as ``rocking capacity
    --out FILE.parquet`` writes them (docs/tables.md).
    """
    import polars as pl

    if isinstance(blocks, (Block, dict)):
        # One block, not in a list.
        blocks = [blocks]
    made = []
    for i, b in enumerate(blocks):
        if isinstance(b, Block):
            made.append(b)
            continue
        try:
            made.append(Block(**dict(b)))
        except ValueError as e:
            raise ValueError(f"blocks[{i}]: {e}") from None
    if not made:
        raise ValueError("blocks: give at least one block")
    for b in made:
        _warn(b)
    paths, arrays = _records(records)
    data = _core.capacities(made, paths, arrays, True, **search)
    return pl.read_parquet(io.BytesIO(data))


def fragility(b: float, h: float, **kw: Any) -> Dict[str, Any]:
    """P(overturn | IM) of a block of half sizes b, h (m): ``rocking fragility --json``.

    Keywords as the command's options: ``eps`` (``"housner"``), levels in
    PGA (``pga``, g) or in ``im`` (``pgv``, ``sa(1.0)``, …) at ``at``;
    ``source``: ``"paper"`` (the published regression) or a pipeline file
    whose study to use (under ``outputs``); ``direct``: also run the block
    through ``records`` (a folder; default the bundled far-field set);
    ``states``: damage states (``"rocking=0.1,overturned=overturned"``)
    fitted by ``method`` (``fractile``, ``mle``, or ``empirical``: the
    records' own curve); ``if_not_lognormal`` (``"curve"``, the default, or
    ``"lognormal"``): what the fragility is where the records' capacities
    fail the lognormal check; ``floor`` (modes ``[T, zeta, gamma_phi]``) or
    ``building`` (modes ``[T, zeta, gamma, phi1, ..., phin]``) with
    ``level``; ``mu``, ``auto_tol``; ``orientation`` (``"as-recorded"``,
    ``"random"`` or ``"worst"``: the block facing any direction of the
    records' pairs, every ``angle_step`` degrees; ``direct=True``), and a
    pair's ``im`` (``"rotd50_pga"``, ``"rotd50_sa(1.0)"``, …); ``tree``: a
    logic tree over ε and the model (a TOML file, or ``"restitution-tests"``):
    each branch's fragility, their mean (the mixture) and quantiles.
    """
    return _warn_answer(_core.fragility(b=b, h=h, **_options(kw)))


def risk(
    hazard: Union[PathLike, Tuple[Any, Any]],
    *,
    hazard_im: Optional[str] = None,
    **kw: Any,
) -> Union[Dict[str, Any], List[Dict[str, Any]]]:
    """The annual rate of overturning at a site: ``rocking risk --json``.

    ``hazard``: an OpenQuake hazard-curve CSV or a plain ``pga_g,annual_rate``
    CSV, or arrays ``(levels, annual_rates)`` in ``hazard_im`` (``pga`` in g,
    ``pgv`` in cm/s, ``sa(T)``, ``avgsa``; required with arrays, which
    carry no unit), handed to the library
    as values; a file declares its IM itself, so ``hazard_im`` with a file is
    refused.
    One block (``b``, ``h``, ``eps``, ``mu``) gives a dict, an ``inventory``
    CSV a list of dicts. ``tree``: a logic tree over ε and the model (a TOML
    file, or ``"restitution-tests"``): each site's ``mean_annual_rate``, the
    branches' rates and quantiles; ``bootstrap`` (resamples, with
    ``direct=True``) and ``seed``: a 90 % ``annual_rate_band`` from the
    records' pairs. Other keywords as the command's options.
    """
    if isinstance(hazard, list):
        # A list could be two arrays or a list of (level, rate) pairs.
        raise ValueError("hazard: give a file, or a tuple (levels, annual_rates) of two arrays")
    if isinstance(hazard, tuple):
        if len(hazard) != 2:
            raise ValueError(
                f"hazard: give a file, or (levels, annual_rates): two arrays, not {len(hazard)}"
            )
        try:
            levels, rates = (np.asarray(x, dtype=np.float64) for x in hazard)
        except (TypeError, ValueError) as e:
            raise ValueError(f"hazard: levels and annual rates must be numbers ({e})") from None
        if levels.ndim != 1 or rates.ndim != 1:
            raise ValueError("hazard: give levels and annual rates as 1-D arrays")
        if hazard_im is None:
            # Arrays carry no unit: a PGV curve in cm/s or PGA in m/s² read
            # as PGA in g is off by orders of magnitude without a word.
            raise ValueError(
                "hazard_im: levels given as arrays carry no unit; say which IM they are in "
                "(hazard_im=\"pga\" for PGA in g, \"pgv\" in cm/s, \"sa(1.0)\" in g, …)"
            )
        given: Any = {"im": hazard_im, "levels": levels.tolist(), "rates": rates.tolist()}
    elif hazard_im is not None:
        raise ValueError(
            f"hazard_im={hazard_im!r}: a hazard file declares its own IM (its header); "
            "hazard_im is the IM of levels given as arrays (to ask for the fragility's IM, give im=)"
        )
    else:
        given = _path(hazard, "hazard")
    return _warn_answer(_core.risk(hazard=given, **_options(kw)))


def risk_events(gmf: PathLike, **kw: Any) -> Dict[str, Any]:
    """Risk from OpenQuake's event-based ground-motion fields: ``rocking risk
    --gmf DIR --json``. ``gmf``: the folder ``oq run … --exports csv`` wrote
    (gmf-data, events, sitemesh CSVs; ``eff_years`` when no job.ini beside
    them says it). One block (``b``, ``h``, ``eps``) or an ``inventory``;
    ``together`` (``"same-record"`` or ``"independent"``): how the items at
    a site fall in one event; ``vector=True`` with ``direct=True``: also
    P(OT | PGA, PGV/PGA). Returns the answer, with two polars tables:
    ``"rates"`` (block, site, lon, lat, annual_rate, annual_rate_vector) and
    ``"counts"`` (site, k, rate of k or more items falling per year; site
    None for every site together); the command's count list (expected
    numbers, numbers at return periods) is ``"count_summary"``.
    """
    import polars as pl

    a = _warn_answer(_core.risk(gmf=_path(gmf, "gmf"), **_options(kw)))
    rows = [
        {
            "block": b["block"]["name"],
            "site": s["site"],
            "lon": s["lon"],
            "lat": s["lat"],
            "annual_rate": s["annual_rate"],
            "annual_rate_vector": s.get("annual_rate_vector"),
        }
        for b in a["blocks"]
        for s in b["sites"]
    ]
    counts = [
        {"site": c["site"], "k": k, "rate_at_least": r}
        for c in a["counts"]
        for k, r in enumerate(c["rate_at_least"])
    ]
    a["count_summary"] = a["counts"]
    a["rates"] = pl.DataFrame(rows, schema_overrides={"annual_rate_vector": pl.Float64})
    a["counts"] = pl.DataFrame(counts, schema_overrides={"site": pl.Int64})
    return a


def export(out: PathLike, **kw: Any) -> Dict[str, Any]:
    """A block's (or an inventory's) fragilities written for an engine into
    the folder ``out``: ``rocking export``. Keywords as the command's
    options: ``format`` (``"pelicun"`` or ``"nrml"``), one block (``b``,
    ``h``, ``eps``, ``mu``) or an ``inventory`` CSV, ``direct`` with
    ``records`` (and ``records_unit``, ``records_column``, ``records_ground``
    for a structural model's text floor motions), ``im`` (``"pfv"``, ``"pfa"``, ``"pga"``,
    …), ``states``, ``method``, ``if_not_lognormal``, ``floor``,
    ``hazard``, ``tree`` (OpenQuake gets each branch and a taxonomy
    mapping, pelicun the mean). Returns ``{"files": [...], "blocks": [...]}``, the blocks
    as ``rocking export --json`` prints them.
    """
    return _warn_answer(_core.export(out=_path(out, "out"), **_options(kw)))


def ims() -> List[Dict[str, Any]]:
    """Every measure a record has (``rocking ims``), then the floor demands
    PFA, PFV and FSA(T) and a pair's RotD50 and RotD100 (SA at 1 s standing
    for any period), with what each answers: ``name``, ``key`` (its column),
    ``unit``, whether it ``scales`` (a capacity can be stated in it),
    whether a ``hazard`` curve may be in it, whether it is a ``floor``
    demand (of the motion the block stands on, ``direct=True`` only) or a
    ``pair``'s measure (of the records' pairs, ``direct=True`` only), and
    its ``openquake`` and ``pelicun`` names (``None``: none)."""
    return _core.ims()


def record_ims(
    record: Record,
    dt: Optional[float] = None,
    *,
    pair: Optional[Record] = None,
    pair_dt: Optional[float] = None,
    periods: Sequence[float] = (),
) -> Dict[str, Any]:
    """A record's intensity measures: ``rocking ims --json``, by the same
    function. ``record`` (and ``pair``, the other horizontal component, 90°
    from it) an AT2 path, or an array of accelerations (g) with its
    ``dt`` (``pair_dt``) in s; ``periods``: SA also at these (s).

    Returns ``pga_g``, ``pgv_cm_s``, ``pgd_cm``, ``sa_g`` (period → SA, 5 %
    damping), ``avgsa_g``, ``arias_m_s``, ``cav_g_s``, ``d5_95_s``,
    ``pgv_pga_s`` and ``tm_s``; with ``pair`` also ``rotd50`` and
    ``rotd100`` (PGA, PGV and SA over the angles)."""
    def samples(r: Any, step: Any, key: str, what: str) -> Tuple[bytes, float]:
        if _is_path(r):
            if step is not None:
                raise ValueError(f"{key} comes from the AT2 file; give it only with an array")
            data, step = _core.read_at2(os.fspath(r))
            return data, step
        if step is None:
            raise ValueError(f"{what} is an array: give its time step {key} (s)")
        return _samples(r, step, what)

    data, step = samples(record, dt, "dt", "the record")
    if isinstance(periods, (str, bytes)):
        raise ValueError(f"periods: give numbers (s), not the text {periods!r}")
    ts = [_number(t, "periods") for t in np.atleast_1d(np.asarray(periods, dtype=object)).ravel()]
    if pair is None:
        if pair_dt is not None:
            raise ValueError("pair_dt: give pair too")
        return _core.record_ims(data, step, periods=ts)
    b, b_step = samples(pair, pair_dt, "pair_dt", "the pair")
    return _core.record_ims(data, step, pair=b, pair_dt=b_step, periods=ts)


def run(
    pipeline: PathLike,
    outputs: PathLike = "outputs",
    *,
    force: bool = False,
    from_: Optional[str] = None,
    to: Optional[str] = None,
    threads: Optional[int] = None,
) -> List[Dict[str, Any]]:
    """Run a pipeline as ``rocking run`` does: its stale stages; every stage
    with ``force``; ``from_`` (``--from``) that stage and every later one;
    through ``to`` (``--to``) only; on ``threads`` workers (``--threads``,
    default one per core).

    Returns one dict per stage: ``stage``, ``ran``, ``seconds``, ``why``.
    The tables are then in ``outputs/<name>/``: :func:`load` reads them.
    """
    if not isinstance(force, (bool, np.bool_)):
        raise ValueError(f"force: give True or False, not {force!r}")
    force = bool(force)
    for key, v in (("from_", from_), ("to", to)):
        if v is not None and not isinstance(v, str):
            raise ValueError(f"{key}: give a stage's name, not {type(v).__name__}")
    if threads is not None:
        if isinstance(threads, (bool, np.bool_)) or not isinstance(threads, (int, np.integer)) or threads < 0:
            raise ValueError(f"threads: give a whole number of worker threads, not {threads!r}")
        threads = int(threads)
    rows, _ = _core.run(_path(pipeline, "pipeline"), _path(outputs, "outputs"), force,
                        from_=from_, to=to, threads=threads)
    return rows


def load(pipeline: PathLike, outputs: PathLike = "outputs") -> Dict[str, "polars.DataFrame"]:  # noqa: F821
    """A study's tables as polars DataFrames, by name (``capacities``, ``capacity_fractiles``, …).

    Sharded tables (``name.shard-K-of-N.parquet``) are read together as one.
    Columns are documented in docs/tables.md.
    """
    import polars as pl

    folder = Path(_core.study_dir(_path(pipeline, "pipeline"), _path(outputs, "outputs")))
    if not folder.is_dir():
        raise ValueError(f"{folder}: no study here yet; run the pipeline first (rocking.run)")
    tables: Dict[str, List[Path]] = {}
    for f in sorted(folder.glob("*.parquet")):
        name = f.name[: -len(".parquet")].split(".shard-")[0]
        tables.setdefault(name, []).append(f)
    return {name: pl.concat([pl.read_parquet(f) for f in files]) for name, files in tables.items()}
