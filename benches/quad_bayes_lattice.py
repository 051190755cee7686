"""Integration to a tolerance with one randomly shifted lattice of quad's extensible
sequence and a Bayesian cubature posterior on a shift-invariant kernel (the form of
QMCPy's CubBayesLatticeG), emulated in Python, against `stillpoint.quad`'s own runs and
the references of benches/quad.py (their JSONs in results/quad/, not rerun).

results/quad/single-tol.md measured the same doubling on one Owen-scrambled Sobol'
sequence with CubBayesNetG's posterior, whose order-1 Walsh kernel prices every
integrand as rough. On a rank-1 lattice the Gram matrix of a shift-invariant kernel is
circulant in the lattice's natural order, so its eigenvalues are one FFT, and the kernel
can be smooth: K(x, y) = prod_j (1 + theta * eta_r(frac(x_j - y_j))) with
eta_r(t) = sum_{h != 0} e^{2 pi i h t} / |h|^{2r} = (-1)^{r+1} (2 pi)^{2r} / (2r)! B_2r(t).

Per cell of benches/quad.py (family, s, relative tolerance; the instance ``run`` as
quad.py draws it for the references) and run:
- the points: quad's extensible lattice (the tent table of sequences/src/
  extensible_table.rs, benches/quad_rules.py) with one uniform shift drawn from the run,
  tent-transformed; n = 256, 512, ... up to 2^20, each doubling evaluating the new half;
- at each n: the posterior half-width at 99 % (theta by maximum likelihood on
  ln theta in [-5, 0], as bayes_bound) raised to the round change |Q_n - Q_{n/2}|;
  stop when it is <= tol * |Q_n|;
- forms ``lattice-r1`` and ``lattice-r2``: the kernel's order r = 1 or 2.
Reliability and evaluations as benches/quad.py defines them. The model families are
integrated on the cube through their laws' quantiles, as the references see them.

    nice -n 5 target/py-venv/bin/python benches/quad_bayes_lattice.py --runs 200 \\
        --cell-seconds 200 [--families ...] [--genz]
    target/py-venv/bin/python benches/quad_bayes_lattice.py --table

Writes results/quad/bayes-lattice/single-tol-lattice-r{1,2}.json.gz (benches/quad.py's
format).
"""

import argparse
import math
import os
import re
import sys
import warnings

import numpy as np
from scipy import special, stats

sys.path.insert(0, os.path.dirname(__file__))
import quad as bench  # noqa: E402
import quad_single_tol as single  # noqa: E402
from quad_single_study import mle_fit  # noqa: E402
from quad_models import FAMILIES as CUBE_FAMILIES  # noqa: E402
from quad_rules import BITS, generator, points  # noqa: E402

# form: (kernel order r, generating vector's table, tent transform)
FORMS = {"tent-r1": (1, "extensible_table.rs", True), "tent-r2": (2, "extensible_table.rs", True),
         "first-r1": (1, "engine_table.rs", False), "first-r2": (2, "engine_table.rs", False),
         "first-mle": ("mle", "engine_table.rs", False), "tent-mle": ("mle", "extensible_table.rs", True),
         "first-alpha": ("alpha", "engine_table.rs", False),
         "first-tent-alpha": ("alpha", "engine_table.rs", True)}
ALPHAS = (2.0, 2.5, 3.0, 3.5, 4.0)  # the kernel's decay |h|^-alpha chosen among these
_TABLES = {}


def table_vector(name, d):
    """The first d entries of a tabulated generating vector (sequences/src/NAME)."""
    if name not in _TABLES:
        with open(os.path.join(bench.ROOT, "sequences", "src", name)) as fh:
            text = fh.read()
        body = text[text.index("= [") + 3:text.index("];")]
        _TABLES[name] = np.array([int(v) for v in re.findall(r"\d+", body)], dtype=np.int64)
    return _TABLES[name][:d]


def lattice_points(z, shift, start, count, tent):
    """Points [start, start + count) of the extensible lattice with generator z (20 bits) in
    radical-inverse order, shifted, tent-transformed if asked."""
    k = np.arange(start, start + count, dtype=np.int64)
    j = reversed_bits(k, BITS)
    y = ((j[:, None] * z[None, :]) & ((1 << BITS) - 1)).astype(float) / (1 << BITS)
    y = (y + shift[None, :]) % 1.0
    return 1.0 - np.abs(2.0 * y - 1.0) if tent else y
Z99 = float(stats.norm.ppf(0.995))
N0 = 256
OUT = os.path.join(bench.ROOT, "results", "quad", "bayes-lattice")
VERSION = (" quad's tent lattice (benches/quad_rules.py), one shift, the posterior of a "
           "Bayesian cubature on a shift-invariant kernel (benches/quad_bayes_lattice.py)")


def eta(t, r):
    """sum_{h != 0} e^{2 pi i h t} / |h|^{2r}, through the Bernoulli polynomial B_2r; for a
    pair ("decay", alpha) the same with |h|^-alpha at t = k/n (t given as the integers k
    and n), by one FFT of the aliased coefficients (Hurwitz zeta)."""
    if isinstance(r, tuple):
        _, alpha, k, n = r
        q = np.arange(n) / n
        a = np.empty(n)
        a[0] = 2 * special.zeta(alpha)
        a[1:] = special.zeta(alpha, q[1:]) + special.zeta(alpha, 1 - q[1:])
        table = np.real(np.fft.fft(a)) * n ** -alpha
        return table[k]
    if r == 1:
        return 2 * math.pi ** 2 * (t * t - t + 1.0 / 6)
    if r == 2:
        return -(2 * math.pi ** 4 / 3) * (t ** 4 - 2 * t ** 3 + t * t - 1.0 / 30)
    raise ValueError(r)


