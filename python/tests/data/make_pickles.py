"""Writes the pickle fixtures of test_old_pickles.py: Engines and Designs pickled by
stillpoint 0.1.0 as it stood before the package was split into modules by concern,
each with what it did next (the next draws, the table). Kept for the record; running it
again with later code would only re-record that code, which is not what the fixtures
are for."""

import json
import pathlib
import pickle

import numpy as np

import stillpoint as sp

HERE = pathlib.Path(__file__).resolve().parent

# name -> (how it was made, the engine); each drew once before it was pickled.
ENGINES = {
    "tent": ("Engine(3, seed=4)", lambda: sp.Engine(3, seed=4)),
    "cells": (
        "Engine(2, seed=np.random.default_rng(7), randomize='cells', steps=40, "
        "energy='e-inf', shifts=0)",
        lambda: sp.Engine(
            2, seed=np.random.default_rng(7), randomize="cells", steps=40, energy="e-inf",
            shifts=0,
        ),
    ),
    "shift": (
        "Engine(2, rng=np.random.Generator(np.random.MT19937(3)), randomize='shift')",
        lambda: sp.Engine(2, rng=np.random.Generator(np.random.MT19937(3)), randomize="shift"),
    ),
}

DESIGNS = {
    "mixed": (
        "design(24, ['x=uniform(0,1)', 'y=uniform(-2,2)', 'k=int(1,5)', 'c={a,b,c}'])",
        lambda: sp.design(24, ["x=uniform(0,1)", "y=uniform(-2,2)", "k=int(1,5)", "c={a,b,c}"]),
    ),
    "correlated": (
        "design(30, ['x=normal(0,1)', 'y=lognormal(0,0.5)', 'c={lo,hi}'], "
        "correlation=[[1, 0.6], [0.6, 1]], seed=2)",
        lambda: sp.design(
            30, ["x=normal(0,1)", "y=lognormal(0,0.5)", "c={lo,hi}"],
            correlation=[[1, 0.6], [0.6, 1]], seed=2,
        ),
    ),
}

PROTOCOLS = (2, 5)


def main() -> None:
    record = {"version": sp.__version__, "engines": {}, "designs": {}}
    arrays = {}
    for name, (made, make) in ENGINES.items():
        e = make()
        e.random(16)
        for p in PROTOCOLS:
            (HERE / f"engine_{name}.p{p}.pkl").write_bytes(pickle.dumps(e, protocol=p))
        record["engines"][name] = {"made": made, "drawn": e.num_generated, "repr": repr(e)}
        arrays[f"engine_{name}_next16"] = e.random(16)
        arrays[f"engine_{name}_next32"] = e.random(32)
    for name, (made, make) in DESIGNS.items():
        d = make()
        for p in PROTOCOLS:
            (HERE / f"design_{name}.p{p}.pkl").write_bytes(pickle.dumps(d, protocol=p))
        record["designs"][name] = {
            "made": made,
            "space": d.space,
            "correlation": d.correlation,
            "names": d.names,
            "figures": d.figures,
            "repr": repr(d),
            # Labels as text; numbers as the npz below holds them.
            "labels": {k: v.tolist() for k, v in d.columns.items() if v.dtype == object},
        }
        arrays[f"design_{name}_unit"] = d.unit
        for k, v in d.columns.items():
            if v.dtype != object:
                arrays[f"design_{name}_column_{k}"] = v
    np.savez(HERE / "pickled_expected.npz", **arrays)
    (HERE / "pickled_expected.json").write_text(json.dumps(record, indent=1) + "\n")


if __name__ == "__main__":
    main()
