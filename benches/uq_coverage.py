#!/usr/bin/env python3
"""Coverage of error bars under a design space: Student intervals from R = 8 randomised
sets, stillpoint's ``randomize=True`` with ``space=`` beside SciPy's scrambled Sobol'
under the same protocol, on models whose inputs are normal, lognormal or uniform.

For each family, n and method, every interval is made from R = 8 independent
randomised sets of n points under the family's space: the 8 estimates (the mean of f
over each set's rows) give the mean m and the standard deviation s, and the interval
m ± t_{7, 0.975} · s / √8. The interval covers when it holds the exact value. Reported:
the coverage over the intervals (and its binomial standard error), the RMSE of one
set's estimate (over all sets drawn), and the mean half-width, both as ratios to
scrambled Sobol's.

Families (fixed parameters; exact values in closed form or from a documented long run):
  keister-5     Keister's function, s = 5: π^{s/2} cos(‖x‖), x ~ N(0, I/2) (every input
                normal(0, 1/√2)); exact from the radial integral (chi law, adaptive quad)
  lognormal-10  ∏ X_j, X_j ~ lognormal(0, σ_j), σ_j = 0.4 / √j, s = 10;
                exact exp(Σ σ_j² / 2)
  ishigami      sin x1 + 7 sin² x2 + 0.1 x3⁴ sin x1, x_j ~ uniform(−π, π); exact 3.5
  asian-32      arithmetic Asian call on m = 32 equal steps (standard construction),
                S0 = K = 100, r = 0.05, σ = 0.2, T = 1: the discounted max(mean S − K, 0)
                of 32 standard normals (a kink where the payoff starts); reference from
                64 scrambled Sobol' sets of 2^18 points (its standard error is printed
                and is below 2 % of every half-width)
  asian-32-pca-path  the same call with the path one variable of the space,
                W=brownian(1,32,pca) (stillpoint builds the path by principal
                components; Sobol' gets 32 normals and f builds the same path);
                reference from 32 scrambled Sobol' sets of 2^18 points on PCA paths
                (standard error about 5e-6, below 1 % of its half-widths; the standard
                construction's long run above is 18 % of the half-width at n = 4 096
                and was 2 standard errors off)

Methods, each randomised afresh per set:
  stillpoint  stillpoint.design(n, space, randomize=True, seed=...): the lattice made
              for the tent randomisation, shifted and folded, every column through its
              law's inverse CDF (the package's own mapping, not ours)
  sobol       scipy.stats.qmc.Sobol(d, scramble=True) (LMS + digital shift), mapped
              through SciPy's ppf of the same laws

    PYTHONPATH=... /work/wt/bench-venv/bin/python benches/uq_coverage.py               # full: 1 000 intervals
    PYTHONPATH=... /work/wt/bench-venv/bin/python benches/uq_coverage.py --intervals 250

Writes results/uq-coverage/coverage.md and coverage.json.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import time
import zlib

import numpy as np
from scipy import integrate, stats
from scipy.stats import qmc

import stillpoint as sp
from stillpoint import _core

R = 8
T7 = stats.t.ppf(0.975, R - 1)
NS = [1024, 4096]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "results", "uq-coverage")


# ---------------------------------------------------------------- the families


def keister_exact(s):
    # E cos(R / √2), R ~ chi(s), times π^{s/2}.
    val, _ = integrate.quad(
        lambda r: math.cos(r / math.sqrt(2.0)) * stats.chi(s).pdf(r), 0, 60, limit=400,
        epsabs=1e-14, epsrel=1e-13,
    )
    return math.pi ** (s / 2) * val


def keister(cols):
    x = np.stack([cols[f"x{j + 1}"] for j in range(5)], axis=1)
    return math.pi ** 2.5 * np.cos(np.sqrt(np.sum(x * x, axis=1)))


LOGN_SIGMA = [0.4 / math.sqrt(j + 1) for j in range(10)]


def lognormal_product(cols):
    out = np.ones(len(cols["x1"]))
    for j in range(10):
        out = out * cols[f"x{j + 1}"]
    return out


def ishigami(cols):
    x1, x2, x3 = cols["x1"], cols["x2"], cols["x3"]
    return np.sin(x1) + 7.0 * np.sin(x2) ** 2 + 0.1 * x3**4 * np.sin(x1)


ASIAN = dict(m=32, s0=100.0, k=100.0, r=0.05, sigma=0.2, t=1.0)


def asian_payoff(z):
    """The discounted arithmetic Asian call of standard normals z, shape (n, m)."""
    a = ASIAN
    dt = a["t"] / a["m"]
    w = np.cumsum(np.sqrt(dt) * z, axis=1)
    times = dt * np.arange(1, a["m"] + 1)
    s = a["s0"] * np.exp((a["r"] - 0.5 * a["sigma"] ** 2) * times + a["sigma"] * w)
    return math.exp(-a["r"] * a["t"]) * np.maximum(s.mean(axis=1) - a["k"], 0.0)


def asian(cols):
    return asian_payoff(np.stack([cols[f"z{j + 1}"] for j in range(ASIAN["m"])], axis=1))


def pca_matrix(m, t=1.0):
    """A with W = Z Aᵀ: the principal components of the Brownian path at m equal steps,
    largest variance first (the construction of ``brownian(T,m,pca)``)."""
    times = t * np.arange(1, m + 1) / m
    lam, vec = np.linalg.eigh(np.minimum.outer(times, times))
    order = np.argsort(lam)[::-1]
    return vec[:, order] * np.sqrt(np.maximum(lam[order], 0.0))


def asian_path_payoff(w):
    """The discounted arithmetic Asian call of Brownian paths w, shape (n, m)."""
    a = ASIAN
    times = a["t"] / a["m"] * np.arange(1, a["m"] + 1)
    s = a["s0"] * np.exp((a["r"] - 0.5 * a["sigma"] ** 2) * times + a["sigma"] * w)
    return math.exp(-a["r"] * a["t"]) * np.maximum(s.mean(axis=1) - a["k"], 0.0)


def asian_path(cols):
    """The same call with the path given as one variable W (columns W_1 … W_m), or as
    m normals z1 … zm made into the path by principal components."""
    m = ASIAN["m"]
    if "W_1" in cols:
        return asian_path_payoff(np.stack([cols[f"W_{j + 1}"] for j in range(m)], axis=1))
    z = np.stack([cols[f"z{j + 1}"] for j in range(m)], axis=1)
    return asian_path_payoff(z @ pca_matrix(m, ASIAN["t"]).T)


def asian_reference(reps=64, m=18, seed=20261128):
    rng = np.random.default_rng(seed)
    est = []
    for _ in range(reps):
        u = qmc.Sobol(ASIAN["m"], scramble=True, seed=rng).random_base2(m)
        est.append(asian_payoff(stats.norm.ppf(u)).mean())
    est = np.array(est)
    return float(est.mean()), float(est.std(ddof=1) / math.sqrt(reps))


def asian_pca_reference(reps=32, m=18, seed=20261129):
    """The same value from paths built by principal components: a scrambled net's
    estimate has about a tenth of the standard construction's spread there (one set of
    4 096 points: RMSE 0.0014 against 0.017), so the long run's standard error (about
    5e-6) stays below 1 % of the PCA cells' half-widths, where asian_reference's
    (1.9e-4) is 18 % of the half-width at n = 4 096."""
    rng = np.random.default_rng(seed)
    a = pca_matrix(ASIAN["m"], ASIAN["t"])
    est = []
    for _ in range(reps):
        u = qmc.Sobol(ASIAN["m"], scramble=True, seed=rng).random_base2(m)
        # kept off the faces as sobol_estimate keeps its points (a 0 would give an
        # infinite normal, and the PCA sum of infinities of both signs no value)
        u = np.clip(u, 2.0**-53, 1 - 2.0**-53)
        est.append(asian_path_payoff(stats.norm.ppf(u) @ a.T).mean())
    est = np.array(est)
    return float(est.mean()), float(est.std(ddof=1) / math.sqrt(reps))


def families():
    """(name, space texts, SciPy laws in the same order, f of named columns, the exact
    value and its standard error as a function: the Asian reference is a long run)."""
    half = 1.0 / math.sqrt(2.0)
    fams = []
    fams.append((
        "keister-5",
        [f"x{j + 1}=normal(0,{half!r})" for j in range(5)],
        [stats.norm(0, half)] * 5,
        keister,
        lambda: (keister_exact(5), 0.0),
    ))
    fams.append((
        "lognormal-10",
        [f"x{j + 1}=lognormal(0,{sig!r})" for j, sig in enumerate(LOGN_SIGMA)],
        [stats.lognorm(s=sig) for sig in LOGN_SIGMA],
        lognormal_product,
        lambda: (math.exp(sum(sig * sig for sig in LOGN_SIGMA) / 2), 0.0),
    ))
    fams.append((
        "ishigami",
        [f"x{j + 1}=uniform({-math.pi!r},{math.pi!r})" for j in range(3)],
        [stats.uniform(-math.pi, 2 * math.pi)] * 3,
        ishigami,
        lambda: (3.5, 0.0),
    ))
    fams.append((
        "asian-32",
        [f"z{j + 1}=normal(0,1)" for j in range(ASIAN["m"])],
        [stats.norm()] * ASIAN["m"],
        asian,
        asian_reference,
    ))
    # The same option with the path a variable of the space (stillpoint builds it by
    # principal components; Sobol' gets 32 normals and the function builds the same
    # path): the value is the standard construction's, measured again by a long run on
    # PCA paths, whose much smaller spread makes it fine enough for these cells.
    fams.append((
        "asian-32-pca-path",
        [f"W=brownian({ASIAN['t']!r},{ASIAN['m']},pca)"],
        [stats.norm()] * ASIAN["m"],
        asian_path,
        asian_pca_reference,
    ))
    return fams


# ---------------------------------------------------------------- the methods


class Stillpoint:
    """stillpoint's randomised sets under ``space`` at n points. ``design(n, space,
    randomize=True, seed=k)`` recomputes the (seed-independent) lattice and its report
    for every seed; the same sets come from the package's own three steps, the lattice
    made for the tent randomisation once (``_core.tent_set``), its randomisation from
    the seed (``_core.randomize``) and the space's inverse-CDF map (``_core.space_values``,
    the library's one map). :meth:`check` asserts that they are the same bits as
    ``design``'s for a few seeds of every cell."""

    def __init__(self, space, n):
        self.space, self.n = space, n
        self.names = list(_core.space_names(space))
        # A space holding a Brownian path takes Owen-scrambled Sobol' (``generate``'s
        # `sobol` baseline from the seed); one whose every law is unbounded the lattice
        # made for the laws (``_core.law_set``, the library's construction); the others
        # the cube's.
        probe = sp.design(min(n, 64), space, randomize=True, seed=0)
        self.owen = probe.rule.startswith("Owen-scrambled Sobol'")
        self.law = probe.rule.startswith("lattice made for the laws")
        self.base = None if self.law or self.owen else _core.tent_set(n, len(self.names))
        if self.owen:  # the net's columns as the rule deals them to the coordinates
            net = self.net(min(n, 64), 0)
            self.order = [next(i for i in range(net.shape[1])
                               if np.array_equal(net[:, i], probe.unit[:, j]))
                          for j in range(net.shape[1])]

    def net(self, n, seed):
        return np.asarray(sp.generate(n, len(self.names), method="sobol", seed=seed))

    def values(self, seed):
        if self.owen:
            u = self.net(self.n, seed)[:, self.order]
        elif self.law:
            u = _core.law_set(self.space, self.n, seed)
        else:
            u = _core.randomize(self.base, "tent", seed)
        x = _core.space_values(self.space, u, None)
        return {name: x[:, j] for j, name in enumerate(self.names)}

    def check(self, seeds):
        for seed in seeds:
            d = sp.design(self.n, self.space, randomize=True, seed=seed)
            mine = self.values(seed)
            for name in self.names:
                if not np.array_equal(d.columns[name], mine[name]):
                    raise SystemExit(f"{name}: not design(randomize=True)'s column, seed {seed}")


