"""Defect families of the Python front end, each tried with its repro and variants:
every refusal is a ValueError naming the argument as the caller wrote it."""

import numpy as np
import pytest

import stillpoint as sp


@pytest.mark.parametrize(
    "bounds",
    [
        ([-1e308, 0], [1e308, 1]),
        (-1e308, 1e308),
        ([0, 0], [1e-320, 1]),
        ([1, 0], [1 + 1e-15, 1]),
        ([0, np.inf], [1, 2]),
        ([0, 0, 0], [1, 1, 1]),
        ([1, 0], [0, 1]),
    ],
)
def test_bounds_get_the_command_lines_check(bounds):
    with pytest.raises(ValueError, match=r"^invalid bounds = "):
        sp.generate(20, 2, bounds=bounds)


def test_bounds_scale_like_scipy():
    x = sp.generate(32, 2)
    y = sp.generate(32, 2, bounds=([-1, 10], [1, 20]))
    np.testing.assert_array_equal(y, np.array([-1.0, 10.0]) + x * np.array([2.0, 10.0]))


def test_wrappers_pass_their_arguments_to_the_library():
    old = sp.generate(20, 2)
    with pytest.raises(ValueError, match=r"^invalid d = 3: expected the dimension of points, 2"):
        sp.extend(old, 5, d=3)
    with pytest.raises(ValueError, match=r"^invalid m = 0"):
        sp.extend(old, 0)
    grown = sp.extend(old, 5, d=2)
    np.testing.assert_array_equal(grown[:20], old)
    np.testing.assert_array_equal(sp.nested("8,16", 2), sp.nested([8, 16], 2))
    with pytest.raises(ValueError, match=r"^invalid sizes = 16,8: expected increasing"):
        sp.nested("16,8", 2)
    with pytest.raises(ValueError, match=r"^invalid sizes"):
        sp.nested([8, 8], 2)


@pytest.mark.parametrize("kind", ["cells", "shift"])
def test_grown_sets_are_never_randomised(kind):
    old = sp.generate(20, 2)
    with pytest.raises(ValueError, match="no randomisation of a grown set"):
        sp.extend(old, 5, randomize=kind)
    with pytest.raises(ValueError, match="no randomisation of a grown set"):
        sp.nested([8, 16], 2, randomize=kind)


def test_region_extension_of_another_dimension_is_refused():
    disc = sp.generate(10, shape="ball:2@0,0", steps=50)
    with pytest.raises(ValueError, match="dimension"):
        sp.extend(disc, 5, shape="ball:2", d=3)


def test_a_user_integrand_that_is_not_finite_is_refused():
    x = sp.generate(16, 2)
    with pytest.raises(ValueError, match=r"^invalid f: f\(x\) is nan at point 1"):
        sp.integrate(x, lambda p: np.full(len(p), np.nan))
    assert np.isfinite(sp.integrate(x, lambda p: p[:, 0]))


def test_engine_random_zero_is_empty():
    e = sp.Engine(3)
    assert e.random(0).shape == (0, 3)
