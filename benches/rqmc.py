#!/usr/bin/env python3
"""The randomised-QMC benchmark: error bars from independent randomisations of
stillpoint's sets against those of the randomised point sets users pick instead.

For every cell (s, n) it draws R independent randomisations of each set and integrates
Genz's six families (oscillatory, product peak, corner peak, Gaussian, continuous,
discontinuous) with parameters drawn at random for the cell (never tuned), then reports

  * the RMSE over the R replicates, per family, as a ratio to scrambled Sobol's
    (geometric mean over the family's instances; below 1 is better than Sobol');
  * the coverage of the 95 % intervals mean ± t·SE built from the R replicates, pooled
    over every instance of every cell;
  * the time to make one randomised set.

Sets, each randomised afresh per replicate:
  stillpoint tent   stillpoint.generate(n, s, randomize=True, seed=r): the lattice made
                    for the shift-and-tent randomisation, shifted and tent-transformed
  stillpoint cells  the default optimised set, randomise='cells' (the former advice)
  sobol             scipy.stats.qmc.Sobol(scramble=True) (Owen-type scrambling)
  halton            scipy.stats.qmc.Halton(scramble=True)
  lhs-cd            scipy.stats.qmc.LatinHypercube(optimization="random-cd")
  qmcpy-lat         qmcpy.Lattice (random shift; n not a power of two: the prefix of
                    its extensible sequence in Gray order)
  qmcpy-lat-tent    the same, then the tent transform x -> 1 - |2x - 1|

Then `scipy.integrate.qmc_quad` on smooth integrands with stillpoint.Engine(d) against
qmc.Sobol(d): the mean standard error over repetitions.

    target/py-venv/bin/python benches/rqmc.py            # 35 cells, R = 32 (~40 min, 2 cores)
    target/py-venv/bin/python benches/rqmc.py --quick    # 6 cells

Needs the package installed in the venv (./test.sh does it), numpy, scipy and qmcpy
(pip install qmcpy). Writes results/rqmc/rqmc.md and rqmc.json.
"""

import argparse
import json
import math
import os
import sys
import time
import warnings

import numpy as np
from scipy import stats
from scipy.integrate import qmc_quad
from scipy.stats import qmc

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from anchors import FAMILIES, genz_exact, genz_instances, genz_value  # noqa: E402
from fingerprint import commit, digest, section  # noqa: E402

import stillpoint as sp  # noqa: E402

S_FULL = [2, 3, 5, 8, 10, 15, 20]
N_FULL = [32, 100, 256, 500, 2048]
QUICK = [(2, 32), (3, 100), (5, 256), (8, 500), (10, 256), (20, 1024)]


def tent(x):
    return 1.0 - np.abs(2.0 * x - 1.0)


def makers(s, n):
    import qmcpy as qp

    power = n & (n - 1) == 0
    order = "RADICAL INVERSE" if power else "GRAY"
    default = sp.generate(n, s)

    def qmcpy_lattice(r):
        lat = qp.Lattice(dimension=s, randomize="SHIFT", seed=7000 + r, order=order)
        return lat.gen_samples(n_min=0, n_max=n)

    return {
        "stillpoint tent": lambda r: sp.generate(n, s, randomize=True, seed=1000 + r),
        "stillpoint cells": lambda r: sp._core.randomize(default, "cells", 2000 + r),
        "sobol": lambda r: qmc.Sobol(s, scramble=True, seed=3000 + r).random(n),
        "halton": lambda r: qmc.Halton(s, scramble=True, seed=4000 + r).random(n),
        "lhs-cd": lambda r: qmc.LatinHypercube(
            s, optimization="random-cd", seed=5000 + r
        ).random(n),
        "qmcpy-lat": qmcpy_lattice,
        "qmcpy-lat-tent": lambda r: tent(qmcpy_lattice(r)),
    }


