#!/usr/bin/env python3
"""Follows docs/guide-effect.md ("Adding an effect") exactly as written, and checks what it promises.

The guide's steps are read from the guide itself (its "## Steps" section), not copied here:
  1. the first ```rust block is written to the path named in step 1;
  2. the three snippets step 2 names (`mod pendulum;`, `pub use pendulum::Pendulum;`,
     `&Pendulum,`) are added after the last line of their kind in the effects' mod.rs (the
     `mod` lines, the `pub use` lines, the list of `catalogue()`);
  3. the second ```rust block is appended to hide_each.rs and the effect's name added to the
     guard test's `tested` list;
  4. every command of the plain ``` block of step 4 is run, in order, from the tree's root.
Then the promises of step 4 are checked: every command exits 0, `diagnose` names the new effect
as the missing one, and the fit with it is compatible with the noise (chi2_red below 1.2).

Usage: .ci/walkthrough.py [--in-place]
  --in-place  edit this checkout (it must be clean: `git status` empty) and restore it
              afterwards; reuses its build (what CI does, on its throwaway clone). Without it, a
              copy of the tracked files goes to target/walkthrough/tree, built in
              target/walkthrough/target (a full build: minutes).
Exit 0 when the walkthrough works as written, 1 when a step or a promise fails.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
CREATED = []


def fail(msg):
    print(f"walkthrough: FAILED: {msg}", file=sys.stderr)
    sys.exit(1)


GUIDE = "docs/guide-effect.md"


def section(guide):
    start = guide.index("\n## Steps")
    end = guide.find("\n## ", start + 5)
    return guide[start:] if end < 0 else guide[start:end]


def blocks(sec):
    """(language, code) of every fenced block, dedented by the fence's indentation."""
    out = []
    for m in re.finditer(r"^( *)```(\w*)\n(.*?)^\1```", sec, re.S | re.M):
        indent = len(m.group(1))
        lines = [l[indent:] if l.startswith(" " * indent) else l.lstrip() for l in m.group(3).splitlines()]
        out.append((m.group(2), "\n".join(lines) + "\n"))
    return out


def insert_after_last(text, pattern, line, within=None):
    lines = text.splitlines(keepends=True)
    lo, hi = within if within else (0, len(lines))
    idx = [i for i in range(lo, hi) if re.match(pattern, lines[i])]
    if not idx:
        fail(f"no line matching {pattern!r} to insert {line.strip()!r} after")
    i = idx[-1]
    indent = re.match(r"\s*", lines[i]).group(0)
    lines.insert(i + 1, indent + line.strip() + "\n")
    return "".join(lines)


def apply_steps(tree, sec):
    bl = blocks(sec)
    rust = [c for (lang, c) in bl if lang == "rust"]
    plain = [c for (lang, c) in bl if lang == ""]
    if len(rust) < 2 or not plain:
        fail("the section has not the two rust blocks and the command block it had")
    # step 1: the file
    m = re.search(r"1\. Create `([^`]+\.rs)`", sec)
    if not m:
        fail("step 1 names no file")
    path = tree / m.group(1)
    name = path.stem
    path.write_text(rust[0])
    CREATED.append(path)
    # step 2: registration, the snippets as the guide writes them
    step2 = sec[sec.index("2. Register"):sec.index("3. ")]
    mod_rs = tree / re.search(r"`(models/[^`]+/mod\.rs)`", step2).group(1)
    snippets = re.findall(r"`([^`]+)`", re.sub(r"\s*\n\s*", " ", step2))
    mod_line = next(s for s in snippets if s.startswith("mod "))
    use_line = next(s for s in snippets if s.startswith("pub use "))
    item = next(s for s in snippets if s.startswith("&") and s.endswith(","))
    text = mod_rs.read_text()
    text = insert_after_last(text, r"^mod \w+;", mod_line)
    text = insert_after_last(text, r"^pub use \w+::\w+;", use_line)
    lines = text.splitlines()
    start = next(i for i, l in enumerate(lines) if "fn catalogue()" in l)
    end = next(i for i in range(start, len(lines)) if lines[i].startswith("}"))
    text = insert_after_last(text, r"^\s+&\w+,$", item, (start, end))
    mod_rs.write_text(text)
    # step 3: the hiding test and the guard's list
    step3 = sec[sec.index("3. "):sec.index("4. ")]
    tests = tree / re.search(r"`(verification/[^`]+\.rs)`", step3).group(1)
    t = tests.read_text()
    t = t.replace("let tested = [", f'let tested = [\n        "{name}",', 1)
    tests.write_text(t + "\n" + rust[1])
    return name, plain[0]


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
        base = ROOT / "target" / "walkthrough"
        tree = base / "tree"
        shutil.rmtree(tree, ignore_errors=True)
        files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
        for f in filter(None, files.split("\0")):
            dst = tree / f
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / f, dst)
        env["CARGO_TARGET_DIR"] = str(base / "target")
    try:
        name, block = apply_steps(tree, sec)
        print(f"walkthrough: added the effect `{name}` as {GUIDE} says; running step 4", flush=True)
        outputs = {}
        for cmd in commands(block):
            print(f"walkthrough: $ {cmd}", flush=True)
            if env.get("CARGO_TARGET_DIR") and cmd.startswith("./target/"):
                cmd = env["CARGO_TARGET_DIR"] + cmd[len("./target"):]
            r = subprocess.run(cmd, shell=True, cwd=tree, env=env, capture_output=True, text=True)
            sys.stdout.write(r.stdout[-3000:])
            sys.stderr.write(r.stderr[-2000:])
            if r.returncode != 0:
                fail(f"`{cmd}` exited {r.returncode}")
            outputs[cmd] = r.stdout
        diag = next((o for c, o in outputs.items() if " diagnose " in c), None)
        fit = next((o for c, o in outputs.items() if " fit " in c), None)
        if diag is None or fit is None:
            fail("step 4 has no diagnose or no fit command")
        m = re.search(r"^missing:\s*(\S+)", diag, re.M)
        if not m or m.group(1) != name:
            fail(f"diagnose does not name `{name}` as the missing effect:\n{diag[-1500:]}")
        c = re.search(r"chi2_red\s*=\s*([0-9.]+)", fit)
        if not c or float(c.group(1)) >= 1.2:
            fail(f"the fit with `{name}` is not compatible with the noise:\n{fit[-1500:]}")
        print(f"walkthrough: passed (diagnose names `{name}`; fit chi2_red {c.group(1)})")
    finally:
        if in_place:
            subprocess.run(["git", "checkout", "--", "."], cwd=ROOT, check=False)
            for p in CREATED:
                p.unlink(missing_ok=True)
            print(
                "walkthrough: checkout restored; target/ still holds the build with the example "
                "effect until the next cargo build",
                file=sys.stderr,
            )


if __name__ == "__main__":
    main()
