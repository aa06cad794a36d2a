#!/usr/bin/env python3
"""Follows docs/loop.md (issue 36: the loop closed) exactly as written, and checks what it promises.

The commands are read from the guide itself, not copied here: every line of its ```sh blocks, in
order, run from the tree's root. Then the promises of the text are checked:
  1. the first discover ends `explained: false` with the leading term of the truth's kind;
  2. the scaffold writes the effect's file, its registration and its hiding test;
  3. `git status` shows them, rustfmt and clippy pass on them (their commands exit 0);
  4. after the rebuild, discover adds the new effect and ends `explained: true`, its parameter
     within 3 reported sigma of the truth (data/examples/outside/*.truth.json, `outside`), and
     `history` shows chi2_red falling across the model versions;
  5. the hiding test and the guard test pass.

Usage: .ci/loop.py [--in-place]
  --in-place  edit this checkout (it must be clean: `git status` empty) and restore it afterwards
              (`git checkout -- .` and the new effect's file removed); reuses its build (what CI
              does, on its throwaway clone). Without it, a copy of the tracked files goes to
              target/loop/tree, built in target/loop/target (a full build: minutes).
Exit 0 when the guide works as written, 1 when a step or a promise fails.
"""
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
GUIDE = "docs/loop.md"


def fail(msg):
    print(f"loop: FAILED: {msg}", file=sys.stderr)
    sys.exit(1)


def commands(guide):
    """Every command of the guide's ```sh blocks, in order (continuation lines joined)."""
    out = []
    for m in re.finditer(r"^```sh\n(.*?)^```", guide, re.S | re.M):
        joined = re.sub(r"\\\n\s*", "", m.group(1))
        out += [l.strip() for l in joined.splitlines() if l.strip() and not l.strip().startswith("#")]
    return out


