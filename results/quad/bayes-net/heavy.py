"""Coverage at a fixed n of a rule of `stillpoint.quad` on heavy-tailed lognormal models
written on the cube: exp(c·Σ Φ⁻¹(x_j)) in d = 4 dimensions with total variance
4c² = 0.75, 1.5 and 3 (skewness about 4, 12 and 140), n = 1 024 and 4 096, 200 seeds:
the share of runs whose exact value e^(2c²) lies within the interval at level 0.95. Why
the Bayesian net keeps the skew gate of the Bayesian lattice (a first round skewed
beyond |γ̂| = 3 leaves for scrambled Sobol').

    target/py-venv/bin/python results/quad/bayes-net/heavy.py "bayesian net" 200
    target/py-venv/bin/python results/quad/bayes-net/heavy.py sobol 200
"""
import math
import sys

import numpy as np
from scipy import stats

import stillpoint as sp

rule = sys.argv[1] if len(sys.argv) > 1 else "bayesian net"
seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 200
d = 4
for var in [0.75, 1.5, 3.0]:
    c = math.sqrt(var / d)
    truth = math.exp(var / 2)
    for n in [1024, 4096]:
        hits = 0
        for seed in range(seeds):
            r = sp.quad(lambda x, c=c: np.exp(c * stats.norm.ppf(x).sum(axis=1)), d,
                        rule=rule, rel_tol=0, max_n=n, seed=seed)
            hits += abs(r.estimate - truth) <= r.half_width
        print(f"{rule}: variance {var}, n = {n}: coverage {hits / seeds:.3f}", flush=True)
