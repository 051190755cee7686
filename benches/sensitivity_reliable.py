"""Which reference is reliable to a tolerance: QMCPy's `CubQMCNetG(SensitivityIndices)`
(and, with --salib, SALib's doubling to its bootstrap half-widths) run to abs_tol over
--seeds seeds on every model of benches/sensitivity.py; a reference counts as reliable on
a model when at least 95 % of its runs end with every index within the tolerance of the
closed form (as stillpoint is held).

    PYTHONPATH=benches python benches/sensitivity_reliable.py --tol 0.02 --seeds 12 \
        --out results/sensitivity/reliable_qmcpy.csv

Writes one row per model and seed: evaluations, whether the reference's own bound met the
tolerance, the share of indices within it and whether all were.
"""

from __future__ import annotations

import argparse
import csv
import time

import numpy as np

from sensitivity import models, qmcpy_si, salib, share_within


def salib_to_tol(f, d, lo, hi, seed, tol, largest):
    n_base = 64
    while True:
        fs, ts, n, h = salib(f, d, lo, hi, n_base, seed=seed, conf=True)
        if h <= tol or n_base >= largest:
            return fs, ts, n, h
        n_base *= 2


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--tol", type=float, default=0.02)
    p.add_argument("--seeds", type=int, default=12)
    p.add_argument("--largest", type=int, default=2**17)
    p.add_argument("--salib", action="store_true")
    p.add_argument("--models", default="")
    p.add_argument("--out", required=True)
    a = p.parse_args()
    only = [m for m in a.models.split(",") if m]
    rows = []
    for name, f, d, lo, hi, exact in models():
        if only and name not in only:
            continue
        for seed in range(a.seeds):
            started = time.time()
            if a.salib:
                fs, ts, n, h = salib_to_tol(f, d, lo, hi, seed, a.tol, a.largest)
            else:
                fs, ts, n, h = qmcpy_si(f, d, lo, hi, seed=seed, tol=a.tol, largest=a.largest)
            share = share_within(fs, ts, exact, a.tol)
            rows.append({"model": name, "seed": seed, "tol": a.tol, "evals": n,
                         "met": bool(h <= a.tol), "share_within": share,
                         "all_within": bool(share == 1.0),
                         "seconds": round(time.time() - started, 2)})
            print(rows[-1], flush=True)
    with open(a.out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    for name in dict.fromkeys(r["model"] for r in rows):
        rs = [r for r in rows if r["model"] == name]
        print(f"{name:22s} median evals {int(np.median([r['evals'] for r in rs]))}  "
              f"runs all within {sum(r['all_within'] for r in rs)}/{len(rs)}  "
              f"indices within {np.mean([r['share_within'] for r in rs]):.0%}")


if __name__ == "__main__":
    main()
