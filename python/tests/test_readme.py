"""The Python examples of the README's "Python" section run as written."""

import pathlib
import re

import numpy as np

README = pathlib.Path(__file__).resolve().parents[2] / "README.md"


def python_section() -> str:
    text = README.read_text(encoding="utf-8")
    start = text.index("\n## Python\n")
    end = text.index("\n## ", start + 1)
    return text[start:end]


def test_readme_python_examples_run():
    blocks = re.findall(r"```python\n(.*?)```", python_section(), flags=re.S)
    assert len(blocks) >= 2
    scope = {}
    for block in blocks:
        exec(compile(block, str(README), "exec"), scope)
    assert scope["x"].shape == (50, 3)
    assert scope["g"].shape == (75, 3)
    assert np.array_equal(scope["g"][:50], scope["x"])
    assert scope["h"].shape == (64, 2)
    assert abs(scope["res"].integral - (np.e**2 - 1) ** 3) < 4 * scope["res"].standard_error
    assert scope["res"].standard_error > 0
