#!/usr/bin/env python3
"""Two runs of the large-n benchmark (benches/large_n.py) side by side: per s and family,
the geometric mean of the default's ratio to scrambled Sobol' before and after, and the
families that got worse beyond the noise.

    python3 benches/large_n_compare.py --before 155be1e:results/large-n/large_n.json \\
        --after results/large-n/large_n.json [--md OUT.md]

--before and --after take a file or REV:PATH (read with `git show`).

Noise. The Sobol' reference is the same 16 scrambles (SciPy's seeds 0–15) on the same
instances in both runs, so with the same SciPy it is the same numbers (the script checks
and prints the largest relative difference): it cancels from the before/after quotient,
which is then the default's RMS after over its RMS before. What is left is which 16
instances were drawn: on fixed integrands a deterministic rule's error is one draw per
instance (and its seeds need not differ: with every shift tried, seeds 1–3 give the same
set in some cells). So the quotient is bootstrapped over the instances,
paired (the same resampled instances before and after, each cell resampled on its own),
2 000 times; SE is the standard deviation of the log of the per-s geometric mean (or of a
cell's quotient). To it is added, from s = 2 on, the spread of the choice of shift itself:
on 28 cells (s = 5–50, n = 512–16 384) five settings of the shift's corner choice (8
shifts, the best alone, 4, 16, rates 0.5 and 1 only), none better than another over the
cells, moved a cell's log ratio by a standard deviation of SHIFT_SD (median over the
cells); before and after are each one such draw, so 2·SHIFT_SD² per cell, divided by k²
summed over the k cells of a geometric mean. A family is flagged worse at an s when
log(after/before) > 2 SE, a cell when its own quotient is.
"""

import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from anchors import FAMILIES  # noqa: E402

SHORT = ["osc", "prod", "corner", "gauss", "cont", "disc"]
SMOOTH = [0, 1, 2, 3]
Z = 2.0
SHIFT_SD = np.array([0.19, 0.21, 0.29, 0.15, 0.17, 0.52])


def load(spec):
    if os.path.exists(spec):
        with open(spec) as fh:
            return json.load(fh)
    rev, path = spec.split(":", 1)
    out = subprocess.run(["git", "show", f"{rev}:{path}"], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out)


def mean_squares(cell):
    """families × instances: the default's squared relative error, mean over its seeds."""
    d = cell["methods"]["default"]
    count = cell.get("instances", 16)
    e = np.asarray(d["errors"]).reshape(len(d["errors"]), len(FAMILIES), count)
    return (e ** 2).mean(axis=0)


def same_sets(cell):
    e = np.asarray(cell["methods"]["default"]["errors"])
    return bool(np.all(e == e[0]))


def fmt(v):
    if v is None:
        return "—"
    return f"{v:.2f}" if v >= 0.01 else f"{v:.1e}"


def compare(before, after, boots=2000):
    b_cells, a_cells = before["cells"], after["cells"]
    common = sorted((k for k in a_cells if k in b_cells
                     and "default" in a_cells[k]["methods"]
                     and "default" in b_cells[k]["methods"]),
                    key=lambda k: tuple(map(int, k.split(":"))))
    sob_diff = max((abs(x / y - 1.0) for k in common
                    for x, y in zip(a_cells[k]["methods"]["sobol"]["rms"],
                                    b_cells[k]["methods"]["sobol"]["rms"])), default=0.0)
    rng = np.random.default_rng(20261128)
    by_s = {}
    for k in common:
        by_s.setdefault(int(k.split(":")[0]), []).append(k)
    rows, flags, cell_flags = [], [], []
    for s, keys in sorted(by_s.items()):
        lb = np.array([np.log(b_cells[k]["methods"]["default"]["ratio"]) for k in keys])
        la = np.array([np.log(a_cells[k]["methods"]["default"]["ratio"]) for k in keys])
        # cells × boots × families: the log quotient on resampled instances
        logq = []
        for k in keys:
            mb, ma = mean_squares(b_cells[k]), mean_squares(a_cells[k])
            idx = rng.integers(0, mb.shape[1], (boots, mb.shape[1]))
            logq.append(0.5 * np.log(ma[:, idx].sum(axis=2) / mb[:, idx].sum(axis=2)).T)
        logq = np.array(logq)
        shift_var = 2.0 * SHIFT_SD ** 2 if s >= 2 else 0.0 * SHIFT_SD
        cell_se = np.sqrt(logq.std(axis=1) ** 2 + shift_var)
        se = np.sqrt(logq.mean(axis=0).std(axis=0) ** 2 + shift_var / len(keys))
        d = (la - lb).mean(axis=0)
        gb, ga = np.exp(lb.mean(axis=0)), np.exp(la.mean(axis=0))
        rows.append((s, len(keys), gb, ga, d, se))
        for f in range(len(FAMILIES)):
            if d[f] > Z * se[f]:
                flags.append((s, f, gb[f], ga[f], math.exp(d[f]), math.exp(Z * se[f])))
            for i, k in enumerate(keys):
                step = la[i, f] - lb[i, f]
                if step > Z * cell_se[i, f]:
                    cell_flags.append((k, f, math.exp(lb[i, f]), math.exp(la[i, f]),
                                       math.exp(step), math.exp(Z * cell_se[i, f])))
    return common, sob_diff, rows, flags, cell_flags


