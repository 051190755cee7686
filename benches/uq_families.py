"""The model families of benches/uq_models.py: input laws, a function of the inputs,
parameters drawn per instance and the reference value per instance.

A family is an object with

    variants              the variants measured (a dimension s, or (m, construction))
    params(v, rng)        the random parameters of one instance of variant v
    laws(v, p)            the input laws: a list of (NAME, (kind, a, b)), kind one of
                          'normal', 'lognormal', 'uniform' (stillpoint's --var types)
    prepare(v, X, is_path) work shared by every instance on one set (a path from normals)
    value(v, p, P)        f at the prepared inputs P, shape (n,)
    exact(v, p)           the integral in closed form, or None (then a long run)
    ref_key(v, i)         the key of the instance's reference (path families share it
                          between constructions: the expectation does not depend on how
                          the path is built)

Every law is written twice from the same tuple: as a stillpoint space text
(``law_text``) and as a map from the unit cube (``law_map``, Φ⁻¹ of x clipped to
[2^-53, 1 - 2^-53] as benches/quad_models.py does), so the peers and stillpoint integrate
the same laws.

Path families take m standard normals Z_1..Z_m and build W(t_1..t_m) of a Brownian
motion on [0, T] inside ``prepare`` (standard: cumulative sums; bridge: Brownian-bridge
order; pca: the eigenvectors of min(t_i, t_j)). HOOK: with ``path_space='brownian'``
their space is the single variable ``W=brownian(T,m,construction)`` (columns W_1..W_m,
already a path), and ``prepare`` leaves the stillpoint columns as they are; the peers'
map still builds the path from normals.
"""

import math
import os
import sys

import numpy as np
from scipy.special import ndtr

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from quad_models import keister_exact, normal  # noqa: E402

UQ_SEED = 20261145  # the instances' seed, used nowhere else in this repository


# ---------------------------------------------------------------- laws

def law_text(name, law):
    if law[0] == "brownian":  # HOOK: ("brownian", T, m, construction)
        return f"{name}=brownian({float(law[1])!r},{law[2]},{law[3]})"
    kind, a, b = law
    return f"{name}={kind}({float(a)!r},{float(b)!r})"


def law_map(law, u):
    kind, a, b = law
    if kind == "uniform":
        return a + (b - a) * u
    if kind == "normal":
        return a + b * normal(u)
    if kind == "lognormal":
        return np.exp(a + b * normal(u))
    raise ValueError(kind)


def map_cube(laws, u):
    """The peers' map: column j of the unit-cube set through law j's quantile."""
    return np.column_stack([law_map(law, u[:, j]) for j, (_, law) in enumerate(laws)])


def perturb(law, rng):
    """A law near the nominal one, per instance (the UQ user's inputs are not textbook
    constants): a uniform range moved by up to a tenth of its width, a (log-)normal's
    location by up to half its scale and its scale by 0.8–1.2."""
    kind, a, b = law
    d = rng.uniform(-1.0, 1.0)
    if kind == "uniform":
        w = b - a
        return (kind, a + 0.1 * d * w, b + 0.1 * d * w)
    return (kind, a + 0.5 * d * b, b * rng.uniform(0.8, 1.2))


# ---------------------------------------------------------------- base class

class Family:
    name = ""
    variants = []
    fixed_laws = True  # the laws do not depend on the instance (one default set serves all)

    def prepare(self, v, X, is_path=False):
        return X

    def space_laws(self, v, p, path_space="normals"):
        """The laws stillpoint is given (path families: see the module's HOOK)."""
        return self.laws(v, p)

    def exact(self, v, p):
        return None

    def ref_key(self, v, i):
        return f"{self.name}|{v}|{i}"

    def dim(self, v):
        return len(self.laws(v, self.params(v, np.random.default_rng(0))))

    def label(self, v):
        return f"s = {v}"


class Keister(Family):
    """∫ cos‖t‖ e^{-‖t‖²} dt = E[π^{s/2} cos‖T‖], T ~ N(0, I/2). No parameters."""
    name = "keister"
    variants = [2, 5, 10, 20]

    def params(self, s, rng):
        return {}

    def laws(self, s, p):
        return [(f"t{j + 1}", ("normal", 0.0, math.sqrt(0.5))) for j in range(s)]

    def value(self, s, p, X):
        return np.pi ** (s / 2) * np.cos(np.sqrt(np.sum(X * X, axis=1)))

    def exact(self, s, p):
        return keister_exact(s)


