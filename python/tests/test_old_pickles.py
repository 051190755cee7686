"""Engines and Designs pickled by an earlier stillpoint (data/, written by
data/make_pickles.py before the package was split into modules) load and behave as they
did: an engine draws what it drew then, and what a fresh engine made the same way draws;
a design holds the same table and figures."""

import json
import pathlib
import pickle
import warnings

import numpy as np
import pytest

import stillpoint as sp

DATA = pathlib.Path(__file__).resolve().parent / "data"
RECORD = json.loads((DATA / "pickled_expected.json").read_text())
ARRAYS = np.load(DATA / "pickled_expected.npz")

# The same engines built now, as the record says they were made (before pickling each
# drew 16 points). Engines then drew an independent set per call, which is now asked for
# by name (the default continues one sequence); the others imply it.
MADE_NOW = {
    "tent": lambda: sp.Engine(3, seed=4, draws="independent"),
    "cells": lambda: sp.Engine(
        2, seed=np.random.default_rng(7), randomize="cells", steps=40, energy="e-inf", shifts=0
    ),
    "shift": lambda: sp.Engine(2, rng=np.random.Generator(np.random.MT19937(3)), randomize="shift"),
}


def load(name):
    return [pickle.loads((DATA / f"{name}.p{p}.pkl").read_bytes()) for p in (2, 5)]


@pytest.mark.parametrize("name", sorted(RECORD["engines"]))
def test_an_old_engine_pickle_draws_what_it_drew(name):
    rec = RECORD["engines"][name]
    for e in load(f"engine_{name}"):
        assert type(e) is sp.Engine and isinstance(e, sp.Engine)
        assert e.num_generated == rec["drawn"] and repr(e) == rec["repr"]
        fresh = MADE_NOW[name]()
        fresh.random(rec["drawn"])
        assert e == fresh
        a, b = e.random(16), e.random(32)
        assert a.tobytes() == ARRAYS[f"engine_{name}_next16"].tobytes()
        assert b.tobytes() == ARRAYS[f"engine_{name}_next32"].tobytes()
        assert a.tobytes() == fresh.random(16).tobytes()
        assert b.tobytes() == fresh.random(32).tobytes()
        # reset goes back to the engine's first draw, as a fresh engine makes it.
        first = MADE_NOW[name]().random(16)
        assert e.reset().random(16).tobytes() == first.tobytes()


def test_an_old_tent_engine_in_qmc_quad_still_draws_independently():
    from scipy.integrate import qmc_quad

    # qmc_quad builds its engines from the old engine's arguments: independent draws
    # take 50 points without a word, where the sequence would warn (50 is no power of 2).
    (old, _) = load("engine_tent")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = qmc_quad(lambda x: np.prod(0.5 + x, axis=0), [0] * 3, [1] * 3,
                       n_estimates=4, n_points=50, qrng=old)
    assert abs(res.integral - 1.0) < 4 * res.standard_error + 1e-12
    with pytest.warns(UserWarning, match="balance"):
        qmc_quad(lambda x: np.prod(0.5 + x, axis=0), [0] * 3, [1] * 3,
                 n_estimates=4, n_points=50, qrng=sp.Engine(3, seed=4))


@pytest.mark.parametrize("name", sorted(RECORD["designs"]))
def test_an_old_design_pickle_holds_its_table_and_figures(name):
    rec = RECORD["designs"][name]
    for d in load(f"design_{name}"):
        assert type(d) is sp.Design and repr(d) == rec["repr"]
        assert d.space == rec["space"] and d.correlation == rec["correlation"]
        assert d.names == rec["names"] and d.figures == rec["figures"]
        assert d.unit.tobytes() == ARRAYS[f"design_{name}_unit"].tobytes()
        for k in d.names:
            if k in rec["labels"]:
                assert d.columns[k].tolist() == rec["labels"][k]
            else:
                want = ARRAYS[f"design_{name}_column_{k}"]
                assert d.columns[k].dtype == want.dtype
                assert d.columns[k].tobytes() == want.tobytes()
        assert list(d.table()) == d.names and len(d) == len(d.unit)
        # The library measures the loaded table as the design was measured.
        assert sp.design_figures(d.columns, d.space, correlation=d.correlation) == d.figures


def test_new_pickles_name_the_public_classes():
    e = sp.Engine(2, seed=1)
    d = sp.design(8, ["x=uniform(0,1)", "c={a,b}"])
    for value, name in ((e, b"Engine"), (d, b"Design")):
        for p in (2, pickle.HIGHEST_PROTOCOL):
            data = pickle.dumps(value, protocol=p)
            assert b"stillpoint" in data and name in data
            assert b"stillpoint._" not in data
