#!/usr/bin/env python3
"""Follows docs/guide-check.md ("Adding a check and a requirement family") exactly as written.

The guide's steps are read from the guide itself (its "## Steps" section), not copied here:
  1. the first ```yaml block is written to the requirement file step 1 names;
  2. the first ```rust block is written to the check's file step 2 names;
  3. the two snippets of step 3 (`pub mod NAME;`, `all.extend(NAME::checks());`) go into the
     file it names: the module among the `pub mod` lines in name order, the registration after
     the last `all.extend(` line of `registry_with`;
  4. the entry of step 4 goes into `REQUIREMENTS` of the file it names, in file-name order;
  5. the second ```rust block is written to the test file step 5 names, and `mod NAME;` into
     that test binary's main.rs among its `mod` lines in name order;
  6. every command of the plain ``` block of step 6 is run, in order, from the tree's root.
Then the promise of step 6 is checked: every command exits 0, or the status its comment states
(`# exits N`), and the row `verify` prints for
the new requirement holds, in order, each part of the row the guide quotes after "prints"
(its ID, `compliant`, the basis, the value, the limit, the margin), and is not non-compliant.

Usage: .ci/guide_check.py [--in-place]
  --in-place  edit this checkout (it must be clean: `git status` empty) and restore it
              afterwards; reuses its build (what CI does, on its throwaway clone). Without it, a
              copy of the tracked files goes to target/guide-check/tree, built in
              target/guide-check/target (a full build: minutes).
Exit 0 when the guide works as written, 1 when a step or the promise fails.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
GUIDE = "docs/guide-check.md"
CREATED = []


def fail(msg):
    print(f"guide-check: FAILED: {msg}", file=sys.stderr)
    sys.exit(1)


def section(text):
    start = text.index("\n## Steps")
    end = text.find("\n## ", start + 5)
    return text[start:] if end < 0 else text[start:end]


def step(sec, n):
    """The text of step `n` (from `n. ` at the start of a line to the next step)."""
    m = re.search(rf"^{n}\. (.*?)(?=^{n + 1}\. |\Z)", sec, re.S | re.M)
    if not m:
        fail(f"the guide has no step {n}")
    return m.group(0)


def blocks(sec):
    """(language, code) of every fenced block, dedented by the fence's indentation."""
    out = []
    for m in re.finditer(r"^( *)```(\w*)\n(.*?)^\1```", sec, re.S | re.M):
        indent = len(m.group(1))
        lines = [l[indent:] if l.startswith(" " * indent) else l.lstrip() for l in m.group(3).splitlines()]
        out.append((m.group(2), "\n".join(lines) + "\n"))
    return out


def snippets(text):
    return re.findall(r"`([^`]+)`", re.sub(r"\s*\n\s*", " ", text))


def path_in(text, pattern):
    m = re.search(pattern, re.sub(r"\s*\n\s*", " ", text))
    if not m:
        fail(f"no path matching {pattern!r} in: {text[:200]!r}")
    return m.group(1)


def create(tree, rel, text):
    p = tree / rel
    if p.exists():
        fail(f"{rel} exists already: the guide must create it")
    p.write_text(text)
    CREATED.append(p)


def insert_sorted(text, pattern, line):
    """Inserts `line` among the lines matching `pattern` (group 1: the sort key), in order."""
    lines = text.splitlines(keepends=True)
    key = re.match(pattern, line.strip()).group(1)
    idx = [(i, re.match(pattern, l.strip()).group(1)) for i, l in enumerate(lines) if re.match(pattern, l.strip())]
    if not idx:
        fail(f"no line matching {pattern!r} to insert {line!r} among")
    at = next((i for i, k in idx if k > key), idx[-1][0] + 1)
    indent = re.match(r"\s*", lines[idx[0][0]]).group(0)
    lines.insert(at, indent + line.strip() + "\n")
    return "".join(lines)


