"""stillpoint.sobol_indices: closed forms (Ishigami, a linear model under normal laws),
SciPy's names, the space's names, continuation, pickling, executors, progress, and the
refusals naming the keyword and the value as typed."""

import concurrent.futures
import math
import pickle

import numpy as np
import pytest

import stillpoint as sp


def ishigami(x):
    return np.sin(x[:, 0]) + 7 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_exact():
    a, b, p4 = 7.0, 0.1, math.pi**4
    v1 = b * p4 / 5 + b * b * p4 * p4 / 50 + 0.5
    v2 = a * a / 8
    v13 = 8 * b * b * p4 * p4 / 225
    v = v1 + v2 + v13
    return np.array([v1, v2, 0]) / v, np.array([v1 + v13, v2, v13]) / v


def linear(x):
    return x[:, 0] + 2 * x[:, 1] + 0 * x[:, 2]


def test_ishigami_meets_its_closed_form_within_the_tolerance():
    r = sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi)
    first, total = ishigami_exact()
    assert r.met and r.reason == "met"
    assert r.first.shape == (3,) and r.total.shape == (3,)
    assert np.all(np.abs(r.first - first) <= 0.01)
    assert np.all(np.abs(r.total - total) <= 0.01)
    assert np.all(r.first_half_width <= 0.01) and np.all(r.total_half_width <= 0.01)
    assert r.first_order is not None and np.array_equal(r.first_order, r.first)
    assert np.array_equal(r.total_order, r.total)
    assert r.names == ["x1", "x2", "x3"]
    # (d + 2) evaluations per point of 8 blocks, and the face test's 2·d at 4 points.
    faces = 2 * 3 * 4
    assert (r.n - faces) % (8 * 5) == 0 and ((r.n - faces) // 40) & ((r.n - faces) // 40 - 1) == 0


def test_second_order_indices_meet_ishigami_s_closed_form():
    # V_13 = 8 b² π⁸ / 225 is Ishigami's only interaction: S_13 = T_3, S_12 = S_23 = 0,
    # and the first-order and second-order indices add up to 1.
    r = sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi, second_order=True)
    first, total = ishigami_exact()
    want = np.array([[np.nan, 0, total[2]], [0, np.nan, 0], [total[2], 0, np.nan]])
    assert r.met and r.second.shape == (3, 3) and r.second_half_width.shape == (3, 3)
    off = ~np.eye(3, dtype=bool)
    assert np.all(np.isnan(r.second[~off])) and np.array_equal(r.second, r.second.T, equal_nan=True)
    assert np.all(np.abs(r.second[off] - want[off]) <= 0.01), r.second
    assert np.all(r.second_half_width[off] <= 0.01)
    assert np.all(np.abs(r.first - first) <= 0.01)
    assert abs(r.first.sum() + r.second[np.triu_indices(3, 1)].sum() - 1) <= 0.02
    # 2d + 2 evaluations per point of 8 blocks, and the face test's.
    per = (r.n - 2 * 3 * 4) // 8
    assert (r.n - 24) % 8 == 0 and per % 8 == 0
    assert sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi).second is None


def test_second_order_indices_of_a_product_and_of_several_outputs():
    # f = x1·x2 on the unit cube (x3 inert): V = 7/144, V_1 = V_2 = 3/144, S_12 = 1/7.
    r = sp.sobol_indices(lambda x: np.stack([x[:, 0] * x[:, 1], x[:, 2]], axis=1), 3,
                         second_order=True)
    assert r.second.shape == (3, 3, 2)
    assert abs(r.second[0, 1, 0] - 1 / 7) <= 0.01 and abs(r.second[0, 2, 0]) <= 0.01
    assert np.all(np.abs(r.second[np.triu_indices(3, 1)][:, 1]) <= 0.01)
    # A continuation keeps the design of its points.
    with pytest.raises(ValueError, match=r"invalid second_order = False with start: .* design \(second_order = true\)"):
        sp.sobol_indices(lambda x: x[:, 0] * x[:, 1], 3, start=sp.sobol_indices(
            lambda x: x[:, 0] * x[:, 1], 3, second_order=True, abs_tol=0.2),
            second_order=False)


