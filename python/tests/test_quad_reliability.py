"""quad at the edges: huge and tiny magnitudes, boxes and spaces checked as everywhere
else, continuations that honour or refuse every setting, the real stop reason,
refusals naming the argument, the correlation as text, and what f and executor may be."""

import concurrent.futures
import pickle

import numpy as np
import pytest

import stillpoint as sp


def line(x):
    return 1.0 + x[:, 0]


@pytest.mark.parametrize("c", [1e200, 1e300, -1e307, 1e-300])
def test_huge_and_tiny_integrands_give_finite_honest_intervals(c):
    r = sp.quad(lambda x: c * np.exp(x[:, 0] + x[:, 1]), 2, seed=1)
    one = sp.quad(lambda x: np.exp(x[:, 0] + x[:, 1]), 2, seed=1)
    assert r.met and r.reason == "met" and r.n == one.n
    assert np.isfinite(r.half_width) and 0 < r.half_width <= 1e-3 * abs(r.estimate)
    assert r.estimate / c == pytest.approx(one.estimate, rel=1e-12)
    assert r.half_width / abs(c) == pytest.approx(one.half_width, rel=1e-6)


def test_sums_that_would_overflow_reach_the_integral():
    r = sp.quad(lambda x: 1e308 * x[:, 0], 1)
    assert r.met and r.estimate == pytest.approx(5e307, rel=1e-3)
    assert np.isfinite(r.half_width)
    # k = 2 outputs, one overflowing plain sums: each on its own scale.
    r = sp.quad(lambda x: np.column_stack([1e308 * x[:, 0], x[:, 0] ** 2]), 2)
    assert r.met and r.estimate[0] == pytest.approx(5e307, rel=1e-3)
    assert r.estimate[1] == pytest.approx(1 / 3, rel=1e-3)
    # A volume of 1e360 with an integral of 1e260 is computed; 1e360 is refused.
    r = sp.quad(lambda x: np.full(len(x), 1e-100), 3, a=0, b=1e120)
    assert r.estimate == pytest.approx(1e260, rel=1e-12) and r.half_width == 0
    with pytest.raises(ValueError, match=r"invalid f = values whose estimated integral .* 1\.0e360"):
        sp.quad(lambda x: np.ones(len(x)), 3, a=0, b=1e120)
    # x over a symmetric box of volume 1.6e401: 0, but no estimate fits a float; the run
    # goes to its budget and is refused there (the tent lattice asked for: its doublings
    # fill the budget, where a face test's 7 evaluations would leave room for fewer).
    with pytest.raises(ValueError, match=r"values whose estimated .* after 4096 evaluations"):
        sp.quad(lambda x: x[:, 0], 2, a=-1e200, b=1e200, max_n=4096, rule="lattice")


def test_a_zero_spread_is_met_only_for_a_constant():
    r = sp.quad(lambda x: np.full(len(x), 2.5), 3)
    assert r.met and r.half_width == 0 and r.estimate == 2.5
    # 1e16 + 4x: the sums round alike; an absolute tolerance of 0.1 is not claimed.
    r = sp.quad(lambda x: 1e16 + 4 * x[:, 0], 1, abs_tol=0.1, rel_tol=0, max_n=2**14)
    assert not r.met and r.reason == "max_n" and 0.1 < r.half_width < np.inf


@pytest.mark.parametrize(
    "a, b",
    [(-1e308, 1e308), (1e15, 1e15 + 0.1), ([0, 0], [1, 1e-160]), ([0, 2], [1, 1])],
)
def test_boxes_are_checked_as_everywhere(a, b):
    d = 2 if isinstance(a, list) else 1
    with pytest.raises(ValueError, match=r"^invalid a, b = \(") as e:
        sp.quad(lambda x: np.ones(len(x)), d, a=a, b=b)
    assert repr(a) in str(e.value) and repr(b) in str(e.value)


@pytest.mark.parametrize(
    "spec",
    [
        "uniform(1000000000000000,1000000000000000.1)",
        "uniform(1e15,1.0000000000000002e15)",
        "normal(1e20,1e3)",
    ],
)
def test_a_space_whose_scale_vanishes_is_refused_as_design_refuses_it(spec):
    with pytest.raises(ValueError, match=r"invalid space x = .*distinct values"):
        sp.quad(lambda x: x[:, 0], 1, space={"x": spec})
    # A range that holds the values is integrated: E[x] of uniform(1e15, 1e15 + 1e4).
    r = sp.quad(lambda x: x[:, 0] - 1e15, 1, space={"x": "uniform(1e15,1.00000000001e15)"})
    assert r.met and r.estimate == pytest.approx(5e3, rel=1e-3)


