#!/usr/bin/env python3
"""A declared dependency that no code uses fails CI (issue 51).

For each workspace member's Cargo.toml, every dependency of [dependencies],
[dev-dependencies] and [build-dependencies] (and their `[target.*.…]` forms) is looked up in
the code that can use it: its name in code is the key with `-` -> `_` (a `package = "…"` rename
keeps the key); the normal and dev dependencies are searched in `src/`, `tests/`, `benches/`,
`examples/` and `build.rs`, the build dependencies in `build.rs`; a normal dependency that
only `tests/`, `benches/` or `examples/` use is reported too (it belongs in
[dev-dependencies]: the library and the binary do not need it). A use is `name::`, `use name`,
`extern crate name`, `name!` (a macro) or the name inside a `#[derive(…)]` / attribute. Comments
do not count. A dev-dependency used only by `src/` (a `#[cfg(test)]` module) counts; a normal
dependency used only by `#[cfg(test)]` modules of `src/` is reported as a dev-dependency.

ALLOWED lists the dependencies kept without a use in code, each with its reason.

Usage: python3 .ci/unused_deps.py [--root DIR]. Exit 1 naming each unused dependency as
`Cargo.toml:line: member declares NAME (section), which no code uses`.
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if "--root" in sys.argv:
    ROOT = Path(sys.argv[sys.argv.index("--root") + 1]).resolve()

# (member package or "*", dependency or "*"): why it is declared without a use in code
ALLOWED = {
    ("*", "geodesic-workspace-hack"):
        "one feature set for every build: its use is being built (workspace-hack/Cargo.toml)",
    ("geodesic-workspace-hack", "*"):
        "it declares the shared dependencies only for their features, its lib.rs is empty",
}

SECTIONS = re.compile(r"^\[(?:target\..+\.)?(dependencies|dev-dependencies|build-dependencies)\]$")


def members():
    text = (ROOT / "Cargo.toml").read_text()
    block = text.split("members = [", 1)[1].split("]", 1)[0]
    return [m.strip().strip('",') for m in block.split() if m.strip().strip('",')]


def declared(manifest):
    """(package, [(line, section, key, name in code)]) of a Cargo.toml."""
    text = manifest.read_text()
    package = re.search(r'^name\s*=\s*"([^"]+)"', text, re.M).group(1)
    out, section = [], None
    for n, line in enumerate(text.splitlines(), 1):
        s = line.split("#", 1)[0].strip()
        if s.startswith("["):
            m = SECTIONS.match(s)
            section = m.group(1) if m else None
            # `[dependencies.name]` tables
            t = re.match(r"^\[(?:target\..+\.)?(dependencies|dev-dependencies|build-dependencies)\.([\w-]+)\]$", s)
            if t:
                out.append((n, t.group(1), t.group(2), t.group(2).replace("-", "_")))
            continue
        if section is None:
            continue
        m = re.match(r"^([A-Za-z0-9_-]+)(\.workspace)?\s*=", s)
        if m:
            out.append((n, section, m.group(1), m.group(1).replace("-", "_")))
    return package, out


def code(path):
    """A Rust file without its comments (string contents kept: a `name::` in a string is rare
    and a macro's path may be built in one)."""
    text = path.read_text(errors="replace")
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return "\n".join(re.sub(r"//.*", "", l) for l in text.splitlines())


CFG_TEST_MOD = re.compile(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+\w+\s*\{")


def without_test_modules(text):
    """`text` (comments removed) without its inline `#[cfg(test)] mod NAME { ... }` blocks,
    matched by counting braces (a brace inside a string literal could end a block early: then
    more code is kept, never less)."""
    out, pos = [], 0
    while (m := CFG_TEST_MOD.search(text, pos)) is not None:
        out.append(text[pos:m.start()])
        depth, i = 1, m.end()
        while i < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[i], 0)
            i += 1
        pos = i
    out.append(text[pos:])
    return "".join(out)


def files(member, section):
    d = ROOT / member
    if section == "build-dependencies":
        return [d / "build.rs"] if (d / "build.rs").is_file() else []
    out = [d / "build.rs"] if (d / "build.rs").is_file() else []
    for sub in ("src", "tests", "benches", "examples"):
        if (d / sub).is_dir():
            out.extend(sorted((d / sub).rglob("*.rs")))
    # a [[bin]] / [[test]] / [[bench]] with a path outside those folders
    for m in re.finditer(r'^path\s*=\s*"([^"]+\.rs)"', (d / "Cargo.toml").read_text(), re.M):
        p = d / m.group(1)
        if p.is_file() and p not in out:
            out.append(p)
    return out


def used(name, texts):
    pat = re.compile(
        rf"(?<![\w:])(?:::)?{name}::|\buse\s+(?:::)?{name}\b|\bextern\s+crate\s+{name}\b"
        rf"|(?<![\w:])(?:::)?{name}!"
        rf"|#\[[^\]]*\b{name}\b")
    return any(pat.search(t) for t in texts)


def main():
    bad = []
    for member in members():
        manifest = ROOT / member / "Cargo.toml"
        package, deps = declared(manifest)
        cache = {}
        for n, section, key, name in deps:
            if {("*", key), (package, key), (package, "*")} & ALLOWED.keys():
                continue
            fs = tuple(files(member, section))
            if fs not in cache:
                cache[fs] = [code(f) for f in fs]
            where = f"{manifest.relative_to(ROOT)}:{n}: {package} declares {key} ({section})"
            if not used(name, cache[fs]):
                bad.append(f"{where}, which no code uses")
            elif section == "dependencies":
                lib = tuple(f for f in fs if not set(f.relative_to(ROOT / member).parts[:1])
                            & {"tests", "benches", "examples"})
                if ("lib", lib) not in cache:
                    cache[("lib", lib)] = [without_test_modules(code(f)) for f in lib]
                if not used(name, cache[("lib", lib)]):
                    bad.append(f"{where}, which only its tests, benches or examples use "
                               "(a dev-dependency)")
    for b in bad:
        print(b)
    print(f"unused dependencies: {len(bad)}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
