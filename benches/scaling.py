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


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default="target/release/stillpoint")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--max-n", type=int, default=None, help="leave out larger sizes")
    ap.add_argument("--out", default="results/scaling")
    args = ap.parse_args()
    lines = ["| n | s | seconds | ratio to previous | D_MD start | D_MD result | descent |",
             "|---|---|---|---|---|---|---|"]
    with tempfile.TemporaryDirectory() as tmp:
        for s in (5, 10):
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
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "scaling.md"), "w") as f:
        f.write("# Cost against size (`" + " ".join(
            ["python3 benches/scaling.py"] + (["--quick"] if args.quick else [])) +
            "`, 2 cores)\n\n" + "\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
