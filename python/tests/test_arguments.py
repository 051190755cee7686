"""Arguments as Python code has them: NumPy integers wherever a count or seed is taken,
spaces in every form generate takes (also through generate_many), SciPy laws checked
before their values are written, design tables crossing as values; every refusal a
ValueError naming the argument."""

import numbers
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import stillpoint as sp

stats = pytest.importorskip("scipy.stats")


class Index:
    """An integer-like that is no int: only ``__index__``."""

    def __init__(self, v):
        self.v = v

    def __index__(self):
        return self.v


# --- integer-likes ---------------------------------------------------------------------


@pytest.mark.parametrize("seed", [np.int64(7), np.uint64(7), np.int32(7), Index(7), 7.0])
def test_integer_like_seeds_are_the_seed_they_say(seed):
    np.testing.assert_array_equal(sp.generate(16, 2, seed=seed), sp.generate(16, 2, seed=7))


def test_a_numpy_seed_above_2_to_63_is_exact():
    big = 2**63 + 5
    a = sp.generate(8, 2, method="sobol", seed=np.uint64(big))
    np.testing.assert_array_equal(a, sp.generate(8, 2, method="sobol", seed=big))
    # A float would have rounded it to 2^63 + 0 (or + 8): a different scramble.
    assert not np.array_equal(a, sp.generate(8, 2, method="sobol", seed=2**63 + 8))


def test_a_seed_loop_over_arange_runs_in_every_entry_point():
    for s in np.arange(3):
        assert sp.generate(np.int64(16), np.int64(2), seed=s).shape == (16, 2)
        d = sp.design(np.int64(8), {"x": "uniform(0,1)", "c": ["a", "b"]}, seed=s)
        assert len(d) == 8
        e = sp.Engine(2, seed=s)
        assert e.random(np.int64(8)).shape == (8, 2)
    out = sp.generate_many([{"n": 8, "d": 2, "seed": s} for s in np.arange(2)],
                           executor=_Inline())
    np.testing.assert_array_equal(out[1], sp.generate(8, 2, seed=1))


def test_integer_likes_are_counts_in_every_function():
    x = sp.generate(8, 2)
    assert sp.extend(x, np.int64(4)).shape == (12, 2)
    np.testing.assert_array_equal(sp.nested(np.array([4, 8]), np.int64(2)),
                                  sp.nested([np.int64(4), Index(8)], 2))
    assert sp.baseline("sobol", np.int64(8), np.uint8(2), seed=np.uint64(3)).shape == (8, 2)
    assert sp.generate(np.int32(8), 2, steps=np.int64(5), method="paper").shape == (8, 2)
    with pytest.raises(ValueError, match=r"^invalid n = "):
        sp.generate(np.float64(8.5), 2)
    with pytest.raises(ValueError, match=r"^invalid d = "):
        sp.generate(8, np.True_)


@pytest.mark.parametrize("seed", [True, np.True_, 1.5, "x", -1, 2**64, np.float64(2.5)])
def test_bools_fractions_and_out_of_range_seeds_are_refused_by_name(seed):
    with pytest.raises(ValueError, match=r"^invalid seed = "):
        sp.generate(8, 2, seed=seed)


@pytest.mark.parametrize("seed", [1.5, "1", True, [1]])
def test_engine_seeds_are_refused_by_name(seed):
    with pytest.raises(ValueError, match=r"^invalid seed = "):
        sp.Engine(2, seed=seed)
    with pytest.raises(ValueError, match=r"^invalid rng = "):
        sp.Engine(2, rng=seed)


def test_engine_takes_integer_likes_and_generators():
    a = sp.Engine(2, seed=np.int64(3)).random(8)
    np.testing.assert_array_equal(a, sp.Engine(2, seed=3).random(8))
    np.testing.assert_array_equal(a, sp.Engine(2, rng=np.random.default_rng(3)).random(8))
    assert isinstance(np.int64(3), numbers.Integral)


# --- generate_many takes what generate takes -------------------------------------------


