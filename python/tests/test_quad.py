"""``stillpoint.quad``: integrals to a tolerance checked against closed forms, several
outputs, expectations under a space's distributions, continuing from a result without
evaluating again, an executor giving the result of one process, and the refusals."""

import concurrent.futures
import logging
import math
import pickle
import re
import warnings

import numpy as np
import pytest

import stillpoint as sp


def product_peak(x):
    # ∏ 1/(c⁻² + (x_j − w)²) with c = 2, w = 0.3: smooth, integral in closed form.
    return np.prod(1.0 / (0.25 + (x - 0.3) ** 2), axis=1)


def product_peak_integral(d):
    one = 2.0 * (math.atan(2 * 0.7) + math.atan(2 * 0.3))
    return one**d


@pytest.mark.parametrize("d", [1, 3, 6])
@pytest.mark.parametrize("rel_tol", [1e-2, 1e-3, 1e-4])
def test_a_known_integral_within_the_tolerance(d, rel_tol):
    exact = product_peak_integral(d)
    r = sp.quad(product_peak, d, rel_tol=rel_tol, seed=d)
    assert r.met
    assert isinstance(r.estimate, float)
    assert r.half_width <= rel_tol * abs(r.estimate)
    # At 95 % the interval misses now and then; the tolerance itself is wider than
    # the half-width only by chance, so allow the error up to the tolerance doubled.
    assert abs(r.estimate - exact) <= 2 * rel_tol * exact
    # The face test's seven evaluations first; f is smooth, so the tent lattice's rounds.
    assert r.rule == "lattice" and "by a face test (7 evaluations" in r.rule_reason
    assert (r.n - 7) % r.replicates == 0 and r.n - 7 >= 64 * r.replicates


def test_a_box_scales_the_points_and_the_volume():
    # ∫_[1,3]×[0,2] x y dx dy = 4 · 2 = 8.
    r = sp.quad(lambda x: x[:, 0] * x[:, 1], 2, a=[1, 0], b=[3, 2], rel_tol=1e-4, seed=1)
    assert r.met
    assert abs(r.estimate - 8.0) <= 2e-3


def test_several_outputs_each_within_its_tolerance():
    def f(x):
        return np.column_stack([x.sum(axis=1), np.prod(x, axis=1), np.cos(x[:, 0])])

    exact = np.array([1.5, 1 / 8, math.sin(1.0)])
    r = sp.quad(f, 3, rel_tol=1e-3, seed=2)
    assert r.met
    assert r.estimate.shape == (3,) and r.half_width.shape == (3,)
    assert np.all(r.half_width <= 1e-3 * np.abs(r.estimate))
    assert np.all(np.abs(r.estimate - exact) <= 2e-3 * np.abs(exact))


def test_expectation_under_a_normal_input_is_its_closed_form():
    mu, sigma = 0.5, 0.4
    r = sp.quad(
        lambda x: np.exp(x[:, 0]) * x[:, 1],
        2,
        space={"x": f"normal({mu},{sigma})", "y": "uniform(2,4)"},
        rel_tol=1e-4,
        seed=3,
    )
    exact = math.exp(mu + sigma**2 / 2) * 3.0
    assert r.met
    assert abs(r.estimate - exact) <= 2e-4 * exact


def test_levels_of_a_space_are_equally_likely():
    # E[k] for k uniform on {1, ..., 4} is 2.5; a label's index on {a, b} has mean 0.5.
    r = sp.quad(
        lambda x: np.column_stack([x[:, 0], x[:, 1]]),
        2,
        space={"k": "int(1,4)", "c": ["a", "b"]},
        rel_tol=1e-3,
        seed=4,
    )
    assert np.allclose(r.estimate, [2.5, 0.5], rtol=2e-3)


