"""stillpoint: evenly spread point sets in [0, 1)^d as NumPy arrays.

The points are the static solution of a damped many-body problem (the dynamical
evolutionary model): :func:`generate` gives exactly what ``stillpoint generate -n N -s D``
writes, :func:`metrics` what ``stillpoint eval --json`` prints, :func:`baseline` the
classic sequences (scrambled Sobol', Halton, lattices, Latin hypercubes, ...),
:func:`integrate` the paper's test integrals, :func:`design` a design in a mixed space
(distributions, integer and categorical factors; ``generate(n, space=...)`` as a table),
and :class:`Engine` a SciPy
``scipy.stats.qmc.QMCEngine`` that draws randomised copies of an optimised set
(usable with ``scipy.integrate.qmc_quad``).

Every function accepts any array-like of points (lists, float32, Fortran order: they are
cast to C-ordered float64) and returns float64 arrays of shape (n, d). Every refusal is a
``ValueError`` whose message names the argument; the long computations release the GIL.
"""

from __future__ import annotations

import copy
import json
import operator
import os
import sys
import threading
import warnings
from typing import Any, Callable, Dict, Optional, Sequence, Tuple

import numpy as np

from . import _core

__version__: str = _core.__version__

__all__ = [
    "Design",
    "Engine",
    "baseline",
    "baselines",
    "design",
    "design_figures",
    "discrepancy",
    "extend",
    "generate",
    "generate_many",
    "integrate",
    "metrics",
    "nested",
]

# Arguments of `generate` that an Engine sets itself or cannot take (it draws in the
# unit cube).
_ENGINE_REFUSES = ("n", "d", "region", "box", "shape", "bounds")


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


def _check_generate(n: Any = None, d: Any = None, **options: Any) -> None:
    """Refuses what :func:`generate` would refuse before its run, without running (a
    space in any form :func:`generate` takes, a dict with SciPy laws among them)."""
    if options.get("space") is not None:
        _core.check_generate(**_design_kwargs(n, options.pop("space"), {"d": d, **options}))
        return
    _core.check_generate(**_arrays({"n": n, "d": d, **options}))


