"""Every option of ``quad`` and ``sobol_indices`` as the library declares it
(``stillpoint._core.options(command=...)``), walked: a good value is taken, a bad one is
refused naming the keyword and echoing the value as typed, and given with ``start=`` each
is honoured or refused by name. The examples come from each declaration's kind, so a new
option is walked without editing this file."""

import re

import numpy as np
import pytest

import stillpoint as sp

COMMANDS = {"quad": sp.quad, "sensitivity": sp.sobol_indices}
# Python spells the declared box as its corners apart (``a``, ``b``); ``start`` is the
# earlier result itself, walked below.
SPACE = {"x": "normal(0,1)", "y": "normal(0,1)"}


def f(x):
    return x[:, 0] + 2 * x[:, 1] + x[:, 0] * x[:, 1]


def declared(command):
    return [o for o in sp._core.options(command=command) if o["kind"] != "front_end"]


def good(o, command):
    """A value the declaration accepts, with what it needs beside it."""
    kind, default = o["kind"], o["default"].get(command)
    if o["name"] == "bounds":
        return {"a": [0, 0], "b": [2, 1]}
    if kind == "texts":
        return {o["python"]: {"x": "uniform(0,1)", "y": "uniform(1,2)"}}
    if kind == "rows":
        return {o["python"]: "1,0.5;0.5,1", "space": SPACE}
    if kind == "word":
        return {o["python"]: o["words"][-1]}
    if kind == "flag":
        return {o["python"]: True}
    if kind == "seed":
        return {o["python"]: 7}
    if kind == "count":
        return {o["python"]: int(default) if default else 2}
    return {o["python"]: float(default) if default else 0.5}


def bad(o):
    """Values the declaration refuses, and the text each refusal must echo."""
    kind, kw = o["kind"], o["python"]
    if o["name"] == "bounds":
        return [({"a": [0, 2], "b": [1, 1]}, "a, b = ([0, 2], [1, 1])")]
    if kind == "texts":
        return [({kw: ["x=nope(1)", "y=uniform(0,1)"]}, "nope(1)")]
    if kind == "rows":
        return [({kw: "1,a;0.5,1", "space": SPACE}, f"{kw} = ")]
    if kind in ("word", "flag"):
        return [({kw: "nope"}, f"{kw} = 'nope'")]
    if kind in ("count", "seed"):
        return [({kw: v}, f"{kw} = {v!r}") for v in (-1, "x", 1.5)]
    below = o.get("below")
    over = [below] if below is not None else []
    return [({kw: v}, f"{kw} = {v!r}") for v in ["x", -1.0, float("nan")] + over]


def call(command, kwargs):
    kwargs = dict(kwargs)
    d = kwargs.pop("d", 2)
    loose = {"rel_tol": 1e-2} if command == "quad" else {"abs_tol": 0.05}
    return COMMANDS[command](f, d, **{**loose, **kwargs})


def walked():
    return [(c, o) for c in COMMANDS for o in declared(c)]


def test_every_python_keyword_of_both_commands_is_declared():
    import inspect

    for command, fn in COMMANDS.items():
        names = {o["python"] for o in sp._core.options(command=command)}
        keywords = set(inspect.signature(fn).parameters) - {"f", "executor", "progress"}
        # The box is declared once (bounds) and spelled a, b; correlation is refused by
        # sobol_indices by name (its inputs are independent).
        assert keywords - {"a", "b", "correlation"} <= names, command
        assert names - keywords <= {"bounds"}, command


@pytest.mark.parametrize("command, o", walked(), ids=lambda v: v if isinstance(v, str) else v["name"])
def test_a_good_value_is_taken(command, o):
    kwargs = good(o, command)
    if command == "quad" and "abs_tol" in kwargs:
        kwargs["abs_tol"] = 1e-3
    if command == "sensitivity" and "abs_tol" in kwargs:
        kwargs["abs_tol"] = 0.05
    if o["python"] == "level" and command == "sensitivity":
        kwargs["level"] = 0.9
    r = call(command, kwargs)
    assert r.n > 0


