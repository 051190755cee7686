#!/usr/bin/env python3
"""Candidate randomised unit-cube sets for spaces with input laws, measured on the cells
of the benchmark of models users bring (results/uq-models) against the scrambled Sobol'
RMSE stored there (same instances, same references): the prototype that chose the rule
of `stillpoint::pipeline::measure::cube_rule` (results/law-lattice/rules-by-law.md).

Every candidate's set goes through the peers' map (each law's quantile at u clipped to
[2^-53, 1 - 2^-53]); RMSE over the stored cell's instances and REPS randomisations,
divided by the stored scrambled Sobol' RMSE.

    cur         the cube's tent lattice (`stillpoint generate -n N -s D --randomize`)
    odd_dup     the cube's tent lattice of n - 1 points (odd) and one of its points again
    odd_only    the cube's tent lattice of n - 1 points alone (not n points: a bound)
    law_halves  the lattice made for the laws (`_core.law_set`: two odd lattices for
                even n)
    law_pq      the lattice made for the laws as two prime-sized lattices adding to n
    law_odd     the lattice made for the laws at n - 1 points alone (a bound)
    law_odd_dup the same and one of its points again
    sobol_fresh SciPy's scrambled Sobol' with other seeds: the noise of the stored
                denominator (its ratio would be 1 with exact RMSEs)
    owen        Owen-scrambled Sobol' (`stillpoint baseline sobol --seed`)
    eng_seq     `Engine(d, seed=...).random(n)`: the engine's default (the sequence)
    eng_ind     `Engine(d, seed=..., draws='independent').random(n)`: the tent lattice
                made for n, shifted and folded
    law_wG      prototype (NumPy): the lattice for the laws as two odd halves for even
                n, every coordinate scored with the first-order kernel at weight G
    even_wG     the same as one lattice of n points (measured where a bounded law takes
                part and not taken: results/law-lattice/rules-by-law.md)

Run (the bench venv of benches/uq_models.py, the CLI built in target/release):

    REPS=12 NS=1024,4096 CANDS=cur,law_halves target/bench-venv/bin/python benches/uq_rules.py
    (FAM=keister,lognormal: only those families)
"""
import json, math, os, subprocess, sys, hashlib
import numpy as np
HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import uq_models as U
from uq_families import BY_NAME, instance, map_cube

BIN = os.path.join(ROOT, "target", "release", "stillpoint")
CACHE = os.path.join(ROOT, "target", "uq-rules-sets")
os.makedirs(CACHE, exist_ok=True)
REPS = int(os.environ.get("REPS", 8))
NS = [int(x) for x in os.environ.get("NS", "1024,4096").split(",")]
FAM = os.environ.get("FAM")
CANDS = os.environ.get("CANDS", "cur,odd_dup").split(",")

def cli(n, d, seed):
    p = f"{CACHE}/t_{n}_{d}_{seed}.npy"
    if not os.path.exists(p):
        subprocess.run([BIN, "generate", "-n", str(n), "-s", str(d), "--randomize", "--seed",
                        str(seed), "-q", "-o", p], check=True, capture_output=True)
    return np.load(p)

def law(texts, n, seed):
    import stillpoint
    return np.asarray(stillpoint._core.law_set(list(texts), n, seed))

def isprime(m):
    return m > 1 and all(m % k for k in range(2, int(m ** .5) + 1))
def pq(n):
    for d in range(0, n):
        a, b = n // 2 - d, n - n // 2 + d
        if isprime(a) and isprime(b):
            return a, b
def dup(x, seed):
    k = np.random.default_rng(seed).integers(len(x))
    return np.vstack([x, x[k][None]])

def owen(n, d, seed):
    p = f"{CACHE}/o_{n}_{d}_{seed}.npy"
    if not os.path.exists(p):
        subprocess.run([BIN, "baseline", "sobol", "-n", str(n), "-s", str(d), "--seed",
                        str(seed), "-o", p], check=True, capture_output=True)
    return np.load(p)

