"""Every option declared in the library (``stillpoint._core.options()``) walked through
Python with its keyword: a good value runs, a bad value and a refused combination raise a
``ValueError`` naming the keyword; and the keywords ``stillpoint.generate`` accepts are
exactly the declared ones. A new option fails here until its walk is written."""

import inspect

import numpy as np
import pytest

import stillpoint as sp

OLD = np.array([[0.1, 0.2], [0.6, 0.7]])
FAR = np.array([[0.1, 0.2], [3.0, 0.7]])
MIX = np.array([[0.2, 0.3, 0.5], [0.5, 0.25, 0.25]])
NORMALS = ["a=normal(0,1)", "b=normal(0,1)"]
CUBE = dict(n=8, d=2)
PAPER = dict(n=8, d=2, steps=5)
DISC = dict(region="x^2 + y^2 - 1", box=[-1, 1, -1, 1])


def paper(key, good, bad):
    return (
        {**PAPER, key: good},
        {**CUBE, key: bad},
        {**CUBE, key: good, "goal": "integration"},
    )


# Per option (by its library name): generate's keyword arguments that succeed, carry a bad
# value (None: no value is bad), and make a refused combination (None: nothing excludes it).
WALKS = {
    "n": (CUBE, dict(n=0, d=2), dict(n=9, d=2, nested=[4, 8])),
    "s": (CUBE, dict(n=8, d=0), dict(n=3, d=3, extend=OLD)),
    "seed": ({**CUBE, "seed": 3}, {**CUBE, "seed": -1}, None),
    "method": (
        {**CUBE, "method": "sobol"},
        {**CUBE, "method": "nope"},
        {**CUBE, "method": "paper", "goal": "integration"},
    ),
    "goal": (
        {**PAPER, "goal": "space-filling"},
        {**CUBE, "goal": "nope"},
        {**CUBE, "goal": "integration", "q": 1},
    ),
    "target": (
        {**CUBE, "target": "md"},
        {**CUBE, "target": "nope"},
        {**CUBE, "target": "md", "method": "paper"},
    ),
    "randomize": (
        {**CUBE, "randomize": "shift"},
        {**CUBE, "randomize": "nope"},
        {**CUBE, "randomize": "shift", "shape": "ball:1"},
    ),
    "extend": (
        dict(n=3, extend=OLD),
        dict(n=3, extend=FAR),
        dict(n=3, extend=OLD, goal="space-filling"),
    ),
    "nested": (
        dict(n=None, d=2, nested=[4, 8]),
        dict(n=None, d=2, nested=[8, 4]),
        dict(n=None, d=2, nested=[4, 8], goal="space-filling"),
    ),
    "bounds": (
        {**CUBE, "bounds": ([0, -1], [2, 1])},
        {**CUBE, "bounds": "0,x"},
        {**CUBE, "bounds": ([0, 0], [1, 1]), "shape": "ball:1"},
    ),
    "region": (
        dict(n=8, steps=5, **DISC),
        dict(n=8, region="x^^", box=[-1, 1, -1, 1]),
        dict(n=8, region="x", box=[0, 1, 0, 1], constraints=["x1 <= 1"]),
    ),
    "box": (
        dict(n=8, steps=5, **DISC),
        dict(n=8, region="x^2 + y^2 - 1", box="-1,x"),
        {**CUBE, "box": [0, 1, 0, 1]},
    ),
    "shape": (
        {**PAPER, "shape": "ball:1"},
        {**CUBE, "shape": "nope:1"},
        dict(n=8, shape="ball:1", constraints=["x1 <= 1"], box=[0, 1, 0, 1]),
    ),
    "constraints": (
        dict(n=8, steps=5, constraints=["x1 + x2 <= 1.5"], box=[0, 1, 0, 1]),
        dict(n=8, constraints=["x1 * x2 <= 1"], box=[0, 1, 0, 1]),
        dict(n=8, constraints=["x1 <= 1"], box=[0, 1, 0, 1], region="x"),
    ),
    "mixture": (
        dict(n=8, d=3, steps=5, mixture=True),
        dict(n=8, d=3, mixture="maybe"),
        dict(n=3, mixture=True, extend=OLD),
    ),
    "energy": paper("energy", "e-inf", "nope"),
    "integrator": paper("integrator", "lbfgs", "nope"),
    "q": paper("q", 1, -1),
    "p": paper("p", 1, 0),
    "precision": paper("precision", "full", "nope"),
    "steps": ({**CUBE, "steps": 5}, {**CUBE, "steps": 0}, {**CUBE, "steps": 5, "goal": "integration"}),
    "init": paper("init", "random", "nope"),
    "kappa": paper("kappa", 100, 0.5),
    "restart": paper("restart", "off", -1),
    "tolerance": paper("tolerance", 0, -1),
    "polish": paper("polish", "md", "nope"),
    "shifts": paper("shifts", 2, -1),
    "log_every": paper("log_every", 2, -1),
    "exact": (
        {**CUBE, "exact": True},
        {**CUBE, "exact": "maybe"},
        {**CUBE, "exact": True, "method": "sobol"},
    ),
    "space": (
        dict(n=8, space=["a=normal(0,1)", "b=int(1,3)"]),
        dict(n=8, space=["a=nope"]),
        dict(n=8, space=NORMALS, nested=[4, 8]),
    ),
    "correlation": (
        dict(n=8, space=NORMALS, correlation="1,0.5;0.5,1"),
        dict(n=8, space=NORMALS, correlation="1,x"),
        {**CUBE, "correlation": "1,0.5;0.5,1"},
    ),
}

