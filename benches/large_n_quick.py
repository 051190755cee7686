#!/usr/bin/env python3
"""One seed of the default against the scrambled Sobol' reference stored in a large-n
grid's large_n.json: the quick check of a change to the default at many cells.

With every shift tried, seeds 1-3 give the same set in the cells of s >= 5 checked, and
the Sobol' sets depend only on their seeds and SciPy's version, so the ratio printed is
the grid's own for that set without drawing the 16 Sobol' sets again.

    target/bench-venv/bin/python benches/large_n_quick.py --bin target/release/stillpoint \\
        --cells 20:1000,50:16384

Prints per cell the six families' ratios (oscillatory, product peak, corner peak,
Gaussian, continuous, discontinuous) of the binary's set, then the stored default's.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import large_n as grid  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default="target/release/stillpoint")
    ap.add_argument("--cells", required=True, help='"s:n,s:n"')
    ap.add_argument("--json", default="results/large-n/large_n.json")
    args = ap.parse_args()
    stored = json.load(open(args.json))["cells"]
    for s, n in grid.parse_cells(args.cells):
        inst, exact = grid.instances(s, 16)
        methods = stored[f"{s}:{n}"]["methods"]
        ref = np.array(methods["sobol"]["rms"])
        old = np.array(methods["default"]["rms"])
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "x.npy")
            subprocess.run([args.bin, "generate", "-n", str(n), "-s", str(s), "--seed", "1",
                            "-q", "-o", path], check=True, capture_output=True)
            e = grid.relative_errors(np.load(path), inst, exact)
        rms = np.sqrt((e.reshape(len(grid.FAMILIES), 16) ** 2).mean(axis=1))
        print(f"({s},{n}) new", " ".join(f"{v:.3g}" for v in rms / ref), "| stored",
              " ".join(f"{v:.3g}" for v in old / ref), flush=True)


if __name__ == "__main__":
    main()
