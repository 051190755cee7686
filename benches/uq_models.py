#!/usr/bin/env python3
"""The benchmark of the models users bring: integrals against input laws (normal,
lognormal, uniform; Brownian paths), stillpoint called with the laws against the point
sets a UQ user would pick, every error relative to scrambled Sobol'.

Setup (a venv of its own, the package from this tree):

    python3 -m venv target/bench-venv
    target/bench-venv/bin/pip install numpy scipy qmcpy "maturin>=1.16,<2"
    PATH=$PWD/target/bench-venv/bin:$PATH PYO3_PYTHON=$PWD/target/bench-venv/bin/python \\
        target/bench-venv/bin/python -m pip install --no-build-isolation --no-deps ./python

Run:

    PY=target/bench-venv/bin/python
    $PY benches/uq_models.py --check        # every closed form against 2^20 Sobol' points
    $PY benches/uq_models.py --quick        # 5 min: n = 1024, 4096, 8 reps, 4 instances
    $PY benches/uq_models.py --mid          # results/uq-models' grid: n = 1024, 4096,
                                            # 16384 (only up to s = 20), 16 reps, 4
                                            # instances (33 min on 2 shared cores)
    $PY benches/uq_models.py                # the full grid: n = 1024, 4096, 10000, 16384,
                                            # 65536, 64 reps, 8 instances: about 20 h on 2
                                            # shared cores (15 h the randomised sets, 4 h
                                            # the designs; the mid grid's times scaled by
                                            # n·s·reps·instances)
    ... --families keister,asian   only the families whose name contains one of these
                                   (also with --check)
    ... --n 1024,4096  --reps 64  --instances 8  --seeds 1,2,3  --out DIR  --fresh
    ... --variants 'm = 32;s = 10'   only variants whose label contains one of these
    ... --big-n-max-d 20           n above 4096 only up to this dimension (--mid: 20)
    ... --refine                   cells whose reference is too coarse measured again,
                                   with long runs 4× as long (the report lists them)
    ... --path-space brownian      path families given to stillpoint as
                                   W=brownian(T,m,construction), one per asset (the
                                   space a user writes for a path; the report says
                                   which method's cells were given it)

Every finished cell (family, variant, n) is stored in DIR/uq_models.json at once; a
rerun skips it unless --fresh (or unless it was measured with fewer reps or instances).
DIR/uq_models.md is made from everything the json holds. Reference values without a
closed form are long runs cached in DIR/references.json with their standard errors.

The families (benches/uq_families.py; instances from seed 20261145, used nowhere else):
Keister (s = 2, 5, 10, 20; normal inputs), Genz's oscillatory and Gaussian with normal
inputs (s = 2, 5, 10, 20), a lognormal product (s = 5, 10, 20, 50), Morokoff–Caflisch
(s = 5, 10, 20), Ishigami, Sobol' G (s = 6, 10, 20), wing weight, piston, OTL circuit
and robot arm with mixed laws, an arithmetic Asian call and a four-asset basket Asian
call (m = 32, 64, 256 normals; standard, Brownian-bridge and PCA paths).

The methods, every one on the same instances and the same code of f:

* ``default``: ``stillpoint.design(n, space, seed=K)`` (what ``generate(n, space=...)``
  tabulates: the integration goal, columns already in the laws), K = 1, 2, 3;
  deterministic, so its RMSE is over instances × seeds. Families whose laws vary per
  instance make one design per instance.
* ``randomize``: ``design(n, space, seed=r, randomize=True)``; when the library refuses
  a randomisation under a space (main today), the randomisation of
  ``generate(n, d, randomize=True)`` (drawn as ``Engine(d, draws='independent',
  seed=r).random(n)``, which makes the set once per process) mapped by the peers' map,
  labelled "randomize (cube, mapped)".
* ``engine``: ``stillpoint.Engine(d, seed=r).random(n)`` through the peers' map (above
  the sequence's 100 dimensions ``draws='independent'``, noted in the cell).
* ``sobol``: SciPy's ``Sobol(d, scramble=True)``, the reference every ratio divides by;
  ``halton``: SciPy's scrambled Halton; ``lattice``: QMCPy's ``Lattice(d)`` (random
  shift, its default vector), ``lattice-tent``: the same, then x → 1 − |2x − 1|;
  ``dnet``: QMCPy's ``DigitalNetB2(d)`` (LMS + digital shift). At n not a power of two
  the first n points of the next power of two. Peers map the cube through the laws'
  quantiles, Φ⁻¹ at x clipped to [2^-53, 1 − 2^-53].

Error: e = (Q − I)/|I| per instance; a method's figure per cell is the RMS of e over its
instances and randomisations (--reps, default 64; seeds for the default), the ratio that
over scrambled Sobol''s. Reported: per cell every ratio, per family the geometric mean
over its cells, the geometric mean over all cells, and the cells and families where
stillpoint loses. A reference without a closed form is accurate enough in a cell when its
relative standard error is at most a tenth of the smallest RMSE there; the report flags
the cells where it is not.
"""

