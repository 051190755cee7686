#!/usr/bin/env python3
"""The integration benchmark: stillpoint's default set against the point sets users
would pick instead, on discrepancies, distances and integration errors.

For every cell (n, s) of the grid it measures
  * `stillpoint generate` (the default: --goal integration) and `--method paper`,
  * SciPy's scrambled Sobol', scrambled Halton, Latin hypercube and optimised Latin
    hypercube (`LatinHypercube(optimization="random-cd")`), each over R seeds,
with the *same* metric code on every set (`stillpoint eval --json` and
`stillpoint integrate --json`), and the integration error over Genz's six families
(oscillatory, product peak, corner peak, Gaussian, continuous, discontinuous; 50
random instances each from a fixed seed, exact integrals in closed form or, for the
corner peak, a one-dimensional quadrature of its Laplace representation).

Randomised baselines report the mean of each discrepancy over their seeds and the
root-mean-square of each integration error. Writes results/anchors/anchors.md and
anchors.json.

    python3 benches/anchors.py --bin target/release/stillpoint            # the grid below
    python3 benches/anchors.py --bin target/release/stillpoint --quick    # a 12-cell subset
    python3 benches/anchors.py --s 8,10,15,20 --reuse results/anchors/anchors.json \
        --out results/anchors-high-s      # only the default made again; baselines reused

With --reuse the seeded baselines (and `--method paper`) are read from an earlier run's
anchors.json instead of being drawn again (they depend only on their seeds and SciPy's
version), and the report adds each family's error as a ratio to scrambled Sobol's.

Needs numpy and scipy.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np
from fingerprint import commit, digest, section
from scipy import integrate as sintegrate
from scipy.special import erf
from scipy.stats import qmc

N_FULL = [16, 32, 64, 128, 256, 512, 1024, 10, 50, 100, 200, 400, 800, 1500]
S_FULL = [2, 3, 5, 8, 10, 15, 20]
QUICK = [(16, 2), (256, 2), (100, 3), (1024, 3), (50, 5), (128, 5), (1500, 5),
         (200, 8), (512, 10), (64, 15), (400, 20), (1500, 20)]
GENZ_DIFFICULTY = [9.0, 7.25, 1.85, 7.03, 20.4, 4.3]
FAMILIES = ["oscillatory", "product peak", "corner peak", "gaussian", "continuous",
            "discontinuous"]


def genz_instances(s, count, seed):
    rng = np.random.default_rng(seed)
    out = []
    for f, h in enumerate(GENZ_DIFFICULTY):
        for _ in range(count):
            a = rng.uniform(0, 1, s)
            a = a * h / a.sum()
            u = rng.uniform(0, 1, s)
            out.append((f, a, u))
    return out


def genz_value(f, a, u, x):
    if f == 0:
        return np.cos(2 * np.pi * u[0] + x @ a)
    if f == 1:
        return np.prod(1.0 / (a ** -2.0 + (x - u) ** 2), axis=1)
    if f == 2:
        return (1.0 + x @ a) ** (-(x.shape[1] + 1))
    if f == 3:
        return np.exp(-((x - u) ** 2) @ (a ** 2))
    if f == 4:
        return np.exp(-np.abs(x - u) @ a)
    mask = x[:, 0] <= u[0]
    if x.shape[1] > 1:
        mask &= x[:, 1] <= u[1]
    return np.where(mask, np.exp(x @ a), 0.0)


def genz_exact(f, a, u):
    s = len(a)
    if f == 0:
        z = np.exp(2j * np.pi * u[0]) * np.prod((np.exp(1j * a) - 1) / (1j * a))
        return z.real
    if f == 1:
        return np.prod(a * (np.arctan(a * (1 - u)) + np.arctan(a * u)))
    if f == 2:
        # (1 + a·x)^-(s+1) = (1/s!) ∫_0^∞ t^s e^{-t(1 + a·x)} dt, integrated over x first.
        def g(t):
            if t == 0.0:
                return 0.0
            return math.exp(s * math.log(t) - t - math.lgamma(s + 1)) * np.prod(
                -np.expm1(-t * a) / (t * a))
        val, _ = sintegrate.quad(g, 0, np.inf, epsabs=0, epsrel=1e-13, limit=500)
        return val
    if f == 3:
        return np.prod(np.sqrt(np.pi) / (2 * a) * (erf(a * (1 - u)) + erf(a * u)))
    if f == 4:
        return np.prod((2 - np.exp(-a * u) - np.exp(-a * (1 - u))) / a)
    k = min(2, s)
    first = np.prod(np.expm1(a[:k] * u[:k]) / a[:k])
    rest = np.prod(np.expm1(a[k:]) / a[k:]) if s > k else 1.0
    return first * rest


def stillpoint_json(binary, args):
    out = subprocess.run([binary] + args, check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def measure(binary, x, path, genz):
    np.save(path, x)
    ev = stillpoint_json(binary, ["eval", path, "--json"])
    it = stillpoint_json(binary, ["integrate", path, "--json"])
    f18 = {r["function"]: r["error"] for r in it["functions"]}
    errs = np.array([genz_value(f, a, u, x).mean() - exact for (f, a, u, exact) in genz])
    return {
        "md": ev["modified_l2"], "l2star": ev["star_l2"], "cd": ev["centered_l2"],
        "wd": ev["wrap_around_l2"], "mindist": ev["min_distance"] or 0.0,
        "genz": errs, "f": f18,
    }


def summarise(ms, randomised):
    keys = ["md", "l2star", "cd", "wd", "mindist"]
    out = {k: float(np.mean([m[k] for m in ms])) for k in keys}
    genz = np.array([m["genz"] for m in ms])  # seeds × instances
    per_instance = np.sqrt(np.mean(genz ** 2, axis=0)) if randomised else np.abs(genz[0])
    count = len(per_instance) // len(FAMILIES)
    out["genz"] = [float(np.mean(per_instance[i * count:(i + 1) * count]))
                   for i in range(len(FAMILIES))]
    for fn in ms[0]["f"]:
        e = np.array([m["f"][fn] for m in ms])
        out[fn] = float(np.sqrt(np.mean(e ** 2)))
    return out


def run_cell(binary, n, s, seeds, tmp):
    genz = [(f, a, u, genz_exact(f, a, u)) for (f, a, u) in genz_instances(s, 50, 2024)]
    path = os.path.join(tmp, "x.npy")
    rows = {}
    for name, extra in [("stillpoint (default)", []), ("stillpoint --method paper",
                                                       ["--method", "paper"])]:
        out = os.path.join(tmp, "gen.npy")
        t0 = time.perf_counter()
        subprocess.run([binary, "generate", "-n", str(n), "-s", str(s), "-o", out, "-q"]
                       + extra, check=True, capture_output=True)
        secs = time.perf_counter() - t0
        x = np.load(out)
        rows[name] = summarise([measure(binary, x, path, genz)], False)
        rows[name]["seconds"] = secs
        rows[name]["sha256"] = digest(x)
    makers = {
        "Sobol' (scrambled)": lambda k: qmc.Sobol(s, scramble=True, seed=k).random(n),
        "Halton (scrambled)": lambda k: qmc.Halton(s, scramble=True, seed=k).random(n),
        "LHS": lambda k: qmc.LatinHypercube(s, seed=k).random(n),
        "LHS random-cd": lambda k: qmc.LatinHypercube(
            s, optimization="random-cd", seed=k).random(n),
    }
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, make in makers.items():
            t0 = time.perf_counter()
            sets = [make(1000 + k) for k in range(seeds)]
            secs = (time.perf_counter() - t0) / seeds
            rows[name] = summarise([measure(binary, x, path, genz) for x in sets], True)
            rows[name]["seconds"] = secs
    return rows


def rerun_default(binary, n, s, stored, tmp):
    """The cell with only the default made again, the stored baselines beside it."""
    genz = [(f, a, u, genz_exact(f, a, u)) for (f, a, u) in genz_instances(s, 50, 2024)]
    out = os.path.join(tmp, "gen.npy")
    t0 = time.perf_counter()
    subprocess.run([binary, "generate", "-n", str(n), "-s", str(s), "-o", out, "-q"],
                   check=True, capture_output=True)
    secs = time.perf_counter() - t0
    x = np.load(out)
    rows = {"stillpoint (default)": summarise(
        [measure(binary, x, os.path.join(tmp, "x.npy"), genz)], False)}
    rows["stillpoint (default)"]["seconds"] = secs
    rows["stillpoint (default)"]["sha256"] = digest(x)
    rows.update({k: v for k, v in stored.items() if k != "stillpoint (default)"})
    return rows


def sobol_ratios(results):
    """Per family: cells at or below scrambled Sobol's RMSE, and the geometric mean of
    the default's error over Sobol's."""
    ratios = np.array([[rows["stillpoint (default)"]["genz"][i]
                        / rows["Sobol' (scrambled)"]["genz"][i] for i in range(6)]
                       for rows in results.values()])
    lines = ["## The default against scrambled Sobol' (integration errors)", "",
             "| family | cells at or below Sobol' | geometric mean of the ratio | worst |",
             "|---|---|---|---|"]
    for i, fam in enumerate(FAMILIES):
        r = ratios[:, i]
        lines.append(f"| {fam} | {int((r <= 1).sum())}/{len(r)} | "
                     f"{math.exp(np.log(r).mean()):.2f} | {r.max():.2f} |")
    return lines + [""]


def fingerprints(results):
    """One fingerprint line per cell and set that carries its hash (the default always;
    `--method paper` where this run made it)."""
    flags = {"stillpoint (default)": "", "stillpoint --method paper": " --method paper"}
    out = []
    for (n, s), rows in results.items():
        for name, flag in flags.items():
            if "sha256" in rows.get(name, {}):
                out.append(f"fingerprint: generate -n {n} -s {s}{flag} "
                           f"sha256:{rows[name]['sha256']}")
    return out


def report(results, seeds, command, made_at):
    names = list(next(iter(results.values())).keys())
    ours = names[0]
    lines = ["# Integration benchmark (anchors)", "",
             f"Command: `{command}` on a 2-core machine. Baselines are SciPy "
             f"{__import__('scipy').__version__}, {seeds} seeds each: discrepancies are "
             "means over the seeds, integration errors root-mean-squares. Every figure "
             "comes from the same code (`stillpoint eval`, `stillpoint integrate`). "
             "Lower is better, except the minimum distance.", ""]
    cols = [("md", "D_MD"), ("l2star", "D_L2*"), ("cd", "CD"), ("wd", "WD"),
            ("mindist", "min dist")]
    wins = {c: 0 for c, _ in cols}
    wins.update({f"genz{i}": 0 for i in range(6)})
    wins.update({f: 0 for f in ["F1", "F2", "F3"]})
    total = 0
    body = []
    for (n, s), rows in results.items():
        total += 1
        body.append(f"### n = {n}, s = {s}")
        body.append("")
        body.append("| set | " + " | ".join(h for _, h in cols)
                    + " | " + " | ".join(FAMILIES) + " | F1 | F2 | F3 | seconds |")
        body.append("|" + "---|" * (len(cols) + len(FAMILIES) + 5))
        for name, r in rows.items():
            body.append(f"| {name} | " + " | ".join(f"{r[c]:.3e}" for c, _ in cols)
                        + " | " + " | ".join(f"{g:.2e}" for g in r["genz"])
                        + f" | {r['F1']:.1e} | {r['F2']:.1e} | {r['F3']:.1e} | "
                        f"{r['seconds']:.2f} |")
        body.append("")
        me = rows[ours]
        others = {k: v for k, v in rows.items() if k != ours}
        for c, _ in cols:
            if c == "mindist":
                wins[c] += all(me[c] > o[c] for o in others.values()
                               if o is not rows["stillpoint --method paper"])
            else:
                wins[c] += all(me[c] < rows[b][c] for b in
                               ["Sobol' (scrambled)", "LHS random-cd"])
        for i in range(6):
            wins[f"genz{i}"] += me["genz"][i] <= min(o["genz"][i] for o in others.values())
        for f in ["F1", "F2", "F3"]:
            wins[f] += me[f] <= rows["LHS"][f]
    lines.append(f"## Summary over {total} cells")
    lines.append("")
    lines.append("| column | cells where the default wins | rule |")
    lines.append("|---|---|---|")
    for c, h in cols[:4]:
        lines.append(f"| {h} | {wins[c]}/{total} | below the Sobol' mean and the "
                     "random-cd LHS mean |")
    lines.append(f"| min dist | {wins['mindist']}/{total} | above every baseline "
                 "(the paper's DEM set excluded) |")
    for i, fam in enumerate(FAMILIES):
        lines.append(f"| Genz {fam} | {wins[f'genz{i}']}/{total} | lowest error of all "
                     "sets |")
    for f in ["F1", "F2", "F3"]:
        lines.append(f"| {f} | {wins[f]}/{total} | error at most LHS's RMS |")
    lines.append("")
    lines += sobol_ratios(results)
    return "\n".join(lines + body + section(made_at, command, fingerprints(results))) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default="target/release/stillpoint")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--seeds", type=int, default=16)
    ap.add_argument("--out", default="results/anchors")
    ap.add_argument("--s", help="only these dimensions, e.g. 8,10,15,20")
    ap.add_argument("--reuse", help="an earlier anchors.json: its baselines are reused")
    a = ap.parse_args()
    cells = QUICK if a.quick else [(n, s) for s in S_FULL for n in N_FULL if n >= 2 * s]
    if a.s:
        keep = {int(v) for v in a.s.split(",")}
        cells = [(n, s) for (n, s) in cells if s in keep]
    stored = json.load(open(a.reuse)) if a.reuse else None
    results = {}
    os.makedirs(a.out, exist_ok=True)
    command = "python3 benches/anchors.py" + (" --quick" if a.quick else "") + (
        f" --seeds {a.seeds}" if a.seeds != 16 else "") + (f" --s {a.s}" if a.s else "") + (
        f" --reuse {a.reuse} --out {a.out}" if a.reuse else "")
    made_at = commit()
    with tempfile.TemporaryDirectory() as tmp:
        for n, s in cells:
            t0 = time.perf_counter()
            if stored is None:
                results[(n, s)] = run_cell(a.bin, n, s, a.seeds, tmp)
            else:
                results[(n, s)] = rerun_default(a.bin, n, s, stored[f"{n}x{s}"], tmp)
            print(f"n = {n}, s = {s}: {time.perf_counter() - t0:.1f} s", file=sys.stderr,
                  flush=True)
            with open(os.path.join(a.out, "anchors.md"), "w") as fh:
                fh.write(report(results, a.seeds, command, made_at))
            with open(os.path.join(a.out, "anchors.json"), "w") as fh:
                json.dump({f"{n}x{s}": r for (n, s), r in results.items()}, fh, indent=1)


if __name__ == "__main__":
    main()
