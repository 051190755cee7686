#!/usr/bin/env python3
"""Mixed design spaces: stillpoint's designs against the tools users have for them.

For each space and n, every design is written as a labelled CSV and measured by the
same code, ``stillpoint eval --json --var ...``: the largest excess of a level count
over ⌊n/L⌋..⌈n/L⌉, the same for level pairs of two unordered factors, the share of
(slice, continuous column) that is stratified, the centred L2 discrepancy of the
continuous part (overall and the mean over slices; on the unit scale, continuous
values through their CDF) and the smallest mixed distance. Randomised anchors are
means over seeds.

Anchors:
- SMT's mixed-integer LHS (``MixedIntegerSamplingMethod`` with LHS 'ese'), 8 seeds;
- SciPy's scrambled Sobol' with levels by flooring (``qmc.Sobol``; what
  ``integers``-style rounding gives), 16 seeds;
- OpenTURNS' LHS on the composed distribution (levels as ``UserDefined`` marginals),
  16 seeds.

Ours twice: the default (the integration goal) and ``--goal space-filling``.

Usage (needs numpy, scipy, smt and openturns in the interpreter; the binary built with
``cargo build --release``):

    python benches/design_spaces.py --bin target/release/stillpoint --out results/design-spaces
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import tempfile
import time

import numpy as np
from scipy import stats
from scipy.stats import qmc

# Each space: variables as --var writes them, and the sizes it is measured at.
SPACES = {
    "2 cont + int(1..5) + cat(3)": (
        ["x1=uniform(0,1)", "x2=uniform(0,1)", "k=int(1,5)", "c={a,b,c}"],
        [30, 60, 90, 150],
    ),
    "4 cont + cat(2) + cat(4)": (
        [
            "x1=uniform(0,1)",
            "x2=uniform(0,1)",
            "x3=uniform(0,1)",
            "x4=uniform(0,1)",
            "a={p,q}",
            "b={r,s,t,u}",
        ],
        [48, 96],
    ),
    "normal + lognormal + beta + cat(3)": (
        ["z=normal(0,1)", "w=lognormal(0,0.5)", "v=beta(2,5)", "c={a,b,c}"],
        [30, 90],
    ),
}


def parse(var: str):
    """(name, kind, parameters) of a --var text."""
    name, spec = var.split("=", 1)
    if spec.startswith("{"):
        return name, "cat", spec.strip("{}").split(",")
    func, args = spec.rstrip(")").split("(")
    return name, func, [float(a) for a in args.split(",")]


def marginal(kind, p):
    """The SciPy distribution of a continuous variable."""
    return {
        "uniform": lambda: stats.uniform(p[0], p[1] - p[0]),
        "normal": lambda: stats.norm(p[0], p[1]),
        "lognormal": lambda: stats.lognorm(s=p[1], scale=math.exp(p[0])),
        "beta": lambda: stats.beta(p[0], p[1]),
    }[kind]()


def from_unit(u: np.ndarray, variables):
    """Columns of a design from a unit-cube set: quantiles for continuous variables,
    flooring for levels (what scaling and rounding gives)."""
    cols = {}
    for j, var in enumerate(variables):
        name, kind, p = parse(var)
        x = np.clip(u[:, j], 0.0, 1.0 - 1e-12)
        if kind == "int":
            lo, hi = int(p[0]), int(p[1])
            cols[name] = (lo + np.floor(x * (hi - lo + 1))).astype(int)
        elif kind == "cat":
            cols[name] = [p[int(v)] for v in np.floor(x * len(p))]
        else:
            cols[name] = marginal(kind, p).ppf(np.clip(x, 1e-12, None))
    return cols


def write_csv(path, cols, variables):
    names = [parse(v)[0] for v in variables]
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        n = len(cols[names[0]])
        for i in range(n):
            cells = []
            for m in names:
                v = cols[m][i]
                cells.append(repr(float(v)) if isinstance(v, (float, np.floating)) else str(v))
            f.write(",".join(cells) + "\n")


def figures(binary, path, variables):
    args = [binary, "eval", "--json"]
    for v in variables:
        args += ["--var", v]
    out = subprocess.run(args + [path], check=True, capture_output=True, text=True).stdout
    f = json.loads(out)["figures"]
    slices = f["slices"]
    return {
        "level excess": max([l["excess"] for l in f["levels"]] or [0]),
        "pair excess": max([p["excess"] for p in f["pairs"]] or [0]),
        "slice strat": (
            sum(s["stratified"] for s in slices) / max(1, sum(s["columns"] for s in slices))
        ),
        "CD": f["centered_l2"],
        "slice CD": float(np.mean([c for s in slices for c in s["centered_l2"]])) if slices else float("nan"),
        "d_min": f["min_distance"],
    }


def rounded_columns(x, variables, continuous):
    """Columns of a design whose discrete columns hold level numbers (rounded to the
    nearest; a label's index) and whose continuous ones ``continuous(kind, p, column)``
    maps."""
    cols = {}
    for j, var in enumerate(variables):
        name, kind, p = parse(var)
        if kind == "int":
            cols[name] = np.round(x[:, j]).astype(int)
        elif kind == "cat":
            cols[name] = [p[int(round(v))] for v in x[:, j]]
        else:
            cols[name] = continuous(kind, p, x[:, j])
    return cols


def smt_design(variables, n, seed):
    from smt.applications.mixed_integer import MixedIntegerSamplingMethod
    from smt.design_space import (
        CategoricalVariable,
        DesignSpace,
        FloatVariable,
        IntegerVariable,
    )
    from smt.sampling_methods import LHS

    spec = []
    for var in variables:
        name, kind, p = parse(var)
        if kind == "int":
            spec.append(IntegerVariable(int(p[0]), int(p[1])))
        elif kind == "cat":
            spec.append(CategoricalVariable(p))
        else:
            # SMT samples boxes: the unit interval, then the marginal's quantiles.
            spec.append(FloatVariable(0.0, 1.0))
    space = DesignSpace(spec, seed=seed)
    sampling = MixedIntegerSamplingMethod(LHS, space, criterion="ese", seed=seed)
    x = sampling(n)
    # SMT's continuous columns are unit scores: the marginal's quantiles map them.
    return rounded_columns(
        x, variables, lambda kind, p, v: marginal(kind, p).ppf(np.clip(v, 1e-12, 1 - 1e-12))
    )


def openturns_design(variables, n, seed):
    import openturns as ot

    ot.RandomGenerator.SetSeed(seed)
    margins = []
    for var in variables:
        name, kind, p = parse(var)
        if kind == "int":
            values = [[float(k)] for k in range(int(p[0]), int(p[1]) + 1)]
            margins.append(ot.UserDefined(values))
        elif kind == "cat":
            margins.append(ot.UserDefined([[float(k)] for k in range(len(p))]))
        elif kind == "normal":
            margins.append(ot.Normal(p[0], p[1]))
        elif kind == "lognormal":
            margins.append(ot.LogNormal(p[0], p[1], 0.0))
        elif kind == "beta":
            margins.append(ot.Beta(p[0], p[1], 0.0, 1.0))
        else:
            margins.append(ot.Uniform(p[0], p[1]))
    x = np.array(ot.LHSExperiment(ot.JointDistribution(margins), n).generate())
    return rounded_columns(x, variables, lambda kind, p, v: v)


def sobol_design(variables, n, seed):
    u = qmc.Sobol(len(variables), scramble=True, seed=seed).random(n)
    return from_unit(u, variables)


def ours(binary, variables, n, path, goal="integration"):
    args = [binary, "generate", "-n", str(n), "-q", "--goal", goal, "-o", path]
    for v in variables:
        args += ["--var", v]
    t = time.perf_counter()
    subprocess.run(args, check=True, capture_output=True)
    return time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default="target/release/stillpoint")
    ap.add_argument("--out", default="results/design-spaces")
    ap.add_argument("--smt-seeds", type=int, default=8)
    ap.add_argument("--seeds", type=int, default=16)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    keys = ["level excess", "pair excess", "slice strat", "CD", "slice CD", "d_min"]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "d.csv")
        for label, (variables, sizes) in SPACES.items():
            for n in sizes:
                sets = {}
                t = ours(a.bin, variables, n, path)
                sets["stillpoint"] = (figures(a.bin, path, variables), t)
                t = ours(a.bin, variables, n, path, "space-filling")
                sets["stillpoint space-filling"] = (figures(a.bin, path, variables), t)
                anchors = [
                    ("SMT mixed LHS (ese)", smt_design, a.smt_seeds),
                    ("Sobol' + flooring", sobol_design, a.seeds),
                    ("OpenTURNS LHS", openturns_design, a.seeds),
                ]
                for name, make, seeds in anchors:
                    per = []
                    t0 = time.perf_counter()
                    for seed in range(seeds):
                        write_csv(path, make(variables, n, seed), variables)
                        per.append(figures(a.bin, path, variables))
                    mean = {k: float(np.mean([p[k] for p in per])) for k in keys}
                    mean["level excess"] = max(p["level excess"] for p in per)
                    mean["pair excess"] = max(p["pair excess"] for p in per)
                    sets[name] = (mean, (time.perf_counter() - t0) / seeds)
                for name, (f, t) in sets.items():
                    rows.append({"space": label, "n": n, "set": name, "seconds": t, **f})
                    print(
                        f"{label:36s} n={n:4d} {name:26s} "
                        + " ".join(f"{k}={f[k]:.4g}" for k in keys)
                        + f" t={t:.2f}s",
                        flush=True,
                    )
    with open(os.path.join(a.out, "design-spaces.json"), "w") as f:
        json.dump(rows, f, indent=1)
    lines = [
        "| space | n | set | level excess (max) | pair excess (max) | slices stratified | CD | mean slice CD | d_min | s |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['space']} | {r['n']} | {r['set']} | {r['level excess']} | {r['pair excess']} | "
            f"{r['slice strat']:.2f} | {r['CD']:.4f} | {r['slice CD']:.4f} | {r['d_min']:.4f} | {r['seconds']:.2f} |"
        )
    with open(os.path.join(a.out, "design-spaces.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
