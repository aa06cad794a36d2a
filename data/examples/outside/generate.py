#!/usr/bin/env python3
"""Public example of physics outside the catalogue (issue 36): a TMMF release whose TM mock-up
feels a viscous damping force -c dx/dt, c = m gamma, which no effect of the catalogue holds.

Written by the independent generator of verification/discover/tests/independent/generate.py (NumPy and
SciPy from the equations of docs/spec/physics.md; it shares no code with geodesic's `synth` or
its effects): this script only calls it with the example's values and writes the answer file
`NAME.truth.json` in the form of the other public examples (data/examples/*.truth.json), with
`missing: null` (no catalogue effect is missing) and `outside` (the physics that is).

Usage: python3 data/examples/outside/generate.py [--out DIR]
Requires numpy and scipy (python3 -m venv target/pyenv && target/pyenv/bin/pip install numpy scipy).
The committed files were written with numpy 2.4.6 and scipy 1.17.1; a rerun reproduces them.
"""

import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "verification", "fit", "tests", "independent"))
import generate as g  # noqa: E402

NAME = "tmmf-damping"
GAMMA = 100.0  # damping rate [1/s]
SEED = 3601
FS, PRE, POST = 2e5, 1e-3, 9e-3  # sampling [Hz], before and after the trigger [s]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=HERE)
    out = ap.parse_args().out
    os.makedirs(out, exist_ok=True)
    m = g.M_MID
    p = dict(g.TMMF_BASE, c_damp=GAMMA * m)
    g.tmmf_record(out, NAME, SEED, p, fs=FS, pre=PRE, post=POST, m=m,
                  description=f"TMMF release with a viscous damping gamma = {GAMMA:g} 1/s "
                              "(outside the catalogue; issue 36's public example)")
    truth = {
        "dataset": NAME + ".yaml",
        "scenario": "tmmf-release",
        "baseline": ["needle_contact", "tip_contact"],
        "missing": None,
        "truth_effects": ["needle_contact", "tip_contact"],
        "params": {
            "needle_contact.k_nd": g.TMMF_BASE["k_nd"],
            "needle_contact.F_pre": g.TMMF_BASE["F_pre"],
            "tip_contact.k_c": g.TMMF_BASE["k_c"],
        },
        "outside": {
            "kind": "velocity",
            "law": "F = -m gamma dx/dt on the TM mock-up",
            "params": {"gamma": GAMMA, "c_damp": GAMMA * m},
            "units": {"gamma": "1/s", "c_damp": "N s/m"},
        },
        "noise": {"x": 8e-10, "y": 3e-9},
        "noise_in_yaml": True,
        "known": {"m": m},
        "sampling": {"fs_hz": FS, "pre_trigger_s": PRE, "post_trigger_s": POST},
        "tip_profile": {"v": g.V_TIP, "t1": (2.0 * g.V_TIP / g.JERK) ** 0.5, "jerk": g.JERK},
        "seed": SEED,
        "generator": "verification/discover/tests/independent/generate.py (tmmf_record), via data/examples/outside/generate.py",
        "note": "physics outside the catalogue: diagnose names no catalogue effect; "
                "discover --scaffold writes the damping effect (docs/loop.md)",
    }
    with open(os.path.join(out, NAME + ".truth.json"), "w") as f:
        json.dump(truth, f, indent=2)
        f.write("\n")
    print(f"wrote {NAME}.yaml, .csv and .truth.json to {out}")


if __name__ == "__main__":
    sys.exit(main())
