"""Coverage at a fixed n of quad's Bayesian lattice asked for by name on the families of
benches/quad_interval.py (not Keister's or the lognormal, which the face test sends to
the first-order lattice): SEEDS seeds, n = 1 024, 4 096, 16 384.

    SP_BAYES_TENT=1 target/py-venv/bin/python results/quad/bayes-tent/coverage.py SEEDS [CASES] [NS]

(SP_BAYES_TENT from bayes_tent.patch: the tent table with the tent.)
"""
import sys, os, math, warnings
import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "benches"))
import quad_interval as qi
import stillpoint as sp
warnings.simplefilter("ignore")
cases = qi.CASES + qi.CHECK_CASES
only = sys.argv[2].split(",") if len(sys.argv) > 2 and sys.argv[2] else None
seeds = int(sys.argv[1])
ns = [int(v) for v in (sys.argv[3] if len(sys.argv) > 3 else "1024,4096,16384").split(",")]
rule = os.environ.get("RULE", "bayesian lattice")
print("| case | n | coverage | median hw/err | median rel hw |")
for label, fam, s in cases:
    if fam in ("keister", "lognormal"): continue
    if only and not any(o in label for o in only): continue
    for n in ns:
        hits, w, rel = 0, [], []
        for seed in range(seeds):
            f, truth = qi.integrand(fam, s, seed)
            r = sp.quad(f, s, rule=rule, rel_tol=0, abs_tol=0, max_n=n, seed=seed)
            assert r.n == n, (r.n, n)
            err = abs(r.estimate - truth)
            hits += err <= r.half_width
            w.append(r.half_width / max(err, 1e-300)); rel.append(r.half_width / abs(truth))
        print(f"| {label} | {n} | {hits/seeds:.1%} | {np.median(w):.1f} | {np.median(rel):.2e} |", flush=True)
