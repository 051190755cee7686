"""Writes the QuadResult and SobolResult pickles test_quad_pickles.py loads: results made
by stillpoint 0.2.0 as released (before quad's settings were resolved by the library),
with what they held and what continuing them gave then. Run once with that build:
python make_quad_pickles.py (from this directory)."""

import json
import math
import pathlib
import pickle

import numpy as np
from scipy import stats

import stillpoint as sp

HERE = pathlib.Path(__file__).resolve().parent


def peak(x):
    return np.prod(1.0 / (0.25 + (x - 0.3) ** 2), axis=1)


def two(x):
    return np.column_stack([x.sum(axis=1), np.cos(x[:, 0])])


def ishigami(x):
    return np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])


MADE = {
    "quad_scalar": (lambda: sp.quad(peak, 3, rel_tol=1e-2, seed=5), dict(rel_tol=1e-4)),
    "quad_outputs": (lambda: sp.quad(two, 2, rel_tol=1e-9, max_n=4096, seed=2), dict(max_n=2**14)),
    "quad_space": (
        lambda: sp.quad(
            lambda x: x[:, 0] * x[:, 1],
            2,
            space={"z": stats.norm(0, 1), "u": "uniform(1,2)"},
            rel_tol=1e-1,
            seed=3,
        ),
        dict(rel_tol=1e-3),
    ),
    "sobol": (
        lambda: sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi, abs_tol=0.05),
        dict(abs_tol=0.02),
    ),
}

FUNCTIONS = {"quad_scalar": peak, "quad_outputs": two, "sobol": ishigami}


def summary(r):
    if isinstance(r, sp.QuadResult):
        return {
            "estimate": np.atleast_1d(r.estimate).tolist(),
            "half_width": np.atleast_1d(r.half_width).tolist(),
            "n": r.n,
            "met": r.met,
            "reason": r.reason,
            "rule": r.rule,
            "rule_reason": r.rule_reason,
            "replicates": r.replicates,
            "scalar": isinstance(r.estimate, float),
        }
    return {
        "first": np.asarray(r.first).tolist(),
        "total": np.asarray(r.total).tolist(),
        "total_half_width": np.asarray(r.total_half_width).tolist(),
        "n": r.n,
        "met": r.met,
        "names": r.names,
        "replicates": r.replicates,
    }


if __name__ == "__main__":
    record = {}
    for name, (make, more) in MADE.items():
        r = make()
        (HERE / f"{name}.pkl").write_bytes(pickle.dumps(r, protocol=4))
        f = FUNCTIONS.get(name, lambda x: x[:, 0] * x[:, 1])
        if isinstance(r, sp.QuadResult):
            later = sp.quad(f, r.d, start=r, **more)
        else:
            later = sp.sobol_indices(f, r.d, start=r, **more)
        record[name] = {"then": summary(r), "continued": summary(later), "more": more}
    (HERE / "quad_pickles.json").write_text(json.dumps(record, indent=1) + "\n")
