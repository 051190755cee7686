#!/usr/bin/env python3
"""The large-n benchmark: stillpoint's deterministic default from
512 to 10^6 points against scrambled Sobol', QMCPy's tent-transformed lattice, QMCPy's
order-2 interlaced digital net and SciPy's random-cd Latin hypercube, on Genz's six
families.

Setup (once; a venv of its own under target/, so the system Python is untouched):

    cargo build --release --bin stillpoint
    python3 -m venv target/bench-venv
    target/bench-venv/bin/pip install numpy scipy qmcpy

Run:

    target/bench-venv/bin/python benches/large_n.py                 # the full grid
    target/bench-venv/bin/python benches/large_n.py --sweep         # n = 1000..1100, s = 8
    target/bench-venv/bin/python benches/large_n.py --quick         # a handful of small cells
    target/bench-venv/bin/python benches/large_n.py --cells 5:1000,10:4096,1:2000
    target/bench-venv/bin/python benches/large_n.py --sweep --sweep-range 1000:1010
    ... --skip-peers     only the default and scrambled Sobol' (the reference)
    ... --out DIR        where large_n.md and large_n.json go (results/large-n)
    ... --fresh          measure the chosen cells again even if large_n.json has them
    ... --default-only   measure only the default's side again (its sets, errors and
                         discrepancies) and keep the stored Sobol' reference and peers:
                         they do not depend on stillpoint's build

Every finished cell (and every n of the sweep) is stored in DIR/large_n.json at once, and
a rerun skips it unless --fresh: an interrupted run goes on where it stopped. The report
DIR/large_n.md is made from everything large_n.json holds (the runs that made it are
listed in its header), so the grid and the sweep can be run as two commands.

How long (estimated from the quick cells on the project's 2 shared cores at load 3–4):
the full grid (76 cells) about 4 h: SciPy's random-cd LHS ~2 h of it (~5 s a set at
1 000 points, ~50 s at 10^4 × 10, ~5 min at 10^4 × 50), the integrands ~1 h (51 sets
per cell, 96 instances; each cell at 10^6 points ~15 min at s = 10), the discrepancies
~0.5 h (`eval --exact` at 65 536 and 10^5 points, s ≤ 2: ~40–90 s a set); plus the
default's own time, 3 runs per cell (the targets: ≤ 10 s a run up to 10^5 points at
s ≤ 10, ≤ 20 s at s ≤ 20, ≤ 60 s at 10^6 × 5). With --skip-peers about 1 h. The sweep
(101 n) takes ~1 min plus 303 runs of the default (~0.05 s each at 1 000 × 8 now).

What it measures, per cell (s, n), with the same metric code for every method:

* Integrands: Genz's six families from benches/anchors.py (oscillatory, product peak,
  corner peak, Gaussian, continuous, discontinuous), 16 instances per family (--instances)
  drawn from seed 20261126, a seed used nowhere else in this repository; exact integrals
  in closed form, the corner peak's by one quadrature of its Laplace representation.
  Relative error per instance e = (Q - I) / |I|; each method's figure per family is the
  root-mean-square of e over its instances and its sets (seeds or randomisations).
* The default: `stillpoint generate -n N -s S --seed K -o FILE` for K = 1, 2, 3; time is
  the wall time of the whole command (report included), the median of the three.
* Scrambled Sobol' (SciPy, `Sobol(d, scramble=True, rng=r)`, r = 0..15, `random(n)`):
  the reference every ratio divides by.
* QMCPy's lattice (`Lattice(d, seed=r)`, its default random shift), then the tent
  transform x -> 1 - |2x - 1|; 16 shifts; at n not a power of two the first n points of
  its (radical-inverse ordered, extensible) sequence.
* QMCPy's order-2 interlaced digital net `DigitalNetB2(d, seed=r, alpha=2)` (default
  randomisation: linear matrix scramble and digital shift); 16 randomisations; the first
  n points at n not a power of two.
* SciPy's `LatinHypercube(d, optimization="random-cd", rng=r)` up to n = 10^4 only:
  16 sets up to 1 024 points, 8 up to 2 000, 4 up to 4 096, 2 up to 10^4 (random-cd
  costs ~5 s a set at 1 000 points, ~50 s at 10^4 × 10).
* Discrepancies, up to n = 10^5 (--disc-max-n): `stillpoint eval FILE --json` (fields
  star_l2, centered_l2, the roots) on the default's three sets and on the first 4 Sobol'
  sets (--disc-sets); the default's mean over the Sobol' mean. eval's sums are exact up
  to 50 000 points; above, its random-pair estimate is too coarse (D_L2* of 65 536
  Sobol' points: 0 ± 2e-4), so `eval --exact` is used, which also computes every 2-D
  projection's star discrepancy exactly (s(s−1)/2 × O(n²)): only up to s = 2 by default
  (--disc-exact-max-s), the other cells say so and show "—".

A peer that fails at a size is recorded with its reason and shown as "—". The report has
per-cell tables, per s and family the geometric mean of each method's ratio, the bounds
(which one is missed and by how much), the times and
the sweep with its flags (an n whose ratio is above 1.3× the median of its ±5
neighbours).
"""