@pytest.mark.parametrize("command, o", walked(), ids=lambda v: v if isinstance(v, str) else v["name"])
def test_a_bad_value_is_refused_naming_the_keyword_and_echoing_it(command, o):
    for kwargs, echoed in bad(o):
        with pytest.raises(ValueError) as e:
            call(command, kwargs)
        assert str(e.value).startswith("invalid "), e.value
        assert echoed in str(e.value), (kwargs, str(e.value))


@pytest.mark.parametrize("command, o", walked(), ids=lambda v: v if isinstance(v, str) else v["name"])
def test_with_start_each_is_honoured_or_refused_by_name(command, o):
    first = call(command, {"max_n": 40960 if command == "sensitivity" else 4096})
    kwargs = good(o, command)
    kwargs.pop("space", None) if o["kind"] == "rows" else None
    try:
        later = call(command, {**kwargs, "start": first})
    except ValueError as e:
        spelled = "a, b" if o["name"] == "bounds" else o["python"]
        assert re.match(rf"invalid {re.escape(spelled)}\b.* with start|invalid {spelled}\b", str(e)), e
        assert "start" in str(e) or o["python"] == "d", e
    else:
        assert later.n >= first.n


def test_refused_combinations_name_both_options():
    for kwargs, message in [
        ({"space": SPACE, "a": 0}, "invalid a with space"),
        ({"correlation": "1,0.5;0.5,1"}, "invalid correlation without space"),
        ({"space": {"x": "normal(0,1)"}}, "invalid d = 2: space has 1 coordinates"),
    ]:
        for command in COMMANDS:
            if command == "sensitivity" and "correlation" in kwargs:
                message = "invalid correlation = "
            with pytest.raises(ValueError, match=re.escape(message)):
                call(command, kwargs)


def test_the_defaults_users_see_are_the_declared_ones():
    r = sp.quad(f, 2, rel_tol=1e-2)
    defaults = {o["name"]: o["default"]["quad"] for o in declared("quad")}
    abs_tol, rel_tol, level, replicates, max_n, seed = r._state.settings
    assert (replicates, max_n, seed) == tuple(
        int(defaults[k]) for k in ("replicates", "max_n", "seed")
    )
    assert (abs_tol, level) == (float(defaults["abs_tol"]), float(defaults["level"]))
    s = sp.sobol_indices(f, 2, abs_tol=0.05)
    defaults = {o["name"]: o["default"]["sensitivity"] for o in declared("sensitivity")}
    assert s.replicates == int(defaults["replicates"])
    assert s.level == float(defaults["level"])
    assert np.isclose(sp.sobol_indices(f, 2)._state.settings[0], float(defaults["abs_tol"]))


def _said(doc, keyword):
    """The defaults the docstring's entry for ``keyword`` states ("by default X", or
    "by default X and Y" for an entry of two keywords), by keyword."""
    entries = re.split(r"\n    (?=[a-z_, ]+ : )", doc.split("Returns")[0])
    for entry in entries:
        head = entry.split(" : ", 1)[0].split(", ")
        if keyword in head:
            m = re.search(r"by default (?:``)?\"?([\w.^-]+)\"?(?:``)?(?: and ([\w.^-]+))?", entry, re.I)
            return dict(zip(head, (g.rstrip(".") for g in m.groups() if g))) if m else {}
    return {}


def _same(said, declared):
    try:
        return float(eval(said.replace("^", "**"))) == float(declared)
    except (NameError, SyntaxError, ValueError):
        return said.lower() == declared.lower()


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_the_docstring_states_each_declared_default(command):
    # The keywords default to None (a continuation sees which were given): the default
    # users read is the docstring's, which must be the library's.
    doc = COMMANDS[command].__doc__
    checked = 0
    for o in declared(command):
        default = o["default"].get(command)
        if default is None or o["python"] in ("d", "seed"):
            continue
        said = _said(doc, o["python"]).get(o["python"])
        assert said is not None, f"{command}: no default stated for {o['python']}"
        assert _same(said, default), (command, o["python"], said, default)
        checked += 1
    assert checked >= 4
