"""Point sets: :func:`generate` (the library's run for one request: the default
construction, the paper's pipeline, a baseline, a region, a design space as a table),
:func:`extend` (new points settled among old ones) and :func:`nested` (one set whose
prefixes are each a good set)."""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from . import _core
from ._design import design
from ._request import _warn_if_long
from ._validate import _arrays, _fresh_seed, _points


def generate(
    n: int,
    d: Optional[int] = None,
    *,
    seed: Optional[int] = 0,
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
    seed : int or None
        Seed of every random choice (the random start; a baseline's scramble; a
        randomisation). The default 0 gives the same points on every call; None draws a
        fresh seed (independent randomisations, see "Seeds" in docs/python.md).
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
        ``'cells'`` or ``'shift'`` randomise the optimised set; with ``space=`` the
        randomised set goes through each law's inverse CDF, levels as ⌊u·L⌋ rather than
        dealt by rank, so that every seed gives an unbiased estimate of E f(X), see
        :func:`design`), ``extend`` (see :func:`extend`), ``nested`` (see :func:`nested`);
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
        Before a run the library's cost model estimates at more than 5 seconds
        (on this machine's cores), with the estimate (the command line's note); ``warnings.filterwarnings``
        silences it or, with ``'error'``, turns it into an exception before any work.
    UserWarning
        Before a run of the default lattice with more columns than its φ(n)/2
        generators that differ: how many columns will reuse one (the command line's
        note).
    """
    seed = _fresh_seed(seed)
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


def _option_table() -> str:
    """The docstring's table of every keyword, from the library's one declaration of each
    option (the command line's ``-h`` prints the same doc lines)."""
    lines = [
        "",
        "    Options",
        "    -------",
        "    Every keyword as the library declares it (``stillpoint._core.options()``), with",
        "    the command line's flag and the groups of rules it falls under:",
        "",
    ]
    for o in _core.options():
        if o["python"] is None:
            continue
        groups = ", ".join(o["groups"]) or "any run"
        lines.append(f"    ``{o['python']}`` (``{o['cli']}``; {groups})")
        lines.append(f"        {o['doc']}")
    return "\n".join(lines) + "\n"


if generate.__doc__ is not None:
    generate.__doc__ = generate.__doc__.rstrip() + "\n" + _option_table()