import argparse
import datetime
import hashlib
import json
import math
import os
import platform
import shlex
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np
import scipy
from scipy.stats import qmc

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fingerprint import digest, section  # noqa: E402
from anchors import FAMILIES, genz_exact, genz_instances, genz_value  # noqa: E402

INSTANCE_SEED = 20261126  # never used before in this repository
GRID_N = [1000, 1024, 2000, 4096, 10000, 16384, 65536, 100000]
GRID_S = [1, 2, 5, 10, 20, 50]
BIG_N, BIG_MAX_S = 1000000, 10
OFF_N = [512, 1500, 7919, 30000]
OFF_S = [3, 8, 12, 14, 15, 30]
QUICK = [(1, 2000), (5, 1000), (10, 4096), (3, 1500), (20, 1024)]
DEFAULT_SEEDS = [1, 2, 3]
REPLICATES = 16
CHUNK = 1 << 16
SHORT = ["osc", "prod", "corner", "gauss", "cont", "disc"]
METHODS = ["default", "sobol", "lattice-tent", "dnet-alpha2", "lhs-random-cd"]
LABEL = {
    "default": "stillpoint default",
    "sobol": "scrambled Sobol'",
    "lattice-tent": "QMCPy lattice + tent",
    "dnet-alpha2": "QMCPy DigitalNetB2 α=2",
    "lhs-random-cd": "SciPy LHS random-cd",
}
LHS_MAX_N = 10000
# The bounds: on the geometric mean over the cells of one s, and
# on every cell.
GM_BOUND = {0: 0.5, 1: 0.5, 3: 0.5, 2: 0.8, 4: 0.8}
CELL_BOUND = {0: 1.0, 1: 1.0, 2: 1.0, 3: 1.0, 4: 1.0, 5: 1.1}
SWEEP_FACTOR = 1.3
SWEEP_HALF = 5


def grid_cells():
    cells = [(s, n) for s in GRID_S for n in GRID_N]
    cells += [(s, BIG_N) for s in GRID_S if s <= BIG_MAX_S]
    cells += [(s, n) for s in OFF_S for n in OFF_N]
    return sorted(cells, key=lambda c: (c[0] * c[1], c[1]))


# ---------------------------------------------------------------- integrands

_INSTANCES = {}


def instances(s, count):
    key = (s, count)
    if key not in _INSTANCES:
        inst = genz_instances(s, count, INSTANCE_SEED)
        exact = np.array([genz_exact(f, a, u) for (f, a, u) in inst])
        _INSTANCES[key] = (inst, exact)
    return _INSTANCES[key]


def relative_errors(x, inst, exact):
    """e = (Q - I)/|I| for every instance; the set is read in chunks of CHUNK rows."""
    n = x.shape[0]
    sums = np.zeros(len(inst))
    for lo in range(0, n, CHUNK):
        c = np.ascontiguousarray(x[lo:lo + CHUNK], dtype=np.float64)
        for i, (f, a, u) in enumerate(inst):
            sums[i] += genz_value(f, a, u, c).sum()
    return (sums / n - exact) / np.abs(exact)


def family_rms(errs, count):
    """errs: sets × (6·count) relative errors -> RMS per family over sets and instances."""
    e = np.asarray(errs).reshape(len(errs), len(FAMILIES), count)
    return np.sqrt((e ** 2).mean(axis=(0, 2)))


# ---------------------------------------------------------------- the methods

EVAL_EXACT_UP_TO = 50000  # `stillpoint eval` forms its pair sums exactly up to here


def disc_plan(n, s, a):
    """(eval's extra flags, None) where the discrepancies are measured, else (None, why)."""
    if n > a.disc_max_n:
        return None, f"not measured above n = {a.disc_max_n}"
    if n <= EVAL_EXACT_UP_TO:
        return [], None
    if s <= a.disc_exact_max_s:
        return ["--exact"], None
    return None, (f"not measured: above {EVAL_EXACT_UP_TO} points eval estimates the sums "
                  "from random pairs (too coarse here: the estimate of D_L2* at 65 536 "
                  "Sobol' points is 0 ± 2e-4), and `eval --exact` also computes the "
                  "s(s−1)/2 two-dimensional star discrepancies exactly, O(n²) each "
                  f"(hours per set); run with --disc-exact-max-s {s} to pay for it")


def stillpoint_eval(binary, path, flags):
    cmd = [binary, "eval", path, "--json"] + flags
    out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    v = json.loads(out.stdout)
    if "estimate" in v:
        raise RuntimeError(f"eval estimated the discrepancies of {path}")
    return {"star_l2": v["star_l2"], "centered_l2": v["centered_l2"]}


