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


# --- seeds: None draws a fresh seed everywhere, the default stays 0 ----------------------


def _mean_product(x):
    return float(np.mean(np.prod(x, axis=1)))


@pytest.mark.parametrize("n, d", [(64, 3), (100, 2), (37, 5)])
def test_eight_fresh_randomisations_differ_and_give_an_error_bar(n, d):
    sets = [sp.generate(n, d, randomize=True, seed=None) for _ in range(8)]
    assert len({x.tobytes() for x in sets}) == 8
    estimates = [_mean_product(x) for x in sets]
    assert np.std(estimates, ddof=1) > 0
    # Omitted, the seed is 0, as it always was: the same set every time.
    assert np.array_equal(sp.generate(n, d, randomize=True), sp.generate(n, d, randomize=True, seed=0))


@pytest.mark.parametrize(
    "call",
    [
        lambda seed: sp.generate(32, 2, randomize="cells", seed=seed),
        lambda seed: sp.baseline("sobol", 32, 3, seed=seed),
        lambda seed: sp.baseline("lhs", 32, 3, seed=seed),
        lambda seed: sp.generate(32, 2, method="paper", steps=5, init="random", seed=seed),
    ],
)
def test_seed_none_is_fresh_and_the_default_is_fixed(call):
    assert not np.array_equal(call(None), call(None))
    assert np.array_equal(call(0), call(0))


@pytest.mark.parametrize(
    "space", [["x=uniform(0,1)", "y=normal(0,1)"], ["k=int(1,5)", "c={a,b}", "z=uniform(0,1)"], {"t": "uniform(2,3)", "u": "normal(0,1)"}]
)
def test_a_fresh_design_reports_its_seed_and_is_made_again_from_it(space):
    a, b = sp.design(24, space, seed=None), sp.design(24, space, seed=None)
    assert a.seed != b.seed and not np.array_equal(a.unit, b.unit)
    again = sp.design(24, space, seed=a.seed)
    assert np.array_equal(again.unit, a.unit)
    assert sp.design(24, space).seed == 0
    table = sp.generate(24, space=space, seed=None)
    seed = table.attrs["seed"]
    assert sp.generate(24, space=space, seed=seed).equals(table)


def test_an_engines_fresh_generate_seed_is_drawn_once_and_shown():
    import copy
    import pickle

    e = sp.Engine(2, randomize="cells", generate_seed=None, seed=1)
    seed = e._generate_kwargs["seed"]
    assert isinstance(seed, int) and f"seed={seed}" in repr(e)
    same = sp.Engine(2, randomize="cells", generate_seed=seed, seed=1)
    assert np.array_equal(e.random(16), same.random(16))
    other = sp.Engine(2, randomize="cells", generate_seed=None, seed=1)
    assert other._generate_kwargs["seed"] != seed
    # A copy and a pickle randomise the same set: the seed travels with the engine.
    e.reset()
    for twin in (copy.deepcopy(e), pickle.loads(pickle.dumps(e))):
        assert np.array_equal(twin.random(16), sp.Engine(2, randomize="cells", generate_seed=seed, seed=1).random(16))


def test_generate_many_draws_a_fresh_seed_per_request():
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(2) as pool:
        out = sp.generate_many([{"n": 32, "d": 2, "randomize": True, "seed": None}] * 4, executor=pool)
        fixed = sp.generate_many([{"n": 32, "d": 2, "randomize": True}] * 2, executor=pool)
    assert len({x.tobytes() for x in out}) == 4
    assert np.array_equal(fixed[0], fixed[1])


# --- every refusal a ValueError or TypeError naming the argument --------------------------

_X = np.random.default_rng(0).random((20, 2))

_ARGUMENT_CALLS = {
    "n": lambda v: sp.generate(v, 2),
    "d": lambda v: sp.generate(8, v),
    "seed": lambda v: sp.generate(8, 2, seed=v),
    "steps": lambda v: sp.generate(8, 2, steps=v),
    "target": lambda v: sp.generate(8, 2, target=v),
    "bounds": lambda v: sp.generate(8, 2, bounds=v),
    "shape": lambda v: sp.generate(8, 2, shape=v),
    "randomize": lambda v: sp.generate(8, 2, randomize=v),
    "nested": lambda v: sp.generate(None, 2, nested=v),
    "space": lambda v: sp.design(8, v),
    "correlation": lambda v: sp.design(8, ["x=uniform(0,1)", "y=normal(0,1)"], correlation=v),
    "optimization": lambda v: sp.Engine(2, optimization=v),
    "draws": lambda v: sp.Engine(2, draws=v),
    "rng": lambda v: sp.Engine(2, rng=v),
    "requests": lambda v: sp.generate_many(v),
    "executor": lambda v: sp.generate_many([{"n": 4, "d": 2}], executor=v),
    "x": lambda v: sp.metrics(v),
    "box": lambda v: sp.metrics(_X, region="x1-0.5", box=v),
    "constraints": lambda v: sp.metrics(_X, box=[0, 1, 0, 1], constraints=v),
    "exact": lambda v: sp.metrics(_X, exact=v),
}


class _Opaque:
    def __repr__(self):
        return "_Opaque()"


@pytest.mark.parametrize("name", sorted(_ARGUMENT_CALLS))
@pytest.mark.parametrize("value", ["abc", 1.5, -1, 2**70, [1], {"a": 1}, _Opaque(), float("nan")])
def test_a_bad_argument_is_a_value_or_type_error_naming_it(name, value):
    from concurrent.futures import ThreadPoolExecutor

    if name == "executor" and value == "abc":
        value = ThreadPoolExecutor  # the class, not an executor
    try:
        _ARGUMENT_CALLS[name](value)
    except (ValueError, TypeError) as e:
        assert name in str(e), (name, value, str(e))
    # Some values are accepted (a float seed that is whole, ...): no other exception.
