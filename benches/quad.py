"""Integration to a tolerance: `stillpoint.quad` against QMCPy's adaptive cubatures and
SciPy's `qmc_quad` with n doubled until its interval is narrow enough.

Per cell (Genz family, s, relative tolerance) and method, over RUNS runs (each a new
random instance of the family, benches/anchors.py's parameters, and a new seed): the
reliability (the share of runs whose true relative error is within the tolerance; a run
stopped by the budget of 2^20 evaluations counts as a failure) and the median number of
evaluations of f (every evaluation counted, including the rounds `qmc_quad` throws
away).

Methods:
- ``stillpoint``: ``stillpoint.quad(f, s, rel_tol=tol, seed=run)`` (8 shifts of the
  extensible lattice, Student t interval at 95 %).
- ``qmcpy-lattice``, ``qmcpy-net``: ``CubQMCLatticeG`` and ``CubQMCNetG`` at their
  defaults, with ``abs_tol=0`` and ``rel_tol=tol``.
- ``qmc_quad``: ``scipy.integrate.qmc_quad`` with 8 scrambled Sobol' estimates of n
  points, n = 64, 128, ... until t_{7,0.975}·standard error ≤ tol·|integral| (each round
  starts afresh).

QMCPy lives in its own environment, so the script runs once per environment and then
merges:

    target/py-venv/bin/python benches/quad.py --methods stillpoint,qmc_quad --runs 100
    target/bench-venv/bin/python benches/quad.py --methods qmcpy-lattice,qmcpy-net --runs 100
    target/py-venv/bin/python benches/quad.py --table

(target/bench-venv: ``python3 -m venv target/bench-venv && target/bench-venv/bin/pip
install qmcpy``.) The whole run takes a few minutes on 2 shared cores.

Writes results/quad/<method>.json and results/quad/quad.md.
"""

import argparse
import json
import math
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from anchors import genz_exact, genz_value  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FAMILIES = {0: "oscillatory", 1: "product peak"}
DIFFICULTY = {0: 9.0, 1: 7.25}
MAX_N = 2**20
T_7 = 2.3646242510102993  # t_{7, 0.975}


def instance(f, s, run):
    rng = np.random.default_rng([f, s, run, 37])
    a = rng.uniform(0, 1, s)
    a = a * DIFFICULTY[f] / a.sum()
    u = rng.uniform(0, 1, s)
    return a, u


def run_stillpoint(g, s, tol, seed):
    import stillpoint as sp

    r = sp.quad(g, s, rel_tol=tol, seed=seed, max_n=MAX_N)
    return r.estimate, r.n, r.met


def run_qmc_quad(g, s, tol, seed):
    from scipy.integrate import qmc_quad
    from scipy.stats import qmc

    total, n = 0, 64
    rng = np.random.default_rng(seed)
    while total + 8 * n <= MAX_N:
        # qmc_quad passes points as (s, n) and probes f once at the centre, (s,).
        res = qmc_quad(lambda x: g(x.T) if x.ndim == 2 else g(x[None, :])[0],
                       np.zeros(s), np.ones(s), n_estimates=8,
                       n_points=n, qrng=qmc.Sobol(s, scramble=True, rng=rng))
        total += 8 * n
        if T_7 * res.standard_error <= tol * abs(res.integral):
            return res.integral, total, True
        n *= 2
    return res.integral, total, False


def run_qmcpy(kind, g, s, tol, seed):
    import qmcpy as qp

    if kind == "lattice":
        dist, cub = qp.Lattice(s, seed=seed), qp.CubQMCLatticeG
    else:
        dist, cub = qp.DigitalNetB2(s, seed=seed), qp.CubQMCNetG
    integrand = qp.CustomFun(qp.Uniform(dist), g=g)
    c = cub(integrand, abs_tol=0.0, rel_tol=tol, n_limit=MAX_N)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sol, data = c.integrate()
    # QMCPy warns when the next doubling would pass n_limit and returns what it has.
    hit_max = any("Already generated" in str(w.message) for w in caught)
    return float(np.ravel(sol)[0]), int(np.ravel(data.n_total)[0]), not hit_max


