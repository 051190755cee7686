#!/usr/bin/env python3
"""Models benches/uq_models.py does not name, to check its verdicts on others: stillpoint's
randomised set under a space (`design(n, space, randomize=True)`; the CLI's
`generate --var ... --randomize` for the borehole) against SciPy's scrambled Sobol'
mapped through SciPy's ppf, RMSE over REPS randomisations each, n = 1 024 and 4 096.

  digital   1{mean(Z) > 0.3}, Z ~ N(0, I_8): a discontinuity; exact 1 − Φ(0.3·√8)
  corr_exp  exp(a·Y), Y normal with correlation 0.5 between every pair (s = 6, a_j =
            0.4/j; stillpoint through `correlation=`, Sobol' through the Cholesky
            factor); exact exp(aᵀCa/2)
  borehole  the borehole function (8 inputs: normal, lognormal, six uniform); reference
            8 scrambled Sobol' sets of 2^20 points

    REPS=32 target/py-venv/bin/python benches/uq_unnamed.py [digital corr_exp borehole]

With METHOD=default, stillpoint's deterministic default under the space instead
(`design(n, space, seed=k)`, no randomisation; the CLI without --randomize for the
borehole), its RMSE over the seeds k = 1 … SEEDS (default 8), beside "cube": the cube's
default `generate(n, d, seed=k)` through SciPy's ppf (the set the default under a space
mapped before the lattice with picked offsets took spaces of unbounded laws; the dealt
design is that set up to the dealing), and the same scrambled Sobol' RMSE.
"""
import math, subprocess, sys, os, numpy as np
from scipy import stats
from scipy.stats import qmc
import stillpoint as sp
REPS = int(os.environ.get("REPS", 32)); NS = [1024, 4096]
METHOD = os.environ.get("METHOD", "randomize"); SEEDS = int(os.environ.get("SEEDS", 8))
RANDOM = METHOD == "randomize"
BIN = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "target", "release", "stillpoint")
def sobol_cols(laws, n, r):
    u = np.clip(qmc.Sobol(len(laws), scramble=True, seed=90000 + r).random(n), 2**-53, 1 - 2**-53)
    return np.column_stack([l.ppf(u[:, j]) for j, l in enumerate(laws)])
def ours_py(space, n, r, corr=None):
    kw = {"correlation": corr} if corr is not None else {}
    kw.update(randomize=True, seed=5000 + r) if RANDOM else kw.update(seed=r + 1)
    d = sp.design(n, space, **kw)
    return np.column_stack([np.asarray(d.columns[k], float) for k in space]), d.rule
def ours_cli(texts, n, r):
    out = f"/tmp/uq_unnamed_{os.getpid()}_{n}_{r}.npy"
    args = [BIN, "generate", "-n", str(n), "-q", "-o", out]
    args += ["--randomize", "--seed", str(5000 + r)] if RANDOM else ["--seed", str(r + 1)]
    for t in texts: args += ["--var", t]
    subprocess.run(args, check=True, capture_output=True)
    return np.load(out)
s = 8; c = 0.3
digital = dict(space={f"z{j+1}": "normal(0,1)" for j in range(s)}, laws=[stats.norm()] * s,
               f=lambda X: (X.mean(1) > c).astype(float), exact=1 - stats.norm.cdf(c * math.sqrt(s)))
a = np.array([0.4 / (j + 1) for j in range(6)]); rho = 0.5
C = np.full((6, 6), rho) + (1 - rho) * np.eye(6)
corr_exp = dict(space={f"y{j+1}": "normal(0,1)" for j in range(6)}, laws=None, corr=C,
                f=lambda X: np.exp(X @ a), exact=math.exp(a @ C @ a / 2))
bh_texts = ["rw=normal(0.10,0.0161812)", "r=lognormal(7.71,1.0056)", "Tu=uniform(63070,115600)",
            "Hu=uniform(990,1110)", "Tl=uniform(63.1,116)", "Hl=uniform(700,820)",
            "L=uniform(1120,1680)", "Kw=uniform(9855,12045)"]
bh_laws = [stats.norm(0.10, 0.0161812), stats.lognorm(s=1.0056, scale=math.exp(7.71)),
           stats.uniform(63070, 115600 - 63070), stats.uniform(990, 120), stats.uniform(63.1, 116 - 63.1),
           stats.uniform(700, 120), stats.uniform(1120, 560), stats.uniform(9855, 12045 - 9855)]
def borehole(X):
    rw, r, Tu, Hu, Tl, Hl, L, Kw = X.T
    lr = np.log(r / rw)
    return 2 * np.pi * Tu * (Hu - Hl) / (lr * (1 + 2 * L * Tu / (lr * rw**2 * Kw) + Tu / Tl))
def bh_ref():
    v = [borehole(sobol_cols(bh_laws, 2**20, 777 + k)).mean() for k in range(8)]
    return float(np.mean(v)), float(np.std(v, ddof=1) / math.sqrt(8))
def cube_cols(laws, n, r, corr=None):
    """The cube's default from seed r + 1 through SciPy's ppf (correlated normals
    through the Cholesky factor)."""
    u = np.clip(np.asarray(sp.generate(n, len(laws), seed=r + 1)), 2**-53, 1 - 2**-53)
    x = np.column_stack([l.ppf(u[:, j]) for j, l in enumerate(laws)])
    return x if corr is None else x @ np.linalg.cholesky(corr).T
which = sys.argv[1:] or ["digital", "corr_exp", "borehole"]
OURS = range(REPS) if RANDOM else range(SEEDS)
for name in which:
    for n in NS:
        cube = None
        if name == "borehole":
            ex, se = bh_ref() if n == NS[0] else (ex, se)
            q = [borehole(ours_cli(bh_texts, n, r)).mean() for r in OURS]
            if not RANDOM:
                cube = [borehole(cube_cols(bh_laws, n, r)).mean() for r in OURS]
            qs = [borehole(sobol_cols(bh_laws, n, r)).mean() for r in range(REPS)]
            rule = "cli"
        else:
            m = digital if name == "digital" else corr_exp
            ex = m["exact"]; se = 0
            res = [ours_py(m["space"], n, r, m.get("corr")) for r in OURS]
            if not RANDOM:
                cube = [m["f"](cube_cols(m["laws"] or [stats.norm()] * 6, n, r, m.get("corr"))).mean()
                        for r in OURS]
            rule = res[0][1][:40]
            q = [m["f"](X).mean() for X, _ in res]
            if m["laws"] is None:  # correlated normals for Sobol': Cholesky of the scores
                Lc = np.linalg.cholesky(m["corr"])
                qs = [m["f"](sobol_cols([stats.norm()] * 6, n, r) @ Lc.T).mean() for r in range(REPS)]
            else:
                qs = [m["f"](sobol_cols(m["laws"], n, r)).mean() for r in range(REPS)]
        e1 = math.sqrt(np.mean((np.array(q) - ex) ** 2)); e2 = math.sqrt(np.mean((np.array(qs) - ex) ** 2))
        more = ""
        if cube is not None:
            e3 = math.sqrt(np.mean((np.array(cube) - ex) ** 2))
            more = f" cube {e3:.3g} ratio {e3/e2:.2f}"
        print(f"{name:9s} n={n:5d} exact {ex:.8g} (se {se:.1g}) {METHOD} RMSE {e1:.3g} Sobol' {e2:.3g} ratio {e1/e2:.2f}{more}  [{rule}]", flush=True)
