"""Which reference is reliable to a tolerance: QMCPy's `CubQMCNetG(SensitivityIndices)`
(and, with --salib, SALib's doubling to its bootstrap half-widths) run to abs_tol over
--seeds seeds on every model of benches/sensitivity.py; a reference counts as reliable on
a model when at least 95 % of its runs end with every index within the tolerance of the
closed form (as stillpoint is held).

    PYTHONPATH=benches python benches/sensitivity_reliable.py --tol 0.02 --seeds 12 \
        --out results/sensitivity/reliable_qmcpy.csv

Writes one row per model and seed: evaluations, whether the reference's own bound met the
tolerance, the share of indices within it and whether all were. With --table, reads such
files (label=path, comma-separated) and prints per model each reference's median
evaluations and share of runs with every index within, the best reference and the best
reliable one, and stillpoint's evaluations over each (--ours model=evaluations,...):

    python benches/sensitivity_reliable.py --table \
        qmcpy=results/sensitivity/reliable_qmcpy.csv,salib=results/sensitivity/reliable_salib.csv \
        --ours ishigami=20504,...
"""

from __future__ import annotations

import argparse
import csv
import time

import numpy as np

from sensitivity import RELIABLE, models, qmcpy_si, salib, share_within


def salib_to_tol(f, d, lo, hi, seed, tol, largest):
    n_base = 64
    while True:
        fs, ts, n, h = salib(f, d, lo, hi, n_base, seed=seed, conf=True)
        if h <= tol or n_base >= largest:
            return fs, ts, n, h
        n_base *= 2


def table(inputs, ours):
    runs = {}
    for item in inputs.split(","):
        label, path = item.split("=")
        with open(path) as fh:
            for r in csv.DictReader(fh):
                runs.setdefault(r["model"], {}).setdefault(label, []).append(r)
    mine = dict((k, int(v)) for k, v in (x.split("=") for x in ours.split(",") if x))
    labels = [i.split("=")[0] for i in inputs.split(",")]
    head = ["model", "stillpoint"] + [f"{x} (runs all within)" for x in labels]
    head += ["best reference", "/ best", "best reliable reference", "/ best reliable"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for name, per in runs.items():
        cells, best, reliable = [], [], []
        for label in labels:
            rs = per.get(label, [])
            if not rs:
                cells.append("not run")
                continue
            met = [int(r["evals"]) for r in rs if r["met"] == "True"]
            share = np.mean([r["all_within"] == "True" for r in rs])
            median = int(np.median(met)) if met else None
            cells.append(f"{median} ({share:.0%} of {len(rs)})")
            if median is not None:
                best.append((median, label))
                if share >= RELIABLE and len(met) == len(rs):
                    reliable.append((median, label))
        ours_n = mine.get(name)

        def versus(c):
            if not c:
                return "none", "–"
            n, label = min(c)
            return f"{label} {n}", (f"{ours_n / n:.2f}" if ours_n else "–")

        b, r = versus(best), versus(reliable)
        print(f"| {name} | {ours_n or '–'} | " + " | ".join(cells) + f" | {b[0]} | {b[1]} | "
              f"{r[0]} | {r[1]} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--tol", type=float, default=0.02)
    p.add_argument("--seeds", type=int, default=12)
    p.add_argument("--largest", type=int, default=2**17)
    p.add_argument("--salib", action="store_true")
    p.add_argument("--models", default="")
    p.add_argument("--out")
    p.add_argument("--table", help="label=path,... of earlier runs: print the table")
    p.add_argument("--ours", default="", help="model=evaluations,... (with --table)")
    a = p.parse_args()
    if a.table:
        table(a.table, a.ours)
        return
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
