#!/usr/bin/env python3
"""Writes the lab-style variants of the public examples (data/examples/*.yaml + .csv) into
this folder: the same measurements as a lab delivers them. Run from anywhere:

    python3 data/examples/lab/make.py

Every number is the example's decimal with its exponent shifted (exact: Decimal.scaleb), so a
variant in ms and nm holds the same values as the example in s and m. Deterministic.
"""
import os
from decimal import Decimal

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.join(HERE, "..")


def rows(name):
    with open(os.path.join(SRC, name + ".csv")) as f:
        lines = f.read().splitlines()
    return lines[0].split(","), [l.split(",") for l in lines[1:]]


def shift(text, k):
    """The decimal `text` times 10^k, written plainly (`-6.3212200e-10`, 9 -> `-0.63212200`)."""
    d = Decimal(text).scaleb(k)
    s = format(d, "f")
    return s


def write(name, yaml, header, body):
    with open(os.path.join(HERE, name + ".yaml"), "w") as f:
        f.write(yaml)
    if header is not None:
        with open(os.path.join(HERE, name + ".csv"), "w") as f:
            f.write(header)
            for l in body:
                f.write(l + "\n")


def tmmf():
    _, data = rows("tmmf-adhesion")
    yaml = """# The public example tmmf-adhesion as a lab delivers it (data/examples/lab/make.py):
# time in ms, displacements in nm under the lab's own column names, another column order, an
# extra column, comment lines. Same measurements, same fit as ../tmmf-adhesion.yaml.
scenario: tmmf-release
description: TMMF release, intermediate TM mock-up, stiff blades, low residual load
data: tmmf-adhesion-lab.csv
time_column: Time [ms]
time_unit: ms
channels:
  x: {column: "TM displacement [nm]", unit: nm}
  y:
    column: Tip displacement [nm]
    unit: nm
known:
  m: 0.089          # kg
noise:              # 1 sigma, in each channel's unit (nm)
  x: 0.8
  y: 3
"""
    header = ("# TMMF campaign 2026-11, run 17: intermediate TM mock-up, stiff blades\n"
              "# interferometer (x) and DOSS (y) at 200 kHz, trigger at t = 0\n"
              "Tip displacement [nm],Time [ms],Chamber temperature [K],TM displacement [nm]\n")
    body = []
    for i, (t, x, y) in enumerate(data):
        if i == 200:
            body.append("# trigger armed")
        body.append(f"{shift(y, 9)},{shift(t, 3)},293.15,{shift(x, 9)}")
    write("tmmf-adhesion-lab", yaml, header, body)


def rt(name, what, edit):
    _, data = rows("rt-plunger")
    yaml = f"""# The public example rt-plunger as a lab delivers it (data/examples/lab/make.py): time in
# us, the tip in um under the vibrometer's column name, comment lines{what}.
scenario: rt-retraction
description: GPRM release tip retraction from 120 V, no contact, vibrometer at 1 MHz
data: {name}.csv
time_column: time (us)
time_unit: us
channels:
  y: {{column: "tip retraction (um)", unit: um}}
known:
  E0: 120           # V
noise:
  y: 0.001          # um
"""
    header = ("# GPRM tip retraction, vibrometer at 1 MHz, trigger at t = 0\n"
              "time (us),tip retraction (um)\n")
    body = [f"{shift(t, 6)},{shift(y, 6)}" for t, y in data]
    body = edit(body)
    write(name, yaml, header, body)
    return yaml


def missing(body):
    # line 402 of the CSV (two header lines, data row 400): the vibrometer dropped a sample
    t = body[399].split(",")[0]
    body[399] = f"{t},"
    return body


def wild(body):
    # line 302 of the CSV (data row 300): one sample of 1e24 um (1e18 m), a transmission error
    t = body[299].split(",")[0]
    body[299] = f"{t},1e24"
    return body


tmmf()
y = rt("rt-plunger-lab", "", lambda b: b)
rt("rt-plunger-missing", "; one empty cell (a dropped sample, line 402)", missing)
rt("rt-plunger-wild", "; one wild sample (a transmission error, line 302)", wild)
# a typo in a key: refused with its line and the nearest key
write("rt-plunger-typo", y.replace("noise:", "noize:").replace(
    "comment lines.", "comment lines;\n# a typo `noize:` (refused at line 13: did you mean `noise`?)."),
    None, None)
