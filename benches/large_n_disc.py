#!/usr/bin/env python3
"""Why the discontinuous family moved at 65 536 and 10^5 points when the generating
vector's tie rule changed z_2: the two-dimensional projection (x1, x2) alone, which is
all the family's discontinuity sees, measured over many instances and many shifts.

Genz's discontinuous family is exp(a·x) on the box x1 <= u1, x2 <= u2 and 0 outside. In
the default's set at a given n the projection (x1, x2) is the same at every s (the
vector and the first two shift numerators are chosen before any later coordinate), so
the five cells of the large-n grid at one n are one projection measured five times.

For each n and each z_2 (before the tie rule: the smallest of the tied candidates; after:
the first-order criterion's choice among them) this measures, on the s = 2 family (Σa =
4.3) and on the box alone (a = 0), the RMS relative error over --instances instances

* under the default's own shifts (seeds 1, 2, 3, as `stillpoint generate` chose them),
* under --shifts random odd shift numerators (q1, q2): the spread the shift's choice adds,

against scrambled Sobol' (--shifts scrambles, SciPy) on the same instances.

    target/bench-venv/bin/python benches/large_n_disc.py > results/large-n/disc_projection.txt

With --cells (as large_n.py's, e.g. 5:65536,10:100000) it measures instead the grid's own
cells with the grid's 16 instances (large_n.py's seed): per instance of the discontinuous
family, the box's area u1·u2, the default's RMS relative error over its three seeds and
scrambled Sobol''s over its 16 sets; then the cell's ratio with every instance, without
its smallest box, and the ratio's bootstrap interval over the instances.

    target/bench-venv/bin/python benches/large_n_disc.py --bin target/release/stillpoint \
        --cells 2:65536,5:65536,10:65536,20:65536,50:65536
"""

import argparse
import math
import os
import sys
import tempfile

import numpy as np
from scipy.stats import qmc

# (n, z2 before the tie rule, z2 after, the default's shift numerators (q1, q2) for
# seeds 1, 2, 3 after): from the sets' headers (`generate -n N -s 10 --seed K`).
CASES = [
    (65536, 2481, 19463, [(5525, 106475), (254253, 86291), (243229, 222115)]),
    (100000, 2489, 29107, [(8429, 42565), (387959, 22951), (371139, 43211)]),
]
SUM_A = 4.3


def lattice(n, z2, q):
    k = np.arange(n, dtype=np.int64)
    cols = []
    for z, qj in ((1, q[0]), (z2, q[1])):
        # y = frac(k z/n + q/(4n)) in quarters of 1/n, exactly; then the tent transform.
        t = (4 * ((k * z) % n) + qj) % (4 * n)
        y = t / (4.0 * n)
        cols.append(1.0 - np.abs(2.0 * y - 1.0))
    return np.stack(cols, axis=1)


def errors(x, inst):
    """Relative errors of the family (a, u) per instance on the set x (n × 2)."""
    out = np.empty(len(inst))
    n = len(x)
    for i, (a, u) in enumerate(inst):
        mask = (x[:, 0] <= u[0]) & (x[:, 1] <= u[1])
        q = np.exp(x[mask] @ a).sum() / n
        if np.all(a == 0):
            exact = u[0] * u[1]
        else:
            exact = np.prod(np.expm1(a * u) / a)
        out[i] = (q - exact) / exact
    return out


def rms(e):
    return math.sqrt(float(np.mean(np.square(e))))