def test_a_larger_max_n_continues_a_run_stopped_by_the_budget():
    f = lambda x: np.exp(x[:, 0] + x[:, 1])  # noqa: E731
    # The tent lattice asked for, so that the doublings fill each budget exactly.
    first = sp.quad(f, 2, rel_tol=1e-9, max_n=4096, seed=3, rule="lattice")
    assert (first.n, first.reason, first.met) == (4096, "max_n", False)
    more = sp.quad(f, 2, start=first, max_n=2**16)
    direct = sp.quad(f, 2, rel_tol=1e-9, max_n=2**16, seed=3, rule="lattice")
    assert more.n == direct.n == 2**16 and more.estimate == direct.estimate
    assert first.n == 4096, "the earlier result is unchanged"
    # A level changes the half-width by the ratio of the t quantiles; seed and
    # replicates equal to the earlier ones are honoured.
    from scipy.stats import t

    wide = sp.quad(f, 2, start=first, level=0.99, seed=3, replicates=4)
    assert wide.n == first.n
    # The t part scales with the quantile; the round guard under it does not.
    means = first.replicate_means
    t_part = t.ppf(0.975, 3) * np.std(means, ddof=1) / 2
    change = first._state.round_change[0]
    assert first.half_width == pytest.approx(max(t_part, change), rel=1e-9)
    ratio = t.ppf(0.995, 3) / t.ppf(0.975, 3)
    assert wide.half_width == pytest.approx(max(t_part * ratio, change), rel=1e-9)
    # A pickled result continues alike.
    again = sp.quad(f, 2, start=pickle.loads(pickle.dumps(first)), max_n=2**16)
    assert again.estimate == more.estimate


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"replicates": 16}, r"invalid replicates = 16 with start"),
        ({"seed": 4}, r"invalid seed with start = 4"),
        ({"seed": None}, r"invalid seed with start = None"),
        ({"max_n": 10}, r"invalid max_n = 10"),
        ({"level": 2}, r"invalid level = 2"),
        ({"a": 0}, r"invalid a with start"),
        ({"correlation": "1,0.5;0.5,1"}, r"invalid correlation with start"),
    ],
)
def test_a_continuation_refuses_what_it_cannot_honour_by_name(kwargs, message):
    first = sp.quad(line, 2, rel_tol=1e-9, max_n=4096, seed=3)
    before = pickle.dumps(first)
    with pytest.raises(ValueError, match=message):
        sp.quad(line, 2, start=first, **kwargs)
    assert pickle.dumps(first) == before


def test_the_stop_reason_is_the_real_one():
    f = lambda x: x[:, 0] * x[:, 1]  # noqa: E731
    r = sp.quad(f, 2, rel_tol=0, max_n=10**8)
    assert (r.n, r.reason, r.met) == (r.replicates * 2**20, "sequence", False)
    assert r.replicates == 4
    r = sp.quad(f, 2, rel_tol=0, max_n=5000)
    assert (r.n, r.reason) == (4096, "max_n")
    assert sp.quad(f, 2).reason == "met"
    assert "reason='met'" in repr(sp.quad(f, 2))
    seen = []
    sp.quad(f, 2, rel_tol=1e-6, progress=seen.append)
    assert [s.reason for s in seen[:-1]] == [None] * (len(seen) - 1)
    assert seen[-1].reason == "met"


@pytest.mark.parametrize(
    "kwargs, start",
    [
        ({"replicates": 100000}, "invalid replicates = 100000: expected 2 to 16384"),
        ({"replicates": 100, "max_n": 1000}, "invalid max_n = 1000: expected"),
        ({"max_n": 0}, "invalid max_n = 0: expected"),
        ({"level": "x"}, "invalid level = 'x'"),
        ({"level": -1e-20}, "invalid level = -1e-20: expected a value in (0, 1)"),
        ({"rel_tol": -1e-300}, "invalid rel_tol = -1e-300: "),
    ],
)
def test_refusals_name_the_keyword_and_the_value_typed(kwargs, start):
    with pytest.raises(ValueError) as e:
        sp.quad(line, 1, **kwargs)
    assert str(e.value).startswith(start) and "start_n" not in str(e.value)


def test_the_correlation_takes_design_s_text_form():
    space = {"x": "normal(0,1)", "y": "normal(0,1)"}
    f = lambda x: x[:, 0] * x[:, 1]  # noqa: E731
    text = sp.quad(f, 2, space=space, correlation="1,0.5;0.5,1", rel_tol=1e-2)
    matrix = sp.quad(f, 2, space=space, correlation=[[1, 0.5], [0.5, 1]], rel_tol=1e-2)
    assert text.estimate == matrix.estimate
    assert text.estimate == pytest.approx(0.5, abs=4 * text.half_width + 1e-3)
    for bad in ["1,a;0.5,1", "1,2;2,1", "1,0.5;0.4,1", [["a", 1], [1, 1]]]:
        with pytest.raises(ValueError, match=r"^invalid correlation = "):
            sp.quad(f, 2, space=space, correlation=bad)


def test_executor_must_be_an_instance():
    for bad, kind in [
        (concurrent.futures.ThreadPoolExecutor, TypeError),
        (concurrent.futures.ProcessPoolExecutor, TypeError),
        ("pool", ValueError),
        (3, ValueError),
    ]:
        with pytest.raises(kind, match=r"^invalid executor = "):
            sp.quad(line, 1, executor=bad)


@pytest.mark.parametrize(
    "f, what",
    [
        (lambda x: ["1.0"] * len(x), "list"),
        (lambda x: np.array(["a"] * len(x)), "dtype <U1"),
        (lambda x: (v for v in x[:, 0]), "generator"),
        (lambda x: iter(x[:, 0]), "iterator"),
        (lambda x: [[1.0, 2.0]] + [[1.0]] * (len(x) - 1), "ragged"),
        (lambda x: None, "None"),
        (lambda x: x[:, 0] + 0j, "complex"),
    ],
)
def test_f_returning_non_numbers_is_refused_naming_f(f, what):
    with pytest.raises(ValueError, match=r"^invalid f: it returned ") as e:
        sp.quad(f, 1)
    assert what in str(e.value)
    # The same on an executor.
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        with pytest.raises(ValueError, match=r"^invalid f: it returned "):
            sp.quad(f, 1, executor=pool)


def test_the_seed_is_0_when_omitted_and_fresh_for_none():
    f = lambda x: np.exp(x[:, 0] * x[:, 1])  # noqa: E731

    def means(**kwargs):
        return sp.quad(f, 2, rel_tol=1e-2, **kwargs).replicate_means.tolist()

    omitted = means()
    assert omitted == means(seed=0)
    assert omitted != means(seed=1)
    fresh = [means(seed=None) for _ in range(3)]
    assert len({tuple(m) for m in fresh}) == 3 and omitted not in fresh