def test_continuing_evaluates_only_new_points():
    seen = []

    def f(x):
        seen.append(x.copy())
        return product_peak(x)

    first = sp.quad(f, 4, rel_tol=1e-2, seed=5)
    calls, evaluated = len(seen), sum(len(x) for x in seen)
    assert evaluated == first.n
    finer = sp.quad(f, 4, rel_tol=1e-5, start=first)
    assert finer.n > first.n
    assert sum(len(x) for x in seen) == finer.n
    new = np.concatenate(seen[calls:])
    old = np.concatenate(seen[:calls])
    # No point evaluated before is asked again.
    assert not (set(map(tuple, new)) & set(map(tuple, old)))
    # The earlier result stands; a run straight to the finer tolerance is the same.
    assert first.n == evaluated
    direct = sp.quad(product_peak, 4, rel_tol=1e-5, seed=5)
    assert direct.n == finer.n and direct.estimate == finer.estimate


def test_a_result_pickles_and_continues():
    r = sp.quad(product_peak, 2, rel_tol=1e-2, seed=6)
    back = pickle.loads(pickle.dumps(r))
    assert (back.estimate, back.half_width, back.n, back.met) == (
        r.estimate,
        r.half_width,
        r.n,
        r.met,
    )
    more = sp.quad(product_peak, 2, rel_tol=1e-4, start=back)
    assert more.n > r.n and more.met


def square_sum(x):
    return np.column_stack([x.sum(axis=1) ** 2, np.exp(-x.sum(axis=1))])


def test_an_executor_gives_the_result_of_one_process():
    alone = sp.quad(square_sum, 3, rel_tol=1e-4, seed=7)
    with concurrent.futures.ThreadPoolExecutor(max_workers=3) as pool:
        threads = sp.quad(square_sum, 3, rel_tol=1e-4, seed=7, executor=pool)
    assert threads.n == alone.n
    assert np.array_equal(threads.estimate, alone.estimate)
    assert np.array_equal(threads.half_width, alone.half_width)


def test_an_executor_s_chunks_are_held_to_one_shape_and_its_futures_checked():
    # Chunks of one round must give what one call would: the same outputs per point and
    # the same shape (k = 1 in one chunk and 2 in another was numpy's concatenate error).
    def mixed(x):
        return x[:, 0] if x[0, 0] < 0.5 else np.column_stack([x[:, 0], x[:, 1]])

    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        with pytest.raises(ValueError, match=r"^invalid f: it returned"):
            sp.quad(mixed, 2, rel_tol=1e-3, executor=pool)

        def column_sometimes(x):
            return x[:, :1] if x[0, 0] < 0.5 else x[:, 0]

        with pytest.raises(ValueError, match="the same shape for every chunk"):
            sp.quad(column_sometimes, 2, rel_tol=1e-3, executor=pool)

    class NoFutures(concurrent.futures.Executor):
        _max_workers = 2

        def submit(self, fn, /, *args, **kwargs):
            return None

    with pytest.raises(TypeError, match=r"^invalid executor: its submit\(\) returned NoneType"):
        sp.quad(product_peak, 2, rel_tol=1e-3, executor=NoFutures())


def test_a_process_pool_gives_the_result_of_one_process():
    alone = sp.quad(square_sum, 2, rel_tol=1e-3, seed=8)
    with concurrent.futures.ProcessPoolExecutor(max_workers=2) as pool:
        procs = sp.quad(square_sum, 2, rel_tol=1e-3, seed=8, executor=pool)
    assert procs.n == alone.n and np.array_equal(procs.estimate, alone.estimate)


def test_a_dask_executor_gives_the_result_of_one_process():
    distributed = pytest.importorskip("dask.distributed")
    alone = sp.quad(square_sum, 2, rel_tol=1e-3, seed=14)
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=False,
        dashboard_address=":0",
        silence_logs=logging.ERROR,
    ) as cluster, distributed.Client(cluster) as client:
        with client.get_executor() as executor:
            r = sp.quad(square_sum, 2, rel_tol=1e-3, seed=14, executor=executor)
    assert r.n == alone.n and np.array_equal(r.estimate, alone.estimate)


