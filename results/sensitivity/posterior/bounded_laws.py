"""The posterior interval under bounded laws other than the uniform (the lattice, the
face test and the posterior all apply there), on models with closed-form indices:

* linear: f = Σ c_i x_i, c = (1, 2, 3, 0.5), x_i ~ beta(2, 5), triangular(0, 0.3, 1),
  beta(0.5, 0.5), uniform(0, 1): S_i = T_i = c_i² Var x_i / Σ c_j² Var x_j;
* product: f = Π (1 + x_i) over the same four laws: with m_i = E(1 + x_i) and
  q_i = E(1 + x_i)², S_i = (q_i − m_i²) Π_{j≠i} m_j² / V and T_i = (q_i − m_i²)
  Π_{j≠i} q_j / V, V = Π q_j − Π m_j².

Coverage of each index's own interval and mean half-width at fixed N (40 seeds), and the
evaluations to 0.01 with the share of runs every index within 0.01 (20 seeds), for the
posterior (the default) and the blocks.

    python results/sensitivity/posterior/bounded_laws.py
"""

import numpy as np
from scipy import stats

import stillpoint as sp

LAWS = {"a": stats.beta(2, 5), "b": stats.triang(0.3, loc=0, scale=1),
        "c": stats.beta(0.5, 0.5), "d": stats.uniform(0, 1)}
C = np.array([1.0, 2.0, 3.0, 0.5])
mean = np.array([law.mean() for law in LAWS.values()])
var = np.array([law.var() for law in LAWS.values()])


def linear(x):
    return x @ C


def product(x):
    return np.prod(1 + x, axis=1)


lin_s = C**2 * var / np.sum(C**2 * var)
m, q = 1 + mean, var + (1 + mean) ** 2
v = np.prod(q) - np.prod(m**2)
prod_s = np.array([(q[i] - m[i] ** 2) * np.prod(np.delete(m, i) ** 2) / v for i in range(4)])
prod_t = np.array([(q[i] - m[i] ** 2) * np.prod(np.delete(q, i)) / v for i in range(4)])
MODELS = {"linear": (linear, lin_s, lin_s), "product": (product, prod_s, prod_t)}

for name, (f, s1, st) in MODELS.items():
    exact = np.r_[s1, st]
    for n_base in (1024, 4096):
        line = f"{name:8s} N={n_base:5d}"
        for interval in ("posterior", "blocks"):
            inside, hw = [], []
            for seed in range(40):
                r = sp.sobol_indices(f, space=LAWS, abs_tol=0.0, seed=seed, interval=interval,
                                     max_n=n_base * 6 + 32)
                est = np.r_[r.first, r.total]
                h = np.r_[r.first_half_width, r.total_half_width]
                inside.append(np.abs(est - exact) <= h)
                hw.append(h)
            line += f"  {interval} ({r.interval}): cover {np.mean(inside):.3f} mean_hw {np.mean(hw):.2e}"
        print(line, flush=True)
    line = f"{name:8s} tol=0.01"
    for interval in ("posterior", "blocks"):
        ns, ok = [], []
        for seed in range(20):
            r = sp.sobol_indices(f, space=LAWS, abs_tol=0.01, seed=seed, interval=interval)
            ns.append(r.n)
            ok.append(bool(r.met and np.all(np.abs(np.r_[r.first, r.total] - exact) <= 0.01)))
        line += f"  {interval}: median n {np.median(ns):.0f} all within {np.mean(ok):.2f}"
    print(line, flush=True)
