"""Integration to a tolerance: `stillpoint.quad` against QMCPy's adaptive cubatures and
SciPy's `qmc_quad` with n doubled until its interval is narrow enough.

Per cell (integrand family, s, relative tolerance) and method, over RUNS runs (each a new
random instance of the family and a new seed; the integrands and their exact integrals
are in benches/quad_models.py):
- reliability: the share of runs whose true relative error is within the tolerance AND
  the method says it met the tolerance (a run stopped by the budget of 2^20 evaluations
  counts as a failure, whatever its error);
- the median number of evaluations of f (every evaluation counted, including rounds a
  method throws away);
- the median time outside f: the wall time of the method's call minus the time spent
  inside f (f is wrapped in a timer; the point generation, transforms, error estimate
  and bookkeeping are what remains). The JSONs also hold the same difference in the
  process's CPU time (``outside_cpu``), which the other loads of a shared machine
  disturb less (it adds up all threads, though). On the model families the references'
  f is the model after the map through the laws' quantiles, stillpoint's the model
  alone (``space=`` maps inside quad), so the JSONs also hold the time outside the
  model itself (``outside_model``, ``outside_model_cpu``: the map counted as the
  method's work for every method).

Families (quad_models.py): Genz's oscillatory, product peak, corner peak and gaussian
and the models keister and lognormal at s = 2, 5, 10, 20, and ishigami at s = 3, all on
the unit cube. The model families of benches/uq_families.py with a closed-form mean
(``MODEL_FAMILIES``: uq keister s = 5, 10; the oscillatory and gaussian Genz functions
of normal inputs, s = 8; the lognormal product and Morokoff–Caflisch, s = 10; the
geometric-average Asian call on a 32-step path, PCA and standard construction) are
integrated by stillpoint against their laws through ``space=`` (so quad chooses its
rule from them) and by the references on the cube through the same laws' quantiles.
Tolerances: 1e-2, 1e-3, 1e-4, 1e-5, relative (abs_tol = 0 everywhere). A method is
reliable in a cell at 185 of 200 runs (92.5 %, the one-sided binomial bound for 95 %).

Methods (the budget, max_n or n_limit, is 2^20 evaluations for all):
- ``stillpoint``: ``stillpoint.quad(f, s, rel_tol=tol, seed=run)`` (``space=`` the
  laws for the model families; 4 replicates of the rule chosen from the laws, 64
  points each first, the Student t interval at 95 % guarded by the round's change).
- ``qmcpy-lattice``, ``qmcpy-net``: ``CubQMCLatticeG`` (``Lattice(s, seed=run)``, its
  default Baker transform) and ``CubQMCNetG`` (``DigitalNetB2(s, seed=run)``) at their
  defaults (n_init = 1024) with ``abs_tol=0, rel_tol=tol, n_limit=2**20``.
- ``qmcpy-lattice-512``, ``qmcpy-net-512``: the same with ``n_init=512``, stillpoint's
  first round (8 × 64).
- ``qmcpy-rep``: ``CubQMCRepStudentT`` at its defaults (n_init = 256 points per
  replication, alpha = 0.01) on ``Lattice(s, replications=25, seed=run)`` (the class has
  no default number of replications; 25 is the one of QMCPy's own examples).
- ``qmcpy-rep-8x64``: the same with 8 replications of n_init = 64 points (stillpoint's
  first round), alpha still QMCPy's default 0.01.
- ``qmcpy-bayes-lattice``, ``qmcpy-bayes-net``: ``CubBayesLatticeG`` (``Lattice(s,
  seed=run)``) and ``CubBayesNetG`` (``DigitalNetB2(s, seed=run)``) at their defaults
  with ``abs_tol=0, rel_tol=tol, n_limit=2**20``.
- ``qmc_quad``: ``scipy.integrate.qmc_quad`` with 8 scrambled Sobol' estimates of n
  points, n = 64, 128, ... until t_{7,0.975}·standard error ≤ tol·|integral| (each round
  starts afresh; the rounds thrown away are counted).
QMCPy's "met" is its ``comb_flags`` with no ``MaxSamplesWarning`` (the warning it gives
when the next doubling would pass n_limit).

Every method's per-cell results go to results/quad/<method>.json.gz as each cell finishes;
a later call skips cells already holding the requested runs, and continues a cell that
holds fewer (so an interrupted run resumes). ``--cell-seconds T`` stops a cell after
the run that takes its wall time (over all calls) past T; the runs done are recorded and
the table says how many there were.

QMCPy lives in its own environment (target/bench-venv: ``python3 -m venv
target/bench-venv && target/bench-venv/bin/pip install qmcpy``), so the script runs once
per environment and the table merges the JSONs. On 2 shared cores, two processes on
disjoint methods, ``qmc_quad`` after whichever of the two finishes first:

    nice -n 5 target/bench-venv/bin/python benches/quad.py --runs 200 --cell-seconds 15 \\
        --methods qmcpy-lattice,qmcpy-lattice-512,qmcpy-rep &
    nice -n 5 target/bench-venv/bin/python benches/quad.py --runs 200 --cell-seconds 15 \\
        --methods qmcpy-net,qmcpy-net-512,qmcpy-rep-8x64 &
    wait -n; nice -n 5 target/bench-venv/bin/python benches/quad.py --runs 200 \\
        --cell-seconds 15 --methods qmc_quad; wait
    target/py-venv/bin/python benches/quad.py --runs 200 --cell-seconds 15 --methods stillpoint
    target/py-venv/bin/python benches/quad.py --runs 200 --cell-seconds 60 --methods stillpoint
    target/py-venv/bin/python benches/quad.py --table

On 2 cores shared with other work (load 4 to 6) the seven reference methods took 66
minutes of wall time (6980 s summed over the cells, 14 to 19 minutes per method; 36 to
59 of each method's 100 cells were stopped by the 15 s cap), ``stillpoint`` about 10.

``--check-keister`` (bench-venv) compares the Keister values with QMCPy's recurrence;
``--check-space`` (py-venv) integrates the lognormal instances through stillpoint's own
``space=`` (SciPy's lognormal laws) as well as on the cube and prints both estimates.
``--rerun-unmet --methods stillpoint`` runs again, in place, the stored runs that did
not meet their tolerance (after a change that acts only once a run can no longer
double, the others cannot change). ``--rerun-above N --methods stillpoint`` runs again,
in place, the stored runs that made more than N evaluations, met or not (after a change
that acts only on a run's last rounds, such as how a doubling that passes the budget is
made). ``--families``, ``--s`` and ``--tols`` restrict the cells (e.g. ``--families keister
--s 20 --tols 1e-5``); ``--runs 5 --out /tmp/quad`` is a quick check. Writes
results/quad/<method>.json.gz and results/quad/quad.md.
"""

