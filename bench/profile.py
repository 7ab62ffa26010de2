#!/usr/bin/env python3
"""Where a certified search spends its time.

Samples `rocking-bench --sections floor` (the 12 far-field records, p = 2,
ε = 0.7) with `perf record -e cpu-clock` and attributes each sample in the
exact stepper's event loop to what it was doing, by the innermost named
frame of its inlined call chain (`addr2line -i`): the event walk (impacts
located by Newton, hops solved in closed form, turning points, the rest of
the walk), whole intervals crossed on a proof (two runs in step, or one
alone), and the quiet of a block at rest. Prints a Markdown table.

The event loop is compiled into one function per stepper and CPU dispatch
(`dispatch::drive_v4`, `dispatch::drive_pair_v4`, or v3's), everything inlined, so a
profile by symbol says nothing; by inlined frame it does. Needs `perf`,
`nm` and `addr2line` (Debian's linux-perf and binutils) and a release build
with debug info (the workspace's release profile has it):

    cargo build --release -p rocking-bench
    python3 bench/profile.py            # from the repository root

Any other command of a binary built so can be sampled in its place, the
nonlinear paper grid's sweep (the Taylor stepper) for instance:

    python3 bench/profile.py --binary target/release/rocking -- \
        target/release/rocking run pipelines/paper-alpha-0.2.toml --to sweep --force

Samples are wall-clock ticks of one process: run it on a quiet machine.
"""

import argparse
import collections
import os
import subprocess
import sys
import tempfile

# The event loop's compilations, by the name `perf` gives their symbol.
LOOPS = tuple(
    f"{loop}_{isa}" for loop in ("drive", "drive_pair", "drive_lanes") for isa in ("v3", "v4")
)

# Innermost frame → what the sample was doing; the first name found in the
# chain, innermost first, decides.
KINDS = [
    ("locate", "walk: impact located (Newton)"),
    ("first_guess", "walk: impact located (Newton)"),
    ("close_bracket", "walk: impact located (Newton)"),
    ("hop_return", "walk: hop in closed form"),
    ("hop", "walk: hop in closed form"),
    ("turning_points", "walk: turning points"),
    ("low_hop", "walk: hop in closed form"),
    ("rock", "walk: the rest of it"),
    ("cruise_pair", "cruise: two runs in step"),
    ("cruise_lanes", "cruise: runs in lanes"),
    ("quiet_until", "quiet: at rest"),
    ("interval", "walk: the rest of it"),
    ("cruise", "cruise: one run"),
    ("after_record", "after the record"),
]


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw).stdout


def loop_symbols(binary):
    """(start, size) of each compilation of the event loop in `binary`."""
    out = []
    for line in run(["nm", "-S", "-C", binary]).splitlines():
        parts = line.split(None, 3)
        if len(parts) == 4 and parts[3].rsplit("::", 1)[-1] in LOOPS:
            out.append((int(parts[0], 16), int(parts[1], 16)))
    return out


def samples(data):
    """(runtime address, its symbol's runtime start) → samples, for samples
    in the event loop; the number of samples in all; the others by the last
    part of their symbol's name."""
    counts, outside = collections.Counter(), collections.Counter()
    total = 0
    for line in run(["perf", "script", "-i", data, "-F", "ip,sym,symoff"]).splitlines():
        parts = line.strip().split(None, 1)
        if len(parts) < 2:
            continue
        total += 1
        name, _, off = parts[1].rpartition("+0x")
        if name and name.rsplit("::", 1)[-1] in LOOPS:
            ip = int(parts[0], 16)
            counts[(ip, ip - int(off, 16))] += 1
        else:
            outside[short(name or parts[1])] += 1
    return counts, total, outside


