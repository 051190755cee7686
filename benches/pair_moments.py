#!/usr/bin/env python3
"""Why the deterministic default integrates the product-peak and Gaussian families worse
than scrambled Sobol' at high s: its two-dimensional moments of degree 2.

For a set x and two coordinates i < j, the error of the rule on the product of shifted
Legendre polynomials P_a(x_i) P_b(x_j) (P_1 = sqrt(3)(2x - 1), P_2 = sqrt(5)(6x^2 - 6x + 1),
each of mean 0 and variance 1) is the mean of that product over the points. This script
reports, per cell, the mean over the pairs of coordinates of |error| for (a, b) = (1, 1)
("linear"), (1, 2) and (2, 1) ("mixed") and (2, 2) ("quadratic"), for the default set,
the tent set of `--randomize` (mean over 16 randomisations) and scrambled Sobol' (mean over
16 seeds). The L2 discrepancies the default lowers weigh the linear products far more than
the quadratic ones; integrands such as Genz's product peak and Gaussian, whose every
factor varies like (x - u)^2, need both.

    target/py-venv/bin/python benches/pair_moments.py            # s 8-20, n 128-1024
    target/py-venv/bin/python benches/pair_moments.py --cells 20:1024,15:512

Needs the package installed in the venv (./test.sh does it), numpy and scipy. Writes
results/pair-moments/pair_moments.md.
"""

import argparse
import os

import numpy as np
from scipy.stats import qmc

import stillpoint as sp

CELLS = [(s, n) for s in (8, 10, 15, 20) for n in (128, 256, 512, 1024)]


def moments(x):
    """Mean |error| over coordinate pairs of the linear, mixed and quadratic products."""
    p1 = np.sqrt(3.0) * (2.0 * x - 1.0)
    p2 = np.sqrt(5.0) * (6.0 * x * x - 6.0 * x + 1.0)
    n, s = x.shape
    off = ~np.eye(s, dtype=bool)
    upper = np.triu(off)
    linear = np.abs(p1.T @ p1 / n)[upper].mean()
    mixed = np.abs(p1.T @ p2 / n)[off].mean()
    quadratic = np.abs(p2.T @ p2 / n)[upper].mean()
    return np.array([linear, mixed, quadratic])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cells", help="s:n pairs, e.g. 20:1024,15:512")
    ap.add_argument("--out", default="results/pair-moments")
    args = ap.parse_args()
    cells = CELLS
    if args.cells:
        cells = [tuple(int(v) for v in c.split(":")) for c in args.cells.split(",")]
    md = ["# Two-dimensional moments of degree 1 and 2: mean |error| over coordinate pairs",
          "", "Command: `target/py-venv/bin/python benches/pair_moments.py"
          + (f" --cells {args.cells}" if args.cells else "") + "` (2 cores). Ratios are "
          "to scrambled Sobol's mean over 16 seeds (below 1 is better).", "",
          "| s | n | Sobol' linear | mixed | quadratic | default linear | mixed | quadratic "
          "| tent set linear | mixed | quadratic |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for s, n in cells:
        sob = np.mean([moments(qmc.Sobol(s, seed=k).random(n)) for k in range(16)], axis=0)
        default = moments(sp.generate(n, s))
        base = sp._core.tent_set(n, s)
        tent = np.mean([moments(sp._core.randomize(base, "tent", k)) for k in range(16)],
                       axis=0)
        row = (f"| {s} | {n} | " + " | ".join(f"{v:.2e}" for v in sob) + " | "
               + " | ".join(f"{v:.2f}" for v in default / sob) + " | "
               + " | ".join(f"{v:.2f}" for v in tent / sob) + " |")
        md.append(row)
        print(row, flush=True)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "pair_moments.md"), "w") as f:
        f.write("\n".join(md) + "\n")


if __name__ == "__main__":
    main()
