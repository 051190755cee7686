"""Added replicates against doubling only: `stillpoint.quad`'s runs of benches/quad.py
before and after replicates could be added, cell by cell on the runs both hold (the same
instances and seeds).

Usage (py-venv; OLD is the doubling-only stillpoint.json.gz, NEW the rerun's):
    benches/quad.py --methods stillpoint --runs 200 --cell-seconds 20 --out DIR
    benches/quad_grow.py OLD DIR/stillpoint.json.gz > results/quad/grow.md

Per cell: the runs compared, the reliability (true relative error within the tolerance
and met) of each, the median and mean evaluations of each and the new over the old.
Then the geometric means of the ratios over the cells (all, and per family) and the
cells whose reliability crossed 92.5 % (185 of 200, benches/quad.py's bar) either way.
"""

import gzip
import json
import math
import sys

import numpy as np

RELIABLE = 0.925


def cells(path):
    with gzip.open(path) as fh:
        return json.load(fh)["cells"]


def main():
    old, new = cells(sys.argv[1]), cells(sys.argv[2])
    rows = []
    for k, c in new.items():
        if k not in old:
            continue
        o = {r["run"]: r for r in old[k]["runs"]}
        n = {r["run"]: r for r in c["runs"]}
        common = sorted(set(o) & set(n))
        if not common:
            continue

        def stat(d, f):
            return f([d[i]["calls_n"] for i in common])

        rows.append({
            "key": k, "family": c["family"], "runs": len(common),
            "rel": (np.mean([o[i]["ok"] for i in common]), np.mean([n[i]["ok"] for i in common])),
            "median": (stat(o, np.median), stat(n, np.median)),
            "mean": (stat(o, np.mean), stat(n, np.mean)),
        })
    out = ["# Added replicates against doubling only", "",
           "`stillpoint.quad` on benches/quad.py's cells, doubling only (results/quad/"
           "stillpoint.json.gz) and with replicates added when predicted to meet the "
           "tolerance for less than a doubling, on the runs both hold (same instances "
           "and seeds). Written by `benches/quad_grow.py` (commands in its docstring).", "",
           "| cell (family, s, tol) | runs | reliability before → after | median n before → after "
           "| mean n after / before |",
           "|---|---|---|---|---|"]
    for r in rows:
        family, s, tol = r["key"].split("|")
        out.append(f"| {family}, {s}, {tol} | {r['runs']} | {r['rel'][0]:.3f} → {r['rel'][1]:.3f} "
                   f"| {r['median'][0]:.0f} → {r['median'][1]:.0f} "
                   f"| {r['mean'][1] / r['mean'][0]:.3f} |")

    def gm(xs):
        return math.exp(np.mean(np.log(xs)))

    out += ["", f"Over the {len(rows)} cells: geometric mean of the mean evaluations after over "
            f"before {gm([r['mean'][1] / r['mean'][0] for r in rows]):.3f}, of the medians "
            f"{gm([r['median'][1] / r['median'][0] for r in rows]):.3f}; reliability "
            f"{np.mean([r['rel'][0] for r in rows]):.4f} → {np.mean([r['rel'][1] for r in rows]):.4f} "
            "(mean over the cells).", "", "Per family (geometric mean of the mean-evaluation ratio, "
            "lowest reliability after on cells of ≥ 100 runs):", ""]
    for fam in dict.fromkeys(r["family"] for r in rows):
        mine = [r for r in rows if r["family"] == fam]
        full = [r["rel"][1] for r in mine if r["runs"] >= 100]
        low = f"{min(full):.3f}" if full else "—"
        out.append(f"- {fam}: {gm([r['mean'][1] / r['mean'][0] for r in mine]):.3f} "
                   f"({len(mine)} cells), lowest reliability {low}")
    crossed = [r for r in rows if (r["rel"][0] >= RELIABLE) != (r["rel"][1] >= RELIABLE)]
    out += ["", "Cells whose reliability crossed 92.5 %: " + (", ".join(
        f"{r['key']} ({r['runs']} runs, {r['rel'][0]:.3f} → {r['rel'][1]:.3f})" for r in crossed)
        or "none") + "."]
    print("\n".join(out))


if __name__ == "__main__":
    main()
