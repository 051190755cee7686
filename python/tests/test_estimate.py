"""The long-call warning: generate, extend and nested warn with the library's note
before a run its cost model puts above 5 seconds (the command line's rule), and before any work (so that a filter turning the
warning into an error stops the call at once)."""

import time
import warnings

import pytest

import stillpoint as sp
from stillpoint import _core

# Each is hours on 2 cores by the cost model, so minutes even on a large machine. The
# default from 500 points on is a lattice built in seconds at (20 000, 50); its report's
# pair passes at thousands of coordinates are what take hours.
HUGE = [
    ("generate", lambda: sp.generate(10000, 5000)),
    ("extend", lambda: sp.extend(sp.generate(8, 50), 19992)),
    ("nested", lambda: sp.nested([10000, 20000], 50)),
    ("paper", lambda: sp.generate(20000, 50, method="paper")),
]


class Stopped(Exception):
    pass


def warning_of(call):
    """The warning `call` issues first, as (message, category, file, line), stopping the
    call there; None when it issues none (then the call has run)."""
    seen = []

    def stop(message, category, filename, lineno, file=None, line=None):
        seen.append((str(message), category, filename, lineno))
        raise Stopped

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.showwarning = stop
        try:
            call()
        except Stopped:
            pass
    return seen[0] if seen else None


def test_the_estimate_is_the_librarys_and_refuses_like_generate():
    assert _core.estimate(n=10000, d=5000) > 30
    assert 0 < _core.estimate(n=16, d=2) < 1
    assert _core.estimate(n=1000, d=5, method="sobol") < 0.1
    with pytest.raises(ValueError, match=r"^invalid steps = 0"):
        _core.estimate(n=16, d=2, steps=0)


@pytest.mark.parametrize("name, call", HUGE, ids=[h[0] for h in HUGE])
def test_a_huge_call_warns_before_it_starts(name, call):
    started = time.monotonic()
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.raises(RuntimeWarning, match=r"may take about .*estimated for this machine"):
            call()
    # The warning came before the run: nothing of an hours-long run was done.
    assert time.monotonic() - started < 5.0


@pytest.mark.parametrize("name, call", HUGE[:3], ids=[h[0] for h in HUGE[:3]])
def test_the_warning_points_at_the_callers_line(name, call):
    message, category, filename, _ = warning_of(call)
    assert category is RuntimeWarning
    assert filename == __file__
    assert message.startswith("stillpoint: this run may take about ")


def test_the_warning_is_the_librarys_note_and_its_threshold():
    message, category, _, _ = warning_of(lambda: sp.generate(10000, 5000))
    assert category is RuntimeWarning
    assert message == "stillpoint: " + _core.long_run_note(n=10000, d=5000)
    # One rule with the command line: a note exactly when the estimate is above 5 s.
    for n, d in [(64, 3), (400, 30), (400, 100), (2000, 2000)]:
        assert (_core.long_run_note(n=n, d=d) is not None) == (_core.estimate(n=n, d=d) > 5), (n, d)


def test_an_ordinary_call_does_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        x = sp.generate(64, 3)
        sp.extend(x, 16)
        sp.nested([8, 16], 2)
        sp.generate(1000, 5, method="sobol")
    assert warning_of(lambda: sp.generate(32, 2)) is None
