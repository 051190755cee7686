"""A check on a model benches/sensitivity.py does not name (the estimators and design were
chosen on its models): f = exp(Σ c_i x_i) on [0, 1]^6, c = (2, 1.5, 1, 0.5, 0.25, 0.1),
a product of independent factors with closed-form indices. RMSE of all 12 indices at
equal evaluations over 10 seeds, and evaluations to a half-width of 0.02 (3 seeds), with
the benchmark's own method code.

    PYTHONPATH=benches python results/sensitivity/unnamed_check.py
"""

import math

import numpy as np

import sensitivity as b

C = np.array([2, 1.5, 1, 0.5, 0.25, 0.1])


def f(x):
    return np.exp(x @ C)


def exact():
    m = (np.exp(C) - 1) / C
    m2 = (np.exp(2 * C) - 1) / (2 * C)
    s2 = m2 - m**2
    v = np.prod(m2) - np.prod(m**2)
    first = s2 * np.prod(m**2) / m**2 / v
    total = s2 * np.prod(m2) / m2 / v
    return first, total


def main():
    d, ex = len(C), exact()
    methods = {"stillpoint": lambda n, s: b.ours(f, d, 0.0, 1.0, n_base=n, seed=s)[:3],
               "salib": lambda n, s: b.salib(f, d, 0.0, 1.0, n, seed=s)[:3],
               "scipy": lambda n, s: b.scipy_si(f, d, 0.0, 1.0, n, seed=s)[:3],
               "qmcpy": lambda n, s: b.qmcpy_si(f, d, 0.0, 1.0, n, seed=s)[:3]}
    for n_base in (1024, 8192):
        rmse = {k: math.sqrt(np.mean([b.rmse(*m(n_base, s)[:2], ex) ** 2 for s in range(10)]))
                for k, m in methods.items()}
        print(f"exp6 N={n_base}: " + "  ".join(f"{k} {v:.2e}" for k, v in rmse.items())
              + "  ratios " + " ".join(f"{rmse['stillpoint'] / rmse[k]:.2f}"
                                       for k in ("salib", "scipy", "qmcpy")))
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
        print(f"exp6 tol={tol} seed {seed}: stillpoint {n} (within {within:.2f})  "
              f"SALib {n_salib}  QMCPy {n_q if h_q <= tol else None} "
              f"(within {b.share_within(qf, qt, ex, tol):.2f})")


if __name__ == "__main__":
    main()