def stillpoint_estimate(sets, f, seed):
    return float(np.mean(f(sets.values(seed))))


def sobol_estimate(space, laws, f, n, rng):
    # A coordinate of exactly 0 (the scramble reaches it about once in 2^32) is kept off
    # the face as stillpoint's quantile functions keep theirs (2^-53), so that an
    # unbounded law gives a finite value on both sides.
    u = np.clip(qmc.Sobol(len(laws), scramble=True, seed=rng).random(n), 2.0**-53, 1 - 2.0**-53)
    names = [t.split("=", 1)[0] for t in space]
    if len(names) != len(laws):  # a path variable: its normals, built into it by f
        names = [f"z{j + 1}" for j in range(len(laws))]
    cols = {name: law.ppf(u[:, j]) for j, (name, law) in enumerate(zip(names, laws))}
    return float(np.mean(f(cols)))


def coverage(estimates, exact):
    """Coverage, its binomial standard error, RMSE of one set, mean half-width."""
    e = np.asarray(estimates).reshape(-1, R)
    m = e.mean(axis=1)
    half = T7 * e.std(axis=1, ddof=1) / math.sqrt(R)
    hit = np.abs(m - exact) <= half
    cov = float(hit.mean())
    return {
        "coverage": cov,
        "coverage_se": math.sqrt(cov * (1 - cov) / len(hit)),
        "rmse": float(np.sqrt(np.mean((e - exact) ** 2))),
        "half_width": float(half.mean()),
        "intervals": int(len(hit)),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--intervals", type=int, default=1000)
    ap.add_argument("--families", default="", help="comma-separated subset")
    ap.add_argument("--n", default="", help="comma-separated subset of 1024,4096")
    ap.add_argument("--merge", action="store_true",
                    help="keep the rows of coverage.json for the cells not run")
    args = ap.parse_args()
    ns = [int(v) for v in args.n.split(",")] if args.n else NS
    wanted = set(filter(None, args.families.split(",")))
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True
    ).stdout.strip()
    command = "benches/uq_coverage.py " + " ".join(sys.argv[1:])
    rows = []
    started = time.time()
    for name, space, laws, f, reference in families():
        if wanted and name not in wanted:
            continue
        exact, ref_se = reference()
        for n in ns:
            total = args.intervals * R
            # Seeds distinct per family and n: the seed picks the randomisation only.
            base = (zlib.crc32(name.encode()) % 1000) * 10**8 + n * 10**4
            sets = Stillpoint(space, n)
            sets.check([base, base + 1])
            t0 = time.time()
            ours = [stillpoint_estimate(sets, f, base + i) for i in range(total)]
            t_ours = (time.time() - t0) / total
            rng = np.random.default_rng(base)
            t0 = time.time()
            theirs = [sobol_estimate(space, laws, f, n, rng) for _ in range(total)]
            t_theirs = (time.time() - t0) / total
            a, b = coverage(ours, exact), coverage(theirs, exact)
            row = {
                "family": name, "n": n, "exact": exact, "reference_se": ref_se,
                "stillpoint": a, "sobol": b,
                "seconds_per_set": {"stillpoint": t_ours, "sobol": t_theirs},
            }
            rows.append(row)
            print(
                f"{name:13s} n={n:5d}  coverage stillpoint {a['coverage']:.3f} "
                f"sobol {b['coverage']:.3f}  RMSE ratio {a['rmse'] / b['rmse']:.3f}  "
                f"half-width ratio {a['half_width'] / b['half_width']:.3f}  "
                f"({time.time() - started:.0f} s)",
                flush=True,
            )
            # Written after every cell, so that a run stopped part-way keeps what it
            # measured (a later cell's run then merges with it).
            save(rows, args.merge, commit, command, args.intervals, started)


