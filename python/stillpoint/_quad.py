"""Integration to a tolerance: :func:`quad` doubles the number of points on R
independently randomised replicates of one extensible rule (the tent-transformed lattice;
under unbounded laws a lattice made for them when f is even in them, scrambled Sobol'
otherwise), never discarding an evaluation, until the
interval from the replicate means is narrow enough; :class:`QuadResult` holds the answer
and the state to continue from with a tighter tolerance."""

from __future__ import annotations

import concurrent.futures
from typing import Any, Callable, List, Optional, Union

import numpy as np

from . import _core
from ._rounds import _SEED, _Result, _run


class QuadResult(_Result):
    """What :func:`quad` returns: the estimate of each output's integral, the half-width
    of its interval at ``level``, ``n`` (evaluations of f), ``replicates``, ``met``
    (whether every output reached its tolerance), ``reason`` (why it stopped:
    ``"met"``, ``"max_n"`` or ``"sequence"``) and ``warnings``. ``estimate`` and
    ``half_width`` are floats when f returns one value per point, arrays of shape (k,)
    when it returns k.

    Pass it back as ``quad(f, d, rel_tol=..., start=result)`` to continue with a tighter
    tolerance: the evaluations already made are kept, only new points are evaluated.
    Picklable.
    """

    _core = _core.Cubature
    _made_by = "quad"

    def _shaped(self, values: List[float]) -> Any:
        a = np.array(values, dtype=np.float64)
        return float(a[0]) if self._setup.get("scalar", True) and a.size == 1 else a

    @property
    def estimate(self) -> Any:
        """The estimate of the integral (a float, or one per output)."""
        return self._shaped(self._state.estimate)

    @property
    def half_width(self) -> Any:
        """The half-width of the interval at ``level`` (a float, or one per output)."""
        return self._shaped(self._state.half_width)

    @property
    def n(self) -> int:
        """Evaluations of f made, all replicates together."""
        return int(self._state.n)

    @property
    def replicates(self) -> int:
        """Independent randomisations R evaluated: the ``replicates`` asked for, and those
        added when one more was predicted to meet the tolerance for less than a
        doubling."""
        means = self._state.replicate_means
        return len(means[0]) if means else int(self._state.replicates)

    @property
    def d(self) -> int:
        """The dimension."""
        return int(self._state.d)

    @property
    def met(self) -> bool:
        """Whether every output's half-width is within max(abs_tol, rel_tol·|estimate|)."""
        return bool(self._state.met)

    @property
    def reason(self) -> Optional[str]:
        """Why the run stopped: ``"met"`` (every output reached its tolerance),
        ``"max_n"`` (the next doubling would pass ``max_n``; continue with a larger one
        through ``start=``) or ``"sequence"`` (the sequence's 2^20 points per replicate
        are used: a larger ``max_n`` cannot help). None only for a result seen by a
        ``progress`` callable before the last doubling."""
        return self._state.reason

    @property
    def rule(self) -> str:
        """The rule evaluated: ``"lattice"`` (the extensible lattice, shifted and
        tent-transformed), ``"sobol"`` (Owen-scrambled Sobol'), also when a pilot round
        chose it (``rule="pilot"``), ``"first-order lattice"`` (the extensible lattice
        of ``Engine(d)``'s table, which a face test over the cube gives an f steep at a
        face), ``"bayesian lattice"`` (one shift of that lattice without the tent, its
        interval a Bayesian cubature's posterior: under unbounded laws, for an f the probe
        round finds even in them or the face test after it flat at the faces; over the
        cube, for an f steep at a face that the probe finds even), or ``"bayesian net"``
        (one Owen-scrambled Sobol' sequence, its interval the posterior of a digital
        kernel: for an f steep at a face that is not even and shows no plateau)."""
        return str(self._state.rule[0])

    @property
    def rule_reason(self) -> str:
        """Why that rule: from the laws of ``space`` (an unbounded law takes Sobol' unless
        the probe round finds f even, or the face test after it flat at the faces: then
        the Bayesian lattice), the
        box and the face test (the first-order lattice for an f steep at a face, the
        Bayesian lattice when its probe round finds f even), as asked
        through ``rule=``, or the pilot round's ratio of half-widths."""
        return str(self._state.rule[1])

    @property
    def warnings(self) -> List[str]:
        """Warnings about the settings (too few replicates for the level)."""
        return list(self._state.warnings)

    @property
    def replicate_means(self) -> np.ndarray:
        """The R replicate estimates, shape (R,) for one output, (k, R) for k."""
        m = np.array(self._state.replicate_means, dtype=np.float64)
        return m[0] if self._setup.get("scalar", True) and m.shape[0] == 1 else m

    def __repr__(self) -> str:
        return (
            f"QuadResult(estimate={self.estimate!r}, half_width={self.half_width!r}, "
            f"n={self.n}, replicates={self.replicates}, met={self.met}, "
            f"reason={self.reason!r}, rule={self.rule!r})"
        )



