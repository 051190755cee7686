"""What :func:`quad` and :func:`sobol_indices` share, and only what Python does: the
library resolves their settings (defaults, checks, refused combinations, a continuation
from ``start=``) into a state machine (``_core.Cubature``, ``_core.Sensitivity``); here
its batches are mapped to f's inputs, f is called (in process or on an executor), what f
returned is checked and fed back, and progress is reported after each round."""

from __future__ import annotations

import concurrent.futures
import copy
import math
import secrets
import sys
import time
import types
import warnings
from typing import Any, Callable, Dict, Optional, Tuple

import numpy as np

from ._space import _space_items
from ._validate import _executor

# Rows per task when f runs on an executor: large enough that sending the points costs
# little next to an expensive f, small enough that a doubling feeds every worker.
_CHUNK_ROWS = 4096


class _OmittedSeed(int):
    """The seed when none is given: 0, told apart from an explicit ``seed=0`` so that a
    continuation can refuse a seed given with ``start``."""

    def __repr__(self) -> str:
        return "0"


class _FreshSeed(int):
    """A seed drawn for ``seed=None``, shown in refusals as the None the caller typed."""

    def __repr__(self) -> str:
        return "None"


_SEED = _OmittedSeed(0)


class _Result:
    """A state machine's result with its setup (the box or space f's inputs come from);
    picklable as ``{"state", "setup"}``, as every earlier version pickled it."""

    def __init__(self, state: Any, setup: Dict[str, Any]) -> None:
        self._state = state
        self._setup = setup

    def __getstate__(self) -> Dict[str, Any]:
        return {"state": self._state, "setup": self._setup}

    def __setstate__(self, state: Dict[str, Any]) -> None:
        self._state = state["state"]
        self._setup = state["setup"]


_Report = Callable[[Any, Dict[str, Any], float], None]


def _run(
    kind: Any,
    f: Any,
    given: Dict[str, Any],
    start: Any,
    executor: Any,
    progress: Any,
) -> Tuple[Any, Dict[str, Any]]:
    """Runs ``kind``'s computation (``kind`` is the result class, whose ``_core`` names
    its state machine): the state the library resolves from ``given`` (or ``start``
    continued with them), evaluated round after round. Returns the state and setup."""
    started = time.perf_counter()
    if not callable(f):
        raise ValueError(f"invalid f = {f!r}: expected a callable taking an (n, d) array")
    report = _reporter(progress, kind)
    _executor(executor)
    seed = given.pop("seed", _SEED)
    given = {k: v for k, v in given.items() if v is not None}
    if seed is None:
        given["seed"] = _FreshSeed(secrets.randbits(64))
    elif seed is not _SEED:
        given["seed"] = seed
    setup: Dict[str, Any] = {"scalar": True}
    if "space" in given:
        items, frozen = _space_items(given["space"])
        given["space"] = _rule_items(items, frozen)
        setup.update(space=items, frozen=frozen)
    if start is not None:
        if not isinstance(start, kind):
            raise ValueError(
                f"invalid start = {start!r}: expected a {kind.__name__} of an earlier "
                f"{kind._made_by}"
            )
        state, _ = kind._core.resolve(start._state, **given)
        setup = dict(start._setup)
    else:
        state, (names, correlation) = kind._core.resolve(**given)
        setup.update(names=names, correlation=correlation)
        for message in state.warnings:
            warnings.warn(message, stacklevel=3)
    if progress is True and start is None and hasattr(state, "rule"):
        print(f"quad: {state.rule[1]}", file=sys.stderr, flush=True)
    _rounds(f, state, setup, executor, report, started)
    return state, setup


