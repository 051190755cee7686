"""Coverage at a fixed n of `stillpoint.quad`'s Bayesian rules (``rule="bayesian lattice"``,
the rule the probe chooses under unbounded laws for an f even in them or flat at the faces;
``--rule "bayesian net"``, the one for an f steep at a face): per model and n, over seeds
(instance ``seed`` of benches/quad.py's family, a model family through its laws or a cube
family such as ``lognormal``, or a fixed model; the rule's randomisation from ``seed``),
the share of runs whose exact value lies within the interval at level 0.95, and the
median half-width over the true error. Each run is ``quad(f, d, space=..., rule=RULE,
rel_tol=0, max_n=n, seed=seed)``: no tolerance, so it stops at exactly n points.

    target/py-venv/bin/python benches/quad_bayes_coverage.py --seeds 300 --n 1024,4096,16384
        [--models "uq keister:5,uq keister:10,uq gaussian (normal):8"] [--unnamed]
        [--rule "bayesian net"]

``--unnamed`` adds five models of eight standard normal inputs the rule was not chosen on;
``--heavy`` three lognormal models of heavier tails written on the cube, exp(c·Σ Φ⁻¹(x_j))
in four dimensions of total variance 4c² = 0.75, 1.5 and 3 (skewness about 4, 12 and
140; why the Bayesian rules leave a skewed first round for Sobol'):

    target/py-venv/bin/python benches/quad_bayes_coverage.py --models "" --heavy \
        --seeds 200 --n 1024,4096 --rule "bayesian net"      (and --rule sobol)
``--level 0.875`` asks for the interval whose posterior quantile is 0.975, the posterior's
own 95 % (the rule takes the quantile at 1 − (1 − level)/5); coverage is then still
counted against 0.95.
"""

import argparse
import math
import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import quad as bench  # noqa: E402

D = 8
UNNAMED = {
    "Σz²": (lambda z: (z ** 2).sum(axis=1), D),
    "exp(−|z|²/8)": (lambda z: np.exp(-(z ** 2).sum(axis=1) / 8), (1 + 2 / 8) ** (-D / 2)),
    "cos(Σz/3)": (lambda z: np.cos(z.sum(axis=1) / 3), math.exp(-D / 18)),
    "Π(1 + z²/10)": (lambda z: np.prod(1 + z ** 2 / 10, axis=1), 1.1 ** D),
    "exp(−|z − ½|²/4)": (lambda z: np.exp(-((z - 0.5) ** 2).sum(axis=1) / 4),
                         (1.5 ** -0.5 * math.exp(-0.25 / 6)) ** D),
}


HEAVY_D = 4


def heavy(variance):
    """exp(c·Σ Φ⁻¹(x_j)) on the cube in HEAVY_D dimensions, 4c² = variance: (f, exact)."""
    from scipy.special import ndtri

    c = math.sqrt(variance / HEAVY_D)
    return (lambda x: np.exp(c * ndtri(x).sum(axis=1))), math.exp(variance / 2)


def cell(make, n, seeds, level, rule):
    import stillpoint as sp

    hits, widths = 0, []
    for seed in range(seeds):
        f, d, space, truth = make(seed)
        r = sp.quad(f, d, space=space, rule=rule, rel_tol=0, max_n=n,
                    seed=seed, level=level)
        assert r.n == n, (r.n, n)
        err = abs(r.estimate - truth)
        hits += err <= r.half_width
        widths.append(r.half_width / max(err, 1e-300))
    return hits / seeds, float(np.median(widths))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", default="uq keister:5,uq keister:10,uq gaussian (normal):8")
    ap.add_argument("--unnamed", action="store_true")
    ap.add_argument("--n", default="1024,4096,16384")
    ap.add_argument("--seeds", type=int, default=300)
    ap.add_argument("--level", type=float, default=0.95)
    ap.add_argument("--rule", default="bayesian lattice")
    ap.add_argument("--heavy", action="store_true")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    makers = {}
    for spec in filter(None, args.models.split(",")):
        family, s = spec.rsplit(":", 1)

        def make(seed, family=family, s=int(s)):
            if family not in bench.MODEL_FAMILIES:
                p = bench.instance(family, s, seed)
                return (lambda x: bench.value(family, p, x)), s, None, bench.exact(family, p)
            _, texts, on_values, truth = bench.model(family, s, seed)
            return on_values, s, texts, truth

        makers[f"{family} s={s}"] = make
    if args.unnamed:
        laws = [f"z{i}=normal(0,1)" for i in range(D)]
        for name, (g, truth) in UNNAMED.items():
            makers[name] = lambda seed, g=g, truth=truth: (g, D, laws, truth)
    if args.heavy:
        for variance in [0.75, 1.5, 3.0]:
            g, truth = heavy(variance)
            makers[f"exp(c·ΣΦ⁻¹), variance {variance}"] = (
                lambda seed, g=g, truth=truth: (g, HEAVY_D, None, truth))
    print("| model | n | coverage at 0.95 | median half-width / error |")
    print("|---|---|---|---|")
    for name, make in makers.items():
        for n in [int(v) for v in args.n.split(",")]:
            cover, width = cell(make, n, args.seeds, args.level, args.rule)
            print(f"| {name} | {n} | {cover:.1%} | {width:.1f} |", flush=True)


if __name__ == "__main__":
    main()