class GenzOscNormal(Family):
    """cos(c + a·X), X ~ N(0, I): E = cos(c) exp(-|a|²/2). a_j ∝ U[0,1] with |a| = 1.5;
    c ~ U[-π/3, π/3] (|cos c| ≥ 1/2, so the relative error is not divided by ~0)."""
    name = "genz oscillatory (normal)"
    variants = [2, 5, 10, 20]

    def params(self, s, rng):
        a = rng.uniform(0, 1, s)
        return {"a": a * 1.5 / np.linalg.norm(a), "c": rng.uniform(-np.pi / 3, np.pi / 3)}

    def laws(self, s, p):
        return [(f"x{j + 1}", ("normal", 0.0, 1.0)) for j in range(s)]

    def value(self, s, p, X):
        return np.cos(p["c"] + X @ p["a"])

    def exact(self, s, p):
        return math.cos(p["c"]) * math.exp(-0.5 * float(p["a"] @ p["a"]))


class GenzGaussNormal(Family):
    """exp(-Σ a_j² (X_j - u_j)²), X ~ N(0, I): E = Π (1 + 2a_j²)^{-1/2}
    exp(-a_j² u_j² / (1 + 2a_j²)). a_j ∝ U[0,1] with Σa_j² = 2, u_j ~ U[-1, 1]."""
    name = "genz gaussian (normal)"
    variants = [2, 5, 10, 20]

    def params(self, s, rng):
        a = rng.uniform(0, 1, s)
        return {"a": a * math.sqrt(2.0) / np.linalg.norm(a), "u": rng.uniform(-1, 1, s)}

    def laws(self, s, p):
        return [(f"x{j + 1}", ("normal", 0.0, 1.0)) for j in range(s)]

    def value(self, s, p, X):
        return np.exp(-((X - p["u"]) ** 2) @ (p["a"] ** 2))

    def exact(self, s, p):
        a2 = p["a"] ** 2
        return float(np.prod((1 + 2 * a2) ** -0.5 * np.exp(-a2 * p["u"] ** 2 / (1 + 2 * a2))))


class LognormalProduct(Family):
    """Π X_j, X_j ~ lognormal(μ_j, σ_j): E = Π exp(μ_j + σ_j²/2). μ_j ~ U[-0.5, 0.5],
    σ_j ∝ U[0, 1] with Σσ_j² = 0.25 (quad_models.py's)."""
    name = "lognormal product"
    variants = [5, 10, 20, 50]
    fixed_laws = False

    def params(self, s, rng):
        w = rng.uniform(0, 1, s)
        return {"mu": rng.uniform(-0.5, 0.5, s), "sigma": w * math.sqrt(0.25 / np.sum(w * w))}

    def laws(self, s, p):
        return [(f"x{j + 1}", ("lognormal", p["mu"][j], p["sigma"][j])) for j in range(s)]

    def value(self, s, p, X):
        return np.prod(X, axis=1)

    def exact(self, s, p):
        return float(np.exp(np.sum(p["mu"] + p["sigma"] ** 2 / 2)))


class MorokoffCaflisch(Family):
    """Π (1 + q_j) X_j^{q_j}, X uniform on [0,1]^s, q_j ∝ U[0.5, 1.5] with Σq_j = 1
    (q_j = 1/s is Morokoff and Caflisch's f = (1 + 1/s)^s Π x_j^{1/s}): E = 1."""
    name = "morokoff-caflisch"
    variants = [5, 10, 20]

    def params(self, s, rng):
        q = rng.uniform(0.5, 1.5, s)
        return {"q": q / q.sum()}

    def laws(self, s, p):
        return [(f"x{j + 1}", ("uniform", 0.0, 1.0)) for j in range(s)]

    def value(self, s, p, X):
        return np.exp(np.log(np.maximum(X, 1e-300)) @ p["q"] + np.sum(np.log1p(p["q"])))

    def exact(self, s, p):
        return 1.0


