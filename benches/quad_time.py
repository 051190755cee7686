"""Time outside f in one window: stillpoint's `quad` now and before against QMCPy's
`CubQMCLatticeG` and `CubQMCNetG` on the model cells of benches/quad.py.

The runs are benches/quad.py's own (same cells, instances and seeds), made one method
after another on the same machine so that its load is the same for all; DIR/new holds
the references' JSONs and the current package's, DIR/before the JSON of the package
before the change:

    FAMS="uq keister,uq oscillatory (normal),uq gaussian (normal),uq lognormal product,uq morokoff-caflisch,geometric asian"
    target/bench-venv/bin/python benches/quad.py --out DIR/new --runs 20 --cell-seconds 30 \\
        --families "$FAMS" --tols 0.01,0.001 --methods qmcpy-lattice,qmcpy-net
    target/py-venv/bin/python benches/quad.py --out DIR/new --runs 20 --cell-seconds 30 \\
        --families "$FAMS" --tols 0.01,0.001 --methods stillpoint
    BEFORE-VENV/bin/python benches/quad.py --out DIR/before --runs 20 --cell-seconds 30 \\
        --families "$FAMS" --tols 0.01,0.001 --methods stillpoint
    python benches/quad_time.py DIR

Prints, per cell, the median time outside f (wall, ms) of each and the ratios, then the
medians of the per-cell ratios (the claim of the issue: ≤ 1 against each reference) in
wall and CPU time; once with f as each method is given it (``outside``: a reference's f
holds the map through the laws, stillpoint's does not) and once outside the model itself
(``outside_model``: the map counted as every method's work).
"""

import gzip
import json
import os
import statistics
import sys


def load(path):
    with gzip.open(path, "rt") as fh:
        return json.load(fh)["cells"]


def med(cell, field):
    return statistics.median(r[field] for r in cell["runs"])


def main(base):
    now = load(os.path.join(base, "new", "stillpoint.json.gz"))
    before = load(os.path.join(base, "before", "stillpoint.json.gz"))
    lat = load(os.path.join(base, "new", "qmcpy-lattice.json.gz"))
    net = load(os.path.join(base, "new", "qmcpy-net.json.gz"))
    cells = [k for k in now if k in before and k in lat and k in net]
    for field, what in [("outside", "outside f as each method is given it"),
                        ("outside_model", "outside the model itself")]:
        print(f"\nTime {what} (median per cell, wall, ms)\n")
        print("| cell | evaluations: ours · lattice · net | ours before | ours now | "
              "CubQMCLatticeG | CubQMCNetG | now/before | now/lattice | now/net |")
        print("|---|---|---|---|---|---|---|---|---|")
        ratios = {"wall": ([], [], []), "CPU": ([], [], [])}
        for k in cells:
            for unit, f in [("wall", field), ("CPU", field + "_cpu")]:
                a, b, l, n = (med(c[k], f) for c in (now, before, lat, net))
                for v, r in zip(ratios[unit], (a / b, a / l, a / n)):
                    v.append(r)
                if unit == "wall":
                    evals = " · ".join(f"{med(c[k], 'calls_n'):.0f}" for c in (now, lat, net))
                    print(f"| {k.replace('|', ' ')} | {evals} | {1e3 * b:.2f} | {1e3 * a:.2f} | "
                          f"{1e3 * l:.2f} | {1e3 * n:.2f} | {a / b:.2f} | {a / l:.2f} | "
                          f"{a / n:.2f} |")
        for unit, (b, l, n) in ratios.items():
            print(f"\nMedian over the {len(cells)} cells, {unit} time: now/before "
                  f"{statistics.median(b):.2f}, now/CubQMCLatticeG {statistics.median(l):.2f}, "
                  f"now/CubQMCNetG {statistics.median(n):.2f}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else
         os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                      "results", "quad", "time-window"))