import argparse
import gzip
import json
import math
import os
import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from quad_models import FAMILIES as CUBE_FAMILIES  # noqa: E402
from quad_models import exact, instance, keister_exact, value  # noqa: E402
import uq_families as uq  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The model families of benches/uq_families.py with a closed-form mean, under the names
# the table uses: (family, variants). Each is integrated by stillpoint through
# ``space=`` (the family's laws as stillpoint's texts, so the rule is chosen from them)
# and by the references on the cube through the same laws' quantiles (``map_cube``).
# ``geometric asian`` is the path family's geometric-average call (a kink; closed form).
MODEL_FAMILIES = {
    "uq keister": ("keister", [5, 10]),
    "uq oscillatory (normal)": ("genz oscillatory (normal)", [8]),
    "uq gaussian (normal)": ("genz gaussian (normal)", [8]),
    "uq lognormal product": ("lognormal product", [10]),
    "uq morokoff-caflisch": ("morokoff-caflisch", [10]),
    "geometric asian": ("asian call", [(32, "pca"), (32, "standard")]),
}
FAMILIES = dict(CUBE_FAMILIES)
FAMILIES.update({k: v for k, (_, v) in MODEL_FAMILIES.items()})


def model(family, v, run, wrap=lambda g: g):
    """(f on the cube, the space's texts, f on the space's values, exact) of instance
    `run` of a model family; `wrap` wraps the model on the space's values before f on
    the cube is built from it (a timer of the model alone)."""
    fam = uq.BY_NAME[MODEL_FAMILIES[family][0]]
    p = uq.instance(fam, v, run)
    laws = fam.laws(v, p)
    if family == "geometric asian":
        def on_values(x):
            return fam.payoffs(v, p, fam.prepare(v, x))[1]
        truth = fam.geometric_exact(v, p)
    else:
        def on_values(x):
            return fam.value(v, p, fam.prepare(v, x))
        truth = fam.exact(v, p)

    on_values = wrap(on_values)

    def on_cube(u):
        return on_values(uq.map_cube(laws, u))

    return on_cube, [uq.law_text(n, law) for n, law in laws], on_values, float(truth)
