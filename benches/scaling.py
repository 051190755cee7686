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

With --versus-sobol (cells NxS, by default 100000x20, 200000x50 and 1000000x50) it times
`generate -q` against `baseline sobol` of the same size side by side instead, each run
three times (median), with the peak memory of each (the children's maximum resident
set, read from /usr/bin/time when it is there, from getrusage otherwise), and prints the
time ratio and each peak's ratio to the output's n·s·8 bytes; it writes
results/scaling/versus-sobol.md a section with the command, commit, machine and load
average (the file's earlier sections are kept).

    python3 benches/scaling.py --bin target/release/stillpoint --versus-sobol

Above 50 000 points the report's discrepancies are estimates that cannot resolve an even
set, so for the sizes of --check (default 100000x10) the script computes D_MD, D_L2* and
CD exactly with the Python package (run it with the virtualenv that has `stillpoint`,
e.g. target/py-venv/bin/python) for the result and for the stratified scrambled Sobol'
set it started from, rebuilt from the seed the report names (the same construction:
each coordinate's value kept where it lies in the cell of its rank, the cell's midpoint
otherwise), and prints their ratios.

With --cost it times instead every pipeline on a grid of cells (s ≤ 50, n ≤ 10^6: the
small-n descent, the default lattice with its exact and its estimated report, each
--randomize, design spaces, the paper's pipeline, space-filling, regions, nested sets,
baselines) as processor time (user + sys of the child) with RAYON_NUM_THREADS=1, beside
the library's run-time estimate for the same request (`stillpoint._core.estimate`, so
run it with the virtualenv that has the package), and prints their ratio; it writes
results/scaling/cost.md with the command, commit, machine and load average.

    target/py-venv/bin/python benches/scaling.py --bin target/release/stillpoint --cost
