"""The interval of `stillpoint.quad` at a fixed number of evaluations: coverage and width
of the alternatives, on the same evaluations.

For each family (benches/quad_models.py's integrands, plus the corner peak with every
a_j = 1, ``(1 + Σx)^-(s+1)``) and each seed 0 … SEEDS−1 (a new random instance of the
family and new shifts), 16 independent replicates of the extensible randomised lattice
(benches/quad_rules.py: quad's points, with shifts drawn by NumPy) are evaluated at their
first n/4 points, and from these nested prefixes every interval below is formed at the same total
of n evaluations:

- ``t8``: R = 8 replicates of n/8 points, Student t at 95 % (quad's interval);
- ``t2``, ``t4``, ``t16``: R = 2 of n/2 (the first two replicates are evaluated at n/2
  points), R = 4 of n/4, R = 16 of n/16;
- ``t8+round``: t8 widened to |Q_n − Q_{n/2}| when that is larger (Q_{n/2} is the same
  eight replicates' estimate at half their points: nested, so no extra evaluation);
- ``t4+round``, ``t16+round``: the same guard on t4 and t16;
- ``t4+skew``, ``t8+skew``, ``t16+skew``: the t interval widened on both sides by
  Johnson's (1978) skewness term |μ̂3|/(6 s² R) of the replicate means;
- ``quantile8``: the order statistics [x_(2), x_(7)] of the eight replicate means (a
  distribution-free interval for their median; 93 % for a symmetric law);
- ``t4+round+skew``: ``t4+round`` raised to the skew guard of quad's interval: with γ̂
  and σ̂ the skewness and standard deviation of all n values of f, w = clamp((|γ̂| − 1)/4,
  0, 1) and z the normal quantile, the half-width is at least
  w · 1.2 · min(h, z·σ̂/√n) · (1 + |γ̂|(2z² + 1)/(6z√n)) (h: ``t4+round``'s);
- ``t4+round+skew+ulp``: quad's interval, ``t4+round+skew`` raised to the rounding
  bound of its sums, (n/4)·ε·max|f| (n/4 values summed per replicate; ε = 2^−52): an
  integrand the rule integrates exactly (Ishigami on the tent lattice) leaves only
  rounding in the replicate means, which the t part cannot measure;
- ``t4+round+skew:mc``, ``t4+round+skew:geo``: the skew guard on plain Monte Carlo's
  half-width z·σ̂/√n instead of min(h, z·σ̂/√n), or on their geometric mean √(h·z·σ̂/√n)
  (measured for the heavier corners the guard misses, not built).

Coverage is the share of seeds whose interval holds the exact integral; "width" is the
geometric mean over seeds of the half-width divided by t8's (the price in accuracy), and
"rmse" the root mean square error of the estimate divided by t8's; "ulps" (per case)
the largest |error| of quad's estimate over the seeds in units of ε·|integral|.

    target/py-venv/bin/python benches/quad_interval.py [--seeds 300] [--n 4096] [--first-seed 300]

Writes results/quad/interval-<n>.json and prints a Markdown table.
``--misses LABEL`` prints, for one case, where quad's interval misses: the signs of the
misses, the skewness γ̂ of f's values on the misses against its median, and the errors
over plain Monte Carlo's half-width z·σ̂/√n, and the coverage and width (over quad's) with
the skew guard's factor 1.2 raised to 1.5 … 3. ``--package`` instead runs the installed package's ``quad`` at exactly n evaluations on
Ishigami's family (its own shifts and sums) and prints the coverage and the largest
error in units of ε·|integral|.
"""

import argparse
import json
import math
import os
import sys

import numpy as np
from scipy import stats