TOLS = [1e-2, 1e-3, 1e-4, 1e-5]
MAX_N = 2**20
RULE = None  # --rule
T_7 = 2.3646242510102993  # t_{7, 0.975}
RELIABLE = 0.925  # 185 of 200 runs: the one-sided binomial bound for 95 %


def run_stillpoint(g, s, tol, seed, space=None):
    import stillpoint as sp

    r = sp.quad(g, s, rel_tol=tol, seed=seed, max_n=MAX_N, space=space,
                **({"rule": RULE} if RULE else {}))
    return r.estimate, r.n, r.met


def run_qmc_quad(g, s, tol, seed):
    from scipy.integrate import qmc_quad
    from scipy.stats import qmc

    total, n = 0, 64
    rng = np.random.default_rng(seed)
    while total + 8 * n <= MAX_N:
        # qmc_quad passes points as (s, n) and probes f once at the centre, (s,).
        res = qmc_quad(lambda x: g(x.T) if x.ndim == 2 else g(x[None, :])[0],
                       np.zeros(s), np.ones(s), n_estimates=8,
                       n_points=n, qrng=qmc.Sobol(s, scramble=True, rng=rng))
        total += 8 * n
        if T_7 * res.standard_error <= tol * abs(res.integral):
            return res.integral, total, True
        n *= 2
    return res.integral, total, False


def run_qmcpy(kind, g, s, tol, seed):
    import qmcpy as qp

    def gq(t):
        # Points come as (n, s), or (replications, n, s) for CubQMCRepStudentT.
        return g(t.reshape(-1, s)).reshape(t.shape[:-1])

    if kind.startswith("lattice"):
        dist, cub = qp.Lattice(s, seed=seed), qp.CubQMCLatticeG
    elif kind.startswith("net"):
        dist, cub = qp.DigitalNetB2(s, seed=seed), qp.CubQMCNetG
    elif kind == "bayes-lattice":
        dist, cub = qp.Lattice(s, seed=seed), qp.CubBayesLatticeG
    elif kind == "bayes-net":
        dist, cub = qp.DigitalNetB2(s, seed=seed), qp.CubBayesNetG
    elif kind == "rep":
        dist, cub = qp.Lattice(s, replications=25, seed=seed), qp.CubQMCRepStudentT
    else:
        dist, cub = qp.Lattice(s, replications=8, seed=seed), qp.CubQMCRepStudentT
    extra = {}
    if kind in ("lattice-512", "net-512"):
        extra["n_init"] = 512
    elif kind == "rep-8x64":
        extra["n_init"] = 64
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        integrand = qp.CustomFun(qp.Uniform(dist), g=gq)
        c = cub(integrand, abs_tol=0.0, rel_tol=tol, n_limit=MAX_N, **extra)
        sol, data = c.integrate()
    hit_max = any(issubclass(w.category, qp.util.MaxSamplesWarning) for w in caught)
    met = bool(np.all(data.comb_flags)) and not hit_max
    return float(np.ravel(sol)[0]), int(np.ravel(data.n_total)[0]), met


METHODS = {
    "stillpoint": run_stillpoint,
    "qmcpy-lattice": lambda g, s, tol, seed: run_qmcpy("lattice", g, s, tol, seed),
    "qmcpy-lattice-512": lambda g, s, tol, seed: run_qmcpy("lattice-512", g, s, tol, seed),
    "qmcpy-net": lambda g, s, tol, seed: run_qmcpy("net", g, s, tol, seed),
    "qmcpy-net-512": lambda g, s, tol, seed: run_qmcpy("net-512", g, s, tol, seed),
    "qmcpy-rep": lambda g, s, tol, seed: run_qmcpy("rep", g, s, tol, seed),
    "qmcpy-rep-8x64": lambda g, s, tol, seed: run_qmcpy("rep-8x64", g, s, tol, seed),
    "qmc_quad": run_qmc_quad,
    "qmcpy-bayes-lattice": lambda g, s, tol, seed: run_qmcpy("bayes-lattice", g, s, tol, seed),
    "qmcpy-bayes-net": lambda g, s, tol, seed: run_qmcpy("bayes-net", g, s, tol, seed),
}
REFERENCES = [m for m in METHODS if m != "stillpoint"]