import argparse
import hashlib
import json
import math
import os
import shlex
import sys
import time
import warnings

import numpy as np
from scipy.stats import qmc

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from large_n import (_prefix, _seeded, gmean, machine, now, save_json,  # noqa: E402
                     sobol_set)
from uq_families import (BY_NAME, FAMILIES, UQ_SEED, PathOption, cached_path_matrix,  # noqa: E402
                         instance, law_text, map_cube)

N_FULL = [1024, 4096, 10000, 16384, 65536]
N_MID = [1024, 4096, 16384]
N_QUICK = [1024, 4096]
METHODS = ["default", "randomize", "engine", "sobol", "halton", "lattice", "lattice-tent",
           "dnet"]
LABEL = {
    "default": "stillpoint default (space=)",
    "randomize": "stillpoint randomize (space=)",
    "randomize-cube": "stillpoint randomize (cube, mapped)",
    "engine": "stillpoint Engine(d), mapped",
    "sobol": "SciPy scrambled Sobol'",
    "halton": "SciPy scrambled Halton",
    "lattice": "QMCPy Lattice (shift, no tent)",
    "lattice-tent": "QMCPy Lattice + tent",
    "dnet": "QMCPy DigitalNetB2",
}
SHORT = {"default": "default", "randomize": "randomize", "engine": "Engine",
         "sobol": "Sobol'", "halton": "Halton", "lattice": "lattice", "lattice-tent":
         "lattice+tent", "dnet": "dnet"}
OURS = ["default", "randomize", "engine"]
CHUNK = 8192
REF_SEED = 777000  # Sobol' seeds of the long runs: not the methods' 0..reps-1
QUICK_VARIANTS = {  # family -> variants kept by --quick
    "keister": [5, 20], "genz oscillatory (normal)": [10], "genz gaussian (normal)": [10],
    "lognormal product": [20], "morokoff-caflisch": [10], "ishigami": [3],
    "sobol g": [10], "wing weight": [0], "piston": [0], "otl circuit": [0],
    "robot arm": [0], "asian call": [(64, "standard"), (64, "pca")],
    "basket asian call": [(64, "bridge")],
}


def log(msg):
    print(msg, file=sys.stderr, flush=True)


# ---------------------------------------------------------------- integration

def means_on(family, v, insts, sets, is_path=False):
    """Q per instance: sets(i) gives instance i's inputs (the same array object for
    instances that share laws, which are then prepared once per chunk)."""
    arrays = [sets(i) for i in range(len(insts))]
    n = arrays[0].shape[0]
    sums = np.zeros(len(insts))
    for lo in range(0, n, CHUNK):
        prepared = {}
        for i, p in enumerate(insts):
            key = id(arrays[i])
            if key not in prepared:
                prepared[key] = family.prepare(v, arrays[i][lo:lo + CHUNK], is_path)
            sums[i] += family.value(v, p, prepared[key]).sum()
    return sums / n


def cube_sets(family, v, insts, U):
    """The peers' map of one cube set, once per distinct list of laws."""
    cache = {}

    def get(i):
        laws = family.laws(v, insts[i])
        key = tuple((name, tuple(float(x) if not isinstance(x, str) else x for x in law))
                    for name, law in laws)
        if key not in cache:
            cache[key] = map_cube(laws, U)
        return cache[key]
    return get


_DESIGNS = {}  # (n, seed, space, options) -> columns: variants sharing a space share it


def design_sets(family, v, insts, n, seed, path_space, **kw):
    """stillpoint's design under each instance's space (one per distinct space; kept
    for the process, so the three path constructions and the two option families, whose
    spaces are the same m normals, make it once)."""
    import stillpoint

    def get(i):
        laws = family.space_laws(v, insts[i], path_space)
        texts = tuple(law_text(name, law) for name, law in laws)
        key = (n, seed, texts, tuple(sorted(kw.items())))
        if key not in _DESIGNS and kw.get("randomize") and _law_set_columns(
                n, texts, seed, key):
            return _DESIGNS[key]
        if key not in _DESIGNS:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                d = stillpoint.design(n, list(texts), seed=seed, **kw)
            if len(_DESIGNS) >= 24:
                _DESIGNS.pop(next(iter(_DESIGNS)))
            _DESIGNS[key] = np.column_stack([np.asarray(d.columns[name], dtype=np.float64)
                                             for name in d.names])
        return _DESIGNS[key]
    return get


_LAW_CHECKED = {}  # space -> its rule, once its columns were checked against design()'s


