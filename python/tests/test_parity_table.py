"""One request for both front ends: every combination below runs through the command
line and through Python and gives the same bytes, or is refused by both with the same
message (the parameter spelled each front end's way: ``--log-every`` / ``log_every``,
``-s`` / ``d``). The rules live once, in the library; this table checks that neither
front end adds or drops one."""

import os
import pathlib
import re
import subprocess

import numpy as np
import pytest

import stillpoint as sp

ROOT = pathlib.Path(__file__).resolve().parents[2]
BIN = pathlib.Path(os.environ.get("STILLPOINT_BIN", ROOT / "target" / "release" / "stillpoint"))

# Flags as Python spells them.
FLAG = {"-n": "n", "-s": "d", "--box": "box", "--log-every": "log_every"}

# (command-line flags, Python keyword arguments); the same request each.
SAME_POINTS = [
    (["-n", "30", "-s", "2"], {"n": 30, "d": 2}),
    (["-n", "17", "-s", "3", "--seed", "5"], {"n": 17, "d": 3, "seed": 5}),
    (["-n", "24", "-s", "2", "--target", "md"], {"n": 24, "d": 2, "target": "md"}),
    (["-n", "24", "-s", "2", "--target", "l2star"], {"n": 24, "d": 2, "target": "l2star"}),
    (["-n", "24", "-s", "3", "--randomize", "cells", "--seed", "2"],
     {"n": 24, "d": 3, "randomize": "cells", "seed": 2}),
    (["-n", "24", "-s", "3", "--randomize", "shift", "--seed", "2"],
     {"n": 24, "d": 3, "randomize": "shift", "seed": 2}),
    (["-n", "24", "-s", "3", "--randomize", "--seed", "2"],
     {"n": 24, "d": 3, "randomize": True, "seed": 2}),
    (["-n", "30", "-s", "4", "--randomize", "tent", "--seed", "5"],
     {"n": 30, "d": 4, "randomize": "tent", "seed": 5}),
    (["-n", "20", "-s", "2", "--goal", "space-filling"], {"n": 20, "d": 2, "goal": "space-filling"}),
    # steps with the space-filling goal: its DEM stage's budget, in both.
    (["-n", "20", "-s", "2", "--goal", "space-filling", "--steps", "50"],
     {"n": 20, "d": 2, "goal": "space-filling", "steps": 50}),
    (["-n", "20", "-s", "2", "--method", "paper", "--steps", "60"],
     {"n": 20, "d": 2, "method": "paper", "steps": 60}),
    (["-n", "20", "-s", "2", "--steps", "60", "--kappa", "200"], {"n": 20, "d": 2, "steps": 60, "kappa": 200}),
    (["-n", "20", "-s", "2", "--steps", "60", "--restart", "off"], {"n": 20, "d": 2, "steps": 60, "restart": "off"}),
    (["-n", "20", "-s", "2", "--steps", "60", "--q", "inf"], {"n": 20, "d": 2, "steps": 60, "q": "inf"}),
    (["-n", "20", "-s", "2", "--steps", "60", "--p", "0.5"], {"n": 20, "d": 2, "steps": 60, "p": 0.5}),
    (["-n", "20", "-s", "2", "--steps", "60", "--shifts", "0"], {"n": 20, "d": 2, "steps": 60, "shifts": 0}),
    (["-n", "20", "-s", "2", "--steps", "30", "--polish", "md"], {"n": 20, "d": 2, "steps": 30, "polish": "md"}),
    (["-n", "20", "-s", "2", "--steps", "30", "--energy", "md", "--integrator", "lbfgs"],
     {"n": 20, "d": 2, "steps": 30, "energy": "md", "integrator": "lbfgs"}),
    (["-n", "20", "-s", "2", "--steps", "40", "--init", "random", "--seed", "3"],
     {"n": 20, "d": 2, "steps": 40, "init": "random", "seed": 3}),
    (["-n", "20", "-s", "2", "--steps", "40", "--precision", "full"],
     {"n": 20, "d": 2, "steps": 40, "precision": "full"}),
    (["-n", "20", "-s", "2", "--method", "paper", "--steps", "40", "--randomize", "cells"],
     {"n": 20, "d": 2, "method": "paper", "steps": 40, "randomize": "cells"}),
    # In a region: restart applies in both (it used to be ignored by the command line).
    (["--shape", "ball:1", "-s", "2", "-n", "20", "--steps", "200", "--restart", "off"],
     {"shape": "ball:1", "d": 2, "n": 20, "steps": 200, "restart": "off"}),
    (["--shape", "ball:1", "-s", "2", "-n", "20", "--steps", "200"],
     {"shape": "ball:1", "d": 2, "n": 20, "steps": 200}),
    (["--shape", "ball:1", "-s", "2", "-n", "20", "--steps", "200", "--kappa", "300"],
     {"shape": "ball:1", "d": 2, "n": 20, "steps": 200, "kappa": 300}),
    (["--shape", "ball:1@0,0", "-n", "20", "--steps", "100", "--energy", "e-p-g", "--p", "6"],
     {"shape": "ball:1@0,0", "n": 20, "steps": 100, "energy": "e-p-g", "p": 6}),
    (["--region", "x^2 + y^2 - 1", "--box", "-1,1,-1,1", "-n", "15", "--steps", "100"],
     {"region": "x^2 + y^2 - 1", "box": [-1, 1, -1, 1], "n": 15, "steps": 100}),
    # The integration goal in a region: the energy distance to uniform on it.
    (["--shape", "ball:1", "-s", "2", "-n", "15", "--goal", "integration", "--seed", "3"],
     {"shape": "ball:1", "d": 2, "n": 15, "goal": "integration", "seed": 3}),
    (["--region", "x1 + 2*x2 - 1", "--box", "0,1,0,1", "-n", "12", "--goal", "integration"],
     {"region": "x1 + 2*x2 - 1", "box": [0, 1, 0, 1], "n": 12, "goal": "integration"}),
    (["--shape", "ball:1", "-s", "2", "-n", "15", "--goal", "space-filling", "--steps", "100"],
     {"shape": "ball:1", "d": 2, "n": 15, "goal": "space-filling", "steps": 100}),
    (["--nested", "8,16,24", "-s", "2"], {"nested": [8, 16, 24], "d": 2}),
    (["--nested", "8,16", "-s", "2", "-n", "16"], {"nested": "8,16", "d": 2, "n": 16}),
    (["-n", "16", "-s", "2", "--bounds", "-1,1,0,10"], {"n": 16, "d": 2, "bounds": ([-1, 0], [1, 10])}),
    (["-n", "16", "-s", "2", "--method", "sobol", "--seed", "4"], {"n": 16, "d": 2, "method": "sobol", "seed": 4}),
    (["-n", "24", "-s", "2", "--exact"], {"n": 24, "d": 2, "exact": True}),
]