def grid_cells(binary, cells, boot):
    """The grid's cells, instance by instance (module documentation)."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import large_n as grid  # noqa: E402

    disc = grid.FAMILIES.index("discontinuous")
    count = 16
    rng = np.random.default_rng(7)
    logs = {"all": [], "without": []}
    for s, n in grid.parse_cells(cells):
        inst, exact = grid.instances(s, count)
        pick = slice(disc * count, (disc + 1) * count)
        inst, exact = inst[pick], exact[pick]
        with tempfile.TemporaryDirectory() as tmp:
            paths, _, _ = grid.run_default(binary, n, s, grid.DEFAULT_SEEDS, tmp, 3600)
            own = np.array([grid.relative_errors(np.load(p), inst, exact) for p in paths])
        ref = np.array([grid.relative_errors(grid.sobol_set(s, n, r), inst, exact)
                        for r in range(grid.REPLICATES)])
        area = np.array([u[0] * u[1] if s > 1 else u[0] for (_, _, u) in inst])
        o2, r2 = (own ** 2).mean(axis=0), (ref ** 2).mean(axis=0)
        ratio = math.sqrt(o2.mean() / r2.mean())
        small = int(np.argmin(area))
        keep = np.arange(count) != small
        without = math.sqrt(o2[keep].mean() / r2[keep].mean())
        draws = [rng.integers(0, count, count) for _ in range(boot)]
        b = sorted(math.sqrt(o2[d].mean() / r2[d].mean()) for d in draws)
        lo, hi = b[int(0.025 * boot)], b[int(0.975 * boot) - 1]
        logs["all"].append(math.log(ratio))
        logs["without"].append(math.log(without))
        order = np.argsort(area)[:3]
        print(f"({s}, {n}): ratio {ratio:.2f} (95 % over the instances {lo:.2f}-{hi:.2f}); "
              f"without the smallest box (area {area[small]:.1e}) {without:.2f}; the three "
              "smallest boxes: " + ", ".join(
                  f"area {area[i]:.1e} default {math.sqrt(o2[i]):.1e} Sobol' "
                  f"{math.sqrt(r2[i]):.1e}" for i in order))
        sys.stdout.flush()
    for k, v in logs.items():
        print(f"geometric mean over the cells, {k}: {math.exp(np.mean(v)):.2f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--instances", type=int, default=400)
    ap.add_argument("--shifts", type=int, default=24)
    ap.add_argument("--seed", type=int, default=20261128)
    ap.add_argument("--bin", default="target/release/stillpoint")
    ap.add_argument("--cells", help="the grid's cells instead, \"s:n,s:n\"")
    ap.add_argument("--boot", type=int, default=2000)
    args = ap.parse_args()
    if args.cells:
        grid_cells(args.bin, args.cells, args.boot)
        return
    rng = np.random.default_rng(args.seed)
    fam, box = [], []
    for _ in range(args.instances):
        a = rng.uniform(0, 1, 2)
        a = a * SUM_A / a.sum()
        u = rng.uniform(0, 1, 2)
        fam.append((a, u))
        box.append((np.zeros(2), u))
    print(f"{args.instances} instances (seed {args.seed}), {args.shifts} random shifts / "
          "scrambles; RMS relative error, then as a ratio to scrambled Sobol''s RMS")
    for n, before, after, defaults in CASES:
        sob = {"family": [], "box": []}
        for r in range(args.shifts):
            x = qmc.Sobol(2, scramble=True, rng=np.random.default_rng(1000 + r)).random(n)
            sob["family"].append(errors(x, fam))
            sob["box"].append(errors(x, box))
        ref = {k: rms(np.concatenate(v)) for k, v in sob.items()}
        print(f"\nn = {n}: scrambled Sobol' family {ref['family']:.3e}, box {ref['box']:.3e}")
        srng = np.random.default_rng(args.seed + n)
        shifts = [tuple(2 * srng.integers(0, 2 * n, 2) + 1) for _ in range(args.shifts)]
        for name, z2 in (("before", before), ("after", after)):
            per = {"family": [], "box": []}
            for q in shifts:
                x = lattice(n, z2, q)
                per["family"].append(rms(errors(x, fam)) / ref["family"])
                per["box"].append(rms(errors(x, box)) / ref["box"])
            line = f"  z2 = {z2:>6} ({name}), random shifts: "
            for k in ("family", "box"):
                v = np.log(per[k])
                line += (f"{k} geometric mean {math.exp(v.mean()):.2f} (log sd {v.std(ddof=1):.2f},"
                         f" range {min(per[k]):.2f}-{max(per[k]):.2f}); ")
            print(line)
            if name == "after":
                for seed, q in enumerate(defaults, 1):
                    x = lattice(n, z2, q)
                    print(f"  z2 = {z2:>6} (after), seed {seed}'s shift {q}: family "
                          f"{rms(errors(x, fam)) / ref['family']:.2f}, box "
                          f"{rms(errors(x, box)) / ref['box']:.2f}")


if __name__ == "__main__":
    main()
