"""Designs in a mixed space (distributions, integer and categorical factors):
:func:`design` makes one, :class:`Design` holds its columns, unit-scale set and figures,
and :func:`design_figures` measures any table the same way."""

from __future__ import annotations

from typing import Any, Dict, Optional

import numpy as np

from . import _core
from ._request import _warn_if_long
from ._space import _design_kwargs, _law_name, _space_items
from ._validate import _fresh_seed


class Design:
    """A design in a mixed space: ``columns`` (name -> values: floats, integers or
    labels), ``unit`` (the design on the unit scale, an (n, d) array: continuous
    values before their marginal's quantile function, a level at the centre of its
    share of [0, 1); for a randomised design the randomised unit-cube set itself, of
    which every column is the inverse-CDF image), ``figures`` (level and pair balance,
    slice stratification, centred L2 of the continuous part overall and per slice,
    minimum distance; all on the unit scale), ``space`` (the variables as
    ``NAME=TYPE``), ``seed`` (the seed it was made with: the one drawn for
    ``seed=None``, so that the design can be made again), ``rule`` (how the unit-cube
    set was made and carried into the space, the phrase the command line's report and
    file header give) and ``unbiased`` (whether the mean of f over the columns is an
    unbiased estimate of E f(X) for every seed: a randomised design)."""

    def __init__(self, raw: Dict[str, Any], frozen: Dict[str, Any], seed: Any = 0) -> None:
        self.seed: Any = seed
        self.space: list = raw["space"]
        self.rule: Optional[str] = raw.get("rule")
        self.unbiased: bool = bool(raw.get("unbiased", False))
        # The correlation as the command line writes it ("1.0,0.7;0.7,1.0"), or None:
        # with the space, all that design_figures needs to reproduce the figures.
        self.correlation: Optional[str] = raw.get("correlation")
        self.names: list = raw["names"]
        self.unit: np.ndarray = raw["unit"]
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
        """The columns as a pandas DataFrame (needs pandas), with the design's seed in
        ``attrs["seed"]`` and its rule in ``attrs["rule"]``."""
        import pandas as pd  # optional: only this method needs it

        frame = pd.DataFrame(self.columns, columns=self.names)
        frame.attrs["seed"] = getattr(self, "seed", 0)
        frame.attrs["rule"] = getattr(self, "rule", None)
        return frame

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
    every other option of :func:`generate` (``goal``, ``seed``, ...; ``seed=None`` draws a
    fresh seed, kept in :attr:`Design.seed`, see "Seeds" in docs/python.md), then every level
    count is made ⌊n/L⌋ or ⌈n/L⌉, pairs of unordered factors balanced, and the
    continuous columns stratified within every level of every unordered factor.

    ``randomize`` (``True`` or ``'tent'``, ``'cells'``, ``'shift'``, as :func:`generate`
    takes it) makes a randomised set instead, for error bars: the randomised unit-cube
    set carried point by point through each law's inverse CDF (continuous variables
    through the copula and their quantile function, a variable with L levels to level
    ⌊u·L⌋). Each seed's mean of f over the columns is then an unbiased estimate of
    E f(X) under the space's law; levels are not dealt by rank (nor pairs balanced or
    slices stratified), which would break that. :attr:`Design.rule` names the rule.
    """
    _items, frozen = _space_items(space)
    if "seed" in kwargs:
        kwargs["seed"] = _fresh_seed(kwargs["seed"])
    seed = kwargs.get("seed", 0)
    kwargs = _design_kwargs(n, space, kwargs)
    _warn_if_long(kwargs)
    return Design(_core.design(**kwargs), frozen, seed)


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
    names = _core.space_names(items)
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
    return _core.design_figures(items, cells, matrix)