_Z = {}
def cbc_b2(m, s, g):
    """Component-by-component vector for the first-order kernel 2π²B2, weight g."""
    if (m, s, g) not in _Z:
        k = np.arange(m); x = k / m; om = 2 * np.pi ** 2 * (x * x - x + 1 / 6)
        cand = np.array([c for c in range(1, m // 2 + 1) if math.gcd(c, m) == 1])
        prod = 1 + g * om; z = [1]
        for j in range(1, s):
            best, bv = None, np.inf
            for c0 in range(0, len(cand), 64):
                cc = cand[c0:c0 + 64]
                vals = ((1 + g * om[np.outer(cc, k) % m]) * prod).sum(1)
                i = int(np.argmin(vals))
                if vals[i] < bv:
                    bv, best = vals[i], int(cc[i])
            z.append(best); prod = prod * (1 + g * om[(k * best) % m])
        _Z[(m, s, g)] = np.array(z)
    return _Z[(m, s, g)]

def halves_w(n, d, g, seed, whole=False):
    parts = [n] if n % 2 or whole else ([n // 2, n // 2] if (n // 2) % 2 else [n // 2 - 1, n // 2 + 1])
    rng = np.random.default_rng(seed)
    out = []
    for m in parts:
        z = cbc_b2(m, d, g)
        x = (np.outer(np.arange(m), z) % m) / m
        x = (x + rng.random(d)) % 1.0
        out.append(1 - np.abs(2 * x - 1))
    return np.vstack(out)

def make(cand, fam, v, p, n, d, r):
    seed = 1000 + r
    if cand == "cur":
        return cli(n, d, seed)
    if cand == "odd_dup":
        return dup(cli(n - 1, d, seed), seed) if n % 2 == 0 else cli(n, d, seed)
    if cand == "odd_only":
        return cli(n - 1 if n % 2 == 0 else n, d, seed)
    if cand == "law_halves":
        texts = [U.law_text(nm, l) for nm, l in fam.laws(v, p)]
        return law(texts, n, seed)
    if cand == "law_pq":
        texts = [U.law_text(nm, l) for nm, l in fam.laws(v, p)]
        a, b = pq(n)
        return np.vstack([law(texts, a, seed), law(texts, b, seed + 7919)])
    if cand == "law_odd":
        texts = [U.law_text(nm, l) for nm, l in fam.laws(v, p)]
        return law(texts, n - 1 + n % 2, seed)
    if cand == "law_odd_dup":
        texts = [U.law_text(nm, l) for nm, l in fam.laws(v, p)]
        return dup(law(texts, n - 1, seed), seed) if n % 2 == 0 else law(texts, n, seed)
    if cand == "sobol_fresh":  # the reference's own method, other seeds: its noise
        from scipy.stats import qmc
        return qmc.Sobol(d, scramble=True, seed=50000 + r).random(n)
    if cand == "owen":
        return owen(n, d, seed)
    if cand in ("eng_seq", "eng_ind"):  # Engine(d)'s default draws, and independent ones
        import stillpoint, warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            draws = "sequence" if cand == "eng_seq" and d <= 1000 else "independent"
            return stillpoint.Engine(d, seed=seed, draws=draws).random(n)
    if cand.startswith("even_w"):  # one lattice of n points, first-order kernel, weight g
        return halves_w(n, d, float(cand[6:]), seed, whole=True)
    if cand.startswith("law_w"):  # the lattice for the laws at another product weight
        return halves_w(n, d, float(cand[5:]), seed)
    raise SystemExit(cand)

data = json.load(open(os.path.join(ROOT, "results", "uq-models", "uq_models.json")))["cells"]
rows = []
for key, c in data.items():
    if c["n"] not in NS or (FAM and not any(f in c["family"] for f in FAM.split(","))):
        continue
    fam = BY_NAME[c["family"]]
    v = next(v for v in fam.variants if fam.label(v) == c["variant"])
    insts = [instance(fam, v, i) for i in range(c["instances"])]
    ref = np.array(c["reference"])
    sob = c["methods"]["sobol"]["rmse"]
    out = {}
    for cand in CANDS:
        errs = []
        for r in range(REPS):
            # one set per instance's laws (they vary per instance for some families)
            cache = {}
            def sets(i):
                texts = tuple(U.law_text(nm, l) for nm, l in fam.laws(v, insts[i]))
                if texts not in cache:
                    X = make(cand, fam, v, insts[i], c["n"], c["d"], r)
                    cache[texts] = map_cube(fam.laws(v, insts[i]), np.clip(X, 2**-53, 1 - 2**-53))
                return cache[texts]
            q = U.means_on(fam, v, insts, sets)
            errs.append(U.relative(q, ref))
        out[cand] = math.sqrt(np.mean(np.array(errs) ** 2)) / sob
    stored = c["methods"].get("randomize", {}).get("ratio")
    rows.append((c["family"], c["variant"], c["n"], stored, out))
    print(c["family"], c["variant"], c["n"], f"stored={stored:.2f}" if stored else "", " ".join(f"{k}={x:.2f}" for k, x in out.items()), flush=True)

def gm(xs): return math.exp(np.mean(np.log(xs)))
fams = sorted(set(r[0] for r in rows))
print("\nfamily", "stored", *CANDS)
for f in fams + ["ALL"]:
    rs = [r for r in rows if f == "ALL" or r[0] == f]
    print(f"{f:30s} {gm([r[3] for r in rs]):.2f} " + " ".join(f"{gm([r[4][k] for r in rs]):.2f}" for k in CANDS))
