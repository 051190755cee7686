"""To abs_tol = 0.01 (the issue's default): stillpoint against SALib's Sobol' analysis
(base sample doubled from 64 until every bootstrap half-width is <= 0.01, charged its
last sample only, as in benches/sensitivity.py), on the benchmark's seven models.
SciPy is left out (its bootstrap reached 0.02 only on the linear model within its
memory limit), and QMCPy with --qmcpy only.

    PYTHONPATH=benches python results/sensitivity/tol001.py [--seeds 2] [--qmcpy]
"""

import argparse
import sys

import numpy as np

import sensitivity as B

p = argparse.ArgumentParser()
p.add_argument("--seeds", type=int, default=2)
p.add_argument("--largest", type=int, default=2**18)
p.add_argument("--qmcpy", action="store_true")
a = p.parse_args()
TOL = 0.01
print("model seed stillpoint_evals stillpoint_met stillpoint_within salib_evals salib_within"
      + (" qmcpy_evals qmcpy_within" if a.qmcpy else ""))
for name, f, d, lo, hi, exact in B.models():
    for seed in range(a.seeds):
        fs, ts, n, h, met = B.ours(f, d, lo, hi, tol=TOL, seed=seed)
        row = [name, seed, n, met, B.share_within(fs, ts, exact, TOL)]
        n_base, done = 64, False
        while n_base <= a.largest:
            sf, st, sn, sh = B.salib(f, d, lo, hi, n_base, seed=seed, conf=True)
            if sh <= TOL:
                done = True
                break
            n_base *= 2
        row += [sn if done else float("nan"), B.share_within(sf, st, exact, TOL)]
        if a.qmcpy:
            qf, qt, qn, qh = B.qmcpy_si(f, d, lo, hi, seed=seed, tol=TOL, largest=a.largest)
            row += [qn if qh <= TOL else float("nan"), B.share_within(qf, qt, exact, TOL)]
        print(" ".join(str(x) for x in row), flush=True)
