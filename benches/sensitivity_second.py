#!/usr/bin/env python3
"""Second-order Sobol' indices: `stillpoint.sobol_indices(..., second_order=True)` against
SALib's Sobol' analysis with `calc_second_order=True` (its Sobol' sample of N·(2d + 2)
points, Saltelli 2002's estimator) at equal evaluations, on the closed-form models of
benches/sensitivity.py: Ishigami (S_13 = V_13 / V, the other pairs 0), three Sobol' G
functions and the product of four inputs (product models: S_ij = Π_{k≠i,j} μ_k²·σ_i²σ_j²
/ V), the linear model (every pair 0) and a G function of 24 inputs of which three
matter (276 pairs).

Both get N·(2d + 2) evaluations (stillpoint also its face test's 8·d, which decides
the lattice's tent per input); the RMSE of all d(d − 1)/2 second-order indices against
the closed form is taken over `--reps` seeds (stillpoint: seeds 0.., SALib: its scramble
seeds 0..). Also printed: the RMSE of the first-order and total indices of the same runs,
and how often each pair lay within stillpoint's own half-width (its coverage).

    python benches/sensitivity_second.py --bases 1024,8192 --reps 10 [--out DIR]
    python benches/sensitivity_second.py --tol 0.01 --reps 20 [--out DIR]

With `--tol`, to a tolerance instead: stillpoint runs with `abs_tol=tol` (every index,
pairs included, to that half-width); SALib doubles its base sample from 64 until every
bootstrap half-width it reports (`S1_conf`, `ST_conf`, `S2_conf`, 100 resamples) is ≤
tol, charged the evaluations of its last sample only. Printed: the median evaluations,
and the share of runs whose every pair landed within tol of the closed form.

Needs SALib (a bench dependency only).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import stillpoint as sp  # noqa: E402
from sensitivity import PI, g_model, ishigami, ishigami_exact, linear_model, product_model  # noqa: E402


def pairs_of_products(mu2, var, total_var):
    """S_ij of a product of independent factors with squared means mu2 and variances
    var, the output's variance total_var."""
    d = len(mu2)
    out = []
    for i in range(d):
        for j in range(i + 1, d):
            rest = np.prod([mu2[k] for k in range(d) if k not in (i, j)])
            out.append(rest * var[i] * var[j] / total_var)
    return np.array(out)


def models():
    """(name, f, d, lower, upper, (first, total), second as the upper triangle)."""
    p4 = PI**4
    v13 = 8 * 0.01 * p4 * p4 / 225
    v = 0.1 * p4 / 5 + 0.01 * p4 * p4 / 50 + 0.5 + 49 / 8 + v13
    out = [("ishigami", ishigami, 3, -PI, PI, ishigami_exact(), np.array([0, v13 / v, 0]))]
    for label, a in [
        ("g-a0-1-4.5-9-99-99", [0, 1, 4.5, 9, 99, 99]),
        ("g-a0x6", [0] * 6),
        ("g-a0-0.5-3-9-99x4", [0, 0.5, 3, 9, 99, 99, 99, 99]),
        ("g-24-sparse", [0, 1, 2] + [99] * 21),
    ]:
        f, ex = g_model(a)
        vi = 1 / (3 * (1 + np.asarray(a, dtype=float)) ** 2)
        second = pairs_of_products(np.ones(len(a)), vi, np.prod(1 + vi) - 1)
        out.append((label, f, len(a), 0.0, 1.0, ex, second))
    f, ex = linear_model([1, 2, 3, 0.5, 0])
    out.append(("linear-5", f, 5, 0.0, 1.0, ex, np.zeros(10)))
    f, ex = product_model(4)
    second = pairs_of_products(np.full(4, 0.25), np.full(4, 1 / 12), 3.0**-4 - 4.0**-4)
    out.append(("product-4", f, 4, 0.0, 1.0, ex, second))
    return out


def upper(m):
    i, j = np.triu_indices(m.shape[0], 1)
    return np.asarray(m)[i, j]


def ours(f, d, lo, hi, n_base, seed):
    faces = 2 * 4 * d
    r = sp.sobol_indices(f, d, a=lo, b=hi, abs_tol=0.0, second_order=True, seed=seed,
                         max_n=n_base * (2 * d + 2) + faces)
    return r.first, r.total, upper(r.second), upper(r.second_half_width), r.n


def salib(f, d, lo, hi, n_base, seed):
    from SALib.analyze import sobol as sa
    from SALib.sample import sobol as ss

    problem = {"num_vars": d, "names": [f"x{i}" for i in range(d)], "bounds": [[lo, hi]] * d}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        x = ss.sample(problem, n_base, calc_second_order=True, scramble=True, seed=seed)
        y = f(x)
        res = sa.analyze(problem, y, calc_second_order=True, seed=seed, num_resamples=2)
    return np.asarray(res["S1"]), np.asarray(res["ST"]), upper(res["S2"]), len(y)


def ours_to(f, d, lo, hi, tol, seed):
    r = sp.sobol_indices(f, d, a=lo, b=hi, abs_tol=tol, second_order=True, seed=seed)
    return upper(r.second), r.n, r.met


