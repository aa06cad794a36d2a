#!/usr/bin/env python3
"""Reference counts of the ReqIF test files of other tools, by the reference parser.

Usage: reqif-reference-counts.py [--check] DIR

For every DIR/*.reqif (and DIR/*.reqifz: each document in it), parses the file with the PyPI package `reqif` (strictdoc-project/reqif,
the parser bundled with the OMG schema; pinned in reqif-venv.sh) and records how many
SPEC-OBJECTs, SPECIFICATIONs and SPEC-RELATIONs it reads, and, independently of any ReqIF
model, how many SPEC-OBJECT elements the XML holds (lxml). Writes DIR/reference-counts.json;
with --check, compares with the file instead and exits 1 when they differ (CI runs it so that
the committed counts stay the parser's). `geodesic import reqif` accounts for every
SPEC-OBJECT (requirements + headings + objects without text + duplicates + skipped =
`spec_objects`): verification/exchange/tests/reqif.rs asserts that its `spec_objects` equals
these counts.
"""

import json
import os
import sys


def count_archive(path: str) -> dict:
    """A .reqifz: the counts of each ReqIF document in it, by name (the reference parser's
    ReqIFZParser), and which one `geodesic import reqif` reads (the first .reqif by name)."""
    import zipfile

    from reqif.parser import ReqIFZParser

    out = {"documents": {}}
    try:
        bundle = ReqIFZParser.parse(path)
        for name, b in sorted(bundle.reqif_bundles.items()):
            c = b.core_content.req_if_content if b.core_content else None
            out["documents"][name] = {
                "spec_objects": len(c.spec_objects or []) if c else 0,
                "specifications": len(c.specifications or []) if c else 0,
                "spec_relations": len(c.spec_relations or []) if c else 0,
            }
    except Exception as e:
        out["parser_error"] = f"{type(e).__name__}: {str(e).splitlines()[0][:160]}"
    with zipfile.ZipFile(path) as z:
        docs = sorted(
            n
            for n in z.namelist()
            if n.lower().endswith(".reqif")
            and not n.startswith("__MACOSX/")
            and not n.rsplit("/", 1)[-1].startswith("._")
        )
    out["imported_document"] = docs[0] if docs else None
    if docs and docs[0] in out["documents"]:
        out["spec_objects"] = out["documents"][docs[0]]["spec_objects"]
    return out


def count(path: str) -> dict:
    from lxml import etree
    from reqif.parser import ReqIFParser

    if path.endswith(".reqifz"):
        return count_archive(path)
    out = {}
    try:
        bundle = ReqIFParser.parse(path)
        content = bundle.core_content.req_if_content if bundle.core_content else None
        out["spec_objects"] = len(content.spec_objects or []) if content else 0
        out["specifications"] = len(content.specifications or []) if content else 0
        out["spec_relations"] = len(content.spec_relations or []) if content else 0
    except Exception as e:  # the reference parser refuses some real files
        out["parser_error"] = f"{type(e).__name__}: {str(e).splitlines()[0][:160]}"
    tree = etree.parse(path, etree.XMLParser(huge_tree=True, resolve_entities=False))
    out["xml_spec_object_elements"] = sum(
        1
        for e in tree.getroot().iter()
        if isinstance(e.tag, str) and etree.QName(e).localname == "SPEC-OBJECT"
    )
    return out


def main() -> int:
    args = sys.argv[1:]
    check = "--check" in args
    args = [a for a in args if a != "--check"]
    if len(args) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    folder = args[0]
    import reqif

    counts = {
        "parser": f"reqif {getattr(reqif, '__version__', 'unknown')}",
        "files": {
            f: count(os.path.join(folder, f))
            for f in sorted(os.listdir(folder))
            if f.endswith(".reqif") or f.endswith(".reqifz")
        },
    }
    target = os.path.join(folder, "reference-counts.json")
    text = json.dumps(counts, indent=2, sort_keys=True) + "\n"
    if check:
        with open(target, encoding="utf-8") as fh:
            old = fh.read()
        if old != text:
            print(f"{target} is not what the reference parser counts now:", file=sys.stderr)
            print(text, file=sys.stderr)
            return 1
        print(f"{target}: the reference parser's counts, {len(counts['files'])} files")
        return 0
    with open(target, "w", encoding="utf-8") as fh:
        fh.write(text)
    print(f"wrote {target} ({len(counts['files'])} files)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
