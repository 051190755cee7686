"""Every option declared in the library (``stillpoint._core.options()``) walked through
Python with its keyword, from its declaration: each word it accepts and numbers at and
beyond the bounds of its kind are good and bad values (a count's bad values are one below
its least and ``"x"``, a word's ``"nope"``, ...); the combinations its groups' rules
refuse come from its groups (a baseline refuses every option outside the baseline group
and the design space's, a goal every option of the paper's pipeline, a design space every
option that places the unit-cube set), and ``RULES`` adds the rules of single options. A new option is walked without a line here, unless its kind has no value
to make up (an expression, a variable's law): then ``EXAMPLES`` gives one, and the walk
fails until it does. The keywords ``generate`` and ``metrics`` accept are the declared
ones."""

import inspect

import numpy as np
import pytest

import stillpoint as sp

OLD = np.array([[0.1, 0.2], [0.6, 0.7]])
FAR = np.array([[0.1, 0.2], [3.0, 0.7]])
MIX = np.array([[0.2, 0.3, 0.5], [0.5, 0.25, 0.25]])
NORMALS = ["a=normal(0,1)", "b=normal(0,1)"]
DISC = "x^2 + y^2 - 1"

# Values of the options whose kind has none to make up: (good values, bad values).
EXAMPLES = {
    "region": ([DISC], ["x^^"]),
    "shape": (["ball:1"], ["nope:1"]),
    "constraints": ([["x1 + x2 <= 1.5"], "x1 + x2 <= 1.5"], [["x1 * x2 <= 1"]]),
    "space": ([["a=normal(0,1)", "b=int(1,3)"]], [["a=nope"]]),
    "correlation": (["1,0.5;0.5,1", [[1, 0.5], [0.5, 1]]], ["1,x"]),
}

# The other keywords with which an option's good value runs, where those of its groups
# do not do.
COMPANY = {
    "extend": dict(n=3),
    "nested": dict(n=None, d=2),
    "region": dict(n=8, box=[-1, 1, -1, 1], steps=5),
    "box": dict(n=8, region=DISC, steps=5),
    "shape": dict(n=8, d=2, steps=5),
    "constraints": dict(n=8, box=[0, 1, 0, 1], steps=5),
    "mixture": dict(n=8, d=3, steps=5),
    "space": dict(n=8),
    "correlation": dict(n=8, space=NORMALS),
}

METRICS_COMPANY = {
    "region": dict(x=OLD, box=[-1, 1, -1, 1]),
    "box": dict(x=OLD, region=DISC),
    "constraints": dict(x=OLD, box=[0, 1, 0, 1]),
    "mixture": dict(x=MIX),
}

# A region in which every option of the paper's pipeline runs.
REGION = dict(n=8, d=2, shape="ball:1", steps=5)

# Rules of one option rather than of a group: (option, function, keywords, what the
# refusal names besides the option).
RULES = [
    ("n", "generate", dict(n=9, d=2, nested=[4, 8]), "nested"),
    ("s", "generate", dict(n=3, d=3, extend=OLD), "extend"),
    ("method", "generate", dict(n=8, d=2, method="paper", goal="integration"), "goal"),
    ("correlation", "generate", dict(n=8, d=2, correlation="1,0.5;0.5,1"), "space"),
    # A region is given one way.
    ("constraints", "metrics", dict(x=OLD, constraints=["x1 <= 1"], box=[0, 1, 0, 1], region="x"), "region"),
    ("region", "metrics", dict(x=OLD, region="x", constraints=["x1 <= 1"], box=[0, 1, 0, 1]), "constraints"),
    ("shape", "metrics", dict(x=OLD, shape="ball:1", constraints=["x1 <= 1"], box=[0, 1, 0, 1]), "constraints"),
    ("mixture", "metrics", dict(x=MIX, mixture=True, region="x", box=[0, 1, 0, 1, 0, 1]), "region"),
    ("box", "metrics", dict(x=OLD, box=[0, 1, 0, 1]), "region"),
    ("exact", "metrics", dict(x=OLD, exact=True, shape="ball:1"), "region"),
]

GENERATE = [o for o in sp._core.options("generate") if o["python"] is not None]
EVAL = [o for o in sp._core.options("eval") if o["python"] is not None]


def num(v):
    """A number as a caller would write it: 0, not 0.0."""
    return int(v) if v == int(v) else v


