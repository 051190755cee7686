"""stillpoint.Engine as a SciPy QMC engine."""

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
    with pytest.raises(ValueError, match="invalid table = sobol: expected 'tent'"):
        sp._core.sequence_points(2, table="sobol")
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