def test_a_nan_is_refused_naming_the_point():
    def f(x):
        y = x.sum(axis=1)
        y[x[:, 0] > 0.9] = np.nan
        return y

    with pytest.raises(ValueError, match=r"invalid f: nan at x = \[0\.9"):
        sp.quad(f, 2, seed=9)


def test_an_infinity_in_a_space_names_the_value_f_saw():
    with pytest.raises(ValueError, match=r"inf at x = \[-?\d"):
        sp.quad(lambda x: np.where(x[:, 0] > 1.5, np.inf, 1.0), 1, space=["x=normal(0,1)"])


def test_ctrl_c_is_not_swallowed():
    calls = []

    def f(x):
        calls.append(len(x))
        if len(calls) == 2:
            raise KeyboardInterrupt
        return product_peak(x)

    with pytest.raises(KeyboardInterrupt):
        sp.quad(f, 3, rel_tol=1e-9, seed=10)
    assert len(calls) == 2


def test_a_real_sigint_stops_quad_every_time():
    import os
    import signal

    # The integrand itself says the run is under way: it sends SIGINT to this process
    # at its second call, so the signal lands inside quad however fast the machine is.
    # The tolerance is out of reach, so only the signal can end the run.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        for _ in range(5):
            calls = []

            def f(x):
                calls.append(len(x))
                if len(calls) == 2:
                    os.kill(os.getpid(), signal.SIGINT)
                return product_peak(x)

            with pytest.raises(KeyboardInterrupt):
                sp.quad(f, 3, rel_tol=1e-15, max_n=2**40, seed=10)
            assert 2 <= len(calls) <= 3
            # The next call runs normally.
            assert sp.quad(product_peak, 2, rel_tol=1e-2, seed=1).met
    finally:
        signal.signal(signal.SIGINT, previous)



def test_progress_true_writes_one_line_per_round(capsys):
    rounds = []

    def f(x):
        rounds.append(len(x))
        return product_peak(x)

    r = sp.quad(f, 3, rel_tol=1e-4, seed=20, progress=True)
    captured = capsys.readouterr()
    assert captured.out == ""
    rule_line, *lines = captured.err.splitlines()
    # The first line says the rule and why (a face test first, over the cube); then one
    # line per round, the face test's saying the rule it chose.
    assert rule_line.startswith("quad: a face test first") and "tent lattice" in rule_line
    assert r.rule_reason.startswith("tent lattice") and "smooth at the faces" in r.rule_reason
    assert lines[0] == "quad: n=7  rule: lattice" and rounds[0] == 7
    assert len(lines) == len(rounds) >= 2
    ns = [int(re.search(r"\bn=(\d+)", line).group(1)) for line in lines]
    assert ns == list(np.cumsum(rounds))
    assert ns[-1] == r.n
    last = lines[-1]
    assert last.startswith("quad: n=")
    estimate = float(re.search(r"estimate=(\S+)", last).group(1))
    half_width = float(re.search(r"half-width=(\S+)", last).group(1))
    target = float(re.search(r"\(target (\S+)\)", last).group(1))
    assert estimate == pytest.approx(r.estimate, rel=1e-5)
    assert half_width == pytest.approx(r.half_width, rel=0.06)
    assert target == pytest.approx(1e-4 * abs(r.estimate), rel=0.06)
    assert re.search(r"\d+\.\d s$", last)
    # Silent by default.
    sp.quad(product_peak, 3, rel_tol=1e-3, seed=20)
    assert capsys.readouterr() == ("", "")


def test_progress_lines_name_the_output_furthest_from_its_target(capsys):
    r = sp.quad(square_sum, 2, rel_tol=1e-3, seed=21, progress=True)
    lines = capsys.readouterr().err.splitlines()[2:]  # after the rule's and the face test's
    assert lines and all("(output " in line for line in lines)
    assert int(re.search(r"\bn=(\d+)", lines[-1]).group(1)) == r.n


