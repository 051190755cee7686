"""`quad` through the tail map (`Cubature::widen_tails`) on functions of few normal
inputs: how often a run claims its tolerance and misses it, how often its interval
covers the integral, and its evaluations.

Two groups (``GROUP``):

- ``one`` (default): closed forms of one to three normal inputs, SEEDS seeds each
  (default 100): cos(Z/√2), Z², exp(Z), exp(ΣZ/3) of three, exp(Z1 + Z2) and the
  indicator of Z1 + Z2 > 1. "wrong met" is the share of runs that claimed the tolerance
  with a true relative error above it, "covers" the share whose half-width holds the
  true error.
- ``laws``: one input of other unbounded laws (SciPy's t(4) and exponential laws, a
  normal law truncated to one side, a lognormal law), SEEDS seeds (default 100).
- ``models``: the model families of benches/quad.py (Keister, the Gaussian and
  oscillatory Genz functions of normal inputs, the lognormal product) at s = DIMS
  (default 1–5), their instances drawn as benches/quad.py draws them, RUNS runs per cell
  (default 60) or CAP seconds (default 25): reliability (met within the tolerance) and
  the median evaluations.

The map's spread and reach are the library's `TAIL_SPREAD` and `TAIL_MOST`; the
comparisons in results/quad/tails.md were made with builds where they were changed.

    GROUP=one SEEDS=100 target/py-venv/bin/python benches/quad_tails.py
    GROUP=laws SEEDS=100 target/py-venv/bin/python benches/quad_tails.py
    GROUP=models RUNS=60 CAP=25 target/py-venv/bin/python benches/quad_tails.py
"""

import math
import os
import sys
import time

import numpy as np

import stillpoint as sp

def one():
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from quad_one_normal import CASES, table

    two = [
        ("exp(Z1+Z2)", 2, lambda z: np.exp(z[:, 0] + z[:, 1]), math.exp(1.0)),
        ("1{Z1+Z2>1}", 2, lambda z: (z[:, 0] + z[:, 1] > 1).astype(float),
         0.5 * math.erfc(1 / 2)),
    ]
    table(CASES + two, int(os.environ.get("SEEDS", "100")))


def laws():
    from scipy import stats

    cases = [
        ("x² under t(4)", {"x": stats.t(4)}, lambda x: x[:, 0] ** 2, 2.0),
        ("x under expon", {"x": stats.expon()}, lambda x: x[:, 0], 1.0),
        ("x² under expon", {"x": stats.expon()}, lambda x: x[:, 0] ** 2, 2.0),
        ("exp(x/3) under expon", {"x": stats.expon()}, lambda x: np.exp(x[:, 0] / 3), 1.5),
        ("x under truncnormal(0,1,0,inf)", {"x": "truncnormal(0,1,0,inf)"},
         lambda x: x[:, 0], math.sqrt(2 / math.pi)),
        ("x² under lognormal(0,0.5)", {"x": "lognormal(0,0.5)"}, lambda x: x[:, 0] ** 2,
         math.exp(0.5)),
    ]
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from quad_one_normal import table

    table(cases, int(os.environ.get("SEEDS", "100")))


def models():
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import quad as bench

    runs = int(os.environ.get("RUNS", "60"))
    cap = float(os.environ.get("CAP", "25"))
    fams = os.environ.get("FAMS", "uq keister,uq gaussian (normal),uq oscillatory (normal),"
                          "uq lognormal product").split(",")
    dims = [int(v) for v in os.environ.get("DIMS", "1,2,3,4,5").split(",")]
    tols = [float(v) for v in os.environ.get("TOLS", "0.01,0.001").split(",")]
    for fam in fams:
        for s in dims:
            for tol in tols:
                ok, ns, t0 = 0, [], time.time()
                for run in range(runs):
                    _, texts, on_values, truth = bench.model(fam, s, run)
                    r = sp.quad(on_values, s, rel_tol=tol, seed=run, max_n=2**20, space=texts)
                    err = abs(r.estimate - truth) / abs(truth)
                    ok += bool(r.met and err <= tol)
                    ns.append(r.n)
                    if time.time() - t0 > cap:
                        break
                print(f"{fam:26s} s={s} tol={tol:g}: reliability {ok / len(ns):.2f}, "
                      f"median n {int(np.median(ns))}, runs {len(ns)}", flush=True)


if __name__ == "__main__":
    {"one": one, "laws": laws, "models": models}[os.environ.get("GROUP", "one")]()
