#!/usr/bin/env python3
"""Why the lattice default misses two of the large-n benchmark's bounds, measured.

1. The discontinuous family (exp(a·x) on the box x1 <= w1, x2 <= w2): its error is the
   local discrepancy of the (x1, x2) projection at a random anchor. Per cell this prints
   the family's ratio to scrambled Sobol' (16 instances, seeds 1-3 against 16 sets), the
   ratio of the projection's L2-star discrepancy (the mean over all anchors), the box
   indicator alone, and the correlation of the two ratios over the cells.
2. The continuous family (kinks at random points) under `--randomize`: RMSE against n at
   s = 5 for the randomised lattice and for scrambled Sobol', with the fitted rates.

    target/bench-venv/bin/python benches/large_n_why.py --bin target/release/stillpoint
"""

import argparse
import os
import subprocess
import sys
import tempfile
import warnings

import numpy as np
from scipy.stats import qmc

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from anchors import genz_exact, genz_instances, genz_value  # noqa: E402

SEED = 20261126
CELLS = [(5, 1000), (5, 4096), (10, 1024), (10, 4096), (12, 7919), (15, 7919),
         (20, 1000), (20, 4096), (8, 2000), (3, 7919)]


def sobol(s, n, r):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return qmc.Sobol(s, scramble=True, seed=r).random(n)


def ours(binary, n, s, seed, extra, path):
    subprocess.run([binary, "generate", "-n", str(n), "-s", str(s), "--seed", str(seed),
                    "-o", path, "-q"] + extra, check=True, capture_output=True)
    return np.load(path)


def rms(v):
    return float(np.sqrt(np.mean(np.square(v))))


def discontinuous(binary, path):
    rows = []
    for s, n in CELLS:
        inst = [(a, u) for (f, a, u) in genz_instances(s, 16, SEED) if f == 5]
        exact = [genz_exact(5, a, u) for a, u in inst]

        def errors(x):
            fam = [(genz_value(5, a, u, x).mean() - e) / abs(e) for (a, u), e in zip(inst, exact)]
            box = [(((x[:, 0] <= u[0]) & (x[:, 1] <= u[1])).mean() - u[0] * u[1]) / (u[0] * u[1])
                   for a, u in inst]
            return np.array(fam), np.array(box), qmc.discrepancy(x[:, :2], method="L2-star")

        d = [errors(ours(binary, n, s, k, [], path)) for k in (1, 2, 3)]
        b = [errors(sobol(s, n, r)) for r in range(16)]
        ratio = [rms([x[i] for x in d]) / rms([x[i] for x in b]) for i in range(3)]
        rows.append(ratio)
        print(f"s = {s:2d}, n = {n:5d}: discontinuous {ratio[0]:.2f}, box alone {ratio[1]:.2f}, "
              f"L2-star of (x1, x2) {ratio[2]:.2f}", flush=True)
    r = np.log(np.array(rows))
    print(f"correlation of the log ratios (family, projection): {np.corrcoef(r[:, 0], r[:, 2])[0, 1]:.2f}")


def continuous(binary, path):
    s = 5
    inst = [(a, u) for (f, a, u) in genz_instances(s, 16, SEED) if f == 4]
    exact = [genz_exact(4, a, u) for a, u in inst]

    def errors(x):
        return np.array([(genz_value(4, a, u, x).mean() - e) / abs(e) for (a, u), e in zip(inst, exact)])

    ns = [1024, 4096, 16384]
    lat, sob = [], []
    for n in ns:
        lat.append(rms([errors(ours(binary, n, s, r + 1, ["--randomize"], path)) for r in range(8)]))
        sob.append(rms([errors(sobol(s, n, r)) for r in range(16)]))
        print(f"n = {n:5d}: randomised lattice {lat[-1]:.3e}, Sobol' {sob[-1]:.3e}, ratio {lat[-1] / sob[-1]:.2f}", flush=True)
    for name, y in (("randomised lattice", lat), ("scrambled Sobol'", sob)):
        print(f"{name}: RMSE ~ n^{np.polyfit(np.log(ns), np.log(y), 1)[0]:.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default="target/release/stillpoint")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "x.npy")
        print("## The discontinuous family and the (x1, x2) projection")
        discontinuous(args.bin, path)
        print("\n## The continuous family under --randomize, s = 5")
        continuous(args.bin, path)


if __name__ == "__main__":
    main()
