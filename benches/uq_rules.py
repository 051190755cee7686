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

Deterministic candidates, for the default under a space (one set per seed r; compare
with STORED=default, the stored default's ratio; results/law-lattice/deterministic.md):

    cube        the cube's default, `stillpoint generate -n N -s D --seed r+1` (the
                lattice with its shift searched on the cosine-space error): what the
                default under a space maps through the quantiles
    odd2        the same made as two odd sets of n/2 -+ 1 points (no reflected pairs)
    cq          the cube's default shifted by 1/4 modulo 1 (pairs not reflected)
    mid_wG      the lattice for the laws (weight G, odd parts), each part shifted by
                (a_j + 1/4)/m with integer offsets a_j drawn from the seed: every column
                the midpoints after the tent
    mid0_wG     the same with every a_j = 0
    tmid        the cube's tent generator, one lattice of n, drawn midpoint offsets
    tmid_odd    the same in odd parts
    bestKgC     mid_w0.05's offsets, the best of K draws on the unanchored Sobolev
                (smoothness 1, weight C) worst-case error
    srchA       the lattice for the laws in odd parts with the shift searched as the
                cube's default searches it (greedy, every odd numerator q < 2m, on the
                pair part of the cosine-space error of smoothness A = 1, 2); srchTA
                with the cube's tent generator; srchFA adds the error of the set folded
                by y -> 2y mod 1 (what an integrand even in every normal input sees)
    anti        Owen-scrambled Sobol' of n/2 points and the same points reflected,
                1 - x (through a normal law: each path beside its negative, the
                antithetic pairs the tent lattice's reflections give, on a net)
    antiK       the same with only the first K columns reflected
    hybK        the cube's tent lattice of n points (`generate --randomize`) on the first
                K columns, Owen-scrambled Sobol' of d - K columns on the rest (two
                independent uniform randomisations: every point uniform)
    pcaK_G      a randomly shifted lattice made for n, then the tent, on the first K
                columns with product weights G/(2 ceil((j+1)/A) - 1)^2 (A = the
                assets: a path's variance by PCA index, the columns asset-interleaved),
                Owen-scrambled Sobol' on the rest
    ordK_G      the same with weights by the cell's construction, i = j // A the
                column's step: PCA G/(2i + 1)^2 (the eigenvalues), bridge
                G 2^-floor(log2(i + 1)) (the level's variance), standard G ((k - i)/k)^2
                (k steps: how much of the average the i-th increment moves)
    wl{t|f|p}G[s|n|e|a|q]
                a randomly shifted rank-1 lattice of the whole set, made for n by the
                weighted component-by-component search (`weighted_lattice_generator`,
                through the example `weighted_lattice` of stillpoint-sequences: build it
                with `cargo build --release -p stillpoint-sequences --example
                weighted_lattice`), product weights by the cell's construction
                (`path_weights`, first weight G), the columns asset-interleaved; t: the
                tent kernel then the tent, f: the first-order kernel then the tent, p:
                the first-order kernel and the shift alone. Suffix s: the weights'
                square roots; n: bridge weights by the path's squared norm; e: equal
                weights on standard paths; a: 0.05 + G w; q: equal weights everywhere
    pickK       mid_w0.05's offsets, the draw among K whose errors on exp(-|Z|^2/2),
                cos(sum Z/sqrt(s)) and exp(sum Z/sqrt(s)) (Z the normal scores
                Phi^-1(u), closed forms) are smallest, each over its median

Run (the bench venv of benches/uq_models.py, the CLI built in target/release):

    REPS=12 NS=1024,4096 CANDS=cur,law_halves target/bench-venv/bin/python benches/uq_rules.py
    (FAM=keister,lognormal: only those families; VAR="m = 32,pca": only variants whose
    label holds one of these; SEED0=K: seeds K + r, 1000 + r unless given)
    REPS=3 STORED=default CANDS=cube,mid_w0.05,srch2 ... (the default's candidates)
    benches/uq_rules.py OUT1 OUT2 ...  (pools saved outputs over seed blocks, `pool`)
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

def parts(n):
    """The odd sizes of the lattice for the laws (`law_lattice_parts`)."""
    return [n] if n % 2 else ([n // 2, n // 2] if (n // 2) % 2 else [n // 2 - 1, n // 2 + 1])

def owen(n, d, seed):
    p = f"{CACHE}/o_{n}_{d}_{seed}.npy"
    if not os.path.exists(p):
        subprocess.run([BIN, "baseline", "sobol", "-n", str(n), "-s", str(d), "--seed",
                        str(seed), "-o", p], check=True, capture_output=True)
    return np.load(p)

def cbc_b2(m, s, g):
    """Component-by-component vector for the first-order kernel 2π²B2, weight g."""
    return cbc_weights(m, np.full(s, g))

def halves_w(n, d, g, seed, whole=False):
    rng = np.random.default_rng(seed)
    out = []
    for m in ([n] if whole else parts(n)):
        z = cbc_b2(m, d, g)
        x = (np.outer(np.arange(m), z) % m) / m
        x = (x + rng.random(d)) % 1.0
        out.append(1 - np.abs(2 * x - 1))
    return np.vstack(out)

def mid_part(m, z, a):
    """The m-point lattice with generator z shifted by (a + 1/4)/m, then the tent: every
    column the midpoints (i + 1/2)/m."""
    x = ((np.outer(np.arange(m), z) + a) % m + 0.25) / m
    return 1 - np.abs(2 * x - 1)

def law_mid(n, d, g, seed, pick="seed"):
    """The lattice for the laws (two odd parts for even n), each part shifted by
    (a + 1/4)/m per coordinate: after the tent every coordinate is the m-point midpoint
    rule; a from the seed."""
    rng = np.random.default_rng(seed)
    out = []
    for m in parts(n):
        z = cbc_b2(m, d, g)
        a = rng.integers(0, m, d) if pick == "seed" else np.zeros(d, dtype=int)
        out.append(mid_part(m, z, a))
    return np.vstack(out)

def cube(n, d, seed):
    """The cube's deterministic default, `stillpoint generate -n N -s D --seed K`."""
    p = f"{CACHE}/c_{n}_{d}_{seed}.npy"
    if not os.path.exists(p):
        subprocess.run([BIN, "generate", "-n", str(n), "-s", str(d), "--seed", str(seed),
                        "-q", "-o", p], check=True, capture_output=True)
    return np.load(p)

def sob1(X, g):
    """Squared worst-case error of the equal-weight rule X in the unanchored Sobolev
    space of smoothness 1, product weight g (kernel 1 + g(B1(x)B1(y) + B2(|x-y|)/2))."""
    m = len(X); tot = 0.0
    b1 = X - 0.5
    for lo in range(0, m, 256):
        A = X[lo:lo + 256, None, :]; t = np.abs(A - X[None, :, :])
        k = b1[lo:lo + 256, None, :] * b1[None, :, :] + 0.5 * (t * t - t + 1 / 6)
        tot += np.prod(1 + g * k, axis=2).sum()
    return tot / m / m - 1

_BEST = {}
def law_mid_best(n, d, g, seed, tries=8, crit_g=1.0):
    key = (n, d, g, seed, tries, crit_g)
    if key not in _BEST:
        rng = np.random.default_rng(seed)
        out = []
        for m in parts(n):
            z = cbc_b2(m, d, g)
            best = None
            for t in range(tries):
                X = mid_part(m, z, rng.integers(0, m, d))
                c = sob1(X, crit_g)
                if best is None or c < best[0]:
                    best = (c, X)
            out.append(best[1])
        _BEST[key] = np.vstack(out)
    return _BEST[key]

def tent_z(m, d):
    import stillpoint
    x = np.asarray(stillpoint._core.tent_set(m, d))
    return np.round(x[1] * m).astype(np.int64) if m >= 2 else np.ones(d, dtype=np.int64)

def tent_mid(n, d, seed, split):
    rng = np.random.default_rng(seed)
    out = []
    for m in (parts(n) if split else [n]):
        out.append(mid_part(m, tent_z(m, d), rng.integers(0, m, d)))
    return np.vstack(out)

def p_alpha(t, alpha):
    """sum_{h>=1} cos(2 pi h t)/h^(2 alpha), t in [0, 1)."""
    if alpha == 1:
        return np.pi ** 2 * (t * t - t + 1 / 6)
    return -(np.pi ** 4 / 3) * (t ** 4 - 2 * t ** 3 + t ** 2 - 1 / 30)

_SRCH = {}
def law_searched(n, d, g, alpha, gen="law", fold=False):
    """Odd parts; q_j odd < 2m chosen greedily on the order-2 part of the shifted, tented
    set's cosine-space error of smoothness alpha (the cube default's kind of search)."""
    key = (n, d, g, alpha, gen, fold)
    if key in _SRCH:
        return _SRCH[key]
    out = []
    for m in parts(n):
        z = cbc_b2(m, d, g) if gen == "law" else tent_z(m, d)
        e = np.arange(m)
        qs = np.arange(1, 2 * m, 2)
        C = np.zeros(m)
        CF = np.zeros(m)  # the folded set's (2y mod 1: what an integrand even in each
        q = []            # coordinate's Z sees) sums over k + k'
        def folded(r, qq):
            return p_alpha(((2 * r[None, :] + 2 * qq[:, None]) % (2 * m)) / (2 * m), alpha)
        for j in range(d):
            r = (2 * e * z[j]) % (2 * m)
            if j == 0:
                qj = 1
            else:
                # B_j(e; q) = P((2 e z_j + q)/(2m)); score(q) = sum_e B_j(e;q) C(e)
                best, bv = None, np.inf
                for c0 in range(0, len(qs), 256):
                    qq = qs[c0:c0 + 256]
                    B = p_alpha(((r[None, :] + qq[:, None]) % (2 * m)) / (2 * m), alpha)
                    sc = B @ C
                    if fold:
                        sc = sc + folded(r, qq) @ CF
                    i = int(np.argmin(sc))
                    if best is None or sc[i] < bv - 1e-12 * abs(bv):
                        bv, best = sc[i], int(qq[i])
                qj = best
            q.append(qj)
            C += p_alpha(((r + qj) % (2 * m)) / (2 * m), alpha)
            CF += folded(r, np.array([qj]))[0]
        x = (((np.outer(e, z) % m) + np.array(q) / 4.0) / m) % 1.0
        out.append(1 - np.abs(2 * x - 1))
    _SRCH[key] = np.vstack(out)
    return _SRCH[key]

_PICK = {}
def law_mid_pick(n, d, g, seed, tries):
    """Among `tries` draws of the midpoint offsets, the set whose errors on three test
    integrals of normal scores Z = Phi^-1(u) with closed forms are smallest (each
    error over its median among the draws): exp(-|Z|^2/2) (radial, even),
    cos(sum Z/sqrt(s)) and exp(sum Z/sqrt(s)) (a ridge, odd and even parts)."""
    from scipy.special import ndtri
    key = (n, d, g, seed, tries)
    if key not in _PICK:
        rng = np.random.default_rng(seed)
        cands = []
        for t in range(tries):
            out = []
            for m in parts(n):
                out.append(mid_part(m, cbc_b2(m, d, g), rng.integers(0, m, d)))
            X = np.vstack(out)
            Z = ndtri(X)
            w = Z.sum(1) / np.sqrt(d)
            errs = [np.exp(-0.5 * (Z * Z).sum(1)).mean() / 2 ** (-d / 2) - 1,
                    np.cos(w).mean() / np.exp(-0.5) - 1,
                    np.exp(w).mean() / np.exp(0.5) - 1]
            cands.append((np.abs(errs), X))
        E = np.array([c[0] for c in cands])
        score = ((E / np.median(E, axis=0)) ** 2).sum(1)
        _PICK[key] = cands[int(np.argmin(score))][1]
    return _PICK[key]

_ZW = {}
def cbc_weights(m, gam):
    """Component-by-component vector for the first-order kernel 2pi^2 B2 with product
    weights gam[j] (the squared worst-case error of the shifted lattice)."""
    key = (m, tuple(np.round(gam, 12)))
    if key not in _ZW:
        k = np.arange(m); x = k / m; om = 2 * np.pi ** 2 * (x * x - x + 1 / 6)
        cand = np.array([c for c in range(1, m // 2 + 1) if math.gcd(c, m) == 1])
        prod = 1 + gam[0] * om; z = [1]
        for j in range(1, len(gam)):
            best, bv = None, np.inf
            for c0 in range(0, len(cand), 64):
                cc = cand[c0:c0 + 64]
                vals = ((1 + gam[j] * om[np.outer(cc, k) % m]) * prod).sum(1)
                i = int(np.argmin(vals))
                if vals[i] < bv:
                    bv, best = vals[i], int(cc[i])
            z.append(best); prod = prod * (1 + gam[j] * om[(k * best) % m])
        _ZW[key] = np.array(z)
    return _ZW[key]

WBIN = os.path.join(ROOT, "target", "release", "examples", "weighted_lattice")

def path_weights(how, k, A, G, var="cond"):
    """Product weights of the d = k·A columns (asset-interleaved, step i = j // A) by the
    construction's variance of the i-th normal, the first G: PCA the eigenvalues
    (2i + 1)^-2; bridge the i-th point's variance given the earlier ones (1, then halving
    per level: 1/4, 1/8, 1/8, 1/16 ...; var="norm": the squared norm of the path the
    normal moves, quartering per level); standard ((k - i)/k)^2 (how much of the average
    the i-th increment moves), or equal (var="eq"); var="sqrt" their square roots (the
    standard deviations), var="add" 0.05 + G w (the cube's weight on every column)."""
    i = np.arange(k * A) // A
    if how == "pca":
        w = 1.0 / (2 * i + 1.0) ** 2
    elif how == "bridge":
        lev = np.where(i == 0, 0, np.floor(np.log2(np.maximum(i, 1))) + 1)
        w = (0.5 if var != "norm" else 0.25) ** (lev + (i > 0))
    elif var == "eq":
        w = np.ones(len(i))
    else:
        w = ((k - i) / k) ** 2
    if var == "sqrt":  # the standard deviations: gamma_i ~ c_i balances the bound
        return G * np.sqrt(w)
    if var == "add":  # the cube's weight on every column and the construction's on top
        return 0.05 + G * w
    return G * w

_WZ = {}
def weighted_lattice(cand, v, n, d, A, seed):
    kern = "tent" if cand[2] == "t" else "first"  # wlp: first order, shift alone
    var = {"n": "norm", "e": "eq", "s": "sqrt", "a": "add", "q": "eq"}.get(cand[-1], "cond")
    G = float(cand[3:].rstrip("nesaq"))
    how = "standard" if cand[-1] == "q" else v[1]  # q: equal weights on every construction
    key = (kern, G, how, var, n, d, A)
    if key not in _WZ:
        w = path_weights(how, d // A, A, G, var)
        path = f"{CACHE}/w_{hashlib.md5(repr(key).encode()).hexdigest()}.txt"
        open(path, "w").write(" ".join(repr(float(x)) for x in w))
        out = subprocess.run([WBIN, str(n), kern, path], check=True, capture_output=True,
                             text=True).stdout
        _WZ[key] = np.array([int(x) for x in out.split()], dtype=np.int64)
    z = _WZ[key]
    x = (np.outer(np.arange(n), z) % n) / n
    x = (x + np.random.default_rng(seed).random(d)) % 1.0
    return x if cand[2] == "p" else 1 - np.abs(2 * x - 1)

def assets_of(fam):
    return getattr(fam, "assets", 1)

def make(cand, fam, v, p, n, d, r):
    seed = int(os.environ.get("SEED0", 1000)) + r
    if cand == "anti":
        x = owen(n // 2, d, seed)
        return np.vstack([x, 1 - x])
    if cand.startswith("anti"):
        K = int(cand[4:]); x = owen(n // 2, d, seed); y = x.copy(); y[:, :K] = 1 - y[:, :K]
        return np.vstack([x, y])
    if cand.startswith("hyb"):
        K = min(int(cand[3:]), d)
        parts_ = [cli(n, K, seed)] + ([owen(n, d - K, seed)] if d > K else [])
        return np.hstack(parts_)
    if cand.startswith("pca") or cand.startswith("ord"):
        K, G = cand[3:].split("_"); K = min(int(K), d); G = float(G)
        A = assets_of(fam)
        steps = d // A
        how = v[1] if cand.startswith("ord") else "pca"
        if how == "pca":
            gam = np.array([G / (2 * (j // A) + 1) ** 2 for j in range(K)])
        elif how == "bridge":
            gam = np.array([G * 2.0 ** -math.floor(math.log2(j // A + 1)) for j in range(K)])
        else:
            gam = np.array([G * ((steps - j // A) / steps) ** 2 for j in range(K)])
        z = cbc_weights(n, gam)
        x = (np.outer(np.arange(n), z) % n) / n
        x = (x + np.random.default_rng(seed).random(K)) % 1.0
        lat = 1 - np.abs(2 * x - 1)
        return np.hstack([lat] + ([owen(n, d - K, seed)] if d > K else []))
    if cand.startswith("wl"):  # wl{t|f}{G}[n|h]: the weighted lattice of the whole set
        return weighted_lattice(cand, v, n, d, assets_of(fam), seed)
    if cand.startswith("pick"):
        return law_mid_pick(n, d, 0.05, seed, int(cand[4:]))
    if cand.startswith("srch"):  # srch1, srch2, srchT2 (tent generator), srchF2 (folded)
        gen = "tent" if cand[4] == "T" else "law"
        return law_searched(n, d, 0.05, int(cand[-1]), gen, fold=cand[4] == "F")
    if cand in ("tmid", "tmid_odd"):
        return tent_mid(n, d, seed, cand == "tmid_odd")
    if cand.startswith("best"):  # best8g1 : 8 tries, criterion weight 1
        t, cg = cand[4:].split("g")
        return law_mid_best(n, d, 0.05, seed, int(t), float(cg))
    if cand == "cube":
        return cube(n, d, r + 1)
    if cand == "odd2":
        return np.vstack([cube(m, d, r + 1) for m in parts(n)])
    if cand == "cq":
        return (cube(n, d, r + 1) + 0.25) % 1.0
    if cand.startswith("mid_w"):
        return law_mid(n, d, float(cand[5:]), seed)
    if cand.startswith("mid0_w"):
        return law_mid(n, d, float(cand[6:]), seed, pick="zero")
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

def pool(paths):
    """Pools this script's printed outputs of the same candidates over seed blocks of
    equal REPS (ratio² averaged: the same stored denominator), then geometric means by
    construction, family and n, and each candidate over owen cell by cell."""
    cells = {}
    for path in paths:
        for line in open(path):
            if " owen=" not in line:
                continue
            head = line.split(" stored=")[0].split(" owen=")[0]
            for t in line.split():
                if "=" in t and t != "=" and not t.startswith("stored"):
                    k, x = t.split("=")
                    cells.setdefault(head, {}).setdefault(k, []).append(float(x))
    P = {h: {k: math.sqrt(np.mean(np.square(x))) for k, x in d.items()} for h, d in cells.items()}
    cands = [k for k in next(iter(P.values())) if all(k in d for d in P.values())]
    def group(h, g):
        return {"construction": next(c for c in ("standard", "bridge", "pca") if c in h),
                "family": h.split(" m =")[0], "n": h.split()[-1], "all": "all"}[g]
    def gm(xs): return math.exp(np.mean(np.log(xs)))
    print("group cells", *cands, "| over owen:", *[c for c in cands if c != "owen"])
    for g in ("construction", "family", "n", "all"):
        for val in sorted({group(h, g) for h in P}):
            hs = [h for h in P if group(h, g) == val]
            print(val, len(hs), *[f"{gm([P[h][c] for h in hs]):.2f}" for c in cands], "|",
                  *[f"{gm([P[h][c] / P[h]['owen'] for h in hs]):.2f}" for c in cands if c != "owen"])

if len(sys.argv) > 1:  # uq_rules.py OUT1 OUT2 ...: pool earlier runs' outputs
    pool(sys.argv[1:])
    sys.exit(0)

data = json.load(open(os.path.join(ROOT, "results", "uq-models", "uq_models.json")))["cells"]
rows = []
for key, c in data.items():
    if c["n"] not in NS or (FAM and not any(f in c["family"] for f in FAM.split(","))):
        continue
    if os.environ.get("VAR") and not any(x in c["variant"] for x in os.environ["VAR"].split(",")):
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
    stored = c["methods"].get(os.environ.get("STORED", "randomize"), {}).get("ratio")
    rows.append((c["family"], c["variant"], c["n"], stored, out))
    print(c["family"], c["variant"], c["n"], f"stored={stored:.2f}" if stored else "", " ".join(f"{k}={x:.2f}" for k, x in out.items()), flush=True)

def gm(xs): return math.exp(np.mean(np.log(xs)))
fams = sorted(set(r[0] for r in rows))
print("\nfamily", "stored", *CANDS)
for f in fams + ["ALL"]:
    rs = [r for r in rows if f == "ALL" or r[0] == f]
    print(f"{f:30s} {gm([r[3] for r in rs]):.2f} " + " ".join(f"{gm([r[4][k] for r in rs]):.2f}" for k in CANDS))
