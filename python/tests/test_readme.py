"""The Python examples of the proposed README section run as written."""

import pathlib
import re

import numpy as np

README = pathlib.Path(__file__).resolve().parents[1] / "README-section.md"


def test_readme_python_examples_run():
    text = README.read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 2
    scope = {}
    for block in blocks:
        exec(compile(block, str(README), "exec"), scope)
    assert scope["x"].shape == (50, 3)
    assert abs(scope["res"].integral - (np.e**2 - 1) ** 3) < 4 * scope["res"].standard_error
    assert scope["res"].standard_error > 0
