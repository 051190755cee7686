"""`stillpoint.quad` on integrands even under the reflection x ↦ 1 − x that benches/quad.py
does not hold, and on two that are not even, with this package and an earlier one: the
evaluations to a tolerance and the reliability, per integrand and tolerance.

Integrands on [0, 1]^s (closed forms; parameters drawn per seed):

- ``center gaussian``: exp(−Σ a_j (x_j − ½)²), a_j ~ U[1, 5], s = 6 (even);
- ``radial normal``: E cos(‖Z‖·c) for Z ~ N(0, I), c ~ U[0.1, 0.35], s = 8, written as
  cos(c‖Φ⁻¹(x)‖) (even; a radial model of normal inputs, like Keister's);
- ``abs product``: Π (1 + b_j |2x_j − 1|)/(1 + b_j/2), b_j ~ U[0, 1], s = 10 (even in
  every coordinate; exactly 1);
- ``bilinear``: 1 + Σ_{j<k} c_jk (x_j − ½)(x_k − ½), s = 5 (even under x ↦ 1 − x, odd
  under a single coordinate's reflection; exactly 1), with an added term so that the
  rule does not integrate it exactly: + d·Π cos(x_j − ½);
- ``shifted gaussian`` (not even): exp(−Σ a_j (x_j − u_j)²), u_j ~ U[0, 1], s = 6;
- ``exp sum`` (not even): exp(Σ w_j x_j), w_j ~ U[0, 1], s = 8.

A run is within the tolerance when its relative error is at most the tolerance and it
says it met it. Per cell: reliability and median evaluations over the seeds.

    target/py-venv/bin/python benches/quad_even.py --out results/quad/even-new.json
    /work/wt/before-venv/bin/python benches/quad_even.py --out results/quad/even-before.json
    python3 benches/quad_even.py --compare results/quad/even-before.json results/quad/even-new.json
"""

import argparse
import json
import math
import sys

import numpy as np

SEEDS = 50
TOLS = [1e-2, 1e-3, 1e-4]


def normal(x):
    from scipy.special import ndtri

    return ndtri(np.clip(x, 2.0 ** -53, 1 - 2.0 ** -53))


def case(name, seed):
    """(f, s, exact integral) of instance `seed`."""
    rng = np.random.default_rng([20261130, seed, sum(map(ord, name))])
    if name == "center gaussian":
        s = 6
        a = rng.uniform(1, 5, s)
        one = [math.sqrt(math.pi / aj) * math.erf(math.sqrt(aj) / 2) for aj in a]
        return (lambda x: np.exp(-((x - 0.5) ** 2) @ a)), s, float(np.prod(one))
    if name == "radial normal":
        s = 8
        c = rng.uniform(0.1, 0.35)
        from scipy import integrate
        from scipy.special import gammaln

        # E cos(c R), R the chi distribution with s degrees of freedom.
        log_norm = (1 - s / 2) * math.log(2) - gammaln(s / 2)
        val, _ = integrate.quad(
            lambda r: math.cos(c * r) * math.exp(log_norm + (s - 1) * math.log(r) - r * r / 2)
            if r > 0 else 0.0, 0, 40, epsabs=0, epsrel=1e-13, limit=400)
        return (lambda x: np.cos(c * np.sqrt(np.sum(normal(x) ** 2, axis=1)))), s, val
    if name == "abs product":
        s = 10
        b = rng.uniform(0, 1, s)
        return (lambda x: np.prod((1 + b * np.abs(2 * x - 1)) / (1 + b / 2), axis=1)), s, 1.0
    if name == "bilinear":
        s = 5
        c = rng.uniform(-1, 1, (s, s))
        c = np.triu(c, 1)
        d = rng.uniform(0.5, 1)

        def f(x):
            y = x - 0.5
            return 1 + np.einsum("ij,jk,ik->i", y, c, y) + d * np.prod(np.cos(y), axis=1)

        return f, s, 1 + d * (2 * math.sin(0.5)) ** s
    if name == "shifted gaussian":
        s = 6
        a = rng.uniform(1, 5, s)
        u = rng.uniform(0, 1, s)
        one = [math.sqrt(math.pi / aj) / 2 * (math.erf(math.sqrt(aj) * (1 - uj))
                                              + math.erf(math.sqrt(aj) * uj))
               for aj, uj in zip(a, u)]
        return (lambda x: np.exp(-((x - u) ** 2) @ a)), s, float(np.prod(one))
    if name == "exp sum":
        s = 8
        w = rng.uniform(0, 1, s)
        return (lambda x: np.exp(x @ w)), s, float(np.prod(np.expm1(w) / w))
    raise ValueError(name)


CASES = ["center gaussian", "radial normal", "abs product", "bilinear",
         "shifted gaussian", "exp sum"]


def measure(seeds):
    import stillpoint as sp

    out = {"version": getattr(sp, "__version__", "?"), "cells": {}}
    for name in CASES:
        for tol in TOLS:
            rows = []
            for seed in range(seeds):
                f, s, exact = case(name, seed)
                r = sp.quad(f, s, rel_tol=tol, seed=seed)
                err = abs(float(r.estimate) - exact) / abs(exact)
                rows.append({"n": int(r.n), "ok": bool(r.met and err <= tol),
                             "reason": str(r.rule_reason)})
            ok = np.mean([r["ok"] for r in rows])
            med = float(np.median([r["n"] for r in rows]))
            halved = np.mean(["one point of each pair" in r["reason"] for r in rows])
            out["cells"][f"{name}|{tol:g}"] = {"reliability": float(ok), "median_n": med,
                                               "halved": float(halved)}
            print(f"{name:17s} tol={tol:g}: reliability {ok:.2f}, median n {med:.0f}, "
                  f"halved in {halved:.0%} of runs", flush=True)
    return out


def compare(before, new):
    a, b = (json.load(open(p)) for p in (before, new))
    print("| integrand | tol | before: reliable · median n | now: reliable · median n | "
          "halved | ratio |")
    print("|---|---|---|---|---|---|")
    for k, c in b["cells"].items():
        o = a["cells"][k]
        name, tol = k.split("|")
        print(f"| {name} | {tol} | {o['reliability']:.0%} · {o['median_n']:.0f} | "
              f"{c['reliability']:.0%} · {c['median_n']:.0f} | {c['halved']:.0%} | "
              f"{c['median_n'] / o['median_n']:.2f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out")
    ap.add_argument("--seeds", type=int, default=SEEDS)
    ap.add_argument("--compare", nargs=2, metavar=("BEFORE", "NEW"))
    args = ap.parse_args()
    if args.compare:
        compare(*args.compare)
        return
    data = measure(args.seeds)
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(data, fh, indent=1)


if __name__ == "__main__":
    sys.exit(main())
