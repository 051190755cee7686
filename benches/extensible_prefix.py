"""Prefix quality of the extensible randomised lattice sequence.

At each power of two n = 2^6 ... 2^16, the first n points of the sequence (the embedded
lattice {j z / n}, z = stillpoint::sequences::ExtensibleLattice's generating vector,
shifted and tent-transformed) against the lattice made for that n alone
(`tent_lattice_generator(n, s)`, what `--randomize tent` randomises), on four smooth
Genz families (oscillatory, product peak, corner peak, Gaussian; benches/anchors.py's
parameters) at s = 2, 5, 10, 20, with 16 random instances per family and R random
shifts per instance. Per (family, s, n) the table gives the ratio of the root mean
square relative errors, sequence / single-n lattice (at most 1.2 is the aim).

The generating vectors come from `cargo run --release --example extensible_prefix`;
the rules are evaluated here in numpy (the Rust tests check that the sequence's 2^m
prefix is this lattice). Writes results/extensible-prefix/prefix.md and prefix.json. Beside the RMSE ratios, the
table gives the ratio of the two rules' criteria (the shift-averaged squared worst-case
error the construction minimises, `tent_criterion`, computed here independently) and, at
s = 2, the best any embedded lattice can do: every odd z_2 mod 2^14 is tried, and the
smallest, over z_2, of the largest criterion ratio over the levels 2^6..2^14 is printed
(a lower bound for every generating vector, since a generator's levels ≤ 2^14 depend
only on z_2 mod 2^14).

    python3 benches/extensible_prefix.py [--shifts 64] [--s 2,5,10,20] [--mmax 16]

Needs numpy and scipy.
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from anchors import genz_exact, genz_instances, genz_value  # noqa: E402

FAMILIES = ["oscillatory", "product peak", "corner peak", "gaussian"]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def generators(s, levels):
    out = subprocess.run(
        ["cargo", "run", "-q", "--release", "-p", "stillpoint", "--example",
         "extensible_prefix", "--", str(s), ",".join(map(str, levels))],
        cwd=ROOT, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def terms(n):
    """gamma (2 pi)^4 / 24 (-B4(r/n)), r < n: the criterion's factor minus one."""
    x = np.arange(n) / n
    return -0.05 * (2 * np.pi) ** 4 / 24 * (x ** 4 - 2 * x ** 3 + x ** 2 - 1 / 30)


def criterion(z, n):
    """The tent criterion, carried as prod(1 + t) - 1 per point (no rounding of 1 + t)."""
    t, j, q = terms(n), np.arange(n, dtype=np.int64), np.zeros(n)
    for zj in z:
        tj = t[(j * (int(zj) % n)) % n]
        q = q + tj + q * tj
    return q.mean()


def two_dimensional_bound(top=14, low=6):
    """min over z_2 of max over levels 2^low..2^top of criterion / best criterion."""
    n = 1 << top
    best = {}
    for m in range(low, top + 1):
        best[m] = min(criterion([1, c], 1 << m) for c in range(1, 1 << (m - 1), 2))
    worst = []
    for c in range(1, n // 2, 2):
        worst.append(max(criterion([1, c], 1 << m) / best[m] for m in range(low, top + 1)))
    return float(min(worst))


def rule(z, n, shift):
    """The lattice {frac(j z / n + shift)} tent-transformed, n x s."""
    j = np.arange(n, dtype=np.int64)[:, None]
    x = ((j * (np.asarray(z, dtype=np.int64) % n)) % n) / n + shift
    x -= np.floor(x)
    return 1.0 - np.abs(2.0 * x - 1.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--shifts", type=int, default=64)
    ap.add_argument("--instances", type=int, default=16)
    ap.add_argument("--s", default="2,5,10,20")
    ap.add_argument("--mmin", type=int, default=6)
    ap.add_argument("--mmax", type=int, default=16)
    ap.add_argument("--out", default=os.path.join(ROOT, "results", "extensible-prefix"))
    ap.add_argument("--table", action="store_true",
                    help="only rewrite prefix.md from the prefix.json in --out")
    args = ap.parse_args()
    if args.table:
        with open(os.path.join(args.out, "prefix.json")) as fh:
            record = json.load(fh)
        write_table(record, args.out)
        return
    levels = list(range(args.mmin, args.mmax + 1))
    rng = np.random.default_rng(20261127)
    record = {"shifts": args.shifts, "instances": args.instances, "cells": []}
    for s in map(int, args.s.split(",")):
        t0 = time.time()
        g = generators(s, levels)
        print(f"s = {s}: generators in {time.time() - t0:.1f} s", flush=True)
        inst = [i for i in genz_instances(s, args.instances, 7 + s) if i[0] < 4]
        exact = [genz_exact(f, a, u) for f, a, u in inst]
        for m in levels:
            n = 1 << m
            sq = {"seq": np.zeros(4), "single": np.zeros(4)}
            for _ in range(args.shifts):
                for name, z in (("seq", g["extensible"]), ("single", g["single"][str(m)])):
                    x = rule(z, n, rng.random(s))
                    for (f, a, u), e in zip(inst, exact):
                        err = (genz_value(f, a, u, x).mean() - e) / abs(e)
                        sq[name][f] += err * err
            crit = criterion(g["extensible"], n) / criterion(g["single"][str(m)], n)
            for f in range(4):
                rmse = {k: float(np.sqrt(v[f] / (args.shifts * args.instances)))
                        for k, v in sq.items()}
                record["cells"].append({"family": FAMILIES[f], "s": s, "n": n,
                                        "rmse_sequence": rmse["seq"],
                                        "rmse_single": rmse["single"],
                                        "ratio": rmse["seq"] / rmse["single"],
                                        "criterion_ratio": float(crit)})
            worst = max(c["ratio"] for c in record["cells"] if c["s"] == s and c["n"] == n)
            print(f"  s = {s}, n = {n}: worst ratio {worst:.2f}", flush=True)
    if 2 in map(int, args.s.split(",")):
        record["two_dimensional_bound"] = two_dimensional_bound()
        print("s = 2 bound:", record["two_dimensional_bound"], flush=True)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "prefix.json"), "w") as fh:
        json.dump(record, fh, indent=1)
    write_table(record, args.out)


