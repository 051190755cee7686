#!/usr/bin/env python3
"""Models of correlated normal inputs with closed forms: stillpoint's deterministic
default under a space with `correlation=` (`design(n, space, correlation=C, seed=k)`)
against SciPy's scrambled Sobol' mapped through the normal quantile and the Cholesky
factor of C, RMSE over instances (the default: one seed per instance; Sobol': REPS
randomisations per instance), n = 1 024 and 4 096. Every instance draws its parameters
and its correlation matrix at random (seeded by the instance), never tuned:

  exp      exp(a·Y), a = u·σ/√(uᵀCu), σ uniform in [0.5, 1.5]; exact exp(aᵀCa/2)
  cos      cos(a·Y), a as for exp;                             exact exp(−aᵀCa/2)
  gauss    exp(−½ Σ d_j Y_j²), d_j = u_j;                  exact det(I + C D)^−½
  digital  1{a·Y > c}, a_j = u_j, c = 0.5·√(aᵀCa);        exact 1 − Φ(c/√(aᵀCa))

with u_j uniform in [0.2, 1], s = 3, 6, 12, and C either equicorrelated (ρ uniform in
[0.2, 0.8]) or a random correlation matrix (a Wishart draw with s + 2 degrees of freedom,
scaled to unit diagonal), alternating over the instances.

    RULE=default|cube INSTANCES=8 REPS=16 python benches/uq_correlated.py

RULE=cube maps the cube's default `generate(n, s, seed=k)` through the same quantile and
Cholesky factor (the set the dealt default under a correlated space is, up to the
dealing), to compare the rules on the same instances. Prints per (family, s, n) the RMSE
ratio to Sobol' and the geometric means per family and overall.
"""
import math
import os

import numpy as np
from scipy import stats
from scipy.stats import qmc

import stillpoint as sp

RULE = os.environ.get("RULE", "default")
INSTANCES = int(os.environ.get("INSTANCES", 8))
REPS = int(os.environ.get("REPS", 16))
NS = [int(x) for x in os.environ.get("NS", "1024,4096").split(",")]
SS = [int(x) for x in os.environ.get("SS", "3,6,12").split(",")]
FAMILIES = os.environ.get("FAMILIES", "exp,cos,gauss,digital").split(",")


def correlation(s, k, rng):
    if k % 2 == 0:
        rho = rng.uniform(0.2, 0.8)
        return np.full((s, s), rho) + (1 - rho) * np.eye(s)
    g = rng.standard_normal((s, s + 2))
    w = g @ g.T
    d = np.sqrt(np.diag(w))
    return w / np.outer(d, d)


def instance(family, s, k):
    rng = np.random.default_rng([sum(map(ord, family)), s, k])
    C = correlation(s, k, rng)
    u = rng.uniform(0.2, 1.0, s)
    # a scaled so that a·Y has standard deviation σ uniform in [0.5, 1.5]: a product of
    # lognormals (or an oscillation) of moderate spread whatever s and C.
    a = u / math.sqrt(u @ C @ u) * rng.uniform(0.5, 1.5)
    if family == "exp":
        return C, (lambda Y: np.exp(Y @ a)), math.exp(a @ C @ a / 2)
    if family == "cos":
        return C, (lambda Y: np.cos(Y @ a)), math.exp(-a @ C @ a / 2)
    if family == "gauss":
        D = np.diag(u)
        return C, (lambda Y: np.exp(-0.5 * (Y * Y) @ u)), np.linalg.det(np.eye(s) + C @ D) ** -0.5
    if family == "digital":
        v = math.sqrt(u @ C @ u)
        c = 0.5 * v
        return C, (lambda Y: (Y @ u > c).astype(float)), 1 - stats.norm.cdf(c / v)
    raise ValueError(family)


def scores_to_y(z, C):
    return z @ np.linalg.cholesky(C).T


def ours(n, s, C, k):
    if RULE == "cube":
        u = np.clip(np.asarray(sp.generate(n, s, seed=k + 1)), 2**-53, 1 - 2**-53)
        return scores_to_y(stats.norm.ppf(u), C), "cube"
    space = {f"y{j + 1}": "normal(0,1)" for j in range(s)}
    d = sp.design(n, space, correlation=C.tolist(), seed=k + 1)
    return np.column_stack([np.asarray(d.columns[f"y{j + 1}"], float) for j in range(s)]), d.rule


def sobol(n, s, C, r):
    u = np.clip(qmc.Sobol(s, scramble=True, seed=70000 + r).random(n), 2**-53, 1 - 2**-53)
    return scores_to_y(stats.norm.ppf(u), C)


fam_ratios = {f: [] for f in FAMILIES}
rules = set()
for family in FAMILIES:
    for s in SS:
        for n in NS:
            e_ours, e_sobol = [], []
            for k in range(INSTANCES):
                C, f, exact = instance(family, s, k)
                Y, rule = ours(n, s, C, k)
                rules.add(rule[:60])
                e_ours.append((f(Y).mean() - exact) / exact)
                e_sobol += [(f(sobol(n, s, C, 100 * k + r)).mean() - exact) / exact for r in range(REPS)]
            r_ours = math.sqrt(np.mean(np.square(e_ours)))
            r_sobol = math.sqrt(np.mean(np.square(e_sobol)))
            ratio = r_ours / r_sobol
            fam_ratios[family].append(ratio)
            print(f"{family:8s} s={s:3d} n={n:5d} {RULE} {r_ours:.3g} Sobol' {r_sobol:.3g} ratio {ratio:.2f}", flush=True)
every = []
for family, v in fam_ratios.items():
    every += v
    print(f"{family:8s} geometric mean {math.exp(np.mean(np.log(v))):.2f}")
print(f"all {len(every)} cells: geometric mean {math.exp(np.mean(np.log(every))):.2f}; rules {sorted(rules)}")