def salib_to(f, d, lo, hi, tol, seed, largest=2**16):
    from SALib.analyze import sobol as sa
    from SALib.sample import sobol as ss

    problem = {"num_vars": d, "names": [f"x{i}" for i in range(d)], "bounds": [[lo, hi]] * d}
    n_base = 64
    while True:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            x = ss.sample(problem, n_base, calc_second_order=True, scramble=True, seed=seed)
            y = f(x)
            res = sa.analyze(problem, y, calc_second_order=True, seed=seed,
                             num_resamples=100)
        conf = np.r_[res["S1_conf"], res["ST_conf"], upper(res["S2_conf"])]
        if np.nanmax(conf) <= tol or n_base >= largest:
            return upper(res["S2"]), len(y), bool(np.nanmax(conf) <= tol)
        n_base *= 2


def to_tolerance(a):
    rows = []
    for name, f, d, lo, hi, _, second in models():
        if d > 8:
            continue  # SALib's bootstrap over 276 pairs to 0.01 is beyond this bench's time
        t0 = time.perf_counter()
        res = {"stillpoint": [], "salib": []}
        for seed in range(a.reps):
            for label, run in (("stillpoint", ours_to), ("salib", salib_to)):
                s2, n, met = run(f, d, lo, hi, a.tol, seed)
                res[label].append((n, met, bool(np.all(np.abs(s2 - second) <= a.tol))))
        row = {"model": name, "d": d, "tol": a.tol, "seconds": round(time.perf_counter() - t0, 1)}
        for label, rs in res.items():
            row[f"{label}_median_n"] = float(np.median([n for n, _, _ in rs]))
            row[f"{label}_met"] = float(np.mean([m for _, m, _ in rs]))
            row[f"{label}_within"] = float(np.mean([w for _, _, w in rs]))
        row["ratio"] = row["stillpoint_median_n"] / row["salib_median_n"]
        rows.append(row)
        print(f"{name:20s} tol {a.tol}  ours median n {row['stillpoint_median_n']:.0f} "
              f"(met {row['stillpoint_met']:.2f}, every pair within tol "
              f"{row['stillpoint_within']:.2f})  SALib {row['salib_median_n']:.0f} (met "
              f"{row['salib_met']:.2f}, within {row['salib_within']:.2f})  ratio "
              f"{row['ratio']:.2f}  {row['seconds']} s", flush=True)
    return rows


def rms(xs):
    return float(np.sqrt(np.mean(np.square(xs))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bases", default="1024,8192")
    ap.add_argument("--reps", type=int, default=10)
    ap.add_argument("--out", default=None)
    ap.add_argument("--tol", type=float, default=None)
    a = ap.parse_args()
    if a.tol is not None:
        rows = to_tolerance(a)
        if a.out:
            os.makedirs(a.out, exist_ok=True)
            with open(os.path.join(a.out, f"second_order_tol{a.tol}.json"), "w") as fh:
                json.dump({"command": " ".join(sys.argv), "reps": a.reps, "rows": rows}, fh,
                          indent=1)
        return
    rows = []
    for n_base in [int(x) for x in a.bases.split(",")]:
        for name, f, d, lo, hi, (first, total), second in models():
            t0 = time.perf_counter()
            e_ours, e_salib, e1_ours, e1_salib, covered = [], [], [], [], []
            for seed in range(a.reps):
                s1, st, s2, h2, n_ours = ours(f, d, lo, hi, n_base, seed)
                e_ours.append(s2 - second)
                covered.append(np.abs(s2 - second) <= h2)
                e1_ours.append(np.r_[s1 - first, st - total])
                t1, tt, t2, n_salib = salib(f, d, lo, hi, n_base, seed)
                e_salib.append(t2 - second)
                e1_salib.append(np.r_[t1 - first, tt - total])
            row = {"model": name, "d": d, "n_base": n_base, "evaluations": n_salib,
                   "stillpoint_evaluations": n_ours,
                   "second_rmse": rms(e_ours), "salib_second_rmse": rms(e_salib),
                   "first_total_rmse": rms(e1_ours), "salib_first_total_rmse": rms(e1_salib),
                   "coverage": float(np.mean(covered)),
                   "seconds": round(time.perf_counter() - t0, 1)}
            row["ratio"] = row["second_rmse"] / row["salib_second_rmse"]
            row["ratio_first_total"] = row["first_total_rmse"] / row["salib_first_total_rmse"]
            rows.append(row)
            print(f"{name:20s} N={n_base:5d} evals {n_salib:7d} (ours {n_ours:7d})  "
                  f"S2 RMSE {row['second_rmse']:.2e} vs SALib {row['salib_second_rmse']:.2e} "
                  f"ratio {row['ratio']:.2f}  S1/ST ratio {row['ratio_first_total']:.2f}  "
                  f"coverage {row['coverage']:.2f}  {row['seconds']} s", flush=True)
    g = math.exp(np.mean([math.log(r["ratio"]) for r in rows]))
    print(f"geometric mean of the second-order RMSE ratio: {g:.3f} over {len(rows)} cells; "
          f"largest {max(r['ratio'] for r in rows):.2f}")
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        with open(os.path.join(a.out, "second_order.json"), "w") as fh:
            json.dump({"command": " ".join(sys.argv), "reps": a.reps, "rows": rows,
                       "geomean_ratio": g}, fh, indent=1)


if __name__ == "__main__":
    main()
