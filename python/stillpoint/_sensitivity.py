"""Sobol' sensitivity indices to a tolerance: :func:`sobol_indices` evaluates f on a
pick-freeze design drawn from the extensible randomised lattice in 2d dimensions
(Owen-scrambled Sobol' points under an unbounded law), doubling the points (never
discarding an evaluation), the estimate from all of them and each index's interval from a
Bayesian posterior of the rule of all of them (or from R blocks of them), until every
index's interval is narrow enough; :class:`SobolResult` holds the indices, their
half-widths and the state to continue from."""

from __future__ import annotations

import concurrent.futures
from typing import Any, Callable, List, Optional, Union

import numpy as np

from . import _core
from ._rounds import _SEED, _Result, _run


class SobolResult(_Result):
    """What :func:`sobol_indices` returns.

    ``first`` and ``total`` are the first-order and total Sobol' indices, shape (d,) when
    f returns one value per point, (d, k) for k outputs (SciPy's names ``first_order``
    and ``total_order`` are the same arrays); ``first_half_width`` and
    ``total_half_width`` the half-widths of their intervals at ``level`` (each index's
    own interval, or all together when ``simultaneous``); ``n`` the evaluations of f, all
    rounds; ``met`` whether every half-width is within ``abs_tol``; ``reason`` why it
    stopped (``"met"``, ``"max_n"`` or ``"sequence"``); ``names`` the inputs' names
    (the space's, or ``x1`` … ``xd``); with ``second_order=True``, ``second`` and
    ``second_half_width`` the pairs' indices, symmetric (d, d) arrays with NaN on the
    diagonal.

    Pass it back as ``sobol_indices(f, d, abs_tol=..., start=result)`` to continue with
    a tighter tolerance: only new points are evaluated. Picklable.
    """

    _core = _core.Sensitivity
    _made_by = "sobol_indices"

    def _shaped(self, which: int) -> np.ndarray:
        k = max(1, int(self._state.outputs))
        a = np.array(self._state.current[which], dtype=np.float64).reshape(-1, k)
        return a[:, 0] if self._setup.get("scalar", True) and k == 1 else a

    @property
    def first(self) -> np.ndarray:
        """First-order indices: the share of the output's variance due to each input
        alone."""
        return self._shaped(0)

    @property
    def total(self) -> np.ndarray:
        """Total indices: the share of the variance in which each input takes part."""
        return self._shaped(1)

    @property
    def first_half_width(self) -> np.ndarray:
        """Half-width of each first-order index's interval at ``level``."""
        return self._shaped(2)

    @property
    def total_half_width(self) -> np.ndarray:
        """Half-width of each total index's interval at ``level``."""
        return self._shaped(3)

    first_order = first
    total_order = total

    def _pairs(self, which: int) -> Optional[np.ndarray]:
        """The second-order indices (which = 0) or their half-widths (1) as a symmetric
        (d, d) array, (d, d, k) for k outputs, NaN on the diagonal; None unless asked
        for."""
        if not self._state.second_order:
            return None
        d, k = self.d, max(1, int(self._state.outputs))
        flat = np.array(self._state.second[which], dtype=np.float64).reshape(-1, k)
        out = np.full((d, d, k), np.nan)
        i, j = np.triu_indices(d, 1)
        out[i, j] = flat
        out[j, i] = flat
        return out[:, :, 0] if self._setup.get("scalar", True) and k == 1 else out

    @property
    def second(self) -> Optional[np.ndarray]:
        """Second-order indices S_ij (``second_order=True``): the share of the variance
        due to inputs i and j together beyond each alone, a symmetric (d, d) array
        ((d, d, k) for k outputs) with NaN on the diagonal; None when not asked for."""
        return self._pairs(0)

    @property
    def second_half_width(self) -> Optional[np.ndarray]:
        """Half-width of each second-order index's interval at ``level``, shaped as
        ``second``; None when not asked for."""
        return self._pairs(1)

    @property
    def n(self) -> int:
        """Evaluations of f made, all rounds: (d + 2) per point of every replicate (2d + 2
        with ``second_order``), and
        over a box or bounded laws the face test's 8·d (f at 4 points with each input in
        turn just inside both ends of its range; the lattice takes the inputs f is
        periodic in without the tent)."""
        return int(self._state.n)

    @property
    def d(self) -> int:
        """The number of inputs."""
        return int(self._state.d)

    @property
    def names(self) -> List[str]:
        """The inputs' names."""
        return list(self._state.names)

    @property
    def met(self) -> bool:
        """Whether every index's half-width is within ``abs_tol``."""
        return bool(self._state.met)

    @property
    def reason(self) -> Optional[str]:
        """Why the run stopped: ``"met"``, ``"max_n"`` (continue with a larger one
        through ``start=``) or ``"sequence"`` (the sequence's 2^20 points are used). None
        only for a result seen by a ``progress`` callable before the last round."""
        return self._state.reason

    @property
    def level(self) -> float:
        """The confidence level of the intervals."""
        return float(self._state.settings[1])

    @property
    def simultaneous(self) -> bool:
        """Whether the intervals hold all together at ``level`` (Bonferroni)."""
        return bool(self._state.settings[2])

    @property
    def replicates(self) -> int:
        """Replicates R: the blocks of the one randomised sequence (the blocks' interval
        comes from their spread)."""
        return int(self._state.settings[4])

    @property
    def interval(self) -> str:
        """How the half-widths were computed: ``"posterior"`` or ``"blocks"`` (asked
        for, or where the posterior cannot be formed: Owen-scrambled points under an
        unbounded law, a count of replicates that is not a power of two, more than 2^24
        values of f)."""
        return str(self._state.interval)

    @property
    def warnings(self) -> List[str]:
        """Warnings about the settings (too few replicates)."""
        return list(self._state.warnings)

    def __repr__(self) -> str:
        return (
            f"SobolResult(names={self.names!r}, first={self.first!r}, "
            f"total={self.total!r}, n={self.n}, met={self.met}, reason={self.reason!r})"
        )