# `metrics`: keyword arguments that succeed on points, and (where ``metrics`` refuses
# the combination by keyword) one that is refused.
METRICS = {
    "exact": (dict(x=OLD, exact=True), None),
    "region": (dict(x=OLD, **DISC), dict(x=OLD, region="x", constraints=["x1 <= 1"], box=[0, 1, 0, 1])),
    "box": (dict(x=OLD, **DISC), dict(x=OLD, box=[0, 1, 0, 1])),
    "shape": (dict(x=OLD, shape="ball:1"), dict(x=OLD, shape="ball:1", constraints=["x1 <= 1"], box=[0, 1, 0, 1])),
    "constraints": (
        dict(x=OLD, constraints=["x1 + x2 <= 1.5"], box=[0, 1, 0, 1]),
        dict(x=OLD, constraints=["x1 <= 1"], box=[0, 1, 0, 1], region="x"),
    ),
    # Refused by metrics' own check today, whose message names constraints (the
    # library's resolution of `_core.metrics` names mixture).
    "mixture": (dict(x=MIX, mixture=True), None),
}

DECLARED = [o for o in sp._core.options() if o["python"] is not None]


def test_every_declared_keyword_has_a_walk():
    missing = [o["name"] for o in DECLARED if o["name"] not in WALKS]
    assert not missing, f"options with no walk: {missing}"
    metrics_keys = set(inspect.signature(sp.metrics).parameters) - {"x"}
    eval_options = {o["python"] for o in DECLARED if "eval" in o["groups"]}
    missing = [k for k in metrics_keys & eval_options if k not in METRICS]
    assert not missing, f"metrics keywords with no walk: {missing}"


@pytest.mark.parametrize("option", DECLARED, ids=lambda o: o["name"])
def test_every_option_is_walked_through_generate(option):
    key = option["python"]
    good, bad, refused = WALKS[option["name"]]
    sp.generate(**good)
    if bad is not None:
        with pytest.raises(ValueError) as e:
            sp.generate(**bad)
        assert f"invalid {key}" in str(e.value), str(e.value)
        assert "--" not in str(e.value), str(e.value)
    if refused is not None:
        with pytest.raises(ValueError) as e:
            sp.generate(**refused)
        assert str(e.value).startswith("invalid "), str(e.value)
        assert key in str(e.value), str(e.value)
        assert "--" not in str(e.value), str(e.value)


@pytest.mark.parametrize("key", sorted(METRICS))
def test_the_options_of_metrics_are_walked(key):
    good, refused = METRICS[key]
    figures = sp.metrics(**good)
    assert isinstance(figures, dict) and figures, figures
    if refused is not None:
        with pytest.raises(ValueError) as e:
            sp.metrics(**refused)
        assert key in str(e.value), str(e.value)


def test_generate_accepts_exactly_the_declared_keywords():
    declared = {o["python"] for o in DECLARED}
    front_end = {"progress"}  # how the run is shown, not what it makes
    signature = set(inspect.signature(sp.generate).parameters) - {"later"}
    undeclared = signature - declared - front_end
    assert not undeclared, f"generate's parameters not declared: {undeclared}"
    for key in sorted(declared | signature):
        # An accepted keyword fails, if at all, on its value (named), never as unknown.
        if key in ("n", "d"):
            continue
        try:
            sp.generate(8, 2, **{key: object()})
        except (ValueError, TypeError) as e:
            assert "invalid keyword argument" not in str(e), f"{key}: {e}"
    with pytest.raises(ValueError, match="invalid keyword argument = colour"):
        sp.generate(8, 2, colour="blue")


def test_the_docstring_table_is_the_declaration():
    """generate's docstring lists every Python keyword with the declared doc line."""
    doc = sp.generate.__doc__
    for o in sp._core.options():
        if o["python"] is None:
            continue
        assert f"``{o['python']}`` (``{o['cli']}``" in doc, o["python"]
        assert o["doc"] in doc, o["python"]
