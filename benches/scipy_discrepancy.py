#!/usr/bin/env python3
"""Side by side: SciPy's `qmc.discrepancy` and stillpoint on the same points.

Times the squared centred L2 discrepancy (SciPy's 'CD', which SciPy returns squared) and
the star L2 discrepancy (SciPy's 'L2-star', which SciPy returns as a root) with two
threads on both sides (SciPy's workers=2, RAYON_NUM_THREADS=2), for n = 1500 and 10 000
and s = 2, 6 and 20, prints the median times, their ratios, and checks that the values
agree. SciPy's 'MD' is the mixture discrepancy, not the modified L2 of the paper, so it is
not compared there.

Our side runs `stillpoint --threads 2 bench --points FILE` (see src/bench.rs), which
times only the two
discrepancies on the file's points.

Then the whole of `stillpoint --threads 2 eval FILE` (a process: reading the file, the
five discrepancies, the two minimum distances and U_{q,p} in one pass over the pairs, the
projections' L∞ star discrepancy) is timed against SciPy's CD + L2-star (workers=2)
together on the same points, at each size of --eval-sizes (default n = 10 000, s = 20;
n = 2000, s = 5; n = 10 000, s = 5; n = 1500, s = 20 with --quick), and SciPy's 'MD'
against our mixture discrepancy squared.

Usage:
    cargo build --release
    python3 benches/scipy_discrepancy.py [--stillpoint target/release/stillpoint]
        [--quick] [--reps 3] [--eval-only] [--eval-sizes 10000x20,2000x5,10000x5]

Skipped, with exit status 0 and a message, when NumPy or SciPy is not installed
(`pip install scipy` installs both).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
import warnings


def main() -> int:
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stillpoint", default=os.path.join(root, "target", "release", "stillpoint"),
                    help="the stillpoint binary (default: target/release/stillpoint)")
    ap.add_argument("--reps", type=int, default=3, help="runs per median (default 3)")
    ap.add_argument("--quick", action="store_true", help="n = 1500 only")
    ap.add_argument("--eval-only", action="store_true",
                    help="only the eval row (skip the table of the two discrepancies)")
    ap.add_argument("--eval-sizes", default=None,
                    help="n x s of the eval rows, comma-separated "
                         "(default 10000x20,2000x5,10000x5; 1500x20 with --quick)")
    args = ap.parse_args()
    sizes = args.eval_sizes or ("1500x20" if args.quick else "10000x20,2000x5,10000x5")
    eval_sizes = [tuple(int(v) for v in size.split("x")) for size in sizes.split(",")]

    try:
        import numpy as np
        from scipy.stats import qmc
        import scipy
    except ImportError as e:
        print(f"SKIPPED: SciPy is not installed ({e}); `pip install scipy` to run this comparison.")
        return 0
    if not os.access(args.stillpoint, os.X_OK):
        print(f"error: {args.stillpoint} is not an executable; build it with `cargo build --release`"
              " or pass --stillpoint", file=sys.stderr)
        return 2

    print(f"SciPy {scipy.__version__}, NumPy {np.__version__}; 2 threads on both sides; "
          f"medians of {args.reps} runs\n")
    ok = True
    ns = [] if args.eval_only else [1500] if args.quick else [1500, 10_000]
    if ns:
        print("| n | s | SciPy CD s | ours CD s | CD speed-up | SciPy L2-star s "
              "| ours L2-star s | L2-star speed-up | CD² diff / C_s | L2-star² diff / C_s |")
        print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for n in ns:
            for s in (2, 6, 20):
                # Scrambled Sobol' (n is not a power of 2, which only matters for its
                # balance, not here).
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    x = qmc.Sobol(d=s, scramble=True, seed=12345).random(n)
                path = os.path.join(tmp, f"points_{n}_{s}.npy")
                np.save(path, x.astype(np.float64))

                def scipy_time(method):
                    times, value = [], None
                    for _ in range(args.reps):
                        t0 = time.perf_counter()
                        value = qmc.discrepancy(x, method=method, workers=2)
                        times.append(time.perf_counter() - t0)
                    return statistics.median(times), value

                t_cd, v_cd = scipy_time("CD")
                t_l2, v_l2 = scipy_time("L2-star")

                out = subprocess.run([args.stillpoint, "--threads", "2", "bench",
                                      "--points", path, "--reps", str(args.reps)],
                                     check=True, capture_output=True, text=True).stdout
                ours = json.loads(out.strip().splitlines()[-1])
                # SciPy: CD squared, L2-star a root; ours: the same conventions. The squares
                # are differences of terms of size C_s = (13/12)^s and (1/3)^s that cancel
                # to a small D², so they are compared relative to C_s; the pair term sums
                # n² products in different orders on the two sides (rounding ~1e-12 at
                # n = 10 000).
                d_cd = abs(ours["centered_l2_squared"] - v_cd) / (13 / 12) ** s
                d_l2 = abs(ours["star_l2"] ** 2 - v_l2 ** 2) / (1 / 3) ** s
                ok &= d_cd < 1e-11 and d_l2 < 1e-11
                print(f"| {n} | {s} | {t_cd:.4f} | {ours['centered_seconds']:.4f} "
                      f"| {t_cd / ours['centered_seconds']:.1f}× | {t_l2:.4f} "
                      f"| {ours['star_seconds']:.4f} | {t_l2 / ours['star_seconds']:.1f}× "
                      f"| {d_cd:.1e} | {d_l2:.1e} |", flush=True)
        print("\n`stillpoint --threads 2 eval --json FILE` (every figure, one process) against "
              "SciPy's CD + L2-star (workers=2) on the same points; each repetition runs SciPy "
              "CD, eval, SciPy L2-star in turn, the speed-up is the median of the "
              "repetitions' ratios:\n")
        print("| n | s | SciPy CD s | SciPy L2-star s | SciPy CD + L2-star s | ours eval s "
              "| eval speed-up (range) | SciPy MD s (one run) | MD² diff / (19/12)^s |")
        print("|---|---|---|---|---|---|---|---|---|")
        for n, s in eval_sizes:
            ok &= eval_row(args, np, qmc, tmp, n, s)
    print("\nvalues agree (squares within 1e-11 of the constant term C_s)" if ok
          else "\nVALUES DISAGREE (a square differs by 1e-11·C_s or more)")
    return 0 if ok else 1


def eval_row(args, np, qmc, tmp, n, s):
    """Times `stillpoint --threads 2 eval FILE` (the whole process) against SciPy's CD and
    L2-star together, and prints SciPy's 'MD' beside our mixture discrepancy."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        x = qmc.Sobol(d=s, scramble=True, seed=12345).random(n)
    path = os.path.join(tmp, f"eval_{n}_{s}.npy")
    np.save(path, x.astype(np.float64))

    def timed(f):
        t0 = time.perf_counter()
        value = f()
        return time.perf_counter() - t0, value

    # Each repetition runs the three in turn, so that a change of the shared host's load
    # between repetitions hits both sides alike; the ratio is the median of the
    # repetitions' ratios.
    cd, ev, l2, ratios = [], [], [], []
    for _ in range(args.reps):
        cd.append(timed(lambda: qmc.discrepancy(x, method="CD", workers=2))[0])
        t, out = timed(lambda: subprocess.run(
            [args.stillpoint, "--threads", "2", "eval", "--json", path],
            check=True, capture_output=True, text=True).stdout)
        ev.append(t)
        l2.append(timed(lambda: qmc.discrepancy(x, method="L2-star", workers=2))[0])
        ratios.append((cd[-1] + l2[-1]) / ev[-1])
    t_cd, t_eval, t_l2 = (statistics.median(v) for v in (cd, ev, l2))
    t_md, v_md = timed(lambda: qmc.discrepancy(x, method="MD", workers=2))
    ours = json.loads(out)
    d_md = abs(ours["mixture"] ** 2 - v_md) / (19 / 12) ** s
    print(f"| {n} | {s} | {t_cd:.4f} | {t_l2:.4f} | {t_cd + t_l2:.4f} | {t_eval:.4f} "
          f"| {statistics.median(ratios):.1f}× ({min(ratios):.1f}–{max(ratios):.1f}) "
          f"| {t_md:.4f} | {d_md:.1e} |", flush=True)
    return d_md < 1e-11


if __name__ == "__main__":
    sys.exit(main())
