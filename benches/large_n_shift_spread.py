#!/usr/bin/env python3
"""How far one cell's ratio to scrambled Sobol' moves with the shift alone: the default's
set of a cell of the large-n grid (its generating vector and shift from the file's
header), then the same lattice under random odd shift numerators in every coordinate,
each integrated on the grid's instances (large_n.py's seed, 16 per family) against the
grid's 16 scrambled Sobol' sets.

    target/bench-venv/bin/python benches/large_n_shift_spread.py --cell 3:30000 \\
        --family "corner peak" --shifts 32

Prints the default's ratio, then the quartiles and range of the ratio over the random
shifts: where the default sits among shifts that differ in nothing else.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import large_n as grid  # noqa: E402


def header(path):
    with open(path) as f:
        for line in f:
            if line.startswith("# parameters:"):
                stage = json.loads(line.split(":", 1)[1])["stages"][0]
                return stage["generator"], stage["shift"]
    raise RuntimeError(f"{path}: no parameters line")


def tent_lattice(n, z, q):
    k = np.arange(n, dtype=np.int64)
    x = np.empty((n, len(z)))
    for j, (zj, qj) in enumerate(zip(z, q)):
        t = (4 * ((k * zj) % n) + qj) % (4 * n)
        x[:, j] = 1.0 - np.abs(2.0 * (t / (4.0 * n)) - 1.0)
    return x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default="target/release/stillpoint")
    ap.add_argument("--cell", required=True, help="s:n")
    ap.add_argument("--family", default="corner peak", choices=grid.FAMILIES)
    ap.add_argument("--shifts", type=int, default=32)
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args()
    (s, n), = grid.parse_cells(args.cell)
    fam = grid.FAMILIES.index(args.family)
    count = 16
    inst, exact = grid.instances(s, count)
    inst, exact = inst[fam * count:(fam + 1) * count], exact[fam * count:(fam + 1) * count]
    ref = np.array([grid.relative_errors(grid.sobol_set(s, n, r), inst, exact)
                    for r in range(grid.REPLICATES)])
    ref_rms = math.sqrt(float((ref ** 2).mean()))
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "set.csv")
        subprocess.run([args.bin, "generate", "-n", str(n), "-s", str(s), "--seed", "1",
                        "-q", "-o", path], check=True, capture_output=True)
        z, q = header(path)
    own = tent_lattice(n, z, q)
    e = grid.relative_errors(own, inst, exact)
    default = math.sqrt(float((e ** 2).mean())) / ref_rms
    rng = np.random.default_rng(args.seed)
    ratios = []
    for _ in range(args.shifts):
        qr = [int(2 * rng.integers(0, 2 * n) + 1) for _ in range(s)]
        e = grid.relative_errors(tent_lattice(n, z, qr), inst, exact)
        ratios.append(math.sqrt(float((e ** 2).mean())) / ref_rms)
    r = np.array(ratios)
    below = int((r < default).sum())
    print(f"({s}, {n}) {args.family}: z = {z}, q = {q}; Sobol' RMS {ref_rms:.3e}")
    print(f"  the default's shift: ratio {default:.3g}")
    print(f"  {args.shifts} random shifts: quartiles {np.percentile(r, 25):.3g} "
          f"{np.median(r):.3g} {np.percentile(r, 75):.3g}, range {r.min():.3g}-{r.max():.3g}, "
          f"geometric mean {math.exp(np.log(r).mean()):.3g}; {below} of them below the "
          "default's")


if __name__ == "__main__":
    main()
