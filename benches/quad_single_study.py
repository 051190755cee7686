"""Single-sequence error bounds on a scrambled Sobol' sequence, alone and guarded by
independent randomisations, against quad's interval (4 replicates and the round change)
at a fixed number of evaluations. A prototype on SciPy's scrambled Sobol' (LMS + digital
shift, points put back in the net's natural order), not the package's rule.

Per case (the model families of benches/quad_blocks_study.py and the Genz cube cells of
benches/quad_interval.py, all on Sobol') and seed (a new instance, new scrambles), with
N evaluations unless a name says otherwise:

- ``t4+round`` (quad's layout): 4 independent sequences of N/4, Student t_3 on their
  means, raised to the round change |Q_N − Q_{N/2}|;
- ``net``: one sequence of N, the data-driven bound of QMCPy's ``CubQMCNetG``
  (Hickernell & Jiménez Rugama 2016): the Walsh coefficients of the values in the net's
  order (fast Walsh–Hadamard transform), the wavenumber map κ̃ kept as CubQMCNetG keeps it
  from n_init = 2^10 through each doubling, and the half-width 5·2^−m·Σ|f̃_κ| over the band
  κ̃ ∈ [2^(m−5), 2^(m−4)) (its default inflation factor 5·2^−m and lag r = 4);
- ``bayes``: one sequence of N, ``CubBayesNetG``'s posterior half-width (Jagadeeswaran &
  Hickernell: the order-1 Walsh kernel Π(1 + θ/10·ω(x ⊕ x_0)), its eigenvalues by the
  fast transform, θ by maximum likelihood on ln θ ∈ [−5, 0], the "MLE" bound) at z_0.975
  (``bayes99``: the same at z_0.995, QMCPy's default level); the kernel is evaluated at
  x_i ⊕ x_0 (the unshifted net, whose Gram matrix the transform diagonalises);
- ``bayes-qmcpy``: the same with the kernel at the points themselves, as QMCPy 2.4 does
  under its default LMS + digital shift (``--check-qmcpy`` shows the two agree without the
  shift);
- ``… +round``: raised to the round change |Q_N − Q_{N/2}| of the sequence (nested, free);
- ``… 2×N/2 d×c``: two independent sequences of N/2, the mean of both; the bound on the
  mean ((B_a + B_b)/2 for ``net``, √(h_a² + h_b²)/2 for ``bayes``) raised to the round
  change and to c·|Q_a − Q_b|/2 (the independent check);
- ``… N+N/4 check`` (costs 1.25 N): the sequence of N and an independent check sequence of
  N/4 with its own bound B_c; when |Q_N − Q_c| ≤ B_N + B_c the interval is the round-guarded
  bound of the N sequence, otherwise the stop is refused and the interval given is
  |Q_N − Q_c| + B_c (what the check's own bound allows); "refused" counts those runs.

Per case and interval: coverage at level 0.95 (±1.3 % at 300 seeds), the geometric mean of
the half-width over ``t4+round``'s, the RMSE of the relative error over ``t4+round``'s; per
case the wall time of each bound (outside f) per sequence.

    python benches/quad_single_study.py [--seeds 300] [--n 4096] [--raw DIR] [--owen]
    python benches/quad_single_study.py --from-raw DIR
    python benches/quad_single_study.py --markdown
    python benches/quad_single_study.py --check-qmcpy

(python: one with NumPy and SciPy; ``--owen`` also needs the stillpoint package,
``--check-qmcpy`` QMCPy.) ``--owen`` adds one sequence of N of the package's
Owen-scrambled Sobol' (``baseline("sobol")``, natural order) and the three bounds on it
(``… owen 1×N+round``): nested scrambling is not a shifted linear net, so neither fast
transform has its footing there; the study measures what they give anyway. Writes
results/quad/single-<N>.json and prints a Markdown table; ``--raw DIR`` also writes each
case's per-seed means and bounds to DIR, from which ``--from-raw DIR`` forms the JSONs
again. ``--markdown`` prints the tables of every N and the evaluations the Bayesian
interval at 99 % would save (``savings``). ``--check-qmcpy`` compares the two bounds with
QMCPy's own on QMCPy's points (they agree to every printed digit; under QMCPy's default
digital shift, CubBayesNetG's agrees with ``at_points``).
"""

import json
import math
import os
import sys
import time

import numpy as np
from scipy import optimize, stats