def short(symbol):
    """A symbol's function path without generic arguments, its last two
    parts: `poly::root_to`, and `Exact::bare_pass` for `…::<impl …::Exact>::
    bare_pass` or `<…::Exact>::bare_pass` (a bracket that opens the path or
    follows `::` names a type; one after a name holds its generic arguments)."""
    depth, plain, group = 0, [], []
    for ch in symbol:
        if ch == "<":
            depth += 1
            if depth == 1:
                group = []
                names_type = not plain or "".join(plain).endswith("::")
            continue
        if ch == ">" and depth > 0:
            depth -= 1
            if depth == 0 and names_type:
                ty = "".join(group)
                ty = ty.split(" for ")[-1] if ty.startswith("impl ") else ty
                ty = ty.removeprefix("impl ").split(" as ")[0]
                plain.append(ty.split("::")[-1])
            continue
        if depth == 0:
            plain.append(ch)
        elif depth == 1:
            group.append(ch)
    path = "".join(plain).replace("::::", "::").strip()
    return "::".join((path or symbol).split("::")[-2:])


def frames(binary, addrs):
    """Address → innermost-first names of its inlined frames."""
    out = run(["addr2line", "-e", binary, "-i", "-f", "-C", "-a"] + [hex(a) for a in addrs])
    chains, cur, lines, i = {}, None, out.splitlines(), 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("0x"):
            cur = int(line, 16)
            chains[cur] = []
            i += 1
            continue
        # A function's name, then its file and line.
        chains[cur].append(line.split("<")[0].rsplit("::", 1)[-1])
        i += 2
    return chains


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bench", default="target/release/rocking-bench")
    ap.add_argument("--reps", type=int, default=60, help="passes of the floor section")
    ap.add_argument("--binary", help="the binary the command after `--` runs "
                    "(default: the floor section of --bench)")
    ap.add_argument("command", nargs="*", help="a command to sample instead, after `--`")
    args = ap.parse_args()
    binary = args.binary or args.bench
    if not os.path.exists(binary):
        sys.exit(f"{binary} not found: cargo build --release (-p rocking-bench)")
    if args.command and not args.binary:
        sys.exit("a command needs --binary, the binary whose symbols it runs")
    with tempfile.TemporaryDirectory() as tmp:
        data = os.path.join(tmp, "perf.data")
        command = args.command or [args.bench, "--sections", "floor", "--reps",
                                   str(args.reps), "--out-dir", tmp]
        run(["perf", "record", "-q", "-e", "cpu-clock", "-o", data] + command)
        counts, total, outside = samples(data)
    # The load bias (runtime address − the binary's): the one offset, page
    # aligned, that puts every sample's symbol on a compilation of the loop.
    starts = loop_symbols(binary)
    biases = collections.Counter()
    for (_, start), c in counts.items():
        for s, _ in starts:
            if (start - s) % 0x1000 == 0:
                biases[start - s] += c
    if not biases:
        sys.exit("no sample in the event loop: is the binary the one sampled?")
    bias = biases.most_common(1)[0][0]
    by_addr = collections.Counter()
    for (ip, _), c in counts.items():
        by_addr[ip - bias] += c
    chains = frames(binary, sorted(by_addr))
    kinds = collections.Counter()
    for a, c in by_addr.items():
        names = chains.get(a, [])
        kind = next((k for n, k in KINDS if n in names), "the loop itself (runs' setup, bookkeeping)")
        kinds[kind] += c
    in_loop = sum(kinds.values())
    print(f"{total} samples, {in_loop} ({100 * in_loop / total:.0f} %) in the event loop\n")
    print("| what | share of the event loop's samples |\n|---|---:|")
    for kind, c in sorted(kinds.items(), key=lambda kc: -kc[1]):
        print(f"| {kind} | {100 * c / in_loop:.1f} % |")
    walk = sum(c for k, c in kinds.items() if k.startswith("walk"))
    cruise = sum(c for k, c in kinds.items() if k.startswith("cruise"))
    print(f"| **the event walk** | **{100 * walk / in_loop:.1f} %** |")
    print(f"| **whole intervals crossed on a proof** | **{100 * cruise / in_loop:.1f} %** |")
    print(f"\nOutside the event loop, the largest shares of all {total} samples:\n")
    print("| symbol | share of all samples |\n|---|---:|")
    for name, c in outside.most_common(6):
        print(f"| `{name}` | {100 * c / total:.1f} % |")


if __name__ == "__main__":
    main()