METHODS = {
    "stillpoint": run_stillpoint,
    "qmc_quad": run_qmc_quad,
    "qmcpy-lattice": lambda g, s, tol, seed: run_qmcpy("lattice", g, s, tol, seed),
    "qmcpy-net": lambda g, s, tol, seed: run_qmcpy("net", g, s, tol, seed),
}


def measure(method, s_list, tols, runs):
    cells = []
    for f in FAMILIES:
        for s in s_list:
            for tol in tols:
                rows = []
                for run in range(runs):
                    a, u = instance(f, s, run)
                    exact = genz_exact(f, a, u)
                    calls = [0]

                    def g(x, f=f, a=a, u=u):
                        calls[0] += x.shape[0]
                        return genz_value(f, a, u, np.asarray(x, dtype=np.float64))

                    t0 = time.perf_counter()
                    est, n, met = METHODS[method](g, s, tol, run)
                    seconds = time.perf_counter() - t0
                    err = abs(est - exact) / abs(exact)
                    rows.append({"rel_error": float(f"{err:.3g}"), "n": int(n),
                                 "calls_n": calls[0], "met": bool(met),
                                 "seconds": round(seconds, 4),
                                 "ok": bool(met and err <= tol)})
                cells.append({"family": FAMILIES[f], "s": s, "tol": tol, "runs": rows})
                ok = np.mean([r["ok"] for r in rows])
                med = np.median([r["calls_n"] for r in rows])
                print(f"{method:14s} {FAMILIES[f]:13s} s={s} tol={tol:g}: "
                      f"reliability {ok:.2f}, median n {med:.0f}", flush=True)
    return cells


def table(out):
    data = {}
    for m in METHODS:
        path = os.path.join(out, f"{m}.json")
        if os.path.exists(path):
            with open(path) as fh:
                data[m] = json.load(fh)
    methods = list(data)
    lines = ["# Integration to a tolerance", "",
             "Reliability (share of runs with true relative error ≤ tol and the method "
             "saying it met the tolerance) and median evaluations of f, per cell "
             f"(runs per cell: {len(data[methods[0]]['cells'][0]['runs'])}). "
             "Written by `benches/quad.py` (commands in its docstring).", "",
             "| family | s | tol | " + " | ".join(methods) + " |",
             "|---|---|---|" + "---|" * len(methods)]
    for i, cell in enumerate(data[methods[0]]["cells"]):
        row = [cell["family"], str(cell["s"]), f"{cell['tol']:g}"]
        for m in methods:
            runs = data[m]["cells"][i]["runs"]
            ok = np.mean([r["ok"] for r in runs])
            med = np.median([r["calls_n"] for r in runs])
            row.append(f"{ok:.0%}, {med:.0f}")
        lines.append("| " + " | ".join(row) + " |")
    lines += ["", "Versions: " + ", ".join(f"{m}: {data[m]['version']}" for m in methods), ""]
    with open(os.path.join(out, "quad.md"), "w") as fh:
        fh.write("\n".join(lines))
    print("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--methods", default="stillpoint,qmc_quad")
    ap.add_argument("--s", default="2,5")
    ap.add_argument("--tols", default="1e-2,1e-3")
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--out", default=os.path.join(ROOT, "results", "quad"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.table:
        table(args.out)
        return
    s_list = [int(v) for v in args.s.split(",")]
    tols = [float(v) for v in args.tols.split(",")]
    for method in args.methods.split(","):
        if method.startswith("qmcpy"):
            import qmcpy

            version = f"qmcpy {qmcpy.__version__}"
        elif method == "stillpoint":
            import stillpoint

            version = f"stillpoint {stillpoint.__version__}"
        else:
            import scipy

            version = f"scipy {scipy.__version__}"
        cells = measure(method, s_list, tols, args.runs)
        with open(os.path.join(args.out, f"{method}.json"), "w") as fh:
            json.dump({"method": method, "version": version, "runs": args.runs,
                       "cells": cells}, fh, separators=(",", ":"))


if __name__ == "__main__":
    main()