def test_a_progress_callable_gets_each_round_and_the_final_result():
    seen = []
    r = sp.quad(product_peak, 4, rel_tol=1e-4, seed=22, progress=seen.append)
    assert len(seen) >= 2 and all(isinstance(s, sp.QuadResult) for s in seen)
    ns = [s.n for s in seen]
    assert all(a < b for a, b in zip(ns, ns[1:]))
    last = seen[-1]
    assert (last.n, last.estimate, last.half_width, last.met) == (
        r.n,
        r.estimate,
        r.half_width,
        r.met,
    )
    assert not any(s.met for s in seen[:-1])
    assert isinstance(seen[0].estimate, float)
    # With start=, the rounds continue from the earlier n.
    more = []
    finer = sp.quad(product_peak, 4, rel_tol=1e-5, start=r, progress=more.append)
    assert more and more[0].n > r.n and more[-1].n == finer.n


def test_a_raising_progress_callable_stops_the_run_like_ctrl_c():
    calls = []
    seen = []

    def f(x):
        calls.append(len(x))
        return product_peak(x)

    def stop(result):
        seen.append(result)
        if len(seen) == 2:
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        sp.quad(f, 3, rel_tol=1e-9, seed=23, progress=stop)
    # The face test's batch (no estimate, so no call), then two rounds.
    assert calls[0] == 7 and len(calls) == 3
    # The earlier result given as start= is unchanged, and a result the callable got
    # continues as an uninterrupted run would.
    first = sp.quad(product_peak, 3, rel_tol=1e-2, seed=23)
    before = (first.n, first.estimate, first.half_width)
    with pytest.raises(RuntimeError, match="enough"):
        seen.clear()
        sp.quad(product_peak, 3, rel_tol=1e-6, start=first, progress=stop)
    assert (first.n, first.estimate, first.half_width) == before
    resumed = sp.quad(product_peak, 3, rel_tol=1e-6, start=seen[-1])
    direct = sp.quad(product_peak, 3, rel_tol=1e-6, seed=23)
    assert (resumed.n, resumed.estimate) == (direct.n, direct.estimate)


@pytest.mark.parametrize("value", [None, 1, "yes", [True]])
def test_a_bad_progress_value_is_refused_naming_progress(value):
    calls = []

    def f(x):
        calls.append(len(x))
        return product_peak(x)

    with pytest.raises(ValueError, match=r"invalid progress\b"):
        sp.quad(f, 2, progress=value)
    assert not calls

def test_too_few_replicates_warn():
    with pytest.warns(UserWarning, match="replicates"):
        sp.quad(product_peak, 2, replicates=2, rel_tol=1e-2, seed=11)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sp.quad(product_peak, 2, rel_tol=1e-2, seed=11)


def test_max_n_stops_and_says_the_tolerance_was_not_met():
    r = sp.quad(product_peak, 5, rel_tol=1e-12, max_n=2**12, seed=12)
    assert not r.met and r.n <= 2**12


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"d": 0}, "d"),
        ({"d": 1001}, "d"),
        ({"d": 2.5}, "d"),
        ({"rel_tol": -1.0}, "rel_tol"),
        ({"abs_tol": float("nan")}, "abs_tol"),
        ({"level": 1.0}, "level"),
        ({"replicates": 1}, "replicates"),
        ({"a": [0, 0, 0]}, "a"),
        ({"b": [1, 1, "x"]}, "b"),
        ({"a": [0, 2], "b": [1, 1]}, "b"),
        ({"seed": -1}, "seed"),
        ({"executor": object()}, "executor"),
        ({"start": 3}, "start"),
        ({"space": {"x": "normal(0,1)"}}, "d"),
        ({"space": ["x=nope(1)", "y=normal(0,1)"]}, "space"),
    ],
)
def test_bad_arguments_name_the_argument(kwargs, name):
    args = {"d": 2, **kwargs}
    d = args.pop("d")
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        sp.quad(product_peak, d, **args)