def _law_set_columns(n, texts, seed, key):
    """``design(n, texts, seed=seed, randomize=True)``'s columns without its figures
    (an O(n²) pass per set): the unit set of the space's rule, through the library's
    inverse-CDF map (``_core.space_values``): for a space of unbounded laws the lattice
    made for the laws (``_core.law_set``), for a space holding a Brownian path
    Owen-scrambled Sobol' (``generate(n, d, method='sobol', seed=seed)``). Checked bit
    for bit against ``design`` once per space; False where the package has no
    ``law_set`` or the space takes another rule."""
    import stillpoint
    core = stillpoint._core
    if not hasattr(core, "law_set"):
        return False

    def unit(rule, m, order=None):
        if rule.startswith("lattice made for the laws"):
            return core.law_set(list(texts), m, seed)
        d = len(core.space_names(list(texts)))
        net = np.asarray(stillpoint.generate(m, d, method="sobol", seed=seed))
        # the net's columns as the rule deals them to the space's coordinates
        return net if order is None else net[:, order]

    if texts not in _LAW_CHECKED:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            d = stillpoint.design(min(n, 256), list(texts), seed=seed, randomize=True)
        if not d.rule.startswith(("lattice made for the laws", "Owen-scrambled Sobol'")):
            return False
        order = None
        if d.rule.startswith("Owen-scrambled Sobol'"):
            net = unit(d.rule, min(n, 256))
            order = [next(i for i in range(net.shape[1])
                          if np.array_equal(net[:, i], d.unit[:, j]))
                     for j in range(net.shape[1])]
        x = core.space_values(list(texts), unit(d.rule, min(n, 256), order), None)
        cols = np.column_stack([np.asarray(d.columns[nm], dtype=np.float64)
                                for nm in d.names])
        if not np.array_equal(x, cols):
            raise SystemExit(f"the rule's set differs from design(randomize=True) for {texts}")
        _LAW_CHECKED[texts] = (d.rule, order)
    rule, order = _LAW_CHECKED[texts]
    _DESIGNS[key] = core.space_values(list(texts), unit(rule, n, order), None)
    if len(_DESIGNS) > 24:
        _DESIGNS.pop(next(iter(_DESIGNS)))
    return True


def stored_cells(ns, families=None, max_d=None):
    """The cells of results/uq-models/uq_models.json at the sizes `ns` (of the families
    whose names contain one of the comma-separated `families`; of at most `max_d`
    coordinates), each as (cell, family, variant, instances, reference values, scrambled
    Sobol''s stored RMSE): what the prototypes that read the stored denominators share."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = os.path.join(root, "results", "uq-models", "uq_models.json")
    for c in json.load(open(path))["cells"].values():
        if c["n"] not in ns or (families and not any(f in c["family"]
                                                     for f in families.split(","))):
            continue
        if max_d is not None and c["d"] > max_d:
            continue
        fam = BY_NAME[c["family"]]
        v = next(v for v in fam.variants if fam.label(v) == c["variant"])
        insts = [instance(fam, v, i) for i in range(c["instances"])]
        yield c, fam, v, insts, np.array(c["reference"]), c["methods"]["sobol"]["rmse"]


def relative(q, ref):
    return (q - ref[:, 0]) / np.abs(ref[:, 0])


# ---------------------------------------------------------------- the peers

def halton_set(s, n, r):
    return _seeded(qmc.Halton, s, scramble=True, r=r).random(n)


def lattice_set(s, n, r):
    import qmcpy
    return _prefix(qmcpy.Lattice(s, seed=r), n)


def lattice_tent_set(s, n, r):
    return 1.0 - np.abs(2.0 * lattice_set(s, n, r) - 1.0)


def dnet_set(s, n, r):
    import qmcpy
    return _prefix(qmcpy.DigitalNetB2(s, seed=r), n)


def engine_set(s, n, r):
    import stillpoint
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return stillpoint.Engine(s, seed=r).random(n), None
        except ValueError as e:
            note = f"Engine({s}) refused ({e}); draws='independent'"
            return stillpoint.Engine(s, seed=r, draws="independent").random(n), note


def randomize_cube_set(s, n, r):
    """generate(n, d, randomize=True)'s randomisation (the lattice made for the shift and
    the tent transform), drawn through Engine(d, draws='independent'), which makes that
    set once per process instead of once per call."""
    import stillpoint
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return stillpoint.Engine(s, seed=1000 + r, draws="independent").random(n)


PEERS = {"sobol": sobol_set, "halton": halton_set, "lattice": lattice_set,
         "lattice-tent": lattice_tent_set, "dnet": dnet_set}


def probe(kind):
    """Whether the library takes a randomisation / a Brownian variable under a space
    (None) or its refusal's message."""
    import stillpoint
    space = ["x=normal(0.0,1.0)"] if kind == "randomize" else ["W=brownian(1.0,4,pca)"]
    kw = {"randomize": True} if kind == "randomize" else {}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            stillpoint.design(16, space, seed=1, **kw)
        return None
    except (ValueError, TypeError) as e:
        return f"{type(e).__name__}: {e}"


# ---------------------------------------------------------------- references

def params_digest(p):
    def plain(x):
        if isinstance(x, dict):
            return {k: plain(v) for k, v in sorted(x.items())}
        if isinstance(x, (list, tuple)):
            return [plain(v) for v in x]
        if isinstance(x, np.ndarray):
            return [float(v) for v in x.ravel()]
        return float(x) if isinstance(x, (float, np.floating)) else x
    return hashlib.sha256(json.dumps(plain(p)).encode()).hexdigest()[:16]


