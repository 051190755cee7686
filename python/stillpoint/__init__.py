"""stillpoint: evenly spread point sets in [0, 1)^d as NumPy arrays.

The points are the static solution of a damped many-body problem (the dynamical
evolutionary model): :func:`generate` gives exactly what ``stillpoint generate -n N -s D``
writes, :func:`metrics` what ``stillpoint eval --json`` prints, :func:`baseline` the
classic sequences (scrambled Sobol', Halton, lattices, Latin hypercubes, ...),
:func:`integrate` the paper's test integrals, :func:`quad` an integral to a tolerance
(doubling n on an extensible randomised lattice until the interval is narrow enough),
:func:`design` a design in a mixed space
(distributions, integer and categorical factors; ``generate(n, space=...)`` as a table),
and :class:`Engine` a SciPy
``scipy.stats.qmc.QMCEngine`` whose draws continue one randomised extensible lattice
sequence (or, by name, are independent randomised sets; usable with
``scipy.integrate.qmc_quad``).

Every function accepts any array-like of points (lists, float32, Fortran order: they are
cast to C-ordered float64) and returns float64 arrays of shape (n, d). Every refusal is a
``ValueError`` whose message names the argument; the long computations release the GIL.

The package is laid out by concern, each in a private module: ``_generate`` (generate,
extend, nested), ``_design`` (Design, design, design_figures), ``_metrics`` (metrics,
discrepancy), ``_baselines``, ``_integrate``, ``_quad`` (quad, QuadResult), ``_engine`` (Engine),
``_many`` (generate_many), with the argument checks in ``_validate``, design spaces in ``_space``
and the checks before a call in ``_request``. Every public name is this package's:
import it from ``stillpoint``.
"""

from . import _core
from ._baselines import baseline, baselines
from ._design import Design, design, design_figures
from ._engine import Engine
from ._generate import extend, generate, nested
from ._integrate import integrate
from ._many import generate_many
from ._metrics import discrepancy, metrics
from ._quad import QuadResult, quad
from ._sensitivity import SobolResult, sobol_indices

__version__: str = _core.__version__

__all__ = [
    "Design",
    "Engine",
    "QuadResult",
    "SobolResult",
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
    "quad",
    "sobol_indices",
]

# Each public name says it is `stillpoint`'s, not its private module's: pickles of an
# Engine or a Design (and of the functions, which executors send by name) then point to
# the path users import, which stays when the modules behind it move.
for _name in __all__:
    globals()[_name].__module__ = __name__
del _name