def apply_steps(tree, sec):
    bl = blocks(sec)
    yaml = [c for (lang, c) in bl if lang == "yaml"]
    rust = [c for (lang, c) in bl if lang == "rust"]
    plain = [c for (lang, c) in bl if lang == ""]
    if not yaml or len(rust) < 2 or not plain:
        fail("the steps have not the yaml block, the two rust blocks and the command block they had")
    # 1: the requirement family
    s1 = step(sec, 1)
    create(tree, path_in(s1, r"`(requirements/[^`]+\.yaml)`"), yaml[0])
    # 2: the check
    s2 = step(sec, 2)
    create(tree, path_in(s2, r"`(verification/checks/src/[^`]+\.rs)`"), rust[0])
    # 3: registration
    s3 = step(sec, 3)
    lib = tree / path_in(s3, r"`(verification/checks/src/lib\.rs)`")
    sn = snippets(s3)
    mod_line = next(s for s in sn if s.startswith("pub mod "))
    reg_line = next(s for s in sn if s.startswith("all.extend("))
    text = insert_sorted(lib.read_text(), r"^pub mod (\w+);$", mod_line)
    lines = text.splitlines(keepends=True)
    start = next(i for i, l in enumerate(lines) if "fn registry_with" in l)
    end = next(i for i in range(start, len(lines)) if lines[i].startswith("}"))
    last = max((i for i in range(start, end) if lines[i].strip().startswith("all.extend(")), default=None)
    if last is None:
        fail("registry_with has no `all.extend(` line to register after")
    indent = re.match(r"\s*", lines[last]).group(0)
    lines.insert(last + 1, indent + reg_line.strip() + "\n")
    lib.write_text("".join(lines))
    # 4: the built-in embedding
    s4 = step(sec, 4)
    builtin = tree / path_in(s4, r"`(verification/cli/src/builtin\.rs)`")
    entry = next(s for s in snippets(s4) if s.startswith("(\"") and s.endswith("),"))
    name = re.match(r'\("([^"]+)"', entry).group(1)
    lines = builtin.read_text().splitlines(keepends=True)
    start = next(i for i, l in enumerate(lines) if "REQUIREMENTS" in l and "&[" in l)
    end = next(i for i in range(start, len(lines)) if lines[i].strip() == "];")
    at = end
    for i in range(start, end):
        m = re.match(r'\s*"([^"]+\.yaml)",', lines[i])
        if m and m.group(1) > name:
            at = i - 1 if lines[i - 1].strip() == "(" else i
            break
    lines.insert(at, "    " + entry.strip() + "\n")
    builtin.write_text("".join(lines))
    # 5: the traced test and its module
    s5 = step(sec, 5)
    test = path_in(s5, r"`(verification/checks/tests/[^`]+\.rs)`")
    create(tree, test, rust[1])
    main_rs = (tree / test).parent / "main.rs"
    mod_line = next(s for s in snippets(s5) if re.match(r"^mod \w+;$", s))
    main_rs.write_text(insert_sorted(main_rs.read_text(), r"^mod (\w+);$", mod_line))
    # 6: the commands and the promised row
    s6 = step(sec, 6)
    m = re.search(r"prints\s+`([^`]+)`", re.sub(r"\s*\n\s*", " ", s6))
    if not m:
        fail("step 6 quotes no row after `prints`")
    return plain[0], m.group(1)


def commands(block):
    joined = re.sub(r"\\\n\s*", "", block)
    return [l.strip() for l in joined.splitlines() if l.strip()]


def main():
    in_place = "--in-place" in sys.argv[1:]
    sec = section((ROOT / GUIDE).read_text())
    env = dict(os.environ)
    if in_place:
        if subprocess.run(["git", "status", "--porcelain"], cwd=ROOT, capture_output=True, text=True).stdout.strip():
            fail("--in-place needs a clean checkout (git status is not empty)")
        tree = ROOT
    else:
        base = ROOT / "target" / "guide-check"
        tree = base / "tree"
        shutil.rmtree(tree, ignore_errors=True)
        files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
        for f in filter(None, files.split("\0")):
            dst = tree / f
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / f, dst)
        env["CARGO_TARGET_DIR"] = str(base / "target")
    try:
        block, promised = apply_steps(tree, sec)
        rid = promised.split()[0]
        print(f"guide-check: applied steps 1 to 5 of {GUIDE} (requirement {rid}); running step 6", flush=True)
        verify_out = None
        for cmd in commands(block):
            print(f"guide-check: $ {cmd}", flush=True)
            if env.get("CARGO_TARGET_DIR") and cmd.startswith("./target/"):
                cmd = env["CARGO_TARGET_DIR"] + cmd[len("./target"):]
            r = subprocess.run(cmd, shell=True, cwd=tree, env=env, capture_output=True, text=True)
            sys.stdout.write(r.stdout[-3000:])
            sys.stderr.write(r.stderr[-2000:])
            m = re.search(r"#\s*exits\s+(\d+)", cmd)
            expected = int(m.group(1)) if m else 0
            if r.returncode != expected:
                fail(f"`{cmd}` exited {r.returncode}, not {expected}")
            if " verify " in f" {cmd} ":
                verify_out = r.stdout
        if verify_out is None:
            fail("step 6 runs no verify")
        row = next((l for l in verify_out.splitlines() if l.startswith(rid + " ")), None)
        if row is None:
            fail(f"verify printed no row for {rid}:\n{verify_out[-1500:]}")
        if "non-compliant" in row:
            fail(f"{rid} is non-compliant: {row}")
        parts = [p.strip() for p in re.split(r"\.\.\.|\s{2,}", promised) if p.strip()]
        at = 0
        for p in parts:
            i = row.find(p, at)
            if i < 0:
                fail(f"the row of {rid} lacks `{p}` (in the order the guide quotes):\n{row}")
            at = i + len(p)
        print(f"guide-check: passed ({row.split()[0]}: {' '.join(row.split())})")
    finally:
        if in_place:
            subprocess.run(["git", "checkout", "--", "."], cwd=ROOT, check=False)
            for p in CREATED:
                p.unlink(missing_ok=True)
            print(
                "guide-check: checkout restored; target/ still holds the build with the example "
                "check until the next cargo build",
                file=sys.stderr,
            )


if __name__ == "__main__":
    main()