def long_run(family, v, p, log2n, reps):
    """Scrambled Sobol' (seeds REF_SEED + r): per replicate the mean of f, or for path
    families the geometric call's closed form plus the mean of (arithmetic − geometric)
    on PCA paths. Returns (value, standard error, per-replicate values)."""
    vals = []
    d = family.dim(v)
    if isinstance(family, PathOption):
        v = (v[0], "pca")
        geo = family.geometric_exact(v, p)
    for r in range(reps):
        U = _seeded(qmc.Sobol, d, scramble=True, r=REF_SEED + r).random_base2(log2n)
        total = 0.0
        for lo in range(0, U.shape[0], CHUNK):
            X = map_cube(family.laws(v, p), U[lo:lo + CHUNK])
            P = family.prepare(v, X)
            if isinstance(family, PathOption):
                a, g = family.payoffs(v, p, P)
                total += (a - g).sum()
            else:
                total += family.value(v, p, P).sum()
        vals.append(total / U.shape[0] + (geo if isinstance(family, PathOption) else 0.0))
    vals = np.array(vals)
    return float(vals.mean()), float(vals.std(ddof=1) / math.sqrt(reps)), vals.tolist()


def reference(family, v, i, p, store, path, boost=0):
    """The closed form, or the cached long run (made again, 4^boost times longer, when
    the cached one is shorter than that)."""
    exact = family.exact(v, p)
    if exact is not None:
        return float(exact), 0.0
    key = family.ref_key(v, i)
    digest = params_digest(p)
    rec = store.get(key)
    log2n, reps = (16, 16) if isinstance(family, PathOption) else (18, 16)
    log2n += 2 * boost
    if rec is None or rec["params"] != digest or rec["n"] < 2 ** log2n:
        t0 = time.perf_counter()
        val, se, vals = long_run(family, v, p, log2n, reps)
        rec = {"value": val, "se": se, "params": digest, "n": 2 ** log2n, "reps": reps,
               "how": ("scrambled Sobol', PCA paths, geometric-average call as control "
                       "variate (coefficient 1)") if isinstance(family, PathOption)
               else "scrambled Sobol' through the laws' quantiles",
               "replicates": vals, "seconds": time.perf_counter() - t0, "date": now()}
        store[key] = rec
        save_json(path, store)
        log(f"  reference {key}: {val:.10g} ± {se:.2g} ({rec['seconds']:.1f} s)")
    return rec["value"], rec["se"]


# ---------------------------------------------------------------- a cell

def run_cell(family, v, n, a, refs, refs_path, notes, boost=0):
    insts = [instance(family, v, i) for i in range(a.instances)]
    ref = np.array([reference(family, v, i, p, refs, refs_path, boost)
                    for i, p in enumerate(insts)])
    d = family.dim(v)
    is_path = a.path_space == "brownian" and isinstance(family, PathOption)
    cell = {"family": family.name, "variant": family.label(v), "n": n, "d": d,
            "instances": a.instances, "reps": a.reps, "seeds": a.seeds,
            "reference_rel_se": float(np.max(ref[:, 1] / np.abs(ref[:, 0]))),
            "reference": ref.tolist(), "methods": {}, "failures": {}, "notes": [],
            "date": now(), "path_space": a.path_space if isinstance(family, PathOption)
            else None}
    for m in a.methods:
        t0 = time.perf_counter()
        errs, label = [], LABEL[m]
        try:
            if m == "default":
                for k in a.seeds:
                    q = means_on(family, v, insts,
                                 design_sets(family, v, insts, n, k, a.path_space), is_path)
                    errs.append(relative(q, ref))
            elif m == "randomize" and notes.get("randomize") is None:
                for r in range(a.reps):
                    q = means_on(family, v, insts, design_sets(
                        family, v, insts, n, 1000 + r, a.path_space, randomize=True), is_path)
                    errs.append(relative(q, ref))
            else:
                if m == "randomize":
                    make, label = randomize_cube_set, LABEL["randomize-cube"]
                elif m == "engine":
                    make = None
                else:
                    make = PEERS[m]
                for r in range(a.reps):
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        if make is None:
                            U, note = engine_set(d, n, r)
                            if note and note not in cell["notes"]:
                                cell["notes"].append(note)
                        else:
                            U = make(d, n, r)
                    U = np.asarray(U, dtype=np.float64)
                    if U.shape != (n, d):
                        raise RuntimeError(f"shape {U.shape}, expected {(n, d)}")
                    errs.append(relative(means_on(family, v, insts,
                                                  cube_sets(family, v, insts, U)), ref))
        except Exception as e:  # noqa: BLE001 — recorded, the cell goes on
            cell["failures"][m] = f"{type(e).__name__}: {str(e)[:400]}"
            log(f"  {m} FAILED: {cell['failures'][m]}")
            continue
        e = np.array(errs)
        cell["methods"][m] = {"label": label, "rmse": float(np.sqrt(np.mean(e ** 2))),
                              "sets": len(errs), "seconds": time.perf_counter() - t0,
                              "instance_rmse": np.sqrt(np.mean(e ** 2, axis=0)).tolist()}
        if isinstance(family, PathOption) and m in ("default", "randomize"):
            # what stillpoint was given: m normals, or the path as one variable
            cell["methods"][m]["path_space"] = a.path_space
    base = cell["methods"].get("sobol", {}).get("rmse")
    for rec in cell["methods"].values():
        rec["ratio"] = rec["rmse"] / base if base else None
    rmses = [r["rmse"] for r in cell["methods"].values() if r["rmse"] > 0]
    cell["smallest_rmse"] = min(rmses) if rmses else None
    cell["reference_ok"] = (cell["smallest_rmse"] is None
                            or cell["reference_rel_se"] <= 0.1 * cell["smallest_rmse"])
    return cell


