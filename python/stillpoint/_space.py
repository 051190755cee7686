"""A design space as the library takes it: ``NAME=TYPE`` texts from any form the
package accepts (texts, a dict of types, label lists, ranges, SciPy frozen laws), the
SciPy laws checked and kept aside to map their variables through ``ppf``, and a design
call's keyword arguments."""

from __future__ import annotations

from typing import Any, Dict, Tuple

import numpy as np

from ._validate import _arrays


def _design_kwargs(n: Any, space: Any, kwargs: Dict[str, Any]) -> Dict[str, Any]:
    """The library's keyword arguments for a design of ``n`` points in ``space``: the
    variables as ``NAME=TYPE`` texts (a SciPy law as the uniform it is mapped from), the
    correlation as an array."""
    items, _frozen_laws = _space_items(space)
    kwargs = dict(kwargs)
    if kwargs.get("correlation") is not None and not isinstance(kwargs["correlation"], str):
        kwargs["correlation"] = _correlation_matrix(kwargs["correlation"])
    return _arrays({"n": n, "space": items, **kwargs})


def _correlation_matrix(value: Any) -> np.ndarray:
    """A correlation given as numbers, as a float array (the library checks its shape
    and entries); refuses what is not numbers, naming ``correlation``."""
    try:
        return np.ascontiguousarray(value, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(
            f"invalid correlation = {value!r}: expected a k × k matrix of numbers ({e})"
        ) from None


def _space_items(space: Any) -> Tuple[list, Dict[str, Any]]:
    """A design space as the library's ``NAME=TYPE`` texts, and the variables whose
    marginal is a SciPy frozen distribution (made uniform, then mapped by its ``ppf``)."""
    if isinstance(space, str):
        space = [space]
    if isinstance(space, dict):
        items = []
        frozen: Dict[str, Any] = {}
        for name, spec in space.items():
            name = str(name)
            if hasattr(spec, "ppf") and callable(spec.ppf):
                frozen[name] = _continuous_law(name, spec)
                items.append(f"{name}=uniform(0,1)")
            elif isinstance(spec, str):
                items.append(f"{name}={spec}")
            elif isinstance(spec, range):
                # Not len(spec): a range wider than 2^63 has no len (OverflowError); the
                # library refuses its size with the accepted one.
                if spec.step != 1 or spec.stop <= spec.start:
                    raise ValueError(
                        f"invalid space {name} = {spec!r}: expected a range with step 1 "
                        "and at least one value"
                    )
                items.append(f"{name}=int({spec.start},{spec.stop - 1})")
            elif isinstance(spec, (list, tuple)) and spec:
                labels = [str(x) for x in spec]
                if any("," in x for x in labels):
                    raise ValueError(
                        f"invalid space {name} = {spec!r}: expected labels without commas"
                    )
                items.append(f"{name}={{{','.join(labels)}}}")
            else:
                raise ValueError(
                    f"invalid space {name} = {spec!r}: expected a type as text "
                    "('normal(0,1)', 'int(1,5)', '{a,b}', 'ordered{lo,hi}', "
                    "'brownian(1,64,pca)'), a list of "
                    "labels, a range, or a scipy.stats frozen distribution"
                )
        return items, frozen
    if isinstance(space, (list, tuple)) and all(isinstance(x, str) for x in space):
        return list(space), {}
    raise ValueError(
        f"invalid space = {space!r}: expected a list of 'NAME=TYPE' texts or a dict "
        "{name: type}"
    )


def _law_name(law: Any) -> str:
    """A frozen SciPy law as its maker wrote it: ``norm(0, -1)``."""
    dist = getattr(law, "dist", None)
    name = getattr(dist, "name", type(law).__name__)
    args = [repr(a) for a in getattr(law, "args", ())]
    args += [f"{k}={v!r}" for k, v in getattr(law, "kwds", {}).items()]
    return f"{name}({', '.join(args)})"


def _continuous_law(name: str, law: Any) -> Any:
    """A frozen SciPy law a continuous variable can follow: refuses a discrete one (its
    quantiles are whole numbers, with ties no stratification can show) and one whose
    quantile function gives NaN or ±inf inside (0, 1) (invalid parameters, an infinite
    scale)."""
    try:
        from scipy import stats as _stats

        discrete = isinstance(getattr(law, "dist", None), _stats.rv_discrete)
    except ImportError:  # pragma: no cover - a law without SciPy is a duck-typed one
        discrete = False
    if discrete:
        raise ValueError(
            f"invalid space {name} = {_law_name(law)}: a discrete law takes whole values with "
            "ties; expected a continuous law, or write the variable as 'int(lo,hi)' or as "
            "a list of levels"
        )
    probe = np.array([2.0**-53, 1e-6, 0.25, 0.5, 0.75, 1 - 1e-6, 1 - 2.0**-53])
    try:
        values = np.asarray(law.ppf(probe), dtype=np.float64)
    except Exception as e:  # a law's own failure, whatever its type
        raise ValueError(f"invalid space {name} = {_law_name(law)}: its ppf fails ({e})") from None
    if values.shape != probe.shape or not np.all(np.isfinite(values)):
        raise ValueError(
            f"invalid space {name} = {_law_name(law)}: its quantile function (ppf) gives "
            f"{values.tolist()} at {probe.tolist()}; expected finite values (valid "
            "parameters, a finite scale)"
        )
    return law
