"""Randomised sets under a space from Python: ``generate(..., space=, randomize=True)``
and ``design(..., randomize=)`` give, for every seed, an unbiased estimate of E f(X)
under the space's law (SciPy laws, texts, integers, labels, a correlation); every
column is the inverse-CDF image of the randomised unit-cube set, the same as the command
line's file with its rule in the header; what stays unsupported is refused by name."""

import numpy as np
import pytest
from scipy import stats

import stillpoint as sp

# Independent laws of every kind: a SciPy law (mapped by its ppf), texts, an integer
# range and labels.
SPACE = {
    "x": stats.norm(1.0, 2.0),
    "w": "lognormal(0.3,0.5)",
    "u": "uniform(-1,3)",
    "k": range(1, 5),
    "c": ["a", "b", "c"],
}

# (statistic of a frame, its exact mean under SPACE's law)
EW = np.exp(0.3 + 0.125)
STATS = {
    "x^2+x": (lambda f: f.x**2 + f.x, 6.0),
    "w^2": (lambda f: f.w**2, np.exp(1.1)),
    "u^2": (lambda f: f.u**2, 7.0 / 3.0),
    "k^2": (lambda f: f.k**2, 7.5),
    "1{c=b}": (lambda f: (f.c == "b").astype(float), 1.0 / 3.0),
    "x*k": (lambda f: f.x * f.k, 2.5),
    "w*u": (lambda f: f.w * f.u, EW),
}


def _assert_unbiased(what, estimates, exact):
    est = np.asarray(estimates)
    se = est.std(ddof=1) / np.sqrt(len(est))
    assert abs(est.mean() - exact) <= 4.5 * se + 1e-12 * (1 + abs(exact)), (
        f"{what}: exact {exact}, mean {est.mean()} over {len(est)} seeds, se {se}"
    )


@pytest.mark.parametrize("kind", [True, "cells", "shift"])
def test_every_seed_is_an_unbiased_estimate(kind):
    estimates = {name: [] for name in STATS}
    for seed in range(200):
        frame = sp.generate(32, space=SPACE, randomize=kind, seed=seed)
        assert frame.attrs["seed"] == seed and "inverse CDF" in frame.attrs["rule"]
        for name, (f, _) in STATS.items():
            estimates[name].append(float(np.mean(f(frame))))
    for name, (_, exact) in STATS.items():
        _assert_unbiased(f"{kind} {name}", estimates[name], exact)


def test_a_correlated_space_is_unbiased_too():
    corr = [[1.0, 0.6], [0.6, 1.0]]
    space = ["y1=normal(0,1)", "y2=lognormal(0,0.5)"]
    products, squares = [], []
    for seed in range(200):
        d = sp.design(32, space, correlation=corr, randomize=True, seed=seed)
        assert d.unbiased
        products.append(np.mean(d.columns["y1"] * d.columns["y2"]))
        squares.append(np.mean(d.columns["y2"] ** 2))
    # Stein's lemma: E[Z1 e^{0.5 Z2}] = 0.6 · 0.5 · e^{0.125}; E e^{Z2} = e^{0.5}.
    _assert_unbiased("y1*y2", products, 0.3 * np.exp(0.125))
    _assert_unbiased("y2^2", squares, np.exp(0.5))


def test_columns_are_quantile_images_of_the_randomised_cube_set():
    for kind in (True, "cells", "shift"):
        d = sp.design(40, SPACE, randomize=kind, seed=11)
        cube = sp.generate(40, 5, randomize=kind, seed=11)
        assert np.array_equal(d.unit, cube)
        np.testing.assert_array_equal(d.columns["x"], stats.norm(1.0, 2.0).ppf(cube[:, 0]))
        np.testing.assert_allclose(
            d.columns["w"], stats.lognorm(s=0.5, scale=np.exp(0.3)).ppf(cube[:, 1]), rtol=1e-12
        )
        np.testing.assert_allclose(d.columns["u"], -1 + 4 * cube[:, 2], rtol=1e-15, atol=1e-15)
        assert list(d.columns["k"]) == list(1 + np.minimum(np.floor(cube[:, 3] * 4), 3).astype(int))
        labels = np.array(["a", "b", "c"])[np.minimum(np.floor(cube[:, 4] * 3), 2).astype(int)]
        assert list(d.columns["c"]) == list(labels)
        assert d.unbiased and "inverse CDF" in d.rule
    plain = sp.design(40, SPACE, seed=11)
    assert not plain.unbiased and "by rank" in plain.rule


def test_the_cli_file_is_the_same_design_with_its_rule_in_the_header(cli, tmp_path):
    texts = ["x=normal(1,2)", "k=int(1,4)", "c={a,b,c}"]
    out = tmp_path / "r.csv"
    args = ["generate", "-n", 24, "--randomize", "cells", "--seed", 4, "-o", out]
    for v in texts:
        args += ["--var", v]
    report = cli(*args)
    rule = "set randomised by cells through each law's inverse CDF (levels ⌊u·L⌋, not by rank)"
    assert rule in report
    lines = out.read_text().splitlines()
    assert f'# rule: "{rule}"' in lines
    rows = [l.split(",") for l in lines if not l.startswith("#")][1:]
    d = sp.design(24, texts, randomize="cells", seed=4)
    assert d.rule == rule
    assert [float(r[0]) for r in rows] == list(d.columns["x"])
    assert [int(r[1]) for r in rows] == list(d.columns["k"])
    assert [r[2] for r in rows] == list(d.columns["c"])


@pytest.mark.parametrize(
    "extra, named",
    [
        ({"bounds": [0, 1]}, "bounds"),
        ({"method": "sobol"}, "randomize"),
        ({"goal": "space-filling"}, "randomize"),
        ({"nested": [8, 16]}, "nested"),
    ],
)
def test_what_stays_unsupported_is_refused_by_name(extra, named):
    with pytest.raises(ValueError, match=named):
        sp.generate(16, space=SPACE, randomize=True, **extra)


def test_a_bad_randomisation_under_a_space_echoes_the_value():
    with pytest.raises(ValueError, match="randomize.*nope"):
        sp.generate(16, space=SPACE, randomize="nope")


def test_a_space_holding_a_brownian_path_takes_owen_scrambled_sobol():
    space = {"W": "brownian(1,8,bridge)", "z": "normal(0,1)"}
    d = sp.design(64, space, randomize=True, seed=5)
    assert d.rule.startswith("Owen-scrambled Sobol'") and d.unbiased
    # The net's first column goes to z (not a path), the next eight to the path's steps.
    net = sp.generate(64, 9, method="sobol", seed=5)
    assert np.array_equal(d.unit, net[:, [1, 2, 3, 4, 5, 6, 7, 8, 0]])
    np.testing.assert_allclose(d.columns["z"], stats.norm().ppf(d.unit[:, 8]), rtol=1e-12, atol=1e-14)
    # Each seed's mean of W(t_8)² = W(1)² estimates t_8 = 1, of W(t_2)·W(t_8) estimates
    # min(t_2, t_8) = 1/4, without bias.
    ends, products = [], []
    for seed in range(200):
        d = sp.design(32, space, randomize=True, seed=seed)
        ends.append(np.mean(d.columns["W_8"] ** 2))
        products.append(np.mean(d.columns["W_2"] * d.columns["W_8"]))
    _assert_unbiased("W_8^2", ends, 1.0)
    _assert_unbiased("W_2*W_8", products, 0.25)