def test_a_callable_is_required_and_its_shape_checked():
    with pytest.raises(ValueError, match="invalid f"):
        sp.quad(3, 2)
    with pytest.raises(ValueError, match=r"invalid f: it returned shape"):
        sp.quad(lambda x: x.sum(), 2)


def test_start_keeps_its_dimension():
    r = sp.quad(product_peak, 2, rel_tol=1e-2, seed=13)
    with pytest.raises(ValueError, match=r"invalid d = 3"):
        sp.quad(product_peak, 3, start=r)
    with pytest.raises(ValueError, match=r"invalid seed with start"):
        sp.quad(product_peak, 2, start=r, seed=1)


def test_a_pilot_round_chooses_the_rule_when_asked_and_is_counted():
    # Singular at every face, where either rule may be narrower after one round.
    f = lambda x: np.prod(x * (1 - x), axis=1) ** -0.25  # noqa: E731
    kept = set()
    for seed in range(8):
        r = sp.quad(f, 4, rel_tol=1e-7, max_n=4096 + 256, seed=seed, rule="pilot")
        assert "a pilot of 256 evaluations, counted" in r.rule_reason
        alone = sp.quad(f, 4, rel_tol=1e-7, max_n=4096, seed=seed, rule=r.rule)
        # The rule kept goes on from its own first round: its answer, and the other
        # rule's first round counted.
        assert (r.estimate, r.half_width, r.n) == (alone.estimate, alone.half_width,
                                                   alone.n + 256)
        kept.add(r.rule)
    assert kept == {"lattice", "sobol"}
    # Near the tolerance there is no pilot round: the lattice's run as it is.
    r = sp.quad(f, 4, rel_tol=0.5, seed=1, rule="pilot")
    assert r.rule == "lattice" and "without a pilot round" in r.rule_reason
    assert r.n == sp.quad(f, 4, rel_tol=0.5, seed=1, rule="lattice").n
    # A progress display sees the lattice's first round, then the rule kept.
    seen = []
    sp.quad(f, 4, rel_tol=1e-7, max_n=4096 + 256, seed=0, rule="pilot",
            progress=seen.append)
    assert [s.n for s in seen][:2] == [256, 512] and seen[0].rule == "lattice"
    with pytest.raises(ValueError, match=r"invalid rule = 'halton': expected lattice.*pilot"):
        sp.quad(f, 1, rule="halton")


