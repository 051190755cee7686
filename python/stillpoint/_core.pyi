"""Type stubs of the extension module ``stillpoint._core`` (built from python/src/lib.rs).

These functions take C-ordered float64 arrays of shape (n, d) (the wrappers in
``stillpoint`` cast any array-like first) and release the GIL while they compute. Every
refusal of the library is a ``ValueError`` with the library's message, which names the
argument.
"""

from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

def generate(**kwargs: Any) -> npt.NDArray[np.float64]:
    """The points of the library's request made of the keyword arguments (``n``, ``d``,
    ``seed``, ``method``, ``goal``, ``target``, ``randomize``, ``extend``, ``nested``,
    ``bounds``, ``region``, ``box``, ``shape``, ``constraints``, ``mixture`` and the
    paper's options): by default
    exactly ``stillpoint generate -n N -s D``; a baseline with ``method=NAME``. ``names``
    renames parameters in refusals; ``progress`` prints the stages. Returns an (n, d)
    array."""

def check_generate(**kwargs: Any) -> None:
    """Resolves the keyword arguments of :func:`generate` without running: raises the
    ``ValueError`` generate would raise."""

def estimate(**kwargs: Any) -> float:
    """The estimated seconds of :func:`generate` with these keyword arguments on this
    machine's thread pool (the library's cost model, measured on a 2-core machine; a
    larger pool divides it). Raises the ``ValueError`` generate would raise, without
    running."""

def notes(**kwargs: Any) -> List[str]:
    """What the library says before running :func:`generate` with these keyword arguments
    besides its time (e.g. that the default lattice will reuse generators); raises the
    ``ValueError`` generate would raise."""

def randomize(
    x: npt.NDArray[np.float64], kind: str, seed: int
) -> npt.NDArray[np.float64]:
    """``x`` randomised from ``seed`` as ``generate(..., randomize=kind)`` does:
    ``'tent'``, ``'cells'`` or ``'shift'``."""

def law_set(space: List[str], n: int, seed: int) -> npt.NDArray[np.float64]: ...
def tent_set(n: int, d: int) -> npt.NDArray[np.float64]:
    """The set ``generate(n, d, randomize='tent')`` randomises, unrandomised."""

def metrics(x: npt.NDArray[np.float64], **kwargs: Any) -> Dict[str, Any]:
    """Every figure ``stillpoint eval --json`` prints, as the dict ``json.loads`` makes of
    it; the keywords (``exact``, ``region``, ``box``, ``shape``, ``constraints``,
    ``mixture``) make ``eval``'s request, resolved and refused by the library."""

def discrepancy(x: npt.NDArray[np.float64], kind: str) -> float:
    """The root of one discrepancy: ``'l2star'`` (SciPy's 'L2-star', a root there
    too), ``'md'`` (modified L2; not SciPy's 'MD'), ``'cd'`` (centred; SciPy's 'CD' is
    its square), ``'wd'`` (wrap-around; SciPy's 'WD' is its square), ``'mixture'``
    (SciPy's 'MD' is its square)."""

def baselines() -> List[Tuple[str, str, str]]:
    """Every baseline as (name, the paper's label, exact description)."""

def integrate(x: npt.NDArray[np.float64]) -> Dict[str, Any]:
    """The F1-F8 test integrals of points in [0, 1]^d as a dict: ``n``, ``s``, ``exact``
    (0) and ``functions`` (function, formula, estimate, error), as ``stillpoint integrate
    --json`` prints them without the file name."""

def design(**kwargs: Any) -> Dict[str, Any]:
    """A design: :func:`generate`'s request with ``space`` (the ``NAME=TYPE`` texts), as a
    dict: ``space``, ``correlation`` (the command line's text or None), ``names``,
    ``columns`` (one list per variable: floats, ints or labels), ``unit`` (the unit-scale
    set, an (n, d) array) and ``figures``."""

def design_figures(
    space: Sequence[str],
    columns: Sequence[Tuple[str, Sequence[str]]],
    correlation: Optional[Sequence[float]] = None,
) -> Dict[str, Any]:
    """The design made of named columns of cells (each a label, an integer's digits or a
    float's exact text) read back onto the unit scale of ``space``: the figures of
    :func:`design`'s dict. ``correlation`` is the matrix row-major."""

