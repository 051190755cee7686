#!/usr/bin/env python3
"""Prototype extensible lattice generators for `Engine(d)`'s sequence (NumPy), to see
whether another vector at 2^10..2^12 points in 5..50 coordinates would close the gap
between the sequence's prefixes and the lattice made for n on the models with input
laws (results/law-lattice/randomize-engine.md). Nothing here changes the library's
tables; a vector written here is read by benches/uq_engine.py's candidate `vec:NAME`.
The library's `embedded_first_order_generator` is the KERNEL=b2 construction carried to
2^20 points (sequences/src/engine_table.rs, `Engine(d)`'s table; results/law-lattice/
engine-table.md), with point 0's term left out of the comparison so that it keeps
choosing past about 230 coordinates, where this script's score saturates.

Construction (embedded, component by component, as `embedded_tent_generator` but with
another score): z_1 = 1; for each further coordinate every odd value below 2^B (up to
sign) is scored by the mean over the levels 2^m, m = LO..B, of log e_m, e_m the
criterion of the prefix of 2^m points (the lattice with z mod 2^m) with the coordinates
chosen so far:

    e_m = -1 + 2^-m sum_k prod_j (1 + g_j w(frac(k z_j / 2^m)))

    KERNEL=tent  w(x) = -(2 pi)^4/24 (x^4 - 2x^3 + x^2 - 1/30)  (the table's: the
                 half-period cosine space of smoothness 2, after the tent)
    KERNEL=b2    w(x) = 2 pi^2 (x^2 - x + 1/6) (first order: the lattice made for the
                 laws' kernel)

with product weight g_j = G (or G j^-A with A = DECAY). The mean of logs is, up to a
constant, the mean of log(e_m / e_m*) against the rules made for each 2^m alone.

With several weights (GS=0.05,0.3: the same kernel at each G, DECAY applied to each),
S_G is each weight's sum over the levels of log e_m, and a candidate is scored by

    SCORE=sum    the sum of the S_G (the mean of the log criteria over levels and weights)
    SCORE=worst  max over G of S_G - min over the candidates of S_G: its larger loss,
                 in log-ratio, against the best candidate under either weight

(results/law-lattice/engine-table.md, "The robot arm at 16 384": a second weight 0.3
brings the benchmark's robot arm at 2^14 points from 3.0 to 0.9 times scrambled
Sobol's error, but not in other orders of its inputs).

    NAME=b2g05 KERNEL=b2 G=0.05 D=50 B=14 LO=6 python benches/engine_vector.py
    NAME=b2worst03 KERNEL=b2 GS=0.05,0.3 SCORE=worst D=20 python benches/engine_vector.py
    NAME=... CRIT=1 ...   also print each level's criterion for the vector and the table
    NAME=b2guard KERNEL=b2 G=0.05 GUARD=1 D=20 ...  the table's score among the candidates
                 that leave no dual vector with entries in {-1, 0, 1} of order <= log3(2^m)
                 at a level 2^m (`guard_mask`)
    NAME=b2proj512 KERNEL=b2 G=0.05 PROJ=512 D=20 ...  among the PROJ best candidates by
                 the table's score, the one whose worst three-dimensional projection
                 through it is least bad, summed over the levels (`worst_triple`)
    NAME=pick4_v0 KERNEL=b2 G=0.05 PICK=4 SEEDV=0 D=20 ...  at every coordinate after
                 the first, a candidate drawn uniformly among the PICK lowest-scoring ones
                 (ties in score kept in candidate order), by a generator seeded with
                 (SEEDV, the coordinate's index): vectors v0, v1, ... for a mixture drawn
                 per engine (benches/uq_engine.py's candidate `mix:PREFIX:K`). PICK=1 (the
                 default) is the argmin, the construction unchanged; PICKHEAD=h keeps
                 the argmin for coordinates 2..h as well (drawing from coordinate h + 1)

Writes target/engine-vectors/NAME.npy (the first D entries, values below 2^B).
"""
import itertools
import math
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
OUT = os.path.join(ROOT, "target", "engine-vectors")
os.makedirs(OUT, exist_ok=True)

KERNEL = os.environ.get("KERNEL", "tent")
G = float(os.environ.get("G", 0.05))
GS = [float(g) for g in os.environ.get("GS", str(G)).split(",")]
SCORE = os.environ.get("SCORE", "sum")
DECAY = float(os.environ.get("DECAY", 0.0))
D = int(os.environ.get("D", 50))
B = int(os.environ.get("B", 14))
LO = int(os.environ.get("LO", 6))
NAME = os.environ.get("NAME", f"{KERNEL}_g{G}_a{DECAY}")


def omega(x, kernel):
    if kernel == "tent":
        return -((2 * math.pi) ** 4 / 24) * (x * x * (x * x - 2 * x + 1) - 1 / 30)
    return 2 * math.pi ** 2 * (x * x - x + 1 / 6)


def weight(j, g=G):
    return g * (j + 1) ** -DECAY


def table(d):
    text = open(os.path.join(ROOT, "sequences", "src", "extensible_table.rs")).read()
    body = text[text.index("= [") + 3:text.index("];")]
    return np.array([int(v) for v in re.findall(r"\d+", body)], dtype=np.int64)[:d]


def level_criteria(z, kernel=KERNEL):
    """e_m for every level m = LO..B of the vector z (weights by coordinate)."""
    out = {}
    for m in range(LO, B + 1):
        n = 1 << m
        k = np.arange(n)
        w = omega(k / n, kernel)
        P = np.ones(n)
        for j, zj in enumerate(z):
            P *= 1 + weight(j) * w[(k * int(zj)) % n]
        out[m] = P.mean() - 1
    return out


