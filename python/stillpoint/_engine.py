"""The SciPy engine: :class:`Engine`, a ``scipy.stats.qmc.QMCEngine`` whose draws
continue one extensible randomised lattice sequence (as SciPy's engines continue
theirs), or, by name, are independent randomised copies of a set computed once per
process and cached."""

from __future__ import annotations

import copy
import threading
import warnings
from typing import Any, Dict, Optional, Tuple

import numpy as np

from . import _core
from ._generate import generate
from ._request import _check_generate
from ._rounds import _rule_items, _to_space
from ._space import _correlation_matrix, _law_name, _space_items
from ._validate import _engine_seed, _fresh_seed, _int

# Arguments of `generate` that an Engine sets itself or cannot take (it draws in the
# unit cube).
_ENGINE_REFUSES = ("n", "d", "region", "box", "shape", "bounds")

# The extensible sequence's reach: its lattice has generators for this many dimensions
# (the tent table's, which quad reads), and each replicate this many points.
_SEQUENCE_MAX_D = _core.SEQUENCE_MAX_D
_SEQUENCE_MAX_POINTS = 2**20

# The generating vector an engine's sequence uses: the engine's own, built for the
# first-order kernel, up to its size; above it, and for engines pickled before it
# existed (which have no record), the tent table.
_SEQUENCE_TABLE = "first-order"
_OWN_TABLE_MAX_D = _core.ENGINE_SEQUENCE_MAX_D
_EARLIER_SEQUENCE_TABLE = "tent"

_DRAWS = ("sequence", "independent")

# The sequences an engine can be asked for by name (as quad's results name the same
# rules), and the tables they read: the engine's own lattice, quad's tent lattice, and
# Owen-scrambled Sobol' points (which the library deals path-first under a space).
_RULES = {"first-order lattice": "first-order", "lattice": "tent", "sobol": "sobol"}
_SOBOL_MAX_D = _core.SOBOL_MAX_D

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


def _engine_space(
    d: Any, space: Any, correlation: Any, generate_kwargs: Dict[str, Any]
) -> Tuple[int, Optional[Dict[str, Any]]]:
    """The engine's dimension and, under ``space``, what its draws and :meth:`to_space`
    need: the variables' texts (SciPy laws as the uniforms they are mapped from), the
    texts the rule is chosen from (a SciPy law of unbounded support as a normal one, as
    ``quad`` takes it), the column names, the correlation and the SciPy laws."""
    if space is None:
        if d is None:
            raise ValueError("invalid d = None: expected the dimension, or space=")
        if correlation is not None:
            raise ValueError(
                "invalid correlation without space: it correlates the variables of space="
            )
        return _int("d", d, 0), None
    if generate_kwargs:
        key = next(iter(generate_kwargs))
        raise ValueError(
            f"invalid {key} with space: an engine under a space draws the rule for its "
            "laws; name a sequence with rule= instead"
        )
    items, frozen = _space_items(space)
    names = list(_core.space_names(items))
    if d is not None and _int("d", d, 0) != len(names):
        raise ValueError(
            f"invalid d = {d!r}: space has {len(names)} coordinates ({', '.join(names[:6])}"
            f"{', …' if len(names) > 6 else ''}); leave d out or give {len(names)}"
        )
    matrix = None
    if isinstance(correlation, (str, bytes)):
        raise ValueError(
            f"invalid correlation = {correlation!r}: expected a k × k matrix of numbers "
            "(not a text)"
        )
    if correlation is not None:
        matrix = _correlation_matrix(correlation)
    rule_items = _rule_items(items, frozen)
    # The library reads the correlation and refuses a bad one, naming it, before any draw.
    flat = None if matrix is None else [float(v) for v in np.ravel(matrix)]
    _core.space_values(items, np.full((1, len(names)), 0.5), flat)
    return len(names), {
        "items": items,
        "rule_items": rule_items,
        "names": names,
        "correlation": flat,
        "matrix": matrix,
        "frozen": frozen,
    }