def overall(data, keys, min_s=5):
    ks = [k for k in keys if int(k.split(":")[0]) >= min_s]
    la = np.array([np.log(data["cells"][k]["methods"]["default"]["ratio"]) for k in ks])
    return np.exp(la.mean(axis=0)), len(ks)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", default="155be1e:results/large-n/large_n.json")
    ap.add_argument("--after", default="results/large-n/large_n.json")
    ap.add_argument("--md", help="also write the tables here")
    a = ap.parse_args()
    before, after = load(a.before), load(a.after)
    common, sob_diff, rows, flags, cell_flags = compare(before, after)
    same = sum(same_sets(c) for c in after["cells"].values() if "default" in c["methods"])
    out = [f"Before: `{a.before}`; after: `{a.after}`; {len(common)} cells in both "
           f"(after has {len(after['cells'])}, before {len(before['cells'])}).", "",
           f"Scrambled Sobol' reference: largest relative difference of its RMS between the "
           f"runs {sob_diff:.1e} (the same scrambles on the same instances). Cells of the after "
           f"run whose three seeds gave the same errors: {same} of {len(after['cells'])}.",
           "",
           "Geometric mean of the default's ratio to scrambled Sobol' over the cells common "
           "to both runs, before → after; ×: after/before; ±: 2 SE of that quotient "
           "(bootstrap over the instances and the spread of the shift's choice, module "
           "documentation). **Bold**: worse beyond the noise.", "",
           "| s | cells | " + " | ".join(SHORT) + " |",
           "|---|---|" + "---|" * len(SHORT)]
    for s, kk, gb, ga, d, se in rows:
        cells = []
        for f in range(len(FAMILIES)):
            text = f"{fmt(gb[f])} → {fmt(ga[f])} (×{math.exp(d[f]):.2f} ±{math.exp(Z * se[f]):.2f})"
            cells.append(f"**{text}**" if d[f] > Z * se[f] else text)
        out.append(f"| {s} | {kk} | " + " | ".join(cells) + " |")
    out.append("")
    gb, kb = overall(before, common)
    ga, ka = overall(after, common)
    gall, kall = overall(after, list(after["cells"]))
    out += [f"Over the common cells with s ≥ 5 ({kb}): before "
            + " ".join(fmt(v) for v in gb) + "; after " + " ".join(fmt(v) for v in ga)
            + f". Over all {kall} cells with s ≥ 5 of the after run: "
            + " ".join(fmt(v) for v in gall) + ".", ""]
    if flags:
        out += ["Families worse beyond the noise (s, family: before → after, ×, 2 SE):", ""]
        out += [f"- s = {s}, {FAMILIES[f]}: {fmt(b)} → {fmt(x)} (×{q:.2f} > ×{lim:.2f})"
                for s, f, b, x, q, lim in flags]
    else:
        out += ["No family worse beyond the noise at any s."]
    out.append("")
    smooth_cells = [(k, f, b, x, q, lim) for k, f, b, x, q, lim in cell_flags]
    if smooth_cells:
        out += ["Cells worse beyond their own noise (cell, family: before → after):", ""]
        out += [f"- ({k.replace(':', ', ')}) {FAMILIES[f]}: {fmt(b)} → {fmt(x)} "
                f"(×{q:.2f} > ×{lim:.2f})" for k, f, b, x, q, lim in smooth_cells]
        out.append("")
    text = "\n".join(out) + "\n"
    print(text)
    if a.md:
        with open(a.md, "w") as fh:
            fh.write(text)


if __name__ == "__main__":
    main()
