"""`stillpoint.quad` on integrands benches/quad.py does not hold, with this package and an
earlier one: the evaluations to a tolerance, the reliability and how often an interval
that claims the tolerance misses it, per integrand and tolerance.

``--group even``: integrands even under the reflection x ↦ 1 − x, and two that are not
(parameters drawn per seed; closed forms):

- ``center gaussian``: exp(−Σ a_j (x_j − ½)²), a_j ~ U[1, 5], s = 6 (even);
- ``radial normal``: E cos(c‖Z‖) for Z ~ N(0, I), c ~ U[0.1, 0.35], s = 8, written as
  cos(c‖Φ⁻¹(x)‖) (even; a radial model of normal inputs, like Keister's);
- ``abs product``: Π (1 + b_j |2x_j − 1|)/(1 + b_j/2), b_j ~ U[0, 1], s = 10 (even in
  every coordinate; exactly 1);
- ``bilinear``: 1 + Σ_{j<k} c_jk (x_j − ½)(x_k − ½) + d·Π cos(x_j − ½), s = 5 (even under
  x ↦ 1 − x, odd under a single coordinate's reflection);
- ``shifted gaussian`` (not even): exp(−Σ a_j (x_j − u_j)²), u_j ~ U[0, 1], s = 6;
- ``exp sum`` (not even): exp(Σ w_j x_j), w_j ~ U[0, 1], s = 8.

``--group steps``: integrands of few values (the same for every seed; the seed moves the
randomisation), where a lattice's replicate means move in lumps:

- ``even step``: 1 + 1{|x1 − ½| < 0.3}, s = 3 (1.6);
- ``step``: 1 + 1{|x1 − 0.45| < 0.3}, s = 3 (1.6);
- ``two steps``: 1{x1 < 0.37} + 1{x2 > 0.71}, s = 2 (0.66);
- ``half-plane event``: 1{x1 + x2 < 0.8}, s = 4 (0.32);
- ``ball event``: 1{‖x − ½‖ < 0.4}, s = 3 (4π·0.4³/3 = 0.268);
- ``count``: the number of j with x_j < 0.2, s = 6 (1.2; seven values).

``--group laws``: models of inputs with unbounded laws, through ``space=`` (parameters
drawn per seed; closed forms), three even under Z ↦ −Z, where the probe round keeps its
lattice, and three that are not, where it leaves for scrambled Sobol':

- ``radial norm``: E‖Z‖, Z ~ N(0, I), s = 6 (even; a cone at the origin);
- ``bump``: E exp(−Σ b_j Z_j²) = Π (1 + 2b_j)^−½, b_j ~ U[0.1, 1], s = 8 (even);
- ``quadratic form``: E (1 + ZᵀCZ) = 1 + tr C, C a random symmetric matrix with
  positive diagonal, s = 5 (even);
- ``lognormal sum`` (not even): E Σ w_j X_j with X_j ~ lognormal(0, σ_j), w_j ~ U[0, 1],
  σ_j ~ U[0.2, 0.6], s = 6;
- ``call on a sum`` (not even): E max(Σ Z_j/√s − k, 0) = φ(k) − k(1 − Φ(k)),
  k ~ U[0, 0.5], s = 8;
- ``quadratic with a slope`` (not even): E Π (1 + a_j Z_j + c_j Z_j²) = Π (1 + c_j),
  a_j, c_j ~ U[0, 0.3], s = 4.

``--group faces``: integrands on the cube whose derivative is unbounded at a face, where
the face test gives the lattice of the first-order table, and two smooth ones, where it
keeps the tent lattice (parameters drawn per seed; closed forms):

- ``root product``: Π (1 + α_j) x_j^α_j, α_j ~ U[0.1, 0.6], s = 5 (exactly 1);
- ``log sum``: 1 − Σ w_j log x_j, w_j ~ U[0, 1]/s, s = 6 (1 + Σ w_j);
- ``normal scores``: Π (1 + c_j Φ⁻¹(x_j)²)/(1 + c_j), c_j ~ U[0, 0.5], s = 6 (exactly 1;
  even under x ↦ 1 − x);
- ``exp of scores`` (a lognormal model written on the cube): exp(Σ σ_j Φ⁻¹(x_j) − Σ σ_j²/2),
  σ_j ~ U[0.1, 0.4], s = 8 (exactly 1);
- ``shifted gaussian`` and ``exp sum`` as in ``--group even`` (smooth).

With ``--rule NAME`` every run asks for that rule (``--rule lattice``: the tent lattice
alone, the rule over the cube before the face test; measured with the same package).

A run is reliable when it says it met the tolerance and its relative error is within
it; "wrong" counts runs that say so and are not within it; "covered" runs whose interval
holds the integral. With BEFORE a virtual environment holding an earlier package:

    target/py-venv/bin/python benches/quad_unnamed.py --group even --out results/quad/even/new.json
    $BEFORE/bin/python benches/quad_unnamed.py --group even --out results/quad/even/before.json
    target/py-venv/bin/python benches/quad_unnamed.py --compare results/quad/even/before.json results/quad/even/new.json

(``--group steps`` and results/quad/steps/, ``--group laws`` and results/quad/probe/ alike;
``--group faces`` and results/quad/face/ with ``--rule lattice`` for the earlier rule.)
"""

