"""Mixed design spaces from Python: the same design as the command line, balance and
slices as promised, marginals equal to SciPy's quantiles, structured results, refusals."""

import pickle

import numpy as np
import pytest
from scipy import stats

import stillpoint as sp

SPACE = ["x=uniform(0,1)", "y=uniform(-2,2)", "k=int(1,5)", "c={a,b,c}"]


def test_a_design_is_the_cli_csv(cli, tmp_path):
    out = tmp_path / "d.csv"
    args = ["generate", "-n", 30, "-q", "-o", out]
    for v in SPACE:
        args += ["--var", v]
    cli(*args)
    rows = [l.split(",") for l in out.read_text().splitlines() if not l.startswith("#")]
    assert rows[0] == ["x", "y", "k", "c"]
    d = sp.design(30, SPACE)
    assert [float(r[0]) for r in rows[1:]] == list(d.columns["x"])
    assert [float(r[1]) for r in rows[1:]] == list(d.columns["y"])
    assert [int(r[2]) for r in rows[1:]] == list(d.columns["k"])
    assert [r[3] for r in rows[1:]] == list(d.columns["c"])


def test_levels_are_balanced_and_slices_stratified():
    d = sp.design(60, SPACE, seed=3)
    counts = {label: int(np.sum(d.columns["c"] == label)) for label in "abc"}
    assert counts == {"a": 20, "b": 20, "c": 20}
    assert sorted(np.bincount(d.columns["k"])[1:]) == [12] * 5
    for label in "abc":
        rows = d.columns["c"] == label
        for name in ("x", "y"):
            u = d.unit[rows, SPACE.index(next(v for v in SPACE if v.startswith(name + "=")))]
            assert sorted(np.floor(u * 20).astype(int)) == list(range(20))
    assert d.figures["slices"][0]["stratified"] == d.figures["slices"][0]["columns"] == 6


@pytest.mark.parametrize(
    "text, frozen",
    [
        ("normal(1.5,2)", stats.norm(1.5, 2)),
        ("lognormal(0.3,0.7)", stats.lognorm(s=0.7, scale=np.exp(0.3))),
        ("beta(2,5)", stats.beta(2, 5)),
        ("beta(0.5,0.5,-1,3)", stats.beta(0.5, 0.5, loc=-1, scale=4)),
        ("triangular(0,0.3,2)", stats.triang(0.15, loc=0, scale=2)),
        ("truncnormal(0,1,-1,2)", stats.truncnorm(-1, 2)),
        ("uniform(-3,5)", stats.uniform(-3, 8)),
    ],
)
def test_marginals_are_scipys_quantiles_of_the_same_uniform_set(text, frozen):
    d = sp.design(64, [f"v={text}", "w=uniform(0,1)"], seed=1)
    want = frozen.ppf(d.unit[:, 0])
    np.testing.assert_allclose(d.columns["v"], want, rtol=1e-12, atol=1e-12)


def test_a_scipy_frozen_distribution_maps_through_its_ppf():
    g = stats.gamma(2.5, scale=1.3)
    d = sp.design(40, {"g": g, "c": ["lo", "hi"], "k": range(0, 4)})
    np.testing.assert_array_equal(d.columns["g"], g.ppf(d.unit[:, 0]))
    assert sorted(set(d.columns["c"])) == ["hi", "lo"]
    assert sorted(set(d.columns["k"].tolist())) == [0, 1, 2, 3]


def test_generate_with_space_returns_a_table():
    t = sp.generate(12, space={"x": "uniform(0,1)", "c": ["a", "b"]})
    pd = pytest.importorskip("pandas")
    assert isinstance(t, pd.DataFrame)
    assert list(t.columns) == ["x", "c"] and len(t) == 12


def test_a_design_pickles_and_its_figures_match_design_figures():
    d = sp.design(24, SPACE)
    back = pickle.loads(pickle.dumps(d))
    assert back.figures == d.figures and np.array_equal(back.unit, d.unit)
    f = sp.design_figures(d.columns, SPACE)
    assert f == d.figures


@pytest.mark.parametrize(
    "space, message",
    [
        (["c={}"], "non-empty labels"),
        (["x=normal(0,-1)"], "sigma"),
        (["x=beta(2,-1)"], "beta"),
        (["k=int(3,1)"], "lo ≤ hi"),
        (["x=weibull(1)"], "one of uniform"),
        ({"c": []}, "expected a type"),
    ],
)
def test_bad_spaces_are_refused_with_the_variable_named(space, message):
    with pytest.raises(ValueError, match="space") as e:
        sp.design(10, space)
    assert message in str(e.value)


def test_too_few_points_for_the_levels_is_refused():
    with pytest.raises(ValueError, match="at least 4 points"):
        sp.design(3, ["c={a,b,c,d}"])
    with pytest.raises(ValueError, match="bounds"):
        sp.generate(10, space=["x=uniform(0,1)"], bounds=(0, 1))


def test_a_correlation_is_kept_and_measured_on_the_independent_scores():
    r = [[1.0, 0.7], [0.7, 1.0]]
    d = sp.design(400, ["x=normal(0,1)", "y=lognormal(0,0.5)", "c={a,b}"], correlation=r)
    z = np.corrcoef(d.columns["x"], np.log(d.columns["y"]))[0, 1]
    assert abs(z - 0.7) < 0.02
    # The written values go back to the same scores: the same figures.
    f = sp.design_figures(d.columns, d.space, correlation=r)
    assert abs(f["centered_l2"] - d.figures["centered_l2"]) < 1e-10
    assert f["slices"][0]["stratified"] == f["slices"][0]["columns"]
    with pytest.raises(ValueError, match="positive definite"):
        sp.design(10, ["x=uniform(0,1)", "y=uniform(0,1)", "z=uniform(0,1)"],
                  correlation=[[1, 0.9, -0.9], [0.9, 1, 0.9], [-0.9, 0.9, 1]])
    with pytest.raises(ValueError, match="correlation"):
        sp.generate(10, 2, correlation=r)


def test_without_pandas_a_table_is_a_dict_of_columns(monkeypatch):
    import sys

    # A module set to None makes its import raise ImportError, as when it is absent.
    monkeypatch.setitem(sys.modules, "pandas", None)
    t = sp.generate(12, space={"x": "uniform(0,1)", "c": ["a", "b"]})
    assert isinstance(t, dict) and list(t) == ["x", "c"]
    assert sorted(t["c"].tolist()) == ["a"] * 6 + ["b"] * 6