class Ishigami(Family):
    """sin x1 + a sin² x2 + b x3⁴ sin x1, x_j uniform on [-π + c_j, π + e_j],
    a ~ U[5, 9], b ~ U[0.05, 0.15], c_j, e_j ~ U[-0.5, 0.5] (on [-π, π]^3, a full period,
    lattice rules integrate the sines exactly and a tent-transformed one, symmetric,
    the whole function to the last bit):
    E = m1 + a m2 + b m4 m1 with m1 = E sin x1, m2 = E sin² x2, m4 = E x3⁴ over the
    ranges."""
    name = "ishigami"
    variants = [3]
    fixed_laws = False

    def params(self, s, rng):
        return {"a": rng.uniform(5, 9), "b": rng.uniform(0.05, 0.15),
                "c": rng.uniform(-0.5, 0.5, 3), "e": rng.uniform(-0.5, 0.5, 3)}

    def laws(self, s, p):
        return [(f"x{j + 1}", ("uniform", -math.pi + p["c"][j], math.pi + p["e"][j]))
                for j in range(3)]

    def value(self, s, p, X):
        s1 = np.sin(X[:, 0])
        return s1 + p["a"] * np.sin(X[:, 1]) ** 2 + p["b"] * X[:, 2] ** 4 * s1

    def exact(self, s, p):
        (l1, h1), (l2, h2), (l3, h3) = [(-math.pi + c, math.pi + e)
                                        for c, e in zip(p["c"], p["e"])]
        m1 = (math.cos(l1) - math.cos(h1)) / (h1 - l1)
        m2 = 0.5 - (math.sin(2 * h2) - math.sin(2 * l2)) / (4 * (h2 - l2))
        m4 = (h3 ** 5 - l3 ** 5) / (5 * (h3 - l3))
        return m1 + p["a"] * m2 + p["b"] * m4 * m1


class SobolG(Family):
    """Π (|4X_j - 2| + a_j)/(1 + a_j), X uniform on [0,1]^s, a_j = (j - 1)/2 + U[0, 1]
    (the first inputs matter most): E = 1."""
    name = "sobol g"
    variants = [6, 10, 20]

    def params(self, s, rng):
        return {"a": np.arange(s) / 2.0 + rng.uniform(0, 1, s)}

    def laws(self, s, p):
        return [(f"x{j + 1}", ("uniform", 0.0, 1.0)) for j in range(s)]

    def value(self, s, p, X):
        return np.prod((np.abs(4 * X - 2) + p["a"]) / (1 + p["a"]), axis=1)

    def exact(self, s, p):
        return 1.0


class Engineering(Family):
    """An engineering formula with mixed input laws; each instance perturbs the nominal
    laws (``perturb``); the reference is a long run."""
    fixed_laws = False
    variants = [0]
    nominal = []

    def dim(self, v):
        return len(self.nominal)

    def label(self, v):
        return f"s = {len(self.nominal)}"

    def params(self, v, rng):
        return {"laws": [(name, perturb(law, rng)) for name, law in self.nominal]}

    def laws(self, v, p):
        return p["laws"]

    def ref_key(self, v, i):
        return f"{self.name}|{i}"


class WingWeight(Engineering):
    """The light aircraft wing weight (Forrester et al. 2008), 10 inputs."""
    name = "wing weight"
    nominal = [
        ("Sw", ("normal", 175.0, 8.0)), ("Wfw", ("uniform", 220.0, 300.0)),
        ("A", ("uniform", 6.0, 10.0)), ("Lam", ("uniform", -10.0, 10.0)),
        ("q", ("lognormal", math.log(30.0), 0.15)), ("lam", ("uniform", 0.5, 1.0)),
        ("tc", ("normal", 0.13, 0.01)), ("Nz", ("normal", 4.25, 0.4)),
        ("Wdg", ("lognormal", math.log(2100.0), 0.06)), ("Wp", ("uniform", 0.025, 0.08)),
    ]

    def value(self, v, p, X):
        Sw, Wfw, A, Lam, q, lam, tc, Nz, Wdg, Wp = X.T
        c = np.cos(np.radians(Lam))
        return (0.036 * Sw ** 0.758 * Wfw ** 0.0035 * (A / c ** 2) ** 0.6 * q ** 0.006
                * lam ** 0.04 * (100 * tc / c) ** -0.3 * (Nz * Wdg) ** 0.49 + Sw * Wp)


class Piston(Engineering):
    """The piston's cycle time (Kenett and Zacks 1998), 7 inputs."""
    name = "piston"
    nominal = [
        ("M", ("lognormal", math.log(45.0), 0.15)), ("S", ("uniform", 0.005, 0.020)),
        ("V0", ("uniform", 0.002, 0.010)), ("k", ("lognormal", math.log(3000.0), 0.25)),
        ("P0", ("normal", 100000.0, 3000.0)), ("Ta", ("normal", 293.0, 1.0)),
        ("T0", ("normal", 350.0, 3.0)),
    ]

    def value(self, v, p, X):
        M, S, V0, k, P0, Ta, T0 = X.T
        A = P0 * S + 19.62 * M - k * V0 / S
        V = S / (2 * k) * (np.sqrt(A * A + 4 * k * P0 * V0 * Ta / T0) - A)
        return 2 * np.pi * np.sqrt(M / (k + S * S * P0 * V0 * Ta / (T0 * V * V)))


