"""The compiled half of ``rocking`` (PyO3): JSON in, JSON out; see ``rocking``."""

from typing import List, Optional, Sequence, Tuple

Mode = Tuple[float, float, float]

def version() -> str: ...
def read_at2(path: str) -> Tuple[bytes, float]: ...
def simulate(
    block_json: str,
    eta: Optional[float] = None,
    pga: Optional[float] = None,
    path: Optional[str] = None,
    accel: Optional[bytes] = None,
    dt: Optional[float] = None,
    record_id: Optional[str] = None,
    floor: Optional[Sequence[Mode]] = None,
) -> str: ...
def capacities(
    blocks_json: List[str],
    paths: List[str],
    arrays: List[Tuple[str, bytes, float]],
    levels: int,
    eta_min: float,
    spacing: str,
    tol: float,
    floor: Optional[Sequence[Mode]] = None,
) -> str: ...
def fragility(
    b: float,
    h: float,
    eps: str,
    im_name: str,
    levels: List[float],
    from_: str,
    outputs: str,
    records: Optional[str],
    direct: bool,
    auto_tol: float,
    floor: Optional[Sequence[Mode]] = None,
    mu: Optional[float] = None,
    states: Optional[str] = None,
    method: str = "fractile",
) -> str: ...
def risk(
    hazard: str,
    b: Optional[float],
    h: Optional[float],
    eps: str,
    inventory: Optional[str],
    site: Optional[int],
    im_name: Optional[str],
    from_: str,
    outputs: str,
    records: Optional[str],
    direct: bool,
    years: float,
    beyond: str,
    auto_tol: float,
    floor: Optional[Sequence[Mode]] = None,
    mu: Optional[float] = None,
    states: Optional[str] = None,
    method: str = "fractile",
) -> str: ...
def run(pipeline: str, outputs: str, force: bool = False) -> Tuple[str, str]: ...
def study_dir(pipeline: str, outputs: str) -> str: ...
