"""The figures of a point set: :func:`metrics` (what ``stillpoint eval --json`` prints,
in the cube, a region or a constrained region) and :func:`discrepancy` (one L2
discrepancy)."""

from __future__ import annotations

from typing import Any, Dict, Optional, Sequence

import numpy as np

from . import _core
from ._validate import _constraint_texts, _points


def metrics(
    x: Any,
    exact: bool = False,
    region: Optional[str] = None,
    box: Optional[Sequence[float]] = None,
    shape: Optional[str] = None,
    constraints: Any = None,
    mixture: bool = False,
) -> Dict[str, Any]:
    """Every figure ``stillpoint eval --json`` prints for points in [0, 1]^d, as a dict
    with the same keys and values: ``n``, ``s``, the discrepancies ``star_l2``,
    ``modified_l2``, ``centered_l2``, ``wrap_around_l2`` (roots), ``min_distance``,
    ``min_distance_periodic``, ``energy_uqp`` (with ``energy_uqp_q``, ``energy_uqp_p``),
    ``energy_e_inf``, ``mean_gap`` and ``notes`` (what each ``None`` stands for).
    O(n^2 d) time up to 50 000 points; above, as ``eval``, the discrepancies are
    estimated from random pairs (an ``estimate`` dict gives each one's standard error),
    the minimum distances come from a grid of cells (``None`` where it cannot prove
    them) and ``energy_uqp`` is ``None``. ``exact=True`` (``eval --exact``) computes
    every figure exactly at any size. The GIL is released meanwhile.

    With ``region`` (an expression g, the region g <= 0 inside ``box``) or ``shape``
    (as in :func:`generate`), the figures of ``stillpoint eval --region/--shape --json``
    for points in that region instead: ``energy_distance`` (D^2 to the uniform
    distribution on it, the square form) with ``energy_distance_se`` (its standard
    error from an independent uniform sample of ``energy_distance_reference_points``
    points), ``min_distance`` and ``fraction_inside``. ``constraints`` (with ``box``) and
    ``mixture`` measure points made with those options of :func:`generate` the same way
    (``stillpoint eval --constraint/--mixture``; a mixture in its first d − 1
    components).
    """
    # The keywords make `eval`'s request, which the library resolves and refuses (each
    # refusal names the keyword); only values Python alone can read are converted here.
    request: Dict[str, Any] = {"exact": exact, "mixture": mixture}
    if region is not None:
        request["region"] = region
    if shape is not None:
        request["shape"] = shape
    if box is not None:
        try:
            request["box"] = [float(v) for v in np.ravel(np.asarray(box, dtype=np.float64))]
        except (TypeError, ValueError):
            raise ValueError(
                f"invalid box = {box!r}: expected LO1,HI1,LO2,HI2,... (numbers)"
            ) from None
    if constraints is not None:
        texts = _constraint_texts(constraints, "constraints")
        if not isinstance(texts, (str, list, tuple)):
            raise ValueError(
                f"invalid constraints = {constraints!r}: expected a linear constraint as "
                "text, such as \"x1 + 2*x2 <= 1\", a pair (a, b) meaning a·x <= b, or a "
                "list of them"
            )
        request["constraints"] = [texts] if isinstance(texts, str) else list(texts)
    return _core.metrics(_points(x), **request)


def discrepancy(x: Any, kind: str = "md") -> float:
    """One L2 discrepancy of points in [0, 1]^d, always the root (never the square).

    ``kind``:

    - ``'l2star'``: star L2 (Warnock), the paper's D_L2. Equals
      ``scipy.stats.qmc.discrepancy(x, method='L2-star')`` (SciPy returns the root).
    - ``'md'``: modified L2 (Hickernell), the paper's D_MD. **Not** SciPy's
      ``method='MD'``, which is the *mixture* discrepancy; SciPy has no equivalent.
    - ``'cd'``: centred L2. Its square equals SciPy's ``method='CD'`` (SciPy returns
      the square).
    - ``'wd'``: wrap-around L2. Its square equals SciPy's ``method='WD'`` (a square
      too).

    Exact closed forms, O(n^2 d), on all cores, with the GIL released.
    """
    return float(_core.discrepancy(_points(x), str(kind)))