sys.path.insert(0, os.path.dirname(__file__))
import quad as bench  # noqa: E402
from quad_blocks_study import CASES as MODEL_CASES  # noqa: E402
from quad_interval import CASES as GENZ_CASES  # noqa: E402
from quad_interval import integrand as genz_integrand  # noqa: E402
from quad_interval import ROOT, study_main  # noqa: E402

CASES = MODEL_CASES + [(f"genz {label}", family, s) for label, family, s in GENZ_CASES]
BOUNDS = ("net", "bayes")
Z = float(stats.norm.ppf(0.975))
# the bounds an interval is made of: (name, bound, factor on it)
KINDS = (("net", "net", 1.0), ("bayes", "bayes", 1.0),
         ("bayes99", "bayes", float(stats.norm.ppf(0.995)) / Z))
VARIANTS = (" 1×N", " 1×N+round", " 2×N/2 d×2", " 2×N/2 d×3", " N+N/4 check")
METHODS = (["t4+round"] + [k + v for k, _, _ in KINDS for v in VARIANTS]
           + ["bayes-qmcpy 1×N+round", "bayes99-qmcpy 1×N+round"])
OWEN_METHODS = [f"{k} owen 1×N+round" for k, _, _ in KINDS]
T3 = float(stats.t.ppf(0.975, 3))
BITS = 30  # SciPy's Sobol' points are multiples of 2^-30
M_INIT = 10  # CubQMCNetG's default n_init = 2^10
LAG = 4  # CubQMCNetG's r_lag
RAW_DIR = None  # --raw DIR: each case's per-seed pieces are also written there
OWEN = False  # --owen: also one sequence of the package's Owen-scrambled Sobol'


def fwht(y):
    """The unnormalised Walsh–Hadamard transform Σ_i (−1)^{popcount(i & k)} y_i, k in
    natural order (QMCPy's ``fwht`` times √n)."""
    a = np.array(y, dtype=float)
    n = a.size
    h = 1
    while h < n:
        a = a.reshape(-1, 2, h)
        a = np.concatenate([a[:, 0] + a[:, 1], a[:, 0] - a[:, 1]], axis=1).reshape(n)
        h *= 2
    return a


def sobol(d, n, key):
    """n points of a scrambled Sobol' sequence (SciPy: LMS + digital shift) in the net's
    natural (radical-inverse) order, as floats and as 30-bit integers. SciPy draws in Gray
    code order: its p-th point is the natural one of index p ^ (p >> 1)."""
    from scipy.stats import qmc

    x = qmc.Sobol(d, scramble=True, seed=np.random.default_rng(key)).random(n)
    p = np.arange(n)
    out = np.empty_like(x)
    out[p ^ (p >> 1)] = x
    return out, np.rint(out * 2.0 ** BITS).astype(np.uint64)


def update_map(kmap, yt, mfrom, mto, m):
    """CubQMCNetG's ``_update_kappanumap``: at each level l, the later half of each pair of
    wavenumbers takes the earlier one's place when its coefficient is larger."""
    for lev in range(mfrom, mto, -1):
        nl = 2 ** lev
        old = np.abs(yt[kmap[1:nl]])
        new = np.abs(yt[kmap[nl + 1: 2 * nl]])
        flip = np.nonzero(new > old)[0] + 1
        if flip.size:
            add = np.arange(0, 2 ** m - 1, 2 ** (lev + 1))
            f = (flip[None, :] + add[:, None]).ravel()
            kmap[f], kmap[nl + f] = kmap[nl + f], kmap[f]
    return kmap


def net_bound(y):
    """CubQMCNetG's half-width on the values y of one net of 2^m points in natural order,
    with the wavenumber map built as its doublings from 2^10 build it."""
    big = int(math.log2(y.size))
    m0 = min(M_INIT, big)
    yt = fwht(y[: 2 ** m0]) / 2 ** m0
    kmap = update_map(np.arange(2 ** m0), yt, m0 - 1, 0, m0)
    for m in range(m0 + 1, big + 1):
        yt = fwht(y[: 2 ** m]) / 2 ** m
        kmap = np.concatenate([kmap, 2 ** (m - 1) + kmap])
        kmap = update_map(kmap, yt, m - 1, m - LAG - 1, m)
    lo = 2 ** (big - LAG - 1)
    return 5.0 * 2.0 ** -big * float(np.abs(yt[kmap[lo: 2 * lo]]).sum())


