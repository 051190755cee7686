#!/usr/bin/env python3
"""Candidate draws for `stillpoint.Engine(d)` (which knows nothing of the integrand)
measured over both benchmarks the engine's default answers to: Genz's six families on
the randomised-QMC grid (benches/rqmc.py's cells, instances and protocol) and the models
with input laws (results/uq-models' cells, through the peers' quantile map, as
benches/uq_rules.py measures them).

Every figure is a ratio of RMSEs to scrambled Sobol' (SciPy, `qmc.Sobol(scramble=True)`)
on the same instances: on the Genz grid Sobol' is drawn here with the same number of
randomisations (seeds 3000 + r, as rqmc.py draws them); on the models the stored
denominator of results/uq-models is used (16 randomisations) unless `sobol_fresh` is
among the candidates, which measures it again.

    seq      Engine(d, seed=SEED0 + r).random(n): the default, the extensible lattice
             sequence with one shift and the tent (the engine's own table, built for the
             first-order kernel, where the package has it)
    seqtent  the same engine's draws with the tent table (sequences/src/extensible_table.rs,
             quad's, and the engine's before it had its own): the same shift, so these
             are the draws `seq` gave for the same seeds before
    ind      Engine(d, seed=SEED0 + r, draws='independent').random(n): the tent lattice
             made for n, shifted and folded
    owen     Owen-scrambled Sobol' (stillpoint.baseline('sobol', n, d, seed=SEED0 + r)):
             a sequence too (its prefixes are the draws' continuation)
    halves   the tent lattice made for each odd part of n (n/2 -+ 1, as the lattice made
             for the laws splits an even n), each with its own shift, then the tent
    seqrec   the sequence rebuilt here (the tabulated generator, radical-inverse order, a
             NumPy shift): `seq` in distribution, the base of the next two
    seqaC    the sequence with an asymmetric tent of apex c per coordinate (y -> y/c
             below c, (1 - y)/(1 - c) above: uniform to uniform, continuous on the torus,
             so the order of the tent's error; the point k + 2^(m-1) of a prefix of 2^m
             is then not the reflection of point k, which through a symmetric law pairs
             Z with -Z): C = r draws c_j uniform in [1/4, 3/4] per engine, else c = C
    indaC    the same asymmetric tent on the lattice made for n (`ind`'s set)
    seqdyad  seq with inputs 1..4 on the first four coordinates and each later input
             dealt within its dyadic block (5..8, 9..16, 17..32, ...) by an order drawn per
             engine
    seqperm  seq with its coordinates dealt to the inputs in an order drawn per engine
             (seeded by the engine's seed): unbiased, and an input order's alias is
             spread over the seeds; seqpermK keeps inputs 1..K on the table's first K
             coordinates and deals only the others
    law1     the lattice made for the laws with every coordinate scored as unbounded
             (`_core.law_set` of d normal laws: the first-order kernel everywhere, an even
             n as two odd lattices, the tent): what `--randomize` under bounded laws would
             be with the kernel of unbounded ones (measured on the bounded families, not
             taken: results/law-lattice/law1-bounded.log)
    vec:NAME the sequence (radical-inverse order, one shift, the tent) with the
             prototype generator target/engine-vectors/NAME.npy of
             benches/engine_vector.py (values below 2^B; n <= 2^B) in place of the table
    mix:PREFIX:K  a mixture of K such vectors drawn per engine: randomisation r (seed
             SEED0 + r) is `vec:PREFIX_v{(SEED0 + r) % K}` (the same radical-inverse
             order, shift and tent), e.g. the K vectors of engine_vector.py's PICK=P
             SEEDV=0..K-1 (each coordinate drawn among the P best by the table's score)

    GRID=genz|uq|both (both)  REPS=16  CANDS=seq,ind,owen  CELLS=2:32,5:256 (Genz cells)
    NS=1024,4096 FAM=keister MAXD=20 (uq cells, as uq_rules.py; MAXD skips those of more
    coordinates)
    ORDER=rev|interleave|late|rand<i>  the models' inputs take the draws' coordinates in
             another order (input order[j] takes coordinate j: reversed, the two halves
             interleaved, the second half first, or a permutation drawn with seed 100 + i),
             to tell a rule from the luck of one order; ORDER=p4.1.2.3.0.5.6.7 gives the
             permutation itself (dot-separated; several orders comma-separated); ORDER=all prints the cells for the
             identity and all of these (rand0..rand3), and per candidate the geometric
             mean and the largest over the orders. Scrambled Sobol's stored RMSE (in the
             inputs' own order) stays the denominator.
    SEED0=1000: the candidates' randomisations are seeds SEED0 + r
    /work/wt/bench-venv/bin/python benches/uq_engine.py

Prints per cell and the geometric means per family, per benchmark and over both (every
family-cell of the Genz grid and every cell of the models counted once).
"""
import math
import os
import re
import sys
import warnings

