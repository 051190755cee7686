"""stillpoint.Engine as a SciPy QMC engine."""

import copy
import pickle
import warnings

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


def test_independent_draws_are_the_tent_lattice_shifted_and_folded():
    d, n = 3, 50
    e = sp.Engine(d, seed=4, draws="independent")
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
    e = sp.Engine(d, seed=2, draws="independent")
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


def test_successive_draws_continue_one_sequence():
    e = sp.Engine(3, seed=21)
    parts = [e.random(64), e.random(64), e.random(128)]
    whole = sp.Engine(3, seed=21).random(256)
    assert np.array_equal(np.concatenate(parts), whole)
    assert e.num_generated == 256
    # Each prefix of 2^m points is a shifted lattice (each column 2^m equally spaced
    # values mod 1, the generators being odd) folded by the tent transform x ↦ 1 − |2x − 1|:
    # each half of the column maps onto [0, 1] with spacing 2/n, so every cell
    # [2k/n, 2(k+1)/n) holds exactly two points.
    for m in (2, 4, 6, 8):
        n = 2**m
        for j in range(3):
            counts = np.bincount(np.floor(whole[:n, j] * n / 2).astype(int), minlength=n // 2)
            assert np.array_equal(counts, np.full(n // 2, 2))


def test_sequence_reset_fast_forward_and_warnings():
    e = sp.Engine(2, seed=22)
    first = e.random(32)
    second = e.random(32)
    assert np.array_equal(e.reset().random(32), first)
    f = sp.Engine(2, seed=22).fast_forward(32)
    assert f.num_generated == 32 and np.array_equal(f.random(32), second)
    with pytest.warns(UserWarning, match="balance properties"):
        sp.Engine(2, seed=22).random(48)
    g = sp.Engine(2, seed=22)
    g.random(16)
    with pytest.warns(UserWarning, match="16\\+8=24"):
        g.random(8)


def test_zero_dimensions_and_the_sequence_limits():
    assert sp.Engine(0, seed=1).random(4).shape == (4, 0)
    assert sp.Engine(0, draws="independent").random(3).shape == (3, 0)
    # The sequence reaches the extensible table's 1 000 dimensions; its first 100
    # coordinates are the same points as an engine of 100 dimensions.
    wide = sp.Engine(1000, seed=3).random(16)
    assert wide.shape == (16, 1000) and ((wide >= 0) & (wide < 1)).all()
    assert np.array_equal(wide[:, :100], sp.Engine(100, seed=3).random(16))
    with pytest.raises(ValueError, match=r"invalid d = 1001.*draws='independent'"):
        sp.Engine(1001)
    assert sp.Engine(1001, draws="independent", seed=1).random(8).shape == (8, 1001)
    with pytest.raises(ValueError, match="invalid draws = 'sometimes'"):
        sp.Engine(2, draws="sometimes")
    with pytest.raises(ValueError, match="invalid draws = 'sequence' with randomize = 'cells'"):
        sp.Engine(2, draws="sequence", randomize="cells")
    with pytest.raises(ValueError, match="invalid n = 2"):
        sp.Engine(1, seed=1).fast_forward(2**20 - 1).random(2)


def test_optimised_set_randomisations_draw_independently():
    for kind in ("cells", "shift"):
        e = sp.Engine(2, seed=23, randomize=kind)
        a, b = e.random(32), e.random(32)
        assert not np.array_equal(a, b)
        # Both are randomisations of the same optimised set for n = 32: same sorted gaps
        # in each coordinate modulo 1 would need the same shift; just check independence
        # from the sequence: neither equals the continued sequence's points.
        assert not np.array_equal(np.concatenate([a, b]), sp.Engine(2, seed=23).random(64))


def test_each_sequence_randomisation_is_unbiased():
    # ∫ ∏ (1/2 + x_j) over [0,1]^3 = 1; the mean over 400 engines (one shift each) within
    # 4 standard errors of it, at a prefix that is not a power of two too.
    for n in (64, 40):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            est = np.array(
                [np.prod(0.5 + sp.Engine(3, seed=s).random(n), axis=1).mean() for s in range(400)]
            )
        se = est.std(ddof=1) / np.sqrt(len(est))
        assert abs(est.mean() - 1.0) < 4 * se


DATA = __import__("pathlib").Path(__file__).parent / "data"


def test_the_sequence_draws_from_the_engines_own_table():
    e = sp.Engine(4, seed=31)
    x = e.random(256)
    seed = e._sequence_seed
    own = sp._core.sequence_points(4, seed=seed, start=0, count=256, table="first-order")
    tent = sp._core.sequence_points(4, seed=seed, start=0, count=256, table="tent")
    assert np.array_equal(x, own)
    assert not np.array_equal(x, tent)
    # The same shift, another lattice: the first coordinate (z₁ = 1 in both) agrees.
    assert np.array_equal(x[:, 0], tent[:, 0])
    assert sp._core.ENGINE_SEQUENCE_MAX_D == sp._engine._OWN_TABLE_MAX_D
    with pytest.raises(ValueError, match="invalid table = halton: expected 'tent'.*'sobol'"):
        sp._core.sequence_points(2, table="halton")
    # A new engine pickled and loaded keeps its table.
    back = pickle.loads(pickle.dumps(e))
    assert back == e and np.array_equal(back.random(256), e.random(256))


def test_an_engine_pickled_before_its_own_table_continues_its_sequence():
    # Written by the package before the engine had its own table (a sequence engine of
    # d = 5, seed 2024, after one draw of 64 points, and the points it drew next): it has
    # no record of a table and continues the tent table's sequence.
    expected = np.load(DATA / "engine_sequence_expected.npz")
    old = pickle.loads((DATA / "engine_sequence.p4.pkl").read_bytes())
    assert "_sequence_table" not in vars(old) and old.num_generated == 64
    assert np.array_equal(old.random(64), expected["next"])
    assert np.array_equal(old.reset().random(64), expected["first"])
    tent = sp._core.sequence_points(5, seed=old._sequence_seed, count=128, table="tent")
    assert np.array_equal(tent[64:], expected["next"])
    # Equal to a new engine of the same seed only in what they will not draw alike.
    new = sp.Engine(5, seed=2024)
    assert new._sequence_seed == old._sequence_seed
    assert new != old.reset()
    assert not np.array_equal(new.random(64), expected["first"])


# Engines under a design space, and sequences by name.

NORMALS = {"x": "normal(0,1)", "y": "lognormal(0,0.5)", "z": "normal(2,3)"}
PATHS = {"W": "brownian(1,4,pca)", "x": "normal(0,1)"}


def test_under_laws_without_a_path_the_draws_are_the_engine_s_own_sequence():
    e = sp.Engine(space={**NORMALS, "u": "uniform(0,2)"}, seed=5)
    assert e.d == 4 and e.rule == "first-order lattice"
    assert e.names == ["x", "y", "z", "u"]
    assert np.array_equal(e.random(64), sp.Engine(4, seed=5).random(64))
    assert sp.Engine(3, seed=5).rule == "first-order lattice"
    assert sp.Engine(3, seed=5, draws="independent").rule is None


def test_under_a_path_the_draws_are_owen_s_net_with_leading_columns_to_leading_steps():
    e = sp.Engine(space=PATHS, seed=3)
    assert e.d == 5 and e.rule == "sobol"
    assert e.names == ["W_1", "W_2", "W_3", "W_4", "x"]
    net = sp.Engine(5, rule="sobol", seed=3).random(64)
    x = e.random(64)
    # x takes the net's first column, then the path its next four in order.
    assert np.array_equal(x[:, 4], net[:, 0])
    assert np.array_equal(x[:, :4], net[:, 1:])
    # Every column of 2^m points of a scrambled net holds one point per 1/2^m.
    for j in range(5):
        assert sorted(np.floor(x[:, j] * 64).astype(int)) == list(range(64))
    # Draws continue one sequence.
    again = sp.Engine(space=PATHS, seed=3)
    assert np.array_equal(np.vstack([again.random(32), again.random(32)]), x)
    # Another seed, another scramble.
    assert not np.array_equal(sp.Engine(space=PATHS, seed=4).random(64), x)
    # A lattice by name is dealt alike: the engine's own draws, x on their first column.
    lat = sp.Engine(space=PATHS, rule="first-order lattice", seed=3)
    assert lat.rule == "first-order lattice"
    own = sp.Engine(5, seed=3).random(64)
    y = lat.random(64)
    assert np.array_equal(y[:, 4], own[:, 0]) and np.array_equal(y[:, :4], own[:, 1:])


def test_each_named_rule_is_the_sequence_it_names():
    for rule in ("first-order lattice", "lattice", "sobol"):
        e = sp.Engine(6, rule=rule, seed=2)
        assert e.rule == rule
        x = e.random(128)
        assert x.shape == (128, 6) and np.all((x >= 0) & (x <= 1))
        for j in range(6):
            assert np.unique(np.floor(x[:, j] * 128)).size >= 64
    # The tent lattice is what an engine unpickled from before its own table draws.
    assert not np.array_equal(
        sp.Engine(6, rule="lattice", seed=2).random(64), sp.Engine(6, seed=2).random(64)
    )


def test_independent_draws_under_a_space_are_the_randomised_design_s_unit_set():
    for space in (NORMALS, {"x": "normal(0,1)", "k": "int(1,3)"}, PATHS):
        e = sp.Engine(space=space, draws="independent", seed=11)
        # The seeds each draw takes from the engine's generator.
        rng = copy.deepcopy(e.rng)
        for n in (64, 101):
            seed = int(rng.integers(0, 2**64, dtype=np.uint64))
            want = sp.design(n, space, randomize=True, seed=seed)
            assert np.array_equal(e.random(n), want.unit)
            assert want.unbiased


def test_to_space_maps_through_each_law():
    from scipy import stats

    law = stats.lognorm(0.4, scale=2.0)
    e = sp.Engine(space={"x": "normal(2,3)", "k": "int(1,3)", "g": law}, seed=0)
    u = np.array([[0.5, 0.1, 0.25], [0.975, 0.9, 0.5]])
    v = e.to_space(u)
    assert np.allclose(v[:, 0], 2 + 3 * stats.norm.ppf(u[:, 0]), rtol=1e-12)
    assert list(v[:, 1]) == [1, 3]
    assert np.allclose(v[:, 2], law.ppf(u[:, 2]), rtol=1e-12)
    # A SciPy law of unbounded support is drawn for as a normal one: no path, so the
    # engine's own sequence.
    assert e.rule == "first-order lattice"


def test_draws_under_normal_laws_integrate_their_moments():
    # E exp(sum a_j Z_j) = exp(|a|^2 / 2), over 16 engines: the mean is unbiased and
    # each engine's error small.
    a = np.array([0.4, 0.3, 0.2, 0.1])
    space = {f"z{j}": "normal(0,1)" for j in range(4)}
    exact = np.exp(a @ a / 2)
    for draws in ("sequence", "independent"):
        est = []
        for seed in range(16):
            e = sp.Engine(space=space, draws=draws, seed=seed)
            est.append(np.exp(e.to_space(e.random(1024)) @ a).mean())
        est = np.array(est)
        assert abs(est.mean() - exact) < 4 * est.std(ddof=1) / 4 + 1e-12
        assert np.sqrt(np.mean((est - exact) ** 2)) < 2e-3 * exact


def test_qmc_quad_copies_an_engine_under_a_space():
    e = sp.Engine(space=PATHS, seed=1)
    copy_ = type(e)(seed=2, **e._init_quad)
    assert copy_.d == 5 and copy_.rule == "sobol" and copy_.names == e.names
    res = qmc_quad(lambda u: np.sum(u, axis=0), np.zeros(5), np.ones(5), n_estimates=4,
                   n_points=256, qrng=e)
    assert abs(res.integral - 2.5) < 1e-2


def test_an_engine_under_a_space_pickles_and_continues():
    from scipy import stats

    e = sp.Engine(space={**PATHS, "g": stats.gamma(2.0)}, seed=9)
    e.random(16)
    f = pickle.loads(pickle.dumps(e))
    assert f == e and f.names == e.names
    assert np.array_equal(f.random(16), e.random(16))
    assert np.array_equal(f.to_space(np.full((1, 6), 0.5)), e.to_space(np.full((1, 6), 0.5)))
    assert sp.Engine(space=PATHS, seed=9) != sp.Engine(5, rule="sobol", seed=9)
    # A correlated space maps its draws through the copula, and shows it.
    c = sp.Engine(space={"x": "normal(0,1)", "y": "normal(0,1)"}, correlation=[[1, 0.8], [0.8, 1]],
                  seed=1)
    v = c.to_space(c.random(4096))
    assert abs(np.corrcoef(v.T)[0, 1] - 0.8) < 0.01
    assert "correlation=[[1.0, 0.8], [0.8, 1.0]]" in repr(c)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(d=3, space=NORMALS | {"u": "uniform(0,1)"}), r"invalid d = 3: space has 4"),
        (dict(space=NORMALS, steps=10), r"invalid steps with space"),
        (dict(d=2, rule="halton"), r"invalid rule = 'halton'"),
        (dict(d=2, rule="sobol", draws="independent"), r"invalid rule = 'sobol' with draws"),
        (dict(d=2, correlation=np.eye(2)), r"invalid correlation without space"),
        (dict(space=NORMALS, correlation="1,0;0,1"), r"invalid correlation = '1,0;0,1'"),
        (dict(space=NORMALS, correlation=np.eye(2)), r"correlation"),
        (dict(), r"invalid d = None"),
        (dict(d=1001), r"invalid d = 1001: the sequence reaches 1000"),
        (dict(d=21202, rule="sobol"), r"invalid d = 21202: the sequence reaches 21201"),
    ],
)
def test_engine_refusals_name_the_argument(kwargs, match):
    with pytest.raises(ValueError, match=match):
        sp.Engine(**kwargs)


def test_to_space_refusals():
    with pytest.raises(ValueError, match="invalid to_space on an engine without space"):
        sp.Engine(2, seed=0).to_space(np.zeros((1, 2)))
    e = sp.Engine(space=NORMALS, seed=0)
    with pytest.raises(ValueError, match=r"invalid u of shape \(1, 2\)"):
        e.to_space(np.zeros((1, 2)))
    with pytest.raises(ValueError, match="unit cube"):
        e.to_space(np.full((1, 3), 1.5))