sys.path.insert(0, os.path.dirname(__file__))
from quad_models import exact, instance, value  # noqa: E402
from quad_rules import points  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = [  # (label, family, s)
    ("oscillatory s=5", "oscillatory", 5),
    ("product peak s=5", "product peak", 5),
    ("corner peak s=5", "corner peak", 5),
    ("corner peak s=20", "corner peak", 20),
    ("gaussian s=5", "gaussian", 5),
    ("(1+Σx)^-5 s=4", "corner1", 4),
    ("keister s=5", "keister", 5),
    ("lognormal s=5", "lognormal", 5),
]
# Families the skew guard was not chosen on (results/quad/interval.md), run with the rest.
CHECK_CASES = [(f"{f if f != 'corner1' else f'(1+Σx)^-{s + 1}'} s={s}", f, s) for f, s in (
    ("oscillatory", 20), ("product peak", 20), ("corner peak", 10), ("gaussian", 20),
    ("corner1", 8), ("ishigami", 3), ("keister", 20), ("lognormal", 20))]
METHODS = ["t8", "t2", "t4", "t16", "t4+round", "t8+round", "t16+round", "t4+skew",
           "t8+skew", "t16+skew", "quantile8", "pool4+round", "pool4+round/3", "t4+round/3", "t4+round/2", "t4+round/rate",
           "t4+round+skew", "t4+round+skew+ulp", "t4+round+skew:mc", "t4+round+skew:geo"]
LEVEL = 0.95


def integrand(family, s, seed):
    if family == "corner1":
        return (lambda x: (1.0 + x.sum(axis=1)) ** -(s + 1)), corner1_exact(s)
    p = instance(family, s, seed)
    return (lambda x: value(family, p, x)), exact(family, p)


def corner1_exact(s):
    """∫ (1 + Σx)^-(s+1) over [0,1]^s = (1/s!) Σ_k (−1)^k C(s,k) / (1 + k) (inclusion–
    exclusion on the iterated integral)."""
    return sum((-1) ** k * math.comb(s, k) / (1 + k) for k in range(s + 1)) / math.factorial(s)


def t_interval(means):
    r = len(means)
    t = stats.t.ppf((1 + LEVEL) / 2, r - 1)
    return means.mean(), t * means.std(ddof=1) / math.sqrt(r)