def version(method):
    if method.startswith("qmcpy"):
        import qmcpy

        return f"qmcpy {qmcpy.__version__}"
    if method == "stillpoint":
        import stillpoint

        return f"stillpoint {stillpoint.__version__}"
    import scipy

    return f"scipy {scipy.__version__}"


def key(family, s, tol):
    return f"{family}|{s}|{tol:g}"


def one_run(method, family, s, tol, run):
    space = None
    # Wall and CPU time inside the model itself (on the model families, without the
    # map through the laws a reference's f holds).
    in_model = [0.0, 0.0]

    def timed(h):
        def wrapped(x):
            t, c = time.perf_counter(), time.process_time()
            y = h(x)
            in_model[0] += time.perf_counter() - t
            in_model[1] += time.process_time() - c
            return y
        return wrapped

    if family in MODEL_FAMILIES:
        on_cube, texts, on_values, truth = model(family, s, run, wrap=timed)
        # stillpoint integrates against the laws themselves; the references on the cube.
        fun = on_values if method == "stillpoint" else on_cube
        space = texts if method == "stillpoint" else None
    else:
        p = instance(family, s, run)
        truth = exact(family, p)

        @timed
        def fun(x):
            return value(family, p, x)
    dim = s[0] if isinstance(s, tuple) else s
    calls = [0, 0.0, 0.0]

    def g(x):
        t, c = time.perf_counter(), time.process_time()
        y = fun(np.asarray(x, dtype=np.float64))
        calls[0] += x.shape[0]
        calls[1] += time.perf_counter() - t
        calls[2] += time.process_time() - c
        return y

    t0, c0 = time.perf_counter(), time.process_time()
    if space is not None:
        est, n, met = run_stillpoint(g, dim, tol, run, space=space)
    else:
        est, n, met = METHODS[method](g, dim, tol, run)
    seconds = time.perf_counter() - t0
    cpu = time.process_time() - c0
    err = abs(est - truth) / abs(truth)
    return {"run": run, "rel_error": float(f"{err:.3g}"), "n": int(n), "calls_n": calls[0],
            "met": bool(met), "ok": bool(met and err <= tol),
            "seconds": round(seconds, 5), "outside": round(seconds - calls[1], 5),
            "outside_cpu": round(cpu - calls[2], 5),
            "outside_model": round(seconds - in_model[0], 5),
            "outside_model_cpu": round(cpu - in_model[1], 5)}


def load(path):
    if os.path.exists(path):
        with gzip.open(path, "rt") as fh:
            d = json.load(fh)
        if isinstance(d.get("cells"), dict):
            return d
    return None


def save(path, d):
    # Compressed (the run files are ~2 MB of JSON each) with no timestamp in the header,
    # so that the same runs give the same bytes.
    tmp = path + ".tmp"
    with open(tmp, "wb") as raw, gzip.GzipFile(fileobj=raw, mode="wb", mtime=0) as fh:
        fh.write(json.dumps(d, separators=(",", ":")).encode())
    os.replace(tmp, path)


def measure(method, cells, runs, cell_seconds, out):
    path = os.path.join(out, f"{method}.json.gz")
    d = load(path) or {"method": method, "cells": {}}
    d["version"] = version(method)
    for family, s, tol in cells:
        k = key(family, s, tol)
        cell = d["cells"].setdefault(k, {"family": family, "s": s, "tol": tol,
                                         "seconds": 0.0, "runs": []})
        rows = cell["runs"]
        if len(rows) >= runs or (cell_seconds and cell["seconds"] >= cell_seconds):
            continue
        while len(rows) < runs:
            if cell_seconds and cell["seconds"] >= cell_seconds:
                break
            t = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                rows.append(one_run(method, family, s, tol, len(rows)))
            cell["seconds"] = round(cell["seconds"] + time.perf_counter() - t, 3)
        cell["cell_seconds"] = cell_seconds
        save(path, d)
        ok = np.mean([r["ok"] for r in rows])
        med = np.median([r["calls_n"] for r in rows])
        print(f"{method:17s} {family:12s} s={str(s):>2s} tol={tol:g}: reliability {ok:.2f}, "
              f"median n {med:.0f}, runs {len(rows)}, {cell['seconds']:.1f} s", flush=True)


