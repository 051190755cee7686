"""Shared fixtures: the command-line binary the package is compared with."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """Runs `stillpoint ARGS...` (target/release/stillpoint, or $STILLPOINT_BIN) and
    returns its standard output; a failure fails the test with its standard error."""
    path = pathlib.Path(os.environ.get("STILLPOINT_BIN", ROOT / "target" / "release" / "stillpoint"))
    if not path.is_file():
        pytest.fail(
            f"{path} not found: build it with `cargo build --release` (test.sh does) or "
            "set STILLPOINT_BIN"
        )

    def run(*args):
        done = subprocess.run(
            [str(path), *map(str, args)], capture_output=True, text=True, timeout=600
        )
        if done.returncode != 0:
            pytest.fail(f"stillpoint {' '.join(map(str, args))} failed:\n{done.stderr}")
        return done.stdout

    return run
