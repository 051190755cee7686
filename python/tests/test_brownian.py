"""Brownian paths in Python spaces: ``space={'W': 'brownian(T,m,construction)'}`` gives
m columns W_1 … W_m with the Brownian covariance, in ``design``, ``design_figures`` and
``quad(space=…)`` (up to 1 000 coordinates), and bad parameters are refused naming
``space``, the text and what is accepted."""

import numpy as np
import pytest

import stillpoint as sp


def test_design_writes_named_columns_with_the_path_as_typed():
    d = sp.design(64, {"S0": "lognormal(4.6,0.1)", "W": "brownian(1,8,bridge)"})
    assert d.names == ["S0"] + [f"W_{i}" for i in range(1, 9)]
    assert list(d.columns) == d.names
    assert all(np.all(np.isfinite(d.columns[name])) for name in d.names)
    assert "W=brownian(1,8,bridge)" in d.space
    # The figures of the table read back are the design's own.
    table = d.columns
    space = {"S0": "lognormal(4.6,0.1)", "W": "brownian(1,8,bridge)"}
    assert sp.design_figures(table, space) == d.figures


@pytest.mark.parametrize("construction", ["standard", "bridge", "pca"])
def test_quad_gives_the_brownian_covariance(construction):
    # E[W(t_i) W(t_j)] = min(t_i, t_j): three of them at once, each within 1e-2.
    t = 2.0

    def f(x):
        return np.stack([x[:, 0] * x[:, 3], x[:, 1] ** 2, x[:, 2] * x[:, 3]], axis=1)

    r = sp.quad(f, 4, space={"W": f"brownian({t},4,{construction})"}, abs_tol=1e-2, seed=3)
    assert r.met
    want = np.array([0.5, 1.0, 1.5])
    assert np.all(np.abs(np.asarray(r.estimate) - want) < 2e-2), r.estimate


def test_quad_reaches_a_thousand_step_path():
    # E[W(T)²] = T for the last column of a 1000-step path (mixed with a normal).
    r = sp.quad(
        lambda x: x[:, 999] ** 2,
        1000,
        space=["W=brownian(0.5,1000,pca)"],
        abs_tol=0.05,
        max_n=2**14,
        seed=1,
    )
    assert r.met and abs(r.estimate - 0.5) < 0.1, r
    with pytest.raises(ValueError, match="space has 1000 coordinates"):
        sp.quad(lambda x: x[:, 0], 999, space=["W=brownian(0.5,1000,pca)"])


@pytest.mark.parametrize(
    "spec, says",
    [
        ("brownian(0,4)", "T = 0"),
        ("brownian(1,0)", "m = 0"),
        ("brownian(1,5000,pca)", "m = 5000"),
        ("brownian(1,4,cholesky)", "pca (the default), bridge or standard"),
    ],
)
def test_bad_paths_are_refused_naming_space_and_the_text(spec, says):
    with pytest.raises(ValueError) as e:
        sp.design(16, {"W": spec})
    msg = str(e.value)
    assert "space" in msg and f"W={spec}" in msg and says in msg, msg


def test_a_correlation_that_counts_the_path_names_it():
    with pytest.raises(ValueError, match=r"W=brownian\(1,2,pca\)"):
        sp.design(
            16,
            {"x": "normal(0,1)", "y": "normal(0,1)", "W": "brownian(1,2)"},
            correlation=np.eye(4),
        )
