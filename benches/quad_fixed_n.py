"""`stillpoint.quad` at a fixed number of evaluations, per rule and number of replicates,
on the families where it needs more evaluations than the references: the coverage of its
interval and the width it pays.

For each case (a family of benches/quad.py: a Genz or model family on the cube, or a
model family of benches/uq_families.py through ``space=``), each seed 0 … SEEDS−1 (a new
instance of the family and a new randomisation) and each setting (``rule``,
``replicates``), ``stillpoint.quad(f, s, abs_tol=0, rel_tol=0, max_n=N, ...)`` runs to
its budget of N evaluations, so its estimate and half-width are the package's own at
exactly N (the round guard included). Per case and setting:

- coverage: the share of seeds whose interval holds the exact integral (at level 0.95;
  with 300 seeds uncertain by about ±1.3 %);
- width: the geometric mean over seeds of the half-width over the exact integral's
  magnitude (the relative tolerance the setting reaches at N, so a setting with half the
  width meets a tolerance about one doubling earlier when the error falls like 1/n);
- rmse: the root mean square relative error of the estimate.

    target/py-venv/bin/python benches/quad_fixed_n.py [--seeds 300] [--n 4096]
    target/py-venv/bin/python benches/quad_fixed_n.py --markdown   # every N measured

Writes results/quad/fixed-n-<N>.json and prints a Markdown table.
"""

import math
import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import quad as bench  # noqa: E402
from quad_interval import study_main  # noqa: E402

CASES = [  # (label, family of benches/quad.py, s)
    ("keister s=5 (cube)", "keister", 5),
    ("keister s=10 (cube)", "keister", 10),
    ("uq keister s=5", "uq keister", 5),
    ("uq keister s=10", "uq keister", 10),
    ("uq gaussian (normal) s=8", "uq gaussian (normal)", 8),
    ("geometric asian m=32 pca", "geometric asian", (32, "pca")),
    ("corner peak s=5 (cube)", "corner peak", 5),
]
SETTINGS = [("sobol", 4), ("lattice", 4), ("sobol", 8), ("lattice", 8)]


def integrand(family, s, seed):
    """(f, d, space texts or None, exact integral) of instance `seed`."""
    if family in bench.MODEL_FAMILIES:
        _, texts, on_values, truth = bench.model(family, s, seed)
        return on_values, s[0] if isinstance(s, tuple) else s, texts, truth
    p = bench.instance(family, s, seed)
    return (lambda x: bench.value(family, p, x)), s, None, bench.exact(family, p)


def run_case(family, s, n, seeds):
    import stillpoint as sp

    rows = {f"{rule} R={r}": [] for rule, r in SETTINGS}
    for seed in range(seeds):
        f, d, space, truth = integrand(family, s, seed)
        for rule, r in SETTINGS:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = sp.quad(f, d, abs_tol=0.0, rel_tol=0.0, max_n=n, replicates=r,
                              space=space, seed=seed, rule=rule)
            rows[f"{rule} R={r}"].append(
                [float(res.estimate - truth) / abs(truth),
                 float(res.half_width) / abs(truth), int(res.n)])
    return rows


def summary(rows):
    out = {}
    for k, v in rows.items():
        a = np.array(v)
        err, hw = a[:, 0], a[:, 1]
        out[k] = {"coverage": float(np.mean(np.abs(err) <= hw)),
                  "width": float(np.exp(np.mean(np.log(np.maximum(hw, 1e-300))))),
                  "rmse": float(math.sqrt(np.mean(err ** 2))),
                  "n": int(np.median(a[:, 2]))}
    return out


def table(data, n):
    """The Markdown table of one N: per case and setting, coverage · width · rmse."""
    names = [f"{rule} R={r}" for rule, r in SETTINGS]
    lines = [f"| family (N = {n}, seeds) | " + " | ".join(names) + " |",
             "|---" * (len(names) + 1) + "|"]
    for label, _, _ in CASES:
        if label not in data:
            continue
        sm = data[label]["summary"]
        cells = [f"{sm[m]['coverage'] * 100:.1f} % · {sm[m]['width']:.2g} · "
                 f"{sm[m]['rmse']:.2g}" for m in names]
        lines.append(f"| {label} ({data[label]['seeds']}) | " + " | ".join(cells) + " |")
    return lines


def main():
    study_main("fixed-n", CASES, run_case, summary, table)


if __name__ == "__main__":
    main()
