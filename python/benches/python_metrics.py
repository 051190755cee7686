#!/usr/bin/env python3
"""The Python package against SciPy: discrepancies and drawing points.

Times, as medians of --reps runs:

- ``stillpoint.discrepancy(x, 'centered')`` and ``'l2star'`` against
  ``scipy.stats.qmc.discrepancy(x, method='CD' / 'L2-star', workers=2)`` at n = 10 000,
  s = 20 (ours on the rayon pool, RAYON_NUM_THREADS=2 unless set), and
  ``stillpoint.metrics(x)`` (every figure of ``stillpoint eval --json``);
- ``stillpoint.Engine(d).random(n)`` after its first (cached) call against
  ``scipy.stats.qmc.Sobol(d).random(n)``, and that first call itself.

Prints a Markdown table with the ratios, and checks that the values agree (CD and
L2-star squared, relative to the size of the closed form's terms).

Usage (with the package installed, e.g. by ``bash test.sh``):
    target/py-venv/bin/python python/benches/python_metrics.py [--quick] [--reps 3]
"""

import argparse
import os
import platform
import statistics
import sys
import time

os.environ.setdefault("RAYON_NUM_THREADS", "2")

import numpy as np  # noqa: E402

try:
    import scipy  # noqa: E402
    from scipy.stats import qmc  # noqa: E402
except ImportError as e:  # pragma: no cover
    print(f"SKIPPED: SciPy is not installed ({e})")
    sys.exit(0)

import stillpoint  # noqa: E402


def median_time(f, reps):
    times = []
    value = None
    for _ in range(reps):
        t = time.perf_counter()
        value = f()
        times.append(time.perf_counter() - t)
    return statistics.median(times), value


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=3, help="runs per median (default 3)")
    ap.add_argument("--quick", action="store_true", help="n = 2000 for the discrepancies")
    ap.add_argument("--n", type=int, default=10_000, help="points for the discrepancies")
    ap.add_argument("--s", type=int, default=20, help="dimension for the discrepancies")
    ap.add_argument("--engine-n", type=int, default=1024, help="points per engine draw")
    ap.add_argument("--engine-d", type=int, default=4, help="dimension of the engines")
    args = ap.parse_args()
    n = 2000 if args.quick else args.n
    s = args.s

    print(
        f"stillpoint {stillpoint.__version__}, SciPy {scipy.__version__}, NumPy "
        f"{np.__version__}, Python {platform.python_version()}; {os.cpu_count()} cores, "
        f"RAYON_NUM_THREADS={os.environ['RAYON_NUM_THREADS']}, SciPy workers=2; "
        f"medians of {args.reps} runs\n"
    )
    x = np.random.default_rng(0).random((n, s))

    rows = []
    t_cd, cd = median_time(lambda: stillpoint.discrepancy(x, "centered"), args.reps)
    t_cd_sp, cd_sp = median_time(lambda: qmc.discrepancy(x, method="CD", workers=2), args.reps)
    rows.append((f"centred L2, n = {n}, s = {s}", t_cd, "qmc.discrepancy(method='CD', workers=2)", t_cd_sp))
    t_l2, l2 = median_time(lambda: stillpoint.discrepancy(x, "l2star"), args.reps)
    t_l2_sp, l2_sp = median_time(
        lambda: qmc.discrepancy(x, method="L2-star", workers=2), args.reps
    )
    rows.append((f"star L2, n = {n}, s = {s}", t_l2, "qmc.discrepancy(method='L2-star', workers=2)", t_l2_sp))
    t_m, m = median_time(lambda: stillpoint.metrics(x), args.reps)
    rows.append((
        f"metrics (every eval --json figure), n = {n}, s = {s}",
        t_m,
        "CD + L2-star above, together (metrics also computes MD, WD, U_{q,p}, distances)",
        t_cd_sp + t_l2_sp,
    ))

    en, ed = args.engine_n, args.engine_d
    t = time.perf_counter()
    stillpoint.Engine(ed, seed=0).random(en)
    t_first = time.perf_counter() - t
    engine = stillpoint.Engine(ed, seed=1)
    t_draw, _ = median_time(lambda: engine.random(en), max(args.reps, 5))
    t_sobol, _ = median_time(lambda: qmc.Sobol(ed, seed=1).random(en), max(args.reps, 5))
    sobol = qmc.Sobol(ed, seed=1)
    t_sobol_next, _ = median_time(lambda: sobol.random(en), max(args.reps, 5))
    label = f"Engine({ed}).random({en}), cached set"
    rows.append((label, t_draw, f"qmc.Sobol({ed}, seed=1).random({en}) (a new scramble)", t_sobol))
    rows.append((label, t_draw, f"the next {en} points of one qmc.Sobol({ed})", t_sobol_next))

    print("| ours | time | SciPy | time | SciPy / ours |")
    print("|---|---|---|---|---|")
    for name, ours, theirs_name, theirs in rows:
        print(f"| {name} | {ours:.4g} s | {theirs_name} | {theirs:.4g} s | {theirs / ours:.1f}× |")
    print(
        f"\nfirst Engine({ed}).random({en}) (the optimised set, computed once per process): "
        f"{t_first:.2f} s"
    )

    # The values agree (squares, relative to the size of the closed form's terms).
    cd_scale, l2_scale = (13 / 12) ** s, (1 / 3) ** s
    print(
        f"CD² difference / (13/12)^s = {abs(cd**2 - cd_sp) / cd_scale:.1e}; "
        f"L2-star² difference / (1/3)^s = {abs(l2**2 - l2_sp**2) / l2_scale:.1e}; "
        f"metrics agree with discrepancy(): {m['centered_l2'] == cd and m['star_l2'] == l2}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
