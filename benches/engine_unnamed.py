#!/usr/bin/env python3
"""Candidate draws of benches/uq_engine.py (`seq`, `ind`, `vec:NAME`, ...) on integrands
neither benchmark names, through the quantiles of standard normal laws, against SciPy's
scrambled Sobol' (seeds 90000 + r): RMSE over REPS randomisations of each, n = 1 024 and
4 096 (results/law-lattice/randomize-engine.md).

  digital8   1{mean(Z) > 0.3}, Z ~ N(0, I_8); exact 1 - Phi(0.3 sqrt 8)
  corr_exp6  exp(a.Y), Y = L Z with correlation 0.5 between every pair (L its Cholesky
             factor), a_j = 0.4/j, s = 6; exact exp(a^T C a / 2)
  normrad16  |Z|, Z ~ N(0, I_16); exact sqrt 2 Gamma(17/2) / Gamma(8)
  ridge12    log(1 + exp(w.Z)), w_j = 1/sqrt(12) (a softplus of a ridge, s = 12); exact by
             Gauss-Hermite quadrature in one dimension

    REPS=32 CANDS=seq,vec:b2_256 target/py-venv/bin/python benches/engine_unnamed.py
"""
import math
import os
import sys

import numpy as np
from scipy import special
from scipy.stats import qmc

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from uq_engine import draw, gm  # noqa: E402

REPS = int(os.environ.get("REPS", 32))
CANDS = os.environ.get("CANDS", "seq").split(",")
NS = [int(x) for x in os.environ.get("NS", "1024,4096").split(",")]

C6 = np.full((6, 6), 0.5) + 0.5 * np.eye(6)
A6 = np.array([0.4 / (j + 1) for j in range(6)])
L6 = np.linalg.cholesky(C6)
gh_x, gh_w = np.polynomial.hermite_e.hermegauss(120)
MODELS = {
    "digital8": (8, lambda Z: (Z.mean(1) > 0.3).astype(float),
                 0.5 * special.erfc(0.3 * math.sqrt(8) / math.sqrt(2))),
    "corr_exp6": (6, lambda Z: np.exp((Z @ L6.T) @ A6), math.exp(A6 @ C6 @ A6 / 2)),
    "normrad16": (16, lambda Z: np.sqrt((Z * Z).sum(1)),
                  math.sqrt(2) * math.exp(special.gammaln(8.5) - special.gammaln(8))),
    "ridge12": (12, lambda Z: np.logaddexp(0.0, Z.sum(1) / math.sqrt(12)),
                float(np.sum(gh_w * np.logaddexp(0.0, gh_x)) / math.sqrt(2 * math.pi))),
}


def main():
    rows = []
    for name, (d, f, exact) in MODELS.items():
        for n in NS:
            rmse = {}
            for cand in ["sobol_scipy"] + CANDS:
                e = []
                for r in range(REPS):
                    if cand == "sobol_scipy":
                        u = qmc.Sobol(d, scramble=True, seed=90000 + r).random(n)
                    else:
                        u = draw(cand, n, d, r)
                    Z = special.ndtri(np.clip(u, 2**-53, 1 - 2**-53))
                    e.append(f(Z).mean() / exact - 1)
                rmse[cand] = math.sqrt(float(np.mean(np.square(e))))
            out = {c: rmse[c] / rmse["sobol_scipy"] for c in CANDS}
            rows.append(out)
            print(f"{name} n={n} sobol={rmse['sobol_scipy']:.2e} " +
                  " ".join(f"{c}={x:.2f}" for c, x in out.items()), flush=True)
    print("geometric mean " + " ".join(f"{c}={gm([r[c] for r in rows]):.2f}" for c in CANDS))


if __name__ == "__main__":
    main()
