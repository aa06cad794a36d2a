#!/usr/bin/env python3
"""Applies the blocks of docs/guide-mission.md, step 3, to a generated project exactly as written
(.ci/new-mission.sh). A block is announced by a comment line before its fence:

  <!-- new-mission: create FILE -->   the next fenced block is FILE's text
  <!-- new-mission: append FILE -->   the next fenced block is appended to FILE
  <!-- new-mission: replace FILE -->  the next two fenced blocks: the text in FILE (once, exactly)
                                      and what replaces it
  <!-- new-mission: run -->           the next fenced block is printed, one command a line, for
                                      the caller to run (--commands)

Usage: guide_mission_apply.py GUIDE PROJECT [--commands]. Exit 1 naming the block that does
not apply.
"""
import re
import sys
from pathlib import Path


def blocks(text):
    """[(action, file, [block texts])] in the guide's order."""
    lines = text.splitlines(keepends=True)
    out, i = [], 0
    while i < len(lines):
        m = re.match(r"<!-- new-mission: (create|append|replace|run)\s*(\S*) -->", lines[i])
        i += 1
        if not m:
            continue
        need = 2 if m.group(1) == "replace" else 1
        got = []
        while len(got) < need and i < len(lines):
            if lines[i].startswith("```"):
                j = i + 1
                while not lines[j].startswith("```"):
                    j += 1
                got.append("".join(lines[i + 1:j]))
                i = j
            i += 1
        out.append((m.group(1), m.group(2), got))
    return out


def main():
    guide, project = Path(sys.argv[1]), Path(sys.argv[2])
    todo = blocks(guide.read_text())
    if "--commands" in sys.argv:
        for action, _, got in todo:
            if action == "run":
                print(got[0], end="")
        return 0
    n = 0
    for action, name, got in todo:
        f = project / name
        if action == "create":
            f.parent.mkdir(parents=True, exist_ok=True)
            f.write_text(got[0])
        elif action == "append":
            f.write_text(f.read_text() + got[0])
        elif action == "replace":
            text = f.read_text()
            if text.count(got[0]) != 1:
                print(f"{guide}: replace {name}: the text {got[0].strip()!r} is in {name} "
                      f"{text.count(got[0])} times (expected once)", file=sys.stderr)
                return 1
            f.write_text(text.replace(got[0], got[1]))
        else:
            continue
        n += 1
    if n == 0:
        print(f"{guide}: no `<!-- new-mission: ... -->` block", file=sys.stderr)
        return 1
    print(f"guide-mission: {n} blocks applied to {project}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
