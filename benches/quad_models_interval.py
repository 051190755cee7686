"""The interval of `stillpoint.quad` under input laws (the rule the laws choose:
Owen-scrambled Sobol' where a law is unbounded, the tent lattice where every law is
bounded, as Morokoff–Caflisch's uniform inputs) at a fixed number of evaluations: which
part of it binds, and what a round guard scaled to the rule's rate would cost in coverage.

For each model family of benches/quad.py (through ``space=``) and each seed 0 … SEEDS−1
(a new instance and a new randomisation), ``stillpoint.quad(f, s, abs_tol=0, rel_tol=0,
max_n=N, space=...)`` runs to exactly N evaluations with its default rule and replicates
(R = 4); its replicate means and its round change |Q_N − Q_{N/2}| (``round_change``) are
read from the result, and every interval below is formed from them (no extra
evaluation):

- ``t4``: the Student t half-width t_{3,0.975}·sd/√4 alone;
- ``t4+round``: quad's interval, the t half-width raised to the round change;
- ``t4+round/c``: the round change divided by c before it is compared: c = 2^α − 1 bounds
  the error at N when the error falls at least like N^−α per doubling (c = 1: α = 1;
  c = 1.83: α = 1.5, the rate of a scrambled net on smooth integrands; c = 3: α = 2);
- ``bound``: the share of seeds where the round change, not the t half-width, set quad's
  interval;
- ``quad``: quad's own interval (``t4+round`` with the skew guard and the rounding floor;
  its coverage only).

Per case and interval: coverage of the exact integral at level 0.95 (±1.3 % at 300
seeds), the geometric mean of the relative half-width over ``t4+round``'s (below 1: the
tolerance is reached earlier), and the RMSE of the relative error (the same for all).

    target/py-venv/bin/python benches/quad_models_interval.py [--seeds 300] [--n 4096]
    target/py-venv/bin/python benches/quad_models_interval.py --markdown

Writes results/quad/models-interval-<N>.json and prints a Markdown table.

``--ceiling`` measures instead what replicates cost in accuracy, the most an interval
from one sequence could win: per case and seed, the relative error of one scrambled
Sobol' sequence of N points (SciPy's, LMS + digital shift, on the cube through the same
laws' quantiles) and of the mean of 4 independent ones of N/4 (quad's layout); per case
their RMSEs and the ratio (results/quad/models-ceiling-<N>.json). Sobol' on every case,
also Morokoff–Caflisch's, whose bounded laws take the lattice in quad.
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
    ("uq keister s=5", "uq keister", 5),
    ("uq keister s=10", "uq keister", 10),
    ("uq oscillatory (normal) s=8", "uq oscillatory (normal)", 8),
    ("uq gaussian (normal) s=8", "uq gaussian (normal)", 8),
    ("uq lognormal product s=10", "uq lognormal product", 10),
    ("uq morokoff-caflisch s=10", "uq morokoff-caflisch", 10),
    ("geometric asian m=32 pca", "geometric asian", (32, "pca")),
    ("geometric asian m=32 standard", "geometric asian", (32, "standard")),
]
T_3 = 3.182446305284263  # t_{3, 0.975}
DIVISORS = [1.0, 2 ** 1.5 - 1, 3.0]
METHODS = ["t4"] + ["t4+round" if c == 1 else f"t4+round/{c:.3g}" for c in DIVISORS]


def run_case(family, s, n, seeds):
    import stillpoint as sp

    rows = []
    for seed in (range(seeds) if isinstance(seeds, int) else seeds):
        _, texts, on_values, truth = bench.model(family, s, seed)
        d = s[0] if isinstance(s, tuple) else s
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = sp.quad(on_values, d, abs_tol=0.0, rel_tol=0.0, max_n=n, space=texts,
                          seed=seed)
        means = np.asarray(res.replicate_means, dtype=float)
        r = means.size
        t = T_3 / math.sqrt(r) * float(np.std(means, ddof=1))
        change = res._state.round_change[0]
        change = 0.0 if change is None else float(change)
        err = (float(res.estimate) - truth) / abs(truth)
        row = {"err": err, "t": t / abs(truth), "change": change / abs(truth),
               "hw": float(res.half_width) / abs(truth), "rule": res.rule, "n": res.n}
        rows.append(row)
    return rows


def summary(rows):
    err = np.array([r["err"] for r in rows])
    t = np.array([r["t"] for r in rows])
    change = np.array([r["change"] for r in rows])
    base = np.maximum(t, change)
    out = {"rmse": float(math.sqrt(np.mean(err ** 2))),
           "bound": float(np.mean(change > t)),
           "rule": sorted({r["rule"] for r in rows}),
           "n": int(np.median([r["n"] for r in rows])),
           # quad's own half-width agrees with the one formed here
           "agree": float(np.max(np.abs(base - np.array([r["hw"] for r in rows]))
                                 / np.maximum(base, 1e-300)))}
    # quad's own interval: t4+round with the skew guard and the rounding floor.
    out["quad"] = {"coverage": float(np.mean(np.abs(err) <= np.array([r["hw"] for r in rows])))}
    for m, hw in zip(METHODS, [t] + [np.maximum(t, change / c) for c in DIVISORS]):
        out[m] = {"coverage": float(np.mean(np.abs(err) <= hw)),
                  "width": float(np.exp(np.mean(np.log(np.maximum(hw, 1e-300)
                                                       / np.maximum(base, 1e-300))))),
                  "relative": float(np.exp(np.mean(np.log(np.maximum(hw, 1e-300)))))}
    return out


def table(data, n):
    lines = [f"| family (N = {n}, seeds) | rule | rmse | guard binds | " + " | ".join(METHODS)
             + " | quad |", "|---" * (len(METHODS) + 5) + "|"]
    for label, _, _ in CASES:
        if label not in data:
            continue
        sm = data[label]["summary"]
        cells = [f"{sm[m]['coverage'] * 100:.1f} % ({sm[m]['width']:.2f}×)" for m in METHODS]
        lines.append(f"| {label} ({data[label]['seeds']}) | {', '.join(sm['rule'])} | "
                     f"{sm['rmse']:.2g} | "
                     f"{sm['bound'] * 100:.0f} % | " + " | ".join(cells) + " | "
                     + (f"{sm['quad']['coverage'] * 100:.1f} %" if "quad" in sm else "—")
                     + " |")
    return lines


def run_ceiling(family, s, n, seeds):
    from scipy.stats import qmc

    rows = []
    for seed in range(seeds):
        on_cube, _, _, truth = bench.model(family, s, seed)
        d = s[0] if isinstance(s, tuple) else s

        def mean(m, r):
            u = qmc.Sobol(d, scramble=True, seed=np.random.default_rng([seed, 47, r]))
            return float(np.mean(on_cube(u.random(m))))

        one = mean(n, 0)
        four = float(np.mean([mean(n // 4, 1 + r) for r in range(4)]))
        rows.append([(one - truth) / abs(truth), (four - truth) / abs(truth)])
    return rows


def summary_ceiling(rows):
    a = np.array(rows)
    one, four = (float(math.sqrt(np.mean(a[:, k] ** 2))) for k in (0, 1))
    return {"one": one, "four": four, "ratio": four / one}


def table_ceiling(data, n):
    lines = [f"| family (N = {n}, seeds) | one sequence of N | 4 of N/4 | ratio |",
             "|---|---|---|---|"]
    for label, _, _ in CASES:
        if label in data:
            sm = data[label]["summary"]
            lines.append(f"| {label} ({data[label]['seeds']}) | {sm['one']:.2g} | "
                         f"{sm['four']:.2g} | {sm['ratio']:.2f} |")
    return lines


def main():
    if "--ceiling" in sys.argv:
        sys.argv.remove("--ceiling")
        study_main("models-ceiling", CASES, run_ceiling, summary_ceiling, table_ceiling)
        return
    study_main("models-interval", CASES, run_case, summary, table)


if __name__ == "__main__":
    main()
