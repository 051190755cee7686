"""Before a call into the library runs: its refusal without running
(:func:`_check_generate`, what :class:`~stillpoint.Engine` and
:func:`~stillpoint.generate_many` ask up front), and a warning when the library's cost
model expects a long run."""

from __future__ import annotations

import os
import sys
import warnings
from typing import Any, Dict

from . import _core
from ._space import _design_kwargs
from ._validate import _arrays


def _check_generate(n: Any = None, d: Any = None, **options: Any) -> None:
    """Refuses what :func:`generate` would refuse before its run, without running (a
    space in any form :func:`generate` takes, a dict with SciPy laws among them)."""
    if options.get("space") is not None:
        _core.check_generate(**_design_kwargs(n, options.pop("space"), {"d": d, **options}))
        return
    _core.check_generate(**_arrays({"n": n, "d": d, **options}))


_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))


def _caller_stacklevel() -> int:
    """The ``stacklevel`` of the first frame outside this package, as seen from the
    function calling this one: a warning then points at the user's line, whichever of
    the package's functions led to it."""
    level, frame = 2, sys._getframe(2)
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(
        _PACKAGE_DIR
    ):
        frame, level = frame.f_back, level + 1
    return level


def _warn_if_long(kwargs: Dict[str, Any]) -> None:
    """Before any work starts: a ``RuntimeWarning`` with the library's note when its cost
    model puts the call above its long-run threshold (the command line's rule and words),
    and a ``UserWarning`` for each thing the run will do that the caller may not expect.
    Resolving the request here also refuses a bad argument, with generate's message."""
    note = _core.long_run_note(**kwargs)
    if note is not None:
        warnings.warn(f"stillpoint: {note}", RuntimeWarning, stacklevel=_caller_stacklevel())
    for note in _core.notes(**kwargs):
        warnings.warn(note, UserWarning, stacklevel=_caller_stacklevel())