def run_default(binary, n, s, seeds, tmp, timeout):
    """The default's sets for each seed: their paths, times, one report and the SHA-256
    of each set's coordinates (the results' fingerprints)."""
    sets, times, report, hashes = [], [], None, []
    for k in seeds:
        path = os.path.join(tmp, f"default-s{s}-n{n}-seed{k}.npy")
        cmd = [binary, "generate", "-n", str(n), "-s", str(s), "--seed", str(k), "-o", path]
        t0 = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        times.append(time.perf_counter() - t0)
        if p.returncode != 0:
            raise RuntimeError(f"{shlex.join(cmd)} exited {p.returncode}: "
                               f"{p.stderr.strip()[-500:]}")
        x = np.load(path)
        if x.shape != (n, s):
            raise RuntimeError(f"{path}: shape {x.shape}, expected {(n, s)}")
        if report is None:
            report = p.stdout[-6000:]
        sets.append(path)
        hashes.append(digest(x))
    return sets, times, report, hashes


def _seeded(cls, *args, r, **kw):
    """SciPy ≥ 1.15 names the seed `rng` (an int gives default_rng(r) either way)."""
    try:
        return cls(*args, rng=r, **kw)
    except TypeError:
        return cls(*args, seed=r, **kw)


def sobol_set(s, n, r):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the balance warning at n not a power of two
        return _seeded(qmc.Sobol, s, scramble=True, r=r).random(n)


