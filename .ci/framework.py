#!/usr/bin/env python3
"""The framework's shape, checked (issues 34, 51): the framework crates name no mission (in
their sources, their Cargo.toml descriptions and the paths they embed with include_str! /
include_bytes!), no crate depends upward of the layers drawn in docs/architecture.md, the
generic crates depend on no mission or physics crate, no module cycle, no function over 150
lines, the CLI crate under 2 500 non-test lines.

The mission words are every mission's names read from its mission.yaml (`name`, its
capitalised `title` words) and the words of MISSION_WORDS below; the missions' folders (a
mission.yaml's folder under missions/, the root mission's declared files and folders) are what
a framework crate must not embed.

Usage: python3 .ci/framework.py [--strict-size] [--root DIR]
Exit 1 on a named mission, an upward dependency or a module cycle; the function lengths and the
CLI's size are reported, and fail too with --strict-size. --root checks another copy of the
repository (.ci/guards_test.py mutates one).
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if "--root" in sys.argv:
    ROOT = Path(sys.argv[sys.argv.index("--root") + 1]).resolve()

# crates whose sources, descriptions and embedded paths must name no mission
FRAMEWORK = ["verification/util", "verification/core", "verification/report",
             "verification/verify", "verification/exchange", "verification/testrun",
             "verification/cli"]
# words of the missions beyond their names and titles: the root mission's short names, its
# inputs' and subsystems' names (the GRS, DFACS, the housing), the thesis it reproduces
MISSION_WORDS = ["LISA", "Pathfinder", "LPF", "lpf_", "CubeSat", "DFC", "GRS", "DFACS",
                 "housing", "thesis", "budget", "capture"]

# the generic crates (the framework and the identification engine) depend only on generic
# crates: no mission's checks, no physics model
GENERIC_CRATES = {"geodesic-util", "geodesic-plot", "geodesic-core", "geodesic-report",
                  "geodesic-verify", "geodesic-exchange", "geodesic-testrun", "geodesic-fit",
                  "geodesic-discover", "geodesic-numeric", "geodesic-dataset", "geodesic-codegen"}
# known edges that break a rule, each with its issue: a NEW one fails
KNOWN_EXCEPTIONS = {
    ("geodesic-fit", "geodesic-facility"):
        "issue 51, item 3: the identification engine still takes the facility's scenarios",
    ("geodesic-discover", "geodesic-facility"):
        "issue 51, item 3: diagnose and discover try the facility's effects on its scenarios",
    ("geodesic-dataset", "geodesic-facility"):
        "issue 51, item 3: a record's channels and synthetic records come from the facility's scenarios",
    ("geodesic-codegen", "geodesic-facility"):
        "issue 51, item 3: a new effect's code is written against the facility's Effect traits",
}
# members outside the layers: tools on top (they may use any crate), the feature-set crate
# under everything
TOOLS = {"geodesic-benches", "geodesic-fuzz", "xtask"}
BOTTOM = {"geodesic-workspace-hack"}
MAX_FN_LINES = 150
MAX_CLI_LINES = 2500


def mission_words():
    """MISSION_WORDS and every mission's names: `name` (as written, with `_`, without `-`) and
    the capitalised words of `title`, as one case-insensitive pattern."""
    words = set(MISSION_WORDS)
    for y in [ROOT / "mission.yaml", *sorted((ROOT / "missions").glob("*/mission.yaml"))]:
        if not y.is_file():
            continue
        text = y.read_text()
        name = re.search(r"^name:\s*(\S+)", text, re.M)
        if name:
            n = name.group(1).strip("\"'")
            words |= {n, n.replace("-", "_")}
        title = re.search(r"^title:\s*(.+)$", text, re.M)
        if title:
            for w in re.findall(r"[A-Za-z][\w-]*", title.group(1)):
                if w[0].isupper() and len(w) > 2:
                    words.add(w)
    alts = "|".join(sorted((re.escape(w) for w in words), key=len, reverse=True))
    return re.compile(rf"(?<![A-Za-z0-9])({alts})(?![A-Za-z0-9])", re.I), sorted(words)


def mission_folders():
    """The folders and files that are a mission's: every missions/*/ holding a mission.yaml, and
    the root mission's requirement folder and declared files (inputs, document, dispositions,
    baseline), resolved."""
    out = [y.parent.resolve() for y in (ROOT / "missions").glob("*/mission.yaml")]
    root = ROOT / "mission.yaml"
    if root.is_file():
        out.append(root.resolve())
        for m in re.finditer(r"^\s*(?:-\s*)?(?:requirements|path|document|dispositions|baseline):\s*(\S+)",
                             root.read_text(), re.M):
            out.append((ROOT / m.group(1)).resolve())
    return out


def code_only(text):
    """`text` with comments blanked and string literals kept (the include paths are strings),
    line numbers kept."""
    return "\n".join(re.sub(r"//.*", "", l) for l in text.splitlines())


def embeds(crate):
    """(file, line, path, in a test module) of every include_str!/include_bytes! in a crate's
    sources."""
    for f in rust_files(crate):
        text = f.read_text()
        tests_from = text[: text.find("\n#[cfg(test)]")].count("\n") + 2 if "\n#[cfg(test)]" in text else 10**9
        for n, line in enumerate(code_only(text).splitlines(), 1):
            for m in re.finditer(r"include_(?:str|bytes)!\s*\(\s*(?:concat!\s*\(\s*env!\s*\(\s*\"CARGO_MANIFEST_DIR\"\s*\)\s*,\s*)?\"([^\"]+)\"", line):
                yield f, n, m.group(1), n >= tests_from


def doc_layers():
    """The layers drawn in docs/architecture.md ("## Layers", its code block): {crate folder:
    row}, row 0 the top. A row lists crate folders (`verification/fit  report  exchange`,
    `models/release, capture, charge`) before its description."""
    text = (ROOT / "docs/architecture.md").read_text()
    block = text.split("## Layers", 1)[1].split("```", 2)[1]
    rows, row = {}, -1
    for line in block.splitlines()[1:]:
        left = re.split(r"\s{3,}", line.strip(), maxsplit=1)[0]
        if not left or left == "|":
            continue
        row += 1
        prefix = ""
        for tok in re.findall(r"[\w/.-]+", left.split("(")[0]):
            tok = tok.strip(".,")
            if "/" in tok:
                prefix = tok.rsplit("/", 1)[0] + "/"
            for cand in (tok, prefix + tok):
                if (ROOT / cand / "Cargo.toml").is_file():
                    rows[cand] = row
                    break
    return rows


def members():
    text = (ROOT / "Cargo.toml").read_text()
    block = text.split("members = [", 1)[1].split("]", 1)[0]
    return [m.strip().strip('",') for m in block.split() if m.strip().strip('",')]


def deps(manifest):
    """(package name, [geodesic dependencies]) of a Cargo.toml's [dependencies] and
    [build-dependencies]."""
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
    out = subprocess.run([sys.executable, str(ROOT / ".ci/long_functions.py"), "--max", str(MAX_FN_LINES), str(ROOT)],
                         capture_output=True, text=True).stdout
    return [l for l in out.splitlines() if ": fn " in l]


def main():
    strict = "--strict-size" in sys.argv
    bad = []
    words, _ = mission_words()
    folders = mission_folders()
    for crate in FRAMEWORK:
        for f in rust_files(crate):
            # the code and its documentation; a unit test module's fixtures may quote a
            # requirement ID of this repository
            for n, line in enumerate(f.read_text().split("\n#[cfg(test)]", 1)[0].splitlines(), 1):
                if words.search(line):
                    bad.append(f"{f.relative_to(ROOT)}:{n}: names a mission: {line.strip()[:100]}")
        manifest = ROOT / crate / "Cargo.toml"
        for n, line in enumerate(manifest.read_text().splitlines(), 1):
            if re.match(r"\s*(description|keywords|categories)\s*=", line) and words.search(line):
                bad.append(f"{manifest.relative_to(ROOT)}:{n}: names a mission: {line.strip()[:100]}")
        for f, n, path, in_tests in embeds(crate):
            target = (f.parent / path).resolve()
            inside = [d for d in folders if target == d or d in target.parents]
            if inside or (words.search(path) and not in_tests):
                bad.append(f"{f.relative_to(ROOT)}:{n}: embeds a mission's file: {path}")
    names = {}
    for m in members():
        name, ds = deps(ROOT / m / "Cargo.toml")
        names[name] = (m, ds)
    # every framework and generic crate documents its public surface (issue 51, item 4):
    # `#![warn(missing_docs)]` at its root, which CI's clippy -D warnings turns into an error
    for name, (m, _) in sorted(names.items()):
        if name not in GENERIC_CRATES and m not in FRAMEWORK:
            continue
        roots = [ROOT / m / "src" / f for f in ("lib.rs", "main.rs") if (ROOT / m / "src" / f).is_file()]
        for r in roots:
            if not re.search(r"^#!\[(warn|deny)\(missing_docs\)\]", r.read_text(), re.M):
                bad.append(f"{r.relative_to(ROOT)}: no #![warn(missing_docs)] at the crate's root")
    rows = doc_layers()
    row_of = {name: rows.get(m) for name, (m, _) in names.items()}
    for name, (m, ds) in names.items():
        if name in TOOLS | BOTTOM:
            continue
        if row_of[name] is None:
            bad.append(f"{m}/Cargo.toml: {name} is in no layer of docs/architecture.md")
            continue
        for d in ds:
            if d == name or d in BOTTOM:
                continue
            known = KNOWN_EXCEPTIONS.get((name, d))
            if row_of.get(d) is None or row_of[d] <= row_of[name]:
                if not known:
                    bad.append(f"{m}/Cargo.toml: {name} depends on {d}, not drawn below it in "
                               "docs/architecture.md: upward")
            if name in GENERIC_CRATES and d not in GENERIC_CRATES and not known:
                bad.append(f"{m}/Cargo.toml: generic crate {name} depends on {d}")
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
    for (a, b), why in sorted(KNOWN_EXCEPTIONS.items()):
        if b in names.get(a, (None, []))[1]:
            print(f"(known exception) {a} -> {b}: {why}")
    print(f"framework: {len(bad)} violation(s); {len(sizes)} size finding(s); CLI {cli} non-test lines")
    return 1 if bad or (strict and sizes) else 0


if __name__ == "__main__":
    sys.exit(main())