"""

import argparse
import json
import os
import platform
import resource
import statistics
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


VERSUS_CELLS = "100000x20,200000x50,1000000x50"


def timed(cmd):
    """Wall seconds and peak resident bytes of one run of `cmd` (output discarded)."""
    gnu_time = "/usr/bin/time"
    if os.path.exists(gnu_time):
        with tempfile.NamedTemporaryFile("r", suffix=".rss") as rss:
            t0 = time.perf_counter()
            subprocess.run([gnu_time, "-f", "%M", "-o", rss.name] + cmd, check=True,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            seconds = time.perf_counter() - t0
            return seconds, int(rss.read().split()[-1]) * 1024
    # ru_maxrss of the children is the largest of any child so far: run each in a
    # process of its own so that the value is this run's.
    code = ("import resource, subprocess, sys, time; t = time.perf_counter(); "
            "subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL, "
            "stderr=subprocess.DEVNULL); print(time.perf_counter() - t, "
            "resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
    out = subprocess.run(["python3", "-c", code] + cmd, check=True, capture_output=True,
                         text=True).stdout.split()
    return float(out[0]), int(out[1]) * 1024


def machine():
    cores = os.cpu_count()
    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            model = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{model}, {cores} cores, {platform.system()} {platform.release()}"


def commit():
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], check=True,
                              capture_output=True, text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def versus_sobol(binary, cells, runs, out_dir):
    """`generate -q` against `baseline sobol` of the same size, side by side."""
    header = ["| n × s | generate -q (s) | baseline sobol (s) | time ratio | generate peak (MB) "
              "| sobol peak (MB) | output n·s·8 (MB) | generate peak / output "
              "| sobol peak / output |",
              "|---|---|---|---|---|---|---|---|---|"]
    lines = list(header)
    for line in header:
        print(line, flush=True)
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        for cell in cells:
            n, s = (int(v) for v in cell.split("x"))
            out = os.path.join(tmp, "x.npy")
            cmds = {
                "generate": [binary, "generate", "-n", str(n), "-s", str(s), "-q", "-o", out],
                "sobol": [binary, "baseline", "sobol", "-n", str(n), "-s", str(s), "-o", out],
            }
            got = {k: [] for k in cmds}
            for _ in range(runs):
                # Alternating, so that a change of the machine's load falls on both.
                for k, cmd in cmds.items():
                    got[k].append(timed(cmd))
            med = {k: (statistics.median(v[0] for v in got[k]), max(v[1] for v in got[k]))
                   for k in got}
            output = n * s * 8
            mb = 1e6
            line = (f"| {n} × {s} | {med['generate'][0]:.2f} | {med['sobol'][0]:.2f} | "
                    f"{med['generate'][0] / med['sobol'][0]:.2f} | "
                    f"{med['generate'][1] / mb:.0f} | {med['sobol'][1] / mb:.0f} | "
                    f"{output / mb:.1f} | {med['generate'][1] / output:.2f} | "
                    f"{med['sobol'][1] / output:.2f} |")
            lines.append(line)
            print(line, flush=True)
    load_after = os.getloadavg()[0]
    os.makedirs(out_dir, exist_ok=True)
    command = "python3 benches/scaling.py --versus-sobol" + (
        f" {','.join(cells)}" if ",".join(cells) != VERSUS_CELLS else "")
    section = (f"## Commit {commit()} ({time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())})"
               f"\n\n`{command} --runs {runs}`; {machine()}; median of {runs} runs each, "
               "alternating; peak = largest maximum resident set of the runs; output = the "
               f"points' n·s·8 bytes; load average (1 min) {load_before:.1f} before, "
               f"{load_after:.1f} after.\n\n" + "\n".join(lines) + "\n")
    # Each run adds its section and keeps the earlier ones (before the fingerprint, which
    # stays last).
    path = os.path.join(out_dir, "versus-sobol.md")
    try:
        with open(path) as f:
            old = f.read()
    except FileNotFoundError:
        old = "# The default run against writing a Sobol' set (`benches/scaling.py --versus-sobol`)\n"
    head, mark, tail = old.partition("\n## Fingerprints")
    with open(path, "w") as f:
        f.write(head.rstrip("\n") + "\n\n" + section + (mark + tail if mark else ""))


# (pipeline, n, s, the Python keywords, the command line's arguments): --cost's grid.
COST_CELLS = (
    [("descent", n, s, {}, []) for n, s in
     [(64, 2), (256, 2), (256, 5), (400, 10), (128, 20), (200, 50)]]
    + [("lattice", n, s, {}, []) for n, s in
       [(1000, 5), (4096, 10), (10000, 20), (20000, 50), (30000, 20), (100000, 10),
        (100000, 20), (200000, 50), (1000000, 10), (1000000, 50)]]
    + [(f"randomize {r}", n, s, {"randomize": r}, ["--randomize", r]) for r, n, s in
       [("shift", 10000, 20), ("shift", 100000, 50), ("cells", 4096, 10),
        ("cells", 100000, 20), ("tent", 1000, 20), ("tent", 4096, 50)]]
    + [("space", n, k, {"space": [f"x{i}={law}" for i in range(k)]},
        [a for i in range(k) for a in ("--var", f"x{i}={law}")]) for n, k, law in
       [(10000, 5, "normal(0,1)"), (100000, 20, "uniform(0,1)")]]
    + [("paper", n, s, {"method": "paper"}, ["--method", "paper"]) for n, s in
       [(256, 2), (256, 5), (512, 5)]]
    + [("space-filling", 256, 2, {"goal": "space-filling"}, ["--goal", "space-filling"]),
       ("region", 100, 2, {"shape": "ball:1"}, ["--shape", "ball:1"]),
       ("nested", 2048, 5, {"nested": [1024, 2048]}, ["--nested", "1024,2048"]),
       ("baseline sobol", 200000, 10, {"method": "sobol"}, ["--method", "sobol"]),
       ("baseline lhs-maximin", 4000, 5, {"method": "lhs-maximin"},
        ["--method", "lhs-maximin"])]
)


def cpu_run(cmd, env):
    """Processor seconds (user + sys) of one run of `cmd` in a child process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def cost(binary, limit, out_dir):
    """Every pipeline's processor time against the library's estimate. The measured
    seconds are kept in out_dir/cost.json and reused (the runs are deterministic), so
    that a refitted estimate is compared without running the grid again; delete the file
    to measure again."""
    os.environ["RAYON_NUM_THREADS"] = "1"
    try:
        from stillpoint import _core
    except ImportError:  # measure only; the estimates come with the package
        _core = None
    env = dict(os.environ)
    store = os.path.join(out_dir, "cost.json")
    measured = {}
    if os.path.exists(store):
        with open(store) as f:
            measured = json.load(f)
    load = os.getloadavg()
    lines = ["| pipeline | n | s | processor s | estimate s | estimate / measured |",
             "|---|---|---|---|---|---|"]
    for line in lines:
        print(line, flush=True)
    ratios = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, n, s, kwargs, flags in COST_CELLS:
            dims = {} if "space" in kwargs else {"d": s}
            est = _core.estimate(n=n, **dims, **kwargs) if _core else None
            if est is not None and est > limit:
                line = f"| {name} | {n} | {s} | (not run) | {est:.3g} | |"
            else:
                cmd = [binary, "generate"] + ([] if "nested" in kwargs else ["-n", str(n)]) + (
                    [] if "space" in kwargs else ["-s", str(s)]) + flags + [
                    "-q", "-o", os.path.join(tmp, "x.npy")]
                key = " ".join([name, str(n), str(s)])
                if key not in measured:
                    measured[key] = cpu_run(cmd, env)
                    os.makedirs(out_dir, exist_ok=True)
                    with open(store, "w") as f:
                        json.dump(measured, f, indent=1)
                seconds = measured[key]
                if est is None:
                    line = f"| {name} | {n} | {s} | {seconds:.3g} | | |"
                else:
                    ratios.append(est / seconds)
                    line = (f"| {name} | {n} | {s} | {seconds:.3g} | {est:.3g} | "
                            f"{est / seconds:.2f} |")
            lines.append(line)
            print(line, flush=True)
    summary = (f"{len(ratios)} cells run; estimate / measured from {min(ratios):.2f} to "
               f"{max(ratios):.2f}, geometric mean "
               f"{statistics.geometric_mean(ratios):.2f}" if ratios else "no cell run")
    print(summary, flush=True)
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "cost.md"), "w") as f:
        f.write("# Processor time of every pipeline against its estimate "
                "(`python benches/scaling.py --cost`)\n\n"
                f"Commit {commit()}; {machine()}; RAYON_NUM_THREADS=1, one run per cell, "
                "processor time (user + sys) of the child; load average before "
                f"{load[0]:.1f}, after {os.getloadavg()[0]:.1f}; cells whose estimate is "
                f"above {limit:g} s not run.\n\n" + "\n".join(lines) + f"\n\n{summary}.\n")


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
    ap.add_argument("--versus-sobol", nargs="?", const=VERSUS_CELLS, default=None,
                    metavar="NxS,...",
                    help="time `generate -q` against `baseline sobol` of the same sizes "
                         f"instead (default {VERSUS_CELLS})")
    ap.add_argument("--runs", type=int, default=3, help="runs per command for --versus-sobol")
    ap.add_argument("--cost", action="store_true",
                    help="time every pipeline's processor time against its estimate instead")
    ap.add_argument("--limit", type=float, default=120.0,
                    help="--cost: leave out cells estimated above this many seconds")
    args = ap.parse_args()
    if args.cost:
        cost(args.bin, args.limit, args.out)
        return
    if args.versus_sobol is not None:
        versus_sobol(args.bin, args.versus_sobol.split(","), args.runs, args.out)
        return
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
