"""Integration to a tolerance with one Owen-scrambled Sobol' sequence and CubBayesNetG's
posterior interval, emulated in Python, against `stillpoint.quad`'s own runs and the
references of benches/quad.py (their JSONs in results/quad/, not rerun).

results/quad/single.md measured at a fixed N that one scrambled Sobol' sequence with the
99 % posterior half-width (kernel at x ⊕ x_0) raised to the round change holds its level
at 0.72–0.89× the width of quad's interval. This script asks what that saves to a
tolerance. Per cell of benches/quad.py (family, s, relative tolerance; the same instance
and seed per run as quad.py draws: instance ``run``, seed ``run``) and run:

- the points: ``stillpoint.baseline("sobol", n, s, seed=run)`` (the package's Owen
  scrambling, natural order; its prefixes are nested, so each doubling evaluates f on the
  new half only), n = 256, 512, ... up to 2^20 (benches/quad.py's budget);
- ``posterior``: at each n, CubBayesNetG's "MLE" half-width at 99 %
  (``quad_single_study.bayes_bound``, the kernel at x_i ⊕ x_0) raised to the round change
  |Q_n − Q_{n/2}|; stop when it is ≤ tol·|Q_n|;
- ``posterior-qmcpy``: the same with the kernel at the points themselves, as QMCPy 2.4's
  CubBayesNetG takes it (narrower and below level at a fixed N, single.md);
- reliability and evaluations as benches/quad.py defines them (met and true relative
  error ≤ tol; not met at 2^20 is a failure; every evaluation counted, here n).

The model families are integrated on the cube through their laws' quantiles, as the
references see them; the Genz cube cells (``--genz``) on the cube directly. One run walks
the doubling once for several tolerances (a run stops when every tolerance asked and both
forms have stopped), so the cells of one (family, s) share their runs and their wall
time: ``--cell-seconds T`` stops a (family, s) group's phase after the run that takes it
past T, and the runs done are recorded. Phases: the tolerances 1e-2 and 1e-3 first, then
1e-4 on its own, so that a cap at 1e-4 does not cut the others.

    nice -n 5 target/py-venv/bin/python benches/quad_single_tol.py --runs 200 \\
        --cell-seconds 200 [--families ...]       (the models; 30 s with --genz)
    target/py-venv/bin/python benches/quad_single_tol.py --table

(results/quad/single-tol.md gives the exact commands.) ``--reverse`` walks the groups
from the other end, for a second process beside the first (the files are written under
a lock, and each phase takes up what the other finished); ``--phase 1|2`` runs one phase;
``--forms F --match G`` runs form F only, to as many runs per cell as G's file holds (to
make lost runs again: they are deterministic).

Writes results/quad/single-tol-posterior.json.gz, results/quad/single-tol-posterior-
qmcpy.json.gz (benches/quad.py's format) and, with ``--table``, prints the Markdown tables
of results/quad/single-tol.md: per cell the reliability and median evaluations of both
forms, of quad (results/quad/stillpoint.json.gz) and of CubBayesNetG
(qmcpy-bayes-net.json.gz), the best reliable reference as benches/quad.py chooses it, and
per family the geometric mean of each one's ratio to it.
"""

import argparse
import math
import os
import sys
import tempfile
import time
import warnings

import numpy as np
from scipy import stats

sys.path.insert(0, os.path.dirname(__file__))
import quad as bench  # noqa: E402
from quad_models import FAMILIES as CUBE_FAMILIES  # noqa: E402
from quad_models import exact, instance, value  # noqa: E402
from quad_single_study import BITS, bayes_bound  # noqa: E402

FORMS = {"posterior": False, "posterior-qmcpy": True}  # name: kernel at the points
Z99 = float(stats.norm.ppf(0.995))
N0 = 256  # CubBayesNetG's n_init
PHASES = ([1e-2, 1e-3], [1e-4])
OUT = os.path.join(bench.ROOT, "results", "quad")
REFS = OUT  # quad's and the references' runs are always read from results/quad
# the model families whose laws are unbounded (normal, lognormal, the Brownian path):
# those quad would integrate with this rule; Morokoff–Caflisch's laws are uniform
UNBOUNDED = [f for f in bench.MODEL_FAMILIES if f != "uq morokoff-caflisch"]
SCOPES = {"unbounded": "in the cells of unbounded laws",
          "run": "in every cell measured here"}


