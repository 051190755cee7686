#!/usr/bin/env bash
# Every test of the project: the Rust workspace, then the Python package (built in the
# release profile into a virtualenv under target/) checked against the command line.
set -euo pipefail
cd "$(dirname "$0")"

cargo test --release --workspace
# The binary the Python tests compare with (already built by the tests when warm).
cargo build --release --bin stillpoint

venv=target/py-venv
if [ ! -x "$venv/bin/python" ]; then
    "${PYTHON:-python3}" -m venv "$venv"
fi
# maturin runs as a command during the build: the venv's bin must come first.
export PATH="$PWD/$venv/bin:$PATH"
python -m pip install -q "maturin>=1.16,<2" numpy scipy pytest
# No build isolation: the venv's maturin builds in place, so cargo reuses target/.
python -m pip install -q --no-build-isolation --no-deps --force-reinstall ./python
pytest -q python/tests
