#!/usr/bin/env python3
"""Prefixes of the extensible lattice sequence against QMCPy's extensible lattice.

Ours: the sequence `stillpoint.quad` draws from (`stillpoint._core.sequence_points`
with the tent table, sequences/src/extensible_table.rs): one uniform shift per seed, the
tent (baker's) transform, points in radical-inverse order. Theirs: `qmcpy.Lattice(s,
randomize='SHIFT', seed=...)` with its default generating vector, in its default
radical-inverse order, (a) with the same tent transform x -> 1 - |2x - 1| applied to its
points and (b) as it comes (its default use). QMCPy's lattice is extensible only in
powers of two; at other n its prefix is the first n rows of its 2^16 points in that
order, which is what `gen_samples` gives for the next power of two cut to n (the order
is fixed, the shift is one per seed), and the same rule as ours.

Every side draws 2^16 points per shift once; the prefix of n points is the first n rows
(the sum pairwise, as numpy sums a slice). Integrands: Genz's six families with random
parameters per instance (benches/anchors.py: FAMILIES, genz_instances, genz_value,
genz_exact; the same code on every side). Per (s, n, instance) the RMSE of the relative
error over R shifts per side; per (s, family, n) cell the geometric mean over the
family's instances of the ratio ours / QMCPy's; then geometric means per (s, family),
per s and overall, over the powers of two 2^6 ... 2^16 (the headline) and separately
over the other n.

    target/py-venv/bin/python benches/prefix_qmcpy.py [--shifts 64] [--instances 12]
        [--s 2,3,5,7,10,12,15,20] [--out results/extensible-prefix]
    target/py-venv/bin/python benches/prefix_qmcpy.py --table   # versus-qmcpy.md again
    ... --draw 1 --name versus-qmcpy-draw1   # other instances and shifts, as a check

Needs the package (stillpoint) in the venv, numpy, scipy and qmcpy. Writes
results/extensible-prefix/versus-qmcpy.md and versus-qmcpy.json.
"""

import argparse
import hashlib
import json
import os
import platform
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from anchors import FAMILIES, genz_exact, genz_instances, genz_value  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MMAX = 16
POWERS = [1 << m for m in range(6, MMAX + 1)]
OTHERS = [100, 300, 1000, 3000, 10000, 30000]
SIDES = ["ours", "qmcpy_tent", "qmcpy"]
SEED_OURS, SEED_QMCPY = 1000, 7000


def tent(x):
    return 1.0 - np.abs(2.0 * x - 1.0)


def ours(s, r):
    """2^16 points of the sequence quad draws from, seed SEED_OURS + r (shifted, tent)."""
    import stillpoint as sp

    return np.asarray(sp._core.sequence_points(s, seed=SEED_OURS + r, count=1 << MMAX,
                                               table="tent"))


def theirs(s, r):
    """2^16 points of QMCPy's shifted extensible lattice, seed SEED_QMCPY + r."""
    import qmcpy as qp

    lat = qp.Lattice(dimension=s, randomize="SHIFT", seed=SEED_QMCPY + r,
                     order="RADICAL INVERSE")
    return lat.gen_samples(n_min=0, n_max=1 << MMAX)


def prefix_means(v, ns):
    """The mean of v's first n entries for each n (numpy's pairwise sum per slice, so
    no running-sum rounding grows with n)."""
    return np.array([v[:n].mean() for n in ns])


def gm(xs):
    xs = np.asarray(xs, dtype=float)
    return float(np.exp(np.mean(np.log(xs)))) if xs.size else float("nan")


def measure(s, shifts, instances, ns, draw=0):
    """RMSE of the relative error per side, instance and n: {side: [inst][n]} (six
    significant digits). `draw` > 0 takes other instances and other shifts."""
    insts = genz_instances(s, instances, seed=4_700_000 + 1000 * draw + s)
    exact = np.array([genz_exact(f, a, u) for f, a, u in insts])
    sq = {side: np.zeros((len(insts), len(ns))) for side in SIDES}
    digest = None
    for r in range(shifts):
        x_ours, x_theirs = ours(s, 100_000 * draw + r), theirs(s, 100_000 * draw + r)
        if r == 0:
            digest = hashlib.sha256(np.ascontiguousarray(x_ours, "<f8").tobytes()).hexdigest()
        for side, x in (("ours", x_ours), ("qmcpy_tent", tent(x_theirs)), ("qmcpy", x_theirs)):
            assert x.shape == (1 << MMAX, s) and np.all((x >= 0) & (x <= 1)), side
            for i, (f, a, u) in enumerate(insts):
                est = prefix_means(genz_value(f, a, u, x), ns)
                sq[side][i] += ((est - exact[i]) / abs(exact[i])) ** 2
    rmse = {side: [[float(f"{e:.6g}") for e in row] for row in np.sqrt(v / shifts)]
            for side, v in sq.items()}
    return {"s": s, "families": [int(f) for f, _, _ in insts], "rmse": rmse,
            "ours_first_shift_sha256": digest}