# Refused by both, with the same message.
REFUSED = [
    (["-n", "16", "-s", "2", "--method", "sobol", "--exact"], {"n": 16, "d": 2, "method": "sobol", "exact": True}),
    (["-n", "0", "-s", "2"], {"n": 0, "d": 2}),
    (["-n", "5", "-s", "0"], {"n": 5, "d": 0}),
    (["-n", "5"], {"n": 5}),
    (["-n", "5", "-s", "2", "--goal", "fast"], {"n": 5, "d": 2, "goal": "fast"}),
    (["-n", "5", "-s", "2", "--target", "md", "--method", "paper"],
     {"n": 5, "d": 2, "target": "md", "method": "paper"}),
    (["-n", "5", "-s", "2", "--goal", "integration", "--kappa", "200"],
     {"n": 5, "d": 2, "goal": "integration", "kappa": 200}),
    (["-n", "5", "-s", "2", "--goal", "integration", "--steps", "20"],
     {"n": 5, "d": 2, "goal": "integration", "steps": 20}),
    (["-n", "5", "-s", "2", "--kappa", "0.5"], {"n": 5, "d": 2, "kappa": 0.5}),
    (["-n", "5", "-s", "2", "--restart", "-1"], {"n": 5, "d": 2, "restart": -1}),
    (["-n", "5", "-s", "2", "--tolerance", "-1"], {"n": 5, "d": 2, "tolerance": -1}),
    (["-n", "5", "-s", "2", "--energy", "e-inf-g"], {"n": 5, "d": 2, "energy": "e-inf-g"}),
    (["-n", "5", "-s", "2", "--integrator", "newton"], {"n": 5, "d": 2, "integrator": "newton"}),
    (["-n", "5", "-s", "2", "--randomize", "twist"], {"n": 5, "d": 2, "randomize": "twist"}),
    (["-n", "5", "-s", "2", "--randomize", "--target", "md"], {"n": 5, "d": 2, "randomize": True, "target": "md"}),
    (["-n", "5", "-s", "2", "--randomize", "--method", "paper"], {"n": 5, "d": 2, "randomize": True, "method": "paper"}),
    (["-n", "5", "-s", "2", "--box", "0,1,0,1"], {"n": 5, "d": 2, "box": [0, 1, 0, 1]}),
    (["-n", "5", "-s", "2", "--bounds", "0,1"], {"n": 5, "d": 2, "bounds": "0,1"}),
    (["-n", "5", "-s", "2", "--bounds", "-1e308,1e308,0,1"], {"n": 5, "d": 2, "bounds": ([-1e308, 0], [1e308, 1])}),
    (["-n", "5", "-s", "2", "--bounds", "0,1e-320,0,1"], {"n": 5, "d": 2, "bounds": ([0, 0], [1e-320, 1])}),
    # In a region: options with no effect there are refused, never ignored.
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--polish", "md"], {"shape": "ball:1", "d": 2, "n": 5, "polish": "md"}),
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--shifts", "4"], {"shape": "ball:1", "d": 2, "n": 5, "shifts": 4}),
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--q", "2"], {"shape": "ball:1", "d": 2, "n": 5, "q": 2}),
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--p", "3"], {"shape": "ball:1", "d": 2, "n": 5, "p": 3}),
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--log-every", "5"], {"shape": "ball:1", "d": 2, "n": 5, "log_every": 5}),
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--precision", "full"], {"shape": "ball:1", "d": 2, "n": 5, "precision": "full"}),
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--randomize", "cells"], {"shape": "ball:1", "d": 2, "n": 5, "randomize": "cells"}),
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--bounds", "0,1,0,1"], {"shape": "ball:1", "d": 2, "n": 5, "bounds": "0,1,0,1"}),
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--goal", "integration", "--target", "md"], {"shape": "ball:1", "d": 2, "n": 5, "goal": "integration", "target": "md"}),
    (["--shape", "ball:1", "-s", "2", "-n", "5", "--goal", "integration", "--randomize", "cells"], {"shape": "ball:1", "d": 2, "n": 5, "goal": "integration", "randomize": "cells"}),
    (["--shape", "ball:1", "-s", "3", "-n", "5", "--nested", "2,5"], {"shape": "ball:1", "d": 3, "n": 5, "nested": "2,5"}),
    (["--shape", "ball:1@0,0", "-s", "3", "-n", "5"], {"shape": "ball:1@0,0", "d": 3, "n": 5}),
    (["--shape", "cube:1", "-s", "2", "-n", "5"], {"shape": "cube:1", "d": 2, "n": 5}),
    (["--shape", "ball:1", "-n", "5"], {"shape": "ball:1", "n": 5}),
    (["--region", "x^2 + y^2 - 1", "-n", "5"], {"region": "x^2 + y^2 - 1", "n": 5}),
    (["--region", "x^2 + y^2 + 1", "--box", "-1,1,-1,1", "-n", "5"], {"region": "x^2 + y^2 + 1", "box": [-1, 1, -1, 1], "n": 5}),
    (["--region", "x^2 + y^2 - 1", "--box", "1,-1,-1,1", "-n", "5"], {"region": "x^2 + y^2 - 1", "box": [1, -1, -1, 1], "n": 5}),
    (["--nested", "16,8", "-s", "2"], {"nested": [16, 8], "d": 2}),
    (["--nested", "0,8", "-s", "2"], {"nested": [0, 8], "d": 2}),
    (["--nested", "8,16", "-s", "2", "-n", "20"], {"nested": [8, 16], "d": 2, "n": 20}),
    (["--nested", "8,16", "-s", "2", "--method", "paper"], {"nested": [8, 16], "d": 2, "method": "paper"}),
    (["--nested", "8,16", "-s", "2", "--randomize", "cells"], {"nested": [8, 16], "d": 2, "randomize": "cells"}),
    (["-n", "5", "-s", "2", "--method", "sobol", "--steps", "9"], {"n": 5, "d": 2, "method": "sobol", "steps": 9}),
    (["-n", "5", "-s", "2", "--method", "quasi"], {"n": 5, "d": 2, "method": "quasi"}),
    (["-n", "5", "-s", "2", "--goal", "space-filling", "--target", "md"], {"n": 5, "d": 2, "goal": "space-filling", "target": "md"}),
    (["-n", "5", "-s", "2", "--method", "paper", "--goal", "integration"], {"n": 5, "d": 2, "method": "paper", "goal": "integration"}),
]