import numpy as np
from scipy.stats import qmc

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import stillpoint as sp  # noqa: E402
from anchors import FAMILIES, genz_exact, genz_instances, genz_value  # noqa: E402

REPS = int(os.environ.get("REPS", 16))
CANDS = os.environ.get("CANDS", "seq,ind,owen").split(",")
GRID = os.environ.get("GRID", "both")
S_FULL = [2, 3, 5, 8, 10, 15, 20]
N_FULL = [32, 100, 256, 500, 2048]


def parts(n):
    """The odd sizes of the lattice made for the laws (`law_lattice_parts`)."""
    return [n] if n % 2 else ([n // 2, n // 2] if (n // 2) % 2 else [n // 2 - 1, n // 2 + 1])


def halves(n, d, seed):
    rng = np.random.default_rng(seed)
    out = []
    for m in parts(n):
        x = np.asarray(sp._core.tent_set(m, d))
        y = (x + rng.random(d)) % 1.0
        out.append(1.0 - np.abs(2.0 * y - 1.0))
    return np.vstack(out)


_Z = {}


def table_generator(d):
    """The first d entries of the sequence's tabulated generating vector."""
    if "all" not in _Z:
        text = open(os.path.join(ROOT, "sequences", "src", "extensible_table.rs")).read()
        body = text[text.index("= [") + 3:text.index("];")]
        _Z["all"] = np.array([int(v) for v in re.findall(r"\d+", body)], dtype=np.int64)
    return _Z["all"][:d]


def radical_inverse(k, bits=20):
    out = np.zeros_like(k)
    for b in range(bits):
        out |= ((k >> b) & 1) << (bits - 1 - b)
    return out


def apex_tent(y, c):
    return np.where(y < c, y / c, (1.0 - y) / (1.0 - c))


def apexes(code, d, rng):
    return rng.uniform(0.25, 0.75, d) if code == "r" else np.full(d, float(code))


SEED0 = int(os.environ.get("SEED0", 1000))
MAXD = int(os.environ.get("MAXD", 10**9))
ORDER = os.environ.get("ORDER", "id")


def input_order(name, d):
    """The permutation ORDER names: input order[j] takes the draws' coordinate j."""
    if name == "id":
        return np.arange(d)
    if name == "rev":
        return np.arange(d)[::-1]
    if name == "late":
        return np.roll(np.arange(d), d // 2)
    if name == "interleave":
        h = (d + 1) // 2
        return np.array([i // 2 if i % 2 == 0 else h + i // 2 for i in range(d)])
    if name.startswith("rand"):
        return np.random.default_rng(100 + int(name[4:])).permutation(d)
    if name.startswith("p") and name[1:2].isdigit():
        perm = np.array([int(v) for v in name[1:].split(".")])
        if sorted(perm) != list(range(d)):
            raise SystemExit(f"ORDER {name} is not a permutation of {d} inputs")
        return perm
    raise SystemExit(f"unknown ORDER {name}")


def draw(cand, n, d, r):
    seed = SEED0 + r
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if cand in ("seq", "seqtent"):
            draws = "sequence" if d <= sp._core.SEQUENCE_MAX_D else "independent"
            e = sp.Engine(d, seed=seed, draws=draws)
            if cand == "seqtent" and draws == "sequence":
                return sp._core.sequence_points(d, seed=e._sequence_seed, count=n, table="tent")
            return e.random(n)
        if cand == "ind":
            return sp.Engine(d, seed=seed, draws="independent").random(n)
    if cand.startswith("seqperm"):
        # The default's draws with the coordinates dealt to the inputs in an order drawn
        # per engine: an input order's alias becomes a spread over the seeds. seqpermK
        # keeps the first K inputs on the table's first K coordinates (its best
        # projections, where most integrands put their leading inputs) and deals the rest.
        x = draw("seq", n, d, r)
        head = min(int(cand[7:] or 0), d)
        tail = head + np.random.default_rng([seed, 77]).permutation(d - head)
        return x[:, np.concatenate([np.arange(head), tail])]
    if cand == "seqdyad":
        # The default's draws with inputs 1..4 on the table's first four coordinates and
        # every later input dealt within its dyadic block (5..8, 9..16, 17..32, ...), by an
        # order drawn per engine: leading inputs keep leading coordinates, and an order's
        # alias becomes a spread over the seeds.
        x = draw("seq", n, d, r)
        rng = np.random.default_rng([seed, 78])
        cols, lo = list(range(min(4, d))), 4
        while lo < d:
            hi = min(2 * lo, d)
            cols += list(lo + rng.permutation(hi - lo))
            lo = hi
        return x[:, np.array(cols, dtype=int)]
    if cand == "owen":
        return sp.baseline("sobol", n, d, seed=seed)
    if cand == "halves":
        return halves(n, d, seed)
    if cand == "law1":
        return np.asarray(sp._core.law_set([f"x{j}=normal(0,1)" for j in range(d)], n, seed))
    if cand.startswith("mix:"):
        # A mixture of K vectors drawn per engine: the engine with seed s uses vector
        # s mod K, exactly as `vec:` uses its one vector (same order, shift, tent).
        prefix, kk = cand[4:].rsplit(":", 1)
        return draw(f"vec:{prefix}_v{seed % int(kk)}", n, d, r)
    if cand.startswith("vec:"):
        z = np.load(os.path.join(ROOT, "target", "engine-vectors", cand[4:] + ".npy"))
        if d > len(z):
            raise SystemExit(f"{cand} holds {len(z)} coordinates, {d} asked")
        rng = np.random.default_rng(seed)
        k = radical_inverse(np.arange(n, dtype=np.int64))
        y = ((k[:, None] * z[None, :d]) % (1 << 20)) / float(1 << 20)
        y = (y + rng.random(d)) % 1.0
        return 1.0 - np.abs(2.0 * y - 1.0)
    if cand == "seqrec" or cand.startswith("seqa"):
        rng = np.random.default_rng(seed)
        k = radical_inverse(np.arange(n, dtype=np.int64))
        y = ((k[:, None] * table_generator(d)[None, :]) % (1 << 20)) / float(1 << 20)
        y = (y + rng.random(d)) % 1.0
        if cand == "seqrec":
            return 1.0 - np.abs(2.0 * y - 1.0)
        return apex_tent(y, apexes(cand[4:], d, rng))
    if cand.startswith("inda"):
        rng = np.random.default_rng(seed)
        y = (np.asarray(sp._core.tent_set(n, d)) + rng.random(d)) % 1.0
        return apex_tent(y, apexes(cand[4:], d, rng))
    if cand in ("sobol", "sobol_fresh"):
        return qmc.Sobol(d, scramble=True, seed=(3000 if cand == "sobol" else 50000) + r).random(n)
    raise SystemExit(f"unknown candidate {cand}")


def gm(xs):
    return math.exp(float(np.mean(np.log(xs)))) if len(xs) else float("nan")


def genz_rows():
    cells = [(s, n) for s in S_FULL for n in N_FULL]
    if os.environ.get("CELLS"):
        cells = [tuple(int(v) for v in c.split(":")) for c in os.environ["CELLS"].split(",")]
    rows = []
    for s, n in cells:
        insts = genz_instances(s, 16, seed=1_000_003 * s + n)
        exact = np.array([genz_exact(f, a, u) for f, a, u in insts])
        fam = np.array([f for f, _, _ in insts])
        rmse = {}
        for cand in ["sobol"] + CANDS:
            est = np.empty((REPS, len(insts)))
            for r in range(REPS):
                x = np.clip(draw(cand, n, s, r), 0.0, 1.0)
                est[r] = [genz_value(f, a, u, x).mean() for f, a, u in insts]
            rmse[cand] = np.sqrt(((est - exact) ** 2).mean(axis=0))
        for f, name in enumerate(FAMILIES):
            out = {c: gm(rmse[c][fam == f] / rmse["sobol"][fam == f]) for c in CANDS}
            rows.append(("genz " + name, f"s = {s}", n, out))
        print(f"genz s={s} n={n} " + " ".join(
            f"{c}=" + "/".join(f"{r[3][c]:.2f}" for r in rows[-6:]) for c in CANDS), flush=True)
    return rows


def uq_rows():
    import uq_models as U
    from uq_families import map_cube

    ns = [int(x) for x in os.environ.get("NS", "1024,4096").split(",")]
    famf = os.environ.get("FAM")
    rows = []
    for c, fam, v, insts, ref, den in U.stored_cells(ns, famf, MAXD):
        orders = ORDER.split(",")
        if ORDER == "all":
            orders = ["id", "rev", "interleave", "late"] + [f"rand{i}" for i in range(4)]
        by_order = []
        for name in orders:
            perm = input_order(name, c["d"])
            out = {}
            for cand in CANDS:
                errs = []
                for r in range(REPS):
                    X = np.empty((c["n"], c["d"]))
                    X[:, perm] = np.clip(draw(cand, c["n"], c["d"], r), 2**-53, 1 - 2**-53)
                    q = U.means_on(fam, v, insts, lambda i: map_cube(fam.laws(v, insts[i]), X))
                    errs.append(U.relative(q, ref))
                out[cand] = math.sqrt(float(np.mean(np.array(errs) ** 2))) / den
            if "sobol_fresh" in out:
                out = {k: x / out["sobol_fresh"] for k, x in out.items()}
            by_order.append(out)
            label = "" if name == "id" and len(orders) == 1 else f" [{name}]"
            print(c["family"], c["variant"], c["n"], " ".join(f"{k}={x:.2f}" for k, x in
                                                              out.items()) + label, flush=True)
        if len(orders) > 1:
            print(c["family"], c["variant"], c["n"], f"over {len(orders)} orders: " + " ".join(
                f"{k}={gm([o[k] for o in by_order]):.2f} (max {max(o[k] for o in by_order):.2f})"
                for k in by_order[0]), flush=True)
        out = {k: gm([o[k] for o in by_order]) for k in by_order[0]}
        rows.append((c["family"], c["variant"], c["n"], out))
    return rows


def main():
    rows = []
    if GRID in ("genz", "both"):
        rows += [("genz",) + r for r in genz_rows()]
    if GRID in ("uq", "both"):
        rows += [("uq",) + r for r in uq_rows()]
    print(f"\nREPS={REPS}; geometric means of the RMSE ratio to scrambled Sobol'")
    print(f"{'family':34s} cells " + " ".join(f"{c:>6s}" for c in CANDS))
    fams = []
    for r in rows:
        if r[1] not in fams:
            fams.append(r[1])
    groups = [(f, [r for r in rows if r[1] == f]) for f in fams]
    groups += [(f"ALL {b}", [r for r in rows if r[0] == b]) for b in ("genz", "uq")]
    groups += [("ALL both", rows)]
    for name, rs in groups:
        if rs:
            print(f"{name:34s} {len(rs):5d} " + " ".join(
                f"{gm([r[4][c] for r in rs]):6.2f}" for c in CANDS))
    both = [gm([r[4][c] for r in rows if r[0] == b]) for b in ("genz", "uq") for c in CANDS]
    if GRID == "both":
        print("mean of the two benchmarks' geometric means: " + " ".join(
            f"{c}={math.sqrt(both[i] * both[i + len(CANDS)]):.2f}" for i, c in enumerate(CANDS)))


if __name__ == "__main__":
    main()
