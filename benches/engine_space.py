#!/usr/bin/env python3
"""`stillpoint.Engine(space=...)` on the cells of the benchmark of models users bring
(results/uq-models): the engine given the laws of f's inputs, its draws carried into the
space by `Engine.to_space`, beside `Engine(d)` mapped by the peers' quantile map (the
benchmark's Engine column, drawn again here with the same seeds). Every figure is an RMSE
over the cell's instances and REPS randomisations divided by the scrambled Sobol' RMSE
stored for the cell (SciPy, 16 randomisations), as benches/uq_engine.py reads it.

    engine     Engine(d, seed=SEED0 + r).random(n), the peers' map (path families: the
               m normals of the benchmark, the path built in the function)
    space      Engine(space=S, seed=SEED0 + r): a sequence (Owen-scrambled Sobol' dealt
               path-first where S holds a Brownian path, the engine's lattice otherwise),
               through Engine.to_space; a path family's S is one `W=brownian(1,k,c)` per
               asset, the space a user writes for a path
    space_ind  Engine(space=S, draws='independent', seed=SEED0 + r): each draw the set
               `design(n, S, randomize=True)` makes, through Engine.to_space

    REPS=16 NS=1024,4096,16384 FAM=keister,asian CANDS=engine,space,space_ind SEED0=1000
    target/py-venv/bin/python benches/engine_space.py

Prints a line per cell, then the geometric means per family and over all cells, as a
Markdown table.
"""
import math
import os
import sys
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import stillpoint as sp  # noqa: E402
import uq_models as U  # noqa: E402
from uq_families import PathOption, law_text, map_cube  # noqa: E402

REPS = int(os.environ.get("REPS", 16))
NS = [int(x) for x in os.environ.get("NS", "1024,4096").split(",")]
FAM = os.environ.get("FAM")
CANDS = os.environ.get("CANDS", "engine,space,space_ind").split(",")
SEED0 = int(os.environ.get("SEED0", 1000))


def gm(xs):
    return math.exp(float(np.mean(np.log(xs)))) if len(xs) else float("nan")


def estimates(cand, fam, v, insts, n, d, r):
    """Q per instance for one randomisation of `cand`."""
    seed = SEED0 + r
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if cand == "engine":
            u = np.clip(sp.Engine(d, seed=seed).random(n), 2**-53, 1 - 2**-53)
            cache = {}

            def mapped(i):
                laws = fam.laws(v, insts[i])
                key = repr(laws)
                if key not in cache:
                    cache[key] = map_cube(laws, u)
                return cache[key]
            return U.means_on(fam, v, insts, mapped)
        is_path = isinstance(fam, PathOption)
        space_of = "brownian" if is_path else "normals"
        draws = "independent" if cand == "space_ind" else "sequence"
        texts = [[law_text(nm, law) for nm, law in fam.space_laws(v, p, space_of)]
                 for p in insts]
        # The unit draws depend on the laws' kinds only (the same for every instance);
        # each instance's engine carries them into its own space.
        u = sp.Engine(space=texts[0], draws=draws, seed=seed).random(n)
        cache = {}

        def values(i):
            key = tuple(texts[i])
            if key not in cache:
                cache[key] = sp.Engine(space=texts[i], draws=draws, seed=seed).to_space(u)
            return cache[key]
        return U.means_on(fam, v, insts, values, is_path)


def main():
    rows = []
    for c, fam, v, insts, ref, den in U.stored_cells(NS, FAM):
        out = {}
        for cand in CANDS:
            errs = [U.relative(estimates(cand, fam, v, insts, c["n"], c["d"], r), ref)
                    for r in range(REPS)]
            out[cand] = math.sqrt(float(np.mean(np.array(errs) ** 2))) / den
        rows.append((c["family"], c["variant"], c["n"], out))
        print(c["family"], c["variant"], c["n"],
              " ".join(f"{k}={x:.2f}" for k, x in out.items()), flush=True)
    fams = []
    for f, *_ in rows:
        if f not in fams:
            fams.append(f)
    print()
    print("| family | cells | " + " | ".join(CANDS) + " |")
    print("|---|---|" + "---|" * len(CANDS))
    for f in fams:
        rs = [r for r in rows if r[0] == f]
        print(f"| {f} | {len(rs)} | "
              + " | ".join(f"{gm([r[3][k] for r in rs]):.2f}" for k in CANDS) + " |")
    print(f"| **all cells** | {len(rows)} | "
          + " | ".join(f"**{gm([r[3][k] for r in rows]):.2f}**" for k in CANDS) + " |")


if __name__ == "__main__":
    main()
