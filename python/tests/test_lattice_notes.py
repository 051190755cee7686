"""The default lattice's corners from Python: a long run at large d warns before it
starts (its report's passes are in the estimate), columns that will share a generator
warn with which, and the progress shows the lattice's stages."""

import warnings

import numpy as np
import pytest

import stillpoint as sp
from stillpoint import _core


@pytest.mark.parametrize("n, d", [(600, 20000), (2000, 2000), (800, 8000)])
def test_a_lattice_run_at_large_d_warns_before_it_starts(n, d):
    assert _core.estimate(n=n, d=d) > 30
    with warnings.catch_warnings():
        # The shared-generator note comes after the estimate's warning: only the latter
        # is an error here, and it stops the call before any work.
        warnings.simplefilter("ignore", UserWarning)
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.raises(RuntimeWarning, match=r"may take about .*estimated for this machine"):
            sp.generate(n, d)


@pytest.mark.parametrize(
    "n, d, shared", [(510, 100, 36), (600, 90, 10), (509, 300, 46)]
)
def test_columns_that_will_share_a_generator_warn_with_how_many(n, d, shared):
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        x = sp.generate(n, d)
    notes = [w for w in seen if issubclass(w.category, UserWarning)]
    assert len(notes) == 1, [str(w.message) for w in seen]
    assert f"{shared} columns reuse one" in str(notes[0].message)
    assert notes[0].filename == __file__
    # The columns named as sharing are the same column up to x -> 1 - x and a shift:
    # their 2-D projection has far fewer distinct differences than two free columns.
    assert x.shape == (n, d)
    assert _core.notes(n=n, d=d) == [str(notes[0].message)]


def test_no_note_within_the_distinct_generators_or_off_the_lattice():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sp.generate(510, 64)
        sp.generate(400, 30)
        sp.generate(510, 100, method="sobol")
    assert _core.notes(n=510, d=64) == []
    with pytest.raises(ValueError, match="n"):
        _core.notes(n=0, d=3)


def test_progress_names_the_lattice_stages(capfd):
    sp.generate(600, 5, progress=True)
    err = capfd.readouterr().err
    for stage in ["generating vector", "shift selection", "metrics"]:
        assert f"stillpoint: {stage}" in err, err
    x = sp.generate(20001, 3)
    # Every column the midpoints, as before.
    col = np.sort(x[:, 1])
    assert np.allclose(col, (2 * np.arange(20001) + 1) / 40002, atol=1e-15, rtol=0)


def test_ctrl_c_during_the_lattice_stops_it_before_its_report():
    # The signal is sent once the run says it is building the generating vector (no
    # timer decides); the shift search checks for it at every coordinate, so the run
    # stops there and never reaches its report's figures.
    import signal
    import subprocess
    import sys

    child = (
        "import stillpoint as sp\n"
        "try:\n"
        "    sp.generate(100000, 20, progress=True)\n"
        "    print('finished', flush=True)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', sp.generate(16, 2).shape, flush=True)\n"
    )
    p = subprocess.Popen(
        [sys.executable, "-c", child],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        seen = []
        for line in p.stderr:
            seen.append(line)
            if line.startswith("stillpoint: generating vector"):
                p.send_signal(signal.SIGINT)
                break
        out, err = p.communicate(timeout=300)
    finally:
        p.kill()
    stages = "".join(seen) + err
    assert out.strip() == "interrupted (16, 2)", (out, stages)
    assert "stillpoint: metrics" not in stages, stages