def _cli(args, tmp_path):
    out = tmp_path / "cli.npy"
    done = subprocess.run(
        [str(BIN), "generate", *args, "-o", str(out), "-q"],
        capture_output=True, text=True, timeout=300,
    )
    return done, out


def _python_spelling(message):
    """A command-line refusal as Python would word it: flags as keyword names."""
    message = message.strip().removeprefix("error: ")
    message = re.sub(r"(?<![\w-])(-n|-s|--box|--log-every)\b",
                     lambda m: FLAG[m.group(1)], message)
    return re.sub(r"--([a-z]+)", r"\1", message)


@pytest.mark.parametrize("flags,kwargs", SAME_POINTS, ids=[" ".join(f) for f, _ in SAME_POINTS])
def test_same_request_same_points(flags, kwargs, tmp_path):
    done, out = _cli(flags, tmp_path)
    assert done.returncode == 0, done.stderr
    x = np.load(out)
    y = sp.generate(**kwargs) if "n" in kwargs else sp.generate(None, **kwargs)
    assert x.shape == y.shape
    assert x.tobytes() == y.tobytes()


@pytest.mark.parametrize("flags,kwargs", REFUSED, ids=[" ".join(f) for f, _ in REFUSED])
def test_same_request_same_refusal(flags, kwargs, tmp_path):
    done, out = _cli(flags, tmp_path)
    assert done.returncode == 1, done.stdout
    assert "panicked" not in done.stderr
    assert not out.exists()
    lines = [l for l in done.stderr.splitlines() if l.startswith("error:")]
    assert len(lines) == 1, done.stderr
    with pytest.raises(ValueError) as refused:
        if "n" in kwargs:
            sp.generate(**kwargs)
        else:
            sp.generate(None, **kwargs)
    assert str(refused.value) == _python_spelling(lines[0])


def test_the_table_is_large_enough():
    assert len(SAME_POINTS) + len(REFUSED) >= 40