class _Inline:
    """An executor that runs each request at once in this process."""

    def submit(self, f, *args):
        from concurrent.futures import Future

        fut = Future()
        try:
            fut.set_result(f(*args))
        except BaseException as e:  # noqa: BLE001 - handed to the caller as a future's
            fut.set_exception(e)
        return fut


@pytest.mark.parametrize(
    "space",
    [
        {"x": "normal(0,1)", "c": ["a", "b"]},
        {"x": stats.norm(0, 2), "k": range(1, 4)},
        ["x=uniform(0,1)", "y=beta(2,3)"],
    ],
)
def test_generate_many_takes_every_space_generate_takes(space):
    req = {"n": 12, "space": space, "seed": 4}
    (got,) = sp.generate_many([req], executor=_Inline())
    want = sp.generate(12, space=space, seed=4)
    assert list(got.columns if hasattr(got, "columns") else got) == list(
        want.columns if hasattr(want, "columns") else want
    )
    for name in space if isinstance(space, dict) else [v.split("=")[0] for v in space]:
        np.testing.assert_array_equal(np.asarray(got[name]), np.asarray(want[name]))


def test_generate_many_refuses_a_bad_space_before_any_run():
    with pytest.raises(ValueError, match=r"^invalid requests\[1\]: invalid space"):
        sp.generate_many(
            [{"n": 8, "d": 2}, {"n": 8, "space": {"v": stats.norm(0, -1)}}],
            executor=_Inline(),
        )
    with pytest.raises(ValueError, match=r"^invalid requests\[0\]"):
        sp.generate_many([{"d": 2}], executor=_Inline())


# --- refusals are ValueErrors ----------------------------------------------------------


@pytest.mark.parametrize(
    "space",
    [
        {"k": range(-(2**62), 2**62), "c": ["a", "b"]},
        {"k": range(0, 2**70)},
        {"k": range(5, 5)},
    ],
)
def test_huge_or_empty_ranges_are_value_errors(space):
    with pytest.raises(ValueError, match=r"invalid space"):
        sp.design(8, space)


@pytest.mark.parametrize(
    "table",
    [
        {"x": [0.25, 0.75], "c": ["a"]},
        {"x": [0.25], "c": ["a", "b"]},
        {"x": [], "c": ["a"]},
    ],
)
def test_design_figures_refuses_unequal_columns(table):
    with pytest.raises(ValueError, match=r"^invalid table"):
        sp.design_figures(table, ["x=uniform(0,1)", "c={a,b}"])


# --- design_figures reads values, not a CSV text ---------------------------------------


@pytest.mark.parametrize("label", ["a\n0.5,b", "a,b", 'a"b'])
def test_a_label_with_a_separator_is_a_label_not_a_row(label):
    with pytest.raises(ValueError, match=r"^invalid table row 1, c") as e:
        sp.design_figures({"x": [0.25, 0.75], "c": [label, "b"]}, ["x=uniform(0,1)", "c={a,b}"])
    assert "\n" not in str(e.value)


def test_design_figures_of_a_design_are_its_figures():
    d = sp.design(20, ["x=normal(0,1)", "k=int(1,4)", "c={a,b}"], seed=3)
    assert sp.design_figures(d.columns, d.space) == d.figures
    # Integers as pandas writes a column with a gap: floats with no fraction.
    cols = dict(d.columns, k=d.columns["k"].astype(np.float64))
    assert sp.design_figures(cols, d.space) == d.figures


# --- SciPy laws ------------------------------------------------------------------------


@pytest.mark.parametrize(
    "law, what",
    [
        (stats.norm(0, -1), "norm"),
        (stats.uniform(0, np.inf), "uniform"),
        (stats.norm(np.inf, 1), "norm"),
    ],
)
def test_a_law_with_nan_or_infinite_quantiles_is_refused(law, what):
    with pytest.raises(ValueError, match=rf"^invalid space v = {what}\("):
        sp.design(20, {"v": law, "c": ["a", "b"]})


@pytest.mark.parametrize("law", [stats.poisson(3), stats.binom(10, 0.5), stats.randint(1, 5)])
def test_a_discrete_law_is_refused_with_the_way_to_write_it(law):
    with pytest.raises(ValueError, match=r"int\(lo,hi\)"):
        sp.design(20, {"v": law})