def intervals(y, n):
    """y: 16 replicates' values at their first n/2 (the first two) or n/4 points."""
    out = {}
    for r in (2, 4, 8, 16):
        m = np.array([v[: n // r].mean() for v in y[:r]])
        out[f"t{r}"] = t_interval(m)
    for r in (4, 8, 16):
        est, hw = out[f"t{r}"]
        half = np.mean([v[: n // (2 * r)].mean() for v in y[:r]])
        out[f"t{r}+round"] = (est, max(hw, abs(est - half)))
        m = np.array([v[: n // r].mean() for v in y[:r]])
        dev = m - m.mean()
        var = np.mean(dev ** 2) * r / (r - 1)
        # Johnson's (1978) correction of the mean's bias term μ3/(6 s² R), added to the
        # half-width on both sides (the estimate stays the mean).
        out[f"t{r}+skew"] = (est, hw + abs(np.mean(dev ** 3)) / (6 * var * r) if var > 0 else hw)
    # Cheaper guards and spreads on four replicates: the spread pooled with the one at
    # half the points (its variance divided by 4: an error falling like 1/n), Student t
    # on 2(R − 1) degrees of freedom; the round guard divided by 3 (the bound on the
    # error at n when it falls like 1/n², as the tent lattice's does on smooth f).
    m4 = np.array([v[: n // 4].mean() for v in y[:4]])
    h4 = np.array([v[: n // 8].mean() for v in y[:4]])
    pooled = math.sqrt((m4.var(ddof=1) + h4.var(ddof=1) / 4) / 2 / 4)
    change = abs(m4.mean() - h4.mean())
    tp = stats.t.ppf((1 + LEVEL) / 2, 6) * pooled
    out["pool4+round"] = (m4.mean(), max(tp, change))
    out["pool4+round/3"] = (m4.mean(), max(tp, change / 3))
    out["t4+round/3"] = (m4.mean(), max(out["t4"][1], change / 3))
    out["t4+round/2"] = (m4.mean(), max(out["t4"][1], change / 2))
    # The guard divided by 2^α − 1 for the rate α the last two rounds' changes show
    # (|Q_{n/2} − Q_{n/4}| / |Q_n − Q_{n/2}| ≈ 2^α), held between 1 and 3.
    quarter = np.mean([v[: n // 16].mean() for v in y[:4]])
    rho = abs(h4.mean() - quarter) / change if change > 0 else 4.0
    out["t4+round/rate"] = (m4.mean(), max(out["t4"][1], change / min(max(rho - 1, 1), 3)))
    values = np.concatenate([v[: n // 4] for v in y[:4]])
    out["t4+round+skew"] = (m4.mean(), skew_guard(values, out["t4+round"][1]))
    out["t4+round+skew:mc"] = (m4.mean(), skew_guard(values, out["t4+round"][1], "mc"))
    out["t4+round+skew:geo"] = (m4.mean(), skew_guard(values, out["t4+round"][1], "geo"))
    # The sums' rounding bound, as quad's (per replicate: values summed · ε · max|f|).
    largest = max(np.abs(v[: n // 4]).max() for v in y[:4])
    out["t4+round+skew+ulp"] = (m4.mean(), max(out["t4+round+skew"][1],
                                                (n // 4) * np.finfo(float).eps * largest))
    m = np.sort([v[: n // 8].mean() for v in y[:8]])
    lo, hi = m[1], m[6]
    out["quantile8"] = ((lo + hi) / 2, (hi - lo) / 2)
    return out


def skew_guard(values, h, base="min", factor=1.2):
    """quad's skew guard (cubature/src/lib.rs) on the half-width h from all the values:
    where f's values are skewed (|γ̂| > 1), at least w·1.2·min(h, z·σ̂/√n) times Hall's
    (1992) relative skewness term 1 + |γ̂|(2z² + 1)/(6z√n) of a mean of n values
    (``base``: "mc" puts z·σ̂/√n, "geo" √(h·z·σ̂/√n) in place of the min)."""
    n = len(values)
    dev = values - values.mean()
    m2, m3 = np.mean(dev ** 2), np.mean(dev ** 3)
    if m2 <= 0:
        return h
    gamma = abs(m3) / m2 ** 1.5
    w = min(max((gamma - 1) / 4, 0.0), 1.0)
    if w == 0:
        return h
    z = stats.norm.ppf((1 + LEVEL) / 2)
    mc = z * math.sqrt(m2 * n / (n - 1)) / math.sqrt(n)
    on = {"min": min(h, mc), "mc": mc, "geo": math.sqrt(h * mc)}[base]
    return max(h, w * factor * on * (1 + gamma * (2 * z * z + 1) / (6 * z * math.sqrt(n))))


def run_case(family, s, n, seeds):
    """seeds: a count (0 … seeds − 1) or, with --first-seed, a range."""
    rows = []
    for seed in range(seeds) if isinstance(seeds, int) else seeds:
        f, truth = integrand(family, s, seed)
        rng = np.random.default_rng([seed, 47])
        y = [f(points(s, rng.random(s), 0, n // (2 if rep < 2 else 4))) for rep in range(16)]
        res = intervals(y, n)
        rows.append({k: [float(e - truth), float(hw)] for k, (e, hw) in res.items()}
                    | {"truth": truth})
    return rows


def summary(rows):
    out = {}
    base_hw = np.array([r["t8"][1] for r in rows])
    base_err = np.array([r["t8"][0] for r in rows])
    for m in METHODS:
        err = np.array([r[m][0] for r in rows])
        hw = np.array([r[m][1] for r in rows])
        ok = np.abs(err) <= hw
        ratio = np.exp(np.mean(np.log(np.maximum(hw, 1e-300) / np.maximum(base_hw, 1e-300))))
        rmse = math.sqrt(np.mean(err ** 2)) / math.sqrt(np.mean(base_err ** 2))
        out[m] = {"coverage": float(ok.mean()), "width": float(ratio), "rmse": float(rmse)}
        if m in ("t4+round+skew", "t4+round+skew+ulp", "t4+round+skew:mc",
                 "t4+round+skew:geo"):
            # The share of seeds whose half-width the skew guard (the rounding bound) changed.
            plain = np.array([r[m.split(":")[0].rsplit("+", 1)[0]][1] for r in rows])
            out[m]["raised"] = float(np.mean(hw != plain))
    truth = np.array([abs(r["truth"]) for r in rows])
    err = np.array([abs(r["t4+round+skew+ulp"][0]) for r in rows])
    out["ulps"] = float(np.max(err / (np.finfo(float).eps * np.maximum(truth, 1e-300))))
    return out


def study(name, cases, run_case, summary):
    """Runs the cases the command line asks for (--seeds, --n, --cases), adding each
    case's summary to results/quad/<name>-<n>.json as it finishes; returns (args, data)."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=300)
    ap.add_argument("--n", type=int, default=4096)
    ap.add_argument("--cases", default="", help="comma-separated labels (default: all)")
    ap.add_argument("--first-seed", type=int, default=0,
                    help="seeds first-seed … (other seeds than the table's, to check a "
                    "choice made on it; written to <name>-from<first>-<n>.json)")
    ap.add_argument("--tag", default="",
                    help="a build measured beside the table's (written to "
                    "<name>-<tag>-<n>.json; --markdown --tag TAG prints them)")
    args = ap.parse_args()
    if args.first_seed:
        name = f"{name}-from{args.first_seed}"
    if args.tag:
        name = f"{name}-{args.tag}"
    path = os.path.join(ROOT, "results", "quad", f"{name}-{args.n}.json")
    data = {}
    if os.path.exists(path):
        with open(path) as fh:
            data = json.load(fh)
    wanted = [c for c in cases if not args.cases or c[0] in args.cases.split(",")]
    for label, family, s in wanted:
        seeds = (range(args.first_seed, args.first_seed + args.seeds) if args.first_seed
                 else args.seeds)
        rows = run_case(family, s, args.n, seeds)
        data[label] = {"seeds": args.seeds, "n": args.n, "summary": summary(rows)}
        with open(path, "w") as fh:
            json.dump(data, fh, indent=1)
        print(label, json.dumps(data[label]["summary"]), flush=True)
    return args, data


def study_main(name, cases, run_case, summary, table):
    """The main of a fixed-n study: ``--markdown`` prints ``table(data, n)`` for every N
    in results/quad/<name>-<N>.json; otherwise [`study`] runs and its table is printed."""
    if "--markdown" in sys.argv:
        if "--tag" in sys.argv:
            name = f"{name}-{sys.argv[sys.argv.index('--tag') + 1]}"
        folder = os.path.join(ROOT, "results", "quad")
        # <name>-<N>.json only: other builds' and seeds' files carry a tag before N.
        sizes = sorted(int(f[len(name) + 1:-5]) for f in os.listdir(folder)
                       if f.startswith(f"{name}-") and f.endswith(".json")
                       and f[len(name) + 1:-5].isdigit())
        for n in sizes:
            with open(os.path.join(folder, f"{name}-{n}.json")) as fh:
                print("\n".join(table(json.load(fh), n)) + "\n")
        return
    args, data = study(name, cases, run_case, summary)
    print("\n" + "\n".join(table(data, args.n)))


def package_check():
    """quad itself at a fixed n on Ishigami's family: coverage over the seeds, and the
    largest error in units of ε·|integral| (the rule integrates it exactly)."""
    import stillpoint as sp

    ap = argparse.ArgumentParser()
    ap.add_argument("--package", action="store_true")
    ap.add_argument("--seeds", type=int, default=300)
    ap.add_argument("--n", type=int, default=4096)
    args = ap.parse_args()
    hit, worst = 0, 0.0
    for seed in range(args.seeds):
        f, truth = integrand("ishigami", 3, seed)
        r = sp.quad(f, 3, abs_tol=0, rel_tol=0, max_n=args.n, seed=seed)
        assert r.n == args.n
        hit += abs(r.estimate - truth) <= r.half_width
        worst = max(worst, abs(r.estimate - truth) / (np.finfo(float).eps * abs(truth)))
    print(f"ishigami s=3, n = {args.n}: quad covers {hit} of {args.seeds}; "
          f"largest error {worst:.1f} ε·|integral|")


FACTORS = (1.2, 1.5, 2.0, 2.5, 3.0)


def misses():
    """Where quad's interval (``t4+round+skew+ulp``) misses on one case (``--misses``)."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--misses", required=True)
    ap.add_argument("--seeds", type=int, default=300)
    ap.add_argument("--n", type=int, default=1024)
    args = ap.parse_args()
    _, family, s = next(c for c in CASES + CHECK_CASES if c[0] == args.misses)
    z = stats.norm.ppf((1 + LEVEL) / 2)
    rows = []
    for seed in range(args.seeds):
        f, truth = integrand(family, s, seed)
        rng = np.random.default_rng([seed, 47])
        y = [f(points(s, rng.random(s), 0, args.n // 4)) for _ in range(4)]
        values = np.concatenate(y)
        est = values.mean()
        out = intervals(y + [y[0]] * 12, args.n)
        hw = out["t4+round+skew+ulp"][1]
        dev = values - est
        gamma = np.mean(dev ** 3) / np.mean(dev ** 2) ** 1.5
        rows.append((est - truth, hw, gamma, z * values.std(ddof=1) / math.sqrt(args.n))
                    + tuple(skew_guard(values, out["t4+round"][1], factor=c) for c in FACTORS))
    r = np.array(rows)
    sweep = [f"{c}: {np.mean(np.abs(r[:, 0]) <= r[:, 4 + i]) * 100:.1f} % "
             f"({np.exp(np.mean(np.log(r[:, 4 + i] / r[:, 1]))):.2f}×)"
             for i, c in enumerate(FACTORS)]
    print(f"{args.misses}, n = {args.n}, the skew guard's factor: " + ", ".join(sweep))
    miss = np.abs(r[:, 0]) > r[:, 1]
    print(f"{args.misses}, n = {args.n}: {miss.sum()} misses of {args.seeds}, "
          f"{np.sum(r[miss, 0] < 0)} below the integral; γ̂ on the misses "
          f"{np.min(r[miss, 2]):.1f}–{np.max(r[miss, 2]):.1f} (median over all seeds "
          f"{np.median(r[:, 2]):.1f}); |error| / Monte Carlo's half-width on the misses "
          f"{np.min(np.abs(r[miss, 0]) / r[miss, 3]):.2f}–{np.max(np.abs(r[miss, 0]) / r[miss, 3]):.2f} "
          f"(median over all seeds {np.median(np.abs(r[:, 0]) / r[:, 3]):.2f})")


def main():
    if "--package" in sys.argv:
        package_check()
        return
    if "--misses" in sys.argv:
        misses()
        return
    args, data = study("interval", CASES + CHECK_CASES, run_case, summary)
    print(f"\n| family (n = {args.n}, {args.seeds} seeds) | "
          + " | ".join(METHODS) + " |")
    print("|---" * (len(METHODS) + 1) + "|")
    for label, _, _ in CASES + CHECK_CASES:
        if label not in data:
            continue
        sm = data[label]["summary"]
        cells = [f"{sm[m]['coverage'] * 100:.1f} % ({sm[m]['width']:.2f}×)" for m in METHODS]
        print(f"| {label} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