def values(o):
    """The good and bad values of the option's kind, or None for a kind with none to
    make up."""
    if o["name"] in EXAMPLES:
        return EXAMPLES[o["name"]]
    kind, words = o["kind"], list(o["words"])
    lo = o.get("min")
    if kind == "count":
        bad = ["x", 1.5, lo - 1 if lo > 0 else -1]
        if o["max"] < 2**64 - 1:
            bad.append(o["max"] + 1)
        return [lo, min(lo + 3, o["max"])], bad
    if kind == "seed":
        return [0, 3], [-1, "x"]
    if kind == "real":
        below = o.get("below")
        good = [num((lo + below) / 2 if below is not None else lo + 1)]
        bad = ["x"]
        if o["closed"]:
            good.append(num(lo))
            bad.append(num(lo - 1))
        else:
            bad.append(num(lo))
        if below is not None:
            bad.append(below)
        return good, bad
    if kind == "real_or_word":
        return words + [num(lo + 1)], ["nope", num(lo - 1 if o["closed"] else lo)]
    if kind == "word":
        return words, ["nope"]
    if kind == "word_or_points":
        return words, ["nope", FAR]
    if kind == "points":
        return [OLD], [FAR]
    if kind == "numbers":
        return [[0, 1, 0, 1], "0,1,0,1"], ["0,x"]
    if kind == "sizes":
        return [[4, 8], "4,8"], [[8, 4], [0, 4], "x"]
    if kind == "flag":
        return [True], ["maybe"]
    return None


def context(o, function):
    if function == "metrics":
        return dict(METRICS_COMPANY.get(o["name"], dict(x=OLD)))
    if o["name"] in COMPANY:
        return dict(COMPANY[o["name"]])
    args = dict(n=8, d=2)
    if "paper" in o["groups"]:
        args["steps"] = 5  # a short descent: the walk checks options, not the pipeline
    args.pop(o["python"], None)
    return args


def group_rules(o, given):
    """The combinations the option's groups refuse in ``generate``, each with what the
    refusal names besides the option."""
    design = "design space" in o["groups"]
    cube = dict(n=8) if design else dict(n=8, d=2)
    rules = []
    # A design space is dealt from a baseline's set as from any other.
    if "baseline" not in o["groups"] and not design:
        rules.append(({**cube, "method": "sobol", **given}, "sobol"))
    if "paper" in o["groups"] or "descent" in o["groups"]:
        rules.append(({**cube, "goal": "integration", **given}, "goal"))
    if "placement" in o["groups"]:
        rules.append(({"n": 8, "space": NORMALS, **given}, "space"))
    return rules


def walk(o, function):
    call = getattr(sp, function)
    key = o["python"]
    made = values(o)
    assert made is not None, f"{o['name']}: no values to walk (add it to EXAMPLES)"
    good, bad = made
    for v in good:
        # Every good value runs: with the option's company, or, for an option of the
        # paper's pipeline, in a region (whose energies the cube refuses).
        try:
            call(**{**context(o, function), key: v})
        except ValueError:
            if function != "generate" or "paper" not in o["groups"]:
                raise
            call(**{**REGION, key: v})
    for v in bad:
        with pytest.raises((ValueError, TypeError)) as e:
            call(**{**context(o, function), key: v})
        text = str(e.value)
        assert f"invalid {key}" in text, text
        assert "--" not in text, text
        if isinstance(v, (str, int, float)) and not isinstance(v, bool):
            assert str(v) in text, text
    rules = group_rules(o, {key: good[0]}) if function == "generate" else []
    rules += [(kw, other) for name, f, kw, other in RULES if name == o["name"] and f == function]
    for kw, other in rules:
        with pytest.raises(ValueError) as e:
            call(**kw)
        text = str(e.value)
        assert text.startswith("invalid "), text
        assert key in text and other in text, f"{kw}: {text}"
        assert "--" not in text, text


@pytest.mark.parametrize("option", GENERATE, ids=lambda o: o["name"])
def test_every_option_of_generate_is_walked_from_its_declaration(option):
    walk(option, "generate")


METRICS_KEYS = set(inspect.signature(sp.metrics).parameters) - {"x"}


@pytest.mark.parametrize(
    "option",
    [o for o in EVAL if o["python"] in METRICS_KEYS],
    ids=lambda o: o["name"],
)
def test_every_option_of_metrics_is_walked_from_its_declaration(option):
    walk(option, "metrics")


def test_metrics_takes_only_options_of_eval():
    eval_keys = {o["python"] for o in EVAL}
    assert METRICS_KEYS <= eval_keys, METRICS_KEYS - eval_keys


def test_generate_accepts_exactly_the_declared_keywords():
    declared = {o["python"] for o in GENERATE}
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
    for o in GENERATE:
        assert f"``{o['python']}`` (``{o['cli']}``" in doc, o["python"]
        assert o["doc"] in doc, o["python"]
