"""The Python API: SciPy's conventions, regions, inputs of any layout, refusals."""

import numpy as np
import pytest
from scipy.stats import qmc

import stillpoint as sp


def rel(a, b):
    return abs(a - b) / max(abs(a), abs(b))


SETS = [
    np.random.default_rng(0).random((200, 5)),
    np.random.default_rng(1).random((300, 3)),
    np.random.default_rng(2).random((37, 12)),
    np.random.default_rng(3).random((1000, 20)),
    sp.baseline("sobol", 128, 3, seed=1),
    sp.generate(64, 2),
]


def close_to_scipy(ours, theirs, scale, n):
    """Within 1e-12 relative, or the rounding of a plain sum of n^2 terms of size
    `scale` (about n eps scale): both codes subtract terms of size `scale` to get the
    value, and SciPy sums the pairs plainly, which alone moves a small value by 1e-12
    relative or more (test_squares_match_exact_arithmetic shows which one is closer
    to the exact value)."""
    return abs(ours - theirs) <= 1e-12 * abs(theirs) + n * np.finfo(float).eps * scale


@pytest.mark.parametrize("x", SETS)
def test_discrepancies_follow_scipy(x):
    n, s = x.shape
    # SciPy's names mean SciPy's measures, convention included: 'L2-star' a root, 'CD',
    # 'WD' and 'MD' (the mixture discrepancy) squares.
    assert rel(sp.discrepancy(x, "L2-star"), qmc.discrepancy(x, method="L2-star")) < 1e-12
    assert close_to_scipy(sp.discrepancy(x, "CD"), qmc.discrepancy(x, method="CD"), (13 / 12) ** s, n)
    assert close_to_scipy(sp.discrepancy(x, "WD"), qmc.discrepancy(x, method="WD"), (4 / 3) ** s, n)
    assert close_to_scipy(
        sp.discrepancy(x, method="MD"), qmc.discrepancy(x, method="MD"), (19 / 12) ** s, n
    )
    # Our names are roots, the values `metrics` reports; 'modified' is not SciPy's 'MD'.
    m = sp.metrics(x)
    own = [("star", "star_l2"), ("modified", "modified_l2"), ("centered", "centered_l2"),
           ("wrap-around", "wrap_around_l2"), ("mixture", "mixture")]
    for kind, key in own:
        assert sp.discrepancy(x, kind) == m[key]
    assert sp.discrepancy(x) == m["modified_l2"]
    assert rel(sp.discrepancy(x, "modified") ** 2, qmc.discrepancy(x, method="MD")) > 1e-3


def test_short_names_keep_their_meaning_with_a_warning():
    x = SETS[0]
    m = sp.metrics(x)
    for short, key, write in [("md", "modified_l2", "'modified'"), ("cd", "centered_l2", "'centered'"),
                              ("wd", "wrap_around_l2", "'wrap-around'")]:
        with pytest.warns(DeprecationWarning, match=write):
            assert sp.discrepancy(x, short) == m[key]
    with pytest.raises(TypeError, match="not both"):
        sp.discrepancy(x, "CD", method="CD")
    with pytest.raises(ValueError, match="invalid method = 'cd2'.*'MD' \\(mixture\\)"):
        sp.discrepancy(x, method="cd2")


def exact_squares(x):
    """CD^2 and WD^2 in rational arithmetic (exact for the given float64 points)."""
    from fractions import Fraction as F

    n, s = x.shape
    X = [[F(float(v)) for v in row] for row in x]
    h = F(1, 2)
    cd1 = sum(_prod(1 + h * abs(v - h) - h * abs(v - h) ** 2 for v in row) for row in X)
    cd2 = F(0)
    wd2 = F(0)
    for a in X:
        for b in X:
            cd2 += _prod(1 + h * abs(u - h) + h * abs(v - h) - h * abs(u - v) for u, v in zip(a, b))
            wd2 += _prod(F(3, 2) - abs(u - v) * (1 - abs(u - v)) for u, v in zip(a, b))
    cd = F(13, 12) ** s - 2 * cd1 / n + cd2 / n**2
    wd = -(F(4, 3) ** s) + wd2 / n**2
    return float(cd), float(wd)


def _prod(values):
    p = 1
    for v in values:
        p *= v
    return p