def _rounds(
    f: Any, state: Any, setup: Dict[str, Any], executor: Any, report: Optional[_Report],
    started: float,
) -> None:
    """Asks the state machine for batches until it is met or its budget is spent: each
    batch mapped to f's inputs, evaluated, checked finite and fed back; `report` after
    each round."""
    k = state.outputs or None
    while not state.met:
        u = state.next_points()
        if u is None:
            break
        x = _to_space(u, setup)
        y, flat = _evaluate(f, x, k, executor)
        # A face test's values may be infinite near a corner: the library reads that as f
        # steep at a face (they enter no estimate).
        if getattr(state, "rule", ("",))[0] != "face test":
            _refuse_non_finite(x, y)
        if k is None:
            k = y.shape[1]
            setup["scalar"] = k == 1 and flat
        state.feed(y)
        # A doubling may come as several batches (bounded in memory): report once it is
        # whole.
        if report is not None and not state.in_round:
            report(state, setup, time.perf_counter() - started)


def _reporter(progress: Any, result: Any) -> Optional[_Report]:
    """What to do after each round for ``progress``: nothing (None), the library's
    progress line on standard error, or a call of the user's callable with a copy of the
    result so far (`result`, the result's class, whose function prefixes the line)."""
    if isinstance(progress, (bool, np.bool_)):

        def line(state: Any, setup: Dict[str, Any], t: float) -> None:
            print(state.progress_line(result._made_by, t), file=sys.stderr, flush=True)

        return line if progress else None
    if callable(progress):

        def call(state: Any, setup: Dict[str, Any], *_: float) -> None:
            # Only results with an estimate: a face test's round chooses the rule and
            # estimates nothing.
            if not state.outputs:
                return
            # A copy: the callable may keep it while the run goes on.
            progress(result(copy.deepcopy(state), dict(setup)))

        return call
    raise ValueError(
        f"invalid progress = {progress!r}: expected True, False or a callable taking "
        f"the {result.__name__} after each round"
    )


def _unbounded(law: Any) -> bool:
    """Whether a SciPy frozen law's support is unbounded (None: not a SciPy law)."""
    if law is None:
        return False
    try:
        lo, hi = law.support()
    except Exception:  # a law without support() is taken as bounded
        return False
    return not (math.isfinite(float(lo)) and math.isfinite(float(hi)))


def _rule_items(items: list, frozen: Dict[str, Any]) -> list:
    """The space's texts the library chooses a rule from: SciPy laws are mapped from
    uniform placeholders by their ppf, so one of unbounded support stands as a normal
    law (the rule of such laws), a bounded one as the uniform it is mapped from."""
    return [
        f"{t.split('=', 1)[0]}=normal(0,1)" if _unbounded(frozen.get(t.split("=", 1)[0])) else t
        for t in items
    ]


def _to_space(u: np.ndarray, setup: Dict[str, Any]) -> np.ndarray:
    """The batch as f receives it: the box points as given, or the space's values."""
    from . import _core

    items = setup.get("space")
    if items is None:
        return u
    # The tent-transformed shifts reach 1 only with probability zero; a quantile there
    # would be infinite, so the points stay inside [0, 1).
    u = np.minimum(u, np.nextafter(1.0, 0.0))
    x = _core.space_values(items, np.ascontiguousarray(u), setup.get("correlation"))
    for j, name in enumerate(setup["names"]):
        law = setup["frozen"].get(name)
        if law is not None:
            x[:, j] = law.ppf(x[:, j])
    return x


def _returned(y: Any) -> str:
    """What f returned, for a refusal: its type, and its dtype or a short repr."""
    kind = type(y).__name__
    if isinstance(y, np.ndarray):
        return f"a {kind} of dtype {y.dtype} and shape {y.shape}"
    text = repr(y)
    return f"{kind} {text[:60] + '...' if len(text) > 60 else text}"