def options(command: Optional[str] = None) -> List[Dict[str, Any]]:
    """Every option of ``generate`` and ``eval`` (or of ``command``: ``quad``,
    ``sensitivity``, ...) as the library declares it: ``name``, ``cli``, ``python``
    (``None`` where Python has no keyword), ``doc``, ``groups``, ``commands``, ``kind``
    (with its bounds), ``words``, ``expected`` and ``default`` (per command)."""

def space_set(**kwargs: Any) -> Tuple[npt.NDArray[np.float64], str]:
    """The unit-scale set :func:`design` would deal into ``space`` and the phrase of its
    rule, without the design's figures."""

def space_sequence(space: Sequence[str]) -> Tuple[str, List[int]]:
    """The rule of a randomised sequence under ``space`` (``'first-order lattice'`` or
    ``'sobol'``) and the coordinate each of its columns goes to."""

def space_values(
    space: Sequence[str],
    x: npt.NDArray[np.float64],
    correlation: Optional[Sequence[float]] = None,
) -> npt.NDArray[np.float64]:
    """Unit-cube points mapped to the values of ``space``: continuous variables through
    the copula and their quantile functions, discrete ones to level floor(u·L) (a label
    as its index)."""

def sequence_points(
    d: int,
    seed: int = 0,
    replicate: int = 0,
    start: int = 0,
    count: int = 1,
    table: str = "tent",
) -> npt.NDArray[np.float64]:
    """Points [start, start + count) of one replicate of the extensible randomised
    lattice sequence; ``table`` names its generating vector ('tent', quad's, or
    'first-order', the engine's), or 'sobol' for Owen-scrambled Sobol' points in natural
    order (at most 2^20)."""

class Cubature:
    """The state of an integration to a tolerance (see ``stillpoint.quad``), resolved by
    the library from ``quad``'s keyword arguments."""

    def __init__(self, d: int) -> None: ...
    @staticmethod
    def resolve(
        start: Optional["Cubature"] = None, **kwargs: Any
    ) -> Tuple["Cubature", Tuple[Optional[List[str]], Optional[List[float]]]]:
        """The state ``quad``'s keyword arguments ask for (defaults, checks and refused
        combinations are the library's), or ``start`` continued with them; and the
        space's names and correlation (row-major)."""
    def next_points(self) -> Optional[npt.NDArray[np.float64]]: ...
    def feed(self, values: npt.NDArray[np.float64]) -> None: ...
    def check_representable(self) -> None: ...
    def progress_line(self, prefix: str, seconds: float) -> str: ...
    reason: Optional[str]
    settings: Tuple[float, float, float, int, int, int]
    rule: Tuple[str, str]
    round_change: List[Optional[float]]
    estimate: List[float]
    half_width: List[float]
    n: int
    replicates: int
    d: int
    outputs: int
    met: bool
    warnings: List[str]
    in_round: bool
    replicate_means: List[List[float]]

class Sensitivity:
    """The state of a Sobol' sensitivity analysis (see ``stillpoint.sobol_indices``),
    resolved by the library from its keyword arguments."""

    def __init__(self, d: int) -> None: ...
    @staticmethod
    def resolve(
        start: Optional["Sensitivity"] = None, **kwargs: Any
    ) -> Tuple["Sensitivity", Tuple[Optional[List[str]], Optional[List[float]]]]:
        """The state ``sobol_indices``'s keyword arguments ask for, or ``start``
        continued with them; and the space's names and correlation."""
    def next_points(self) -> Optional[npt.NDArray[np.float64]]: ...
    def feed(self, values: npt.NDArray[np.float64]) -> None: ...
    def progress_line(self, prefix: str, seconds: float) -> str: ...
    current: Tuple[List[float], List[float], List[float], List[float]]
    second: Tuple[List[float], List[float]]
    second_order: bool
    reason: Optional[str]
    settings: Tuple[float, float, bool, str, int, int, int]
    n: int
    d: int
    names: List[str]
    outputs: int
    met: bool
    warnings: List[str]
    in_round: bool