def cell(s, n, reps, per_family):
    insts = genz_instances(s, per_family, seed=1_000_003 * s + n)
    exact = np.array([genz_exact(f, a, u) for f, a, u in insts])
    fam = np.array([f for f, _, _ in insts])
    tcrit = stats.t.ppf(0.975, reps - 1)
    out = {}
    for name, make in makers(s, n).items():
        est = np.empty((reps, len(insts)))
        seconds = 0.0
        for r in range(reps):
            t0 = time.perf_counter()
            x = make(r)
            seconds += time.perf_counter() - t0
            if r == 0 and name == "stillpoint tent":
                first = digest(x)
            assert x.shape == (n, s) and np.all((x >= 0) & (x <= 1)), name
            est[r] = [genz_value(f, a, u, x).mean() for f, a, u in insts]
        rmse = np.sqrt(((est - exact) ** 2).mean(axis=0))
        mean, se = est.mean(axis=0), est.std(axis=0, ddof=1) / math.sqrt(reps)
        covered = np.abs(mean - exact) <= tcrit * se
        out[name] = {"rmse": rmse, "covered": covered, "seconds": seconds / reps}
        if name == "stillpoint tent":
            out[name]["sha256"] = first
    ratios = {
        name: [
            float(np.exp(np.mean(np.log(v["rmse"][fam == f] / out["sobol"]["rmse"][fam == f]))))
            for f in range(len(FAMILIES))
        ]
        for name, v in out.items()
    }
    return out, ratios


def quad_table(reps):
    """qmc_quad's standard error with stillpoint.Engine against qmc.Sobol on smooth
    integrands: a Gaussian, a product peak and an oscillatory one with random
    parameters, each over `reps` repetitions of n_estimates = 8."""
    rows = []
    for d, n in [(3, 64), (6, 128), (10, 256), (5, 100), (15, 512)]:
        rng = np.random.default_rng(d * 100 + n)
        ratios = []
        for _ in range(reps):
            a = rng.uniform(0, 1, d)
            u = rng.uniform(0, 1, d)
            funcs = [
                lambda x, a=a * 7.03 / a.sum(), u=u: np.exp(-(((x.T - u) ** 2) @ (a**2))),
                lambda x, a=a * 7.25 / a.sum(), u=u: np.prod(
                    1.0 / (a[:, None] ** -2.0 + (x - u[:, None]) ** 2), axis=0
                ),
                lambda x, a=a * 9.0 / a.sum(), u=u: np.cos(2 * np.pi * u[0] + a @ x),
            ]
            seed = int(rng.integers(2**31))
            for f in funcs:
                ours = qmc_quad(f, np.zeros(d), np.ones(d), n_estimates=8, n_points=n,
                                qrng=sp.Engine(d, seed=seed))
                sob = qmc_quad(f, np.zeros(d), np.ones(d), n_estimates=8, n_points=n,
                               qrng=qmc.Sobol(d, seed=seed))
                ratios.append((ours.standard_error, sob.standard_error))
        r = np.array(ratios)
        # The ratio of the mean standard errors is dominated by a few large ones; the
        # geometric mean of the per-case ratios says how often and by how much.
        rows.append((d, n, float(r[:, 0].mean()), float(r[:, 1].mean()),
                     float(np.exp(np.mean(np.log(r[:, 0] / r[:, 1]))))))
    return rows