def save(rows, merge, commit, command, intervals, started):
    """coverage.json and coverage.md from this run's rows (and, with ``merge``, the
    stored rows of the cells it did not run)."""
    os.makedirs(OUT, exist_ok=True)
    path = os.path.join(OUT, "coverage.json")
    for row in rows:
        row.update(commit=commit, command=command, intervals=intervals)
    if merge and os.path.exists(path):
        # A rerun of some cells replaces those and keeps the others' rows.
        with open(path) as fh:
            old = json.load(fh)
        kept = old["rows"]
        for r in kept:
            # Rows written before the runs were recorded per row carry them at the top.
            r.setdefault("commit", old.get("commit", "?"))
            r.setdefault("command", old.get("command", "?"))
            r.setdefault("intervals", r["stillpoint"]["intervals"])
        done = {(r["family"], r["n"]) for r in rows}
        order = [f[0] for f in families()]
        rows = sorted(
            [r for r in kept if (r["family"], r["n"]) not in done] + rows,
            key=lambda r: (order.index(r["family"]), r["n"]),
        )
    with open(path, "w") as fh:
        json.dump({"R": R, "rows": rows}, fh, indent=1)
    write_md(rows, time.time() - started)


def write_md(rows, seconds):
    runs = sorted({(r["commit"], r["command"], r["intervals"]) for r in rows})
    lines = [
        "# Coverage of error bars under a design space",
        "",
        "Runs: " + "; ".join(
            f"commit `{c}`, `{cmd.strip()}` ({k} intervals per family, n and method)"
            for c, cmd, k in runs
        ) + f" (the last run {seconds / 60:.1f} min of wall time on the shared 2-core machine). "
        "Every interval is the Student interval m ± t₇ · s/√8 from R = 8 "
        "randomised sets (95 %). stillpoint: "
        "`design(n, space, randomize=True, seed=…)` (Owen-scrambled Sobol' where the space "
        "holds a Brownian path, the lattice made for the laws where every law is "
        "unbounded, the cube's tent-randomised lattice otherwise, as "
        "`Design.rule` names it; each column through its law's inverse CDF); Sobol': "
        "SciPy's `qmc.Sobol(scramble=True)`"
        " mapped through SciPy's `ppf`. RMSE is one set's; ratios are stillpoint / Sobol' "
        "(below 1: stillpoint better). The coverage's binomial standard error is in "
        "brackets.",
        "",
        "| family | n | coverage stillpoint | coverage Sobol' | RMSE stillpoint | RMSE Sobol' "
        "| RMSE ratio | half-width ratio | s per set (stillpoint / Sobol') |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    exact_to_rounding = []
    for r in rows:
        a, b, t = r["stillpoint"], r["sobol"], r["seconds_per_set"]
        mark = ""
        if a["rmse"] <= 1e-12 * (1 + abs(r["exact"])):
            mark = " †"
            exact_to_rounding.append(f"{r['family']} at n = {r['n']}")
        lines.append(
            f"| {r['family']} | {r['n']} | {a['coverage']:.3f} ({a['coverage_se']:.3f}){mark} | "
            f"{b['coverage']:.3f} ({b['coverage_se']:.3f}) | {a['rmse']:.3g} | {b['rmse']:.3g} | "
            f"{a['rmse'] / b['rmse']:.3g} | {a['half_width'] / b['half_width']:.3g} | "
            f"{t['stillpoint']:.4f} / {t['sobol']:.4f} |"
        )
    if exact_to_rounding:
        lines += [
            "",
            "† Every randomised set integrates this family exactly up to rounding ("
            + ", ".join(exact_to_rounding)
            + "): the lattice's columns are equally spaced after the shift and the fold, "
            "and sin x₁, sin² x₂ and x₃⁴ sin x₁ average exactly over them. Its intervals "
            "then measure rounding, not integration error; the coverage there says nothing.",
        ]
    lines += [
        "",
        "Exact values: " + "; ".join(
            f"{r['family']} {r['exact']:.12g}"
            + (f" (reference, standard error {r['reference_se']:.1e})" if r["reference_se"] else "")
            for r in rows if r["n"] == rows[0]["n"]
        ) + ".",
        "",
        "The full run is `benches/uq_coverage.py` (1 000 intervals per family and n, "
        "8 000 sets per method and cell; about 16 min of one core, 38 min of wall time on the "
        "shared machine). stillpoint's sets come from the "
        "package's own steps (the tent set once per cell, `_core.randomize` per seed, the "
        "library's inverse-CDF map `_core.space_values`), checked bit for bit against "
        "`design(n, space, randomize=True, seed=…)` on two seeds of every cell.",
        "",
    ]
    md = os.path.join(OUT, "coverage.md")
    # The sections written by hand below the table (from the first "## " heading: notes
    # on a family, the commit mark) are kept.
    kept = ""
    if os.path.exists(md):
        old = open(md).read()
        if "\n## " in old:
            kept = old[old.index("\n## "):]
    with open(md, "w") as fh:
        fh.write("\n".join(lines).rstrip("\n") + "\n" + kept)


if __name__ == "__main__":
    main()