def test_d_is_taken_from_the_corners():
    # d inferred from the corners; same seed, same indices as the typed d.
    r1 = sp.sobol_indices(ishigami, a=[-math.pi] * 3, b=[math.pi] * 3)
    r2 = sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi)
    assert np.array_equal(r1.first, r2.first) and r1.n == r2.n


def test_a_space_gives_names_and_laws():
    # y = x + 2·z with x, z ~ N(0, 1) and w ~ U(0, 1) unused: S = T = (1/5, 4/5, 0).
    space = {"x": "normal(0,1)", "z": "normal(0,1)", "w": "uniform(0,1)"}
    r = sp.sobol_indices(linear, space=space)
    assert r.names == ["x", "z", "w"]
    want = np.array([0.2, 0.8, 0.0])
    assert np.all(np.abs(r.first - want) <= 0.01), r
    assert np.all(np.abs(r.total - want) <= 0.01), r
    assert r.first[2] == 0.0 and r.total[2] == 0.0


def test_several_outputs_have_shape_d_by_k():
    r = sp.sobol_indices(lambda x: np.stack([ishigami(x), x[:, 0]], axis=1), 3,
                         a=-math.pi, b=math.pi)
    assert r.first.shape == (3, 2) and r.total_half_width.shape == (3, 2)
    assert abs(r.first[0, 1] - 1.0) <= 0.01 and abs(r.total[1, 1]) <= 0.01


def test_a_continuation_equals_the_direct_run_and_pickles():
    loose = sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi, abs_tol=0.2)
    back = pickle.loads(pickle.dumps(loose))
    assert np.array_equal(back.first, loose.first) and back.n == loose.n
    tight = sp.sobol_indices(ishigami, 3, abs_tol=0.01, start=back)
    direct = sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi, abs_tol=0.01)
    assert tight.n == direct.n and np.array_equal(tight.total, direct.total)
    assert tight.n > loose.n
    assert back.n == loose.n  # the earlier result is not changed
    with pytest.raises(ValueError, match=r"invalid replicates = 4 with start"):
        sp.sobol_indices(ishigami, 3, start=loose, replicates=4)
    with pytest.raises(ValueError, match=r"invalid a with start"):
        sp.sobol_indices(ishigami, 3, start=loose, a=0)


def test_an_executor_gives_the_same_result():
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        r = sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi, abs_tol=0.05,
                             executor=pool)
    s = sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi, abs_tol=0.05)
    assert np.array_equal(r.first, s.first) and r.n == s.n


def test_progress_gets_a_copy_each_round(capsys):
    seen = []
    r = sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi, abs_tol=0.05,
                         progress=seen.append)
    assert [s.n for s in seen][-1] == r.n
    assert all(a.n < b.n for a, b in zip(seen, seen[1:]))
    sp.sobol_indices(ishigami, 3, a=-math.pi, b=math.pi, abs_tol=0.05, progress=True)
    assert "sobol_indices: n=" in capsys.readouterr().err


def test_a_large_doubling_comes_in_bounded_batches_and_reports_once():
    # At d = 300 one doubling of 8·64 points is 8·64·302·300 coordinates, 11× the
    # library's batch of 2^22: f sees each batch, the progress each whole doubling.
    d, faces = 300, 8 * 300
    sizes, seen = [], []

    def f(x):
        sizes.append(x.size)
        return x[:, 0] + x[:, 1] * x[:, 2]

    first = 8 * 64 * (d + 2)
    r = sp.sobol_indices(f, d, abs_tol=0.0, max_n=faces + 3 * first, progress=seen.append)
    assert max(sizes) <= 2**22 and sum(sizes) == (r.n - faces) * d + faces * d
    # The face test's batch, then per doubling 12 batches (46 points at most in each).
    assert len(sizes) == 1 + 2 * 12
    assert [s.n for s in seen] == [faces + first, faces + 2 * first]
    assert r.n == faces + 2 * first
    assert abs(r.first[0] - 0.6) < 0.05 and abs(r.total[3]) < 0.01


def test_simultaneous_intervals_are_wider():
    # Wider by the quantile; the round guard (the change since half the points) is a
    # floor under both that does not depend on the level.
    o = dict(a=-math.pi, b=math.pi, abs_tol=0.0, max_n=40960)
    own = sp.sobol_indices(ishigami, 3, **o)
    together = sp.sobol_indices(ishigami, 3, simultaneous=True, **o)
    assert together.simultaneous and not own.simultaneous
    for w in ("first_half_width", "total_half_width"):
        assert np.all(getattr(together, w) >= getattr(own, w))
    assert np.any(together.total_half_width > own.total_half_width)
    assert not own.met and own.reason == "max_n"


