#!/usr/bin/env python3
"""The framework's shape, checked (issue 34): the framework crates name no mission, no crate
depends upward, no module cycle, no function over 150 lines, the CLI crate under 2 500
non-test lines.

Usage: python3 .ci/framework.py [--strict-size]
Exit 1 on a named mission, an upward dependency or a module cycle; the function lengths and the
CLI's size are reported, and fail too with --strict-size.
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# crates whose sources must name no mission (LISA Pathfinder is the root mission's; the words
# below are its names and its inputs')
FRAMEWORK = ["verification/core", "verification/report", "verification/verify", "verification/cli"]
MISSION_WORDS = re.compile(r"\b(LISA|Pathfinder|LPF|thesis|budget|capture)\b", re.I)

# layers, bottom first: a crate may depend only on crates of a lower layer (or its own)
LAYERS = [
    {"geodesic-util", "geodesic-workspace-hack"},
    {"geodesic-plot", "geodesic-contact", "geodesic-mechanism", "geodesic-housing",
     "geodesic-facility"},
    {"geodesic-release", "geodesic-capture", "geodesic-charge", "geodesic-core"},
    {"geodesic-fit", "geodesic-report", "geodesic-exchange", "geodesic-images", "geodesic-testrun"},
    {"geodesic-verify"},
    {"geodesic-checks"},
    {"geodesic-missions"},
    {"geodesic", "geodesic-benches", "geodesic-fuzz", "xtask"},
]
FRAMEWORK_CRATES = {"geodesic-util", "geodesic-plot", "geodesic-core", "geodesic-report",
                    "geodesic-verify", "geodesic-exchange", "geodesic-testrun"}
MAX_FN_LINES = 150
MAX_CLI_LINES = 2500


def layer(name):
    for i, l in enumerate(LAYERS):
        if name in l:
            return i
    return None


def members():
    text = (ROOT / "Cargo.toml").read_text()
    block = text.split("members = [", 1)[1].split("]", 1)[0]
    return [m.strip().strip('",') for m in block.split() if m.strip().strip('",')]


def deps(manifest):
    """(package name, [geodesic dependencies]) of a Cargo.toml's [dependencies]."""
    text = manifest.read_text()
    name = re.search(r'^name\s*=\s*"([^"]+)"', text, re.M).group(1)
    out, section = [], None
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("["):
            section = s
            continue
        if section in ("[dependencies]", "[build-dependencies]"):
            m = re.match(r"(geodesic[-\w]*)", s)
            if m:
                out.append(m.group(1))
    return name, out


def rust_files(crate):
    return sorted(p for p in (ROOT / crate / "src").rglob("*.rs"))


def non_test_lines(path):
    n = 0
    for line in path.read_text().splitlines():
        if line.startswith("#[cfg(test)]"):
            break
        n += 1
    return n


def module_of(crate_src, path):
    rel = path.relative_to(crate_src).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return parts[0] if parts else ""


def cycles(crate):
    """Cycles between a crate's top-level modules (`use crate::x` / `crate::x::`)."""
    src = ROOT / crate / "src"
    graph = {}
    for f in rust_files(crate):
        m = module_of(src, f)
        body = f.read_text().split("#[cfg(test)]", 1)[0]
        # code only: doc links (`[`crate::x`]`) and comments are no dependency
        code = "\n".join(l.split("//", 1)[0] for l in body.splitlines())
        for t in set(re.findall(r"\bcrate::(\w+)", code)):
            if m and t != m and ((src / f"{t}.rs").exists() or (src / t / "mod.rs").exists()):
                graph.setdefault(m, set()).add(t)
    # strongly connected components (Tarjan)
    index, low, stack, on, out, i = {}, {}, [], set(), [], [0]

    def strong(v):
        index[v] = low[v] = i[0]
        i[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
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

    for v in list(graph):
        if v not in index:
            strong(v)
    return out


def long_functions():
    """Functions over MAX_FN_LINES lines, from .ci/long_functions.py (a lexer that skips
    comments, strings and character literals)."""
    import subprocess
    out = subprocess.run([sys.executable, str(ROOT / ".ci/long_functions.py"), "--max", str(MAX_FN_LINES)],
                         capture_output=True, text=True).stdout
    return [l for l in out.splitlines() if ": fn " in l]


def main():
    strict = "--strict-size" in sys.argv
    bad = []
    for crate in FRAMEWORK:
        for f in rust_files(crate):
            for n, line in enumerate(f.read_text().splitlines(), 1):
                if MISSION_WORDS.search(line):
                    bad.append(f"{f.relative_to(ROOT)}:{n}: names a mission: {line.strip()[:100]}")
    names = {}
    for m in members():
        name, ds = deps(ROOT / m / "Cargo.toml")
        names[name] = (m, ds)
    for name, (m, ds) in names.items():
        lv = layer(name)
        if lv is None:
            bad.append(f"{m}/Cargo.toml: {name} is in no layer of .ci/framework.py")
            continue
        for d in ds:
            dl = layer(d)
            if dl is None or dl >= lv and d != name and d != "geodesic-workspace-hack":
                bad.append(f"{m}/Cargo.toml: {name} (layer {lv}) depends on {d} (layer {dl}): upward")
            if name in FRAMEWORK_CRATES and d not in FRAMEWORK_CRATES | {"geodesic-workspace-hack"}:
                bad.append(f"{m}/Cargo.toml: framework crate {name} depends on {d}")
    for name, (m, _) in names.items():
        if (ROOT / m / "src").is_dir():
            for c in cycles(m):
                bad.append(f"{m}: module cycle {' -> '.join(c)}")
    # every command's JSON is a typed struct of its library (issue 34): no json! document is
    # built in the CLI or in the missions' commands
    for crate in ["verification/cli", "missions"]:
        for f in rust_files(crate):
            for n, line in enumerate(f.read_text().splitlines(), 1):
                if line.startswith("#[cfg(test)]"):
                    break
                if "json!" in line and not line.lstrip().startswith("//"):
                    bad.append(f"{f.relative_to(ROOT)}:{n}: a JSON document built with json! "
                               "(make it a typed struct in the command's library)")
    sizes = long_functions()
    cli = sum(non_test_lines(f) for f in rust_files("verification/cli"))
    if cli >= MAX_CLI_LINES:
        sizes.append(f"verification/cli: {cli} non-test lines (>= {MAX_CLI_LINES})")
    for b in bad:
        print(b)
    for s in sizes:
        print(("" if strict else "(size) ") + s)
    print(f"framework: {len(bad)} violation(s); {len(sizes)} size finding(s); CLI {cli} non-test lines")
    return 1 if bad or (strict and sizes) else 0


if __name__ == "__main__":
    sys.exit(main())