# ---------------------------------------------------------------- report

def fmt(v):
    if v is None or not math.isfinite(v):
        return "—"
    return f"{v:.2f}" if 0.01 <= v < 100 else f"{v:.1e}"


def bold_if_over(v, bound=1.0):
    t = fmt(v)
    return f"**{t}**" if v is not None and v > bound else t


def cell_order(cells):
    """Families in their list's order, variants in their family's, then n."""
    rank = {}
    for i, f in enumerate(FAMILIES):
        for j, v in enumerate(f.variants):
            rank[(f.name, f.label(v))] = (i, j)
    return sorted(cells, key=lambda c: (rank.get((c["family"], c["variant"]), (99, 0)),
                                        c["n"]))


def report(data):
    cells = cell_order(data["cells"].values())
    methods = [m for m in METHODS if m != "sobol"]
    lines = ["# The models users bring: integrals against input laws", "",
             "Made by `benches/uq_models.py` (see its header for every definition). Runs "
             "that wrote `uq_models.json` (newest last):", ""]
    for run in data["runs"]:
        mc = run["machine"]
        took = f", {run['seconds'] / 60:.1f} min" if "seconds" in run else ""
        lines.append(f"- `{run['command']}` — {run['date']}{took}, commit "
                     f"{mc.get('commit', '?')}, stillpoint {run.get('stillpoint', '?')}, "
                     f"{mc['nproc']} cores ({mc['cpu']}), load {mc['load']}, Python "
                     f"{mc['python']}, NumPy {mc['numpy']}, SciPy {mc['scipy']}, QMCPy "
                     f"{mc['qmcpy']}")
    probes = data.get("probes", {})
    lines += ["", "Full grid (not run here): `benches/uq_models.py` (n = 1 024 … 65 536, 64 "
              "reps, 8 instances), about 20 h on 2 shared cores (15 h the randomised sets, 4 h "
              "the designs; this run's times scaled by n·s·reps·instances).", "",
              f"Instances from seed {UQ_SEED}; error e = (Q − I)/|I| per instance; every "
              "figure is a method's RMS of e over instances and randomisations (the "
              "default: over instances and seeds 1–3) divided by scrambled Sobol''s on the "
              "same instances. **Bold**: above 1 (stillpoint loses to scrambled Sobol').", ""]
    if probes.get("randomize"):
        lines += ["`randomize` under a space is refused by this build "
                  f"(`{probes['randomize']}`), so the randomize column is "
                  "\"randomize (cube, mapped)\": `generate(n, d, randomize=True)`'s "
                  "randomisation (the lattice made for the shift and the tent transform), "
                  "drawn as `Engine(d, draws='independent', seed=r).random(n)` (which makes "
                  "the set once per process), mapped by the peers' map.", ""]
    given = {}  # (method, path space) -> path cells; records without one: normals
    for c in data["cells"].values():
        if c.get("path_space"):
            for m in ("default", "randomize"):
                if m in c["methods"]:
                    ps = c["methods"][m].get("path_space", "normals")
                    given[(m, ps)] = given.get((m, ps), 0) + 1
    for m in ("default", "randomize"):
        if given.get((m, "brownian")):
            rest = given.get((m, "normals"), 0)
            lines += [f"Path families, `{m}`: {given[(m, 'brownian')]} cells give stillpoint "
                      "the path as one variable, `W=brownian(1,m,construction)` per asset "
                      "(the space a user writes for a path)"
                      + (f", the other {rest} m normals with the path built in the function"
                         if rest else "") + ".", ""]
    if probes.get("brownian"):
        lines += ["A Brownian variable in a space is refused by this build "
                  f"(`{probes['brownian']}`): path families give stillpoint m normals and "
                  "build the path in the function (the HOOK in benches/uq_families.py).", ""]

    # the geometric means
    def gm(cs, m):
        return gmean([c["methods"][m]["ratio"] for c in cs
                      if m in c["methods"] and c["methods"][m].get("ratio")])
    fams = []
    for c in cells:
        if c["family"] not in fams:
            fams.append(c["family"])
    lines += ["## Geometric mean of the ratio to scrambled Sobol'", "",
              "| family | cells | " + " | ".join(SHORT[m] for m in methods) + " |",
              "|---|---|" + "---|" * len(methods)]
    for f in fams:
        cs = [c for c in cells if c["family"] == f]
        lines.append(f"| {f} | {len(cs)} | "
                     + " | ".join(bold_if_over(gm(cs, m)) for m in methods) + " |")
    lines.append(f"| **all cells** | {len(cells)} | "
                 + " | ".join(bold_if_over(gm(cells, m)) for m in methods) + " |")
    lines.append("")
    by_n = sorted({c["n"] for c in cells})
    if len(by_n) > 1:
        lines += ["Per n (all families):", "", "| n | cells | "
                  + " | ".join(SHORT[m] for m in methods) + " |",
                  "|---|---|" + "---|" * len(methods)]
        for n in by_n:
            cs = [c for c in cells if c["n"] == n]
            lines.append(f"| {n} | {len(cs)} | "
                         + " | ".join(bold_if_over(gm(cs, m)) for m in methods) + " |")
        lines.append("")

    paths = [c for c in cells if c["family"] in {f.name for f in FAMILIES
                                                  if isinstance(f, PathOption)}]
    if paths:
        lines += ["Path families by construction (both options, every m and n):", "",
                  "| construction | cells | " + " | ".join(SHORT[m] for m in methods) + " |",
                  "|---|---|" + "---|" * len(methods)]
        for con in ("standard", "bridge", "pca"):
            cs = [c for c in paths if c["variant"].endswith(con)]
            lines.append(f"| {con} | {len(cs)} | "
                         + " | ".join(bold_if_over(gm(cs, m)) for m in methods) + " |")
        lines.append("")

    # where stillpoint loses
    lines += ["## Where stillpoint loses", "",
              "The targets: the default and `randomize` ≤ 1.1 in every family's geometric "
              "mean and ≤ 0.7 over all cells; `Engine` ≤ 1.5 in every family.", ""]
    for m in OURS:
        over = [(f, gm([c for c in cells if c["family"] == f], m)) for f in fams]
        bound = 1.5 if m == "engine" else 1.1
        over = [(f, g) for f, g in over if g is not None and g > bound]
        allg = gm(cells, m)
        lost = [c for c in cells if m in c["methods"] and (c["methods"][m].get("ratio") or 0) > 1]
        lines.append(f"- **{SHORT[m]}**: over all cells {fmt(allg)}"
                     + (" (above 0.7)" if allg is not None and allg > 0.7 and m != "engine"
                        else "")
                     + f"; above Sobol' in {len(lost)} of "
                     f"{sum(m in c['methods'] for c in cells)} cells; families above {bound}: "
                     + (", ".join(f"{f} {fmt(g)}" for f, g in over) if over else "none") + ".")
        worst = sorted(lost, key=lambda c: -c["methods"][m]["ratio"])[:5]
        if worst:
            lines.append("  Worst: " + "; ".join(
                f"{c['family']} {c['variant']} n = {c['n']}: {fmt(c['methods'][m]['ratio'])}"
                for c in worst) + ".")
    best = {}
    for c in cells:
        rs = {m: r["ratio"] for m, r in c["methods"].items() if r.get("ratio")}
        if rs:
            w = min(rs, key=rs.get)
            best[w] = best.get(w, 0) + 1
    lines += ["", "Lowest RMSE per cell: " + ", ".join(
        f"{SHORT[m]} {k}" for m, k in sorted(best.items(), key=lambda t: -t[1])) + ".", ""]

    # references
    bad = [c for c in cells if not c.get("reference_ok", True)]
    lines += ["## Reference values", "",
              "Closed forms where they exist (Keister, Genz with normal inputs, lognormal "
              "product, Morokoff–Caflisch, Ishigami, Sobol' G); the engineering models and "
              "the options by long runs cached in `references.json` (engineering: 16 "
              "scrambled Sobol' sets of 2^18 points; options: 16 sets of 2^16 points on PCA "
              "paths with the geometric-average call's closed form as control variate; 4× "
              "longer where `--refine` found them too coarse for a cell), each with its "
              "standard error; every cell keeps the reference values it was scored with. "
              "A cell's reference is accurate enough when its "
              "largest relative standard error is at most a tenth of the smallest RMSE in "
              "the cell.", ""]
    if bad:
        lines.append("Cells where it is not (their ratios are bounded below by the "
                     "reference's own error):")
        lines += [f"- {c['family']} {c['variant']} n = {c['n']}: reference rel. s.e. "
                  f"{c['reference_rel_se']:.1e} > 0.1 × {c['smallest_rmse']:.1e}" for c in bad]
    else:
        lines.append("Every cell's reference is accurate to a tenth of its smallest RMSE.")
    lines.append("")

    # every cell
    lines += ["## Every cell", "",
              "Sobol' column: its RMS relative error (the denominator); the others: the "
              "ratio to it.", "",
              "| family | variant | n | Sobol' | " + " | ".join(SHORT[m] for m in methods)
              + " | ref ok |", "|---|---|---|---|" + "---|" * len(methods) + "---|"]
    for c in cells:
        sob = c["methods"].get("sobol", {}).get("rmse")
        vals = []
        for m in methods:
            r = c["methods"].get(m)
            vals.append("—" if r is None or r.get("ratio") is None else bold_if_over(r["ratio"]))
        lines.append(f"| {c['family']} | {c['variant']} | {c['n']} | {fmt(sob)} | "
                     + " | ".join(vals) + f" | {'yes' if c.get('reference_ok', True) else 'no'} |")
    lines.append("")
    notes = sorted({(c["family"], c["variant"], note) for c in cells for note in c["notes"]})
    fails = [(c["family"], c["variant"], c["n"], m, why) for c in cells
             for m, why in c["failures"].items()]
    if notes:
        lines += ["Notes: "] + [f"- {f} {v}: {t}" for f, v, t in notes] + [""]
    if fails:
        lines += ["Failed or refused (—):", ""]
        lines += [f"- {f} {v} n = {n}, {SHORT[m]}: {why}" for f, v, n, m, why in fails] + [""]
    lines += ["## Times", "", "Seconds per cell and method (whole cell: all sets, all "
              "instances), summed over the cells:", ""]
    tot = {m: sum(c["methods"][m]["seconds"] for c in cells if m in c["methods"])
           for m in METHODS}
    lines.append(", ".join(f"{SHORT[m]} {t:.0f} s" for m, t in tot.items()) + ".")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- --check

