"""Floor motions of a small nonlinear building, written as OpenSees writes
them (tests/engines.rs).

Usage: python opensees_floors.py OUTDIR PGA_G RECORD.AT2 [RECORD.AT2 ...]

The building: three storeys, a shear building in one horizontal direction
(OpenSees `model basic -ndm 1 -ndf 1`): node 0 the ground (fixed), nodes
1-3 the floors, each of mass 100 t; each storey a bilinear spring (a
`truss` of unit length and area over `Steel01`: initial stiffness 79,800
kN/m, yield force 800 kN, post-yield stiffness 5 % of it), so the first
period is 0.50 s and a storey yields at a drift of 1.0 cm (a base shear of
0.27 of the weight). Rayleigh damping of 5 % on the first two modes.
Each ground record (AT2, g) is scaled to a PGA of PGA_G and applied as a
uniform excitation (`timeSeries Path` with the factor g = 9.80665 m/s²,
interpolated linearly between its samples); Newmark's average
acceleration at the record's step. A `Node` recorder with `-timeSeries`
and `-time` writes each floor's absolute acceleration (m/s²) to
OUTDIR/<record>.out: time, floor 1, floor 2, floor 3. Prints one JSON
object: {"periods": [...], "records": {id: {"scale": s, "peak_drift_m":
[...], "yielded": bool}}}.
"""
import json
import math
import os
import sys

import openseespy.opensees as ops

G = 9.80665
MASS, K, FY, B = 100.0, 79_800.0, 800.0, 0.05


def read_at2(path):
    with open(path) as f:
        lines = f.read().splitlines()
    head = lines[3].upper().replace(",", " ")
    tokens = head.split()
    npts = int(tokens[tokens.index("NPTS=") + 1]) if "NPTS=" in tokens else int(tokens[0])
    dt = float(tokens[tokens.index("DT=") + 1]) if "DT=" in tokens else float(tokens[1])
    values = [float(v.replace("D", "E")) for line in lines[4:] for v in line.split()]
    assert len(values) == npts, path
    return values, dt


def building():
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    for k in range(4):
        ops.node(k, float(k))
        if k > 0:
            ops.mass(k, MASS)
    ops.fix(0, 1)
    ops.uniaxialMaterial("Steel01", 1, FY, K, B)
    for k in range(1, 4):
        ops.element("truss", k, k - 1, k, 1.0, 1)
    w2 = ops.eigen("-fullGenLapack", 2)
    w = [math.sqrt(x) for x in w2]
    zeta = 0.05
    a0 = zeta * 2 * w[0] * w[1] / (w[0] + w[1])
    a1 = zeta * 2 / (w[0] + w[1])
    ops.rayleigh(a0, 0.0, 0.0, a1)
    return [2 * math.pi / x for x in w]


def run(path, out_dir, pga_g):
    rid = os.path.splitext(os.path.basename(path))[0]
    accel, dt = read_at2(path)
    scale = pga_g / max(abs(a) for a in accel)
    periods = building()
    ops.timeSeries("Path", 1, "-dt", dt, "-values", *accel, "-factor", G * scale)
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    out = os.path.join(out_dir, rid + ".out")
    ops.recorder("Node", "-file", out, "-precision", 10, "-timeSeries", 1, "-time", "-node", 1, 2, 3, "-dof", 1, "accel")
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    drift = [0.0, 0.0, 0.0]
    for _ in range(len(accel)):
        if ops.analyze(1, dt) != 0:
            raise SystemExit(f"{rid}: the analysis did not converge")
        u = [0.0] + [ops.nodeDisp(k, 1) for k in range(1, 4)]
        for k in range(3):
            drift[k] = max(drift[k], abs(u[k + 1] - u[k]))
    ops.remove("recorders")
    return periods, rid, {
        "scale": scale,
        "peak_drift_m": drift,
        "yielded": max(drift) > FY / K,
    }


def main():
    out_dir, pga_g, records = sys.argv[1], float(sys.argv[2]), sys.argv[3:]
    os.makedirs(out_dir, exist_ok=True)
    result = {"records": {}}
    for path in records:
        periods, rid, info = run(path, out_dir, pga_g)
        result["periods"] = periods
        result["records"][rid] = info
    print(json.dumps(result))


main()