def _prefix(gen, n):
    m = max(0, math.ceil(math.log2(n)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        x = np.asarray(gen(2 ** m))
    return x[:n]


def lattice_tent_set(s, n, r):
    import qmcpy
    x = _prefix(qmcpy.Lattice(s, seed=r), n)
    return 1.0 - np.abs(2.0 * x - 1.0)


def dnet_set(s, n, r):
    import qmcpy
    return _prefix(qmcpy.DigitalNetB2(s, seed=r, alpha=2), n)


def lhs_set(s, n, r):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return _seeded(qmc.LatinHypercube, s, optimization="random-cd", r=r).random(n)


def lhs_replicates(n):
    # random-cd takes ~3–7 s per set at 1 000 points and ~50 s at 10^4 × 10 on the
    # project's shared cores: fewer sets as n grows (LHS is far behind either way)
    return 16 if n <= 1024 else 8 if n <= 2000 else 4 if n <= 4096 else 2


PEERS = {
    "lattice-tent": (lattice_tent_set, lambda n: REPLICATES, None),
    "dnet-alpha2": (dnet_set, lambda n: REPLICATES, None),
    "lhs-random-cd": (lhs_set, lhs_replicates, LHS_MAX_N),
}


def run_sets(make, s, n, reps, inst, exact, keep=0, tmp=None, tag=""):
    """Draw `reps` sets, integrate every instance on each; keep the first `keep` as .npy."""
    errs, times, kept = [], [], []
    for r in range(reps):
        t0 = time.perf_counter()
        x = make(s, n, r)
        times.append(time.perf_counter() - t0)
        if x.shape != (n, s):
            raise RuntimeError(f"shape {x.shape}, expected {(n, s)}")
        if not (np.all(x >= 0.0) and np.all(x <= 1.0)):
            raise RuntimeError("points outside [0, 1]^s")
        errs.append(relative_errors(x, inst, exact))
        if r < keep:
            path = os.path.join(tmp, f"{tag}-s{s}-n{n}-r{r}.npy")
            np.save(path, x)
            kept.append(path)
        del x
    return np.array(errs), times, kept


def method_record(errs, times, count, extra=None):
    rec = {
        "rms": family_rms(errs, count).tolist(),
        "sets": len(errs),
        "time_s": float(np.median(times)),
        "times_s": [float(t) for t in times],
        # per instance, RMS over this method's sets (raw numbers for later analysis)
        "instance_rms": np.sqrt((np.asarray(errs) ** 2).mean(axis=0)).tolist(),
    }
    if extra:
        rec.update(extra)
    return rec


def run_cell(binary, s, n, a, tmp, log, old=None):
    """One cell; with `old` (--default-only) only the default is measured and the stored
    Sobol' reference and peers are kept."""
    inst, exact = instances(s, a.instances)
    cell = {"s": s, "n": n, "methods": {}, "failures": {}, "skip_peers": a.skip_peers,
            "binary_sha256": sha256(binary), "instances": a.instances,
            "instance_seed": INSTANCE_SEED, "date": now()}
    if old is not None:
        cell["skip_peers"] = old["skip_peers"]
        cell["peers_date"] = old.get("peers_date", old["date"])
        cell["failures"] = {k: v for k, v in old["failures"].items() if k != "default"}
    flags, why = disc_plan(n, s, a)
    disc = flags is not None
    if why:
        cell["disc_note"] = why
    # (1) the default
    try:
        paths, times, report, hashes = run_default(binary, n, s, DEFAULT_SEEDS, tmp,
                                                   a.timeout)
        errs = [relative_errors(np.load(p), inst, exact) for p in paths]
        rec = method_record(errs, times, a.instances,
                            {"seeds": DEFAULT_SEEDS, "report": report,
                             "errors": np.asarray(errs).tolist(), "sha256": hashes})
        if disc:
            ev = [stillpoint_eval(binary, p, flags) for p in paths]
            rec["disc"] = ev
        cell["methods"]["default"] = rec
        log(f"  default: {rec['time_s']:.2f} s (median of {len(times)})")
    except Exception as e:  # noqa: BLE001 — recorded, the cell goes on
        cell["failures"]["default"] = f"{type(e).__name__}: {e}"
        log(f"  default FAILED: {e}")
    finally:
        for k in DEFAULT_SEEDS:
            p = os.path.join(tmp, f"default-s{s}-n{n}-seed{k}.npy")
            if os.path.exists(p):
                os.remove(p)
    if old is not None:
        for name, rec in old["methods"].items():
            if name != "default":
                cell["methods"][name] = rec
        return ratios(cell)
    # (2) scrambled Sobol', the reference
    keep = a.disc_sets if disc else 0
    errs, times, kept = run_sets(sobol_set, s, n, REPLICATES, inst, exact, keep, tmp, "sobol")
    rec = method_record(errs, times, a.instances)
    if kept:
        rec["disc"] = [stillpoint_eval(binary, p, flags) for p in kept]
        for p in kept:
            os.remove(p)
    cell["methods"]["sobol"] = rec
    log(f"  sobol: {rec['time_s']:.3f} s per set")
    # (3)-(5) the peers
    if not a.skip_peers:
        for name, (make, reps, max_n) in PEERS.items():
            if max_n is not None and n > max_n:
                cell["failures"][name] = f"not run above n = {max_n}"
                continue
            t0 = time.perf_counter()
            try:
                errs, times, _ = run_sets(make, s, n, reps(n), inst, exact)
                cell["methods"][name] = method_record(errs, times, a.instances)
                log(f"  {name}: {np.median(times):.3f} s per set, "
                    f"{time.perf_counter() - t0:.1f} s in all")
            except Exception as e:  # noqa: BLE001
                cell["failures"][name] = f"{type(e).__name__}: {e}"
                log(f"  {name} FAILED: {e}")
    return ratios(cell)


def ratios(cell):
    ref = np.array(cell["methods"]["sobol"]["rms"])
    for rec in cell["methods"].values():
        rec["ratio"] = (np.array(rec["rms"]) / ref).tolist()
    return cell


def run_sweep_n(binary, s, n, a, tmp):
    inst, exact = instances(s, a.instances)
    rec = {"s": s, "n": n, "binary_sha256": sha256(binary), "date": now()}
    try:
        paths, times, _, hashes = run_default(binary, n, s, DEFAULT_SEEDS, tmp, a.timeout)
        rec["sha256"] = hashes
        errs = [relative_errors(np.load(p), inst, exact) for p in paths]
        for p in paths:
            os.remove(p)
        d_rms = family_rms(errs, a.instances)
        rec["default_time_s"] = float(np.median(times))
    except Exception as e:  # noqa: BLE001
        rec["failure"] = f"{type(e).__name__}: {e}"
        return rec
    serrs, _, _ = run_sets(sobol_set, s, n, REPLICATES, inst, exact)
    s_rms = family_rms(serrs, a.instances)
    rec["default_rms"] = d_rms.tolist()
    rec["sobol_rms"] = s_rms.tolist()
    rec["ratio"] = (d_rms / s_rms).tolist()
    return rec


# ---------------------------------------------------------------- report

def now():
    return datetime.datetime.now().astimezone().isoformat(timespec="seconds")


def machine():
    model = "?"
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        nproc = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
    except OSError:
        nproc = str(os.cpu_count())
    try:
        import qmcpy
        qv = qmcpy.__version__
    except Exception as e:  # noqa: BLE001
        qv = f"not importable ({type(e).__name__}: {e})"
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True).stdout.strip()
        commit = head + (" (working tree modified)" if dirty else "")
    except OSError:
        commit = "?"
    return {"commit": commit, "nproc": nproc, "cpu": model,
            "load": [round(v, 2) for v in os.getloadavg()],
            "python": platform.python_version(), "numpy": np.__version__,
            "scipy": scipy.__version__, "qmcpy": qv}


def fmt(v, digits=2):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "—"
    return f"{v:.{digits}f}" if abs(v) >= 10 ** -digits or v == 0 else f"{v:.1e}"


def fmt_small(v):
    return f"{v:.2f}" if v >= 0.01 or v == 0 else f"{v:.1e}"


def fmt_ratio(v, fam):
    if v is None:
        return "—"
    text = fmt_small(v)
    return f"**{text}**" if v > CELL_BOUND[fam] else text


def gmean(values):
    values = [v for v in values if v is not None and v > 0]
    return math.exp(sum(math.log(v) for v in values) / len(values)) if values else None


def cell_key(s, n):
    return f"{s}:{n}"


def sorted_cells(cells):
    return sorted(cells.values(), key=lambda c: (c["s"], c["n"]))


def disc_ratio(cell, field):
    d = cell["methods"].get("default", {}).get("disc")
    b = cell["methods"].get("sobol", {}).get("disc")
    if not d or not b:
        return None
    return float(np.mean([v[field] for v in d]) / np.mean([v[field] for v in b]))


def report(data, current_sha):
    cells = sorted_cells(data.get("cells", {}))
    lines = ["# Large-n benchmark: the default against scrambled Sobol' and its peers", ""]
    lines.append("Made by `benches/large_n.py`. Runs that wrote "
                 "`large_n.json` (newest last):")
    lines.append("")
    for run in data.get("runs", []):
        m = run["machine"]
        took = f", {run['seconds'] / 60:.1f} min" if "seconds" in run else ""
        lines.append(f"- `{run['command']}` — {run['date']}{took}, "
                     f"commit {m.get('commit', '?')}, "
                     f"`stillpoint` sha256 {run['binary_sha256'][:12]}, {m['nproc']} cores "
                     f"({m['cpu']}), load {m['load']}, Python {m['python']}, NumPy "
                     f"{m['numpy']}, SciPy {m['scipy']}, QMCPy {m['qmcpy']}")
    count = cells[0].get("instances", 16) if cells else 16
    lines += ["", f"Genz instances: {count} per family per cell from seed {INSTANCE_SEED}, a "
              "seed not used anywhere else in this repository (relative error "
              "e = (Q − I)/|I|, RMS over instances and sets). Every ratio is a method's RMS "
              "over the RMS of 16 scrambled Sobol' sets on the same instances; the "
              "default's RMS is over seeds 1–3. Columns: oscillatory, product peak, corner "
              "peak, Gaussian, continuous, discontinuous. **Bold**: above 1.0 (1.1 for the "
              "discontinuous family). Times: the default's is the median wall time of "
              "`stillpoint generate -n N -s S --seed K -o x.npy` (K = 1, 2, 3, its report "
              "included); a peer's is the median time to draw one set in Python.", ""]
    kept = sorted({c["peers_date"][:10] for c in cells if "peers_date" in c})
    if kept:
        lines += ["The Sobol' reference and the peers of "
                  + ("every cell" if all("peers_date" in c for c in cells) else "the cells "
                     + ", ".join(f"({c['s']}, {c['n']})" for c in cells if "peers_date" in c))
                  + f" were measured on {', '.join(kept)} and kept when "
                  "`--default-only` measured the default again (they do not depend on "
                  "stillpoint's build; the Sobol' sets' discrepancies are from that "
                  "run's `stillpoint eval`).", ""]
    stale = [c for c in cells if c.get("binary_sha256") != current_sha]
    if stale:
        lines += [f"† measured with another build of `stillpoint` than the current one "
                  f"({len(stale)} cells); `--fresh` measures them again.", ""]

    # the default per cell
    lines += ["## The default per cell", "",
              "| s | n | time (s) | " + " | ".join(SHORT) + " | D_L2* / Sobol' | CD / Sobol' |",
              "|---|---|---|" + "---|" * len(SHORT) + "---|---|"]
    for c in cells:
        d = c["methods"].get("default")
        mark = "†" if c.get("binary_sha256") != current_sha else ""
        if d is None:
            lines.append(f"| {c['s']} | {c['n']}{mark} | — | " + " | ".join(["—"] * 6)
                         + " | — | — |")
            continue
        lines.append(f"| {c['s']} | {c['n']}{mark} | {d['time_s']:.2f} | "
                     + " | ".join(fmt_ratio(v, f) for f, v in enumerate(d["ratio"]))
                     + f" | {fmt(disc_ratio(c, 'star_l2'), 3)} | "
                     f"{fmt(disc_ratio(c, 'centered_l2'), 3)} |")
    lines += ["", "Discrepancies: `stillpoint eval FILE --json` (fields `star_l2`, "
              "`centered_l2`, the roots; the ratio of the squares is the square of the "
              "ratio), exact sums up to 50 000 points, `--exact` above where the cell's "
              "note allows; the mean over the default's three sets divided by the mean "
              "over the first Sobol' sets (4 by default).", ""]
    notes = {}
    for c in cells:
        if c.get("disc_note"):
            notes.setdefault(c["disc_note"], []).append(f"({c['s']}, {c['n']})")
    if notes:
        lines += ["Not measured (—):", ""]
        lines += [f"- {', '.join(v)}: {k}" for k, v in notes.items()] + [""]

    # every method per cell
    lines += ["## Every method per cell", "",
              "Scrambled Sobol' rows give its RMS relative error itself (the denominator); "
              "the other rows the ratio to it.", "",
              "| s | n | method | sets | time (s) | " + " | ".join(SHORT) + " |",
              "|---|---|---|---|---|" + "---|" * len(SHORT)]
    for c in cells:
        for m in METHODS:
            rec = c["methods"].get(m)
            if rec is None:
                why = c.get("failures", {}).get(m)
                if why is None and m != "default" and c.get("skip_peers"):
                    continue
                lines.append(f"| {c['s']} | {c['n']} | {LABEL[m]} | — | — | "
                             + " | ".join(["—"] * 6) + " |")
                continue
            vals = (" | ".join(f"{v:.2e}" for v in rec["rms"]) if m == "sobol" else
                    " | ".join(fmt_ratio(v, f) for f, v in enumerate(rec["ratio"])))
            lines.append(f"| {c['s']} | {c['n']} | {LABEL[m]} | {rec['sets']} | "
                         f"{rec['time_s']:.3g} | {vals} |")
    lines.append("")

    # geometric means per s
    by_s = {}
    for c in cells:
        by_s.setdefault(c["s"], []).append(c)
    lines += ["## Geometric mean of the ratio over the cells of each s", "",
              "| s | cells | method | " + " | ".join(SHORT) + " |",
              "|---|---|---|" + "---|" * len(SHORT)]
    gms = {}
    for s, cs in sorted(by_s.items()):
        for m in METHODS:
            if m == "sobol":
                continue
            recs = [c["methods"][m] for c in cs if m in c["methods"]]
            if not recs:
                continue
            g = [gmean([r["ratio"][f] for r in recs]) for f in range(len(FAMILIES))]
            if m == "default":
                gms[s] = (g, len(recs))
            lines.append(f"| {s} | {len(recs)} | {LABEL[m]} | "
                         + " | ".join(fmt(v) for v in g) + " |")
    lines.append("")

    # bounds of the Proof section
    lines += ["## Bounds for the default", "",
              "Geometric mean over the cells of each s ≤ 0.5 (oscillatory, product peak, "
              "Gaussian), ≤ 0.8 (corner peak, continuous); no cell of these five above "
              "1.0; the discontinuous family ≤ 1.1 in every cell.", ""]
    missed = []
    for s, (g, k) in sorted(gms.items()):
        for f, bound in sorted(GM_BOUND.items()):
            if g[f] is not None and g[f] > bound:
                missed.append(f"- s = {s}: {FAMILIES[f]} geometric mean {g[f]:.3f} > "
                              f"{bound} (by {g[f] - bound:.3f}, {100 * (g[f] / bound - 1):.0f} "
                              f"% over; {k} cell{'s' if k > 1 else ''})")
    for c in cells:
        d = c["methods"].get("default")
        if d is None:
            missed.append(f"- ({c['s']}, {c['n']}): the default failed: "
                          f"{c['failures'].get('default')}")
            continue
        for f, bound in CELL_BOUND.items():
            if d["ratio"][f] > bound:
                missed.append(f"- ({c['s']}, {c['n']}): {FAMILIES[f]} {d['ratio'][f]:.3f} > "
                              f"{bound} (by {d['ratio'][f] - bound:.3f}, "
                              f"{100 * (d['ratio'][f] / bound - 1):.0f} % over)")
    lines += (missed or ["- every bound met"]) + [""]
    disc_over = []
    for c in cells:
        for field, name in (("star_l2", "D_L2*"), ("centered_l2", "CD")):
            r = disc_ratio(c, field)
            if r is not None and r > 1.0:
                disc_over.append(f"({c['s']}, {c['n']}) {name} {r:.3f}×")
    lines += ["Discrepancies above the Sobol' mean (item 2): "
              + ("; ".join(disc_over) if disc_over else "none") + ".", ""]

    # times of item 3
    over = []
    for c in cells:
        d = c["methods"].get("default")
        if d is None:
            continue
        s, n, t = c["s"], c["n"], d["time_s"]
        limit = (60.0 if (n >= BIG_N and s <= 5) else None) if n > 100000 else (
            10.0 if s <= 10 else 20.0 if s <= 20 else None)
        if limit is not None and t > limit:
            over.append(f"({s}, {n}) {t:.1f} s > {limit:.0f} s")
    lines += ["Times over item 3's limits (≤ 10 s up to 10^5 points at s ≤ 10, ≤ 20 s at "
              "s ≤ 20, ≤ 60 s at 10^6 × 5; measured here on shared cores): "
              + ("; ".join(over) if over else "none") + ".", ""]

    # failures
    fails = [(c["s"], c["n"], m, why) for c in cells for m, why in c.get("failures", {}).items()]
    if fails:
        lines += ["## Methods not run or failed", "", "| s | n | method | why |",
                  "|---|---|---|---|"]
        lines += [f"| {s} | {n} | {LABEL[m]} | {why.replace('|', '/')[:300]} |"
                  for s, n, m, why in fails]
        lines.append("")

    # sweep
    sweep = data.get("sweep", {})
    if sweep:
        lines += sweep_report(sweep, current_sha)
    return "\n".join(lines + fingerprints(data)) + "\n"


def fingerprints(data):
    """The fingerprints of the default's sets of the cells (and sweep sizes) measured
    since the runs recorded them; none for a file made before."""
    prints = []
    for rec in [c["methods"].get("default", {}) | {"s": c["s"], "n": c["n"]}
                for c in sorted_cells(data.get("cells", {}))] + sorted(
                    data.get("sweep", {}).values(), key=lambda r: (r["s"], r["n"])):
        for k, h in zip(DEFAULT_SEEDS, rec.get("sha256", [])):
            prints.append(f"fingerprint: generate -n {rec['n']} -s {rec['s']} --seed {k} "
                          f"sha256:{h}")
    if not prints:
        return []
    run = data["runs"][-1]
    # One command remakes the file only when its last run made every record; otherwise
    # the runs listed at its top made the others, each rerun with --fresh.
    records = list(data.get("cells", {}).values()) + list(data.get("sweep", {}).values())
    remake = run["command"] if all(r.get("date", "") >= run["date"] for r in records) else (
        f"{run['command']} (the last run; the runs listed at the top made the other cells, "
        "each remade with --fresh)")
    return section(run["machine"].get("commit", "?"), remake, prints,
                   data.get("fingerprint_note", ""))


def sweep_flags(recs):
    """recs sorted by n; flag (n, family, ratio, median) where ratio > 1.3 × the median of
    the ratios at n−5 … n+5 (n itself left out, those measured)."""
    ok = [r for r in recs if "ratio" in r]
    by_n = {r["n"]: r for r in ok}
    flags = []
    for r in ok:
        for f in range(len(FAMILIES)):
            nb = [by_n[m]["ratio"][f] for m in range(r["n"] - SWEEP_HALF, r["n"] + SWEEP_HALF + 1)
                  if m != r["n"] and m in by_n]
            if not nb:
                continue
            med = float(np.median(nb))
            if r["ratio"][f] > SWEEP_FACTOR * med:
                flags.append((r["n"], f, r["ratio"][f], med))
    return flags


def sweep_report(sweep, current_sha):
    lines = []
    for s in sorted({r["s"] for r in sweep.values()}):
        recs = sorted((r for r in sweep.values() if r["s"] == s), key=lambda r: r["n"])
        flags = sweep_flags(recs)
        flagged = {(n, f) for n, f, _, _ in flags}
        lo, hi = recs[0]["n"], recs[-1]["n"]
        lines += [f"## Sweep at s = {s}, n = {lo} … {hi}", "",
                  f"The default's ratio to scrambled Sobol' at every n (seeds 1–3 against 16 "
                  f"sets); ⚑ marks a ratio above {SWEEP_FACTOR}× the median of its "
                  f"±{SWEEP_HALF} neighbours.", "",
                  "| n | time (s) | " + " | ".join(SHORT) + " |",
                  "|---|---|" + "---|" * len(SHORT)]
        for r in recs:
            mark = "†" if r.get("binary_sha256") != current_sha else ""
            if "ratio" not in r:
                lines.append(f"| {r['n']}{mark} | — | " + " | ".join(["—"] * 6) + " |")
                continue
            cells = [fmt_small(v) + (" ⚑" if (r["n"], f) in flagged else "")
                     for f, v in enumerate(r["ratio"])]
            lines.append(f"| {r['n']}{mark} | {r['default_time_s']:.2f} | "
                         + " | ".join(cells) + " |")
        lines.append("")
        g = [gmean([r["ratio"][f] for r in recs if "ratio" in r]) for f in range(6)]
        lines += ["Geometric mean over the sweep: " + ", ".join(
            f"{SHORT[f]} {fmt(v)}" for f, v in enumerate(g)) + ".", ""]
        if flags:
            lines += ["Flagged:"] + [
                f"- n = {n}, {FAMILIES[f]}: {v:.3f} > {SWEEP_FACTOR} × {med:.3f} "
                f"(= {SWEEP_FACTOR * med:.3f})" for n, f, v, med in flags] + [""]
        else:
            lines += [f"No n above {SWEEP_FACTOR}× the median of its neighbours.", ""]
        fails = [r for r in recs if "failure" in r]
        if fails:
            lines += ["Failed: " + "; ".join(f"n = {r['n']}: {r['failure']}" for r in fails),
                      ""]
    return lines


# ---------------------------------------------------------------- main

def parse_cells(text):
    out = []
    for part in text.split(","):
        part = part.strip()
        if not part:
            continue
        s, n = part.split(":")
        out.append((int(s), int(n)))
    return out


def save_json(path, data):
    tmp = path + ".tmp"
    with open(tmp, "w") as fh:
        json.dump(data, fh, indent=1)
    os.replace(tmp, path)


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default="target/release/stillpoint")
    ap.add_argument("--quick", action="store_true", help="a handful of small cells")
    ap.add_argument("--cells", help='only these cells, "s:n,s:n"')
    ap.add_argument("--sweep", action="store_true",
                    help="the sweep n = 1000..1100 at s = 8 instead of the grid")
    ap.add_argument("--sweep-range", default="1000:1100", help="LO:HI, both included")
    ap.add_argument("--sweep-s", type=int, default=8)
    ap.add_argument("--skip-peers", action="store_true",
                    help="only the default and scrambled Sobol'")
    ap.add_argument("--out", default="results/large-n")
    ap.add_argument("--fresh", action="store_true",
                    help="measure the chosen cells again even if large_n.json has them")
    ap.add_argument("--default-only", action="store_true",
                    help="measure only the default of the chosen cells again; keep the "
                    "Sobol' reference and the peers large_n.json holds")
    ap.add_argument("--instances", type=int, default=16, help="Genz instances per family")
    ap.add_argument("--disc-max-n", type=int, default=100000,
                    help="exact discrepancies up to this n")
    ap.add_argument("--disc-exact-max-s", type=int, default=2,
                    help="above 50 000 points, `eval --exact` only up to this s (it "
                    "also computes every 2-D projection's star discrepancy, O(n²) each)")
    ap.add_argument("--disc-sets", type=int, default=4,
                    help="Sobol' sets whose discrepancies are measured")
    ap.add_argument("--timeout", type=float, default=3600.0,
                    help="seconds one `stillpoint generate` may take")
    a = ap.parse_args()

    while not os.path.exists(a.bin):
        print(f"{a.bin} not there yet (cargo build --release --bin stillpoint); waiting",
              file=sys.stderr, flush=True)
        time.sleep(30)
    binary = os.path.abspath(a.bin)
    a.binary_sha = sha256(binary)
    os.makedirs(a.out, exist_ok=True)
    json_path = os.path.join(a.out, "large_n.json")
    md_path = os.path.join(a.out, "large_n.md")
    data = {}
    if os.path.exists(json_path):
        with open(json_path) as fh:
            data = json.load(fh)
    data.setdefault("cells", {})
    data.setdefault("sweep", {})
    data.setdefault("runs", [])
    command = shlex.join(["python3", "benches/large_n.py"] + sys.argv[1:])
    data["runs"].append({"command": command, "date": now(), "machine": machine(),
                         "binary_sha256": a.binary_sha, "instance_seed": INSTANCE_SEED})

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    def write():
        save_json(json_path, data)
        with open(md_path, "w") as fh:
            fh.write(report(data, sha256(binary)))

    t_all = time.perf_counter()
    measured = 0
    with tempfile.TemporaryDirectory(prefix="large-n-") as tmp:
        if a.sweep:
            lo, hi = (int(v) for v in a.sweep_range.split(":"))
            for n in range(lo, hi + 1):
                key = cell_key(a.sweep_s, n)
                if key in data["sweep"] and not a.fresh and "ratio" in data["sweep"][key]:
                    continue
                t0 = time.perf_counter()
                data["sweep"][key] = run_sweep_n(binary, a.sweep_s, n, a, tmp)
                measured += 1
                r = data["sweep"][key]
                log(f"sweep s = {a.sweep_s}, n = {n}: "
                    + (" ".join(fmt_small(v) for v in r["ratio"]) if "ratio" in r
                       else r["failure"]) + f" ({time.perf_counter() - t0:.1f} s)")
                write()
        else:
            cells = (parse_cells(a.cells) if a.cells else QUICK if a.quick else grid_cells())
            for s, n in cells:
                key = cell_key(s, n)
                old = data["cells"].get(key)
                if a.default_only and (old is None or "sobol" not in old["methods"]):
                    sys.exit(f"--default-only: ({s}, {n}) has no stored Sobol' reference "
                             f"in {json_path}; run it without --default-only")
                if (old is not None and not a.fresh and not a.default_only
                        and (a.skip_peers or not old["skip_peers"])):
                    if old.get("binary_sha256") != a.binary_sha:
                        log(f"({s}, {n}) cached from another build of stillpoint; "
                            "--fresh measures it again")
                    continue
                log(f"cell s = {s}, n = {n}")
                t0 = time.perf_counter()
                cell = run_cell(binary, s, n, a, tmp, log, old if a.default_only else None)
                cell["seconds"] = time.perf_counter() - t0
                data["cells"][key] = cell
                measured += 1
                d = cell["methods"].get("default")
                log(f"  ({s}, {n}) done in {cell['seconds']:.1f} s; default / Sobol': "
                    + (" ".join(fmt_small(v) for v in d["ratio"]) if d else "—"))
                write()
    if measured:
        data["runs"][-1]["seconds"] = time.perf_counter() - t_all
    else:  # everything was cached: the report is only made again
        data["runs"].pop()
    write()
    with open(md_path) as fh:
        print(fh.read())


if __name__ == "__main__":
    main()
