#!/usr/bin/env python3
"""Checks the shape of the house: no source file over LIMIT_FILE lines of
non-test code, no function over LIMIT_FN lines, no import circle between
files of a crate. It reads every crate of the repository whose sources
are Rust: the library (`src/`, without the binary), the binary
(`src/bin/rocking/`), the Python binding (`python/src/`) and the
benchmark harness (`bench/src/`). A file or function may be longer when
a comment says why: `// house: <reason>` among a file's first 20 lines,
or on the lines just above a function's signature (its doc comment and
attributes may stand between). Every such exemption is counted and
printed, and more than EXEMPTION_BUDGET of them fail the check.
Standard library only; run from the repository's root.

Non-test code is every line but the items under `#[cfg(test)]`, wherever
they stand (a test module in the middle of a file counts as test code,
and the code after it as non-test). Imports are read from `use crate::…`,
`use super::…` and paths written inline (`crate::a::b::c`); each imported
name is followed to the file that defines it, through `pub use`
re-exports. A `pub use` is itself an arrow from the re-exporting file to
the file it names: a `mod.rs` that only re-exports its children (and
defines nothing they use) ties nothing in a loop, while a `mod.rs` that
re-exports a child which imports a definition of that `mod.rs` is a
circle.
"""

import re
import sys
from pathlib import Path

LIMIT_FILE = 600
LIMIT_FN = 100
EXEMPTION_BUDGET = 3
# Each crate: its root folder, and the folders under it that are other crates.
CRATES = [
    (Path("src"), ("bin",)),
    (Path("src/bin/rocking"), ()),
    (Path("python/src"), ()),
    (Path("bench/src"), ()),
]
SRC = Path("src")

FN = re.compile(r"^(\s*)(?:pub(?:\([^)]*\))?\s+)?(?:const\s+)?(?:unsafe\s+)?(?:extern\s+\"C\"\s+)?fn\s+(\w+)")
DEF = re.compile(
    r"^\s*(?:pub(?:\([^)]*\))?\s+)?(?:const\s+|unsafe\s+)*"
    r"(?:fn|struct|enum|trait|type|const|static|union|macro_rules!)\s*(\w+)"
)
MACRO_EXPORT = re.compile(r"macro_rules!\s*(\w+)")


def strip_strings_and_comments(line: str) -> str:
    """The line without string literals, char literals and a trailing `//` comment."""
    line = re.sub(r'"(?:\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(?:\\.|[^'\\])'", "' '", line)
    return line.split("//")[0]


def non_test_lines(text: str) -> list[str]:
    """The lines of `text` without the items under `#[cfg(test)]` (the
    attribute, any attributes after it, and the item to its closing brace
    or semicolon), wherever they stand."""
    lines = text.split("\n")
    out, i = [], 0
    while i < len(lines):
        if lines[i].strip() != "#[cfg(test)]":
            out.append(lines[i])
            i += 1
            continue
        i += 1
        while i < len(lines) and lines[i].strip().startswith("#["):
            i += 1
        depth, opened = 0, False
        while i < len(lines):
            code = strip_strings_and_comments(lines[i])
            i += 1
            if not opened and ";" in code and "{" not in code:
                break
            for ch in code:
                if ch == "{":
                    depth += 1
                    opened = True
                elif ch == "}":
                    depth -= 1
            if opened and depth <= 0:
                break
    return out


def module_of(root: Path, path: Path) -> tuple[str, ...]:
    """`src/physics/exact/mod.rs` → ("physics", "exact"); `src/lib.rs` → ()."""
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts.pop()
    return tuple(parts)


def reason_above(lines: list[str], i: int) -> bool:
    j = i - 1
    while j >= 0 and (lines[j].strip().startswith(("///", "#[", "//")) or not lines[j].strip()):
        if "house:" in lines[j]:
            return True
        j -= 1
    return False


def long_functions(path: Path, lines: list[str]) -> tuple[list[str], list[str]]:
    """Functions over LIMIT_FN lines without a reason, and those with one."""
    out, exempt = [], []
    for i, line in enumerate(lines):
        m = FN.match(line)
        if not m:
            continue
        depth, opened, end = 0, False, None
        for k in range(i, len(lines)):
            code = strip_strings_and_comments(lines[k])
            if not opened and ";" in code and "{" not in code:
                break  # a declaration in a trait, no body
            for ch in code:
                if ch == "{":
                    depth += 1
                    opened = True
                elif ch == "}":
                    depth -= 1
            if opened and depth <= 0:
                end = k
                break
        if end is None:
            continue
        n = end - i + 1
        if n <= LIMIT_FN:
            continue
        where = f"{path}:{i + 1}: fn {m.group(2)} is {n} lines"
        if reason_above(lines, i):
            exempt.append(where)
        else:
            out.append(f"{where} (over {LIMIT_FN}, no `// house:` reason)")
    return out, exempt


def crate_files(root: Path, others: tuple[str, ...]) -> list[Path]:
    """The crate's source files: under `root`, but not under its sub-crates."""
    return [
        path
        for path in sorted(root.rglob("*.rs"))
        if not any(part in others for part in path.relative_to(root).parts[:-1])
    ]


def read_sources(root: Path, paths: list[Path]) -> dict[tuple[str, ...], tuple[Path, str]]:
    files = {}
    for path in paths:
        code = [strip_strings_and_comments(line) for line in non_test_lines(path.read_text())]
        files[module_of(root, path)] = (path, "\n".join(code))
    return files


