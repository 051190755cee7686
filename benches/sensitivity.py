"""Sobol' indices: stillpoint.sobol_indices against SALib (its Sobol' sample, Saltelli /
Jansen estimators, bootstrap intervals) and scipy.stats.sobol_indices, on models with
closed-form indices.

Two measurements:

* equal evaluations: every method gets N·(d + 2) evaluations (N = 2^m base points;
  stillpoint's estimate uses all N, its 8 replicates being blocks of N/8 for the
  interval), and the RMSE of all 2d indices
  against the closed form is taken over `--reps` seeds;
* to a tolerance: stillpoint runs with abs_tol; each reference doubles its base sample N
  (from 64) until every half-width it reports (SALib's bootstrap `*_conf`, SciPy's
  bootstrap interval) is ≤ tol, and is charged the evaluations of its last sample only
  (a generous count: its earlier samples are not added). Also: whether every index
  landed within tol of the closed form.

    python benches/sensitivity.py --out results/sensitivity [--reps 20] [--quick]

Needs SALib and SciPy (bench dependencies only). Writes equal_evaluations.csv,
to_tolerance.csv and summary.json into --out.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import time
import warnings

import numpy as np

import stillpoint as sp

PI = math.pi


# ---------------------------------------------------------------- models (closed forms)


def ishigami(x):
    return np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_exact():
    a, b, p4 = 7.0, 0.1, PI**4
    v1 = b * p4 / 5 + b * b * p4 * p4 / 50 + 0.5
    v2 = a * a / 8
    v13 = 8 * b * b * p4 * p4 / 225
    v = v1 + v2 + v13
    return np.array([v1, v2, 0]) / v, np.array([v1 + v13, v2, v13]) / v


def g_model(a):
    a = np.asarray(a, dtype=float)

    def f(x):
        return np.prod((np.abs(4 * x - 2) + a) / (1 + a), axis=1)

    vi = 1 / (3 * (1 + a) ** 2)
    all_ = np.prod(1 + vi)
    v = all_ - 1
    return f, (vi / v, vi * all_ / (1 + vi) / v)


def linear_model(c):
    c = np.asarray(c, dtype=float)
    s = c**2 / np.sum(c**2)
    return (lambda x: x @ c), (s, s)


def product_model(d):
    v = 3.0**-d - 4.0**-d
    s = np.full(d, 4.0 ** (1 - d) / 12 / v)
    t = np.full(d, 3.0 ** (1 - d) / 12 / v)
    return (lambda x: np.prod(x, axis=1)), (s, t)


def models():
    """(name, f, d, lower, upper, (first, total))."""
    out = [("ishigami", ishigami, 3, -PI, PI, ishigami_exact())]
    for label, a in [
        ("g-a0-1-4.5-9-99-99", [0, 1, 4.5, 9, 99, 99]),
        ("g-a0x6", [0] * 6),
        ("g-a0-0.5-3-9-99x4", [0, 0.5, 3, 9, 99, 99, 99, 99]),
    ]:
        f, ex = g_model(a)
        out.append((label, f, len(a), 0.0, 1.0, ex))
    f, ex = linear_model([1, 2, 3, 0.5, 0])
    out.append(("linear-5", f, 5, 0.0, 1.0, ex))
    f, ex = product_model(4)
    out.append(("product-4", f, 4, 0.0, 1.0, ex))
    # 24 inputs of which three matter: a G function with large coefficients elsewhere.
    f, ex = g_model([0, 1, 2] + [99] * 21)
    out.append(("g-24-sparse", f, 24, 0.0, 1.0, ex))
    return out


# ---------------------------------------------------------------- methods


def ours(f, d, lo, hi, n_base=None, tol=None, seed=0):
    """(first, total, evaluations, max half-width)."""
    if tol is None:
        # N·(d + 2) evaluations, and the face test's 2·d at each of its 4 points (it decides
        # the lattice's tent per input before the first batch).
        faces = 2 * 4 * d
        r = sp.sobol_indices(f, d, a=lo, b=hi, abs_tol=0.0, max_n=n_base * (d + 2) + faces,
                             seed=seed)
    else:
        r = sp.sobol_indices(f, d, a=lo, b=hi, abs_tol=tol, seed=seed)
    h = max(np.max(r.first_half_width), np.max(r.total_half_width))
    return r.first, r.total, r.n, h, r.met


def salib(f, d, lo, hi, n_base, seed=0, conf=False):
    from SALib.analyze import sobol as sa
    from SALib.sample import sobol as ss

    problem = {"num_vars": d, "names": [f"x{i}" for i in range(d)], "bounds": [[lo, hi]] * d}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        x = ss.sample(problem, n_base, calc_second_order=False, scramble=True, seed=seed)
        y = f(x)
        res = sa.analyze(problem, y, calc_second_order=False, seed=seed,
                         num_resamples=100 if conf else 2)
    h = max(np.max(res["S1_conf"]), np.max(res["ST_conf"])) if conf else float("nan")
    return np.asarray(res["S1"]), np.asarray(res["ST"]), len(y), h


def scipy_si(f, d, lo, hi, n_base, seed=0, conf=False):
    from scipy.stats import sobol_indices, uniform

    dists = [uniform(loc=lo, scale=hi - lo)] * d

    def func(x):  # SciPy passes (d, n) and wants (s, n)
        return f(x.T)[None, :]

    rng = np.random.default_rng(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = sobol_indices(func=func, n=n_base, dists=dists, rng=rng)
        h = float("nan")
        if conf:
            b = res.bootstrap(confidence_level=0.95, n_resamples=100)
            h = max(
                np.max((b.first_order.confidence_interval.high
                        - b.first_order.confidence_interval.low) / 2),
                np.max((b.total_order.confidence_interval.high
                        - b.total_order.confidence_interval.low) / 2),
            )
    return (np.ravel(res.first_order), np.ravel(res.total_order), n_base * (d + 2), h)


def qmcpy_si(f, d, lo, hi, n_base=None, seed=0, tol=None, largest=2**17):
    """QMCPy's SensitivityIndices on its randomised digital net (LMS + digital shift):
    at n_base points, its estimates from the means of its pick-freeze integrand; with
    tol, CubQMCNetG to abs_tol on every index (its own guaranteed bounds). Evaluations
    are counted at f (QMCPy skips the indices already within tol)."""
    import qmcpy

    calls = [0]

    def g(x):
        shape = x.shape
        flat = x.reshape(-1, shape[-1])
        calls[0] += flat.shape[0]
        return f(flat).reshape(shape[:-1])

    net = qmcpy.DigitalNetB2(d, seed=seed)
    integrand = qmcpy.CustomFun(qmcpy.Uniform(net, lower_bound=lo, upper_bound=hi), g=g)
    si = qmcpy.SensitivityIndices(integrand, indices="singletons")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if tol is None:
            m = si(n_base).mean(-1)  # (closed/total, (numerator, mean, 2nd moment), d)
            first, total = (m[k, 0] / (m[k, 2] - m[k, 1] ** 2) for k in (0, 1))
            return first, total, calls[0], float("nan")
        sol, data = qmcpy.CubQMCNetG(si, abs_tol=tol, n_limit=largest).integrate()
    h = float(np.max((data.comb_bound_high - data.comb_bound_low) / 2))
    return np.asarray(sol[0]), np.asarray(sol[1]), calls[0], h


def rmse(first, total, exact):
    e = np.concatenate([first - exact[0], total - exact[1]])
    return float(np.sqrt(np.mean(e**2)))


# ---------------------------------------------------------------- runs


def equal_evaluations(out, reps, bases):
    rows = []
    for name, f, d, lo, hi, exact in models():
        for n_base in bases:
            se = {"stillpoint": [], "salib": [], "scipy": [], "qmcpy": []}
            evals = {}
            for seed in range(reps):
                fs, ts, n, _, _ = ours(f, d, lo, hi, n_base=n_base, seed=seed)
                se["stillpoint"].append(rmse(fs, ts, exact) ** 2)
                evals["stillpoint"] = n
                fs, ts, n, _ = salib(f, d, lo, hi, n_base, seed=seed)
                se["salib"].append(rmse(fs, ts, exact) ** 2)
                evals["salib"] = n
                fs, ts, n, _ = scipy_si(f, d, lo, hi, n_base, seed=seed)
                se["scipy"].append(rmse(fs, ts, exact) ** 2)
                evals["scipy"] = n
                fs, ts, n, _ = qmcpy_si(f, d, lo, hi, n_base, seed=seed)
                se["qmcpy"].append(rmse(fs, ts, exact) ** 2)
                evals["qmcpy"] = n
            row = {"model": name, "d": d, "n_base": n_base}
            for m in se:
                row[f"{m}_rmse"] = math.sqrt(np.mean(se[m]))
                row[f"{m}_evals"] = evals[m]
            row["ratio_salib"] = row["stillpoint_rmse"] / row["salib_rmse"]
            row["ratio_scipy"] = row["stillpoint_rmse"] / row["scipy_rmse"]
            row["ratio_qmcpy"] = row["stillpoint_rmse"] / row["qmcpy_rmse"]
            print(
                f"{name:22s} N={n_base:6d}  ours {row['stillpoint_rmse']:.2e}  "
                f"SALib {row['salib_rmse']:.2e}  SciPy {row['scipy_rmse']:.2e}  "
                f"QMCPy {row['qmcpy_rmse']:.2e}  ratios {row['ratio_salib']:.2f} "
                f"{row['ratio_scipy']:.2f} {row['ratio_qmcpy']:.2f}",
                flush=True,
            )
            rows.append(row)
    write_csv(os.path.join(out, "equal_evaluations.csv"), rows)
    return rows


def to_tolerance(out, tol, reps, largest, ours_only=False):
    """With ours_only, the references' columns are read from the to_tolerance.csv in
    `out` (same models, seeds and tolerance; their code does not depend on ours)."""
    rows = []
    earlier = {}
    if ours_only:
        with open(os.path.join(out, "to_tolerance.csv")) as fh:
            for r in csv.DictReader(fh):
                assert float(r["tol"]) == tol, "--ours-only needs the earlier run's --tol"
                earlier[(r["model"], int(r["seed"]))] = {
                    k: (count(v) if k.endswith("_evals") else
                        float(v) if k.endswith("_share_within") else v)
                    for k, v in r.items() if not k.startswith("stillpoint")}
    for name, f, d, lo, hi, exact in models():
        for seed in range(reps):
            row = {"model": name, "d": d, "tol": tol, "seed": seed}
            fs, ts, n, h, met = ours(f, d, lo, hi, tol=tol, seed=seed)
            row.update(stillpoint_evals=n, stillpoint_met=met,
                       stillpoint_within=bool(np.all(np.abs(fs - exact[0]) <= tol)
                                              and np.all(np.abs(ts - exact[1]) <= tol)),
                       stillpoint_share_within=share_within(fs, ts, exact, tol))
            if ours_only:
                row.update({k: v for k, v in earlier[(name, seed)].items() if k not in row})
                print(f"{name:22s} seed {seed}  ours {n}", flush=True)
                rows.append(row)
                continue
            for label, method in (("salib", salib), ("scipy", scipy_si)):
                n_base, done = 64, False
                # SciPy's bootstrap holds O(N²) memory (16384 base points need > 6 GB).
                top = min(largest, SCIPY_LARGEST) if label == "scipy" else largest
                while n_base <= top:
                    fs, ts, n, h = method(f, d, lo, hi, n_base, seed=seed, conf=True)
                    if h <= tol:
                        done = True
                        break
                    n_base *= 2
                row.update({f"{label}_evals": n if done else float("nan"),
                            f"{label}_met": done,
                            f"{label}_share_within": share_within(fs, ts, exact, tol)})
            fs, ts, n, h = qmcpy_si(f, d, lo, hi, seed=seed, tol=tol, largest=largest)
            row.update(qmcpy_evals=n if h <= tol else float("nan"), qmcpy_met=h <= tol,
                       qmcpy_share_within=share_within(fs, ts, exact, tol))
            print(f"{name:22s} seed {seed}  ours {row['stillpoint_evals']}  SALib "
                  f"{row['salib_evals']}  SciPy {row['scipy_evals']}  QMCPy "
                  f"{row['qmcpy_evals']}", flush=True)
            rows.append(row)
    write_csv(os.path.join(out, "to_tolerance.csv"), rows)
    return rows


# A reference counts as a competitor on a model only where it is reliable: at least this
# share of its runs ended with every index within the tolerance (as stillpoint is held).
RELIABLE = 0.95


def best_references(rows, methods=("salib", "scipy", "qmcpy")):
    """Per model, the reference with the fewest evaluations to the tolerance (median over
    its runs that met it) and the fewest among the reliable ones (every index within the
    tolerance in at least RELIABLE of its runs; its median over all its runs)."""
    out = {}
    for name in dict.fromkeys(r["model"] for r in rows):
        rs = [r for r in rows if r["model"] == name]
        best = {"best_reference": None, "best_reliable_reference": None}
        cands, reliable = [], []
        for m in methods:
            evals = [r[f"{m}_evals"] for r in rs if math.isfinite(float(r[f"{m}_evals"]))]
            if not evals:
                continue
            median = float(np.median(evals))
            share = float(np.mean([float(r[f"{m}_share_within"]) == 1.0 for r in rs]))
            cands.append((median, m))
            if share >= RELIABLE and len(evals) == len(rs):
                reliable.append((median, m))
            best[f"{m}_runs_all_within"] = share
        if cands:
            best["best_reference"] = "%s (%d)" % (min(cands)[1], min(cands)[0])
        if reliable:
            best["best_reliable_reference"] = "%s (%d)" % (min(reliable)[1], min(reliable)[0])
        out[name] = best
    return out


def count(text):
    """An evaluation count as written to the CSV: an integer, or nan (not reached)."""
    x = float(text)
    return int(x) if math.isfinite(x) else x


# The largest base sample SciPy's bootstrap is asked for.
SCIPY_LARGEST = 8192


def share_within(first, total, exact, tol):
    e = np.concatenate([np.abs(first - exact[0]), np.abs(total - exact[1])])
    return float(np.mean(e <= tol))


def write_csv(path, rows):
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


def geomean(v):
    v = [x for x in v if x > 0 and math.isfinite(x)]
    return math.exp(sum(map(math.log, v)) / len(v)) if v else float("nan")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default="results/sensitivity")
    p.add_argument("--reps", type=int, default=20)
    p.add_argument("--tol-reps", type=int, default=5)
    p.add_argument("--tol", type=float, default=0.01)
    p.add_argument("--bases", default="1024,8192")
    p.add_argument("--largest", type=int, default=2**17)
    p.add_argument("--skip-tolerance", action="store_true")
    p.add_argument("--ours-only", action="store_true",
                   help="to a tolerance, rerun stillpoint only; the references' columns "
                        "from to_tolerance.csv in --out")
    p.add_argument("--skip-equal", action="store_true",
                   help="read equal_evaluations.csv from --out instead of running it")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    from importlib.metadata import version

    started = time.time()
    if a.skip_equal:
        with open(os.path.join(a.out, "equal_evaluations.csv")) as fh:
            eq = [{k: (float(v) if k.startswith("ratio") else v) for k, v in r.items() if v}
                  for r in csv.DictReader(fh)]
    else:
        eq = equal_evaluations(a.out, a.reps, [int(b) for b in a.bases.split(",")])
    summary = {
        "versions": {"stillpoint": sp.__version__, "SALib": version("salib"),
                     "scipy": version("scipy"), "qmcpy": version("qmcpy"),
                     "numpy": np.__version__},
        "reps": a.reps,
        "bases": a.bases,
        "geomean_ratio_salib": geomean([r["ratio_salib"] for r in eq]),
        "geomean_ratio_scipy": geomean([r["ratio_scipy"] for r in eq]),
        "geomean_ratio_qmcpy": geomean([r["ratio_qmcpy"] for r in eq if "ratio_qmcpy" in r]),
        "max_ratio_salib": max(r["ratio_salib"] for r in eq),
        "max_ratio_scipy": max(r["ratio_scipy"] for r in eq),
        "max_ratio_qmcpy": max((r["ratio_qmcpy"] for r in eq if "ratio_qmcpy" in r),
                               default=float("nan")),
    }
    if not a.skip_tolerance:
        tt = to_tolerance(a.out, a.tol, a.tol_reps, a.largest, a.ours_only)
        per = {}
        for r in tt:
            m = per.setdefault(r["model"], {"stillpoint": [], "salib": [], "scipy": [],
                                            "qmcpy": [], "within": []})
            for k in ("stillpoint", "salib", "scipy", "qmcpy"):
                m[k].append(r[f"{k}_evals"])
            m["within"].append(r["stillpoint_share_within"])
        summary["to_tolerance"] = {
            name: {k: (float(np.median(v)) if k != "within" else float(np.mean(v)))
                   for k, v in m.items()}
            for name, m in per.items()
        }
        for name, best in best_references(tt).items():
            summary["to_tolerance"][name].update(best)
        summary["tol"] = a.tol
        summary["tol_reps"] = a.tol_reps
    summary["seconds"] = round(time.time() - started, 1)
    with open(os.path.join(a.out, "summary.json"), "w") as fh:
        json.dump(summary, fh, indent=2)
    print(json.dumps(summary, indent=2))


if __name__ == "__main__":
    main()
