"""stillpoint.Engine as a SciPy QMC engine."""

import numpy as np
import pytest
from scipy.integrate import qmc_quad
from scipy.stats import qmc

import stillpoint as sp


def test_is_a_qmc_engine():
    e = sp.Engine(3, seed=1)
    assert isinstance(e, qmc.QMCEngine)
    x = e.random(64)
    assert x.shape == (64, 3) and x.dtype == np.float64
    assert np.all((x >= 0) & (x < 1))
    assert e.num_generated == 64


def assert_cell_randomisation(base, draw):
    """``draw`` is ``base`` with, per coordinate, the cells rotated by one m and the
    offsets within them shifted by one v modulo the cell."""
    n = base.shape[0]
    cells_base, cells_draw = np.floor(base * n), np.floor(draw * n)
    for k in range(base.shape[1]):
        # A stratified column stays stratified.
        if sorted(cells_base[:, k]) == list(range(n)):
            assert sorted(cells_draw[:, k]) == list(range(n))
        turn = (cells_draw[:, k] - cells_base[:, k]) % n
        assert np.all(turn == turn[0])
        move = (draw[:, k] * n - cells_draw[:, k]) - (base[:, k] * n - cells_base[:, k])
        move %= 1.0
        spread = np.abs(((move - move[0] + 0.5) % 1.0) - 0.5)
        assert spread.max() < 1e-9


def test_cell_draws_are_stratified_randomisations_of_the_optimised_set():
    base = sp.generate(64, 3)
    e = sp.Engine(3, seed=2, randomize="cells")
    a, b = e.random(64), e.random(64)
    assert not np.array_equal(a, b)
    for draw in (a, b):
        assert_cell_randomisation(base, draw)
        assert sp.metrics(draw)["stratified"]


def test_default_draws_are_the_tent_lattice_shifted_and_folded():
    d, n = 3, 50
    e = sp.Engine(d, seed=4)
    lattice = sp._core.tent_set(n, d)
    draws = [e.random(n) for _ in range(300)]
    for x in draws[:20]:
        assert np.all((x >= 0) & (x < 1))
        assert sp.metrics(x)["stratified"]
    # generate's randomize=True is the same lattice, randomised the same way.
    assert np.array_equal(
        sp.generate(n, d, randomize=True, seed=11), sp._core.randomize(lattice, "tent", 11)
    )
    # Unbiased: the mean of x1·x2·x3 over the draws is 1/8 within 4 standard errors.
    est = np.array([np.prod(x, axis=1).mean() for x in draws])
    se = est.std(ddof=1) / np.sqrt(len(est))
    assert abs(est.mean() - 0.125) < 4 * se


def test_draws_stay_stratified_and_unbiased_where_a_lattice_must_share_generators():
    # 32 points have 8 lattice generators up to sign: in 12 dimensions the set is the one
    # descended from the lattice, each column still the 32 multiples of 1/32.
    d, n = 12, 32
    base = sp._core.tent_set(n, d)
    assert all(np.array_equal(np.sort(np.round(base[:, j] * n)), np.arange(n)) for j in range(d))
    e = sp.Engine(d, seed=2)
    draws = [e.random(n) for _ in range(300)]
    for x in draws[:20]:
        assert np.all((x >= 0) & (x < 1))
        assert sp.metrics(x)["stratified"]
    # Unbiased: prod(1 + (x - 1/2)) integrates to 1.
    est = np.array([np.prod(0.5 + x, axis=1).mean() for x in draws])
    se = est.std(ddof=1) / np.sqrt(len(est))
    assert abs(est.mean() - 1.0) < 4 * se


def test_reset_and_fast_forward():
    e = sp.Engine(2, seed=3)
    first, second = e.random(32), e.random(32)
    e.reset()
    assert np.array_equal(e.random(32), first)
    f = sp.Engine(2, seed=3)
    f.fast_forward(32)
    assert f.num_generated == 32
    assert np.array_equal(f.random(32), second)


def test_seeds_and_generators():
    a = sp.Engine(2, seed=5).random(16)
    assert np.array_equal(a, sp.Engine(2, seed=5).random(16))
    assert np.array_equal(a, sp.Engine(2, rng=5).random(16))
    assert not np.array_equal(a, sp.Engine(2, seed=6).random(16))
    g = np.random.default_rng(9)
    assert sp.Engine(2, seed=g).random(16).shape == (16, 2)
    with pytest.raises(ValueError, match="seed and rng"):
        sp.Engine(2, seed=1, rng=2)


def test_generate_kwargs_and_cache():
    e = sp.Engine(2, seed=0, steps=20, energy="e-inf", shifts=0)
    base = sp.generate(40, 2, steps=20, energy="e-inf", shifts=0)
    x = e.random(40)
    assert_cell_randomisation(base, x)
    assert "energy='e-inf'" in repr(e)


def test_qmc_quad_within_four_standard_errors():
    # ∫ over [0, 2]^3 of exp(x1 + x2 + x3) = (e^2 - 1)^3.
    exact = (np.e**2 - 1) ** 3
    res = qmc_quad(
        lambda x: np.exp(x.sum(axis=0)),
        [0, 0, 0],
        [2, 2, 2],
        n_estimates=8,
        n_points=128,
        qrng=sp.Engine(3, seed=11),
    )
    assert res.standard_error > 0
    assert abs(res.integral - exact) < 4 * res.standard_error
    # Better than plain Monte Carlo's standard error at this n by far.
    assert res.standard_error < 0.02 * exact


def test_scipy_optimization_is_applied():
    e = sp.Engine(2, seed=1, optimization="random-cd")
    x = e.random(32)
    assert x.shape == (32, 2) and np.all((x >= 0) & (x <= 1))