GUARD = int(os.environ.get("GUARD", 0))


def guard_mask(z, cand):
    """GUARD=1: the candidates for the next coordinate that leave no dual vector with
    entries in {-1, 0, 1} of order <= log3(2^m) at any level 2^m, m = LO..B (such a
    vector with few entries is an alias no choice of weight sees at gamma = 0.05). The
    levels are applied from the top down, and a level whose guard no remaining candidate
    passes is skipped, so the guard fades once it cannot be met (past about ten
    coordinates at 2^14). Entries of a lattice's dual vector on odd z sum to an even
    count, so the new coordinate's partner vectors have odd order."""
    alive = np.ones(len(cand), dtype=bool)
    zz = np.array(z, dtype=np.int64)
    kmax = {m: int(math.floor(m * math.log(2) / math.log(3) + 1e-9)) for m in range(LO, B + 1)}
    residues = {}
    for o in range(1, min(len(zz), max(kmax.values()) - 1) + 1, 2):
        combos = np.array(list(itertools.combinations(range(len(zz)), o)), dtype=np.int64)
        signs = np.array(list(itertools.product((-1, 1), repeat=o)), dtype=np.int64)
        residues[o] = ((zz[combos] @ signs.T) % (1 << B)).ravel()
    for m in range(B, LO - 1, -1):
        mask = (1 << m) - 1
        forbidden = np.zeros(1 << m, dtype=bool)
        for o, r in residues.items():
            if o + 1 <= kmax[m]:
                forbidden[r & mask] = True
                forbidden[(-r) & mask] = True
        keep = alive & ~forbidden[cand & mask]
        if keep.any():
            alive = keep
    return alive


PROJ = int(os.environ.get("PROJ", 0))
PICK = int(os.environ.get("PICK", 1))
SEEDV = int(os.environ.get("SEEDV", 0))
PICKHEAD = int(os.environ.get("PICKHEAD", 1))


def worst_triple(z, cand, w, k):
    """PROJ=S: for each candidate, the sum over the levels 2^m, m = LO..B, of the log of
    its worst three-dimensional projection through the new coordinate (the first-order
    criterion of the projection, unit weights): the table's score sums the projections,
    so a few bad ones hide behind many good ones, and which inputs land on them is the
    luck of the input order."""
    N = len(k)
    rows = np.array([(1 + w[(k * z[a]) & (N - 1)]) * (1 + w[(k * z[b]) & (N - 1)])
                     for a, b in itertools.combinations(range(len(z)), 2)])
    out = np.zeros(len(cand))
    for ci, c in enumerate(cand):
        v = rows * (1 + w[(k * int(c)) & (N - 1)])
        for m in range(LO, B + 1):
            out[ci] += np.log(v[:, ::1 << (B - m)].mean(1).max() - 1)
    return out


def build(d):
    """Every odd candidate below 2^(B-1) scored on the 2^B points of the top level: a
    point k belongs to level m iff 2^(B-m) divides k, and point 0 (the same for every
    candidate) is left out of the comparison, as the library's construction does."""
    N = 1 << B
    k = np.arange(N, dtype=np.int64)
    w = omega(k / N, KERNEL)
    cand = np.arange(1, N // 2, 2, dtype=np.int64)
    Q = [np.zeros(N) for _ in GS]
    z = [1]
    for q, g in zip(Q, GS):
        q += weight(0, g) * w
    for j in range(1, d):
        per = np.zeros((len(GS), len(cand)))
        for gi, (q, g) in enumerate(zip(Q, GS)):
            t = weight(j, g) * w
            p0 = q[0] + t[0] + q[0] * t[0]
            for c0 in range(0, len(cand), 256):
                cc = cand[c0:c0 + 256]
                v = q + t[(cc[:, None] * k) & (N - 1)] * (1 + q)
                v[:, 0] = 0.0
                for m in range(LO, B + 1):
                    per[gi, c0:c0 + 256] += np.log1p(v[:, ::1 << (B - m)].sum(1) / p0)
        if SCORE == "worst":
            score = (per - per.min(axis=1, keepdims=True)).max(0)
        else:
            score = per.sum(0)
        if GUARD:
            score = np.where(guard_mask(z, cand), score, np.inf)
        if PROJ and j >= 2:
            short = np.argsort(score)[:PROJ]
            proj = np.full(len(cand), np.inf)
            proj[short] = worst_triple(z, cand[short], w, k)
            score = proj
        if PICK > 1 and j >= PICKHEAD:
            short = np.argsort(score, kind="stable")[:PICK]
            short = short[np.isfinite(score[short])] if np.isfinite(score[short[0]]) else short
            best = int(cand[int(short[np.random.default_rng([SEEDV, j]).integers(len(short))])])
        else:
            best = int(cand[int(np.argmin(score))])
        z.append(best)
        for q, g in zip(Q, GS):
            q += weight(j, g) * w[(k * best) & (N - 1)] * (1 + q)
        print(f"coordinate {j + 1}: z = {best}", flush=True)
    return np.array(z, dtype=np.int64)


def main():
    z = build(D)
    np.save(os.path.join(OUT, NAME + ".npy"), z)
    if os.environ.get("CRIT"):
        t = table(D) % (1 << B)
        for dd in (5, 10, 20, 50):
            if dd > D:
                continue
            a, b = level_criteria(z[:dd]), level_criteria(t[:dd])
            print(f"d={dd} " + " ".join(f"2^{m}:{a[m] / b[m]:.2f}" for m in a))


if __name__ == "__main__":
    sys.exit(main())