def write_report(record, out, command):
    """rqmc.md from the record (rqmc.json's content)."""
    names = list(record["cells"][0]["ratios"])
    md = ["# Randomised QMC: RMSE ratio to scrambled Sobol' (below 1 is better)", "",
          f"R = {record['reps']} randomisations per set, {record['per_family']} random "
          "instances per Genz family per cell; the ratio is the geometric mean over a "
          "family's instances of RMSE / scrambled Sobol's RMSE. Families: osc = "
          "oscillatory, prp = product peak, cor = corner peak, gau = Gaussian (smooth); "
          "con = continuous (a kink), dis = discontinuous.", "",
          f"Command: `{command}` (2 cores).", ""]
    short = ["osc", "prp", "cor", "gau", "con", "dis"]
    md.append("| s | n | set | " + " | ".join(short) + " |")
    md.append("|---|---|---|" + "---|" * len(short))
    for c in record["cells"]:
        for name in names:
            if name != "sobol":
                md.append(f"| {c['s']} | {c['n']} | {name} | "
                          + " | ".join(f"{x:.2f}" for x in c["ratios"][name]) + " |")
    md += ["", "## Summary over the cells", "",
           "| set | smooth family-cells at or below Sobol' | at or below the bar (Sobol' at "
           "n = 2^k, else the better of Sobol' and random-cd LHS) | coverage of 95 % "
           "intervals | seconds per set (mean) |", "|---|---|---|---|---|"]
    for name in names:
        w, b = record["wins"][name], record["bar_wins"][name]
        secs = np.mean([c["seconds"][name] for c in record["cells"]])
        md.append(f"| {name} | {w[0]}/{w[1]} | {b[0]}/{b[1]} | "
                  f"{100 * record['coverage'][name]:.1f} % | {secs:.4f} |")
    md += ["", f"## scipy.integrate.qmc_quad: standard errors (n_estimates = 8, "
           f"{record['quad_reps']} random instances of each of 3 integrands)", "",
           "| d | n | stillpoint.Engine mean SE | qmc.Sobol mean SE | ratio of the means | "
           "geometric mean of the ratios |", "|---|---|---|---|---|---|"]
    for d, n, a, b, g in record["qmc_quad"]:
        md.append(f"| {d} | {n} | {a:.3e} | {b:.3e} | {a / b:.2f} | {g:.2f} |")
    # The first randomisation of `stillpoint tent` per cell (seed 1000), as the command
    # line makes it.
    prints = [f"fingerprint: generate -n {c['n']} -s {c['s']} --randomize --seed 1000 "
              f"sha256:{c['sha256']}" for c in record["cells"] if "sha256" in c]
    if prints:
        md += [""] + section(record["commit"], record["command"], prints)
    with open(os.path.join(out, "rqmc.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    return md


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--reps", type=int, default=32)
    ap.add_argument("--per-family", type=int, default=16)
    ap.add_argument("--quad-only", action="store_true",
                    help="redo only the qmc_quad table of the record in --out")
    ap.add_argument("--quad-reps", type=int, default=40)
    ap.add_argument("--cells", default=None,
                    help="cells as s:n pairs, e.g. 15:32,20:64 (default: the full grid)")
    ap.add_argument("--out", default="results/rqmc")
    args = ap.parse_args()
    warnings.filterwarnings("ignore")
    command = "target/py-venv/bin/python benches/rqmc.py" + (" --quick" if args.quick else "") + (
        f" --cells {args.cells}" if args.cells else "")
    if args.quad_only:
        with open(os.path.join(args.out, "rqmc.json")) as f:
            record = json.load(f)
        record["qmc_quad"] = quad_table(args.quad_reps)
        record["quad_reps"] = args.quad_reps
        with open(os.path.join(args.out, "rqmc.json"), "w") as f:
            json.dump(record, f, indent=1)
        print("\n".join(write_report(record, args.out, command)[-8:]))
        return
    cells = QUICK if args.quick else [(s, n) for s in S_FULL for n in N_FULL]
    if args.cells:
        cells = [tuple(int(v) for v in c.split(":")) for c in args.cells.split(",")]
    names = None
    record = {"reps": args.reps, "per_family": args.per_family, "cells": [],
              "commit": commit(), "command": command}
    covered, seconds = {}, {}
    wins = {}
    # The issue's bar: at most Sobol's RMSE at n = 2^k, at most the better of Sobol' and
    # random-cd LHS at other n.
    bar_wins = {}
    for s, n in cells:
        t0 = time.time()
        out, ratios = cell(s, n, args.reps, args.per_family)
        names = list(out)
        for name, v in out.items():
            covered.setdefault(name, []).extend(v["covered"].tolist())
            seconds.setdefault(name, []).append(v["seconds"])
            smooth = ratios[name][:4]
            w = wins.setdefault(name, [0, 0])
            w[0] += sum(x <= 1.0 for x in smooth)
            w[1] += len(smooth)
            power = n & (n - 1) == 0
            bar = [1.0 if power else min(1.0, b) for b in ratios["lhs-cd"][:4]]
            b = bar_wins.setdefault(name, [0, 0])
            b[0] += sum(x <= y for x, y in zip(smooth, bar))
            b[1] += len(smooth)
        record["cells"].append({"s": s, "n": n, "ratios": ratios,
                                "seconds": {k: v["seconds"] for k, v in out.items()},
                                "sha256": out["stillpoint tent"]["sha256"]})
        print(f"s={s:2d} n={n:5d} ({time.time() - t0:5.1f} s)  " + "  ".join(
            f"{k}: " + " ".join(f"{x:.2f}" for x in r) for k, r in ratios.items()
            if k in ("stillpoint tent", "lhs-cd", "qmcpy-lat-tent")), flush=True)
    record["qmc_quad"] = quad_table(8 if args.quick else args.quad_reps)
    record["quad_reps"] = 8 if args.quick else args.quad_reps
    record["coverage"] = {k: float(np.mean(v)) for k, v in covered.items()}
    record["wins"] = wins
    record["bar_wins"] = bar_wins
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "rqmc.json"), "w") as f:
        json.dump(record, f, indent=1)
    md = write_report(record, args.out, command)
    print("\n".join(md[-(len(names) + 16):]))


if __name__ == "__main__":
    main()
