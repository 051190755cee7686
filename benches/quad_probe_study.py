"""`quad`'s rules under unbounded laws at a fixed number of evaluations N: four
replicates of N/4 points of Owen-scrambled Sobol' (the rule a probe leaves for), and of
the extensible lattice with the tent table (quad's on the cube) and with the first-order
table (`Engine(d)`'s, the probe's), on the model families of benches/quad.py with normal
and lognormal inputs, mapped through their laws' quantiles. For a family even under
Z ↦ −Z (Keister's) the lattices are halved as `quad` halves them: one point of each
reflected pair, so N evaluations give the mean of the lattice's 2N points (f takes one
value at both). Per (family, s, N) over SEEDS instances (instance and shifts `seed`):
Sobol's RMSE of the relative error, its Student half-width (t_3, level 0.95, geometric
mean) and coverage; for each lattice its RMSE and half-width over Sobol's, and its
coverage. Without quad's round and skew guards.

    SEEDS=48 NS=1024,4096,16384 target/py-venv/bin/python benches/quad_probe_study.py
    SEEDS=48 NS=65536,262144 FAMS="uq keister" target/py-venv/bin/python benches/quad_probe_study.py
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import stillpoint as sp  # noqa: E402
from quad import MODEL_FAMILIES, model  # noqa: E402

SEEDS = int(os.environ.get("SEEDS", 48))
NS = [int(x) for x in os.environ.get("NS", "1024,4096,16384").split(",")]
FAMS = os.environ.get("FAMS", "uq keister,uq oscillatory (normal),uq gaussian (normal),"
                      "uq lognormal product").split(",")
EVEN = {"uq keister"}
T3 = 3.182446305284263
RULES = ("sobol", "tent", "first-order")


def points(rule, s, seed, r, n):
    if rule == "sobol":
        return np.asarray(sp.baseline("sobol", n, s, seed=1000 * seed + r))
    return np.asarray(sp._core.sequence_points(s, seed=seed, replicate=r, count=n, table=rule))


widths = {}
for family in FAMS:
    for v in MODEL_FAMILIES[family][1]:
        for n in NS:
            out = {}
            for rule in RULES:
                # A halved lattice's N evaluations are its 2N points' mean.
                m = 2 * n if (rule != "sobol" and family in EVEN) else n
                errs, w, cov = [], [], 0
                for seed in range(SEEDS):
                    g, texts, _, exact = model(family, v, seed)
                    reps = [g(np.clip(points(rule, len(texts), seed, r, m // 4),
                                      2**-53, 1 - 2**-53)).mean() for r in range(4)]
                    mean, sd = np.mean(reps), np.std(reps, ddof=1)
                    errs.append((mean - exact) / exact)
                    w.append(T3 * sd / 2 / abs(exact))
                    cov += abs(mean - exact) <= w[-1] * abs(exact)
                out[rule] = (math.sqrt(np.mean(np.square(errs))),
                             math.exp(np.mean(np.log(np.maximum(w, 1e-300)))), cov / SEEDS)
            b = out["sobol"]
            line = (f"{family:26s} {str(v):3s} N={n:6d} sobol rmse {b[0]:.2e} "
                    f"w {b[1]:.2e} cov {b[2]:.2f}")
            for rule in RULES[1:]:
                o = out[rule]
                line += f" | {rule} rmse {o[0] / b[0]:.2f} w {o[1] / b[1]:.2f} cov {o[2]:.2f}"
                widths.setdefault((family, rule), []).append(o[1] / b[1])
            print(line, flush=True)
for (family, rule), v in widths.items():
    print(f"{family:26s} {rule:12s} half-width over Sobol's, geometric mean "
          f"{math.exp(np.mean(np.log(v))):.2f}")
