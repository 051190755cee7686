"""The library's reports reach Python as Python objects, typed as the command line's
JSON reads back: ``json.loads`` of ``stillpoint eval/integrate --json`` and the
package's dict hold the same keys, and at every place the same type (an ``int`` where
the JSON has a whole number, a ``float`` where it has a fraction, ``None`` for null)."""

import json

import numpy as np
import pytest

import stillpoint as sp


def same_shape(got, want, where="report"):
    """Asserts the same nesting, keys, types and (for numbers) values within 1e-12."""
    assert type(got) is type(want), (where, got, want)
    if isinstance(want, dict):
        assert list(got) == list(want), where
        for k in want:
            same_shape(got[k], want[k], f"{where}.{k}")
    elif isinstance(want, list):
        assert len(got) == len(want), where
        for i, (g, w) in enumerate(zip(got, want)):
            same_shape(g, w, f"{where}[{i}]")
    elif isinstance(want, float):
        assert abs(got - want) <= 1e-12 * max(abs(got), abs(want)) or got == want, where
    else:
        assert got == want, where


def report(text):
    """The command line's JSON report without its file name (which Python's has not)."""
    v = json.loads(text)
    v.pop("file", None)
    return v


@pytest.fixture
def saved(tmp_path):
    def save(x):
        path = tmp_path / "p.npy"
        np.save(path, np.asarray(x, dtype=np.float64))
        return path

    return save


@pytest.mark.parametrize(
    "points",
    [
        lambda: sp.generate(40, 3),
        # Coinciding points: infinite energies are null.
        lambda: np.array([[0.2, 0.3], [0.2, 0.3], [0.9, 0.1]]),
    ],
)
def test_metrics_are_the_objects_eval_json_reads_as(cli, saved, points):
    x = points()
    same_shape(sp.metrics(x), report(cli("eval", "--json", saved(x))))


def test_region_and_constrained_metrics_are_the_objects_eval_json_reads_as(cli, saved):
    x = sp.generate(30, 2, shape="ball:1", steps=50)
    want = report(cli("eval", "--json", "--shape", "ball:1", saved(x)))
    same_shape(sp.metrics(x, shape="ball:1"), want)
    cons = ["x1 + 2*x2 <= 1.5"]
    y = sp.generate(30, constraints=cons, box=[0, 1, 0, 1], goal="integration")
    same_shape(
        sp.metrics(y, constraints=cons, box=[0, 1, 0, 1]),
        report(cli("eval", "--json", "--constraint", cons[0], "--box", "0,1,0,1", saved(y))),
    )


def test_integrate_is_the_object_integrate_json_reads_as(cli, saved):
    x = sp.baseline("sobol", 64, 1, seed=3)
    got, want = sp.integrate(x), report(cli("integrate", "--json", saved(x)))
    same_shape(got, want)
    # F8 needs two coordinates: None, as JSON's null reads.
    assert got["functions"][-1]["estimate"] is None


def test_design_figures_are_the_objects_eval_var_json_reads_as(cli, tmp_path):
    space = ["x=normal(0,1)", "k=int(1,3)", "c={a,b}"]
    out = tmp_path / "d.csv"
    cli("generate", "-n", 24, "-q", "-o", out, *[a for v in space for a in ("--var", v)])
    want = report(cli("eval", "--json", *[a for v in space for a in ("--var", v)], out))
    d = sp.design(24, space)
    same_shape(d.figures, want["figures"])
    same_shape(sp.design_figures(d.columns, space), want["figures"])
