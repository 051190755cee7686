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


def test_draws_are_shifts_of_the_optimised_set():
    base = sp.generate(64, 3)
    e = sp.Engine(3, seed=2)
    a, b = e.random(64), e.random(64)
    assert not np.array_equal(a, b)
    for draw in (a, b):
        shift = (draw - base) % 1.0
        # One shift for the whole set (up to rounding across the wrap).
        spread = np.abs(((shift - shift[0] + 0.5) % 1.0) - 0.5)
        assert spread.max() < 1e-12
    # The shift preserves the wrap-around discrepancy.
    assert abs(sp.discrepancy(a, "wd") - sp.discrepancy(base, "wd")) < 1e-9


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
    shift = (x[0] - base[0]) % 1.0
    np.testing.assert_allclose((base + shift) % 1.0, x, atol=1e-12)
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
