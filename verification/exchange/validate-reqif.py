#!/usr/bin/env python3
"""Validates ReqIF files against the OMG ReqIF 1.2 schema, as the ReqIF tools read them.

Usage: validate-reqif.py FILE.reqif [FILE.reqif ...]

Needs the PyPI packages `reqif` (strictdoc-project/reqif, which bundles the OMG schema
reqif.xsd with the XHTML modules it imports) and `xmlschema`; .ci/run installs pinned versions
in a virtual environment under target/. For each file:

1. strict XML Schema validation with `xmlschema` against the bundled reqif.xsd (every error is
   listed with its path): the real check;
2. `reqif validate --use-reqif-schema`: the package's own validator (schema and semantic
   checks: dangling references in SPEC-HIERARCHY and SPEC-RELATION, encoding, declaration);
3. passthrough: the package parses the file into its model and writes it back; the output must
   equal the input, i.e. every element and attribute of the file is one the package's model
   knows and keeps.

Exit 0 when every file passes all three, 1 otherwise (the causes on standard error).
"""

import os
import subprocess
import sys


def main() -> int:
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    import xmlschema
    import reqif
    from reqif.parser import ReqIFParser
    from reqif.unparser import ReqIFUnparser

    root = os.path.dirname(os.path.abspath(reqif.__file__))
    xsd = os.path.join(root, "reqif_schema", "reqif.xsd")
    # reqif.xsd imports the xml namespace with an empty schemaLocation and the XHTML driver by a
    # relative path: resolve them from the schema's directory, as the package itself does
    old = os.getcwd()
    files = [os.path.abspath(f) for f in sys.argv[1:]]
    os.chdir(os.path.dirname(root))
    try:
        schema = xmlschema.XMLSchema(xsd)
    finally:
        os.chdir(old)
    failed = False
    tool = os.path.join(os.path.dirname(sys.executable), "reqif")
    for f in files:
        errors = list(schema.iter_errors(f))
        for e in errors[:20]:
            print(f"{f}: schema: {e.path}: {e.reason}", file=sys.stderr)
        if errors:
            print(f"{f}: {len(errors)} schema errors", file=sys.stderr)
            failed = True
            continue
        r = subprocess.run(
            [tool, "validate", "--use-reqif-schema", f],
            capture_output=True,
            text=True,
            check=False,
        )
        if r.returncode != 0:
            print(f"{f}: reqif validate: {r.stdout.strip()} {r.stderr.strip()}", file=sys.stderr)
            failed = True
            continue
        with open(f, encoding="utf-8") as fh:
            text = fh.read()
        back = ReqIFUnparser.unparse(ReqIFParser.parse(f))
        if back != text:
            a, b = text.splitlines(), back.splitlines()
            n = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
            print(
                f"{f}:{n + 1}: passthrough through the reqif package changed the file:\n"
                f"  was: {a[n] if n < len(a) else '<end>'}\n"
                f"  now: {b[n] if n < len(b) else '<end>'}",
                file=sys.stderr,
            )
            failed = True
            continue
        print(f"{f}: valid ReqIF 1.2 (OMG schema, reqif validate, passthrough unchanged)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
