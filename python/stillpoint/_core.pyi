"""Type stubs of the extension module ``stillpoint._core`` (built from python/src/lib.rs).

These functions take C-ordered float64 arrays of shape (n, d) (the wrappers in
``stillpoint`` cast any array-like first) and release the GIL while they compute. Every
refusal of the library is a ``ValueError`` with the library's message, which names the
argument.
"""

from typing import Any, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

__version__: str

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
    box: Optional[Sequence[float]] = None,
    shape: Optional[str] = None,
    progress: bool = False,
    **options: Any,
) -> npt.NDArray[np.float64]:
    """n points of the library's run (by default exactly ``stillpoint generate -n N -s
    D``), in the cube or in a region, or of a baseline (``method=NAME``). ``box`` is the
    flat list lo1, hi1, lo2, hi2, ...; ``options`` are the run's further settings (q, p,
    precision, init, kappa, restart, tolerance, polish, shifts, log_every); an unknown
    one is refused with the list of accepted names. Returns an (n, d) array."""

def check_generate(
    n: int,
    d: Optional[int] = None,
    *,
    seed: int = 0,
    method: Optional[str] = None,
    energy: Optional[str] = None,
    integrator: Optional[str] = None,
    steps: Optional[int] = None,
    region: Optional[str] = None,
    box: Optional[Sequence[float]] = None,
    shape: Optional[str] = None,
    progress: bool = False,
    **options: Any,
) -> None:
    """Checks the arguments of :func:`generate` without running it: raises the
    ``ValueError`` generate would raise for a bad name or range."""

def metrics_json(x: npt.NDArray[np.float64]) -> str:
    """Every figure ``stillpoint eval --json`` prints for points in [0, 1]^d, as the same
    JSON object (compact text). Refuses a coordinate outside [0, 1]."""

def discrepancy(x: npt.NDArray[np.float64], kind: str) -> float:
    """The root of one L2 discrepancy: ``'l2star'`` (SciPy's 'L2-star', a root there
    too), ``'md'`` (modified L2; not SciPy's 'MD', the mixture discrepancy), ``'cd'``
    (centred; SciPy's 'CD' is its square), ``'wd'`` (wrap-around; SciPy's 'WD' is its
    square)."""

def baseline(name: str, n: int, d: int, seed: int = 0) -> npt.NDArray[np.float64]:
    """n points of a baseline in [0, 1)^d, as ``stillpoint baseline NAME -n N -s D
    --seed SEED`` writes them."""

def baselines() -> List[Tuple[str, str, str]]:
    """Every baseline as (name, the paper's label, exact description)."""

def integrate_json(x: npt.NDArray[np.float64]) -> str:
    """The F1-F8 test integrals of points in [0, 1]^d as JSON text: ``n``, ``s``,
    ``exact`` (0) and ``functions`` (function, formula, estimate, error), as
    ``stillpoint integrate --json`` prints them without the file name."""
