#!/usr/bin/env python3
"""Each guard rail proven by a mutation (issue 51): a copy of the files the guards read (the
Rust sources, the manifests, the missions' descriptors, docs/architecture.md, .ci/*.py) in a
temporary folder, checked clean first, then mutated one way at a time; each guard must exit
non-zero naming what was planted:

- .ci/framework.py: a mission's name in a framework crate's code (a word of a mission.yaml's
  title), in a framework crate's Cargo.toml description, a framework crate embedding a
  mission's file (include_str! of the root mission's requirement folder), and a new upward
  dependency (a generic crate on a mission's checks), a module cycle inside a crate (the only
  check of the module graphs), a framework crate without `#![warn(missing_docs)]`;
- .ci/unused_deps.py: a declared dependency no code uses, and one only the tests use;
- .ci/sizes.py --check: a size typed by hand in docs/architecture.md.

Usage: python3 .ci/guards_test.py. Exit 1 on the first guard that misses its mutation.
"""
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def copy_tree(dst):
    files = subprocess.run(
        ["git", "ls-files", "-co", "--exclude-standard", "*.rs", "*Cargo.toml", "mission.yaml",
         "*/mission.yaml", "docs/architecture.md", ".ci/*.py"],
        cwd=REPO, capture_output=True, text=True, check=True).stdout.split()
    for f in files:
        if not (REPO / f).is_file():
            continue
        (dst / f).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(REPO / f, dst / f)


def guard(root, script, *args):
    p = subprocess.run([sys.executable, str(root / ".ci" / script), *args, "--root", str(root)],
                       capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


def edit(path, old, new):
    text = path.read_text()
    assert old in text, f"{path}: {old!r} not found"
    path.write_text(text.replace(old, new, 1))


def mutation(name, root, files, change, script, args, expect):
    """Applies `change`, runs the guard, restores `files`; fails unless the guard exits non-zero
    and prints every string of `expect`."""
    saved = {f: (root / f).read_text() for f in files}
    try:
        change(root)
        code, out = guard(root, script, *args)
    finally:
        for f, t in saved.items():
            (root / f).write_text(t)
    missing = [e for e in expect if e not in out]
    if code == 0 or missing:
        print(f"guards: FAIL {name}: {script} exit {code}, missing {missing}\n{out}")
        return False
    line = next((l for l in out.splitlines() if all(e in l for e in expect[:1])), out.strip()[:120])
    print(f"guards: ok   {name}: {script} exit {code}: {line.strip()[:150]}")
    return True


def main():
    with tempfile.TemporaryDirectory(prefix="geodesic-guards-") as tmp:
        root = Path(tmp)
        copy_tree(root)
        for script, args in [("framework.py", []), ("unused_deps.py", []), ("sizes.py", ["--check"])]:
            code, out = guard(root, script, *args)
            if code != 0:
                print(f"guards: FAIL the unmutated copy: {script} exit {code}\n{out}")
                return 1
        ok = all([
            mutation("a mission's title word in a framework crate's code", root,
                     ["verification/core/src/lib.rs"],
                     lambda r: edit(r / "verification/core/src/lib.rs", "\npub mod ",
                                    "\n/// Sized for the CubeSat.\npub mod "),
                     "framework.py", [], ["verification/core/src/lib.rs:", "names a mission", "CubeSat"]),
            mutation("a mission's name in a framework crate's description", root,
                     ["verification/report/Cargo.toml"],
                     lambda r: edit(r / "verification/report/Cargo.toml", 'description = "',
                                    'description = "lisa-pathfinder reports: '),
                     "framework.py", [], ["verification/report/Cargo.toml:", "names a mission"]),
            mutation("a framework crate embedding a mission's file", root,
                     ["verification/verify/src/lib.rs"],
                     lambda r: edit(r / "verification/verify/src/lib.rs", "\npub mod ",
                                    '\nconst _R: &str = include_str!("../../../requirements/x.yaml");\npub mod '),
                     "framework.py", [], ["verification/verify/src/lib.rs:", "embeds a mission's file"]),
            mutation("a new upward dependency", root,
                     ["verification/report/Cargo.toml"],
                     lambda r: edit(r / "verification/report/Cargo.toml", "[dependencies]\n",
                                    "[dependencies]\ngeodesic-checks.workspace = true\n"),
                     "framework.py", [], ["geodesic-report depends on geodesic-checks"]),
            mutation("a module cycle", root,
                     ["verification/fit/src/identify.rs"],
                     lambda r: edit(r / "verification/fit/src/identify.rs",
                                    "use crate::numeric::observe::Observer;\n",
                                    "use crate::numeric::observe::Observer;\n"
                                    "use crate::estimate::FitOutcome as _Back;\n"),
                     "framework.py", [], ["verification/fit: module cycle", "estimate", "identify"]),
            mutation("an unused dependency", root,
                     ["verification/util/Cargo.toml"],
                     lambda r: edit(r / "verification/util/Cargo.toml", "[dependencies]\n",
                                    "[dependencies]\napprox.workspace = true\n"),
                     "unused_deps.py", [], ["verification/util/Cargo.toml:", "declares approx", "no code uses"]),
            mutation("a dependency only the tests use", root,
                     ["verification/cli/Cargo.toml"],
                     lambda r: edit(r / "verification/cli/Cargo.toml", "[dependencies]\n",
                                    "[dependencies]\ntempfile.workspace = true\n"),
                     "unused_deps.py", [], ["declares tempfile (dependencies)", "a dev-dependency"]),
            mutation("a framework crate without #![warn(missing_docs)]", root,
                     ["verification/util/src/lib.rs"],
                     lambda r: edit(r / "verification/util/src/lib.rs", "#![warn(missing_docs)]\n", ""),
                     "framework.py", [], ["verification/util/src/lib.rs:", "missing_docs"]),
            mutation("a size typed by hand", root,
                     ["docs/architecture.md"],
                     lambda r: edit(r / "docs/architecture.md", "non-test lines (under",
                                    "non-test lines, give or take (under"),
                     "sizes.py", ["--check"], ["out of date"]),
        ])
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