def cell_ratios(rec, ns, against):
    """{(family, n): geometric mean over the family's instances of ours / against}."""
    fam = np.array(rec["families"])
    a, b = np.array(rec["rmse"]["ours"]), np.array(rec["rmse"][against])
    out = {}
    for f in range(len(FAMILIES)):
        for j, n in enumerate(ns):
            out[(f, n)] = gm(a[fam == f, j] / b[fam == f, j])
    return out


def write_table(record, out, name="versus-qmcpy"):
    """NAME.md from the record."""
    ns = record["ns"]
    per_s = {rec["s"]: {k: cell_ratios(rec, ns, k) for k in ("qmcpy_tent", "qmcpy")}
             for rec in record["runs"]}
    ss = sorted(per_s)
    lines = [
        "# Prefixes of the extensible lattice sequence against QMCPy's extensible lattice",
        "",
        f"Made by `{record['command']}` on {record['date']} at commit "
        f"{record['commit'][:7]}, QMCPy {record['qmcpy']}, numpy {record['numpy']}; "
        f"machine: {record['machine']}, {record['seconds'] / 60:.0f} min.",
        "",
        "Ratio of RMSEs of the relative error, ours / QMCPy's (below 1: ours better). Ours: "
        "the first n points of the sequence `stillpoint.quad` draws from (the extensible "
        "lattice sequence with the tent table, one shift per seed, the tent transform, "
        "radical-inverse order). QMCPy: `qmcpy.Lattice(s, randomize='SHIFT', seed=...)`, "
        "its default generating vector, radical-inverse order, **with the same tent "
        "transform** (the headline) and, as a second figure, as it comes (no tent, its "
        "default use). At n that is not a power of two QMCPy's prefix is the first n rows "
        "of its 2^16 points in that order, as ours is. "
        f"{record['shifts']} shifts per side and instance (seeds {SEED_OURS}+r for ours, "
        f"{SEED_QMCPY}+r for QMCPy, r = {100_000 * record.get('draw', 0)} + 0 … "
        f"{record['shifts'] - 1}), "
        f"{record['instances']} random instances of each of "
        "Genz's six families per s (benches/anchors.py, the same code on every side); a "
        "cell's ratio is the geometric mean over its family's instances of the "
        "per-instance RMSE ratios, and every mean below is geometric.",
        "",
    ]
    allp = {k: [r for s in ss for (f, n), r in per_s[s][k].items() if n in POWERS]
            for k in ("qmcpy_tent", "qmcpy")}
    allo = {k: [r for s in ss for (f, n), r in per_s[s][k].items() if n in OTHERS]
            for k in ("qmcpy_tent", "qmcpy")}
    smooth = [r for s in ss for (f, n), r in per_s[s]["qmcpy_tent"].items()
              if n in POWERS and f < 4]
    lines += [
        "## Overall", "",
        "| prefixes | cells | against QMCPy + tent | against QMCPy as it comes |",
        "|---|---|---|---|",
        f"| powers of two 2^6 … 2^16 | {len(allp['qmcpy_tent'])} | "
        f"**{gm(allp['qmcpy_tent']):.2f}** | {gm(allp['qmcpy']):.2f} |",
        f"| the four smooth families only, powers of two | {len(smooth)} | "
        f"{gm(smooth):.2f} | — |",
        f"| n = {', '.join(map(str, OTHERS))} | {len(allo['qmcpy_tent'])} | "
        f"{gm(allo['qmcpy_tent']):.2f} | {gm(allo['qmcpy']):.2f} |",
        f"| every n | {len(allp['qmcpy_tent']) + len(allo['qmcpy_tent'])} | "
        f"{gm(allp['qmcpy_tent'] + allo['qmcpy_tent']):.2f} | "
        f"{gm(allp['qmcpy'] + allo['qmcpy']):.2f} |",
        "",
        f"Cells (s, family, n = 2^k) above 1 against QMCPy + tent: "
        f"{sum(r > 1 for r in allp['qmcpy_tent'])} of {len(allp['qmcpy_tent'])}.",
        "",
    ]
    # Per (s, family), powers of two.
    for k, title in (("qmcpy_tent", "against QMCPy + tent"), ("qmcpy", "against QMCPy as it comes")):
        lines += [f"## Per s and family, {title} (n = 2^6 … 2^16)", "",
                  "| s | " + " | ".join(FAMILIES) + " | all six |",
                  "|---" * (len(FAMILIES) + 2) + "|"]
        for s in ss:
            row = [gm([per_s[s][k][(f, n)] for n in POWERS]) for f in range(len(FAMILIES))]
            tot = gm([per_s[s][k][(f, n)] for f in range(len(FAMILIES)) for n in POWERS])
            lines.append(f"| {s} | " + " | ".join(
                f"**{x:.2f}**" if x > 1 else f"{x:.2f}" for x in row) + f" | {tot:.2f} |")
        lines += [""]
    # Per n and s, against the tent, all six families.
    lines += ["## Per n and s, against QMCPy + tent (all six families)", "",
              "| n | " + " | ".join(f"s = {s}" for s in ss) + " |",
              "|---" * (len(ss) + 1) + "|"]
    for n in POWERS + OTHERS:
        row = [gm([per_s[s]["qmcpy_tent"][(f, n)] for f in range(len(FAMILIES))]) for s in ss]
        lines.append(f"| {n} | " + " | ".join(
            f"**{x:.2f}**" if x > 1 else f"{x:.2f}" for x in row) + " |")
    lines += ["", "Bold: above 1 (QMCPy's prefix better).", ""]
    # Worst cells.
    cells = sorted(((r, s, f, n) for s in ss for (f, n), r in per_s[s]["qmcpy_tent"].items()),
                   reverse=True)
    lines += ["## The worst cells against QMCPy + tent", "",
              "| s | family | n | ratio | our RMSE (median over instances) | QMCPy + tent's |",
              "|---|---|---|---|---|---|"]
    for r, s, f, n in cells[:15]:
        rec = next(x for x in record["runs"] if x["s"] == s)
        fam = np.array(rec["families"]) == f
        j = ns.index(n)
        a = np.median(np.array(rec["rmse"]["ours"])[fam, j])
        b = np.median(np.array(rec["rmse"]["qmcpy_tent"])[fam, j])
        lines.append(f"| {s} | {FAMILIES[f]} | {n} | {r:.2f} | {a:.2e} | {b:.2e} |")
    lines += ["", "Our sequence's first shift per s (2^16 points, row-major little-endian f64, "
              "SHA-256):", ""]
    for rec in record["runs"]:
        lines.append(f"    s = {rec['s']}: {rec['ours_first_shift_sha256']}")
    lines += ["", "## Fingerprints", "",
              "No `generate` cells (randomly shifted sequences drawn through the package), so "
              "none to remake; the commit the figures describe:", "",
              f"    describes commit: {record['commit']} (the extensible lattice sequence's "
              "shifted prefixes through the package against QMCPy's lattice; not `generate` "
              "sets)", ""]
    with open(os.path.join(out, name + ".md"), "w") as fh:
        fh.write("\n".join(lines))
    print("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--shifts", type=int, default=64)
    ap.add_argument("--instances", type=int, default=12)
    ap.add_argument("--s", default="2,3,5,7,10,12,15,20")
    ap.add_argument("--draw", type=int, default=0,
                    help="0: the recorded instances and shifts; k > 0: other ones (a check)")
    ap.add_argument("--out", default=os.path.join(ROOT, "results", "extensible-prefix"))
    ap.add_argument("--name", default="versus-qmcpy", help="the files NAME.md, NAME.json")
    ap.add_argument("--table", action="store_true",
                    help="only rewrite NAME.md from NAME.json in --out")
    args = ap.parse_args()
    path = os.path.join(args.out, args.name + ".json")
    if args.table:
        with open(path) as fh:
            write_table(json.load(fh), args.out, args.name)
        return
    if args.shifts < 2 or args.instances < 1 or args.draw < 0:
        raise SystemExit("invalid --shifts/--instances/--draw: at least 2 shifts, 1 instance, "
                         "draw 0 or more")
    import qmcpy
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, check=True,
                          capture_output=True, text=True).stdout.strip()
    ns = POWERS + OTHERS
    t0 = time.time()
    record = {
        "command": " ".join(["target/py-venv/bin/python benches/prefix_qmcpy.py"] + sys.argv[1:]),
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "commit": head, "qmcpy": qmcpy.__version__, "numpy": np.__version__,
        "machine": f"2 cores, shared ({platform.machine()}, Python {platform.python_version()})",
        "shifts": args.shifts, "instances": args.instances, "draw": args.draw, "ns": ns,
        "runs": [],
    }
    for s in map(int, args.s.split(",")):
        t = time.time()
        record["runs"].append(measure(s, args.shifts, args.instances, ns, args.draw))
        rec = record["runs"][-1]
        r = cell_ratios(rec, ns, "qmcpy_tent")
        print(f"s = {s}: {time.time() - t:.0f} s; ours / QMCPy+tent over 2^k: "
              f"{gm([v for (f, n), v in r.items() if n in POWERS]):.2f}", flush=True)
    record["seconds"] = time.time() - t0
    os.makedirs(args.out, exist_ok=True)
    with open(path, "w") as fh:
        json.dump(record, fh, separators=(",", ":"))
    write_table(record, args.out, args.name)


if __name__ == "__main__":
    main()
