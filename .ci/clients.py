#!/usr/bin/env python3
"""Reads geodesic's files with the programs their users have (issue 52); run by .ci/clients.sh.

  clients.py junit JUNIT.xml junit-10.xsd   xmlschema, junitparser, xunitparser
  clients.py vcd vcd.csv vcd.xlsx            pandas (read_csv, read_excel), openpyxl
  clients.py schema DIR                      jsonschema: DIR/<command>.json against
                                             DIR/<command>.schema.json, for each command

Exit 1 with the reasons on the first file a client cannot read as it should.
"""
import sys


def fail(msg):
    print(f"clients: {msg}")
    sys.exit(1)


def junit(path, xsd):
    import xmlschema
    import junitparser
    import xunitparser

    schema = xmlschema.XMLSchema(xsd)
    errors = list(schema.iter_errors(path))
    if errors:
        for e in errors[:10]:
            print(f"  {e.reason} at {e.path}")
        fail(f"{path}: {len(errors)} error(s) against junit-10.xsd")
    xml = junitparser.JUnitXml.fromfile(path)
    cases, skipped, findings, failed, ids = 0, 0, 0, 0, 0
    for suite in xml:
        for case in suite:
            cases += 1
            out = case.system_out or ""
            kinds = {type(r).__name__ for r in case.result}
            if "Skipped" in kinds:
                skipped += 1
                if out.startswith("compliant with findings"):
                    fail(f"{case.name}: compliant with findings reported as skipped")
            if "Failure" in kinds:
                failed += 1
            if out.startswith("compliant with findings"):
                findings += 1
            if "requirement: " in out:
                ids += 1
    if cases == 0 or ids == 0:
        fail(f"{path}: junitparser read {cases} test cases, {ids} naming a requirement")
    with open(path) as f:
        ts, tr = xunitparser.parse(f)
    if tr.testsRun != cases:
        fail(f"{path}: xunitparser ran {tr.testsRun} test cases, junitparser {cases}")
    print(
        f"junit: {path} valid against junit-10.xsd; junitparser: {cases} cases, {failed} failed, "
        f"{skipped} skipped (not verified or a test not run), {findings} compliant with findings "
        f"(passes); xunitparser: {tr.testsRun} run, {len(tr.failures)} failures, "
        f"{len(tr.skipped)} skipped"
    )


def vcd(csv_path, xlsx_path):
    import openpyxl
    import pandas as pd

    with open(csv_path, "rb") as f:
        if not f.read(3) == b"\xef\xbb\xbf":
            fail(f"{csv_path}: no UTF-8 byte-order mark")
    numeric = ["value", "limit", "margin"]
    for name, df in [
        (csv_path, pd.read_csv(csv_path)),
        (xlsx_path, pd.read_excel(xlsx_path, sheet_name="VCD", engine="openpyxl")),
    ]:
        if df.columns[0] != "id":
            fail(f"{name}: first column {df.columns[0]!r}, not 'id'")
        for col in numeric:
            if not pd.api.types.is_float_dtype(df[col]):
                fail(f"{name}: column {col} is {df[col].dtype}, not numbers")
            if df[col].notna().sum() == 0:
                fail(f"{name}: column {col} has no number")
        if "unit" not in df.columns or df["unit"].dropna().empty:
            fail(f"{name}: no unit column")
        print(
            f"vcd: {name}: pandas reads {len(df)} rows; value, limit, margin as numbers "
            f"({df['value'].notna().sum()}, {df['limit'].notna().sum()}, "
            f"{df['margin'].notna().sum()} given)"
        )
    ws = openpyxl.load_workbook(xlsx_path, read_only=True)["VCD"]
    rows = ws.iter_rows(values_only=True)
    header = list(next(rows))
    idx = [header.index(c) for c in numeric]
    for r in rows:
        for i in idx:
            if r[i] is not None and not isinstance(r[i], (int, float)):
                fail(f"{xlsx_path}: {header[i]} cell {r[i]!r} is not a number (openpyxl)")
    print(f"vcd: {xlsx_path}: openpyxl reads value, limit and margin as number cells")


def schema(folder):
    """Each recorded `geodesic COMMAND --json` document in `folder` (COMMAND.json) against the
    schema `geodesic schema COMMAND` printed (COMMAND.schema.json), draft 2020-12, with the
    `jsonschema` package: the schema itself checked against the draft's metaschema, then the
    document; each error named by command, JSON path and cause."""
    import json
    import os
    import jsonschema

    docs = sorted(f[: -len(".json")] for f in os.listdir(folder)
                  if f.endswith(".json") and not f.endswith(".schema.json"))
    if not docs:
        fail(f"{folder}: no recorded document")
    bad = 0
    for name in docs:
        command = name.split(".")[0]
        with open(os.path.join(folder, f"{command}.schema.json")) as f:
            sch = json.load(f)
        with open(os.path.join(folder, f"{name}.json")) as f:
            doc = json.load(f)
        jsonschema.Draft202012Validator.check_schema(sch)
        errors = sorted(jsonschema.Draft202012Validator(sch).iter_errors(doc),
                        key=lambda e: list(e.absolute_path))
        for e in errors[:10]:
            print(f"  {command}: {e.json_path}: {e.message[:300]}")
        if errors:
            bad += 1
            print(f"schema: {name}.json: {len(errors)} error(s) against `geodesic schema {command}`")
        else:
            print(f"schema: {name}.json valid against `geodesic schema {command}` (draft 2020-12)")
    if bad:
        fail(f"{bad} of {len(docs)} recorded documents do not match their command's schema")


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "junit":
        junit(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 4 and sys.argv[1] == "vcd":
        vcd(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 3 and sys.argv[1] == "schema":
        schema(sys.argv[2])
    else:
        fail(__doc__)