def walsh_factor(xi):
    """The order-1 Walsh kernel's one-dimensional factor ω(x) = 6(1/6 − 2^(⌊log2 x⌋ − 1))
    (QMCPy's ``BuildKernelFunc(1)``) on the integers x·2^30."""
    x = xi.astype(float) * 2.0 ** -BITS
    return 6 * (1 / 6 - 2 ** (np.floor(np.log2(x + np.finfo(float).eps)) - 1))


def bayes_bound(y, xi, z=Z, at_points=False):
    """CubBayesNetG's "MLE" half-width (arb_mean, avoid_cancel_error as QMCPy sets them) on
    the values y at the net points xi (integers, natural order). The kernel's first column
    is taken at x_i ⊕ x_0, or with ``at_points`` at x_i itself as QMCPy 2.4 takes it (the
    same for an unshifted net; under a digital shift not a column of the Gram matrix)."""
    n = y.size
    w = walsh_factor(xi if at_points else xi ^ xi[0])
    ft = fwht(y)

    def kernel(theta):
        km1 = theta / 10 * w[:, 0]
        k = 1 + km1
        for j in range(1, w.shape[1]):
            km1 = theta / 10 * w[:, j] * k + km1
            k = 1 + km1
        factor = float(np.max(np.abs(km1)))
        ring = fwht(km1 / factor)
        lam = ring.copy()
        lam[0] += n / factor
        return np.abs(lam), ring, factor

    return z * mle_fit(ft, kernel, n)[1]


def mle_fit(ft, kernel, n):
    """(the negative log-likelihood at its optimum over ln theta in [-5, 0], the posterior
    standard deviation of the integral) of a Bayesian cubature whose Gram matrix the
    transform diagonalises: ``ft`` the values' transform, ``kernel(theta)`` the
    eigenvalues divided by ``factor``, the first column's transform and ``factor``."""
    tiny = 100 * np.finfo(float).eps

    def objective(lna):
        lam, _, factor = kernel(math.exp(lna))
        keep = lam > tiny
        temp = np.abs(ft[keep]) ** 2 / lam[keep]
        t1 = float(temp[1:].sum()) / factor
        loss1 = float(np.log(np.abs(factor * lam[keep])).sum())
        return loss1 + n * math.log(t1 if t1 != 0 else np.finfo(float).eps)

    best = optimize.minimize_scalar(objective, bounds=(-5, 0), method="bounded",
                                    options={"xatol": 1e-2})
    lam, ring, factor = kernel(math.exp(best.x))
    keep = lam > tiny
    rkhs = float((np.abs(ft[keep]) ** 2 / lam[keep])[1:].sum()) / factor / n
    dsc = abs(factor * ring[0] / (n + factor * ring[0]))
    return float(best.fun), math.sqrt(dsc * rkhs / n)


