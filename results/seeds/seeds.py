"""Checks the package's seed convention: each function called twice with the seed left
out, twice with seed=None and twice with seed=7; prints one Markdown row per function.

    target/py-venv/bin/python results/seeds/seeds.py > results/seeds/seeds.md
"""
import warnings

import numpy as np
import stillpoint as sp


def f(x):
    return np.exp(x.sum(axis=1))


def g(x):
    return x[:, 0] + 2 * x[:, 1]


CASES = {
    "generate(64, 3)": lambda **k: sp.generate(64, 3, **k),
    "generate(64, 3, randomize=True)": lambda **k: sp.generate(64, 3, randomize=True, **k),
    "generate(32, 2, goal='space-filling')": lambda **k: sp.generate(
        32, 2, goal="space-filling", **k),
    "extend(generate(16, 2), 8)": lambda **k: sp.extend(sp.generate(16, 2), 8, **k),
    "nested([16, 32], 2)": lambda **k: sp.nested([16, 32], 2, **k),
    "design(32, {x: normal, k: int})": lambda **k: np.asarray(sp.design(
        32, {"x": "normal(0,1)", "k": "int(1,5)"}, **k).table(), dtype=float),
    "baseline('sobol', 64, 3)": lambda **k: sp.baseline("sobol", 64, 3, **k),
    "generate_many([{n: 32, d: 2, randomize: True}])": lambda **k: np.concatenate(
        [a.ravel() for a in sp.generate_many([{"n": 32, "d": 2, "randomize": True, **k}])]),
    "quad(f, 3, rel_tol=1e-2).estimate": lambda **k: np.array(
        [sp.quad(f, 3, rel_tol=1e-2, **k).estimate]),
    "sobol_indices(g, 3).first": lambda **k: np.asarray(sp.sobol_indices(g, 3, **k).first),
    "Engine(3).random(64)": lambda **k: sp.Engine(3, **k).random(64),
    "Engine(3, generate_seed=...).random(64)": lambda **k: sp.Engine(
        3, seed=1, **{("generate_seed" if kk == "seed" else kk): v for kk, v in k.items()}
    ).random(64),
}


def same(c, **k):
    return np.array_equal(np.asarray(c(**k), float), np.asarray(c(**k), float))


def main():
    warnings.simplefilter("ignore")
    print("# Seeds: the same call twice\n")
    print("Made by `target/py-venv/bin/python results/seeds/seeds.py > "
          "results/seeds/seeds.md`.\n")
    print("| call | seed left out: same result | seed=None: same result | seed=7: same result |")
    print("|---|---|---|---|")
    for name, c in CASES.items():
        print(f"| `{name}` | {same(c)} | {same(c, seed=None)} | {same(c, seed=7)} |")


if __name__ == "__main__":
    main()