def test_a_law_whose_values_collapse_is_refused():
    with pytest.raises(ValueError, match=r"distinct"):
        sp.design(20, {"v": stats.uniform(1e15, 0.1)})


def test_a_good_law_keeps_its_figures():
    d = sp.design(20, {"v": stats.gamma(2.0), "c": ["a", "b"]}, seed=1)
    assert np.all(np.isfinite(d.columns["v"]))
    assert d.figures["slices"][0]["stratified"] == 2


# --- the figures are those of the written values ----------------------------------------


@pytest.mark.parametrize(
    "space",
    [
        ["x=uniform(1000000000000000,1000000000000000.1)"],
        ["x=uniform(0,5e-324)"],
        ["x=normal(1e300,1e-300)", "c={a,b}"],
    ],
)
def test_a_range_without_n_distinct_floats_is_refused(space):
    with pytest.raises(ValueError, match=r"^invalid space x = .*distinct values"):
        sp.design(20, space)


def test_extreme_parameters_are_echoed_short():
    with pytest.raises(ValueError) as e:
        sp.design(20, ["x=uniform(1e300,1e300)"])
    assert "1e300" in str(e.value) and "0000000000" not in str(e.value)
    with pytest.raises(ValueError, match=r"^invalid p = -1e300: ") as e:
        sp.generate(8, 2, method="paper", p=-1e300)


@pytest.mark.parametrize(
    "space, correlation",
    [
        (["x=normal(0,1)", "y=normal(0,1)"], [[1, 0.7], [0.7, 1]]),
        (["a=uniform(0,1)", "k=int(1,3)", "b=lognormal(0,0.5)"], "1,-0.4;-0.4,1"),
        (["x=uniform(-1,1)", "g={p,q}", "y=beta(2,3)"], np.array([[1, 0.9], [0.9, 1]])),
    ],
)
def test_a_correlated_design_records_what_reproduces_its_figures(space, correlation):
    d = sp.design(24, space, correlation=correlation, seed=2)
    assert d.correlation is not None
    assert sp.design_figures(d.columns, d.space, d.correlation) == d.figures


@pytest.mark.parametrize("shape", ["ball:1e-300", "ball:1e-120@0,0", "ellipsoid:1,1e-200"])
def test_a_shape_too_small_for_finite_energies_is_refused(shape):
    with pytest.raises(ValueError, match=r"^invalid shape = "):
        sp.generate(10, 2, shape=shape)
    with pytest.raises(ValueError, match=r"^invalid shape = "):
        sp.metrics(np.zeros((3, 2)), shape=shape)


@pytest.mark.parametrize(
    "constraint", [([1e300, 0.0], 1e299), "1e-300*x1 <= 1e-301", ([-1e300, 0.0], -1e299)]
)
def test_extreme_coefficients_are_the_constraint_they_write(constraint):
    x = sp.generate(10, box=[0, 1, 0, 1], constraints=[constraint])
    lower = isinstance(constraint, tuple) and constraint[0][0] < 0
    if lower:
        assert np.all(x[:, 0] >= 0.1 - 1e-12)
    else:
        assert np.all(x[:, 0] <= 0.1 + 1e-12)


# --- Ctrl-C ----------------------------------------------------------------------------

