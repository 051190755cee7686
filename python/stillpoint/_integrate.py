"""Equal-weight (quasi-Monte Carlo) integrals with a point set: the paper's test
integrands F1-F8, or any vectorised function."""

from __future__ import annotations

from typing import Any, Callable, Optional

import numpy as np

from . import _core
from ._validate import _points


def integrate(x: Any, f: Optional[Callable[[np.ndarray], Any]] = None) -> Any:
    """The equal-weight (quasi-Monte Carlo) integral of f over [0, 1]^d with the
    points x.

    With ``f=None``: the paper's eight test integrands F1-F8 (exact integral 0, unit
    variance), as ``stillpoint integrate --json`` reports them: a dict with ``n``,
    ``s``, ``exact`` (0.0) and ``functions``, one dict per integrand with ``function``,
    ``formula``, ``estimate`` and ``error`` (F8 is ``None`` for d = 1).

    With a vectorised callable ``f(x) -> shape (n,)``: the mean of its values, a float.
    """
    pts = _points(x)
    if f is None:
        return _core.integrate(pts)
    if not callable(f):
        raise ValueError(f"invalid f = {f!r}: expected None or a callable f(x) -> (n,)")
    values = np.asarray(f(pts), dtype=np.float64)
    if values.shape != (pts.shape[0],):
        raise ValueError(
            f"invalid f: f(x) returned shape {values.shape}, expected ({pts.shape[0]},) "
            "(one value per point; f must be vectorised over the rows of x)"
        )
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        raise ValueError(
            f"invalid f: f(x) is {values[bad[0]]} at point {bad[0] + 1} (x = "
            f"{pts[bad[0]].tolist()}); expected a finite value at every point"
        )
    return float(np.mean(values))
