#!/usr/bin/env python3
"""`--randomize` at one large-n cell, for several builds side by side: the RMS relative
error over R randomisations (seeds 1000..1000+R-1) on the large-n benchmark's Genz
instances (benches/large_n.py: 16 per family from seed 20261126), divided by the RMS of
16 scrambled Sobol' sets on the same instances.

    python3 benches/large_n_randomize.py --cell 50:16384 --reps 4 \
        --bins before=/path/to/old/stillpoint,after=target/release/stillpoint

Prints one line per build: oscillatory, product peak, corner peak, Gaussian, continuous,
discontinuous.
"""

import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import large_n as L  # noqa: E402


def randomized_rms(binary, s, n, reps, inst, exact):
    errs = []
    for r in range(reps):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "x.npy")
            subprocess.run([binary, "generate", "-n", str(n), "-s", str(s), "--randomize",
                            "--seed", str(1000 + r), "-o", path, "-q"], check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            errs.append(L.relative_errors(np.load(path), inst, exact))
    return L.family_rms(errs, L_COUNT)


L_COUNT = 16


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cell", default="50:16384", help='"s:n"')
    ap.add_argument("--reps", type=int, default=4)
    ap.add_argument("--bins", required=True, help="label=path,label=path")
    a = ap.parse_args()
    s, n = (int(v) for v in a.cell.split(":"))
    inst, exact = L.instances(s, L_COUNT)
    sobol = L.family_rms([L.relative_errors(L.sobol_set(s, n, r), inst, exact)
                          for r in range(16)], L_COUNT)
    print(f"({s}, {n}) --randomize, {a.reps} randomisations over 16 Sobol' sets "
          "(osc prod corner gauss cont disc)")
    for item in a.bins.split(","):
        label, path = item.split("=", 1)
        ratio = randomized_rms(path, s, n, a.reps, inst, exact) / sobol
        print(f"  {label}: " + " ".join(f"{x:.2f}" for x in ratio), flush=True)


if __name__ == "__main__":
    main()
