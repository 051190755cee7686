"""The second-order indices' intervals with the posterior (the default) and the blocks
(`interval="blocks"`): at a fixed N, the share of pairs inside their own interval and
the mean half-width over the seeds; to a tolerance, the median evaluations and the
share of runs whose every pair lay within it. The models and closed forms are
benches/sensitivity_second.py's (SALib's side is in results/sensitivity/second).

    PYTHONPATH=benches python results/sensitivity/posterior/second_check.py [--bases 1024,4096,16384] [--reps 20] [--tol 0.01]
"""

import argparse

import numpy as np
import stillpoint as sp

from sensitivity_second import models, upper

ap = argparse.ArgumentParser()
ap.add_argument("--bases", default="1024,4096,16384")
ap.add_argument("--reps", type=int, default=20)
ap.add_argument("--tol", type=float, default=0.01)
a = ap.parse_args()
for name, f, d, lo, hi, _, second in models():
    for n_base in [int(x) for x in a.bases.split(",")]:
        line = f"{name:20s} N={n_base:6d}"
        for interval in ("posterior", "blocks"):
            inside, hw = [], []
            for seed in range(a.reps):
                r = sp.sobol_indices(f, d, a=lo, b=hi, abs_tol=0.0, second_order=True,
                                     seed=seed, interval=interval,
                                     max_n=n_base * (2 * d + 2) + 8 * d)
                s2, h2 = upper(r.second), upper(r.second_half_width)
                inside.append(np.abs(s2 - second) <= h2)
                hw.append(h2)
            line += f"  {interval}: cover {np.mean(inside):.3f} mean_hw {np.mean(hw):.2e}"
        print(line, flush=True)
    if d > 8:
        continue
    line = f"{name:20s} tol={a.tol}"
    for interval in ("posterior", "blocks"):
        ns, within = [], []
        for seed in range(a.reps):
            r = sp.sobol_indices(f, d, a=lo, b=hi, abs_tol=a.tol, second_order=True,
                                 seed=seed, interval=interval)
            ns.append(r.n)
            within.append(bool(r.met and np.all(np.abs(upper(r.second) - second) <= a.tol)))
        line += f"  {interval}: median n {np.median(ns):.0f} all within {np.mean(within):.2f}"
    print(line, flush=True)