def main():
    in_place = "--in-place" in sys.argv[1:]
    guide = (ROOT / GUIDE).read_text()
    cmds = commands(guide)
    scaffold = next((c for c in cmds if " --scaffold " in c), None)
    if scaffold is None:
        fail(f"{GUIDE} has no discover --scaffold command")
    name = re.search(r"--scaffold (\w+)", scaffold).group(1)
    record = re.search(r"discover (\S+\.yaml)", scaffold).group(1)
    truth = json.loads((ROOT / record.replace(".yaml", ".truth.json")).read_text())
    outside = truth["outside"]
    env = dict(os.environ)
    if in_place:
        if subprocess.run(["git", "status", "--porcelain"], cwd=ROOT, capture_output=True, text=True).stdout.strip():
            fail("--in-place needs a clean checkout (git status is not empty)")
        tree = ROOT
    else:
        base = ROOT / "target" / "loop"
        tree = base / "tree"
        shutil.rmtree(tree, ignore_errors=True)
        files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
        for f in filter(None, files.split("\0")):
            dst = tree / f
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / f, dst)
        subprocess.run(["git", "init", "-q"], cwd=tree, check=True)
        subprocess.run(["git", "add", "-A"], cwd=tree, check=True)
        subprocess.run(["git", "-c", "user.name=loop", "-c", "user.email=loop@localhost", "commit", "-qm", "copy"],
                       cwd=tree, check=True)
        env["CARGO_TARGET_DIR"] = str(base / "target")
    created = tree / "models" / "facility" / "src" / "effects" / f"{name}.rs"
    try:
        runs = []
        for cmd in cmds:
            print(f"loop: $ {cmd}", flush=True)
            run = cmd
            if env.get("CARGO_TARGET_DIR") and run.startswith("./target/"):
                run = env["CARGO_TARGET_DIR"] + run[len("./target"):]
            r = subprocess.run(run, shell=True, cwd=tree, env=env, capture_output=True, text=True)
            sys.stdout.write(r.stdout[-2500:])
            sys.stderr.write(r.stderr[-1500:])
            if r.returncode != 0:
                fail(f"`{cmd}` exited {r.returncode}")
            runs.append((cmd, r.stdout))
        discovers = [(c, o) for c, o in runs if " discover " in c and " --scaffold " not in c]
        if len(discovers) < 2:
            fail("the guide has not a discover before and one after the scaffold")
        first, after = discovers[0][1], discovers[-1][1]
        # 1. the model fails, the leading term is of the truth's kind
        if "explained: false" not in first:
            fail(f"the first discover does not end `explained: false`:\n{first[-1500:]}")
        lead = re.search(r"best described by .*?\[([^\]]+)\]", first)
        kind_word = {"velocity": "(velocity)", "position": "(position)"}.get(outside["kind"], outside["kind"])
        if not lead or kind_word not in lead.group(0):
            fail(f"the leading term is not of kind {outside['kind']}: {lead.group(0) if lead else None}")
        # 2. the scaffold wrote its three files
        out = next(o for c, o in runs if " --scaffold " in c)
        for f in [f"models/facility/src/effects/{name}.rs", "models/facility/src/effects/mod.rs",
                  "verification/discover/tests/hide_each.rs"]:
            if f"wrote {f}" not in out:
                fail(f"the scaffold did not write {f}:\n{out[-1500:]}")
        # 3. git status shows them
        status = next((o for c, o in runs if c.startswith("git status")), "")
        if f"{name}.rs" not in status or "mod.rs" not in status or "hide_each.rs" not in status:
            fail(f"git status does not show the scaffold's files:\n{status}")
        # 4. the error falls: explained, the new effect added, its parameter near the truth
        if "explained: true" not in after:
            fail(f"discover with the new effect does not end `explained: true`:\n{after[-2500:]}")
        added = re.findall(r"^\s+\d+\s+(\S+)\s", after, re.M)
        if not added or name not in added[-1]:
            fail(f"discover's last model does not hold {name}: {added}")
        checked = 0
        for pname, true in outside["params"].items():
            m = re.search(rf"{name}\.{pname}\s*=\s*(\S+)\s*\+-\s*(\S+)", after)
            if not m:
                continue
            est, sig = float(m.group(1)), float(m.group(2))
            z = abs(est - true) / sig
            print(f"loop: {name}.{pname} = {est:.6g} +- {sig:.3g} (truth {true:g}, {z:.2f} sigma)")
            if not z <= 3.0:
                fail(f"{name}.{pname} = {est} +- {sig} is {z:.2f} sigma from the truth {true}")
            checked += 1
        if checked == 0:
            fail(f"the final fit reports no parameter of {name} with a sigma:\n{after[-2500:]}")
        chi = re.search(r"^\s*chi2_red = ([0-9.e+-]+)", after, re.M)
        print(f"loop: final chi2_red {chi.group(1) if chi else '?'}")
        hist = next((o for c, o in runs if " history " in c), None)
        if hist is None:
            fail("the guide runs no history")
        rows = re.findall(r"^\s*\d+\s+\S+\s+([0-9.e+-]+)\s+\S+\s+\d+\s+(\S+)\s*$", hist, re.M)
        with_it = [float(c) for c, e in rows if name in e.split(",")]
        without = [float(c) for c, e in rows if name not in e.split(",")]
        if not with_it or not without or not min(with_it) < min(without):
            fail(f"history does not show chi2_red falling with {name}:\n{hist[-1500:]}")
        print(f"loop: history: chi2_red {min(without):g} without {name}, {min(with_it):g} with it")
        print(f"loop: passed (discover explains the record with `{name}`; hiding and guard tests pass)")
    finally:
        if in_place:
            subprocess.run(["git", "checkout", "--", "."], cwd=ROOT, check=False)
            created.unlink(missing_ok=True)
            print("loop: checkout restored; target/ still holds the build with the new effect "
                  "until the next cargo build", file=sys.stderr)


if __name__ == "__main__":
    main()
