"""The figures of a point set: :func:`metrics` (what ``stillpoint eval --json`` prints,
in the cube, a region or a constrained region) and :func:`discrepancy` (one L2
discrepancy)."""

from __future__ import annotations

import warnings
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
    if isinstance(box, str):
        request["box"] = box  # text is the library's to read, as generate's box is
    elif box is not None:
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


# SciPy's method names, spelled as SciPy spells them, mean SciPy's measures with SciPy's
# convention: `qmc.discrepancy` returns the square for 'CD', 'WD' and 'MD' and the root
# for 'L2-star'. Each maps to (the core's kind, whether to square its root).
_SCIPY_METHODS = {
    "CD": ("cd", True),
    "WD": ("wd", True),
    "MD": ("mixture", True),
    "L2-star": ("l2star", False),
}

# Our own names, which no SciPy name can be mistaken for: every value is a root.
_OWN_KINDS = {
    "modified": "md",
    "centered": "cd",
    "centred": "cd",
    "wrap-around": "wd",
    "wraparound": "wd",
    "star": "l2star",
    "l2star": "l2star",
    "l2-star": "l2star",
    "mixture": "mixture",
}

# The short names these meant before SciPy's names took SciPy's meaning: kept working
# (with their old meaning, a root) for one release, with a warning saying what to write.
_RENAMED = {"md": "modified", "cd": "centered", "wd": "wrap-around"}

_ACCEPTED = (
    "SciPy's 'CD', 'WD', 'MD' (mixture) or 'L2-star', with SciPy's convention (the square "
    "for CD, WD and MD, the root for L2-star), or one of ours, each a root: 'modified', "
    "'centered', 'wrap-around', 'star', 'mixture'"
)


def discrepancy(x: Any, kind: Optional[str] = None, *, method: Optional[str] = None) -> float:
    """One discrepancy of points in [0, 1]^d.

    SciPy's names mean what ``scipy.stats.qmc.discrepancy(x, method=...)`` returns, its
    square-or-root convention included (``method=`` is accepted as SciPy spells it):

    - ``'CD'``: centred L2, squared; ``'WD'``: wrap-around L2, squared;
    - ``'MD'``: the *mixture* discrepancy, squared;
    - ``'L2-star'``: star L2 (Warnock), the root.

    Our names, each the root (as :func:`metrics` reports them):

    - ``'modified'`` (the default): modified L2 (Hickernell), the paper's D_MD. SciPy
      has no equivalent;
    - ``'centered'`` (or ``'centred'``), ``'wrap-around'``, ``'star'`` (the paper's
      D_L2), ``'mixture'``.

    The short names ``'md'``, ``'cd'`` and ``'wd'`` (the roots of the modified,
    centred and wrap-around L2) still work, with a ``DeprecationWarning`` saying what to
    write; ``'md'`` is not SciPy's ``'MD'``.

    Exact closed forms, O(n^2 d), on all cores, with the GIL released.
    """
    if kind is not None and method is not None:
        raise TypeError("discrepancy() takes kind or method (SciPy's name for it), not both")
    arg, given = ("method", method) if method is not None else ("kind", kind)
    if given is None:
        given = "modified"
    if not isinstance(given, str):
        raise TypeError(f"invalid {arg} = {given!r}: expected a string, {_ACCEPTED}")
    name = given.strip()
    if name in _SCIPY_METHODS:
        core, square = _SCIPY_METHODS[name]
    else:
        key = name.lower()
        square = False
        if key in _RENAMED:
            warnings.warn(
                f"{arg} = {given!r} is the root of the {_RENAMED[key]} L2 discrepancy; "
                f"write {_RENAMED[key]!r} (SciPy's {name.upper()!r} means "
                f"{'the mixture discrepancy, squared' if key == 'md' else 'its square'})",
                DeprecationWarning,
                stacklevel=2,
            )
            core = key
        elif key in _OWN_KINDS:
            core = _OWN_KINDS[key]
        else:
            raise ValueError(f"invalid {arg} = {given!r}: expected {_ACCEPTED}")
    root = float(_core.discrepancy(_points(x), core))
    return root * root if square else root