def reversed_bits(k, m):
    j = np.zeros_like(k)
    for b in range(m):
        j |= ((k >> b) & 1) << (m - 1 - b)
    return j


def lattice_bound(y_nat, frac, r, z=Z99):
    """The posterior half-width ("MLE" form) of a Bayesian cubature on the values y_nat at
    the lattice points in natural order, frac the unshifted points frac(i z / n); with
    r = "mle" the order r in {1, 2} is chosen with theta by maximum likelihood."""
    if r == "mle":
        fits = [lattice_fit(y_nat, frac, order) for order in (1, 2)]
        return min(fits)[1] * z
    if r == "alpha":
        n = y_nat.size
        k = np.rint(frac * n).astype(np.int64)
        fits = [lattice_fit(y_nat, frac, ("decay", a, k, n)) for a in ALPHAS]
        return min(fits)[1] * z
    return lattice_fit(y_nat, frac, r)[1] * z


def lattice_fit(y_nat, frac, r):
    """(the negative log-likelihood at its optimum over theta, the posterior's standard
    deviation)."""
    n = y_nat.size
    e = eta(frac, r)
    ft = np.fft.fft(y_nat)

    def kernel(theta):
        km1 = theta * e[:, 0]
        k = 1 + km1
        for j in range(1, e.shape[1]):
            km1 = theta * e[:, j] * k + km1
            k = 1 + km1
        factor = float(np.max(np.abs(km1)))
        ring = np.real(np.fft.fft(km1 / factor))
        lam = ring.copy()
        lam[0] += n / factor
        return np.abs(lam), ring, factor

    return mle_fit(ft, kernel, n)


def walk(f, d, seed, tols, forms=tuple(FORMS)):
    """One run: the doubling on one shifted lattice; per (form, tol) the (estimate, n, met)
    at which it stopped (or at 2^20, not met)."""
    shift = np.random.default_rng([seed, 0x6c61]).random(d)
    # forms sharing a table and transform share their points and values
    rules = sorted({FORMS[f][1:] for f in forms})
    state = {rule: np.empty(0) for rule in rules}
    stops, n = {}, N0
    while True:
        idx = np.arange(n, dtype=np.int64)
        m = n.bit_length() - 1
        for rule in rules:
            table, tent = rule
            z = table_vector(table, d)
            y = state[rule]
            x = lattice_points(z, shift, y.size, n - y.size, tent)
            y = state[rule] = np.concatenate([y, np.asarray(f(x), dtype=float)])
            y_nat = y[reversed_bits(idx, m)]
            frac = ((idx[:, None] * (z % n)[None, :]) % n).astype(float) / n
            q = float(y.mean())
            change = abs(q - float(y[: n // 2].mean()))
            for form in forms:
                if FORMS[form][1:] != rule:
                    continue
                open_tols = [t for t in tols if (form, t) not in stops]
                if not open_tols:
                    continue
                hw = max(lattice_bound(y_nat, frac, FORMS[form][0]), change)
                for t in open_tols:
                    if hw <= t * abs(q):
                        stops[(form, t)] = (q, n, True)
                for t in tols:
                    last = (q, n, False)
                    state[("last", form, t)] = last
        if len(stops) == len(forms) * len(tols) or n >= bench.MAX_N:
            break
        n *= 2
    for form in forms:
        for t in tols:
            stops.setdefault((form, t), state[("last", form, t)])
    return stops


def check_lattice_order():
    """The natural order's points are frac(i z / n + shift) (a check of the indexing)."""
    d, n = 5, 1024
    shift = np.random.default_rng(1).random(d)
    x = points(d, shift, 0, n, tent=False)
    m = n.bit_length() - 1
    idx = np.arange(n, dtype=np.int64)
    nat = x[reversed_bits(idx, m)]
    zm = generator(d).astype(np.int64) % n
    want = (((idx[:, None] * zm[None, :]) % n) / n + shift) % 1.0
    return float(np.abs(nat - want).max())


def main():
    global OUT
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--families", default=",".join(bench.MODEL_FAMILIES))
    ap.add_argument("--genz", action="store_true")
    ap.add_argument("--s", default=None)
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--cell-seconds", type=float, default=0.0)
    ap.add_argument("--phase", type=int, choices=(1, 2), default=None)
    ap.add_argument("--forms", default=",".join(FORMS))
    ap.add_argument("--table", action="store_true")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--out", default=OUT)
    args = ap.parse_args()
    if args.check:
        print("largest difference of the natural order:", check_lattice_order())
        return
    OUT = args.out
    os.makedirs(OUT, exist_ok=True)
    single.OUT = OUT
    single.FORMS = {k: None for k in FORMS}
    single.walk = walk
    if args.table:
        single.table(args.runs)
        return
    fams = list(CUBE_FAMILIES) if args.genz else args.families.split(",")
    keep = None if args.s is None else set(args.s.split(","))
    groups = [(f, s) for f in fams for s in bench.FAMILIES[f]
              if keep is None or str(s) in keep]
    phases = single.PHASES if args.phase is None else single.PHASES[args.phase - 1:args.phase]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        single.measure(groups, args.runs, args.cell_seconds, phases, args.forms.split(","),
                       version=VERSION)


if __name__ == "__main__":
    main()