def fmt_ms(sec):
    ms = sec * 1e3
    return f"{ms:.2g}" if ms < 10 else f"{ms:.0f}"


def table(out, runs):
    data = {}
    for m in METHODS:
        d = load(os.path.join(out, f"{m}.json.gz"))
        if d:
            data[m] = d
    methods = [m for m in METHODS if m in data]
    refs = [m for m in REFERENCES if m in data]
    order = [key(f, s, t) for f, ss in FAMILIES.items() for s in ss for t in TOLS]
    order = [k for k in order if any(k in data[m]["cells"] for m in methods)]

    def stats(m, k):
        c = data[m]["cells"].get(k)
        if not c or not c["runs"]:
            return None
        rs = c["runs"]
        return {"rel": float(np.mean([r["ok"] for r in rs])),
                "n": float(np.median([r["calls_n"] for r in rs])),
                "out": float(np.median([r["outside"] for r in rs])), "runs": len(rs),
                # Outside the model itself, where every run recorded it (see above).
                "out_model": (float(np.median([r["outside_model"] for r in rs]))
                              if all("outside_model" in r for r in rs) else None)}

    short = []
    lines = ["# Integration to a tolerance", "",
             "Per cell and method: reliability (share of runs with true relative error ≤ "
             "tol and the method saying it met the tolerance; stopping at the budget of "
             "2^20 evaluations is a failure) · median evaluations of f (all rounds) · "
             f"median time outside f in ms. {runs} runs per cell unless the cell says "
             "otherwise in brackets (its per-cell wall-time cap stopped it first). "
             "Best reference: the reference method with ≥ 92.5 % reliability (185 of 200, "
             "the one-sided binomial bound for 95 %) and the fewest "
             "median evaluations; ratio: stillpoint's median evaluations over that one's; "
             "✔ when stillpoint is ≥ 92.5 % reliable and the ratio ≤ 1. "
             "Written by `benches/quad.py --table` (commands in its docstring; machine: "
             "2 shared cores).", "",
             "| family | s | tol | " + " | ".join(methods)
             + " | best reference | ratio | ✔ |",
             "|---|---|---|" + "---|" * len(methods) + "---|---|---|"]
    ratios, misses, met, no_ref, counted = [], [], 0, [], 0
    for k in order:
        family, s, tol = k.split("|")
        row = [family, s, tol]
        st = {m: stats(m, k) for m in methods}
        for m in methods:
            v = st[m]
            if v is None:
                row.append("—")
                continue
            cellt = f"{v['rel']:.0%} · {v['n']:.0f} · {fmt_ms(v['out'])}"
            if v["runs"] < runs:
                cellt += f" ({v['runs']})"
                short.append((m, k, v["runs"]))
            row.append(cellt)
        good = [m for m in refs if st[m] and st[m]["rel"] >= RELIABLE]
        best = min(good, key=lambda m: st[m]["n"]) if good else None
        sp = st.get("stillpoint")
        if not any(st[m] for m in refs):
            row += ["no reference run", "—", "—"]
        elif best is None:
            row += ["none ≥ 92.5 %", "—"]
            if sp is not None:
                counted += 1
                ok = sp["rel"] >= RELIABLE
                no_ref.append((k, ok))
                met += ok
                row.append("✔" if ok else "✘")
                if not ok:
                    misses.append(f"{family}, s={s}, tol={tol}: stillpoint {sp['rel']:.0%} "
                                  "reliable (no reference reaches 92.5 % either)")
            else:
                row.append("—")
        elif sp is None:
            row += [best, "—", "—"]
        else:
            counted += 1
            ratio = sp["n"] / st[best]["n"]
            ratios.append(ratio)
            ok = sp["rel"] >= RELIABLE and ratio <= 1
            met += ok
            row += [best, f"{ratio:.2f}", "✔" if ok else "✘"]
            if not ok:
                why = []
                if sp["rel"] < RELIABLE:
                    why.append(f"reliability {sp['rel']:.0%} < 92.5 %")
                if ratio > 1:
                    why.append(f"{ratio:.2f}× the evaluations of {best}")
                misses.append(f"{family}, s={s}, tol={tol}: " + "; ".join(why))
        lines.append("| " + " | ".join(row) + " |")
    lines.append("")
    if "stillpoint" in data:
        gm = math.exp(np.mean(np.log(ratios))) if ratios else float("nan")
        lines += [f"Cells meeting it (stillpoint ≥ 92.5 % reliable and no more evaluations "
                  f"than the best reliable reference): {met} of {counted}.", "",
                  f"Geometric mean of the ratio over the {len(ratios)} cells with a "
                  f"reliable reference: {gm:.3f} (the claim: ≤ 0.7).", ""]
        if no_ref:
            lines += [f"Cells where no reference reaches 92.5 %: {len(no_ref)} (stillpoint "
                      f"≥ 92.5 % in {sum(ok for _, ok in no_ref)}); they are counted above on "
                      "stillpoint's reliability alone and left out of the mean.", ""]
        lines += time_outside_lines(data, order, stats)
        lines += ["Cells that miss:" if misses else "No cell misses.", ""]
        lines += [f"- {m}" for m in misses]
        lines.append("")
    else:
        lines += ["stillpoint's results are not in this table yet.", ""]
    if short:
        per = []
        for m in methods:
            mine = [r for (mm, _, r) in short if mm == m]
            if mine:
                per.append(f"{m} {len(mine)} (fewest runs: {min(mine)})")
        lines += [f"(Runs) in brackets: cells with fewer than {runs} runs, stopped by the "
                  "per-cell wall-time cap (`--cell-seconds`): " + ", ".join(per) + ". "
                  "A capped cell holds the first runs (instances and seeds 0, 1, ...), "
                  "so its reliability is that of fewer instances; each method's figures "
                  "are over its own runs.", ""]
    lines += ["Versions: " + ", ".join(f"{m}: {data[m]['version']}" for m in methods), ""]
    with open(os.path.join(out, "quad.md"), "w") as fh:
        fh.write("\n".join(lines))
    print("\n".join(lines))


