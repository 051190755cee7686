#!/usr/bin/env bash
# Every test of the project: the Rust workspace, then the Python package (built in the
# release profile into a virtualenv under target/) checked against the command line.
set -euo pipefail
cd "$(dirname "$0")"

# The virtualenv comes first so that cargo and maturin see one interpreter (PyO3's build
# configuration depends on it). maturin still builds PyO3 as an extension module (no
# libpython link) and the tests link it, so each step rebuilds PyO3 once (~20 s warm).
venv=target/py-venv
if [ ! -x "$venv/bin/python" ]; then
    "${PYTHON:-python3}" -m venv "$venv"
fi
export PATH="$PWD/$venv/bin:$PATH"
export PYO3_PYTHON="$PWD/$venv/bin/python"

# The Rust tests (they also build target/release/stillpoint, which the Python tests
# compare with).
cargo test --release --workspace

python -m pip install -q "maturin>=1.16,<2" numpy scipy pytest dask distributed pandas \
    "mkdocs>=1.6,<2" "mkdocs-material>=9.5,<10" "mkdocstrings[python]>=0.26,<2"
# No build isolation: the venv's maturin builds in place, so cargo reuses target/.
python -m pip install -q --no-build-isolation --no-deps --force-reinstall ./python
test -x target/release/stillpoint || cargo build --release --bin stillpoint
pytest -q python/tests
# The documentation site: every page, the API reference from the docstrings, and every
# link a page makes (in docs/ or outside it, anchors included) resolving.
NO_MKDOCS_2_WARNING=1 python -m mkdocs build --strict --quiet
