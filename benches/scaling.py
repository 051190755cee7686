#!/usr/bin/env python3
"""Cost against size: the time of `stillpoint generate -n N -s S` (the default goal)
and the D_MD it reports, for N from 1 000 to 10^6, beside the stratified scrambled Sobol'
set the goal starts from (`--method sobol` stratified is not a baseline, so its D_MD is
the report's start column).

    python3 benches/scaling.py --bin target/release/stillpoint          # s = 5 and 10
    python3 benches/scaling.py --bin target/release/stillpoint --quick  # up to 20 000

Prints a Markdown table: n, s, seconds, the start's D_MD, the result's D_MD, the
descent's rounds and iterations or the reason it was skipped, and the ratio of each
time to the previous size's (the cost should grow smoothly: no step of one size to the
next multiplies it tenfold). Writes results/scaling/scaling.md.

Above 50 000 points the report's discrepancies are estimates that cannot resolve an even
set, so for the sizes of --check (default 100000x10) the script computes D_MD, D_L2* and
CD exactly with the Python package (run it with the virtualenv that has `stillpoint`,
e.g. target/py-venv/bin/python) for the result and for the stratified scrambled Sobol'
set it started from, rebuilt from the seed the report names (the same construction:
each coordinate's value kept where it lies in the cell of its rank, the cell's midpoint
otherwise), and prints their ratios.
"""

import argparse
import json
import os
import subprocess
import tempfile
import time

SIZES = [1000, 2000, 5000, 10000, 20000, 20001, 30000, 50000, 100000, 1000000]
QUICK = [1000, 2000, 5000, 10000, 20000, 20001]


def run(binary, n, s, out):
    t0 = time.perf_counter()
    p = subprocess.run(
        [binary, "generate", "-n", str(n), "-s", str(s), "-q", "--json", "-o", out],
        check=True, capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    return seconds, json.loads(p.stdout)


def descent_text(report):
    for d in report.get("stages", []):
        if d.get("stage") == "descent":
            if d.get("skipped"):
                return "skipped: " + d["skipped"]
            its = sum(r.get("lbfgs_iterations", 0) for r in d.get("rounds", []))
            return f"{len(d.get('rounds', []))} round(s), {its} L-BFGS iterations"
    return ""


def modified_l2(metrics):
    """D_MD as the report gives it: exact, or above the estimate's threshold `≈ value ± SE`
    (the standard errors come in the order star, modified, centred, wrap-around, mixture)."""
    if "estimate" not in metrics:
        return f"{metrics['modified_l2']}"
    return f"≈ {metrics['modified_l2']:.6f} ± {metrics['estimate']['standard_errors'][1]:.6f}"


def stratified_sobol(n, s, seed):
    """The stratified scrambled Sobol' start of a run, as the library makes it."""
    import numpy as np
    import stillpoint as sp
    x = sp.baseline("sobol", n, s, seed=seed)
    out = np.empty_like(x)
    for k in range(s):
        order = np.argsort(x[:, k], kind="stable")
        cells = np.empty(n, dtype=np.int64)
        cells[order] = np.arange(n)
        own = np.minimum(np.floor(x[:, k] * n), n - 1).astype(np.int64)
        out[:, k] = np.where((x[:, k] < 1.0) & (own == cells), x[:, k], (cells + 0.5) / n)
    return out


def start_seed(report):
    for d in report.get("stages", []):
        if d.get("stage") == "start":
            label = d["candidates"][d["kept"]]["label"]
            assert label.startswith("sobol("), label
            return int(label[len("sobol("):-1])
    raise ValueError("no start stage")


def check_below(binary, n, s, tmp):
    """Exact D_MD, D_L2*, CD of the result and of its stratified Sobol' start."""
    import numpy as np
    import stillpoint as sp
    out = os.path.join(tmp, "check.npy")
    seconds, rep = run(binary, n, s, out)
    start = stratified_sobol(n, s, start_seed(rep))
    result = np.load(out)
    row = {"n": n, "s": s, "seconds": seconds}
    for kind in ("md", "l2star", "cd"):
        row[kind] = (sp.discrepancy(start, kind), sp.discrepancy(result, kind))
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default="target/release/stillpoint")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--max-n", type=int, default=None, help="leave out larger sizes")
    ap.add_argument("--out", default="results/scaling")
    ap.add_argument("--check", default="100000x10",
                    help="sizes NxS whose exact discrepancies are compared with the start's "
                         "('' for none)")
    ap.add_argument("--no-table", action="store_true", help="only the --check sizes")
    args = ap.parse_args()
    lines = ["| n | s | seconds | ratio to previous | D_MD start | D_MD result | descent |",
             "|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as tmp:
        for s in () if args.no_table else (5, 10):
            last = None
            for n in (QUICK if args.quick else SIZES):
                if args.max_n and n > args.max_n:
                    continue
                seconds, rep = run(args.bin, n, s, os.path.join(tmp, "x.npy"))
                ratio = f"{seconds / last:.2f}" if last else ""
                last = seconds
                line = (f"| {n} | {s} | {seconds:.1f} | {ratio} | "
                        f"{modified_l2(rep['metrics_start'])} | "
                        f"{modified_l2(rep['metrics_result'])} | {descent_text(rep)} |")
                lines.append(line)
                print(line, flush=True)
        checks = ["", "| n | s | seconds | D_MD start / result | D_L2* start / result "
                  "| CD start / result | ratios (result / start) |", "|---|---|---|---|---|---|---|"]
        for size in filter(None, args.check.split(",")):
            n, s = (int(v) for v in size.split("x"))
            r = check_below(args.bin, n, s, tmp)
            ratios = ", ".join(f"{r[k][1] / r[k][0]:.5f}" for k in ("md", "l2star", "cd"))
            line = (f"| {n} | {s} | {r['seconds']:.1f} | "
                    + " | ".join(f"{r[k][0]:.7g} / {r[k][1]:.7g}" for k in ("md", "l2star", "cd"))
                    + f" | {ratios} |")
            checks.append(line)
            print(line, flush=True)
    os.makedirs(args.out, exist_ok=True)
    name = "below-start.md" if args.no_table else "scaling.md"
    with open(os.path.join(args.out, name), "w") as f:
        f.write("# Cost against size (`" + " ".join(
            ["python benches/scaling.py"] + (["--quick"] if args.quick else [])
            + (["--no-table"] if args.no_table else [])) +
            "`, 2 cores)\n\n" + "\n".join(lines + (checks if len(checks) > 3 else []))
            + "\n")


if __name__ == "__main__":
    main()
