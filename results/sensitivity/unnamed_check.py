"""A check on models benches/sensitivity.py does not name (the estimators, the design and
the face test were chosen on its models), both products of independent factors
f = Π g_i(x_i) on [0, 1]^d with closed-form indices:

* exp6: f = exp(Σ c_i x_i), c = (2, 1.5, 1, 0.5, 0.25, 0.1) (no input periodic);
* mixed5: g = (1 + sin 2πx₁, 1 + x₂, 1 + cos(4πx₃)/2, 1 + 2|x₄ − 1/2|, 1 + x₅²): inputs 1,
  3 and 4 periodic (the lattice takes them without the tent), 2 and 5 not.

RMSE of all 2d indices at equal evaluations over 10 seeds, and evaluations to a
half-width of 0.02 (3 seeds), with the benchmark's own method code.

    PYTHONPATH=benches python results/sensitivity/unnamed_check.py
"""

import math

import numpy as np

import sensitivity as b

C = np.array([2, 1.5, 1, 0.5, 0.25, 0.1])


def exp6(x):
    return np.exp(x @ C)


def mixed5(x):
    return ((1 + np.sin(2 * np.pi * x[:, 0])) * (1 + x[:, 1])
            * (1 + 0.5 * np.cos(4 * np.pi * x[:, 2])) * (1 + 2 * np.abs(x[:, 3] - 0.5))
            * (1 + x[:, 4] ** 2))


def product_indices(m, m2):
    """First and total indices of Π g_i(x_i) from each factor's mean m and E g² m2."""
    s2 = m2 - m**2
    v = np.prod(m2) - np.prod(m**2)
    return s2 * np.prod(m**2) / m**2 / v, s2 * np.prod(m2) / m2 / v


MODELS = {
    "exp6": (exp6, 6, product_indices((np.exp(C) - 1) / C, (np.exp(2 * C) - 1) / (2 * C))),
    "mixed5": (mixed5, 5, product_indices(np.array([1, 1.5, 1, 1.5, 4 / 3]),
                                          np.array([1.5, 7 / 3, 1.125, 7 / 3, 28 / 15]))),
}


def main():
    for name, (f, d, ex) in MODELS.items():
        methods = {"stillpoint": lambda n, s: b.ours(f, d, 0.0, 1.0, n_base=n, seed=s)[:3],
                   "salib": lambda n, s: b.salib(f, d, 0.0, 1.0, n, seed=s)[:3],
                   "scipy": lambda n, s: b.scipy_si(f, d, 0.0, 1.0, n, seed=s)[:3],
                   "qmcpy": lambda n, s: b.qmcpy_si(f, d, 0.0, 1.0, n, seed=s)[:3]}
        for n_base in (1024, 8192):
            rmse = {k: math.sqrt(np.mean([b.rmse(*m(n_base, s)[:2], ex) ** 2
                                          for s in range(10)]))
                    for k, m in methods.items()}
            print(f"{name} N={n_base}: " + "  ".join(f"{k} {v:.2e}" for k, v in rmse.items())
                  + "  ratios " + " ".join(f"{rmse['stillpoint'] / rmse[k]:.2f}"
                                           for k in ("salib", "scipy", "qmcpy")), flush=True)
        tol = 0.02
        for seed in range(3):
            fs, ts, n, _, _ = b.ours(f, d, 0.0, 1.0, tol=tol, seed=seed)
            within = b.share_within(fs, ts, ex, tol)
            n_salib = None
            n_base = 64
            while n_base <= 65536:
                _, _, n_s, h = b.salib(f, d, 0.0, 1.0, n_base, seed=seed, conf=True)
                if h <= tol:
                    n_salib = n_s
                    break
                n_base *= 2
            qf, qt, n_q, h_q = b.qmcpy_si(f, d, 0.0, 1.0, seed=seed, tol=tol, largest=65536)
            print(f"{name} tol={tol} seed {seed}: stillpoint {n} (within {within:.2f})  "
                  f"SALib {n_salib}  QMCPy {n_q if h_q <= tol else None} "
                  f"(within {b.share_within(qf, qt, ex, tol):.2f})", flush=True)


if __name__ == "__main__":
    main()
