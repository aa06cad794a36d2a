#!/usr/bin/env python3
"""Reference values for geodesic_core::stats, computed with SciPy (independent of the Rust code).

    python3 -m venv target/stats-venv && target/stats-venv/bin/pip install scipy
    target/stats-venv/bin/python verification/core/tests/stats_reference.py \
        > verification/core/tests/stats_reference.json

The values are committed; verification/core/tests/stats.rs checks the Rust functions against
them. Generated with SciPy 1.17.1 (scipy.stats.binom, scipy.stats.beta).
"""
import json

import numpy as np
from scipy import stats


def upper_rank(n, p, c):
    """Smallest 1-based rank k with P(Bin(n, p) <= k - 1) >= c, or None."""
    k = np.arange(1, n + 1)
    ok = stats.binom.cdf(k - 1, n, p) >= c
    return int(k[ok][0]) if ok.any() else None


def lower_rank(n, p, c):
    """Largest 1-based rank k with P(Bin(n, p) >= k) >= c, or None."""
    k = np.arange(1, n + 1)
    ok = stats.binom.sf(k - 1, n, p) >= c
    return int(k[ok][-1]) if ok.any() else None


cases = []
for n, p, c in [
    (10, 0.9973, 0.95), (200, 0.9973, 0.95), (1108, 0.9973, 0.95), (1109, 0.9973, 0.95),
    (2000, 0.9973, 0.95), (10_000, 0.9973, 0.95), (100_000, 0.9973, 0.95),
    (100_000, 0.9973, 0.99), (100_000, 0.5, 0.95), (1000, 0.9, 0.9), (59, 0.95, 0.95),
    (300, 0.95445, 0.95),
]:
    cases.append({"n": n, "p": p, "c": c, "upper_rank": upper_rank(n, p, c),
                  "lower_rank": lower_rank(n, p, c)})

proportions = []
for k, n, c in [
    (32, 32, 0.95), (31, 32, 0.95), (30, 32, 0.95), (29, 32, 0.95), (26, 32, 0.95),
    (200, 200, 0.95), (99_990, 100_000, 0.95), (99_730, 100_000, 0.95), (0, 50, 0.95),
    (5, 10, 0.9), (1, 1000, 0.99),
]:
    lo = 0.0 if k == 0 else float(stats.beta.ppf(1 - c, k, n - k + 1))
    hi = 1.0 if k == n else float(stats.beta.ppf(c, k + 1, n - k))
    proportions.append({"k": k, "n": n, "c": c, "lower": lo, "upper": hi})

cdfs = []
for k, n, p in [(269, 100_000, 0.0027), (300, 100_000, 0.0027), (99_700, 100_000, 0.9973),
                (99_750, 100_000, 0.9973), (49_900, 100_000, 0.5), (5, 1109, 0.0027),
                (1106, 1109, 0.9973)]:
    cdfs.append({"k": k, "n": n, "p": p, "cdf": float(stats.binom.cdf(k, n, p)),
                 "sf": float(stats.binom.sf(k - 1, n, p))})

print(json.dumps({"scipy": __import__("scipy").__version__, "quantile_ranks": cases,
                  "clopper_pearson": proportions, "binomial": cdfs}, indent=1))