def test_the_rule_follows_the_laws_and_says_why():
    from scipy import stats

    f = lambda x: x[:, 0] ** 2  # noqa: E731
    g = lambda x: np.exp(x.sum(axis=1))  # noqa: E731
    three = {"z": "normal(0,1)", "y": "normal(0,1)", "w": "normal(0,1)"}
    r = sp.quad(g, 3, space=three, rel_tol=1e-2)
    assert r.rule == "sobol" and "(z, y, w)" in r.rule_reason and "not even" in r.rule_reason
    assert "tail map" not in r.rule_reason
    assert r.estimate == pytest.approx(math.exp(1.5), rel=0.03)
    r = sp.quad(g, 3, space={"z": stats.norm(0, 1), "y": stats.norm(0, 1),
                             "w": stats.norm(0, 1)}, rel_tol=1e-2)
    assert r.rule == "sobol", "a SciPy law with unbounded support counts as unbounded"
    # With one unbounded input its tails are reached through the tail map, where
    # exp(z)·T′ decays: flat at the faces, it goes on with the Bayesian lattice.
    for law in ["normal(0,1)", stats.norm(0, 1)]:
        r = sp.quad(g, 1, space={"z": law}, rel_tol=1e-2)
        assert r.rule == "bayesian lattice" and "tail map" in r.rule_reason
        assert r.replicates == 1 and "smooth at the faces" in r.rule_reason
        assert r.estimate == pytest.approx(math.exp(0.5), rel=0.03)
    # f even in Z: the same lattice, the probe's 64 evaluations counted.
    r = sp.quad(f, 1, space={"z": "normal(0,1)"}, rel_tol=1e-2)
    assert r.rule == "bayesian lattice" and "f even under Z" in r.rule_reason
    assert r.n == 64 + 256 and r.estimate == pytest.approx(1.0, rel=0.03)
    more = sp.quad(f, 1, start=r, rel_tol=r.half_width / 8, rule=r.rule)
    assert more.rule == r.rule and more.n > r.n and more.replicates == 1
    # The result's own count passed back is taken, its one lattice included (a new
    # run's range, 2 to 16384, refuses 1), as is the count asked for (4); another count
    # is refused as before.
    same = sp.quad(f, 1, start=r, rel_tol=r.half_width / 8, rule=r.rule,
                   replicates=r.replicates)
    assert (same.n, same.estimate) == (more.n, more.estimate)
    with pytest.raises(ValueError, match=r"invalid replicates = 8"):
        sp.quad(f, 1, start=r, rel_tol=r.half_width / 8, replicates=8)
    with pytest.raises(ValueError, match=r"invalid replicates = 0"):
        sp.quad(f, 1, start=r, rel_tol=r.half_width / 8, replicates=0)
    assert more.half_width <= r.half_width / 8
    assert more.estimate == pytest.approx(1.0, abs=10 * more.half_width)
    # Asked for by name: from its own first round of 64 points per replicate.
    r = sp.quad(g, 1, space={"z": "normal(0,1)"}, rel_tol=1e-2, rule="first-order lattice")
    assert r.rule == "first-order lattice" and r.rule_reason.startswith("as asked")
    assert r.estimate == pytest.approx(math.exp(0.5), rel=0.03) and r.n % 64 == 0
    r = sp.quad(f, 1, space={"u": "uniform(0,1)"}, rel_tol=1e-2)
    assert r.rule == "lattice" and "bounded" in r.rule_reason
    assert r.estimate == pytest.approx(1 / 3, rel=0.03)
    r = sp.quad(f, 1, rel_tol=1e-2)
    assert r.rule == "lattice" and "rule='lattice'" in repr(r)
    # Asked for: honoured and said so; a continuation keeps it.
    r = sp.quad(f, 1, rule="sobol", rel_tol=1e-2)
    assert (r.rule, r.rule_reason) == ("sobol", "as asked (rule='sobol')")
    more = sp.quad(f, 1, start=r, rel_tol=1e-3)
    assert more.rule == "sobol" and more.n > r.n
    with pytest.raises(ValueError, match=r"invalid rule = 'lattice' with start"):
        sp.quad(f, 1, start=r, rule="lattice")
    with pytest.raises(ValueError, match=r"invalid rule = 'halton': expected lattice"):
        sp.quad(f, 1, rule="halton")


def _grown():
    """A result that added replicates (the first tolerance, from a sweep, at which one
    did)."""
    for i in range(40):
        r = sp.quad(product_peak, 3, rel_tol=3e-3 * 0.85**i, seed=2)
        if r.replicates > 4:
            return r, 3e-3 * 0.85**i
    pytest.fail("no tolerance of the sweep added a replicate")


def test_added_replicates_are_counted_and_continued():
    r, tol = _grown()
    assert r.met and r.half_width <= tol * abs(r.estimate)
    # Every replicate has as many points; the means are the replicates counted.
    assert len(r.replicate_means) == r.replicates
    assert (r.n - 7) % r.replicates == 0  # after the face test's 7
    assert abs(r.estimate - float(np.mean(r.replicate_means))) <= 1e-12 * abs(r.estimate)
    # The replicates asked for (4, the default) continue it; doublings keep the added.
    more = sp.quad(product_peak, 3, rel_tol=tol / 10, start=r, replicates=4)
    assert more.met and more.replicates >= r.replicates and more.n > r.n
    # So does the count the result reports, the added one included.
    shown = sp.quad(product_peak, 3, rel_tol=tol / 10, start=r, replicates=r.replicates)
    assert r.replicates > 4 and (shown.n, shown.estimate) == (more.n, more.estimate)
    # A pickled result continues to the same answer.
    back = sp.quad(product_peak, 3, rel_tol=tol / 10, start=pickle.loads(pickle.dumps(r)))
    assert (back.n, back.estimate, back.replicates) == (more.n, more.estimate, more.replicates)