def sobol_indices(
    f: Callable[[np.ndarray], Any],
    d: Optional[int] = None,
    *,
    space: Any = None,
    a: Any = None,
    b: Any = None,
    abs_tol: Optional[float] = None,
    level: Optional[float] = None,
    simultaneous: Optional[bool] = None,
    first_estimator: Optional[str] = None,
    second_order: Optional[bool] = None,
    interval: Optional[str] = None,
    replicates: Optional[int] = None,
    max_n: Optional[int] = None,
    seed: Any = _SEED,
    executor: Optional[concurrent.futures.Executor] = None,
    start: Optional[SobolResult] = None,
    progress: Union[bool, Callable[[SobolResult], Any]] = False,
    correlation: Any = None,
) -> SobolResult:
    """The first-order and total Sobol' indices of f's inputs to a tolerance.

    The inputs are independent: uniform on the box [a, b] (the unit cube by default), or
    distributed as the variables of ``space``. For each point (A, B) of the extensible
    randomised lattice in 2d dimensions (Owen-scrambled Sobol' points when a law of
    ``space`` is unbounded, as for :func:`quad`; each input's A and B coordinates
    neighbours), f is evaluated at A, at B and at each AB_i (A with input i taken from
    B): d + 2 evaluations per point. The points are the first N of one randomised
    sequence, cut into R aligned blocks (the replicates, 8 by default); from 64 points
    per block, N doubles, extending the earlier points, until every index's half-width
    is at most ``abs_tol``, or the next round would pass ``max_n`` evaluations (``met``
    is then False). Total indices are Janon et al. (2014)'s; first
    order ones Saltelli et al. (2010)'s by default (the more accurate of the two
    measured, for small indices most of all), Janon et al. (2014)'s by name, each from
    all N points. Each index's interval is by default a Bayesian cubature's posterior
    of the rule of all N points: the index's linearisation at every point, a
    shift-invariant kernel weighted per input by the total indices and fitted to it by
    maximum likelihood, and the posterior's normal quantile at 1 − (1 − level)/5; on
    Owen-scrambled points, or by name, a Student t interval from a jackknife over the
    blocks (each a randomised rule of N/R points, so it errs on the wide side). Either is
    raised to the index's change since half the points when that is larger. Up to 500
    inputs (the sequence's 1 000 coordinates hold A and B).

    Parameters
    ----------
    f : callable
        Vectorised: takes an (n, d) array and returns n values, shape (n,), or n rows of
        k outputs, shape (n, k) (each output gets its own indices).
    d : int, optional
        The number of inputs (1 to 500); taken from ``space`` or ``a``/``b`` when
        omitted.
    space : list or dict, optional
        A design space as :func:`quad` takes it (``{"x": "normal(0,1)", "k":
        "int(1,3)"}``, SciPy frozen laws too); f receives the space's values. A Brownian
        path is refused (its values are dependent).
    a, b : array_like, optional
        The box's corners (d numbers each, or one for every input). Not with ``space``.
    abs_tol : float, optional
        The half-width every index must reach, by default 0.01.
    level : float, optional
        The confidence level of the intervals, in (0, 1); by default 0.95.
    simultaneous : bool, optional
        By default False: each index's own interval holds at ``level``. True: all
        2·d·k intervals hold together at ``level`` (Bonferroni), and the tolerance
        applies to these wider ones.
    first_estimator : str, optional
        ``"saltelli"`` or ``"janon"``; by default ``"saltelli"``.
    second_order : bool, optional
        By default False. True: also every pair's second-order index S_ij (the share of
        the variance due to inputs i and j together beyond each alone), Saltelli
        (2002)'s estimator symmetrised, from f at each BA_i (B with input i taken from A)
        as well: 2d + 2 evaluations per point; the tolerance then applies to these
        intervals too. The first-order and total indices are those of the same points
        without them.
    interval : str, optional
        ``"posterior"`` or ``"blocks"``; by default ``"posterior"`` (it keeps every value
        of f, 8 bytes per evaluation and output, up to 2^24 values, then goes on with the
        blocks). A continuation may go from the posterior to the blocks, not back.
    replicates : int, optional
        Replicates R, 2 to 16384 (by default 8): the blocks of the one sequence the
        blocks' interval comes from (the posterior needs R a power of two, and does not
        depend on it otherwise); the estimate uses every point whatever R is.
    max_n : int, optional
        The most evaluations of f, all rounds; by default 2^22.
    seed : int or None
        The sequence's seed, 0 when omitted; None draws a fresh one.
    executor : concurrent.futures.Executor, optional
        Evaluates f on chunks of each round in parallel (f must then be picklable); the
        result is the same as in one process.
    start : SobolResult, optional
        An earlier result to continue from: its evaluations are kept. ``abs_tol``,
        ``level``, ``simultaneous`` and ``max_n`` are honoured when given; ``d`` must
        match; ``space``, ``a`` and ``b`` are refused with it, ``replicates``,
        ``first_estimator``, ``second_order`` and ``seed`` unless equal to the earlier
        ones.
    progress : bool or callable
        After each round: True writes one line to standard error (evaluations, the
        widest half-width against ``abs_tol``, seconds); a callable gets a copy of the
        :class:`SobolResult` so far. An exception it raises stops the run.
    correlation : optional
        Refused: the indices are defined here for independent inputs.

    Returns
    -------
    SobolResult

    Raises
    ------
    ValueError
        For a bad argument (named), a result of f of the wrong shape, a NaN or ±inf from
        f (naming the point), or an output that takes one value at every point of the
        first round (its variance, which every index divides by, is 0).
    """
    given = dict(
        d=d, space=space, a=a, b=b, abs_tol=abs_tol, level=level, simultaneous=simultaneous,
        first_estimator=first_estimator, second_order=second_order, interval=interval,
        replicates=replicates,
        max_n=max_n, seed=seed, correlation=correlation,
    )
    return SobolResult(*_run(SobolResult, f, given, start, executor, progress))
