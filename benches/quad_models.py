"""The integrands of benches/quad.py: four Genz families and three models with known
means, each a function on the unit cube [0,1]^s (every transform is inside the function,
so every method integrates the same code) with a random instance per run and its exact
integral.

    instance(family, s, run) -> params
    value(family, params, x)  -> f(x) for x of shape (n, s)
    exact(family, params)     -> the integral over [0,1]^s

Families:
- ``oscillatory``, ``product peak``, ``corner peak``, ``gaussian``: Genz's families with
  benches/anchors.py's difficulties and values; the exact integrals are anchors.py's
  ``genz_exact`` (closed forms; for the corner peak a one-dimensional quadrature of its
  Laplace representation).
- ``ishigami``: sin x1 + a sin² x2 + b x3⁴ sin x1 with x uniform on [-π, π]^3,
  a ~ U[5, 9], b ~ U[0.05, 0.15]; mean a/2.
- ``keister``: ∫_{R^s} cos(‖t‖) exp(-‖t‖²) dt = E[π^{s/2} cos(‖T‖)], T ~ N(0, I/2),
  written on the cube as T = Φ⁻¹(x)/√2. No parameters (only the seed changes between
  runs). Exact value: the radial integral 2π^{s/2}/Γ(s/2) ∫_0^∞ r^{s-1} cos r e^{-r²} dr
  by adaptive quadrature (``keister_exact``; `--check-keister` in quad.py compares it
  with QMCPy's recurrence).
- ``lognormal``: E[Π X_j] with X_j = exp(μ_j + σ_j Z_j), Z_j = Φ⁻¹(x_j) standard
  normal, μ_j ~ U[-0.5, 0.5] and σ_j ∝ U[0, 1] scaled to Σσ_j² = 0.25; mean
  Π exp(μ_j + σ_j²/2).

Φ⁻¹ is applied to x clipped to [2^-53, 1 - 2^-53], so points on the cube's boundary
(which an unshifted or tent-transformed lattice can produce) give finite values.
"""

import math
import os
import sys

import numpy as np
from scipy import integrate as sintegrate
from scipy.special import gammaln, ndtri

sys.path.insert(0, os.path.dirname(__file__))
from anchors import GENZ_DIFFICULTY, genz_exact, genz_value  # noqa: E402

GENZ = {"oscillatory": 0, "product peak": 1, "corner peak": 2, "gaussian": 3}
FAMILIES = {  # family -> dimensions measured
    "oscillatory": [2, 5, 10, 20],
    "product peak": [2, 5, 10, 20],
    "corner peak": [2, 5, 10, 20],
    "gaussian": [2, 5, 10, 20],
    "ishigami": [3],
    "keister": [2, 5, 10, 20],
    "lognormal": [2, 5, 10, 20],
}
FAMILY_INDEX = {name: i for i, name in enumerate(FAMILIES)}
LOGNORMAL_VARIANCE = 0.25  # Σσ_j²
EPS = 2.0 ** -53


def instance(family, s, run):
    """The random parameters of run `run` (the same for every method and tolerance)."""
    if family in GENZ:
        # The generator's key is the one earlier versions of quad.py used.
        f = GENZ[family]
        rng = np.random.default_rng([f, s, run, 37])
        a = rng.uniform(0, 1, s)
        a = a * GENZ_DIFFICULTY[f] / a.sum()
        u = rng.uniform(0, 1, s)
        return {"a": a, "u": u}
    rng = np.random.default_rng([FAMILY_INDEX[family], s, run, 41])
    if family == "ishigami":
        return {"a": rng.uniform(5, 9), "b": rng.uniform(0.05, 0.15)}
    if family == "keister":
        return {"s": s}
    if family == "lognormal":
        mu = rng.uniform(-0.5, 0.5, s)
        w = rng.uniform(0, 1, s)
        sigma = w * math.sqrt(LOGNORMAL_VARIANCE / np.sum(w * w))
        return {"mu": mu, "sigma": sigma}
    raise ValueError(family)


def normal(x):
    return ndtri(np.clip(x, EPS, 1.0 - EPS))


def value(family, p, x):
    if family in GENZ:
        return genz_value(GENZ[family], p["a"], p["u"], x)
    if family == "ishigami":
        z = np.pi * (2.0 * x - 1.0)
        s1 = np.sin(z[:, 0])
        return s1 + p["a"] * np.sin(z[:, 1]) ** 2 + p["b"] * z[:, 2] ** 4 * s1
    if family == "keister":
        s = x.shape[1]
        r = np.sqrt(np.sum(normal(x) ** 2, axis=1) / 2.0)
        return np.pi ** (s / 2) * np.cos(r)
    if family == "lognormal":
        return np.exp(normal(x) @ p["sigma"] + np.sum(p["mu"]))
    raise ValueError(family)


_KEISTER = {}


def keister_exact(s):
    """2π^{s/2}/Γ(s/2) ∫_0^∞ r^{s-1} cos(r) exp(-r²) dr (surface of the unit sphere times
    the radial integral)."""
    if s not in _KEISTER:
        def radial(r):
            if r == 0.0:
                return 1.0 if s == 1 else 0.0
            return math.exp((s - 1) * math.log(r) - r * r) * math.cos(r)

        val, _ = sintegrate.quad(radial, 0, np.inf, epsabs=0, epsrel=1e-13, limit=500)
        area = math.exp(math.log(2.0) + (s / 2) * math.log(math.pi) - gammaln(s / 2))
        _KEISTER[s] = area * val
    return _KEISTER[s]


def exact(family, p):
    if family in GENZ:
        return float(genz_exact(GENZ[family], p["a"], p["u"]))
    if family == "ishigami":
        return p["a"] / 2
    if family == "keister":
        return keister_exact(p["s"])
    if family == "lognormal":
        return float(np.exp(np.sum(p["mu"] + p["sigma"] ** 2 / 2)))
    raise ValueError(family)