def test_an_event_is_integrated_on_scrambled_sobol_and_says_why():
    # The indicator of x1 + x2 < 0.8 takes two values: after the lattice's first round
    # (counted) scrambled Sobol' goes on from its own first round.
    def f(x):
        return (x[:, 0] + x[:, 1] < 0.8).astype(float)

    r = sp.quad(f, 4, rel_tol=1e-2, seed=3)
    assert r.rule == "sobol" and "took few values" in r.rule_reason, r.rule_reason
    alone = sp.quad(f, 4, rel_tol=1e-2, seed=3, rule="sobol", max_n=2**20 - 256 - 7)
    # The face test's 7 evaluations (a step is flat near the corners: the tent lattice)
    # and the lattice's first round are counted.
    assert (r.n, r.estimate) == (alone.n + 256 + 7, alone.estimate)
    # Asked for by name, the lattice is kept.
    assert sp.quad(f, 4, rel_tol=1e-2, seed=3, rule="lattice").rule == "lattice"


def test_tied_replicate_means_of_a_step_claim_no_tolerance():
    # A step in one coordinate on the lattice: every shift of its grid may hold the same
    # count of points inside, and four equal replicate means are their resolution, not
    # an exact answer.
    def f(x):
        return 1.0 + (np.abs(x[:, 0] - 0.45) < 0.3)

    for seed in range(10):
        r = sp.quad(f, 3, rel_tol=1e-6, max_n=2**14, seed=seed, rule="lattice")
        assert r.half_width > 1e-9 and not r.met, (seed, r.estimate, r.half_width)


def test_a_face_test_reads_f_steep_at_a_face_and_an_infinite_value_there():
    # Over the cube: a quantile function inside f takes the Bayesian net (after the test's
    # 7 evaluations and the probe's 64, counted), or with a plateau the first-order
    # lattice; a smooth f the tent lattice, after the test's 7 evaluations.
    from scipy.special import ndtri, ndtr

    def lognormal(x):
        return np.exp(0.5 * ndtri(x).sum(axis=1))

    steep = sp.quad(lognormal, 3, rel_tol=1e-3, seed=2)
    assert steep.rule == "bayesian net" and "steep at a face" in steep.rule_reason
    alone = sp.quad(lognormal, 3, rel_tol=1e-3, seed=2, rule="bayesian net")
    assert (steep.n, steep.estimate) == (alone.n + 71, alone.estimate)
    assert steep.estimate == pytest.approx(math.exp(3 / 8), rel=3e-3)
    # max(e^{S/2}, 1) for S ~ N(0, 3): a plateau at 1 over half the cube.
    kink = sp.quad(lambda x: np.maximum(lognormal(x), 1.0), 3, rel_tol=1e-3, seed=2)
    assert kink.rule == "first-order lattice" and "plateau" in kink.rule_reason
    exact = 0.5 + math.exp(3 / 8) * ndtr(math.sqrt(3) / 2)
    assert kink.estimate == pytest.approx(exact, rel=3e-3)
    smooth = sp.quad(product_peak, 3, rel_tol=1e-3, seed=2)
    alone = sp.quad(product_peak, 3, rel_tol=1e-3, seed=2, rule="lattice")
    assert (smooth.rule, smooth.n, smooth.estimate) == ("lattice", alone.n + 7, alone.estimate)
    # Infinite only within 1e-7 of the face x1 = 0, which the test's points reach and the
    # net's do not: read as steep, not refused.
    r = sp.quad(lambda x: np.where(x[:, 0] < 1e-7, np.inf, 1 + x[:, 0]), 2, rel_tol=1e-2,
                seed=0)
    assert r.rule == "bayesian net" and "not finite" in r.rule_reason
    assert r.estimate == pytest.approx(1.5, rel=1e-2)


