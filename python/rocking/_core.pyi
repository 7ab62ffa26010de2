"""The compiled half of ``rocking`` (PyO3): keyword arguments into the
library's request types, answers as Python objects or Parquet bytes; see
``rocking``."""

from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

Mode = Union[Tuple[float, float, float], str]
Number = Union[float, int]

class Block:
    """A block (or a grid: p × eps, or each size × eps) and how to run it,
    checked when made. Keywords: ``p`` (1/s) or half sizes ``b``, ``h``
    or full ``width``, ``height`` (m), each a number or a list; ``eps`` (a
    number in (0, 1] or ``"housner"``, needs the sizes; or a list);
    ``alpha`` (rad, with ``p``); ``model`` (``linearized``, ``nonlinear``,
    ``auto``, ``slide-rock``); ``integrator`` (``taylor``, ``dp5``) and
    ``rtol``; ``auto_tol``; ``overturn`` (``static``, ``cap:<c>``,
    ``on-side``, ``escape``); ``mu`` and ``mu_k`` (the base's static and
    kinetic friction: ``slide-rock`` and ``auto`` run the block on them);
    ``floor`` (the building's modes ``[(T, zeta, gamma_phi), …]``, or one
    mode, as numbers or as the command line's text ``"T,ZETA,GAMMA_PHI"``),
    or ``building`` (modes ``[(T, zeta, gamma, phi1, …, phin), …]``) with
    ``level`` (the floor, 1 to n). Equal when made of the same options;
    pickles and copies as its keywords; ``blocks`` lists each block it
    stands for."""

    def __init__(
        self,
        *,
        p: Union[Number, Sequence[Number], None] = None,
        b: Union[Number, Sequence[Number], None] = None,
        h: Union[Number, Sequence[Number], None] = None,
        width: Union[Number, Sequence[Number], None] = None,
        height: Union[Number, Sequence[Number], None] = None,
        eps: Union[Number, str, Sequence[Union[Number, str]]] = ...,
        alpha: Optional[float] = None,
        model: str = "linearized",
        integrator: str = "taylor",
        rtol: Optional[float] = None,
        auto_tol: float = 0.01,
        overturn: str = "static",
        mu: Optional[float] = None,
        mu_k: Optional[float] = None,
        floor: Union[Mode, Sequence[Mode], None] = None,
        building: Union[Sequence[Number], Sequence[Sequence[Number]], str, None] = None,
        level: Optional[int] = None,
    ) -> None: ...
    def __len__(self) -> int: ...
    def __eq__(self, other: object) -> bool: ...
    @property
    def blocks(self) -> List[Dict[str, Any]]: ...
    @property
    def why(self) -> List[str]: ...
    @property
    def warnings(self) -> List[str]: ...

def version() -> str: ...
def record_ims(
    accel: bytes,
    dt: float,
    pair: Optional[bytes] = None,
    pair_dt: Optional[float] = None,
    periods: Sequence[float] = ...,
) -> Dict[str, Any]: ...
def build() -> str: ...
def read_at2(path: str) -> Tuple[bytes, float]: ...
def simulate(
    block: Block,
    eta: Optional[float] = None,
    pga: Optional[float] = None,
    path: Optional[str] = None,
    accel: Optional[bytes] = None,
    dt: Optional[float] = None,
    record_id: Optional[str] = None,
    history: Optional[int] = None,
) -> Tuple[Dict[str, Any], Optional[bytes]]: ...
def capacities(
    blocks: List[Block],
    paths: List[str],
    arrays: List[Tuple[str, bytes, float]],
    table: bool,
    pair: Optional[str] = None,
    angles: List[float] = ...,
    *,
    levels: int = 200,
    eta_min: float = 1e-3,
    spacing: str = "log",
    tol: float = 1e-4,
) -> Union[bytes, List[Dict[str, Any]]]: ...
def fragility(**kwargs: Any) -> Dict[str, Any]: ...
def risk(**kwargs: Any) -> Union[Dict[str, Any], List[Dict[str, Any]]]: ...
def export(**kwargs: Any) -> Dict[str, Any]: ...
def ims() -> List[Dict[str, Any]]: ...
def run(
    pipeline: str,
    outputs: str,
    force: bool = False,
    from_: Optional[str] = None,
    to: Optional[str] = None,
    threads: Optional[int] = None,
) -> Tuple[List[Dict[str, Any]], str]: ...
def study_dir(pipeline: str, outputs: str) -> str: ...
