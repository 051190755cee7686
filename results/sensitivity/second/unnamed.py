"""Second-order indices on two models benches/sensitivity_second.py does not name (closed
forms of products of independent factors), against SALib at equal evaluations, 20 seeds.
Run from the repository root: python results/sensitivity/second/unnamed.py"""
import sys

import numpy as np
sys.path.insert(0, 'benches')
import sensitivity_second as S
from sensitivity import g_model
# Models the bench does not name, closed forms for products of independent factors:
#   G with a = (0.5, 1, 2, 3, 4); f = exp(x1 + x2)·(1 + x3) on [0, 1]^3 (+ x4 inert).
out = []
f, ex = g_model([0.5, 1, 2, 3, 4])
vi = 1 / (3 * (1 + np.array([0.5, 1, 2, 3, 4])) ** 2)
out.append(("g-a0.5-1-2-3-4", f, 5, 0.0, 1.0, ex, S.pairs_of_products(np.ones(5), vi, np.prod(1 + vi) - 1)))
e1 = np.e - 1; m2 = e1**2; e2 = (np.e**2 - 1) / 2
mu2 = np.array([m2, m2, 2.25, 1.0]); var = np.array([e2 - m2, e2 - m2, 1/12, 0.0])
tot = np.prod(mu2 + var) - np.prod(mu2)
def g2(x): return np.exp(x[:, 0] + x[:, 1]) * (1 + x[:, 2]) + 0 * x[:, 3]
first = np.array([np.prod(np.delete(mu2, i)) * var[i] for i in range(4)]) / tot
out.append(("exp(x1+x2)(1+x3)", g2, 4, 0.0, 1.0, (first, None), S.pairs_of_products(mu2, var, tot)))
for n_base in (1024, 8192):
    for name, f, d, lo, hi, (first, _), second in out:
        e_o, e_s, cov, e1o = [], [], [], []
        for seed in range(20):
            s1, st, s2, h2, n = S.ours(f, d, lo, hi, n_base, seed)
            e_o.append(s2 - second); cov.append(np.abs(s2 - second) <= h2); e1o.append(s1 - first)
            t1, tt, t2, ns = S.salib(f, d, lo, hi, n_base, seed)
            e_s.append(t2 - second)
        print(f"{name:18s} N={n_base:5d} S2 RMSE {S.rms(e_o):.2e} vs SALib {S.rms(e_s):.2e} ratio {S.rms(e_o)/S.rms(e_s):.2f} coverage {np.mean(cov):.2f} (first-order RMSE {S.rms(e1o):.1e})", flush=True)