class OTLCircuit(Engineering):
    """The output transformerless push-pull circuit's midpoint voltage (Ben-Ari and
    Steinberg 2007), 6 inputs."""
    name = "otl circuit"
    nominal = [
        ("Rb1", ("normal", 100.0, 10.0)), ("Rb2", ("normal", 47.5, 4.0)),
        ("Rf", ("uniform", 0.5, 3.0)), ("Rc1", ("uniform", 1.2, 2.5)),
        ("Rc2", ("uniform", 0.25, 1.2)), ("beta", ("lognormal", math.log(150.0), 0.3)),
    ]

    def value(self, v, p, X):
        Rb1, Rb2, Rf, Rc1, Rc2, beta = X.T
        Vb1 = 12 * Rb2 / (Rb1 + Rb2)
        bc = beta * (Rc2 + 9)
        den = bc + Rf
        return (Vb1 + 0.74) * bc / den + 11.35 * Rf / den + 0.74 * Rf * bc / (den * Rc1)


class RobotArm(Engineering):
    """The distance of a four-segment robot arm's end from the origin (An and Owen
    2001), 8 inputs: angles uniform, segment lengths lognormal."""
    name = "robot arm"
    nominal = ([(f"th{j + 1}", ("uniform", 0.0, 2 * math.pi)) for j in range(4)]
               + [(f"L{j + 1}", ("lognormal", math.log(0.5), 0.2)) for j in range(4)])

    def value(self, v, p, X):
        ang = np.cumsum(X[:, :4], axis=1)
        L = X[:, 4:]
        return np.hypot(np.sum(L * np.cos(ang), axis=1), np.sum(L * np.sin(ang), axis=1))


# ---------------------------------------------------------------- paths

def path_matrix(m, T, construction):
    """A with W = Z A^T for Z standard normal rows: W(t_1..t_m), t_j = jT/m."""
    t = T * np.arange(1, m + 1) / m
    if construction == "standard":
        return math.sqrt(T / m) * np.tril(np.ones((m, m)))
    if construction == "pca":
        lam, vec = np.linalg.eigh(np.minimum.outer(t, t))
        order = np.argsort(lam)[::-1]
        return vec[:, order] * np.sqrt(np.maximum(lam[order], 0.0))
    if construction == "bridge":
        # Column k of A is the path made from the k-th normal alone: the end point first,
        # then the midpoints of ever finer intervals (the bridge's conditional laws).
        A = np.zeros((m, m))
        t0 = np.concatenate([[0.0], t])
        A[m - 1, 0] = math.sqrt(T)  # rows 1..m of the path with W(0) = 0 implicit
        k = 1
        intervals = [(0, m)]  # indices into t0: W(t0[lo]) and W(t0[hi]) known
        while intervals:
            nxt = []
            for lo, hi in intervals:
                if hi - lo < 2:
                    continue
                mid = (lo + hi) // 2
                wl = (t0[hi] - t0[mid]) / (t0[hi] - t0[lo])
                wr = (t0[mid] - t0[lo]) / (t0[hi] - t0[lo])
                sd = math.sqrt((t0[mid] - t0[lo]) * (t0[hi] - t0[mid]) / (t0[hi] - t0[lo]))
                left = A[lo - 1] if lo > 0 else 0.0
                A[mid - 1] = wl * left + wr * A[hi - 1]
                A[mid - 1, k] += sd
                k += 1
                nxt += [(lo, mid), (mid, hi)]
            intervals = nxt
        assert k == m, (k, m)
        return A
    raise ValueError(construction)


_PATHS = {}


def cached_path_matrix(m, T, construction):
    key = (m, T, construction)
    if key not in _PATHS:
        _PATHS[key] = path_matrix(m, T, construction)
    return _PATHS[key]


def geometric_call(logmean, logvar, K, disc):
    """disc · E[(G - K)^+] for log G ~ N(logmean, logvar)."""
    sd = math.sqrt(logvar)
    d1 = (logmean - math.log(K) + logvar) / sd
    return disc * (math.exp(logmean + logvar / 2) * ndtr(d1) - K * ndtr(d1 - sd))