def test_over_the_cube_an_even_f_steep_at_a_face_takes_the_bayesian_lattice():
    # cos(|Z|/2) with Z = Φ⁻¹(x) written into f: steep at the faces and even under
    # x ↦ 1 − x, so after the face test's 7 evaluations and the probe's 64 it goes on as
    # through normal laws. E cos(a|Z|) = (1 − a²)·e^(−a²/2) for Z standard normal in 3-D.
    from scipy.special import ndtri

    def f(x):
        return np.cos(0.5 * np.sqrt((ndtri(x) ** 2).sum(axis=1)))

    for seed in range(3):
        r = sp.quad(f, 3, rel_tol=1e-3, seed=seed)
        assert r.rule == "bayesian lattice", r.rule_reason
        assert "steep at a face" in r.rule_reason and "even under x ↦ 1 − x" in r.rule_reason
        lattice = r.n - 7 - 64
        assert lattice >= 256 and lattice & (lattice - 1) == 0, r.n
        assert r.estimate == pytest.approx(0.75 * math.exp(-0.125), rel=3e-3)


def test_under_unbounded_laws_a_face_test_after_the_probe_chooses_lattice_or_sobol():
    # Not even under Z ↦ −Z: after the probe's 64 points, 7 at the faces. A Gaussian bump
    # of normal inputs is flat there and goes on with the Bayesian lattice; exp(ΣZ)
    # is steep there and goes on with the Bayesian net (Sobol' where f shows a plateau);
    # both counted.
    laws = [f"z{i}=normal(0,1)" for i in range(3)]
    bump = sp.quad(lambda z: np.exp(-((z - 0.5) ** 2).sum(axis=1)), 3, space=laws,
                   rel_tol=1e-3, seed=3)
    assert bump.rule == "bayesian lattice", bump.rule_reason
    assert "smooth at the faces" in bump.rule_reason
    exact = (math.exp(-0.25 / 3) / math.sqrt(3)) ** 3
    assert bump.estimate == pytest.approx(exact, rel=3e-3)
    grow = sp.quad(lambda z: np.exp(z.sum(axis=1) / 3), 3, space=laws, rel_tol=1e-3, seed=3)
    assert grow.rule == "bayesian net" and "steep at a face" in grow.rule_reason
    assert grow.estimate == pytest.approx(math.exp(1 / 6), rel=3e-3)
    # A call's payoff max(e^X − 1, 0), X = ΣZ/3 ~ N(0, 1/3): zero on half the space, a
    # plateau the probe sees, so Sobol's replicates; E = e^{1/6}·Φ(1/√3) − ½.
    from scipy.special import ndtr

    call = sp.quad(lambda z: np.maximum(np.exp(z.sum(axis=1) / 3) - 1.0, 0.0), 3,
                   space=laws, rel_tol=1e-3, seed=3)
    assert call.rule == "sobol" and "plateau" in call.rule_reason, call.rule_reason
    exact = math.exp(1 / 6) * ndtr(1 / math.sqrt(3)) - 0.5
    assert call.estimate == pytest.approx(exact, rel=3e-3)
    # An infinite value at the faces' points is read as steep there, not refused.
    inf_tail = sp.quad(lambda z: np.where(np.abs(z[:, 0]) > 5.5, np.inf,
                                          np.exp(-((z - 0.5) ** 2).sum(axis=1))),
                       3, space=laws, rel_tol=1e-2, seed=3)
    assert inf_tail.rule == "bayesian net" and "not finite" in inf_tail.rule_reason
