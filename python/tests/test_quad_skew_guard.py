"""quad's skew guard seen from Python: on a heavy-tailed integrand the half-width is the
formula of the module documentation recomputed from every value f returned; on symmetric
values it is the Student t half-width and the round guard alone; and it is the same for
-f."""

import math

import numpy as np
import pytest
from scipy import stats

import stillpoint as sp

Z = 1.959963984540054  # the normal 0.975 quantile


def corner(x):
    return (1.0 + x.sum(axis=1)) ** -(x.shape[1] + 1.0)


def run(f, d, seed):
    """quad at exactly 1 024 evaluations (four replicates of 256), and each replicate's
    values in the order of its points."""
    batches = []

    def g(x):
        v = f(x)
        batches.append(np.asarray(v, dtype=float))
        return v

    r = sp.quad(g, d, abs_tol=0, rel_tol=0, max_n=1024, seed=seed)
    assert (r.n, r.replicates) == (1024, 4)
    reps = [np.concatenate([b[i * (len(b) // 4):(i + 1) * (len(b) // 4)] for b in batches])
            for i in range(4)]
    return r, reps


def student_and_round(reps):
    means = np.array([v.mean() for v in reps])
    half = np.mean([v[: len(v) // 2].mean() for v in reps])
    t = stats.t.ppf(0.975, 3) * means.std(ddof=1) / 2
    return max(t, abs(means.mean() - half))


# Seeds where the guard binds (at seeds 0 and 3 the Student part or the round guard is
# the wider here).
@pytest.mark.parametrize("seed", [1, 2, 4])
def test_a_heavy_tail_gets_the_skew_guard_of_its_values(seed):
    r, reps = run(corner, 20, seed)
    h = student_and_round(reps)
    values = np.concatenate(reps)
    n = len(values)
    dev = values - values.mean()
    gamma = abs(np.mean(dev ** 3)) / np.mean(dev ** 2) ** 1.5
    sd = math.sqrt(np.mean(dev ** 2) * n / (n - 1))
    w = min(max((gamma - 1) / 4, 0), 1)
    hall = 1 + gamma * (2 * Z * Z + 1) / (6 * Z * math.sqrt(n))
    expected = max(h, w * 1.2 * hall * min(h, Z * sd / math.sqrt(n)))
    assert gamma > 5 and expected > 1.05 * h  # the guard binds
    assert r.half_width == pytest.approx(expected, rel=1e-9)


def test_symmetric_values_keep_the_student_and_round_half_width():
    r, reps = run(lambda x: x[:, 0] - x[:, 1] + 0.1 * np.sin(6 * x[:, 2]), 3, 0)
    assert r.half_width == pytest.approx(student_and_round(reps), rel=1e-12)


def test_minus_f_gets_the_same_half_width():
    a = sp.quad(corner, 20, abs_tol=0, rel_tol=0, max_n=1024, seed=3)
    b = sp.quad(lambda x: -corner(x), 20, abs_tol=0, rel_tol=0, max_n=1024, seed=3)
    assert b.estimate == -a.estimate and b.half_width == a.half_width