import argparse
import json
import math
import sys

import numpy as np

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
    if name == "root product":
        s = 5
        a = rng.uniform(0.1, 0.6, s)
        return (lambda x: np.prod((1 + a) * x ** a, axis=1)), s, 1.0
    if name == "log sum":
        s = 6
        w = rng.uniform(0, 1, s) / s
        return (lambda x: 1 - np.log(x) @ w), s, 1 + float(np.sum(w))
    if name == "normal scores":
        s = 6
        c = rng.uniform(0, 0.5, s)
        return (lambda x: np.prod((1 + c * normal(x) ** 2) / (1 + c), axis=1)), s, 1.0
    if name == "exp of scores":
        s = 8
        sig = rng.uniform(0.1, 0.4, s)
        return (lambda x: np.exp(normal(x) @ sig - np.sum(sig ** 2) / 2)), s, 1.0
    raise ValueError(name)


def law_case(name, seed):
    """(f on the space's values, s, space texts, exact integral) of instance `seed`."""
    rng = np.random.default_rng([20261130, seed, sum(map(ord, name))])
    normals = lambda s: [f"z{j}=normal(0,1)" for j in range(s)]  # noqa: E731
    if name == "radial norm":
        s = 6
        exact = math.sqrt(2) * math.exp(math.lgamma((s + 1) / 2) - math.lgamma(s / 2))
        return (lambda z: np.sqrt(np.sum(z ** 2, axis=1))), s, normals(s), exact
    if name == "bump":
        s = 8
        b = rng.uniform(0.1, 1, s)
        return (lambda z: np.exp(-(z ** 2) @ b)), s, normals(s), float(np.prod((1 + 2 * b) ** -0.5))
    if name == "quadratic form":
        s = 5
        c = rng.uniform(-0.3, 0.3, (s, s))
        c = (c + c.T) / 2
        np.fill_diagonal(c, rng.uniform(0.1, 0.5, s))
        return (lambda z: 1 + np.einsum("ij,jk,ik->i", z, c, z)), s, normals(s), 1 + float(np.trace(c))
    if name == "lognormal sum":
        s = 6
        w = rng.uniform(0, 1, s)
        sig = rng.uniform(0.2, 0.6, s)
        space = [f"x{j}=lognormal(0,{float(sg)!r})" for j, sg in enumerate(sig)]
        return (lambda x: x @ w), s, space, float(np.sum(w * np.exp(sig ** 2 / 2)))
    if name == "call on a sum":
        s = 8
        k = rng.uniform(0, 0.5)
        exact = math.exp(-k * k / 2) / math.sqrt(2 * math.pi) - k * 0.5 * math.erfc(k / math.sqrt(2))
        return (lambda z: np.maximum(z.sum(axis=1) / math.sqrt(s) - k, 0)), s, normals(s), exact
    if name == "quadratic with a slope":
        s = 4
        a = rng.uniform(0, 0.3, s)
        c = rng.uniform(0, 0.3, s)
        return (lambda z: np.prod(1 + a * z + c * z ** 2, axis=1)), s, normals(s), float(np.prod(1 + c))
    raise ValueError(name)


GROUPS = {
    "even": ["center gaussian", "radial normal", "abs product", "bilinear",
             "shifted gaussian", "exp sum"],
    "steps": ["even step", "step", "two steps", "half-plane event", "ball event", "count"],
    "laws": ["radial norm", "bump", "quadratic form", "lognormal sum", "call on a sum",
             "quadratic with a slope"],
    "faces": ["root product", "log sum", "normal scores", "exp of scores",
              "shifted gaussian", "exp sum"],
}
SEEDS_OF = {"even": 50, "steps": 100, "laws": 50, "faces": 50}


