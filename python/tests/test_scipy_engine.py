"""SciPy's own generic engine tests (``QMCEngineTests`` of scipy/stats/tests/test_qmc.py)
run against :class:`stillpoint.Engine`: continuing, ``reset``, ``fast_forward``,
d = 0, bounds, distribution, SciPy's optimisers, the generator's state consumed."""

import warnings

import numpy as np
import pytest
from scipy.stats import qmc

import stillpoint as sp

test_qmc = pytest.importorskip("scipy.stats.tests.test_qmc")


def _engine(scramble=True, **kwargs):
    # The engine is always randomised: SciPy's scrambled and unscrambled variants both
    # run it (its `scramble` keyword has no counterpart here).
    return sp.Engine(**kwargs)


def _lloyd_improves(make, seeds):
    """The share of seeds for which SciPy's Lloyd post-processing raises the smallest
    L1 distance between 64 points, as SciPy's test_optimizers asks at one seed."""
    wins = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for s in seeds:
            plain = make(seed=s).random(64)
            lloyd = make(seed=s, optimization="lloyd").random(64)
            wins += test_qmc._l1_norm(lloyd) > test_qmc._l1_norm(plain)
    return wins / len(seeds)


class TestStillpointEngine(test_qmc.QMCEngineTests):
    qmce = staticmethod(_engine)
    can_scramble = True
    unscramble_nd = None
    scramble_nd = None

    @pytest.mark.skip(reason="compares with another engine's reference points (Halton's)")
    def test_sample(self, scramble):
        pass

    @pytest.mark.parametrize(
        "optimization,metric",
        [("random-CD", qmc.discrepancy), ("lloyd", lambda sample: -test_qmc._l1_norm(sample))],
    )
    def test_optimizers(self, optimization, metric):
        # SciPy's check at its one seed asks Lloyd's iterations to raise the smallest
        # distance, which they do for most seeds but not all: the points next to the
        # boundary, whose Voronoi cells are unbounded, do not move, and where the closest
        # pair is among them the distance stays. At SciPy's seed that is the case for this
        # engine (for scrambled Sobol', at 21 of seeds 0..199). The random-CD check runs
        # as SciPy wrote it; Lloyd's is asked over many seeds, against Sobol's rate.
        if optimization == "lloyd":
            seeds = range(100)
            ours = _lloyd_improves(lambda **k: sp.Engine(2, **k), seeds)
            sobol = _lloyd_improves(lambda **k: qmc.Sobol(2, **k), seeds)
            assert ours >= 0.9 and ours >= sobol
        else:
            super().test_optimizers(optimization, metric)


def test_an_engine_works_with_qmc_quad():
    from scipy.integrate import qmc_quad

    # ∫_[0,1]^4 ∏ (1 + (x_j − 1/2)) = 1; each estimate on a fresh engine (qmc_quad builds
    # them from ours with draws unchanged).
    res = qmc_quad(
        lambda x: np.prod(0.5 + x, axis=0),
        [0] * 4,
        [1] * 4,
        n_estimates=8,
        n_points=256,
        qrng=sp.Engine(4, seed=3),
    )
    assert 0 < res.standard_error < 1e-3
    assert abs(res.integral - 1.0) < 4 * res.standard_error
