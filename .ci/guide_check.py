#!/usr/bin/env python3
"""Follows docs/guide-check.md ("Adding a check and a requirement family") exactly as written.

The guide's steps are read from the guide itself (its "## Steps" section), not copied here,
each found by what it does rather than by its number:
  - the step with the ```yaml block: written to the requirement file it names;
  - the step with a ```rust block naming a file of verification/checks/src/: the check;
  - the step naming `all.extend(`: its two snippets (`pub mod NAME;`,
    `all.extend(NAME::checks());`) go into the file it names, the module among the `pub mod`
    lines in name order, the registration after the last `all.extend(` of `registry_with`;
  - the step naming missions/src/lisa_pathfinder.rs, if there is one: its entry goes into
    `FILES`, in path order;
  - the step with a ```rust block naming verification/checks/tests/: the traced test, and
    `mod NAME;` into that test binary's main.rs among its `mod` lines in name order;
  - the step with the plain ``` block: every command run, in order, from the tree's root.
Then the promise of that step is checked: every command exits 0, or the status its comment states
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


def steps_of(sec):
    """The text of every numbered step (`N. ` at the start of a line up to the next one)."""
    return [m.group(0) for m in re.finditer(r"^\d+\. .*?(?=^\d+\. |\Z)", sec, re.S | re.M)]


def flat(text):
    return re.sub(r"\s*\n\s*", " ", text)


def the_step(steps, what, pred, optional=False):
    found = [t for t in steps if pred(t)]
    if not found:
        if optional:
            return None
        fail(f"the guide has no step {what}")
    return found[0]


def apply_steps(tree, sec):
    """Applies the steps, found by what they do (not by their number, so that a step added or
    removed does not shift the others): returns the command block and the promised row."""
    steps = steps_of(sec)
    code = lambda t, lang: [c for (l, c) in blocks(t) if l == lang]
    # the requirement family: the step with the yaml block
    s = the_step(steps, "with a yaml block", lambda t: code(t, "yaml"))
    create(tree, path_in(s, r"`(requirements/[^`]+\.yaml)`"), code(s, "yaml")[0])
    # the check: the step with a rust block that names a file of verification/checks/src/
    s = the_step(steps, "creating the check", lambda t: code(t, "rust") and re.search(r"`verification/checks/src/\w+\.rs`", flat(t)))
    create(tree, path_in(s, r"`(verification/checks/src/\w+\.rs)`"), code(s, "rust")[0])
    # registration: `pub mod NAME;` and `all.extend(NAME::checks());` in the file it names
    s = the_step(steps, "registering the check", lambda t: "`all.extend(" in flat(t))
    lib = tree / path_in(s, r"`(verification/checks/src/lib\.rs)`")
    sn = snippets(s)
    mod_line = next(x for x in sn if x.startswith("pub mod "))
    reg_line = next(x for x in sn if x.startswith("all.extend("))
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
    # the built-in embedding, when the guide has that step (the binary's list of family files)
    s = the_step(steps, "embedding", lambda t: "`missions/src/lisa_pathfinder.rs`" in flat(t), optional=True)
    if s is not None:
        builtin = tree / "missions/src/lisa_pathfinder.rs"
        entry = next(x for x in snippets(s) if x.startswith("(\"") and x.endswith("),"))
        name = re.match(r'\("([^"]+)"', entry).group(1)
        lines = builtin.read_text().splitlines(keepends=True)
        start = next(i for i, l in enumerate(lines) if "FILES" in l and "&[" in l)
        end = next(i for i in range(start, len(lines)) if lines[i].strip() == "];")
        at = end
        for i in range(start, end):
            m = re.match(r'\s*"([^"]+\.yaml)",', lines[i])
            if m and m.group(1) > name:
                at = i - 1 if lines[i - 1].strip() == "(" else i
                break
        lines.insert(at, "    " + entry.strip() + "\n")
        builtin.write_text("".join(lines))
    # the traced test and its module in the test binary's main.rs
    s = the_step(steps, "adding the traced test", lambda t: code(t, "rust") and "verification/checks/tests/" in flat(t))
    test = path_in(s, r"`(verification/checks/tests/[^`]+\.rs)`")
    create(tree, test, code(s, "rust")[0])
    main_rs = (tree / test).parent / "main.rs"
    mod_line = next(x for x in snippets(s) if re.match(r"^mod \w+;$", x))
    main_rs.write_text(insert_sorted(main_rs.read_text(), r"^mod (\w+);$", mod_line))
    # the commands (the plain block) and the promised row
    s = the_step(steps, "with the commands", lambda t: code(t, ""))
    m = re.search(r"prints\s+`([^`]+)`", flat(s))
    if not m:
        fail("the step of the commands quotes no row after `prints`")
    return code(s, "")[0], m.group(1)


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
        print(f"guide-check: applied the steps of {GUIDE} (requirement {rid}); running its commands", flush=True)
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
            fail("the commands run no verify")
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