# Each call is run REPS times in one process, each time interrupted: a helper thread
# waits for an event set just before the call and then sends SIGINT. The helper needs
# the GIL to send it, which the main thread gives up when the call releases it; so the
# signal lands in the call, and a signal that came before it would raise
# KeyboardInterrupt just the same. Nothing here waits for a time: the calls are made
# long (many seconds on a fast machine, see CALLS), so that "finished" means the signal
# was not honoured, never that the machine was quick.
_INTERRUPT = r"""
import os, signal, sys, threading, time, warnings
import numpy as np
import stillpoint as sp
# As an interactive Python has it, even when this process started with SIGINT ignored
# (a child of a background shell): the signal must raise KeyboardInterrupt.
signal.signal(signal.SIGINT, signal.default_int_handler)
warnings.simplefilter("ignore", RuntimeWarning)  # the long-call warning
x = np.random.default_rng(0).random((12000, 5))
sp.metrics(x[:50])  # warm the module
go = threading.Event()
sent = []
def stop():
    go.wait()
    sent.append(time.monotonic())
    os.kill(os.getpid(), signal.SIGINT)
for _ in range(REPS):
    go.clear()
    sent.clear()
    helper = threading.Thread(target=stop, daemon=True)
    helper.start()
    try:
        go.set()
        CALL
        print("finished", flush=True)
        break
    except KeyboardInterrupt:
        print(f"interrupted {time.monotonic() - sent[0]:.3f}", flush=True)
    helper.join()
    # The next call runs normally: the stop request is cleared.
    assert sp.generate(16, 2).shape == (16, 2)
"""

_REPS = 5

# Seconds of work each on a 2-core machine, and far longer than the few milliseconds the
# helper takes to send the signal once the call has begun. An interrupted call's worker
# is waited for by the next call (which then runs normally), so each is also small
# enough for that wait not to slow the repetitions down.
_CALLS = [
    "sp.metrics(x, exact=True)",
    "sp.metrics(x[:, :3], exact=True)",
    "sp.discrepancy(np.vstack([x, x, x]), 'modified')",
    "sp.metrics(np.vstack([x, x])[:, :2] * 0.5, shape='ball:1@0.5,0.5')",
    "sp.design(20000, ['x=uniform(0,1)', 'y=normal(0,1)', 'c={a,b}'])",
    "sp.generate(8000, 5, target='blend')",
    "sp.generate(3000, 3, mixture=True)",
    # Doublings of 2^31 coordinates (the indices at d = 300) and rounds of 2^31 (quad
    # at s = 1 000), made and fed in bounded batches.
    "sp.sobol_indices(lambda u: u.sum(1) + u[:, 0] * u[:, 1], 300, abs_tol=1e-9, "
    "max_n=10**9)",
    "sp.quad(lambda u: u.sum(1) + u[:, 0] * u[:, 1], 1000, rel_tol=1e-15)",
]


@pytest.mark.parametrize("call", _CALLS)
def test_ctrl_c_stops_a_long_call_every_time(call):
    done = subprocess.run(
        [sys.executable, "-c", _INTERRUPT.replace("CALL", call).replace("REPS", str(_REPS))],
        capture_output=True,
        text=True,
        cwd=pathlib.Path(__file__).parent,
    )
    lines = done.stdout.split()
    assert done.returncode == 0, (done.stdout, done.stderr)
    assert lines[::2] == ["interrupted"] * _REPS, (done.stdout, done.stderr)
    # From the signal to KeyboardInterrupt: the call looks at the signals every 50 ms
    # and waits at most 0.3 s more for its worker. The bound is ten times that: the
    # threads that poll and raise are the last to be scheduled on a loaded machine, and
    # this is a promise about not hanging, not a speed claim.
    latencies = [float(v) for v in lines[1::2]]
    assert max(latencies) < 3.5, latencies


def test_every_form_of_a_value_is_the_same_request():
    # Tuples of sides, lists, arrays, pandas Series and a box's pairs: the library reads
    # each form into one request, so the points are the same.
    import pandas as pd

    want = sp._core.generate(n=16, d=2, bounds=([0, 0], [2, 3]))
    for bounds in [(0, [2, 3]), (np.zeros(2), np.array([2.0, 3.0])),
                   (pd.Series([0, 0]), (2, 3)), [0, 2, 0, 3], np.array([0, 2, 0, 3]),
                   [(0, 2), (0, 3)]]:
        np.testing.assert_array_equal(sp._core.generate(n=16, d=2, bounds=bounds), want)
    with pytest.raises(ValueError, match=r"^invalid bounds = \{'lo': 0\}: expected a number, "
                       r"a string, a list of numbers or an \(n, d\) array$"):
        sp._core.generate(n=16, d=2, bounds={"lo": 0})