def quad(
    f: Callable[[np.ndarray], Any],
    d: int,
    *,
    a: Any = None,
    b: Any = None,
    abs_tol: Optional[float] = None,
    rel_tol: Optional[float] = None,
    level: Optional[float] = None,
    replicates: Optional[int] = None,
    max_n: Optional[int] = None,
    space: Any = None,
    correlation: Any = None,
    seed: Any = _SEED,
    executor: Optional[concurrent.futures.Executor] = None,
    start: Optional[QuadResult] = None,
    progress: Union[bool, Callable[[QuadResult], Any]] = False,
    rule: Optional[str] = None,
) -> QuadResult:
    """The integral of f over the box [a, b] (the unit cube by default), or its
    expectation under the distributions of ``space``, to a tolerance.

    The points are R = ``replicates`` randomisations of one extensible rule; n doubles,
    keeping every evaluation, until each output's half-width is at most
    ``max(abs_tol, rel_tol * |estimate|)`` or ``max_n`` would be passed; when a few more
    replicates at the points each has are predicted to meet the tolerance for less than a
    doubling, they are evaluated instead (and later doublings keep them). On the tent
    lattice, whose points come in reflected pairs (x, 1 − x), an f that took one value at
    both points of every pair of the first round has only one point of each later pair
    evaluated (the same estimate, half the evaluations; ``rule_reason`` says so). Under
    unbounded laws (no path) the first round is a probe of 64 points of a lattice made
    for such laws: an f even in them, or one the face test below finds flat at the faces
    (it decays in the laws' tails), goes on with one shifted lattice of 256 points and
    more, its interval a Bayesian cubature's posterior rather than the spread of
    replicates (``rule="bayesian lattice"``, ``replicates`` 1); one steep there goes on
    with one scrambled Sobol' sequence and the posterior of a digital kernel
    (``rule="bayesian net"``), or with scrambled Sobol''s replicates where the probe's
    values show a plateau (one value at 1/16 of them: a payoff's zero); the 64 and 7
    evaluations are counted. A doubling
    that ``max_n`` holds three quarters or more of is made short (each replicate takes
    the first points of it the budget holds); a Bayesian rule whose doubling does not fit
    takes half of it, and the Bayesian net also takes half a doubling where its whole net
    missed the tolerance by at most 5/4 (three cosets of the rule of half the points,
    whose posterior weighs their means). No run stops before 64 points per
    replicate. Over the cube, a box or bounded laws, with a
    tolerance, a face test of 7 evaluations (counted) comes first: f near two opposite
    corners; an f whose derivative is unbounded at a face (a quantile function or a power
    x^α, α < 1, inside it) goes on with that lattice's probe and then as under unbounded
    laws (the Bayesian lattice for an f even under x ↦ 1 − x, the Bayesian net for
    another, that lattice for one with a plateau), any other with the tent lattice. The rule, the interval and its measured coverage: [Integration, to a
    tolerance](integration.md#to-a-tolerance); examples: [Python and
    SciPy](python.md#integrating-to-a-tolerance).

    Parameters
    ----------
    f : callable
        Vectorised: takes an (n, d) array and returns n values, shape (n,), or n rows of
        k outputs, shape (n, k).
    d : int
        The dimension (1 to 1000); with ``space``, the number of its coordinates (a
        path ``'brownian(T,m)'`` counts m).
    a, b : array_like, optional
        The box's corners (d numbers each, or one for every dimension), as in
        ``scipy.integrate.qmc_quad``; the estimate includes the volume. Checked as every
        box of the package (b > a, each width finite, above 1e-150 and not vanishing
        next to the coordinates). Not with ``space``.
    abs_tol, rel_tol : float, optional
        The tolerance, by default 0 and 1e-3 (three significant digits); set
        ``rel_tol=0`` and ``abs_tol`` for an integral near zero.
    level : float, optional
        The confidence level of the interval, in (0, 1); by default 0.95.
    replicates : int, optional
        Independent randomisations R to start with, 2 to 16384, by default 4; fewer
        than 4 warn (the t quantile is then large and the interval unreliable). The
        result's ``replicates`` counts those added on the way.
    max_n : int, optional
        The most evaluations of f, all replicates together; by default 2^20.
    space : list or dict, optional
        A design space as :func:`design` takes it (``{"x": "normal(0,1)", "k":
        "int(1,3)"}``, SciPy frozen laws through their ``ppf``): f receives the space's
        values and the result is the expectation of f. A continuous variable whose
        range cannot hold 4096 distinct floats is refused.
    correlation : array_like or str, optional
        With ``space``, the continuous variables' correlation (a Gaussian copula): a
        k × k matrix, or its rows as text, ``"1,0.5;0.5,1"``.
    seed : int or None
        The shifts' seed, 0 when omitted, as everywhere in the package; None draws a
        fresh one.
    executor : concurrent.futures.Executor, optional
        Evaluates f on chunks of each batch in parallel (a process pool, Dask's
        ``Client.get_executor()``, ...; f must then be picklable), with the result of
        one process.
    start : QuadResult, optional
        An earlier result to continue from, keeping its evaluations (it is not
        changed). ``abs_tol``, ``rel_tol`` (either sets both), ``level`` and ``max_n``
        are honoured when given, the rest is kept; ``d`` must match; ``a``, ``b``,
        ``space`` and ``correlation`` are refused, ``replicates``, ``seed`` and ``rule``
        unless equal to the earlier ones.
    progress : bool or callable
        After each doubling: False (the default) says nothing; True writes the rule and
        why, then a line per doubling to standard error (``quad: n=4096
        estimate=1.23457e+00  half-width=3.1e-04 (target 1.2e-04)  2.3 s``; after a face
        test, ``quad: n=7  rule: lattice``); a callable is given the :class:`QuadResult`
        so far from the first round on (a copy, which ``start=`` can continue), and an
        exception it raises stops the run as Ctrl-C does.
    rule : str, optional
        ``"lattice"`` or ``"sobol"`` chooses the rule instead of the laws and the face
        test (None by default);
        ``"pilot"`` keeps the one whose first round is clearly narrower, the other's first
        round counted in ``n``; ``"first-order lattice"`` the lattice with the table of
        ``Engine(d)`` (made for unbounded laws); ``"bayesian lattice"`` one shift of that
        lattice without the tent and a Bayesian cubature's interval, which the probe round
        chooses for an f even in the laws or flat at the faces (made for such an f; a
        smooth f over the cube that is not periodic is outside its kernel's space);
        ``"bayesian net"`` one scrambled Sobol' sequence and a Bayesian cubature's
        interval with a digital kernel, which the probe and the face test choose for an f
        steep at a face (docs/integration.md).

    Returns
    -------
    QuadResult

    Raises
    ------
    ValueError
        For a bad argument (named), a result of f of the wrong shape, or a NaN or ±inf
        from f (naming the point).
    KeyboardInterrupt
        On Ctrl-C while f runs, as any Python code.
    """
    given = dict(d=d, a=a, b=b, abs_tol=abs_tol, rel_tol=rel_tol, level=level, rule=rule,
                 replicates=replicates, max_n=max_n, space=space, correlation=correlation, seed=seed)
    state, setup = _run(QuadResult, f, given, start, executor, progress)
    # An early estimate may overflow where a later one does not: checked where it stops.
    state.check_representable()
    return QuadResult(state, setup)