def _as_numbers(y: Any, n: int) -> np.ndarray:
    """f's result as a float64 array; refuses None, a generator or iterator, strings,
    ragged rows and other non-numbers, naming f and what it returned."""
    expected = f"expected numbers, shape ({n},) or ({n}, k)"
    if y is None or isinstance(y, (str, bytes, types.GeneratorType, dict, set)) or (
        not isinstance(y, (np.ndarray, list, tuple)) and hasattr(y, "__next__")
    ):
        raise ValueError(f"invalid f: it returned {_returned(y)}; {expected}")
    try:
        a = np.asarray(y)
    except (TypeError, ValueError):
        raise ValueError(
            f"invalid f: it returned {_returned(y)} (ragged rows?); {expected}"
        ) from None
    if a.dtype.kind not in "biuf":
        raise ValueError(f"invalid f: it returned {_returned(y)}; {expected}")
    return a.astype(np.float64, copy=False)


def _values(f: Callable[..., Any], x: np.ndarray, k: Optional[int]) -> Tuple[np.ndarray, bool]:
    """f at the rows of x as an (n, k) array, its shape checked, and whether f gave one
    value per point as a 1-D array (the estimate is then a float, as in qmc_quad)."""
    n = x.shape[0]
    y = _as_numbers(f(x), n)
    flat = y.ndim == 1
    if y.ndim == 1 and y.shape[0] == n:
        y = y[:, None]
    elif not (y.ndim == 2 and y.shape[0] == n and y.shape[1] >= 1):
        raise ValueError(
            f"invalid f: it returned shape {y.shape} for {n} points; expected ({n},) or "
            f"({n}, k)"
        )
    if k is not None and y.shape[1] != k:
        raise ValueError(
            f"invalid f: it returned {y.shape[1]} outputs per point; expected {k}, as at "
            "the first points"
        )
    return y, flat


def _evaluate(
    f: Callable[..., Any],
    x: np.ndarray,
    k: Optional[int],
    executor: Optional[concurrent.futures.Executor],
) -> Tuple[np.ndarray, bool]:
    """f at every row of x, in one call or in chunks on the executor (rows in order, so
    the sums, and the result, are those of one call)."""
    if executor is None or x.shape[0] <= 1:
        return _values(f, x, k)
    workers = max(1, getattr(executor, "_max_workers", 0) or 1)
    rows = max(1, min(_CHUNK_ROWS, -(-x.shape[0] // (4 * workers))))
    futures = []
    parts: list = []
    try:
        for i in range(0, x.shape[0], rows):
            future = executor.submit(f, x[i : i + rows])
            if not callable(getattr(future, "result", None)):
                raise TypeError(
                    f"invalid executor: its submit() returned {_returned(future)}; expected "
                    "a concurrent.futures.Future (an object with result())"
                )
            futures.append(future)
        for i, future in enumerate(futures):
            chunk = x[i * rows : (i + 1) * rows]
            # Every chunk is held to the first one's outputs and shape, as one call is.
            y, flat = _values(lambda _: future.result(), chunk, parts[0][0].shape[1] if parts else k)
            if parts and flat != parts[0][1]:
                raise ValueError(
                    f"invalid f: it returned shape {y.shape if not flat else (y.shape[0],)} for "
                    f"one chunk of points and {'a 1-D' if parts[0][1] else 'a 2-D'} array for "
                    "the first; expected the same shape for every chunk"
                )
            parts.append((y, flat))
    except BaseException:
        for later in futures:
            cancel = getattr(later, "cancel", None)
            if callable(cancel):
                cancel()
        raise
    return np.concatenate([p for p, _ in parts], axis=0), parts[0][1]


def _refuse_non_finite(x: np.ndarray, y: np.ndarray) -> None:
    """A NaN or ±inf from f, refused naming the point (as f saw it) and the output."""
    bad = np.argwhere(~np.isfinite(y))
    if bad.size:
        i, j = (int(v) for v in bad[0])
        output = f" (output {j})" if y.shape[1] > 1 else ""
        raise ValueError(
            f"invalid f: {y[i, j]} at x = {x[i].tolist()}{output}; expected a finite "
            "value at every point"
        )