def test_squares_match_exact_arithmetic():
    x = np.random.default_rng(1).random((150, 3))
    cd, wd = exact_squares(x)
    n, s = x.shape
    # Both within the rounding bound of the closed form (a few 1e-12 relative here).
    for ours, theirs, exact, scale in [
        (sp.discrepancy(x, "centered") ** 2, qmc.discrepancy(x, method="CD"), cd, (13 / 12) ** s),
        (sp.discrepancy(x, "wrap-around") ** 2, qmc.discrepancy(x, method="WD"), wd, (4 / 3) ** s),
    ]:
        assert close_to_scipy(ours, exact, scale, n)
        assert close_to_scipy(theirs, exact, scale, n)


def test_inputs_of_any_layout_and_type():
    x = sp.baseline("halton-scrambled", 100, 4, seed=3)
    want = sp.metrics(x)
    x32 = x.astype(np.float32)
    assert sp.metrics(np.asfortranarray(x)) == want
    assert sp.metrics(x.tolist()) == want
    assert sp.metrics(x[::-1][::-1]) == want
    assert sp.discrepancy(x32, "CD") == sp.discrepancy(x32.astype(np.float64), "CD")
    assert sp.integrate(np.asfortranarray(x)) == sp.integrate(x)
    # A non-contiguous view (every other column).
    wide = np.random.default_rng(4).random((50, 8))
    assert sp.metrics(wide[:, ::2]) == sp.metrics(np.array(wide[:, ::2]))


def test_bounds_scale_like_scipy():
    lo, hi = [-1.0, 0.0, 10.0], [1.0, 5.0, 11.0]
    x = sp.generate(30, 3, steps=50)
    got = sp.generate(30, 3, steps=50, bounds=(lo, hi))
    np.testing.assert_allclose(got, qmc.scale(x, lo, hi), rtol=0, atol=1e-15)


def test_region_points_are_inside():
    ball = sp.generate(40, 3, shape="ball:0.5@1,1,1", steps=300)
    assert ball.shape == (40, 3)
    assert np.all(np.linalg.norm(ball - 1.0, axis=1) <= 0.5)
    diamond = sp.generate(30, None, region="|x| + 2*|y| - 1", box="-1,1,-0.5,0.5", steps=300)
    assert diamond.shape == (30, 2)
    assert np.all(np.abs(diamond[:, 0]) + 2 * np.abs(diamond[:, 1]) <= 1.0)
    simplex = sp.generate(25, 3, shape="simplex", steps=200)
    assert np.all(simplex >= 0) and np.all(simplex.sum(axis=1) <= 1.0)


def test_generate_is_deterministic_and_seeded():
    a = sp.generate(40, 2, init="random", seed=1, steps=100)
    assert np.array_equal(a, sp.generate(40, 2, init="random", seed=1, steps=100))
    assert not np.array_equal(a, sp.generate(40, 2, init="random", seed=2, steps=100))
    start = np.random.default_rng(0).random((40, 2))
    b = sp.generate(40, 2, init=start.astype(np.float32), steps=10)
    assert b.shape == (40, 2) and np.all((b >= 0) & (b < 1))


def test_integrate_a_callable():
    x = sp.baseline("sobol", 1024, 2, seed=5)
    est = sp.integrate(x, lambda p: p[:, 0] * p[:, 1])
    assert isinstance(est, float) and abs(est - 0.25) < 1e-3
    with pytest.raises(ValueError, match="invalid f"):
        sp.integrate(x, lambda p: p)


def test_baselines_are_described():
    names = sp.baselines()
    assert {"sobol", "halton", "halton-scrambled", "lhs", "lhs-maximin", "random"} <= names.keys()
    assert all(len(text) > 40 for text in names.values())


