"""Argument checks and casts shared by the package's functions: an integer within
bounds, any array-like of points as C-ordered float64 of shape (n, d), the keyword
options with their point sets and constraints in the forms the library reads, an
engine's seed. Each refusal is a ``ValueError`` naming the argument as the caller
spelled it."""

from __future__ import annotations

import operator
import secrets
from typing import Any, Dict, Optional

import numpy as np


def _int(name: str, value: Any, lowest: int, highest: Optional[int] = 2**63 - 1) -> int:
    """An integer argument (Python or NumPy integer) within [lowest, highest]."""
    try:
        v = operator.index(value)
    except TypeError:
        raise ValueError(
            f"invalid {name} = {value!r}: expected an integer >= {lowest}"
        ) from None
    if isinstance(value, bool):
        raise ValueError(f"invalid {name} = {value!r}: expected an integer >= {lowest}")
    if v < lowest or (highest is not None and v > highest):
        upper = f" and <= {highest}" if highest is not None else ""
        raise ValueError(f"invalid {name} = {v}: expected an integer >= {lowest}{upper}")
    return v


def _points(x: Any, name: str = "x") -> np.ndarray:
    """`x` as a C-ordered float64 array of shape (n, d)."""
    try:
        a = np.ascontiguousarray(x, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(
            f"invalid {name}: expected an (n, d) array of numbers ({e})"
        ) from None
    if a.ndim != 2:
        raise ValueError(
            f"invalid {name} of shape {a.shape}: expected a 2-D array of shape (n, d)"
        )
    if a.shape[0] == 0 or a.shape[1] == 0:
        raise ValueError(
            f"invalid {name} of shape {a.shape}: expected at least 1 point in at least "
            "1 dimension"
        )
    return a


def _arrays(options: Dict[str, Any]) -> Dict[str, Any]:
    """The keyword options with the point sets among them (``init``, ``extend``) cast like
    any input; everything else goes to the library as given."""
    out = {k: v for k, v in options.items() if v is not None}
    for key in ("init", "extend"):
        value = out.get(key)
        if value is not None and not isinstance(value, str):
            out[key] = _points(value, key)
    if isinstance(out.get("nested"), (range, np.ndarray, list, tuple)):
        # Sizes as the integers they hold (NumPy integers, anything with __index__); a
        # fraction or a bool stays as given, for the library to refuse by name.
        sizes = list(out["nested"])
        if all(not isinstance(k, (bool, np.bool_)) for k in sizes):
            try:
                out["nested"] = [operator.index(k) for k in sizes]
            except TypeError:
                out["nested"] = sizes
    for key in ("constraints", "constraint"):
        if key in out:
            out[key] = _constraint_texts(out[key], key)
    if isinstance(out.get("box"), np.ndarray):
        out["box"] = [float(v) for v in np.ravel(out["box"])]
    if isinstance(out.get("bounds"), np.ndarray):
        out["bounds"] = tuple(np.asarray(out["bounds"], dtype=np.float64).tolist())
    if isinstance(out.get("bounds"), (tuple, list)) and len(out["bounds"]) == 2:
        out["bounds"] = tuple(
            np.asarray(v, dtype=np.float64).tolist() for v in out["bounds"]
        )
    return out


def _constraint_texts(value: Any, key: str) -> Any:
    """Constraints as the library reads them: text as given, and each pair ``(a, b)``
    (meaning a·x <= b) written as the text ``a1*x1 + a2*x2 + ... <= b`` with every number
    in the form that reads back exactly; the library checks them."""
    if isinstance(value, str) or not isinstance(value, (list, tuple)):
        return value

    def text(item: Any) -> Any:
        if isinstance(item, str):
            return item
        try:
            a, b = item
            a = np.asarray(a, dtype=np.float64).ravel()
            b = float(b)
        except (TypeError, ValueError):
            raise ValueError(
                f"invalid {key} = {value!r}: expected constraints as text "
                "('x1 + 2*x2 <= 1') or pairs (a, b) meaning a·x <= b"
            ) from None
        if not (np.all(np.isfinite(a)) and np.isfinite(b)) or a.size == 0:
            raise ValueError(
                f"invalid {key} = {value!r}: expected pairs (a, b) of finite numbers, "
                "a with one coefficient per coordinate"
            )
        terms = " + ".join(f"{float(c)!r}*x{k + 1}" for k, c in enumerate(a))
        return f"{terms} <= {b!r}"

    return [text(item) for item in value]


def _fresh_seed(value: Any) -> Any:
    """A seed as the package reads it (see "Seeds" in docs/python.md): ``None`` draws a
    fresh one from the operating system's entropy, a whole number in [0, 2^64), as
    NumPy's ``default_rng(None)`` does; anything else goes to the library as given, which
    checks it and refuses it naming ``seed``."""
    return secrets.randbits(64) if value is None else value


def _executor(executor: Any) -> None:
    """Refuses what is not an executor instance, naming ``executor``: a class
    (``ThreadPoolExecutor`` rather than ``ThreadPoolExecutor()``, whose ``submit`` is a
    function awaiting its instance) is a TypeError, an object without ``submit`` a
    ValueError."""
    if executor is None:
        return
    if isinstance(executor, type):
        raise TypeError(
            f"invalid executor = {executor!r}: expected an executor instance, e.g. "
            f"{executor.__name__}(), not the class"
        )
    if not callable(getattr(executor, "submit", None)):
        raise ValueError(
            f"invalid executor = {executor!r}: expected a concurrent.futures.Executor "
            "(an object with submit)"
        )


def _engine_seed(name: str, value: Any) -> Any:
    """An engine's seed as NumPy's ``default_rng`` takes it: None, a generator (or bit
    generator, seed sequence) as given, or a whole number >= 0 (any integer type);
    anything else refused naming the argument, before NumPy's TypeError would."""
    if value is None or isinstance(
        value, (np.random.Generator, np.random.BitGenerator, np.random.SeedSequence)
    ):
        return value
    if isinstance(value, (bool, np.bool_)):
        raise ValueError(
            f"invalid {name} = {value!r}: expected None, a whole number >= 0 or a "
            "numpy.random.Generator"
        )
    try:
        v = operator.index(value)
    except TypeError:
        raise ValueError(
            f"invalid {name} = {value!r}: expected None, a whole number >= 0 or a "
            "numpy.random.Generator"
        ) from None
    if v < 0:
        raise ValueError(f"invalid {name} = {v}: expected a whole number >= 0")
    return v