def _sequence_of(
    d: int, rule: Optional[str], space: Optional[Dict[str, Any]], draws: str
) -> Tuple[Optional[str], str, Optional[list]]:
    """The sequence an engine's draws continue: its rule (None: the default), the table
    it reads, and the space's coordinate each of its columns goes to (None: its own
    order). Refuses a d beyond the sequence's reach when draws continue it."""
    order = None
    if space is not None:
        by_law, dealt = _core.space_sequence(space["rule_items"])
        # Without a path the space's sequence is the engine's default (its own table up
        # to its reach, the tent table above, as for Engine(d)).
        if rule is None and by_law == "sobol":
            rule = by_law
        # The sequence's leading columns (its finest, for a net and for a lattice built
        # coordinate by coordinate) go to the paths' leading steps; the identity needs
        # no dealing.
        if dealt != sorted(dealt):
            order = dealt
    most = {"sobol": _SOBOL_MAX_D, "first-order lattice": _OWN_TABLE_MAX_D}.get(
        rule or "", _SEQUENCE_MAX_D
    )
    if draws == "sequence" and d > most:
        raise ValueError(
            f"invalid d = {d}: the sequence reaches {most} dimensions; for more use "
            "draws='independent' (a set made for each n)"
        )
    if rule is None:
        table = _SEQUENCE_TABLE if d <= _OWN_TABLE_MAX_D else _EARLIER_SEQUENCE_TABLE
    else:
        table = _RULES[rule]
    return rule, table, order