def run_case(family, s, n, seeds):
    """Per seed, the raw pieces every interval is formed from (relative to the exact
    value): the means of each sequence and of its first half, and each sequence's bounds."""
    rows = []
    for seed in range(seeds):
        if family in bench.MODEL_FAMILIES:
            f, _, _, truth = bench.model(family, s, seed)
        else:
            f, truth = genz_integrand(family, s, seed)
        d = s[0] if isinstance(s, tuple) else s
        raw = {"seconds": {k: 0.0 for k in BOUNDS}}

        def rel(q):
            return (q - truth) / abs(truth)

        def sequence(name, m, r, bounds=True):
            x, xi = sobol(d, m, [seed, 49, r])
            y = np.asarray(f(x), dtype=float)
            raw[name] = rel(y.mean())
            raw[name + " half"] = rel(y[: m // 2].mean())
            for kind in BOUNDS if bounds else ():
                t0 = time.perf_counter()
                b = net_bound(y) if kind == "net" else bayes_bound(y, xi)
                raw["seconds"][kind] += time.perf_counter() - t0
                raw[f"{kind} {name}"] = b / abs(truth)
            if bounds and name == "one":
                raw["bayes-qmcpy one"] = bayes_bound(y, xi, at_points=True) / abs(truth)

        if OWEN:
            import stillpoint as sp

            x = np.asarray(sp.baseline("sobol", n, d, seed=1000 * seed + 49), dtype=float)
            y = np.asarray(f(x), dtype=float)
            xi = np.floor(x * 2.0 ** BITS).astype(np.uint64)
            raw["owen"], raw["owen half"] = rel(y.mean()), rel(y[: n // 2].mean())
            raw["net owen"] = net_bound(y) / abs(truth)
            raw["bayes owen"] = bayes_bound(y, xi) / abs(truth)
        for r in range(4):
            sequence(f"r{r}", n // 4, 10 + r, bounds=False)
        sequence("one", n, 30)
        sequence("check", n // 4, 31)
        sequence("a", n // 2, 20)
        sequence("b", n // 2, 21)
        raw["seconds"] = {k: v / 4 for k, v in raw["seconds"].items()}  # per bound
        rows.append(raw)
    if RAW_DIR:
        name = "".join(c if c.isalnum() else "_" for c in f"{family} {s} {n}")
        with open(os.path.join(RAW_DIR, name + ".json"), "w") as fh:
            json.dump(rows, fh)
    return rows


def intervals(raw):
    """(relative error, relative half-width) of every method, and the checks' refusals."""
    out = {}
    m4 = np.array([raw[f"r{r}"] for r in range(4)])
    q = m4.mean()
    out["t4+round"] = (q, max(T3 * np.std(m4, ddof=1) / 2,
                              abs(q - np.mean([raw[f"r{r} half"] for r in range(4)]))))
    q1, qc, qa, qb = raw["one"], raw["check"], raw["a"], raw["b"]
    round1 = abs(q1 - raw["one half"])
    q2 = (qa + qb) / 2
    round2 = abs(q2 - (raw["a half"] + raw["b half"]) / 2)
    refused = {}
    for name, kind, factor in KINDS:
        b1, bc, ba, bb = (factor * raw[f"{kind} {k}"] for k in ("one", "check", "a", "b"))
        out[f"{name} 1×N"] = (q1, b1)
        out[f"{name} 1×N+round"] = (q1, max(b1, round1))
        # the mean's bound: errors within their bounds (net); independent posteriors (bayes)
        mean_b = (ba + bb) / 2 if kind == "net" else math.hypot(ba, bb) / 2
        for c in (2, 3):
            out[f"{name} 2×N/2 d×{c}"] = (q2, max(mean_b, round2, c * abs(qa - qb) / 2))
        gap = abs(q1 - qc)
        refused[name] = gap > b1 + bc
        out[f"{name} N+N/4 check"] = (q1, gap + bc if refused[name] else max(b1, round1))
        if kind == "bayes":
            out[f"{name}-qmcpy 1×N+round"] = (q1, max(factor * raw["bayes-qmcpy one"], round1))
    if "owen" in raw:
        q, change = raw["owen"], abs(raw["owen"] - raw["owen half"])
        for name, kind, factor in KINDS:
            out[f"{name} owen 1×N+round"] = (q, max(factor * raw[f"{kind} owen"], change))
    return out, refused


def summary(rows):
    formed = [intervals(r) for r in rows]
    base_hw = np.array([o["t4+round"][1] for o, _ in formed])
    base_err = np.array([o["t4+round"][0] for o, _ in formed])
    out = {}
    for m in METHODS + (OWEN_METHODS if "owen" in rows[0] else []):
        err = np.array([o[m][0] for o, _ in formed])
        hw = np.array([o[m][1] for o, _ in formed])
        out[m] = {"coverage": float(np.mean(np.abs(err) <= hw)),
                  "width": float(np.exp(np.mean(np.log(np.maximum(hw, 1e-300)
                                                       / np.maximum(base_hw, 1e-300))))),
                  "rmse": float(math.sqrt(np.mean(err ** 2) / np.mean(base_err ** 2))),
                  "relative rmse": float(math.sqrt(np.mean(err ** 2)))}
    for name, _, _ in KINDS:
        m = f"{name} N+N/4 check"
        out[m]["refused"] = float(np.mean([r[name] for _, r in formed]))
        # a wrong stop: the check agreed and the interval misses
        out[m]["wrong stops"] = float(np.mean([not r[name] and abs(o[m][0]) > o[m][1]
                                               for o, r in formed]))
    for kind in BOUNDS:
        out[f"{kind} seconds"] = float(np.mean([r["seconds"][kind] for r in rows]))
    return out


def table(data, n):
    """Per case: quad's coverage, the RMSE of the two estimates over quad's, each interval's
    coverage (half-width over quad's), the checks' refusals, and the bounds' times."""
    rest = METHODS[1:]
    lines = [f"| case (N = {n}, seeds) | t4+round | rmse 1×N | rmse 2×N/2 | "
             + " | ".join(rest) + " | refused (net, bayes, bayes99) | time per bound "
             "(net, bayes) |", "|---" * (len(rest) + 6) + "|"]
    for label, _, _ in CASES:
        if label not in data:
            continue
        sm = data[label]["summary"]
        cells = [f"{sm['t4+round']['coverage'] * 100:.1f} %",
                 f"{sm['net 1×N']['rmse']:.2f}×", f"{sm['net 2×N/2 d×2']['rmse']:.2f}×"]
        cells += [f"{sm[m]['coverage'] * 100:.1f} % ({sm[m]['width']:.2f}×)" for m in rest]
        cells.append(", ".join(f"{sm[f'{k} N+N/4 check']['refused'] * 100:.0f} %"
                               for k, _, _ in KINDS))
        cells.append(f"{sm['net seconds'] * 1e3:.1f} ms, {sm['bayes seconds'] * 1e3:.0f} ms")
        lines.append(f"| {label} ({data[label]['seeds']}) | " + " | ".join(cells) + " |")
    shown = [data[label]["summary"] for label, _, _ in CASES if label in data]
    if shown:
        # the worst cell's coverage, and the geometric mean of the widths over the cells
        worst = [f"**{min(sm[m]['coverage'] for sm in shown) * 100:.1f} %** "
                 f"({math.exp(np.mean([math.log(sm[m]['width']) for sm in shown])):.2f}×)"
                 for m in METHODS]
        lines.append("| worst cell (geometric mean of widths) | " + worst[0] + " | | | "
                     + " | ".join(worst[1:]) + " | | |")
    return lines


def load_all():
    """{N: the study's JSON} for every results/quad/single-<N>.json."""
    folder = os.path.join(ROOT, "results", "quad")
    data = {}
    for f in os.listdir(folder):
        if f.startswith("single-") and f.endswith(".json"):
            with open(os.path.join(folder, f)) as fh:
                data[int(f[7:-5])] = json.load(fh)
    return {n: data[n] for n in sorted(data)}


def overview():
    """Per interval and N: the worst case's coverage, the number of cases below 93 %, and
    the geometric mean over the cases of the half-width over quad's."""
    data = load_all()
    lines = ["| interval | " + " | ".join(f"N = {n}: worst, cases < 93 %, width"
                                          for n in data) + " |",
             "|---" * (len(data) + 1) + "|"]
    for m in METHODS + OWEN_METHODS:
        cells = []
        for d in data.values():
            sms = [d[label]["summary"][m] for label, _, _ in CASES
                   if label in d and m in d[label]["summary"]]
            if not sms:
                cells.append("—")
                continue
            cov = [sm["coverage"] for sm in sms]
            width = math.exp(np.mean([math.log(sm["width"]) for sm in sms]))
            cells.append(f"{min(cov) * 100:.1f} %, {sum(c < 0.93 for c in cov)}, "
                         f"{width:.2f}×")
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    return lines


def owen_table():
    """Per case and N, with ``--owen``: the posterior at 99 % on one sequence of the
    package's Owen-scrambled Sobol' (coverage, half-width over quad's) and its RMSE over
    the LMS sequence's."""
    data = {n: d for n, d in load_all().items()
            if all("bayes99 owen 1×N+round" in v["summary"] for v in d.values())}
    if not data:
        return []
    lines = ["| case | " + " | ".join(f"N = {n}: coverage (width), rmse over LMS"
                                      for n in data) + " |", "|---" * (len(data) + 1) + "|"]
    for label, _, _ in CASES:
        cells = []
        for d in data.values():
            sm = d[label]["summary"]
            o, one = sm["bayes99 owen 1×N+round"], sm["bayes99 1×N+round"]
            cells.append(f"{o['coverage'] * 100:.1f} % ({o['width']:.2f}×), "
                         f"{o['relative rmse'] / one['relative rmse']:.2f}×")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return lines


def savings(method="bayes99 1×N+round"):
    """Per case, the evaluations ``method`` would need relative to quad's interval for the
    same half-width, width^(1/α), with α the rate of the one sequence's RMSE between the
    smallest and the largest N measured (held in [0.5, 2])."""
    data = load_all()
    sizes = list(data)
    lines = [f"| case | α | " + " | ".join(f"N = {n}" for n in sizes) + " |",
             "|---" * (len(sizes) + 2) + "|"]
    logs = {n: [] for n in sizes}
    for label, _, _ in CASES:
        if not all(label in data[n] for n in sizes):
            continue
        lo, hi = (data[n][label]["summary"][method]["relative rmse"] for n in (sizes[0],
                                                                                 sizes[-1]))
        alpha = min(2.0, max(0.5, math.log(lo / hi) / math.log(sizes[-1] / sizes[0])))
        cells = []
        for n in sizes:
            r = data[n][label]["summary"][method]["width"] ** (1 / alpha)
            logs[n].append(math.log(r))
            cells.append(f"{r:.2f}×")
        lines.append(f"| {label} | {alpha:.2f} | " + " | ".join(cells) + " |")
    lines.append("| geometric mean | | " + " | ".join(
        f"{math.exp(np.mean(logs[n])):.2f}×" for n in sizes) + " |")
    return lines


def from_raw(folder):
    """Forms results/quad/single-<N>.json again from the pieces a ``--raw`` run wrote."""
    for n in (1024, 4096, 16384):
        data = {}
        for label, family, s in CASES:
            name = "".join(c if c.isalnum() else "_" for c in f"{family} {s} {n}")
            path = os.path.join(folder, name + ".json")
            if os.path.exists(path):
                with open(path) as fh:
                    rows = json.load(fh)
                data[label] = {"seeds": len(rows), "n": n, "summary": summary(rows)}
        if data:
            with open(os.path.join(ROOT, "results", "quad", f"single-{n}.json"), "w") as fh:
                json.dump(data, fh, indent=1)


def check_qmcpy():
    """The two bounds here against QMCPy's on QMCPy's own net (LMS scrambling only, so
    that x ⊕ x_0 is the point itself as QMCPy's kernel assumes) and integrand values."""
    import warnings

    import qmcpy as qp

    for d, n in ((3, 2 ** 12), (8, 2 ** 13)):
        def g(x):
            return np.exp(-np.sum((x - 0.3) ** 2, axis=-1)) + x[..., 0] ** 3

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            net = qp.DigitalNetB2(d, seed=7, randomize="LMS")
            c = qp.CubQMCNetG(qp.CustomFun(qp.Uniform(net), g=g), abs_tol=1e-15, n_limit=n)
            _, data = c.integrate()
            ours = net_bound(np.asarray(data.yfull, dtype=float))
            print(f"net   d={d} n={data.n_total}: qmcpy {float(data.bounds_half_width):.6e} "
                  f"here {ours:.6e}")
            net = qp.DigitalNetB2(d, seed=7, randomize="LMS")
            c = qp.CubBayesNetG(qp.CustomFun(qp.Uniform(net), g=g), abs_tol=1e-15,
                                n_init=n, n_limit=n, alpha=0.05)
            _, data = c.integrate()
            xi = np.rint(np.asarray(data.xfull) * 2.0 ** BITS).astype(np.uint64)
            ours = bayes_bound(np.asarray(data.yfull, dtype=float), xi)
            print(f"bayes d={d} n={data.n_total}: qmcpy {float(data.bounds_half_width):.6e} "
                  f"here {ours:.6e}")
            # QMCPy's default randomisation, LMS + digital shift: its kernel is taken at the
            # shifted points, not at x ⊕ x_0
            net = qp.DigitalNetB2(d, seed=7)
            c = qp.CubBayesNetG(qp.CustomFun(qp.Uniform(net), g=g), abs_tol=1e-15,
                                n_init=n, n_limit=n, alpha=0.05)
            _, data = c.integrate()
            xi = np.rint(np.asarray(data.xfull) * 2.0 ** BITS).astype(np.uint64)
            y = np.asarray(data.yfull, dtype=float)
            print(f"bayes d={d} n={data.n_total} ({net.randomize}): qmcpy "
                  f"{float(data.bounds_half_width):.6e}, here at the points "
                  f"{bayes_bound(y, xi, at_points=True):.6e}, at x ⊕ x_0 "
                  f"{bayes_bound(y, xi):.6e}")


def main():
    if "--check-qmcpy" in sys.argv:
        check_qmcpy()
        return
    global RAW_DIR, OWEN
    if "--owen" in sys.argv:
        OWEN = True
        sys.argv.remove("--owen")
    if "--raw" in sys.argv:
        i = sys.argv.index("--raw")
        RAW_DIR = sys.argv[i + 1]
        del sys.argv[i: i + 2]
    if "--from-raw" in sys.argv:
        from_raw(sys.argv[sys.argv.index("--from-raw") + 1])
        return
    study_main("single", CASES, run_case, summary, table)
    if "--markdown" in sys.argv:
        print("\n".join(overview()) + "\n")
        print("\n".join(owen_table()) + "\n")
        print("\n".join(savings()))


if __name__ == "__main__":
    main()