def check(a):
    """Every closed form against a 2^20-point scrambled Sobol' estimate (8 sets of 2^17)
    within 5 standard errors; the path matrices' covariance; the geometric call."""
    ok = True
    wanted = [w.strip() for w in a.families.split(",")] if a.families else None
    for fam in FAMILIES:
        if wanted and not any(w in fam.name for w in wanted):
            continue
        for v in fam.variants:
            if isinstance(fam, PathOption):
                if v[1] != "pca" and v[0] != 32:
                    continue
                A = cached_path_matrix(v[0] // fam.assets, fam.T, v[1])
                k = v[0] // fam.assets
                t = fam.T * np.arange(1, k + 1) / k
                err = np.abs(A @ A.T - np.minimum.outer(t, t)).max()
                good = err < 1e-12
                ok &= good
                log(f"{'ok ' if good else 'BAD'} {fam.name} {fam.label(v)}: "
                    f"|A Aᵀ − min(t_i, t_j)| = {err:.1e}")
            for i in range(2):
                p = instance(fam, v, i)
                if isinstance(fam, PathOption):
                    exact = fam.geometric_exact(v, p)

                    class Geo:  # the geometric call through the same code
                        def __getattr__(self, k):
                            return getattr(fam, k)

                        def value(self, v, p, B):
                            return fam.payoffs(v, p, B)[1]
                    target = Geo()
                    what = "geometric call"
                else:
                    exact = fam.exact(v, p)
                    target = fam
                    what = "closed form"
                if exact is None:
                    continue
                vals = []
                for r in range(8):
                    U = _seeded(qmc.Sobol, fam.dim(v), scramble=True,
                                r=REF_SEED + 100 + r).random_base2(17)
                    tot = 0.0
                    for lo in range(0, U.shape[0], CHUNK):
                        X = map_cube(fam.laws(v, p), U[lo:lo + CHUNK])
                        tot += target.value(v, p, fam.prepare(v, X)).sum()
                    vals.append(tot / U.shape[0])
                est, se = np.mean(vals), np.std(vals, ddof=1) / math.sqrt(8)
                z = abs(est - exact) / max(se, 1e-13 * abs(exact))
                good = z <= 5
                ok &= good
                log(f"{'ok ' if good else 'BAD'} {fam.name} {fam.label(v)} instance {i}: "
                    f"{what} {exact:.12g}, 2^20 Sobol' {est:.12g} ± {se:.1e} ({z:.1f} s.e.)")
    log("every check passed" if ok else "SOME CHECKS FAILED")
    return ok


# ---------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="n = 1024, 4096, a few variants")
    ap.add_argument("--mid", action="store_true", help="n = 1024, 4096, 16384, 16 reps")
    ap.add_argument("--check", action="store_true", help="the closed forms, then exit")
    ap.add_argument("--n", help="comma-separated sizes")
    ap.add_argument("--reps", type=int)
    ap.add_argument("--instances", type=int)
    ap.add_argument("--seeds", default="1,2,3", help="the default's seeds")
    ap.add_argument("--families", help="comma-separated substrings of family names")
    ap.add_argument("--variants", help="only variants whose label contains one of these "
                    "(';'-separated), e.g. 'm = 32;m = 64'")
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--path-space", choices=["normals", "brownian"], default="normals")
    ap.add_argument("--big-n-max-d", type=int,
                    help="n above 4096 only up to this dimension (--mid: 20)")
    ap.add_argument("--out", default="results/uq-models")
    ap.add_argument("--fresh", action="store_true")
    ap.add_argument("--refine", action="store_true",
                    help="measure again the stored cells whose reference is not accurate "
                    "to a tenth of their smallest RMSE, with long runs 4× longer")
    a = ap.parse_args()
    if a.check:
        sys.exit(0 if check(a) else 1)
    a.n = ([int(x) for x in a.n.split(",")] if a.n else N_QUICK if a.quick
           else N_MID if a.mid else N_FULL)
    a.reps = a.reps or (8 if a.quick else 16 if a.mid else 64)
    a.instances = a.instances or (4 if (a.quick or a.mid) else 8)
    a.seeds = [int(x) for x in a.seeds.split(",")]
    if a.big_n_max_d is None and a.mid:
        a.big_n_max_d = 20
    a.methods = [m for m in a.methods.split(",") if m]
    if "sobol" not in a.methods:
        a.methods.append("sobol")
    import stillpoint

    os.makedirs(a.out, exist_ok=True)
    json_path = os.path.join(a.out, "uq_models.json")
    refs_path = os.path.join(a.out, "references.json")
    data = json.load(open(json_path)) if os.path.exists(json_path) else {}
    data.setdefault("cells", {})
    data.setdefault("runs", [])
    refs = json.load(open(refs_path)) if os.path.exists(refs_path) else {}
    probes = {"randomize": probe("randomize"), "brownian": probe("brownian")}
    data["probes"] = probes
    if a.path_space == "brownian" and probes["brownian"]:
        sys.exit(f"--path-space brownian: this build refuses it: {probes['brownian']}")
    log(f"probes: {probes}")
    data["runs"].append({"command": shlex.join(["python", "benches/uq_models.py"]
                                               + sys.argv[1:]),
                         "date": now(), "machine": machine(),
                         "stillpoint": stillpoint.__version__})

    def write():
        save_json(json_path, data)
        md = os.path.join(a.out, "uq_models.md")
        # The commit mark (a "## Fingerprints" section, see results/README.md) is
        # written by whoever checks what the cells describe; a rewrite keeps it.
        kept = ""
        if os.path.exists(md):
            old = open(md).read()
            if "\n## Fingerprints\n" in old:
                kept = old[old.index("\n## Fingerprints\n"):]
        with open(md, "w") as fh:
            fh.write(report(data).rstrip("\n") + "\n" + kept)

    wanted = [w.strip() for w in a.families.split(",")] if a.families else None
    vwanted = [w.strip() for w in a.variants.split(";")] if a.variants else None
    t_all = time.perf_counter()
    measured = 0
    for fam in FAMILIES:
        if wanted and not any(w in fam.name for w in wanted):
            continue
        variants = QUICK_VARIANTS.get(fam.name, fam.variants) if a.quick else fam.variants
        for v in variants:
            if vwanted and not any(w in fam.label(v) for w in vwanted):
                continue
            for n in a.n:
                if a.big_n_max_d and n > 4096 and fam.dim(v) > a.big_n_max_d:
                    continue
                key = f"{fam.name}|{fam.label(v)}|n={n}"
                old = data["cells"].get(key)
                boost = 0
                if (old is not None and not a.fresh and old["reps"] >= a.reps
                        and old["instances"] >= a.instances
                        and all(m in old["methods"] or m in old["failures"]
                                for m in a.methods)
                        # a randomize measured as the cube's set mapped, before the
                        # library took randomize under a space, is measured again
                        and old["methods"].get("randomize", {}).get("label")
                        != LABEL["randomize-cube"]):
                    if not (a.refine and not old.get("reference_ok", True)):
                        continue
                    boost = old.get("reference_boost", 0) + 1
                t0 = time.perf_counter()
                log(f"{key}" + (f" (reference 4^{boost} times longer)" if boost else ""))
                cell = run_cell(fam, v, n, a, refs, refs_path, probes, boost)
                if (old is not None and old["reps"] == cell["reps"]
                        and old["instances"] == cell["instances"]):
                    # Methods not measured again keep their figures (same instances and
                    # randomisations, so their ratios stand).
                    for m, r in old["methods"].items():
                        cell["methods"].setdefault(m, r)
                cell["reference_boost"] = boost
                cell["seconds"] = time.perf_counter() - t0
                data["cells"][key] = cell
                measured += 1
                log(f"  {cell['seconds']:.1f} s; ratios: " + " ".join(
                    f"{SHORT[m]} {fmt(r['ratio'])}" for m, r in cell["methods"].items()))
                write()
    if measured:
        data["runs"][-1]["seconds"] = time.perf_counter() - t_all
    else:  # everything was stored: only the report is made again
        data["runs"].pop()
    write()


if __name__ == "__main__":
    main()