def step_case(name):
    """(f, s, exact integral) of a step integrand."""
    if name == "even step":
        return (lambda x: 1.0 + (np.abs(x[:, 0] - 0.5) < 0.3)), 3, 1.6
    if name == "step":
        return (lambda x: 1.0 + (np.abs(x[:, 0] - 0.45) < 0.3)), 3, 1.6
    if name == "two steps":
        return (lambda x: (x[:, 0] < 0.37) + (x[:, 1] > 0.71).astype(float)), 2, 0.66
    if name == "half-plane event":
        return (lambda x: (x[:, 0] + x[:, 1] < 0.8).astype(float)), 4, 0.32
    if name == "ball event":
        return ((lambda x: (np.sum((x - 0.5) ** 2, axis=1) < 0.16).astype(float)), 3,
                4 * math.pi * 0.4 ** 3 / 3)
    if name == "count":
        return (lambda x: np.sum(x < 0.2, axis=1).astype(float)), 6, 1.2
    raise ValueError(name)


def measure(group, seeds, rule=None):
    import stillpoint as sp

    out = {"version": getattr(sp, "__version__", "?"), "group": group, "cells": {}}
    for name in GROUPS[group]:
        for tol in TOLS:
            rows = []
            for seed in range(seeds):
                space = None
                if group == "laws":
                    f, s, space, exact = law_case(name, seed)
                else:
                    f, s, exact = (step_case(name) if group == "steps" else case(name, seed))
                r = sp.quad(f, s, rel_tol=tol, seed=seed, space=space,
                            **({"rule": rule} if rule else {}))
                err = abs(float(r.estimate) - exact) / abs(exact)
                rows.append({"n": int(r.n), "ok": bool(r.met and err <= tol),
                             "wrong": bool(r.met and err > tol),
                             "covered": bool(abs(float(r.estimate) - exact)
                                             <= float(r.half_width)),
                             "rule": str(r.rule), "reason": str(r.rule_reason)})
            cell = {k: float(np.mean([r[k] for r in rows]))
                    for k in ("ok", "wrong", "covered")}
            cell["median_n"] = float(np.median([r["n"] for r in rows]))
            cell["halved"] = float(np.mean(["one point of each pair" in r["reason"]
                                            for r in rows]))
            cell["sobol"] = float(np.mean([r["rule"] == "sobol" for r in rows]))
            cell["first_order"] = float(np.mean([r["rule"] == "first-order lattice"
                                                 for r in rows]))
            cell["reliability"] = cell["ok"]
            out["cells"][f"{name}|{tol:g}"] = cell
            print(f"{name:17s} tol={tol:g}: reliability {cell['ok']:.2f}, wrong "
                  f"{cell['wrong']:.2f}, covered {cell['covered']:.2f}, median n "
                  f"{cell['median_n']:.0f}, halved {cell['halved']:.0%}, sobol "
                  f"{cell['sobol']:.0%}, first-order {cell['first_order']:.0%}", flush=True)
    return out


def compare(before, new):
    a, b = (json.load(open(p)) for p in (before, new))
    steps = b.get("group") == "steps"
    if steps:
        head, last = "reliable · wrong · covered · median n", "Sobol'"

        def shown(x):
            return f"{x['ok']:.0%} · {x['wrong']:.0%} · {x['covered']:.0%} · {x['median_n']:.0f}"
    else:
        head, last = "reliable · median n", "halved | ratio"

        def shown(x):
            return f"{x['reliability']:.0%} · {x['median_n']:.0f}"
    print(f"| integrand | tol | before: {head} | now: {head} | {last} |")
    print("|---" * (5 + (not steps)) + "|")
    for k, c in b["cells"].items():
        o = a["cells"][k]
        name, tol = k.split("|")
        tail = (f"{c['sobol']:.0%}" if steps
                else f"{c['halved']:.0%} | {c['median_n'] / o['median_n']:.2f}")
        print(f"| {name} | {tol} | {shown(o)} | {shown(c)} | {tail} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out")
    ap.add_argument("--group", choices=sorted(GROUPS), default="even")
    ap.add_argument("--seeds", type=int, help="default: 50 (even, laws, faces), 100 (steps)")
    ap.add_argument("--rule", help="ask every run for this rule (quad's rule=)")
    ap.add_argument("--compare", nargs=2, metavar=("BEFORE", "NEW"))
    args = ap.parse_args()
    if args.compare:
        compare(*args.compare)
        return
    data = measure(args.group, args.seeds or SEEDS_OF[args.group], args.rule)
    if args.rule:
        data["rule"] = args.rule
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(data, fh, indent=1)


if __name__ == "__main__":
    sys.exit(main())
