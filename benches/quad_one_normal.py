"""`quad` on functions of one or three normal inputs with closed forms: how often a run
claims its tolerance and misses it, and how often its interval covers the integral.

Per integrand and relative tolerance, over SEEDS seeds (default 200):
``stillpoint.quad(f, d, space=..., rel_tol=tol, seed=k)``; "wrong met" is the share of
runs that say met with a true relative error above tol, "covers" the share whose
half-width holds the true error, n the median evaluations. The integrands:
cos(Z/√2) (E = e^{-1/4}), Z² (1), exp(Z) (e^{1/2}) of one standard normal Z, and
exp(ΣZ/3) of three (e^{1/6}); cos and Z² are even, so the probe's lattice is kept for
them; exp is steep in the laws' tails and goes on with scrambled Sobol'.

    SEEDS=200 target/py-venv/bin/python benches/quad_one_normal.py > results/quad/one-normal.md
"""

import math
import os

import numpy as np

import stillpoint as sp

CASES = [
    ("cos(Z/√2)", 1, lambda z: np.cos(z[:, 0] / math.sqrt(2)), math.exp(-0.25)),
    ("Z²", 1, lambda z: z[:, 0] ** 2, 1.0),
    ("exp(Z)", 1, lambda z: np.exp(z[:, 0]), math.exp(0.5)),
    ("exp(ΣZ/3), 3 inputs", 3, lambda z: np.exp(z.sum(axis=1) / 3), math.exp(1 / 6)),
]


def table(cases, seeds):
    """Prints the table of `cases` ((name, d, f, exact) of d standard normal inputs, or
    (name, space, f, exact) of a space's laws), each at 10⁻² and 10⁻³ over `seeds`
    seeds."""
    print("| integrand | rel_tol | wrong met | covers | median n | rule |")
    print("|---|---|---|---|---|---|")
    for name, laws, f, exact in cases:
        if isinstance(laws, int):
            space = [f"z{i}=normal(0,1)" for i in range(laws)]
        else:
            space = laws
        d = len(space)
        for tol in (1e-2, 1e-3):
            wrong = covers = 0
            ns, rules = [], set()
            for seed in range(seeds):
                r = sp.quad(f, d, space=space, rel_tol=tol, seed=seed)
                err = abs(r.estimate - exact)
                wrong += r.met and err > tol * abs(exact)
                covers += err <= r.half_width
                ns.append(r.n)
                rules.add(r.rule)
            print(f"| {name} | {tol:g} | {100 * wrong / seeds:.1f} % | "
                  f"{100 * covers / seeds:.1f} % | {int(np.median(ns))} | "
                  f"{', '.join(sorted(rules))} |", flush=True)


def main():
    table(CASES, int(os.environ.get("SEEDS", "200")))


if __name__ == "__main__":
    main()
