#!/usr/bin/env python3
"""Checks that every relative link of the user documentation resolves.

Reads README.md, every Markdown file under docs/ and the READMEs of missions/ and reports/; for
each Markdown link `[text](target)` outside code blocks and code spans:
  - an `http(s)://` or `mailto:` target is left alone (CI has no network to check it);
  - a relative path must exist in the repository (a file or a folder), relative to the page;
  - an anchor (`page.md#anchor` or `#anchor`) must be the slug of a heading of that page, as
    GitHub makes it (lower case, punctuation other than `-` and `_` dropped, spaces to `-`, a
    repeated heading suffixed `-1`, `-2`, ...).
Prints one line per broken link, `file:line: target: why`, and exits 1 if there is any, else 0.
A page listed in PENDING (written in parallel, landing with issue 34) may be missing: its links
are reported as a warning until it exists, then checked as every other; remove it from the list
once it has landed.

Usage: .ci/links.py [FILE.md ...]   (default: the pages above)
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
LINK = re.compile(r"(?<!!)\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^()\s]*(?:\([^()]*\)[^()\s]*)*)(?:\s+\"[^\"]*\")?\)")
IMAGE = re.compile(r"!\[[^\]]*\]\(([^()\s]+)\)")


def pages():
    out = [ROOT / "README.md"]
    out += sorted((ROOT / "docs").rglob("*.md"))
    out += [p for p in (ROOT / "missions" / "README.md", ROOT / "reports" / "README.md") if p.exists()]
    return out


def slug(heading):
    s = heading.strip().lower()
    s = re.sub(r"<[^>]+>", "", s)  # inline HTML
    s = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", s)  # a link in a heading keeps its text
    s = re.sub(r"[^\w\- ]", "", s)  # GitHub keeps letters, digits, `_`, `-` and spaces
    return s.replace(" ", "-")


def strip_code(lines):
    """Lines with fenced blocks blanked and code spans removed (line numbers kept)."""
    out, fence = [], None
    for line in lines:
        m = re.match(r"^\s*(```+|~~~+)", line)
        if fence:
            if m and m.group(1)[0] == fence[0] and len(m.group(1)) >= len(fence):
                fence = None
            out.append("")
            continue
        if m:
            fence = m.group(1)
            out.append("")
            continue
        out.append(re.sub(r"(`+)(.+?)\1", "", line))
    return out


# pages being written in parallel on another branch (issue 34, part F), relative to the root
PENDING = set()
WARNINGS = []

_anchors = {}


def anchors(path):
    if path not in _anchors:
        seen, found = {}, set()
        for line in strip_code_keep_headings(path.read_text(encoding="utf-8").splitlines()):
            m = re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
            if not m:
                continue
            base = slug(m.group(2))
            n = seen.get(base, 0)
            found.add(base if n == 0 else f"{base}-{n}")
            seen[base] = n + 1
        _anchors[path] = found
    return _anchors[path]


def strip_code_keep_headings(lines):
    """Lines outside fenced blocks (headings keep their code spans' text, as GitHub does)."""
    out, fence = [], None
    for line in lines:
        m = re.match(r"^\s*(```+|~~~+)", line)
        if fence:
            if m and m.group(1)[0] == fence[0] and len(m.group(1)) >= len(fence):
                fence = None
            continue
        if m:
            fence = m.group(1)
            continue
        out.append(line)
    return out


def check(page):
    errors = []
    rel = page.relative_to(ROOT)
    lines = strip_code(page.read_text(encoding="utf-8").splitlines())
    for no, line in enumerate(lines, 1):
        targets = [m.group(1) for m in LINK.finditer(line)] + [m.group(1) for m in IMAGE.finditer(line)]
        for t in targets:
            if re.match(r"^[a-z][a-z0-9+.-]*:", t, re.I):  # http:, https:, mailto:
                continue
            path, _, anchor = t.partition("#")
            target = (page.parent / path).resolve() if path else page
            if path and not target.exists():
                inside = target.is_relative_to(ROOT)
                if inside and str(target.relative_to(ROOT)) in PENDING:
                    WARNINGS.append(f"{rel}:{no}: {t}: not there yet (pending: landing with issue 34)")
                else:
                    errors.append(f"{rel}:{no}: {t}: no such file or folder")
                continue
            try:
                target.relative_to(ROOT)
            except ValueError:
                errors.append(f"{rel}:{no}: {t}: outside the repository")
                continue
            if anchor:
                if target.is_dir() or target.suffix != ".md":
                    errors.append(f"{rel}:{no}: {t}: an anchor into a file that is not Markdown")
                elif anchor not in anchors(target):
                    errors.append(f"{rel}:{no}: {t}: no heading `#{anchor}` in {target.relative_to(ROOT)}")
    return errors


def main():
    files = [pathlib.Path(a).resolve() for a in sys.argv[1:]] or pages()
    errors, links = [], 0
    for f in files:
        errors += check(f)
    for w in WARNINGS:
        print(f"warning: {w}")
    for e in errors:
        print(e)
    if errors:
        print(f"links: {len(errors)} broken link(s) in {len(files)} page(s)", file=sys.stderr)
        return 1
    print(f"links: every relative link and anchor of {len(files)} page(s) resolves")
    return 0


if __name__ == "__main__":
    sys.exit(main())
