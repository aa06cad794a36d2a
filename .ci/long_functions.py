#!/usr/bin/env python3
"""Reports Rust functions longer than a limit (default 150 lines, from `fn` to its closing
brace), issue 34's "no function over 150 lines".

    python3 .ci/long_functions.py [--max 150] [--exclude PATH ...] [ROOT]

Scans every `.rs` file under ROOT (default: the repository) except `target/`; `--exclude`
takes path prefixes relative to ROOT (repeatable). Prints `path:line: fn NAME: N lines` for
each function over the limit, longest first, and exits 1 if there is any (0 otherwise).
A small lexer skips comments, strings (raw strings too) and character literals, so braces in
them are not counted.
"""
import argparse
import os
import re
import sys

IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def tokens(src):
    """Yields (kind, text, line) for `fn`, identifiers, `{`, `}`, `;` outside comments,
    strings and character literals."""
    i, n, line = 0, len(src), 1
    while i < n:
        c = src[i]
        if c == "\n":
            line += 1
            i += 1
        elif src.startswith("//", i):
            j = src.find("\n", i)
            i = n if j < 0 else j
        elif src.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if src.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif src.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    line += src[i] == "\n"
                    i += 1
        elif c in "rb" and re.match(r'(br|r)#*"', src[i:i + 260]):
            m = re.match(r'(br|r)(#*)"', src[i:])
            end = '"' + m.group(2)
            j = src.find(end, i + len(m.group(0)))
            j = n if j < 0 else j + len(end)
            line += src.count("\n", i, j)
            i = j
        elif c == '"' or (c == "b" and src.startswith('b"', i)):
            i += 1 if c == '"' else 2
            while i < n and src[i] != '"':
                if src[i] == "\\":
                    i += 1
                line += src[i] == "\n"
                i += 1
            i += 1
        elif c == "'":
            # a character literal ('x', '\n', '\u{..}'), else a lifetime or label
            m = re.match(r"'(\\u\{[0-9a-fA-F]+\}|\\.|[^\\'\n])'", src[i:i + 12])
            i += len(m.group(0)) if m else 1
        elif c.isalpha() or c == "_":
            m = IDENT.match(src, i)
            yield ("ident", m.group(0), line)
            i = m.end()
        elif c in "{};()[]":
            yield (c, c, line)
            i += 1
        else:
            i += 1


def functions(src):
    """Yields (name, first line, line count) of every function with a body."""
    toks = list(tokens(src))
    stack = []  # open braces: (function name or None, start line)
    pending = None  # (name, line, bracket depth) of a `fn` whose body has not opened yet
    depth = 0  # of parentheses and square brackets (`[u8; 4]` in a signature is no `;`)
    for k, (kind, text, line) in enumerate(toks):
        if kind in "([":
            depth += 1
        elif kind in ")]":
            depth -= 1
        elif kind == "ident" and text == "fn" and k + 1 < len(toks) and toks[k + 1][0] == "ident":
            pending = (toks[k + 1][1], line, depth)
        elif kind == ";" and pending and depth == pending[2]:
            pending = None  # a declaration without a body
        elif kind == "{":
            if pending:
                stack.append(pending[:2])
                pending = None
            else:
                stack.append((None, line))
        elif kind == "}" and stack:
            name, start = stack.pop()
            if name is not None:
                yield name, start, line - start + 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("root", nargs="?", default=os.path.join(os.path.dirname(__file__), ".."))
    ap.add_argument("--max", type=int, default=150)
    ap.add_argument("--exclude", action="append", default=[])
    a = ap.parse_args()
    root = os.path.normpath(a.root)
    found = []
    for d, dirs, files in os.walk(root):
        rel_d = os.path.relpath(d, root)
        dirs[:] = sorted(x for x in dirs if x not in ("target", ".git") and not x.startswith("."))
        for f in sorted(files):
            if not f.endswith(".rs"):
                continue
            rel = os.path.normpath(os.path.join(rel_d, f))
            if any(rel == e.rstrip("/") or rel.startswith(e.rstrip("/") + "/") for e in a.exclude):
                continue
            with open(os.path.join(d, f), encoding="utf-8") as fh:
                src = fh.read()
            for name, start, length in functions(src):
                if length > a.max:
                    found.append((length, rel, start, name))
    for length, rel, start, name in sorted(found, key=lambda t: (-t[0], t[1], t[2])):
        print(f"{rel}:{start}: fn {name}: {length} lines")
    if found:
        print(f"{len(found)} function(s) over {a.max} lines", file=sys.stderr)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
