"""A plain numba loop of the exact linearised stepper, against the package.

What a Python user would write without `rocking`: the closed-form step of
the linearised equation over each sample interval (docs/MODEL.md §3.1),
turning points from the quadratic in δ = e^z − 1 (§3.2), impacts and
overturning by bisection on the monotone pieces, rest below 1e-9·p, the
fate after the record from energy (§3.4), and the capacity search of
`rocking capacity` (200 log levels from η = 1 to 1e-3, first overturning,
bisection to Δη = 1e-4), uncertified. It times the 44 far-field records at
one block against `rocking.capacities` and `rocking capacity`, and counts
the capacities that agree within the search's tolerance.

    pip install ./python numba
    python python/bench/exact_numba.py      # from the repository root
"""

import math
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numba
import numpy as np

import rocking

ROOT = Path(__file__).resolve().parents[2]
FAR = ROOT / "records" / "fema-p695" / "far-field"
P, EPS = 2.0, 0.7
REST = 1e-9


@numba.njit(cache=False)
def _c_s(z):
    """C(z) = cosh z − 1 and S(z) − 1 = sinh z / z − 1, by series for small z."""
    if abs(z) < 1e-3:
        z2 = z * z
        return z2 / 2 * (1 + z2 / 12), z2 / 6 * (1 + z2 / 20)
    return math.cosh(z) - 1.0, math.sinh(z) / z - 1.0


@numba.njit(cache=False)
def _state(xa, va, u, g1e, p, sig):
    z = p * sig
    c, s1 = _c_s(z)
    x = xa + u * c + va * sig * (s1 + 1.0) + g1e * sig * s1
    v = va + p * u * math.sinh(z) + (va + g1e) * c
    return x, v


@numba.njit(cache=False)
def _bisect(xa, va, u, g1e, p, s, lo, hi, level):
    """σ in [lo, hi] where s·x crosses `level` (s·x − level changes sign)."""
    flo = s * _state(xa, va, u, g1e, p, lo)[0] - level
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        fm = s * _state(xa, va, u, g1e, p, mid)[0] - level
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return hi


@numba.njit(cache=False)
def run(psi, dt, p, eps, eta):
    """True if the block overturns under psi scaled to eta."""
    n = psi.shape[0]
    x, v, s, rest = 0.0, 0.0, 1.0, True
    vrest = REST * p
    for k in range(n - 1):
        g0, g1 = psi[k], (psi[k + 1] - psi[k]) / dt
        t = 0.0
        events = 0
        while t < dt:
            ga = g0 + g1 * t
            if rest:
                # Uplift where |ψ| first exceeds η in [t, dt].
                gb = psi[k + 1]
                if abs(ga) > eta:
                    s = 1.0 if ga > 0 else -1.0
                    rest = False
                    continue
                if abs(gb) <= eta:
                    break
                target = eta if gb > 0 else -eta
                t = (target - g0) / g1
                s = 1.0 if gb > 0 else -1.0
                x, v, rest = 0.0, 0.0, False
                # Start just past the threshold (the next pass sees |ψ| > η).
                if t >= dt:
                    break
                continue
            u = x - s + ga / eta
            g1e = g1 / eta
            length = dt - t
            # Turning points: A δ² + 2B δ + 2v = 0, δ in (0, e^{p·len} − 1).
            b = p * u + v
            a = b + g1e
            dmax = math.expm1(p * length)
            cuts = [0.0]
            if a != 0.0:
                disc = b * b - 2.0 * a * v
                if disc >= 0.0:
                    r = math.sqrt(disc)
                    for d in ((-b - r) / a, (-b + r) / a):
                        if 0.0 < d < dmax:
                            cuts.append(math.log1p(d) / p)
            elif b != 0.0:
                d = -v / b
                if 0.0 < d < dmax:
                    cuts.append(math.log1p(d) / p)
            cuts.sort()
            cuts.append(length)
            hit = -1.0
            kind = 0
            for j in range(len(cuts) - 1):
                lo, hi = cuts[j], cuts[j + 1]
                xe = _state(x, v, u, g1e, p, hi)[0]
                if s * xe >= 1.0:
                    return True
                if s * xe <= 0.0 and hi > 0.0:
                    hit = _bisect(x, v, u, g1e, p, s, lo, hi, 0.0)
                    kind = 1
                    break
            if kind == 0:
                x, v = _state(x, v, u, g1e, p, length)
                break
            xi, vi = _state(x, v, u, g1e, p, hit)
            t += hit
            v = eps * vi
            x = 0.0
            s = -s
            events += 1
            if abs(v) < vrest or events > 100000:
                rest, x, v = True, 0.0, 0.0
    if rest:
        return False
    # After the record: free rocking, decided from energy.
    y = s * x - 1.0
    w = s * v / p
    if w > 0:
        if w >= -y:
            return True
        e = 0.5 * w * w - 0.5 * y * y
        v0 = math.sqrt(max(1.0 + 2.0 * e, 0.0))
        return eps * v0 >= 1.0
    v0 = math.sqrt(w * w + 1.0 - y * y)
    return eps * v0 >= 1.0


@numba.njit(cache=False)
def capacity(psi, dt, p, eps, levels, tol):
    survived = 1.0
    for eta in levels:
        if run(psi, dt, p, eps, eta):
            lo, hi = eta, survived
            while hi - lo > tol:
                mid = 0.5 * (lo + hi)
                if run(psi, dt, p, eps, mid):
                    lo = mid
                else:
                    hi = mid
            return lo
        survived = eta
    return -1.0


def main():
    files = sorted(FAR.glob("*.AT2"))
    recs = []
    for f in files:
        a, dt = rocking.read_at2(f)
        recs.append((a / np.max(np.abs(a)), dt))
    levels = np.array([1e-3 ** (j / 200) for j in range(1, 201)])
    levels[-1] = 1e-3
    capacity(recs[0][0], recs[0][1], P, EPS, levels, 1e-4)  # compile

    def numba_all():
        return [capacity(a, dt, P, EPS, levels, 1e-4) for a, dt in recs]

    def timed(f, n=5):
        xs = []
        for _ in range(n):
            s = time.perf_counter()
            out = f()
            xs.append(time.perf_counter() - s)
        return statistics.median(xs), out

    t_numba, ours = timed(numba_all)
    t_py, table = timed(lambda: rocking.capacities(FAR, [dict(p=P, eps=EPS)]))
    binary = ROOT / "target" / "release" / "rocking"
    t_cli, _ = timed(lambda: subprocess.run(
        [str(binary), "capacity", "--record", str(FAR), "--p", str(P), "--eps", str(EPS), "--json"],
        capture_output=True, check=True))
    theirs = [c if c is not None else -1.0 for c in table["eta_c"].to_list()]
    agree = sum(1 for a, b in zip(ours, theirs) if abs(a - b) <= 2e-4)
    print(f"44 far-field records, p = {P}, eps = {EPS}, linearised, 2 threads for rocking")
    print(f"rocking.capacities (certified)   {t_py * 1e3:8.1f} ms")
    print(f"rocking capacity (CLI batch)     {t_cli * 1e3:8.1f} ms")
    print(f"numba loop, 1 thread, uncertified {t_numba * 1e3:8.1f} ms")
    print(f"capacities agreeing within 2 tol: {agree}/{len(ours)}")
    for f, a, b in zip(files, ours, theirs):
        if abs(a - b) > 2e-4:
            print(f"  {f.stem}: numba {a:.6f}, rocking {b:.6f}")


if __name__ == "__main__":
    sys.exit(main())