def definitions(files):
    """Module → names it defines, and module → {name: module it re-exports from}."""
    defined, reexports = {}, {}
    for module, (_, text) in files.items():
        names = set()
        for line in text.split("\n"):
            m = DEF.match(line)
            if m:
                names.add(m.group(1))
            m = MACRO_EXPORT.search(line)
            if m:
                names.add(m.group(1))
            if re.match(r"^\s*(?:pub\s+)?mod\s+(\w+)\s*;", line):
                names.add(re.match(r"^\s*(?:pub\s+)?mod\s+(\w+)", line).group(1))
        defined[module] = names
        re_map = {}
        for m in re.finditer(r"pub(?:\([^)]*\))?\s+use\s+([^;]+);", text):
            for target, name in expand_use(module, m.group(1)):
                re_map[name] = target
        reexports[module] = re_map
    return defined, reexports


def expand_use(module, tree: str):
    """`self::a::{b, c as d}` in `module` → [(("…","a","b"), "b"), (…, "d")]."""
    tree = re.sub(r"\s+", "", tree)

    def walk(prefix, t):
        if t.startswith("{") and t.endswith("}"):
            depth, start, parts = 0, 1, []
            for i, ch in enumerate(t):
                if ch == "{":
                    depth += 1
                elif ch == "}":
                    depth -= 1
                elif ch == "," and depth == 1:
                    parts.append(t[start:i])
                    start = i + 1
            parts.append(t[start:-1])
            for p in parts:
                if p:
                    yield from walk(prefix, p)
            return
        head, sep, rest = t.partition("::")
        if sep and not head.startswith("{"):
            yield from walk(prefix + [head], rest)
            return
        if t == "self":
            yield tuple(prefix), prefix[-1] if prefix else ""
            return
        name, _, alias = t.partition("as")
        yield tuple(prefix + [name]), alias or name

    for path, name in walk([], tree):
        yield absolute(module, path), name


def absolute(module, path):
    path = list(path)
    if not path:
        return ()
    if path[0] == "crate":
        return tuple(path[1:])
    base = list(module)
    if path[0] == "self":
        return tuple(base + path[1:])
    while path and path[0] == "super":
        base = base[:-1]
        path = path[1:]
    if path and path[0] in ("std", "core", "alloc"):
        return ()
    if base == list(module) and path and (tuple(base + [path[0]]) not in MODULES):
        return ()  # an external crate's path
    return tuple(base + path)


MODULES = set()


def defining_file(full, defined, reexports, seen=0):
    """The module that defines the item at `full` (a path of module names then an item)."""
    for cut in range(len(full), 0, -1):
        module = full[:cut]
        if module in MODULES:
            rest = full[cut:]
            if not rest:
                return module
            name = rest[0]
            if name in defined[module]:
                return module
            target = reexports[module].get(name)
            if target and seen < 8:
                return defining_file(target + tuple(rest[1:]) if target[-1] != name else target + tuple(rest[1:]),
                                     defined, reexports, seen + 1) or module
            return module
    return None


def circles(files):
    defined, reexports = definitions(files)
    edges = {m: set() for m in files}
    for module, (_, text) in files.items():
        targets = []
        for m in re.finditer(r"\buse\s+([^;]+);", text):
            # External crates' paths resolve to nothing (`absolute`).
            targets += [t for t, _ in expand_use(module, m.group(1).strip())]
        # Paths written inline, outside `use` items and `pub(in …)`.
        inline = re.sub(r"\buse\s+[^;]+;", "", text)
        inline = re.sub(r"pub\(in\s+[^)]*\)", "pub", inline)
        for m in re.finditer(r"\b((?:crate|super)(?:::\w+)+)", inline):
            targets.append(absolute(module, m.group(1).split("::")))
        for t in targets:
            if not t:
                continue
            d = defining_file(t, defined, reexports)
            if d is not None and d != module and d != ():
                edges[module].add(d)
    # Tarjan's strongly connected components.
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def strong(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in edges:
        if v not in index:
            strong(v)
    return [[str(files[m][0]) for m in comp] for comp in out]


def main() -> int:
    problems, exemptions, counted = [], [], 0
    for root, others in CRATES:
        if not root.is_dir():
            continue
        paths = crate_files(root, others)
        counted += len(paths)
        files = read_sources(root, paths)
        MODULES.clear()
        MODULES.update(files)
        for path in paths:
            lines = non_test_lines(path.read_text())
            n = len(lines)
            if n > LIMIT_FILE:
                where = f"{path}: {n} non-test lines"
                if any("house:" in line for line in lines[:20]):
                    exemptions.append(where)
                else:
                    problems.append(f"{where} (over {LIMIT_FILE}, no `// house:` reason)")
            long, exempt = long_functions(path, lines)
            problems += long
            exemptions += exempt
        for comp in circles(files):
            problems.append("import circle: " + " ↔ ".join(comp))
    for e in exemptions:
        print(f"exempt: {e}")
    if len(exemptions) > EXEMPTION_BUDGET:
        problems.append(f"{len(exemptions)} exemptions, over the budget of {EXEMPTION_BUDGET}")
    for p in problems:
        print(p)
    print(f"house: {counted} files in {len(CRATES)} crates; {len(exemptions)} exemptions; {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