def time_outside_lines(data, order, stats):
    """Per QMCPy method, the median over the cells both ran of the ratio of stillpoint's
    median time outside f to that method's (the claim: ≤ 1)."""
    lines = []
    for what, keep in [("all cells", lambda f: True),
                       ("the model families", lambda f: f in MODEL_FAMILIES)]:
        for field, said in [
                ("out", f"Time outside f over {what}, the median over the cells of "
                        "stillpoint's median over the reference's (the claim: ≤ 1): "),
                ("out_model", f"Time outside the model itself over {what} (the map "
                              "through the laws counted as every method's work), the "
                              "same median: ")]:
            out = []
            for m in [m for m in data if m.startswith("qmcpy")]:
                ratios = []
                for k in order:
                    a, b = stats("stillpoint", k), stats(m, k)
                    if (keep(k.split("|")[0]) and a and b and a[field] is not None
                            and b[field] is not None and b[field] > 0):
                        ratios.append(a[field] / b[field])
                if ratios:
                    out.append(f"{m} {np.median(ratios):.2g} ({len(ratios)} cells)")
            if out:
                lines += [said + "; ".join(out) + ".", ""]
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--methods", default="stillpoint,qmc_quad",
                    help="comma-separated, from: " + ", ".join(METHODS))
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--s", default=None,
                    help="dimensions to keep (default: each family's own)")
    ap.add_argument("--tols", default=",".join(f"{t:g}" for t in TOLS))
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--cell-seconds", type=float, default=0.0,
                    help="wall-time cap per (method, cell); 0: none")
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--rerun-unmet", action="store_true",
                    help="run again, in place, the stored runs of --methods that did not "
                         "meet their tolerance (after a change that acts only once a run "
                         "can no longer double)")
    ap.add_argument("--rerun-above", type=int, default=None,
                    help="run again, in place, the stored runs of --methods that made more "
                         "than this many evaluations, met or not (after a change that acts "
                         "only on a run's last rounds)")
    ap.add_argument("--check-space", action="store_true",
                    help="lognormal through stillpoint's space= against the cube version")
    ap.add_argument("--check-keister", action="store_true",
                    help="compare the Keister values with QMCPy's and stop")
    ap.add_argument("--out", default=os.path.join(ROOT, "results", "quad"))
    ap.add_argument("--rule", default=None,
                    help="stillpoint's rule by name (quad's rule=...; default: its own choice); "
                    "for studies, written to a separate --out")
    args = ap.parse_args()
    global RULE
    RULE = args.rule
    os.makedirs(args.out, exist_ok=True)
    if args.table:
        table(args.out, args.runs)
        return
    if args.check_space:
        # A note, not part of the table: stillpoint's own lognormal laws (space=, SciPy
        # frozen laws through their ppf) against the cube version measured above.
        import stillpoint as sp
        from scipy import stats

        for s in FAMILIES["lognormal"]:
            for run in range(3):
                p = instance("lognormal", s, run)
                space = {f"x{j}": stats.lognorm(s=sg, scale=math.exp(m))
                         for j, (m, sg) in enumerate(zip(p["mu"], p["sigma"]))}
                a = sp.quad(lambda x: np.prod(x, axis=1), s, rel_tol=1e-4, seed=run,
                            space=space)
                b = sp.quad(lambda x: value("lognormal", p, x), s, rel_tol=1e-4, seed=run)
                print(f"s={s:2d} run {run}: space= {a.estimate:.15g} (n {a.n}), cube "
                      f"{b.estimate:.15g} (n {b.n}), exact {exact('lognormal', p):.15g}")
        return
    if args.check_keister:
        import qmcpy as qp

        k = qp.Keister(qp.Lattice(1))
        for s in FAMILIES["keister"]:
            ours, theirs = keister_exact(s), float(k.get_exact_value(s))
            print(f"s={s:2d}: {ours:.15g} (radial quadrature), {theirs:.15g} (QMCPy), "
                  f"relative difference {abs(ours - theirs) / abs(theirs):.1e}")
        return
    keep_s = None if args.s is None else {int(v) for v in args.s.split(",")}
    tols = [float(v) for v in args.tols.split(",")]
    cells = []
    for family in args.families.split(","):
        for s in FAMILIES[family]:
            if keep_s is None or s in keep_s:
                cells += [(family, s, tol) for tol in tols]
    for method in args.methods.split(","):
        if method not in METHODS:
            sys.exit(f"unknown method {method}")
        if args.rerun_unmet or args.rerun_above is not None:
            rerun_unmet(method, cells, args.out, args.rerun_above)
        else:
            measure(method, cells, args.runs, args.cell_seconds, args.out)


