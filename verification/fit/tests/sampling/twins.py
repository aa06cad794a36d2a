"""Regular, jittered (sd 10 % of the step after the trigger) and gapped (one sample in 7 after
the trigger and three holes left out) twins of a retraction record (piezo and a compliant
plunger, 1 MHz) and of a TMMF release (tip adhesion, 200 kHz, 10 ms), made by the independent
generator (../../../discover/tests/independent/generate.py) at their own time stamps (issue 50, item 5).

    python3 twins.py [N_RT [OUT]]   # N_RT samples of the retraction (default 3000), OUT: here
"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "..", "discover", "tests", "independent"))
import generate as g  # noqa: E402

out = sys.argv[2] if len(sys.argv) > 2 else HERE
def stamps(t, kind, h, seed):
    rng = np.random.Generator(np.random.PCG64(seed))
    if kind == "jittered":
        j = rng.standard_normal(len(t)) * 0.1 * h
        t2 = np.where(t > 0, t + j, t)
        return np.sort(t2)
    if kind == "gapped":
        keep = np.ones(len(t), bool)
        idx = np.arange(len(t))
        keep[(t > 0) & (idx % 7 == 3)] = False
        # and three long gaps
        for i0, k in [(len(t)//5, 40), (len(t)//2, 120), (4*len(t)//5, 15)]:
            keep[i0:i0+k] = False
        return t[keep]
    return t
n_rt = int(sys.argv[1]) if len(sys.argv) > 1 else 3000
q = dict(g.RT_NOM, Mg=0.019, Kg=2.15e6)
for kind in ["regular", "jittered", "gapped"]:
    fs = 1e6
    t = g.times(fs, 2e-5, (n_rt - 21) / fs)
    t = stamps(t, kind, 1/fs, 11)
    rng = np.random.Generator(np.random.PCG64(5))
    y = g.rt_truth(t, q, 120.0) + g.noise(rng, len(t), 1e-9)
    g.write_dataset(out, f"rt-{kind}", "rt-retraction", t, {"y": y}, {"E0": 120.0}, {"y": 1e-9}, f"rt {kind}")
    fs = 2e5
    p = dict(g.TMMF_BASE, A1=1.3e5, **{"lambda": 6e-7})
    t = g.times(fs, 1e-3, 9e-3)
    t = stamps(t, kind, 1/fs, 12)
    x = g.tmmf_reading(t, g.tmmf_truth(t, p, g.M_MID, g.JERK, g.V_TIP), p)
    yv = g.tip_profile(t, g.JERK, g.V_TIP)
    rng = np.random.Generator(np.random.PCG64(6))
    xn = x + g.noise(rng, len(t), 8e-10); yn = yv + g.noise(rng, len(t), 3e-9)
    g.write_dataset(out, f"tmmf-{kind}", "tmmf-release", t, {"x": xn, "y": yn}, {"m": g.M_MID}, {"x": 8e-10, "y": 3e-9}, f"tmmf {kind}")
    print(kind, flush=True)