def write_table(record, out):
    """prefix.md from the record."""
    lines = ["# Prefix quality of the extensible lattice sequence", "",
             "RMSE of the relative error over random shifts (%d per instance) and %d Genz "
             "instances per family: the sequence's first n points / the lattice made for n "
             "(both shifted and tent-transformed). Made by `python3 "
             "benches/extensible_prefix.py`." % (record["shifts"], record["instances"]), ""]
    ss = sorted({c["s"] for c in record["cells"]})
    ns = sorted({c["n"] for c in record["cells"]})
    for fam in FAMILIES:
        lines += [f"## {fam}", "", "| n | " + " | ".join(f"s = {s}" for s in ss) + " |",
                  "|---" * (len(ss) + 1) + "|"]
        for n in ns:
            row = [next(c["ratio"] for c in record["cells"]
                        if c["family"] == fam and c["s"] == s and c["n"] == n) for s in ss]
            lines.append(f"| {n} | " + " | ".join(
                f"**{r:.2f}**" if r > 1.2 else f"{r:.2f}" for r in row) + " |")
        lines.append("")
    lines += ["## criterion (squared worst-case error) ratio, sequence / single-n rule", "",
              "An RMSE ratio of 1.2 is a criterion ratio of about 1.44.", "",
              "| n | " + " | ".join(f"s = {s}" for s in ss) + " |", "|---" * (len(ss) + 1) + "|"]
    for n in ns:
        row = [next(c["criterion_ratio"] for c in record["cells"] if c["s"] == s and c["n"] == n)
               for s in ss]
        lines.append(f"| {n} | " + " | ".join(f"{r:.2f}" for r in row) + " |")
    lines.append("")
    misses = [c for c in record["cells"] if c["ratio"] > 1.2]
    lines.append(f"Cells above 1.2: {len(misses)} of {len(record['cells'])} (in bold).")
    lines += ["", "| s | geometric mean of the RMSE ratios | median | cells below 1 |",
              "|---|---|---|---|"]
    for s in ss:
        r = sorted(c["ratio"] for c in record["cells"] if c["s"] == s)
        lines.append(f"| {s} | {np.exp(np.mean(np.log(r))):.2f} | {np.median(r):.2f} | "
                     f"{sum(x < 1 for x in r)} of {len(r)} |")
    if "two_dimensional_bound" in record:
        b = record["two_dimensional_bound"]
        lines += ["", f"At s = 2 no embedded lattice can do better: over every z_2 mod 2^14, the "
                  f"smallest largest criterion ratio over the levels 2^6..2^14 is {b:.1f} "
                  f"(an RMSE ratio of about {np.sqrt(b):.1f} at some level)."]
    with open(os.path.join(out, "prefix.md"), "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