class Engine(_EngineBase):  # type: ignore[misc,valid-type]
    """A randomised QMC engine whose points are each uniform in [0, 1)^d (an unbiased QMC
    rule).

    By default (``draws='sequence'``) successive :meth:`random` calls continue one
    sequence, as SciPy's engines do: ``random(64)`` twice gives the points of
    ``random(128)`` of a fresh engine. The sequence is an extensible rank-1 lattice in
    radical-inverse order (each prefix of 2^m points is a lattice of 2^m points) with one
    uniform random shift per engine, drawn from ``seed``, and the tent transform
    x ↦ 1 − |2x − 1|; up to 1 000 dimensions and 2^20 points. Its generating vector is
    built for the first-order kernel (each prefix of 2^6 to 2^20 points close, on
    average over the levels, to the lattice made for its n), which suits integrands
    through input laws better than the vector ``quad`` uses; engines pickled by earlier
    versions keep the vector they drew from. As for SciPy's Sobol',
    the balance holds at powers of two: a draw that ends elsewhere warns. :meth:`reset`
    goes back to the first point, :meth:`fast_forward` skips points. ``d = 0`` gives
    (n, 0) arrays.

    With ``draws='independent'`` every :meth:`random` call returns a new randomisation
    of a set made for its n (the engine of earlier versions, which unpickled engines of
    those versions keep): by default (``randomize='tent'``) the rank-1 lattice made for this
    randomisation (``generate(n, d, randomize='tent')``; where d exceeds the lattice's
    φ(n)/2 distinct generators, a set descended from it on the same criterion): a uniform
    shift modulo 1, then the tent transform x ↦ 1 − |2x − 1|. Its error decays like n⁻²
    on smooth integrands, and each coordinate of a draw stays stratified (one point in
    each [k/n, (k+1)/n)). ``randomize='cells'`` or ``'shift'`` randomise the optimised set
    :func:`generate` ``(n, d, **generate_kwargs)`` instead (``'cells'``: the cells of
    each coordinate rotated and the offsets shifted within them; ``'shift'``: one uniform
    shift modulo 1); a set is made for each n, so these, and any options describing the
    set, imply ``draws='independent'``. Each n's set is computed on its first draw and
    cached for the process, so later draws cost one randomisation. With
    ``scipy.integrate.qmc_quad(f, a, b, qrng=stillpoint.Engine(d, seed=...))`` each
    estimate uses a freshly seeded engine, hence a new randomisation, and the standard
    error is that of the randomised rule.

    A subclass of ``scipy.stats.qmc.QMCEngine`` when SciPy is installed (then
    ``optimization='random-cd'`` or ``'lloyd'`` is applied after the shift, as SciPy
    does for its engines); a plain class with the same methods otherwise.

    Under a design space (``space=``, the laws of f's inputs, as :func:`quad` takes
    them) the draws are made for those laws and :meth:`to_space` carries them into the
    space: successive draws continue Owen-scrambled Sobol' points where the space holds a
    Brownian path, and the engine's lattice sequence otherwise, the sequence's leading
    columns dealt to every path's first step, then every path's second, …; with
    ``draws='independent'`` each draw is the set ``generate(n, space=...,
    randomize=True)`` makes for its n on the unit scale (the lattice made for the laws
    where every law is unbounded). ``rule=`` names the sequence instead, when you know
    more about f than its laws do.

    Parameters
    ----------
    d : int, optional
        Dimension (0 to 1 000 for the lattice sequences, 21 201 for ``rule='sobol'``);
        under ``space`` its number of coordinates (given, it must agree).
    space : optional
        The laws of f's inputs, in any form :func:`design` takes (texts, a dict of types,
        SciPy frozen laws, Brownian paths ``'brownian(T,m,construction)'``).
    correlation : array_like, optional
        The continuous variables' correlation (``space`` only), as :func:`design` takes it.
    rule : {'first-order lattice', 'lattice', 'sobol'}, optional
        The sequence draws continue: the engine's lattice (the default), ``quad``'s tent
        lattice, or Owen-scrambled Sobol' points in natural order. Not with
        ``draws='independent'``.
    draws : {'sequence', 'independent'}, optional
        Whether draws continue one sequence (the default) or are independent
        randomisations of a set made for each n (the default when ``randomize`` is
        ``'cells'`` or ``'shift'`` or options describe the set, which need it).
    seed, rng : optional
        Seed of the shifts: an int, a ``numpy.random.Generator`` or None (give one of
        the two; ``rng`` is SciPy's newer name); None draws a fresh seed (see "Seeds" in
        docs/python.md). The optimised set itself does not depend on it (it is generated
        with ``generate``'s own ``seed`` given as ``generate_seed``, default 0; None draws
        a fresh one when the engine is made, shown in its repr).
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
        d: Optional[int] = None,
        *,
        space: Any = None,
        correlation: Any = None,
        rule: Optional[str] = None,
        seed: Any = None,
        rng: Any = None,
        optimization: Optional[str] = None,
        draws: Optional[str] = None,
        **generate_kwargs: Any,
    ) -> None:
        d, self._space = _engine_space(d, space, correlation, generate_kwargs)
        if rule is not None and rule not in _RULES:
            raise ValueError(
                f"invalid rule = {rule!r}: expected one of {', '.join(map(repr, _RULES))} "
                "(a sequence), or None for the engine's default (or the space's rule)"
            )
        if rule is not None and (generate_kwargs or draws == "independent"):
            raise ValueError(
                f"invalid rule = {rule!r} with draws='independent' or options of a set: a "
                "rule names the sequence the draws continue; leave it out for independent "
                "draws"
            )
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
        if draws is not None and draws not in _DRAWS:
            raise ValueError(
                f"invalid draws = {draws!r}: expected 'sequence' (successive draws continue "
                "one sequence) or 'independent' (each draw a new randomised set)"
            )
        of_a_set = describes_a_set or kind != "tent"
        if draws is None:
            draws = "independent" if of_a_set else "sequence"
        if draws == "sequence" and of_a_set:
            raise ValueError(
                f"invalid draws = 'sequence' with randomize = {kind!r} or options of a set: "
                "these randomise a set made for each n; use draws='independent', or leave "
                "the options out for the sequence"
            )
        # The sequence the laws choose, and the order its columns are dealt in.
        named = rule
        rule, table, self._order = _sequence_of(d, rule, self._space, draws)
        # A text goes to SciPy, which names the methods it has (in any case); anything
        # else would fail there as an AttributeError.
        if optimization is not None and not isinstance(optimization, str):
            raise ValueError(
                f"invalid optimization = {optimization!r}: expected None, 'random-cd' or "
                "'lloyd' (SciPy's post-processing of each draw)"
            )
        self._draws = draws
        if "generate_seed" in kwargs:
            # Drawn once here for None, so that every draw, copy and pickle of the engine
            # randomises the same set (the seed shows in repr and in _init_quad).
            kwargs["seed"] = _fresh_seed(kwargs.pop("generate_seed"))
            generate_kwargs = {**generate_kwargs, "generate_seed": kwargs["seed"]}
        # Refuse bad generate arguments now rather than at the first draw.
        if d > 0 and self._space is None:
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
        # The sequence's one shift, drawn once: reset() returns to the same points, and
        # engines made from one generator (as qmc_quad makes its copies) differ.
        # Independent draws take nothing from the generator here, so that they are the
        # draws of earlier versions.
        self._sequence_seed = (
            int(self.rng.integers(0, 2**64, dtype=np.uint64)) if draws == "sequence" else None
        )
        self._sequence_table = table
        self._rule = rule
        # What scipy.integrate.qmc_quad passes to build independent copies:
        # type(engine)(seed=..., **engine._init_quad).
        self._init_quad = {"d": d, "optimization": optimization, "draws": draws, **generate_kwargs}
        if space is not None:
            self._init_quad.update(space=space, correlation=correlation)
        if named is not None:
            self._init_quad["rule"] = named

    def _random(self, n: int = 1, *, workers: int = 1) -> np.ndarray:
        """The cached set for n randomised as ``generate(randomize=...)`` does, seeded
        from this engine's generator (see the class)."""
        n = _int("n", n, 0)
        if n == 0 or self.d == 0:
            return np.empty((n, self.d))
        if self._continues():
            return self._sequence(n)
        space = getattr(self, "_space", None)
        if space is not None:
            seed = int(self.rng.integers(0, 2**64, dtype=np.uint64))
            unit, _phrase = _core.space_set(
                n=n,
                space=space["rule_items"],
                correlation=space["matrix"],
                randomize="tent",
                seed=seed,
            )
            return unit
        if self._randomize == "tent":
            base = _tent_set(n, self.d)
        else:
            base = _optimised(n, self.d, self._generate_kwargs)
        seed = int(self.rng.integers(0, 2**64, dtype=np.uint64))
        return _core.randomize(base, self._randomize, seed)

    def _continues(self) -> bool:
        """Whether draws continue the sequence. An engine pickled before the sequence
        existed has no ``_draws``: its draws are independent, as they were."""
        return getattr(self, "_draws", "independent") == "sequence"

    def _sequence(self, n: int) -> np.ndarray:
        """Points num_generated .. num_generated + n of the sequence, with SciPy's
        Sobol' warning where the total drawn leaves the powers of two."""
        start = self.num_generated
        end = start + n
        if end > _SEQUENCE_MAX_POINTS:
            raise ValueError(
                f"invalid n = {n}: {start} points drawn and the sequence has "
                f"{_SEQUENCE_MAX_POINTS}; reset() it, or use draws='independent'"
            )
        if end & (end - 1):
            warnings.warn(
                "The balance properties of the sequence require n to be a power "
                f"of 2. {start} points have been previously generated, then: "
                f"n={start}+{n}={end}. If you still want to do this, the function "
                "'Engine.fast_forward()' can be used.",
                stacklevel=4,
            )
        x = _core.sequence_points(
            self.d,
            seed=self._sequence_seed,
            replicate=0,
            start=start,
            count=n,
            table=self._table(),
        )
        order = getattr(self, "_order", None)
        if order is None:
            return x
        dealt = np.empty_like(x)
        dealt[:, order] = x
        return dealt

    def _table(self) -> str:
        """The generating vector this engine's sequence uses: an engine pickled before
        the engine had its own has no record, and continues the one it drew from."""
        return getattr(self, "_sequence_table", _EARLIER_SEQUENCE_TABLE)

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
        """Skips n points: of the sequence, or (independent draws) one draw of n points,
        whose random numbers are drawn and dropped without computing the set."""
        n = _int("n", n, 0)
        if n > 0 and not self._continues():
            self.rng.integers(0, 2**64, dtype=np.uint64)
        self.num_generated += n
        return self

    @property
    def names(self) -> Optional[list]:
        """The columns' names under ``space`` (a path ``W`` of m steps as ``W_1`` …
        ``W_m``), None without one."""
        space = getattr(self, "_space", None)
        return None if space is None else list(space["names"])

    @property
    def rule(self) -> Optional[str]:
        """The sequence the draws continue: ``'first-order lattice'`` (the default),
        ``'lattice'`` (``quad``'s tent table) or ``'sobol'`` (Owen-scrambled Sobol'); None
        for independent draws."""
        if not self._continues():
            return None
        rule = getattr(self, "_rule", None)
        if rule is not None:
            return rule
        return {v: k for k, v in _RULES.items()}[self._table()]

    def to_space(self, u: Any) -> np.ndarray:
        """Draws of this engine (an (n, d) array in [0, 1]) as the values of its
        ``space``: each continuous variable through the copula and its quantile function
        (a SciPy law through its ``ppf``), a path through its construction, a discrete
        variable to level ⌊u·L⌋ (a label as its index). The mean of f over them estimates
        E f(X) under the space's laws, without bias."""
        space = getattr(self, "_space", None)
        if space is None:
            raise ValueError(
                "invalid to_space on an engine without space: make it with "
                "Engine(space=...) to draw values of a space"
            )
        try:
            u = np.asarray(u, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"invalid u: expected an (n, {self.d}) array of numbers") from None
        if u.ndim != 2 or u.shape[1] != self.d:
            raise ValueError(
                f"invalid u of shape {u.shape}: expected (n, {self.d}), one column per "
                "coordinate of space"
            )
        if not np.all((u >= 0.0) & (u <= 1.0)):
            raise ValueError("invalid u: expected points of the unit cube [0, 1]^d")
        setup = {
            "space": space["items"],
            "correlation": space["correlation"],
            "names": space["names"],
            "frozen": space["frozen"],
        }
        return _to_space(u, setup)

    def __repr__(self) -> str:
        extra = "".join(f", {k}={v!r}" for k, v in self._generate_kwargs.items())
        space = getattr(self, "_space", None)
        if space is not None:
            shown = [
                f"{t.split('=', 1)[0]}={_law_name(space['frozen'][t.split('=', 1)[0]])}"
                if t.split("=", 1)[0] in space["frozen"]
                else t
                for t in space["items"]
            ]
            extra += f", space={shown!r}"
            if space["matrix"] is not None:
                extra += f", correlation={space['matrix'].tolist()!r}"
        if "rule" in getattr(self, "_init_quad", {}):
            extra += f", rule={self._init_quad['rule']!r}"
        if self._randomize != "tent":
            extra = f", randomize={self._randomize!r}" + extra
        elif not self._continues() and hasattr(self, "_draws"):
            extra = ", draws='independent'" + extra
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
            getattr(self, "_draws", "independent"),
            getattr(self, "_sequence_seed", None),
            # Independent draws use no table: an engine pickled before the tables had
            # names equals a new one drawing alike.
            self._table() if self._continues() else None,
            # Engines pickled before spaces had none.
            _frozen(_space_state(getattr(self, "_space", None))),
            _frozen(getattr(self, "_order", None)),
        )

    def __eq__(self, other: object) -> bool:
        """Engines are equal when they will draw the same points from now on (and after
        ``reset``): a copy, or a pickled and loaded engine, equals its original."""
        if not isinstance(other, Engine):
            return NotImplemented
        return self._state() == other._state()

    def __setstate__(self, state: Dict[str, Any]) -> None:
        """The pickled attributes as they are; an engine pickled before the sequence
        existed (no ``_draws``) keeps drawing independently, and so do the copies
        ``scipy.integrate.qmc_quad`` builds from its ``_init_quad``."""
        self.__dict__.update(state)
        if "_draws" not in state and "_init_quad" in state:
            self._init_quad = {**state["_init_quad"], "draws": "independent"}

    # Equal engines stop being equal as either draws: no hash, as for any mutable value.
    # Pickling needs nothing else of its own: the instance's attributes (the generators with
    # their states, the arguments, SciPy's post-processing) are all picklable, and pickle
    # keeps the post-processing's generator the same object as ``rng`` when it is one.
    # The cached optimised set is not carried; each process computes it on its first draw.
    # A pickle names the class `stillpoint.Engine` (the package sets `__module__`), so
    # it loads whichever module defines the class.
    __hash__ = None  # type: ignore[assignment]


def _space_state(space: Optional[Dict[str, Any]]) -> Any:
    """What of a space decides the draws and their values (its SciPy laws by their
    names and arguments)."""
    if space is None:
        return None
    laws = {k: (type(v.dist).__name__, v.args, tuple(sorted(v.kwds.items())))
            for k, v in space["frozen"].items()}
    return (space["items"], space["correlation"], laws)


def _optimizer_rng_state(engine: Engine) -> Any:
    """The state of the generator SciPy's post-processing draws from (after ``reset``
    no longer the engine's own ``rng``), or None without one."""
    rng = getattr(getattr(engine, "optimization_method", None), "keywords", {}).get("rng")
    return None if rng is None else rng.bit_generator.state
