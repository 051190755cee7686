#!/usr/bin/env python3
"""Why the lattice default misses two of the large-n benchmark's bounds, measured.

1. The discontinuous family (exp(a·x) on the box x1 <= w1, x2 <= w2): its error is the
   local discrepancy of the (x1, x2) projection at a random anchor. Per cell this prints
   the family's ratio to scrambled Sobol' (16 instances, seeds 1-3 against 16 sets), the
   ratio of the projection's L2-star discrepancy (the mean over all anchors), the box
   indicator alone, and the correlation of the two ratios over the cells.
2. The continuous family (kinks at random points) under `--randomize`: RMSE against n at
   s = 5 for the randomised lattice and for scrambled Sobol', with the fitted rates.
3. A family at one cell (`--cell S:N --family F`, the corner peak at (50, 100000) by
   default): the ratio per instance, with its spread over the Sobol' sets (bootstrap),
   and for each instance the largest part of its integral one point carries (the
   default's against the median and third quartile over the Sobol' sets), with that
   point's a·x and its rank by Σx; then the same share for the corner step's own test
   functions e^{-c Σx}. Whether the seeds make different sets is printed too (sorted rows
   compared): the default's seed may only reorder one set.

    target/bench-venv/bin/python benches/large_n_why.py --bin target/release/stillpoint
    target/bench-venv/bin/python benches/large_n_why.py --cell 50:100000 --family 2 --sobol 16
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


def one_family(binary, s, n, family, sobol_sets, tmp):
    inst = [(a, u) for (f, a, u) in genz_instances(s, 16, SEED) if f == family]
    exact = [genz_exact(family, a, u) for a, u in inst]

    def figures(x):
        values = [genz_value(family, a, u, x) for a, u in inst]
        err = np.array([(v.mean() - e) / abs(e) for v, e in zip(values, exact)])
        share = np.array([v.max() / (len(x) * abs(e)) for v, e in zip(values, exact)])
        top = [int(np.argmax(v)) for v in values]
        return err, share, top

    sets = []
    for k in (1, 2, 3):
        path = os.path.join(tmp, f"x{k}.npy")
        sets.append(ours(binary, n, s, k, [], path))
    rows = [x[np.lexsort(x.T[::-1])] for x in sets]
    print(f"seeds 1-3 make the same rows (in another order): "
          f"{all(np.array_equal(rows[0], r) for r in rows[1:])}")
    x = sets[0]
    d_err, d_share, d_top = figures(x)
    d_err = np.array([figures(y)[0] for y in sets])
    b = [figures(sobol(s, n, r)) for r in range(sobol_sets)]
    b_err = np.array([e for e, _, _ in b])
    b_share = np.array([sh for _, sh, _ in b])
    ratio = rms(d_err) / rms(b_err)
    rng = np.random.default_rng(0)
    boots = [rms(d_err) / rms(b_err[rng.integers(0, sobol_sets, sobol_sets)]) for _ in range(1000)]
    print(f"({s}, {n}) family {family}: ratio {ratio:.2f} (5-95 % over the Sobol' sets "
          f"{np.quantile(boots, 0.05):.2f}-{np.quantile(boots, 0.95):.2f})")
    sums = x.sum(axis=1)
    rank = np.empty(n, dtype=int)
    rank[np.argsort(sums)] = np.arange(n)
    print("instance | ratio | largest share: ours | Sobol' median | Sobol' q3 | its a·x | its rank by Σx")
    for i, (a, _) in enumerate(inst):
        r = np.sqrt(np.mean(d_err[:, i] ** 2)) / np.sqrt(np.mean(b_err[:, i] ** 2))
        k = d_top[i]
        print(f"{i:8d} | {r:5.2f} | {d_share[i]:.3f} | {np.median(b_share[:, i]):.3f} | "
              f"{np.quantile(b_share[:, i], 0.75):.3f} | {x[k] @ a:.3f} | {rank[k]}")
    print(f"smallest Σx: ours {np.sort(sums)[:3].round(2)}")
    for c in (0.5, 1.0, 2.0, 4.0):
        whole = ((1 - np.exp(-c)) / c) ** s
        ours_share = np.exp(-c * sums).max() / (n * whole)
        theirs = [np.exp(-c * sobol(s, n, r).sum(axis=1)).max() / (n * whole)
                  for r in range(min(sobol_sets, 8))]
        print(f"e^(-{c} Σx): largest share ours {ours_share:.3f}, Sobol' median {np.median(theirs):.3f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default="target/release/stillpoint")
    ap.add_argument("--cell", default=None, help="S:N: only part 3 at this cell")
    ap.add_argument("--family", type=int, default=2, help="0-5 (2: corner peak)")
    ap.add_argument("--sobol", type=int, default=16, help="Sobol' sets of part 3")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "x.npy")
        if args.cell:
            s, n = (int(v) for v in args.cell.split(":"))
            one_family(args.bin, s, n, args.family, args.sobol, d)
            return
        print("## The discontinuous family and the (x1, x2) projection")
        discontinuous(args.bin, path)
        print("\n## The continuous family under --randomize, s = 5")
        continuous(args.bin, path)


if __name__ == "__main__":
    main()
