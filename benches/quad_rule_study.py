"""Which extensible rule for `stillpoint.quad` under input laws: the spread of one
randomised rule of n points over independent randomisations, relative to SciPy's
scrambled Sobol' (LMS + digital shift), on benches/uq_families.py's model families
(one instance each, the laws mapped by its ``map_cube``).

Rules (all extensible, all unbiased; benches/quad_rules.py's lattice with uniform
shifts drawn by NumPy):
- ``tent``: quad's rule, tent(y) = 1 − |2y − 1| on frac(φ₂(k)z + Δ);
- ``shift``: no transform (the reflected pairs of the tent are gone; the periodic
  extension of f ∘ Φ⁻¹ jumps at the faces);
- ``skew tent``: the tent with its apex at c = 1/3, y/c below c and (1 − y)/(1 − c)
  above (it maps uniform to uniform and joins 0 to 1 as the tent does, but the points
  k and k + n/2, whose y differ by ½, no longer land on u and 1 − u).

    target/py-venv/bin/python benches/quad_rule_study.py [--n 4096] [--reps 32]

Prints a Markdown table (the ratio of the RMSE to Sobol''s; geometric means at the end).
"""

import argparse
import math
import os
import sys

import numpy as np
from scipy.stats import qmc

sys.path.insert(0, os.path.dirname(__file__))
import uq_families as uq  # noqa: E402
from quad_rules import points  # noqa: E402

CASES = [("keister", 5), ("keister", 10), ("genz oscillatory (normal)", 8),
         ("genz gaussian (normal)", 8), ("lognormal product", 10),
         ("morokoff-caflisch", 10), ("asian call", (32, "pca")),
         ("asian call", (32, "standard")), ("basket asian call", (32, "pca")),
         ("ishigami", 3), ("sobol g", 10), ("wing weight", None), ("piston", None)]
APEX = 1.0 / 3.0


def skew_tent(y, c=APEX):
    return np.where(y < c, y / c, (1.0 - y) / (1.0 - c))


def rule_points(rule, s, n, rng):
    if rule == "sobol":
        return qmc.Sobol(s, scramble=True, rng=rng).random(n)
    y = points(s, rng.random(s), 0, n, tent=False)
    if rule == "tent":
        return 1.0 - np.abs(2.0 * y - 1.0)
    if rule == "skew tent":
        return skew_tent(y)
    return y


def case(name, v):
    fam = uq.BY_NAME[name]
    if v is None:
        v = fam.variants[0]
    p = uq.instance(fam, v, 0)
    laws = fam.laws(v, p)

    def f(u):
        u = np.minimum(u, np.nextafter(1.0, 0.0))
        return fam.value(v, p, fam.prepare(v, uq.map_cube(laws, u)))

    return f"{name} {fam.label(v)}", len(laws), f


RULES = ["tent", "shift", "skew tent"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=4096)
    ap.add_argument("--reps", type=int, default=32)
    args = ap.parse_args()
    print(f"| family (n = {args.n}, {args.reps} randomisations) | " + " | ".join(RULES) + " |")
    print("|---" * (len(RULES) + 1) + "|")
    logs = {r: [] for r in RULES}
    for name, v in CASES:
        if name not in uq.BY_NAME:
            continue
        label, s, f = case(name, v)
        sd = {}
        for rule in RULES + ["sobol"]:
            rng = np.random.default_rng([args.n, s, 47])
            est = [f(rule_points(rule, s, args.n, rng)).mean() for _ in range(args.reps)]
            sd[rule] = np.std(est, ddof=1)
        cells = []
        for r in RULES:
            ratio = sd[r] / sd["sobol"]
            logs[r].append(math.log(ratio))
            cells.append(f"{ratio:.2f}")
        print(f"| {label} | " + " | ".join(cells) + " |", flush=True)
    print("| **geometric mean** | " + " | ".join(
        f"**{math.exp(np.mean(logs[r])):.2f}**" for r in RULES) + " |")


if __name__ == "__main__":
    main()
