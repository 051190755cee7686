"""Linear constraints and mixtures from Python: the command line's points bit for bit,
constraints held, mixtures summing to 1, pairs (a, b) read as a·x <= b, refusals named
as Python spells them, and the guide's example."""

import json
import re

import numpy as np
import pytest

import stillpoint as sp

from conftest import ROOT


def same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


BOX = [0, 1, 0, 1, 0, 1]


def test_constraints_are_the_cli_npy(cli, tmp_path):
    out = tmp_path / "x.npy"
    cli(
        "generate", "--constraint", "x1 + 2*x2 <= 1", "--constraint", "x2 + x3 >= 0.2",
        "--box", "0,1,0,1,0,1", "--goal", "integration", "-n", 30, "--seed", 4,
        "-q", "-o", out,
    )
    got = sp.generate(
        30, constraints=["x1 + 2*x2 <= 1", "x2 + x3 >= 0.2"], box=BOX, goal="integration",
        seed=4,
    )
    assert same_bits(got, np.load(out))
    assert (got @ np.array([1.0, 2.0, 0.0]) - 1.0).max() <= 1e-12
    assert (0.2 - got @ np.array([0.0, 1.0, 1.0])).max() <= 1e-12
    assert got.min() >= 0 and got.max() <= 1


def test_pairs_mean_a_dot_x_at_most_b():
    text = sp.generate(24, constraints=["x1 + 2*x2 <= 1", "-x2 - x3 <= -0.2"], box=BOX,
                       goal="integration")
    pairs = sp.generate(24, constraints=[([1, 2, 0], 1), (np.array([0.0, -1, -1]), -0.2)],
                        box=BOX, goal="integration")
    assert same_bits(text, pairs)


def test_no_constraint_is_the_box():
    x = sp.generate(12, constraints=[], box=[0, 1, 0, 2], goal="integration")
    assert x.shape == (12, 2) and x[:, 1].max() > 1


def test_a_mixture_is_the_cli_npy_and_sums_to_one(cli, tmp_path):
    out = tmp_path / "m.npy"
    bounds = [0.1, 0.7, 0, 0.6, 0.05, 1, 0, 0.5]
    cli(
        "generate", "--mixture", "-s", 4, "--box", ",".join(map(str, bounds)),
        "--constraint", "x1 + x4 >= 0.3", "-n", 25, "--goal", "integration",
        "-q", "-o", out,
    )
    got = sp.generate(25, 4, mixture=True, box=bounds, constraints=["x1 + x4 >= 0.3"],
                      goal="integration")
    assert same_bits(got, np.load(out))
    assert np.abs(got.sum(axis=1) - 1).max() <= 1e-12
    lo, hi = np.array(bounds[0::2]), np.array(bounds[1::2])
    assert (got >= lo).all() and (got <= hi).all()
    assert (0.3 - got[:, 0] - got[:, 3]).max() <= 1e-12


@pytest.mark.parametrize(
    "kwargs, says",
    [
        (dict(constraints=["x1 + x2 >= 3"], box=[0, 1, 0, 1]), "invalid constraints = "),
        (dict(constraints=["x1*x2 <= 0.5"], box=[0, 1, 0, 1]), "not linear"),
        (dict(constraints=["x4 <= 1"], box=[0, 1, 0, 1]), "x1..x2"),
        (dict(constraints=["x1 + x2 = 1"], box=[0, 1, 0, 1]), "mixture"),
        (dict(constraints=[([1, 2, 3], 1)], box=[0, 1, 0, 1]), "x1..x2"),
        (dict(constraints=[([1, float("nan")], 1)], box=[0, 1, 0, 1]), "finite"),
        (dict(constraints=["x1 <= 0.5"]), "invalid box"),
        (dict(d=3, mixture=True, box=[0.5, 1, 0.6, 1, 0, 1]), "mixture"),
        (dict(d=1, mixture=True), "invalid d = 1"),
    ],
)
def test_refusals_name_the_keyword(kwargs, says):
    with pytest.raises(ValueError) as e:
        sp.generate(10, **kwargs)
    assert says in str(e.value), str(e.value)
    assert "--" not in str(e.value), str(e.value)


def test_the_guides_example_runs_as_written():
    page = (ROOT / "docs" / "regions.md").read_text()
    section = page.split("## Linear constraints and mixtures", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(blocks) == 1
    scope: dict = {}
    exec(compile(blocks[0], "docs/regions.md", "exec"), scope)
    x, blend = scope["x"], scope["blend"]
    assert x.shape == (32, 3) and blend.shape == (20, 3)
    assert (x @ np.array([1.0, 2.0, 0.0]) - 1).max() <= 1e-12
    assert (x @ np.array([0.0, 1.0, 1.0]) - 1.5).max() <= 1e-12
    assert (blend >= [0.1, 0, 0]).all() and (blend <= [0.8, 0.6, 1]).all()
    assert (0.3 - blend[:, 0] - blend[:, 1]).max() <= 1e-12


def test_metrics_of_constrained_and_mixture_sets_are_the_cli_eval(cli, tmp_path):
    cons = ["x1 + 2*x2 <= 1.5"]
    x = sp.generate(80, constraints=cons, box=[0, 1, 0, 1], goal="integration")
    path = tmp_path / "c.npy"
    np.save(path, x)
    want = json.loads(cli("eval", "--json", "--constraint", cons[0], "--box", "0,1,0,1", path))
    got = sp.metrics(x, constraints=cons, box=[0, 1, 0, 1])
    assert got["energy_distance"] == want["energy_distance"]
    assert got["fraction_inside"] == 1.0
    m = sp.generate(60, 3, mixture=True, goal="integration")
    f = sp.metrics(m, mixture=True)
    assert f["mixture"] is True and f["s"] == 2 and f["fraction_inside"] == 1.0
    # Closer to uniform on the simplex than uniform points of it are.
    rng = np.random.default_rng(0)
    u = rng.dirichlet(np.ones(3), size=60)
    assert f["energy_distance"] < sp.metrics(u, mixture=True)["energy_distance"]
    with pytest.raises(ValueError, match="summing to 1"):
        sp.metrics(np.full((4, 3), 0.2), mixture=True)
