"""The classic constructions the optimised sets are compared with (scrambled Sobol',
Halton, lattices, Latin hypercubes, ...)."""

from __future__ import annotations

from typing import Dict, Optional

import numpy as np

from . import _core
from ._validate import _fresh_seed


def baseline(name: str, n: int, d: int, seed: Optional[int] = 0) -> np.ndarray:
    """n points of a classic construction in [0, 1)^d, as ``stillpoint baseline NAME``:
    ``'random'``, ``'halton'``, ``'halton-scrambled'``, ``'sobol'`` (Owen-scrambled),
    ``'hua-wang'``, ``'lattice'``, ``'lhs'``, ``'lhs-maximin'``. :func:`baselines`
    describes each exactly. ``seed`` is ignored by the deterministic ones; None draws a
    fresh seed (see "Seeds" in docs/python.md)."""
    return _core.generate(method=str(name), n=n, d=d, seed=_fresh_seed(seed))


def baselines() -> Dict[str, str]:
    """The baselines' names with the exact description of each construction."""
    return {name: describe for name, _label, describe in _core.baselines()}