def _design_kwargs(n: Any, space: Any, kwargs: Dict[str, Any]) -> Dict[str, Any]:
    """The library's keyword arguments for a design of ``n`` points in ``space``: the
    variables as ``NAME=TYPE`` texts (a SciPy law as the uniform it is mapped from), the
    correlation as an array."""
    items, _frozen_laws = _space_items(space)
    kwargs = dict(kwargs)
    if kwargs.get("correlation") is not None and not isinstance(kwargs["correlation"], str):
        try:
            kwargs["correlation"] = np.ascontiguousarray(kwargs["correlation"], dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise ValueError(
                f"invalid correlation = {kwargs['correlation']!r}: expected a k × k matrix "
                f"of numbers ({e})"
            ) from None
    return _arrays({"n": n, "space": items, **kwargs})


# A call estimated to take longer than this warns before it starts.
_LONG_CALL_SECONDS = 30.0

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
    """A ``RuntimeWarning`` with the library's estimate of the call's seconds when it is
    above 30 seconds, before any work starts (the estimate also refuses
    a bad argument, with generate's message)."""
    seconds = _core.estimate(**kwargs)
    if seconds > _LONG_CALL_SECONDS:
        warnings.warn(
            f"this stillpoint run is estimated to take about {seconds:.0f} seconds on this "
            "machine; Ctrl-C stops it",
            RuntimeWarning,
            stacklevel=_caller_stacklevel(),
        )


def generate(
    n: int,
    d: Optional[int] = None,
    *,
    seed: int = 0,
    method: Optional[str] = None,
    energy: Optional[str] = None,
    integrator: Optional[str] = None,
    steps: Optional[int] = None,
    region: Optional[str] = None,
    box: Any = None,
    shape: Optional[str] = None,
    bounds: Any = None,
    progress: bool = False,
    **later: Any,
) -> np.ndarray:
    """n evenly spread points in [0, 1)^d (or in a region), an array of shape (n, d).

    With the defaults this is exactly ``stillpoint generate -n N -s D`` (the same
    float64 values as its ``.npy`` output): the integration goal, a set stratified in
    every coordinate (one point in each [k/n, (k+1)/n)) with its discrepancy as low as
    the descent reaches. ``method='paper'`` (or any of the paper's options: ``energy``,
    ``integrator``, ``steps``, ``q``, ``p``, ``init``, ...) runs the paper's pipeline
    instead: U_{q,p} with (q, p) from eq. 48, a plain Halton start, 1000 steps of the
    damped dynamics, then the best of 64 periodic shifts.

    Parameters
    ----------
    n, d : int
        Number of points (>= 1) and dimension (>= 1; may be omitted when ``region`` /
        ``shape`` gives it).
    seed : int
        Seed of every random choice (the random start; a baseline's scramble).
    method : str, optional
        ``'paper'`` (or ``'dem'``: the paper's pipeline above) or a baseline's name
        (``'sobol'``, ``'halton-scrambled'``, ``'lhs'``, ... see :func:`baselines`),
        which then takes only n, d and seed.
    energy : str, optional
        In the cube ``'uqp'`` (default), ``'e-inf'``, ``'l2star'``, ``'md'``, ``'cd'``,
        ``'periodic'``; in a region ``'e-inf-g'`` (default), ``'e-inf'``, ``'e-p-g'``.
    integrator : str, optional
        ``'dem'`` (default) or ``'lbfgs'``.
    steps : int, optional
        Step budget (default 1000 in the cube, 10 000 in a region).
    region, box : optional
        A region {x : g(x) <= 0} with g an expression in x1..xd (or x, y, z), e.g.
        ``"x^2 + y^2 - 1"``, and its bounding box ``[lo1, hi1, lo2, hi2, ...]`` (or pairs,
        or the command line's text ``"-1,1,-1,1"``).
    shape : str, optional
        A built-in region as the command line writes it: ``'ball:R[@C1,C2,..]'``,
        ``'ellipsoid:A1,A2,..[@C..]'``, ``'box:LO1,HI1,..'``, ``'simplex'``,
        ``'polytope:FILE'`` (with ``box``).
    bounds : (lo, hi), optional
        Scale the points from [0, 1)^d to [lo, hi) as ``scipy.stats.qmc.scale`` does.
    progress : bool
        Print the stages and steps of the run on standard error.
    **later
        ``goal`` (``'integration'``, the cube's default, or ``'space-filling'``, a
        region's), ``target`` (``'blend'``, the default below d = 8,
        ``'blend-smooth'``, ``'curved'``, the default from d = 8, ``'md'``, ``'l2star'``,
        ``'cd'``,
        ``'periodic'``, ``'smooth'``), ``constraints`` (linear constraints with ``box``,
        which gives d: a list of texts such as ``'x1 + 2*x2 <= 1'`` or of pairs ``(a, b)``
        meaning a·x <= b; the region {A x <= b} within the box), ``mixture`` (``True``: d
        components, each >= 0, summing to 1; ``box`` bounds each one and ``constraints``
        add cuts; every row sums to 1 within 1e-12), ``randomize`` (``True`` or ``'tent'``, recommended for error
        bars: the lattice made for a uniform shift and the tent transform, randomised so;
        ``'cells'`` or ``'shift'`` randomise the optimised set), ``extend`` (see :func:`extend`), ``nested`` (see :func:`nested`);
        and the paper's options, passed through to the library: ``q``, ``p``,
        ``precision``, ``init`` (``'halton'``, ``'random'`` or an (n, d) array),
        ``kappa``, ``restart``, ``tolerance``, ``polish``, ``shifts``, ``log_every``;
        ``exact`` (``generate --exact``: the run's report computes its O(n^2) metrics
        exactly at every size; the points are the same, and :func:`metrics` takes
        ``exact`` for the figures of any array). An unknown name is a ``ValueError`` listing the accepted ones.

    Raises
    ------
    ValueError
        For any argument the library refuses, with its message (naming the argument).

    Warns
    -----
    RuntimeWarning
        Before a run the library's cost model estimates at more than 30 seconds
        (on this machine's cores), with the estimate; ``warnings.filterwarnings``
        silences it or, with ``'error'``, turns it into an exception before any work.
    """
    if later.get("space") is not None:
        # Every option goes to the library, which refuses those a space does not take.
        for name, value in (("method", method), ("energy", energy), ("integrator", integrator),
                            ("steps", steps), ("region", region), ("box", box), ("shape", shape),
                            ("bounds", bounds)):
            if value is not None:
                later[name] = value
        return design(n, later.pop("space"), d=d, seed=seed, **later).table()
    kwargs = _arrays(
        {
            "n": n,
            "d": d,
            "seed": seed,
            "method": method,
            "energy": energy,
            "integrator": integrator,
            "steps": steps,
            "region": region,
            "box": box,
            "shape": shape,
            "bounds": bounds,
            **later,
        }
    )
    _warn_if_long(kwargs)
    return _core.generate(**kwargs, progress=bool(progress))


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
                    "('normal(0,1)', 'int(1,5)', '{a,b}', 'ordered{lo,hi}'), a list of "
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


class Design:
    """A design in a mixed space: ``columns`` (name -> values: floats, integers or
    labels), ``unit`` (the design on the unit scale, an (n, d) array: continuous
    values before their marginal's quantile function, a level at the centre of its
    share of [0, 1)), ``figures`` (level and pair balance, slice stratification,
    centred L2 of the continuous part overall and per slice, minimum distance; all on
    the unit scale) and ``space`` (the variables as ``NAME=TYPE``)."""

    def __init__(self, raw: Dict[str, Any], frozen: Dict[str, Any]) -> None:
        self.space: list = raw["space"]
        # The correlation as the command line writes it ("1.0,0.7;0.7,1.0"), or None:
        # with the space, all that design_figures needs to reproduce the figures.
        self.correlation: Optional[str] = raw.get("correlation")
        self.names: list = raw["names"]
        n = len(raw["columns"][0]) if raw["columns"] else 0
        self.unit: np.ndarray = np.asarray(raw["unit"], dtype=np.float64).reshape(n, len(self.names))
        self.figures: Dict[str, Any] = raw["figures"]
        self.columns: Dict[str, np.ndarray] = {}
        for j, (name, values) in enumerate(zip(self.names, raw["columns"])):
            if name in frozen:
                # The library made this coordinate uniform; its distribution maps it.
                u = np.clip(self.unit[:, j], 2.0**-53, 1.0 - 2.0**-53)
                x = np.asarray(frozen[name].ppf(u), dtype=np.float64)
                self.columns[name] = x
                # The figures are of u: they hold for the written x only where the law
                # kept the points apart (a finite value for each, no ties made).
                if x.shape != u.shape or not np.all(np.isfinite(x)):
                    raise ValueError(
                        f"invalid space {name} = {_law_name(frozen[name])}: its ppf gives a "
                        "value that is not finite at a point of the design; expected a law "
                        "with finite quantiles"
                    )
                if np.unique(x).size < np.unique(u).size:
                    raise ValueError(
                        f"invalid space {name} = {_law_name(frozen[name])}: its quantiles at "
                        f"the design's {len(u)} points take only {np.unique(x).size} distinct "
                        "values in floating point; expected a law whose range holds n "
                        "distinct values"
                    )
            elif values and isinstance(values[0], str):
                self.columns[name] = np.asarray(values, dtype=object)
            elif values and isinstance(values[0], int):
                self.columns[name] = np.asarray(values, dtype=np.int64)
            else:
                self.columns[name] = np.asarray(values, dtype=np.float64)

    def __len__(self) -> int:
        return self.unit.shape[0]

    def __repr__(self) -> str:
        return f"Design({len(self)} points: {' '.join(self.space)})"

    def to_frame(self) -> Any:
        """The columns as a pandas DataFrame (needs pandas)."""
        import pandas as pd  # optional: only this method needs it

        return pd.DataFrame(self.columns, columns=self.names)

    def table(self) -> Any:
        """A pandas DataFrame when pandas is installed, else the dict of columns."""
        try:
            return self.to_frame()
        except ImportError:
            return dict(self.columns)


def design(n: int, space: Any, **kwargs: Any) -> Design:
    """A design of ``n`` points in a mixed space (``stillpoint generate --var ...``).

    ``space`` is a list of ``'NAME=TYPE'`` texts as ``--var`` takes them
    (``'x=uniform(0,1)'``, ``'y=normal(0,1)'``, ``'z=truncnormal(mu,sigma,lo,hi)'``,
    ``'w=lognormal(mu,sigma)'``, ``'b=beta(a,b)'``, ``'t=triangular(lo,mode,hi)'``,
    ``'k=int(1,5)'``, ``'c={a,b,c}'``, ``'q=ordered{low,mid,high}'``) or a dict from
    names to such types, lists of labels, ranges, or ``scipy.stats`` frozen
    distributions (mapped through their ``ppf``). ``correlation`` (a k × k matrix over
    the continuous variables, in their order) correlates them by a Gaussian copula; the
    figures are then those of the independent scores. The set is made in the unit cube with
    every other option of :func:`generate` (``goal``, ``seed``, ...), then every level
    count is made ⌊n/L⌋ or ⌈n/L⌉, pairs of unordered factors balanced, and the
    continuous columns stratified within every level of every unordered factor.
    """
    _items, frozen = _space_items(space)
    kwargs = _design_kwargs(n, space, kwargs)
    _warn_if_long(kwargs)
    return Design(json.loads(_core.design_json(**kwargs)), frozen)


def design_figures(table: Any, space: Any, correlation: Any = None) -> Dict[str, Any]:
    """The figures of any design (a DataFrame, or a dict of columns) in ``space`` (and
    the ``correlation`` it was made with, if any), as :attr:`Design.figures` gives them:
    the same code measures ours and anyone's."""
    items, frozen = _space_items(space)
    if frozen:
        raise ValueError("invalid space: design_figures takes texts, not frozen distributions")
    try:
        pairs = table.items() if hasattr(table, "items") else table
        columns = {str(k): list(v) for k, v in pairs}
    except (TypeError, ValueError):
        raise ValueError(
            f"invalid table = {table!r}: expected a DataFrame or a dict of columns"
        ) from None
    names = [it.split("=", 1)[0].strip() for it in items]
    missing = [m for m in names if m not in columns]
    if missing:
        raise ValueError(f"invalid table: expected a column for every variable, missing {missing}")
    lengths = {m: len(columns[m]) for m in names}
    if len(set(lengths.values())) > 1:
        raise ValueError(
            f"invalid table: expected columns of equal length (one value per point), got "
            f"{lengths}"
        )

    def cell(v: Any) -> str:
        # Each value as the library reads a cell: a float in the form that reads back to
        # the same bits, an integer's digits, a label as it is.
        if isinstance(v, (bool, np.bool_)):
            return str(v)
        if isinstance(v, (float, np.floating)):
            return repr(float(v))
        if isinstance(v, (int, np.integer)):
            return str(int(v))
        return str(v)

    cells = [(m, [cell(v) for v in columns[m]]) for m in names]
    matrix = None
    if isinstance(correlation, str):
        # The rows as Design.correlation and the command line write them.
        correlation = [[float(v) for v in row.split(",")] for row in correlation.split(";")]
    if correlation is not None:
        try:
            matrix = [float(v) for v in np.ravel(np.asarray(correlation, dtype=np.float64))]
        except (TypeError, ValueError):
            raise ValueError(
                f"invalid correlation = {correlation!r}: expected a k × k matrix of numbers"
            ) from None
    return json.loads(_core.design_figures_json(items, cells, matrix))["figures"]


def extend(points: Any, m: int, **kwargs: Any) -> np.ndarray:
    """``points`` followed by ``m`` new points, an array of shape (n + m, d): the old
    points first and unchanged (bit for bit), the new ones settled among them, as
    ``stillpoint generate --extend FILE -n M``. In the cube (the integration goal) the
    new points fill the cells of the union's grid that no old point occupies, so the
    union stays stratified when the old points permit it; in a region (``region=`` /
    ``shape=``) they settle under U_{E,inf,g} with the old points fixed. ``m`` must be at
    least 1. ``kwargs`` go to :func:`generate` (``seed``, ``target``, ``region``, ...),
    which warns before a long run."""
    old = _points(points, "points")
    d = kwargs.pop("d", None)
    return generate(m, d, extend=old, names={"n": "m", "extend": "points"}, **kwargs)


def nested(sizes: Any, d: int, **kwargs: Any) -> np.ndarray:
    """One set of ``sizes[-1]`` points whose first ``sizes[0]``, ``sizes[1]``, ...
    points are each a good set (each stage an extension of the one before), as
    ``stillpoint generate --nested N1,N2,...``. ``sizes`` is a list of increasing sizes
    or the command line's text ``"N1,N2,..."``. ``kwargs`` go to :func:`generate`,
    which warns before a long run."""
    if not isinstance(sizes, str):
        sizes = list(sizes)
    return generate(None, d, nested=sizes, names={"nested": "sizes"}, **kwargs)


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
    if constraints is not None or mixture:
        if region is not None or shape is not None:
            raise ValueError("invalid constraints with region or shape: give the region one way")
        texts = _constraint_texts(constraints if constraints is not None else [], "constraints")
        texts = [texts] if isinstance(texts, str) else list(texts)
        bbox = None if box is None else [float(v) for v in np.ravel(np.asarray(box, dtype=np.float64))]
        return json.loads(_core.constrained_metrics_json(_points(x), texts, bbox, bool(mixture)))
    if region is not None or shape is not None:
        pts = _points(x)
        bbox = None if box is None else [float(v) for v in box]
        return json.loads(_core.region_metrics_json(pts, region, bbox, shape))
    if box is not None:
        raise ValueError("invalid box: a box only with region or shape='polytope:FILE' (it bounds them)")
    return json.loads(_core.metrics_json(_points(x), bool(exact)))


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


def baseline(name: str, n: int, d: int, seed: int = 0) -> np.ndarray:
    """n points of a classic construction in [0, 1)^d, as ``stillpoint baseline NAME``:
    ``'random'``, ``'halton'``, ``'halton-scrambled'``, ``'sobol'`` (Owen-scrambled),
    ``'hua-wang'``, ``'lattice'``, ``'lhs'``, ``'lhs-maximin'``. :func:`baselines`
    describes each exactly. ``seed`` is ignored by the deterministic ones."""
    return _core.generate(method=str(name), n=n, d=d, seed=seed)


def baselines() -> Dict[str, str]:
    """The baselines' names with the exact description of each construction."""
    return {name: describe for name, _label, describe in _core.baselines()}


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
        return json.loads(_core.integrate_json(pts))
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


# ---------------------------------------------------------------------------------------
# The SciPy engine.

try:  # SciPy is optional: without it Engine is a plain class with the same methods.
    from scipy.stats import qmc as _qmc

    _EngineBase: type = _qmc.QMCEngine
except ImportError:  # pragma: no cover - exercised only without SciPy
    _qmc = None
    _EngineBase = object

_cache: Dict[Any, np.ndarray] = {}
_cache_lock = threading.Lock()


def _frozen(value: Any) -> Any:
    """A hashable stand-in for a keyword value (arrays by shape and bytes)."""
    if isinstance(value, np.ndarray):
        return ("ndarray", value.shape, value.dtype.str, value.tobytes())
    if isinstance(value, dict):
        return tuple(sorted((k, _frozen(v)) for k, v in value.items()))
    if isinstance(value, (list, tuple)):
        return tuple(_frozen(v) for v in value)
    try:
        hash(value)
        return value
    except TypeError:
        return repr(value)


def _tent_set(n: int, d: int) -> np.ndarray:
    """The set for the tent randomisation, computed once per process (read-only)."""
    key = ("tent", n, d)
    with _cache_lock:
        hit = _cache.get(key)
    if hit is not None:
        return hit
    x = _core.tent_set(n, d)
    x.flags.writeable = False
    with _cache_lock:
        return _cache.setdefault(key, x)


def _optimised(n: int, d: int, kwargs: Dict[str, Any]) -> np.ndarray:
    """The optimised set for (n, d, kwargs), computed once per process (read-only)."""
    key = (n, d, _frozen(kwargs))
    with _cache_lock:
        hit = _cache.get(key)
    if hit is not None:
        return hit
    x = generate(n, d, **kwargs)
    x.flags.writeable = False
    with _cache_lock:
        return _cache.setdefault(key, x)


class Engine(_EngineBase):  # type: ignore[misc,valid-type]
    """A randomised QMC engine: every :meth:`random` call returns a set for (n, d)
    randomised so that each point is uniform in [0, 1)^d (an unbiased QMC rule), with
    independent draws for an error estimate.

    By default (``randomize='tent'``) the set is the rank-1 lattice made for this
    randomisation (``generate(n, d, randomize='tent')``; where d exceeds the lattice's
    φ(n)/2 distinct generators, a set descended from it on the same criterion): a uniform
    shift modulo 1, then the tent transform x ↦ 1 − |2x − 1|. Its error decays like n⁻²
    on smooth integrands, and each coordinate of a draw stays stratified (one point in
    each [k/n, (k+1)/n)). ``randomize='cells'`` or ``'shift'`` randomise the optimised set
    :func:`generate` ``(n, d, **generate_kwargs)`` instead (cells rotated and offsets
    shifted in them, or a plain shift). Each n's set is computed on its first draw and
    cached for the process, so later draws cost one randomisation. With
    ``scipy.integrate.qmc_quad(f, a, b, qrng=stillpoint.Engine(d, seed=...))`` each
    estimate uses a freshly seeded engine, hence a new randomisation, and the standard
    error is that of the randomised rule.

    A subclass of ``scipy.stats.qmc.QMCEngine`` when SciPy is installed (then
    ``optimization='random-cd'`` or ``'lloyd'`` is applied after the shift, as SciPy
    does for its engines); a plain class with the same methods otherwise.

    Parameters
    ----------
    d : int
        Dimension.
    seed, rng : optional
        Seed of the shifts: an int, a ``numpy.random.Generator`` or None (give one of
        the two; ``rng`` is SciPy's newer name). The optimised set itself does not depend
        on it (it is generated with ``generate``'s own ``seed``, default 0).
    optimization : {None, 'random-cd', 'lloyd'}
        SciPy's post-processing of each draw.
    **generate_kwargs
        ``randomize`` (``'tent'``, the default, ``'cells'`` or ``'shift'``; ``'cells'``
        is the default when other options describe the set); the others are passed to
        :func:`generate` (``method``, ``energy``, ``steps``, ``seed``
        of the run as ``generate_seed``, the options); not ``region``, ``box``,
        ``shape`` or ``bounds`` (the engine draws in the unit cube).
    """

    def __init__(
        self,
        d: int,
        *,
        seed: Any = None,
        rng: Any = None,
        optimization: Optional[str] = None,
        **generate_kwargs: Any,
    ) -> None:
        d = _int("d", d, 1)
        if seed is not None and rng is not None:
            raise ValueError("invalid seed and rng: give one of them (rng is the newer name)")
        rng = _engine_seed("seed" if rng is None else "rng", seed if rng is None else rng)
        for key in _ENGINE_REFUSES:
            if key in generate_kwargs:
                raise ValueError(
                    f"invalid {key} for Engine: it draws n points of [0, 1)^d "
                    "(n from random(n), d from Engine(d)); scale the draws instead"
                )
        kwargs = dict(generate_kwargs)
        # The recommended randomisation (the lattice made for the shift and tent
        # transform) unless another is named, or options describe a set of generate's to
        # randomise: then its cells are rotated, as before tent existed.
        describes_a_set = any(k != "seed" for k in kwargs)
        kind = kwargs.pop("randomize", None)
        if kind is None or kind is True:
            kind = "cells" if describes_a_set else "tent"
        if kind is False:
            raise ValueError(
                "invalid randomize = False for Engine: its draws are randomised "
                "('tent', 'cells' or 'shift')"
            )
        self._randomize = kind
        if "generate_seed" in kwargs:
            kwargs["seed"] = kwargs.pop("generate_seed")
        # Refuse bad generate arguments now rather than at the first draw.
        _check_generate(2, d, randomize=kind, **kwargs)
        self._generate_kwargs = kwargs
        if _qmc is not None:
            super().__init__(d=d, optimization=optimization, rng=rng)
        else:
            if optimization is not None:
                raise ValueError(
                    f"invalid optimization = {optimization!r}: needs SciPy (not installed)"
                )
            self.d = d
            self.rng = np.random.default_rng(rng)
            self.rng_seed = copy.deepcopy(self.rng)
            self.num_generated = 0
            self.optimization_method = None
        # What scipy.integrate.qmc_quad passes to build independent copies:
        # type(engine)(seed=..., **engine._init_quad).
        self._init_quad = {"d": d, "optimization": optimization, **generate_kwargs}

    def _random(self, n: int = 1, *, workers: int = 1) -> np.ndarray:
        """The cached set for n randomised as ``generate(randomize=...)`` does, seeded
        from this engine's generator (see the class)."""
        n = _int("n", n, 0)
        if n == 0:
            return np.empty((0, self.d))
        if self._randomize == "tent":
            base = _tent_set(n, self.d)
        else:
            base = _optimised(n, self.d, self._generate_kwargs)
        seed = int(self.rng.integers(0, 2**64, dtype=np.uint64))
        return _core.randomize(base, self._randomize, seed)

    if _qmc is None:  # pragma: no cover - the methods QMCEngine provides otherwise

        def random(self, n: int = 1, *, workers: int = 1) -> np.ndarray:
            """n points: the optimised set shifted by a uniform random vector mod 1."""
            x = self._random(n, workers=workers)
            self.num_generated += n
            return x

        def reset(self) -> "Engine":
            """Back to the first draw: the same shifts again."""
            self.rng = copy.deepcopy(self.rng_seed)
            self.num_generated = 0
            return self

    def fast_forward(self, n: int) -> "Engine":
        """Skips one draw of n points cheaply: the random numbers it would have used are
        drawn and dropped, without computing the optimised set."""
        n = _int("n", n, 0)
        if n > 0:
            self.rng.integers(0, 2**64, dtype=np.uint64)
        self.num_generated += n
        return self

    def __repr__(self) -> str:
        extra = "".join(f", {k}={v!r}" for k, v in self._generate_kwargs.items())
        if self._randomize != "tent":
            extra = f", randomize={self._randomize!r}" + extra
        return f"stillpoint.Engine(d={self.d}{extra})"

    def _state(self) -> Tuple[Any, ...]:
        """What decides the draws to come: the dimension, the run's arguments, SciPy's
        post-processing, the generators' states (the current one and the one ``reset``
        returns to) and the count drawn."""
        return (
            type(self),
            self.d,
            self._randomize,
            _frozen(self._generate_kwargs),
            getattr(self, "_optimization", None),
            _frozen(self.rng.bit_generator.state),
            _frozen(self.rng_seed.bit_generator.state),
            _frozen(_optimizer_rng_state(self)),
            self.num_generated,
        )

    def __eq__(self, other: object) -> bool:
        """Engines are equal when they will draw the same points from now on (and after
        ``reset``): a copy, or a pickled and loaded engine, equals its original."""
        if not isinstance(other, Engine):
            return NotImplemented
        return self._state() == other._state()

    # Equal engines stop being equal as either draws: no hash, as for any mutable value.
    # Pickling needs nothing of its own: the instance's attributes (the generators with
    # their states, the arguments, SciPy's post-processing) are all picklable, and pickle
    # keeps the post-processing's generator the same object as ``rng`` when it is one.
    # The cached optimised set is not carried; each process computes it on its first draw.
    __hash__ = None  # type: ignore[assignment]


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


def _optimizer_rng_state(engine: Engine) -> Any:
    """The state of the generator SciPy's post-processing draws from (after ``reset``
    no longer the engine's own ``rng``), or None without one."""
    rng = getattr(getattr(engine, "optimization_method", None), "keywords", {}).get("rng")
    return None if rng is None else rng.bit_generator.state


from ._many import generate_many  # noqa: E402  (it uses generate, defined above)