class PathOption(Family):
    """An arithmetic-average call on `assets` correlated assets (one: the Asian option;
    four: the basket), each a geometric Brownian motion observed at k = m/assets equal
    steps on [0, 1]: e^{-rT} (Σ_a w_a mean_j S_a(t_j) - K)^+. Per instance σ_a ~
    U[0.2, 0.5], r ~ U[0, 0.05], K ~ 100·U[0.9, 1.1], S_a(0) = 100, equal weights,
    equicorrelation ρ ~ U[0.2, 0.6]. The geometric average's call has a closed form (log G
    is normal) and is the control variate of the long-run reference. Coordinates: Z
    column j·assets + a is the j-th normal of asset a, so the bridge's and the PCA's
    leading normals come first for every asset."""
    T = 1.0
    S0 = 100.0

    def __init__(self, name, assets, ms):
        self.name = name
        self.assets = assets
        self.variants = [(m, c) for m in ms for c in ("standard", "bridge", "pca")]

    def label(self, v):
        return f"m = {v[0]}, {v[1]}"

    def dim(self, v):
        return v[0]

    def ref_key(self, v, i):
        return f"{self.name}|m={v[0]}|{i}"

    def params(self, v, rng):
        A = self.assets
        return {"sigma": rng.uniform(0.2, 0.5, A), "r": rng.uniform(0.0, 0.05),
                "K": self.S0 * rng.uniform(0.9, 1.1),
                "rho": rng.uniform(0.2, 0.6) if A > 1 else 0.0}

    def laws(self, v, p):
        return [(f"Z{j + 1}", ("normal", 0.0, 1.0)) for j in range(v[0])]

    def space_laws(self, v, p, path_space="normals"):
        if path_space == "brownian":  # HOOK: each asset's path one variable of the space
            m, construction = v
            k = m // self.assets
            return [(f"W{a + 1}" if self.assets > 1 else "W",
                     ("brownian", self.T, k, construction)) for a in range(self.assets)]
        return self.laws(v, p)

    def prepare(self, v, X, is_path=False):
        """The independent paths B, shape (n, assets, k): from normals by the
        construction, or (brownian space) the columns as they are."""
        m, construction = v
        A, k = self.assets, m // self.assets
        n = X.shape[0]
        if X.shape[1] != m:
            raise ValueError(f"expected {m} columns, got {X.shape[1]}")
        if is_path:  # columns W_1..W_k of each asset's variable in turn
            return X.reshape(n, A, k)
        Z = X.reshape(n, k, A).transpose(0, 2, 1)  # (n, assets, k): asset a's normals
        M = cached_path_matrix(k, self.T, construction)
        return Z @ M.T

    def _corr(self, p):
        A = self.assets
        C = np.full((A, A), p["rho"]) + (1 - p["rho"]) * np.eye(A)
        return np.linalg.cholesky(C)

    def payoffs(self, v, p, B):
        """(arithmetic, geometric) discounted payoffs on the prepared paths."""
        A, k = self.assets, v[0] // self.assets
        t = self.T * np.arange(1, k + 1) / k
        W = np.einsum("ab,nbk->nak", self._corr(p), B) if A > 1 else B
        sig = p["sigma"][None, :, None]
        logS = math.log(self.S0) + (p["r"] - sig ** 2 / 2) * t + sig * W
        disc = math.exp(-p["r"] * self.T)
        arith = np.exp(logS).mean(axis=(1, 2))
        geo = np.exp(logS.mean(axis=(1, 2)))
        return disc * np.maximum(arith - p["K"], 0.0), disc * np.maximum(geo - p["K"], 0.0)

    def value(self, v, p, B):
        return self.payoffs(v, p, B)[0]

    def geometric_exact(self, v, p):
        A, k = self.assets, v[0] // self.assets
        t = self.T * np.arange(1, k + 1) / k
        vbar = float(np.minimum.outer(t, t).mean())  # Var(mean_j W(t_j))
        w = np.full(A, 1.0 / A)
        C = self._corr(p) @ self._corr(p).T
        ws = w * p["sigma"]
        logmean = float(np.sum(w * (math.log(self.S0) + (p["r"] - p["sigma"] ** 2 / 2)
                                    * t.mean())))
        logvar = float(ws @ C @ ws) * vbar
        return geometric_call(logmean, logvar, p["K"], math.exp(-p["r"] * self.T))


FAMILIES = [
    Keister(), GenzOscNormal(), GenzGaussNormal(), LognormalProduct(), MorokoffCaflisch(),
    Ishigami(), SobolG(), WingWeight(), Piston(), OTLCircuit(), RobotArm(),
    PathOption("asian call", 1, [32, 64, 256]),
    PathOption("basket asian call", 4, [32, 64, 256]),
]
BY_NAME = {f.name: f for f in FAMILIES}


def instance(family, v, i):
    """Instance i of variant v: its own generator, keyed by the family, the variant's
    dimension and i (so a path family's constructions share their instances)."""
    idx = [f.name for f in FAMILIES].index(family.name)
    return family.params(v, np.random.default_rng([UQ_SEED, idx, family.dim(v), i]))