def rerun_unmet(method, cells, out, above=None):
    """The stored runs of `method` in `cells` that did not meet their tolerance (or,
    with `above`, that made more than `above` evaluations), run again with the same
    instance and seed and put in their place."""
    path = os.path.join(out, f"{method}.json.gz")
    d = load(path)
    if d is None:
        sys.exit(f"no runs stored in {path}")
    wanted = {key(*c) for c in cells}
    changed = total = 0
    for k, cell in d["cells"].items():
        if k not in wanted:
            continue
        s = tuple(cell["s"]) if isinstance(cell["s"], list) else cell["s"]
        for i, row in enumerate(cell["runs"]):
            if (row["met"] if above is None else row["n"] <= above):
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                new = one_run(method, cell["family"], s, cell["tol"], row["run"])
            total += 1
            changed += (new["calls_n"], new["met"]) != (row["calls_n"], row["met"])
            cell["runs"][i] = new
        # Saved cell by cell, so that an interrupted call keeps the cells it finished.
        save(path, d)
        print(f"{k}: {total} run again so far, {changed} changed", flush=True)
    which = "unmet" if above is None else f"more than {above} evaluations:"
    print(f"{method}: {total} runs ({which}) run again, {changed} changed", flush=True)


if __name__ == "__main__":
    main()