@pytest.mark.parametrize(
    "call, names",
    [
        (lambda: sp.generate(0, 2), "invalid n = 0"),
        (lambda: sp.generate(-3, 2), "invalid n = -3"),
        (lambda: sp.generate(2.5, 2), "invalid n = 2.5"),
        (lambda: sp.generate(10, 0), "invalid d = 0"),
        (lambda: sp.generate(2**70, 2), "invalid n = 1180591620717411303424"),
        (lambda: sp.generate(10**12, 20), "invalid n = 1000000000000: expected at least 1 point, at most"),
        (lambda: sp.generate(10, 2, seed=-1), "invalid seed = -1"),
        (lambda: sp.generate(10, 2, steps=0), "invalid steps = 0"),
        (lambda: sp.generate(10, 2, energy="nope"), "invalid energy"),
        (lambda: sp.generate(10, 2, energy="e-inf-g"), "invalid energy"),
        (lambda: sp.generate(10, 2, integrator="rk4"), "invalid integrator"),
        (lambda: sp.generate(10, 2, method="nope"), "invalid method"),
        (lambda: sp.generate(10, 2, method="sobol", steps=5), "invalid steps"),
        (lambda: sp.generate(10, 2, q=-1), "invalid q"),
        (lambda: sp.generate(10, 2, p=0), "invalid p"),
        (lambda: sp.generate(10, 2, polish="xyz"), "invalid polish"),
        (lambda: sp.generate(10, 2, kappa=0.5), "invalid kappa"),
        (lambda: sp.generate(10, 2, colour="blue"), "invalid keyword argument = colour"),
        (lambda: sp.generate(10, 2, goal="l2star-not-yet"), "invalid goal"),
        (lambda: sp.generate(10, 2, goal="integration", energy="md"), "invalid energy"),
        (lambda: sp.generate(10, 2, target="md", method="paper"), "invalid target"),
        (lambda: sp.generate(10, 2, randomize="sometimes"), "invalid randomize"),
        (lambda: sp.generate(10, 2, nested=[4, 2, 10]), "invalid nested"),
        (lambda: sp.generate(10, 2, init=np.full((10, 2), 2.0)), "init"),
        (lambda: sp.generate(10, 2, bounds=([0, 0], [1, -1])), "invalid bounds"),
        (lambda: sp.generate(10, 2, region="x^2 + y^2 - 1"), "needs a bounding box"),
        (lambda: sp.generate(10, 2, region="x^2 + y^2 - 1", box=[1, -1, -1, 1]), "invalid box"),
        (lambda: sp.generate(10, 2, region="x^2 + qq - 1", box=[-1, 1, -1, 1]), "invalid region"),
        (lambda: sp.generate(10, 3, shape="ball:1@0,0"), "invalid d = 3"),
        (lambda: sp.generate(10, shape="torus:1"), "invalid shape"),
        (lambda: sp.baseline("nope", 10, 2), "invalid method = nope"),
        (lambda: sp.baseline("sobol", 0, 2), "invalid n = 0"),
        (lambda: sp.discrepancy(np.ones((4, 2)) * 0.5, "xx"), "invalid kind"),
        (lambda: sp.discrepancy([[0.5, 1.5]], "CD"), "coordinate 2"),
        (lambda: sp.metrics([[0.5, np.nan]]), "coordinate 2"),
        (lambda: sp.metrics([0.1, 0.2]), "invalid x"),
        (lambda: sp.metrics(np.zeros((0, 3))), "invalid x"),
        (lambda: sp.metrics([["a", "b"]]), "invalid x"),
        (lambda: sp.Engine(1001), "invalid d = 1001"),
        (lambda: sp.Engine(2, region="x"), "invalid region"),
        (lambda: sp.Engine(2, energy="nope"), "invalid energy"),
    ],
)
def test_bad_arguments_are_value_errors_naming_them(call, names):
    with pytest.raises(ValueError) as info:
        call()
    assert names in str(info.value)


def test_long_calls_release_the_gil():
    import threading
    import time

    # A call of seconds (far longer than any switch interval); the main thread
    # counts its own turns while the call runs. With the GIL held through the call, it
    # could take none once the call had begun, so the count would stay at the handful
    # it may take before; nothing here depends on how fast the machine is.
    x = np.random.default_rng(6).random((15000, 10))
    started, done = threading.Event(), threading.Event()

    def work():
        started.set()
        sp.discrepancy(x, "CD")
        done.set()

    t = threading.Thread(target=work)
    t.start()
    started.wait()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0)
    t.join()
    assert ticks > 100


def test_metrics_estimate_above_the_threshold_and_exact_on_request():
    rng = np.random.default_rng(3)
    small = rng.random((400, 3))
    assert sp.metrics(small) == sp.metrics(small, exact=True)
    assert "estimate" not in sp.metrics(small)
    big = rng.random((50_001, 2))
    m = sp.metrics(big)
    assert m == sp.metrics(big)  # the same pairs for the same points
    assert m["estimate"]["pairs"] == 4 * 50_001  # four random pairs a point
    for k in ("star_l2", "modified_l2", "centered_l2", "wrap_around_l2", "mixture"):
        assert m["estimate"]["standard_errors"][k] > 0
    assert m["energy_uqp"] is None and "--exact" in m["notes"]["energy_uqp"]
