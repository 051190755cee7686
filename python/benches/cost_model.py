#!/usr/bin/env python3
"""Times of ``stillpoint.generate`` over a grid of (n, d), for the cost model of
``src/pipeline/estimate.rs`` (the estimate behind the long-call warning).

Runs each case once on one thread (``RAYON_NUM_THREADS=1`` unless set) and takes the
process's CPU time, which a shared machine's other work does not lengthen as it does
the wall time (the runs are deterministic; a repeat only measures the load). Prints one
JSON line per case, ``{"case", "n", "d", "seconds", "estimate"}``, the estimate being
the current model's for one thread. Cases whose estimate is above --limit seconds are
skipped. Refit the constants in estimate.rs from these lines when a pipeline's cost
changes.

Usage (with the package installed, e.g. by ``bash test.sh``):
    target/py-venv/bin/python python/benches/cost_model.py [--only default] [--limit 90]
"""

import argparse
import json
import os
import resource
import sys
import warnings

os.environ.setdefault("RAYON_NUM_THREADS", "1")

import stillpoint as sp  # noqa: E402
from stillpoint import _core  # noqa: E402

# (case, generate's keyword arguments); n and d vary as listed.
CASES = {
    "default": (
        {},
        [(n, d) for d in (2, 5, 20) for n in (256, 512, 1024, 2048, 4096, 8000, 12000)]
        + [(4097, 2), (6000, 2)]
        + [(10, 10**4), (10, 10**5), (10, 10**6), (100, 10**4), (100, 10**5)]
        + [(25000, 2), (25000, 5), (50000, 2)],
    ),
    "paper": (
        {"method": "paper"},
        [(n, d) for d in (2, 5) for n in (256, 512, 1024, 1500, 1600, 2048)],
    ),
    "space-filling": (
        {"goal": "space-filling"},
        [(n, d) for d in (2, 5) for n in (256, 512, 1024)],
    ),
    "region": (
        {"shape": "ball:1"},
        [(100, 2), (200, 2), (400, 2), (800, 2), (100, 3), (200, 3), (200, 5)],
    ),
    "baseline": (
        {"method": "lhs-maximin"},
        [(1000, 5), (4000, 5), (16000, 5)],
    ),
}


def cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--only", choices=sorted(CASES), action="append")
    ap.add_argument("--limit", type=float, default=90.0)
    args = ap.parse_args()
    # The long-call warning: these runs are long on purpose.
    warnings.simplefilter("ignore", RuntimeWarning)
    for case in args.only or list(CASES):
        kwargs, grid = CASES[case]
        for n, d in grid:
            est = _core.estimate(n=n, d=d, **kwargs)
            row = {"case": case, "n": n, "d": d, "estimate": round(est, 3)}
            if est > args.limit:
                row["seconds"] = None
            else:
                t = cpu_seconds()
                sp.generate(n, d, **kwargs)
                row["seconds"] = round(cpu_seconds() - t, 3)
            print(json.dumps(row), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
