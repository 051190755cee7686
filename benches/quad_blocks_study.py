"""Intervals from longer sequences under input laws, at a fixed number of evaluations:
what the replicates' cost in accuracy (benches/quad_models_interval.py --ceiling) gives
back when the estimate comes from fewer, longer scrambled Sobol' sequences and the
interval from consecutive blocks of each, and what it costs in coverage. A prototype on
SciPy's scrambled Sobol' (LMS + digital shift), not the package's rule.

Per model family of benches/quad.py whose laws are unbounded (quad's Sobol' cases) and
seed (a new instance, new scrambles), N evaluations in each layout:

- ``t4+round`` (quad's layout): 4 independent sequences of N/4, the mean of their means,
  Student t_3 on their spread, raised to the round change |Q_N − Q_{N/2}|;
- ``2seq a=1``: 2 independent sequences of N/2, the mean of all N; each cut into 4
  consecutive blocks of N/8 (each a scrambled net, an unbiased estimate; blocks of one
  net err against each other, so their spread overstates one block's error); the pooled
  block spread (6 degrees of freedom) scaled to N/2 by an error falling like 1/n
  (÷ 4), t_6, over √2 for the two sequences; raised to the round change and to the
  two sequences' difference |Q_a − Q_b|/2 (an independent measurement of the error);
- ``2seq a=est``: the same with the rate measured per run from the pooled spreads of
  blocks of N/8 and N/16 (2^α = their ratio, α held in [0.5, 1.5]); ``a=est≤1``: held
  in [0.5, 1] (never faster than 1/n); ``d×c``: the two sequences' half difference
  multiplied by c (2, 3) before it is compared (the independent check made stronger);
- ``1seq a=1``: one sequence of N, 4 blocks of N/4, t_3, ÷ 4^1, raised to the round
  change; ``1seq a=est≤1``: the rate from its blocks of N/4 and N/8, held in [0.5, 1].

Per case and interval: coverage at level 0.95 (±1.3 % at 300 seeds), the geometric mean
of the half-width over ``t4+round``'s, the RMSE of the relative error over quad's layout's.

    target/py-venv/bin/python benches/quad_blocks_study.py [--seeds 300] [--n 4096]
    target/py-venv/bin/python benches/quad_blocks_study.py --markdown

Writes results/quad/blocks-<N>.json and prints a Markdown table.
"""

import math
import os
import sys

import numpy as np
from scipy import stats

sys.path.insert(0, os.path.dirname(__file__))
import quad as bench  # noqa: E402
from quad_interval import study_main  # noqa: E402
from quad_models_interval import CASES as ALL_CASES  # noqa: E402

CASES = [c for c in ALL_CASES if c[1] != "uq morokoff-caflisch"]  # bounded laws: lattice
METHODS = ["t4+round", "2seq a=1", "2seq a=est", "2seq a=est≤1", "2seq a=est≤1 d×2",
           "2seq a=est≤1 d×3", "1seq a=1", "1seq a=est≤1"]


def t(df):
    return float(stats.t.ppf(0.975, df))


def blocks(y, b):
    """The means of b consecutive blocks of y."""
    return y.reshape(b, -1).mean(axis=1)


def pooled(seqs, b):
    """The pooled variance of b-block means over the sequences, and its degrees of freedom."""
    v = [np.var(blocks(y, b), ddof=1) for y in seqs]
    return float(np.mean(v)), len(seqs) * (b - 1)


def rate(v, v_half, top):
    """The rate α of an error falling like n^−α from the block variances at m and m/2
    points, held in [0.5, top] (1 when a variance is 0)."""
    if v <= 0 or v_half <= 0:
        return 1.0
    return min(top, max(0.5, 0.5 * math.log2(v_half / v)))


def run_case(family, s, n, seeds):
    from scipy.stats import qmc

    rows = []
    for seed in range(seeds):
        on_cube, _, _, truth = bench.model(family, s, seed)
        d = s[0] if isinstance(s, tuple) else s

        def seq(m, r):
            u = qmc.Sobol(d, scramble=True, seed=np.random.default_rng([seed, 48, r]))
            return np.asarray(on_cube(u.random(m)), dtype=float)

        out = {}
        # quad's layout
        y4 = [seq(n // 4, 10 + r) for r in range(4)]
        m4 = np.array([y.mean() for y in y4])
        h4 = np.array([y[: len(y) // 2].mean() for y in y4])
        q = m4.mean()
        hw = max(t(3) * np.std(m4, ddof=1) / 2, abs(q - h4.mean()))
        out["t4+round"] = (q, hw)
        # two sequences
        y2 = [seq(n // 2, 20 + r) for r in range(2)]
        qa, qb = (y.mean() for y in y2)
        q = (qa + qb) / 2
        half = np.mean([y[: len(y) // 2].mean() for y in y2])
        v8, df8 = pooled(y2, 4)
        v16, _ = pooled(y2, 8)
        for name, alpha, c in (("2seq a=1", 1.0, 1), ("2seq a=est", rate(v8, v16, 1.5), 1),
                               ("2seq a=est≤1", rate(v8, v16, 1.0), 1),
                               ("2seq a=est≤1 d×2", rate(v8, v16, 1.0), 2),
                               ("2seq a=est≤1 d×3", rate(v8, v16, 1.0), 3)):
            sd = math.sqrt(v8) / 4 ** alpha / math.sqrt(2)
            floor = max(abs(q - half), c * abs(qa - qb) / 2)
            out[name] = (q, max(t(df8) * sd, floor))
        # one sequence
        y1 = seq(n, 30)
        q = y1.mean()
        v4, _ = pooled([y1], 4)
        v8, _ = pooled([y1], 8)
        floor = abs(q - y1[: n // 2].mean())
        for name, alpha in (("1seq a=1", 1.0), ("1seq a=est≤1", rate(v4, v8, 1.0))):
            out[name] = (q, max(t(3) * math.sqrt(v4) / 4 ** alpha, floor))
        rows.append({k: [(e - truth) / abs(truth), h / abs(truth)] for k, (e, h) in out.items()})
    return rows


def summary(rows):
    base_hw = np.array([r["t4+round"][1] for r in rows])
    base_err = np.array([r["t4+round"][0] for r in rows])
    out = {}
    for m in METHODS:
        err = np.array([r[m][0] for r in rows])
        hw = np.array([r[m][1] for r in rows])
        out[m] = {"coverage": float(np.mean(np.abs(err) <= hw)),
                  "width": float(np.exp(np.mean(np.log(np.maximum(hw, 1e-300)
                                                       / np.maximum(base_hw, 1e-300))))),
                  "rmse": float(math.sqrt(np.mean(err ** 2) / np.mean(base_err ** 2)))}
    return out


def table(data, n):
    lines = [f"| family (N = {n}, seeds) | " + " | ".join(METHODS) + " |",
             "|---" * (len(METHODS) + 1) + "|"]
    for label, _, _ in CASES:
        if label in data:
            sm = data[label]["summary"]
            cells = [f"{sm[m]['coverage'] * 100:.1f} % ({sm[m]['width']:.2f}×, rmse "
                     f"{sm[m]['rmse']:.2f}×)" for m in METHODS]
            lines.append(f"| {label} ({data[label]['seeds']}) | " + " | ".join(cells) + " |")
    return lines


def main():
    study_main("blocks", CASES, run_case, summary, table)


if __name__ == "__main__":
    main()