def test_the_interval_is_the_posterior_by_default_and_the_blocks_by_name():
    # The same points and indices either way, other half-widths, each covering the
    # closed form.
    o = dict(a=-math.pi, b=math.pi, abs_tol=0.0, max_n=4096 * 5 + 24)
    post = sp.sobol_indices(ishigami, 3, **o)
    blocks = sp.sobol_indices(ishigami, 3, interval="blocks", **o)
    assert post.interval == "posterior" and blocks.interval == "blocks"
    assert np.array_equal(post.first, blocks.first) and post.n == blocks.n
    first, total = ishigami_exact()
    assert np.all(np.abs(post.first - first) <= post.first_half_width)
    assert np.all(np.abs(post.total - total) <= post.total_half_width)
    assert not np.array_equal(post.total_half_width, blocks.total_half_width)
    assert np.all(np.abs(blocks.total - total) <= blocks.total_half_width)
    # A continuation may leave the posterior for the blocks, not come back.
    on = sp.sobol_indices(ishigami, 3, start=post, interval="blocks", max_n=8192 * 5 + 24,
                          abs_tol=0.0)
    assert on.interval == "blocks" and on.n == 8192 * 5 + 24
    with pytest.raises(ValueError, match=r"invalid interval = 'posterior'"):
        sp.sobol_indices(ishigami, 3, start=on, interval="posterior")
    # Under an unbounded law the points are Owen-scrambled Sobol' points: the blocks'.
    z = sp.sobol_indices(lambda x: x[:, 0] + 2 * x[:, 1], space={"a": "normal(0,1)",
                                                                  "b": "normal(0,1)"},
                         abs_tol=0.05)
    assert z.interval == "blocks" and z.met
    assert pickle.loads(pickle.dumps(post)).interval == "posterior"


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(d=0), r"invalid d = 0"),
        (dict(d=3, interval="median"), r"invalid interval = 'median'"),
        (dict(d=501), r"invalid d = 501"),
        (dict(d=3, abs_tol=-1e-3), r"invalid abs_tol = -0\.001"),
        (dict(d=3, level=1.5), r"invalid level = 1\.5"),
        (dict(d=3, max_n=100), r"invalid max_n = 100"),
        (dict(d=3, replicates=1), r"invalid replicates = 1"),
        (dict(d=3, first_estimator="owen"), r"invalid first_estimator = 'owen'"),
        (dict(d=3, simultaneous="yes"), r"invalid simultaneous = 'yes'"),
        (dict(d=3, progress="loud"), r"invalid progress = 'loud'"),
        (dict(), r"invalid d = None"),
        (dict(d=2, correlation=[[1, 0.5], [0.5, 1]]), r"invalid correlation = "),
        (dict(space=["W=brownian(1,4)"]), r"invalid space = W_1"),
        (dict(d=3, space={"x": "normal(0,1)"}), r"invalid d = 3"),
    ],
)
def test_refusals_name_the_keyword_and_the_value(kwargs, message):
    with pytest.raises(ValueError, match=message):
        sp.sobol_indices(ishigami, **kwargs)


def test_constant_and_non_finite_outputs_are_refused():
    with pytest.raises(ValueError, match=r"invalid f = 2\.5 at every one of the first"):
        sp.sobol_indices(lambda x: np.full(len(x), 2.5), 2)
    with pytest.raises(ValueError, match=r"invalid f: nan at x = \["):
        sp.sobol_indices(lambda x: np.where(x[:, 0] > 0.5, np.nan, x[:, 1]), 2)


def test_the_guide_examples_run():
    import pathlib
    import re

    page = pathlib.Path(__file__).resolve().parents[2] / "docs" / "sensitivity.md"
    blocks = re.findall(r"```python\n(.*?)```", page.read_text(encoding="utf-8"), flags=re.S)
    scope = {}
    for block in blocks:
        exec(compile(block, str(page), "exec"), scope)
    first, total = ishigami_exact()
    assert np.all(np.abs(scope["r"].first - first) <= 0.01)
    assert scope["laws"].names == ["E", "k", "n"]
    assert scope["laws"].met
