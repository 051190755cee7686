"""The Python examples of the README and of the guide's Python pages (docs/python.md, then
docs/clusters.md, in one namespace as a reader would run them) run as written."""

import pathlib
import re

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
GUIDE = [ROOT / "docs" / "python.md", ROOT / "docs" / "clusters.md"]

# A block whose first line starts so needs what CI has not (a Slurm cluster).
NOT_RUN = "# Needs a Slurm cluster"


def python_blocks(path: pathlib.Path) -> list:
    return re.findall(r"```python\n(.*?)```", path.read_text(encoding="utf-8"), flags=re.S)


def test_readme_python_example_runs():
    blocks = python_blocks(README)
    assert len(blocks) == 1
    scope = {}
    exec(compile(blocks[0], str(README), "exec"), scope)
    assert scope["x"].shape == (50, 3)
    res = scope["res"]
    assert abs(res.integral - (np.e**2 - 1) ** 3) < 4 * res.standard_error
    assert res.standard_error > 0


def test_guide_python_examples_run():
    blocks = [(path, b) for path in GUIDE for b in python_blocks(path)]
    run = [(path, b) for path, b in blocks if not b.startswith(NOT_RUN)]
    assert len(run) >= 6 and len(blocks) - len(run) == 1
    for path, block in blocks:  # the block not run is still valid Python
        compile(block, str(path), "exec")
    scope = {}
    for path, block in run:
        exec(compile(block, str(path), "exec"), scope)
    assert scope["x"].shape == (50, 3)
    plan = scope["plan"]
    plan = plan if isinstance(plan, dict) else {c: plan[c].to_numpy() for c in plan.columns}
    assert sorted(list(plan["catalyst"]).count(c) for c in ("Pt", "Pd", "Ni")) == [20, 20, 20]
    assert sorted(set(int(k) for k in plan["layers"])) == [1, 2, 3, 4, 5]
    assert scope["d"].figures["slices"][0]["stratified"] == scope["d"].figures["slices"][0]["columns"]
    assert scope["g"].shape == (75, 3)
    assert np.array_equal(scope["g"][:50], scope["x"])
    assert scope["h"].shape == (64, 2)
    design = scope["design"]
    assert design.shape == (64, 3) and (design >= 0).all() and (design <= 1).all()
    assert (design[:, 0] + 2 * design[:, 1] + design[:, 2] <= 1.5).all()
    assert scope["fit"]["fraction_inside"] == 1.0
    # Closer to uniform on the region than the same number of uniform points.
    rng = np.random.default_rng(0)
    u = rng.random((20000, 3))
    u = u[u[:, 0] + 2 * u[:, 1] + u[:, 2] <= 1.5][:64]
    assert scope["fit"]["energy_distance"] < scope["sp"].metrics(u, region=scope["cut"], box=scope["unit"])["energy_distance"]
    assert abs(scope["res"].integral - (np.e**2 - 1) ** 3) < 4 * scope["res"].standard_error
    assert scope["res"].standard_error > 0
    assert [d.shape for d in scope["designs"]] == [(64, 2), (64, 2), (64, 3), (64, 3)]
    assert scope["designs"][3].tobytes() == scope["sp"].generate(64, 3, seed=1).tobytes()
    assert all(a.tobytes() == b.tobytes() for a, b in zip(scope["on_dask"], scope["designs"]))
