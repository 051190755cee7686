"""`quad` on two even integrands of infinite variance, of three standard normal inputs:
exp(Σz²/4) (E = 2^{3/2}) and |z₁|^−½(1 + z₂²) (E = 2·2^{−1/4}Γ(¼)/√π). Per rule, over SEEDS
seeds (default 100) at rel_tol 10⁻²: the share of runs claimed met off the integral and
the median evaluations. ``default`` is the rule `quad` chooses (the probe, then the
Bayesian lattice, which leaves for Sobol' when its first round is skewed); the others are
asked for by name (``bayesian lattice`` then keeps the lattice whatever its values show).

    SEEDS=100 target/py-venv/bin/python benches/quad_heavy.py
"""

import math
import os
import warnings

import numpy as np
from scipy.special import gamma

import stillpoint as sp

CASES = {
    "exp(Σz²/4)": (lambda z: np.exp((z ** 2).sum(axis=1) / 4), math.sqrt(2) ** 3),
    "|z₁|^−½(1 + z₂²)": (lambda z: np.abs(z[:, 0]) ** -0.5 * (1 + z[:, 1] ** 2),
                         2 * 2 ** -0.25 * gamma(0.25) / math.sqrt(math.pi)),
}
RULES = ["default", "bayesian lattice", "first-order lattice", "sobol"]


def main():
    warnings.simplefilter("ignore")
    seeds = int(os.environ.get("SEEDS", "100"))
    laws = [f"z{i}=normal(0,1)" for i in range(3)]
    print("| rule | " + " | ".join(CASES) + " |")
    print("|---|" + "---|" * len(CASES))
    for rule in RULES:
        cells = []
        for f, exact in CASES.values():
            wrong, ns, used = 0, [], set()
            for seed in range(seeds):
                r = sp.quad(f, 3, space=laws, rel_tol=1e-2, seed=seed,
                            rule=None if rule == "default" else rule)
                wrong += r.met and abs(r.estimate - exact) > 1e-2 * exact
                ns.append(r.n)
                used.add(r.rule)
            cells.append(f"{100 * wrong / seeds:.0f} % · {int(np.median(ns))} "
                         f"({', '.join(sorted(used))})")
        print(f"| {rule} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