def walk(f, d, seed, tols, forms=tuple(FORMS)):
    """One run: the doubling on one sequence; per (form, tol) the (estimate, n, met) at
    which it stopped (or at 2^20, not met)."""
    import stillpoint as sp

    stops, y, n = {}, np.empty(0), N0
    while True:
        x = np.asarray(sp.baseline("sobol", n, d, seed=seed), dtype=float)
        y = np.concatenate([y, np.asarray(f(x[y.size:]), dtype=float)])
        # column-major: the kernel's product over coordinates reads columns (3× faster)
        xi = np.asfortranarray(np.floor(x * 2.0 ** BITS).astype(np.uint64))
        q = float(y.mean())
        change = abs(q - float(y[: n // 2].mean()))
        for form in forms:
            at_points = FORMS[form]
            open_tols = [t for t in tols if (form, t) not in stops]
            if not open_tols:
                continue
            hw = max(bayes_bound(y, xi, z=Z99, at_points=at_points), change)
            for t in open_tols:
                if hw <= t * abs(q):
                    stops[(form, t)] = (q, n, True)
        if len(stops) == len(forms) * len(tols) or n >= bench.MAX_N:
            break
        n *= 2
    for form in forms:
        for t in tols:
            stops.setdefault((form, t), (q, n, False))
    return stops


def integrand(family, s, run):
    """(f on the cube, exact) of instance ``run``, as benches/quad.py draws it for the
    references."""
    if family in bench.MODEL_FAMILIES:
        on_cube, _, _, truth = bench.model(family, s, run)
        return on_cube, truth
    p = instance(family, s, run)
    return (lambda x: value(family, p, x)), exact(family, p)


def save(paths, data, cells):
    """Writes the cells this process measures into the files as they are on disk now, so
    that processes on disjoint families can run side by side (under a lock: two writers
    of one file at once leave neither's bytes)."""
    import fcntl

    for m, path in paths.items():
        # the lock file lives outside results/ (it is no result)
        lockname = os.path.join(tempfile.gettempdir(), os.path.basename(path) + ".lock")
        with open(lockname, "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            on_disk = bench.load(path) or {"method": m, "cells": {}}
            on_disk["version"] = data[m]["version"]
            for (mm, _), cell in cells.items():
                if mm == m:
                    s = tuple(cell["s"]) if isinstance(cell["s"], list) else cell["s"]
                    on_disk["cells"][bench.key(cell["family"], s, cell["tol"])] = cell
            bench.save(path, on_disk)


def measure(groups, runs, cell_seconds, phases=PHASES, forms=tuple(FORMS), match=None,
            version=None):
    """Runs the groups' phases for ``forms``; with ``match`` (a form's name) each phase
    gets as many runs as that form's file holds for it, whatever the time."""
    paths = {m: os.path.join(OUT, f"single-tol-{m}.json.gz") for m in forms}
    other = bench.load(os.path.join(OUT, f"single-tol-{match}.json.gz")) if match else None
    data = {m: bench.load(p) or {"method": m, "cells": {}} for m, p in paths.items()}
    import stillpoint as sp

    for m in forms:
        data[m]["version"] = f"stillpoint {sp.__version__}" + (
            version or (" baseline('sobol') + NumPy port of QMCPy 2.4's CubBayesNetG "
                        "bound (benches/quad_single_study.py)"))
    for family, s in groups:
        d = s[0] if isinstance(s, tuple) else s
        for tols in phases:
            # what another process has finished since this one started counts too
            for m in forms:
                on_disk = bench.load(paths[m]) or {"cells": {}}
                for t in tols:
                    k = bench.key(family, s, t)
                    if k in on_disk["cells"]:
                        data[m]["cells"][k] = on_disk["cells"][k]
            cells = {(m, t): data[m]["cells"].setdefault(
                bench.key(family, s, t), {"family": family, "s": s, "tol": t,
                                          "seconds": 0.0, "runs": []})
                for m in forms for t in tols}
            first = cells[(forms[0], tols[0])]
            want, cap = runs, cell_seconds
            if other:
                held = other["cells"].get(bench.key(family, s, tols[0]))
                want, cap = (len(held["runs"]) if held else 0), 0
            t_start = time.perf_counter()
            while len(first["runs"]) < want and not (cap and first["seconds"] >= cap):
                run = len(first["runs"])
                t0 = time.perf_counter()
                f, truth = integrand(family, s, run)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    stops = walk(f, d, run, tols, forms)
                took = time.perf_counter() - t0
                for (m, t), cell in cells.items():
                    q, n, met = stops[(m, t)]
                    err = abs(q - truth) / abs(truth)
                    cell["runs"].append({"run": run, "rel_error": float(f"{err:.3g}"),
                                         "n": n, "calls_n": n, "met": met,
                                         "ok": bool(met and err <= t)})
                    # the phase's runs serve all its cells: each holds the phase's time
                    cell["seconds"] = round(cell["seconds"] + took, 3)
                    cell["cell_seconds"] = cell_seconds
                if time.perf_counter() - t_start > 60:
                    save(paths, data, cells)
                    t_start = time.perf_counter()
            save(paths, data, cells)
            for (m, t), cell in cells.items():
                rs = cell["runs"]
                print(f"{m:16s} {family} s={s} tol={t:g}: reliability "
                      f"{np.mean([r['ok'] for r in rs]):.3f}, median n "
                      f"{np.median([r['n'] for r in rs]):.0f}, runs {len(rs)}, "
                      f"{cell['seconds']:.0f} s", flush=True)


def stats_of(d, k):
    c = d["cells"].get(k) if d else None
    if not c or not c["runs"]:
        return None
    rs = c["runs"]
    return {"rel": float(np.mean([r["ok"] for r in rs])),
            "n": float(np.median([r["calls_n"] for r in rs])), "runs": len(rs)}


def table(runs=200):
    ours = {m: bench.load(os.path.join(OUT, f"single-tol-{m}.json.gz")) for m in FORMS}
    refs = {m: bench.load(os.path.join(REFS, f"{m}.json.gz")) for m in bench.REFERENCES}
    refs = {m: d for m, d in refs.items() if d}
    quad = bench.load(os.path.join(REFS, "stillpoint.json.gz"))
    order = [(f, s, t) for f, ss in bench.FAMILIES.items() for s in ss for t in bench.TOLS]
    shown = ["posterior", "posterior-qmcpy", "quad"]

    def cell(v):
        if v is None:
            return "—"
        txt = f"{v['rel']:.0%} · {v['n']:.0f}"
        return txt + (f" ({v['runs']})" if v["runs"] < runs else "")

    lines = ["| family | s | tol | posterior | posterior-qmcpy | quad | qmcpy-bayes-net "
             "| best reference | ratio: posterior, posterior-qmcpy, quad |",
             "|---|---|---|---|---|---|---|---|---|"]
    ratios = {m: {} for m in shown}  # m: {family: [ratio, ...]}
    over_quad = {}  # family: [the posterior's median n over quad's, ...], every cell
    # over all cells with a reliable reference, the form in place of quad's runs in the
    # cells of unbounded laws ("unbounded") or in every cell it was run in ("run")
    every = {m: {scope: [] for scope in SCOPES} for m in shown}
    missing = {m: {scope: [] for scope in SCOPES} for m in shown}
    for family, s, tol in order:
        k = bench.key(family, s, tol)
        st = {m: stats_of(ours[m], k) for m in FORMS}
        st["quad"] = stats_of(quad, k)
        rst = {m: stats_of(d, k) for m, d in refs.items()}
        good = [m for m, v in rst.items() if v and v["rel"] >= bench.RELIABLE]
        best = min(good, key=lambda m: rst[m]["n"]) if good else None
        if best and st["quad"]:
            # quad's cells stand where the form is not used (not run, or bounded laws)
            for m in shown:
                for scope in SCOPES:
                    v = st[m] if st[m] and (scope == "run" or family in UNBOUNDED) else None
                    v = v or st["quad"]
                    every[m][scope].append(v["n"] / rst[best]["n"])
                    if v["rel"] < bench.RELIABLE or v["n"] > rst[best]["n"]:
                        missing[m][scope].append(k)
        if not (st["posterior"] or st["posterior-qmcpy"]):
            continue
        if st["posterior"] and st["quad"]:
            over_quad.setdefault(family, []).append(st["posterior"]["n"] / st["quad"]["n"])
        rr = []
        for m in shown:
            if best and st[m]:
                r = st[m]["n"] / rst[best]["n"]
                ratios[m].setdefault(family, []).append(r)
                rr.append(f"{r:.2f}" + ("" if st[m]["rel"] >= bench.RELIABLE else " ✘"))
            else:
                rr.append("—")
        lines.append(f"| {family} | {s} | {tol:g} | {cell(st['posterior'])} | "
                     f"{cell(st['posterior-qmcpy'])} | {cell(st['quad'])} | "
                     f"{cell(rst.get('qmcpy-bayes-net'))} | "
                     f"{best + ' · ' + format(rst[best]['n'], '.0f') if best else 'none reliable'}"
                     f" | {', '.join(rr)} |")
    lines += ["", "| family | cells | posterior | posterior-qmcpy | quad | posterior over quad "
              "(cells) |", "|---|---|---|---|---|---|"]

    def gm(v):
        return math.exp(np.mean(np.log(v))) if v else float("nan")

    fams = [f for f in bench.FAMILIES if f in ratios["posterior"]]
    for f in fams:
        lines.append(f"| {f} | {len(ratios['posterior'][f])} | "
                     + " | ".join(f"{gm(ratios[m].get(f, [])):.2f}" for m in shown)
                     + f" | {gm(over_quad.get(f, [])):.2f} ({len(over_quad.get(f, []))}) |")
    for what, keep in (("the model families", bench.MODEL_FAMILIES),
                       ("the families of unbounded laws", UNBOUNDED)):
        over = gm([r for f in keep for r in over_quad.get(f, [])])
        lines.append(f"| {what} | {sum(len(ratios['posterior'].get(f, [])) for f in keep)} "
                     "| " + " | ".join(
                         f"{gm([r for f in keep for r in ratios[m].get(f, [])]):.2f}"
                         for m in shown) + f" | {over:.2f} |")
    for scope, what in SCOPES.items():
        lines += ["", f"Over all {len(every['quad'][scope])} cells of benches/quad.py with a "
                  f"reliable reference, the form {what}, quad's runs elsewhere: geometric "
                  "mean of the ratio " + ", ".join(f"{m} {gm(every[m][scope]):.3f}"
                                                   for m in shown)
                  + "; cells not meeting (reliable and ≤ the best reference): "
                  + ", ".join(f"{m} {len(missing[m][scope])}" for m in shown) + "."]
    print("\n".join(lines))
    return lines


def main():
    global OUT
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--families", default=",".join(bench.MODEL_FAMILIES))
    ap.add_argument("--genz", action="store_true",
                    help="the Genz cube cells of benches/quad.py instead of the models")
    ap.add_argument("--s", default=None, help="dimensions to keep")
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--cell-seconds", type=float, default=0.0)
    ap.add_argument("--phase", type=int, choices=(1, 2), default=None,
                    help="only the first phase (1e-2, 1e-3) or the second (1e-4)")
    ap.add_argument("--forms", default=",".join(FORMS), help="of: " + ", ".join(FORMS))
    ap.add_argument("--match", default=None,
                    help="a form: as many runs per cell as its file holds, no time cap")
    ap.add_argument("--reverse", action="store_true",
                    help="the groups in reverse order (a second process from the other end)")
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--out", default=OUT, help="where the JSONs go (a quick check: /tmp)")
    args = ap.parse_args()
    OUT = args.out
    if args.table:
        table(args.runs)
        return
    fams = list(CUBE_FAMILIES) if args.genz else args.families.split(",")
    keep = None if args.s is None else set(args.s.split(","))
    groups = [(f, s) for f in fams for s in bench.FAMILIES[f]
              if keep is None or str(s) in keep]
    phases = PHASES if args.phase is None else PHASES[args.phase - 1:args.phase]
    if args.reverse:
        groups.reverse()
    measure(groups, args.runs, args.cell_seconds, phases, args.forms.split(","), args.match)


if __name__ == "__main__":
    main()
