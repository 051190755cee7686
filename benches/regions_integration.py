"""Integration in regions: the integration goal in a region against scrambled Sobol' +
rejection (the mean of 16 scrambles), hit-and-run (the mean of 16 chains), uniform
rejection (the mean of 16 seeds) and the region's space-filling run.

Regions: balls s = 2-8, simplices s = 3-6, a polytope with four cuts of [0,1]^3, the
paper's g1-g4 (eq. 58) and bounded mixtures of S = 3-6 components with a cut; n = 50
to 1000. For each region and n it reports the energy distance D^2 to the uniform
distribution on the region (stillpoint.metrics(x, region=...): one fixed independent
uniform sample of 32 768 points, so every set is measured against the same sample), the
RMS error of smooth test integrals with random parameters (each error relative to the
integrand's standard deviation on the region; reference values from 2^22 scrambled
Sobol' points of the region), the minimum distance and the time. A mixture is measured
in its first S - 1 components, where the run is made.

Hit-and-run: BoTorch's HitAndRunPolytopeSampler (botorch.utils.sampling) for the
polytopes (simplices, the polytope, g4, the mixtures with their equality constraint),
with its defaults: a burn-in of 200 steps, then every 20th step kept, from the
Chebyshev centre it finds by linear programming. For the regions that are not polytopes
(balls, g1-g3) the same chain in numpy: a Gaussian direction in the box-normalised
coordinates, the next point uniform on the line's part inside the region (uniform on its
part inside the box, rejected until inside), the same burn-in and thinning.

    python3 benches/regions_integration.py [--quick] [--resume] [--only NAME] [--out DIR]

Needs the built package, SciPy and (for the polytopes' hit-and-run) BoTorch; without
BoTorch the polytopes' hit-and-run column is left empty. The space-filling anchor runs
the CLI (target/release/stillpoint) with a time limit.
"""

import argparse
import json
import os
import pathlib
import subprocess
import tempfile
import time
import warnings

import numpy as np
from scipy.stats import qmc, norm

import stillpoint as sp

ROOT = pathlib.Path(__file__).resolve().parent.parent
CLI = ROOT / "target" / "release" / "stillpoint"
SPACE_FILLING_LIMIT = 90  # seconds
BURN_IN, THINNING = 200, 20  # BoTorch's HitAndRunPolytopeSampler defaults


def region(name, gen, kw, s, inside, lo, hi, sampler="box", polytope=None, project=False):
    """A benchmarked region: `gen` are generate()'s arguments, `kw` metrics()'s (in the
    s measured coordinates), `sampler` how reference points are made ("ball", "simplex"
    or "box": rejection), `polytope` (A, b, C, d, lo, hi) in the generated coordinates
    for BoTorch (A x <= b, C x = d), `project` drops a mixture's last component."""
    return dict(name=name, gen=gen, kw=kw, s=s, inside=inside, lo=np.asarray(lo, float),
                hi=np.asarray(hi, float), sampler=sampler, polytope=polytope,
                project=project)


def ball(s):
    return region(f"ball s={s}", {"shape": "ball:1", "d": s}, {"shape": "ball:1"},
                  s, lambda x: (x * x).sum(1) <= 1.0, -np.ones(s), np.ones(s), "ball")


def simplex(s):
    poly = (np.ones((1, s)), np.ones(1), None, None, np.zeros(s), np.ones(s))
    return region(f"simplex s={s}", {"shape": "simplex", "d": s}, {"shape": "simplex"}, s,
                  lambda x: (x >= 0).all(1) & (x.sum(1) <= 1.0), np.zeros(s), np.ones(s),
                  "simplex", poly)


CUTS = "max(max(x1 + x2 + x3 - 1.8, x1 - x2 - 0.4), max(x2 + 2*x3 - 2, 0.3 - x1 - x3))"


def polytope():
    def inside(x):
        a, b, c = x[:, 0], x[:, 1], x[:, 2]
        return ((a + b + c <= 1.8) & (a - b <= 0.4) & (b + 2 * c <= 2) & (a + c >= 0.3)
                & (x >= 0).all(1) & (x <= 1).all(1))
    A = np.array([[1, 1, 1], [1, -1, 0], [0, 1, 2], [-1, 0, -1]], float)
    b = np.array([1.8, 0.4, 2, -0.3])
    kw = {"region": CUTS, "box": [0, 1, 0, 1, 0, 1]}
    return region("polytope, 4 cuts of [0,1]^3", kw, kw, 3, inside, np.zeros(3),
                  np.ones(3), polytope=(A, b, None, None, np.zeros(3), np.ones(3)))


def paper(i):
    """The paper's g1-g4 (eq. 58) in boxes a little wider than their extents."""
    expr, box, f = {
        1: ("17*x^2 - 16*|x|*y + 17*y^2 - 225", [-4.3, 4.3, -4.3, 4.3],
            lambda x, y: 17 * x**2 - 16 * abs(x) * y + 17 * y**2 - 225),
        2: ("x^2*|x| + 10*y^2 - 100", [-4.7, 4.7, -3.2, 3.2],
            lambda x, y: x**2 * abs(x) + 10 * y**2 - 100),
        3: ("y^2 + 2*|x| - 20", [-10.2, 10.2, -4.5, 4.5],
            lambda x, y: y**2 + 2 * abs(x) - 20),
        4: ("|x| + 2*|y| - 5", [-5.1, 5.1, -2.6, 2.6],
            lambda x, y: abs(x) + 2 * abs(y) - 5),
    }[i]
    lo, hi = np.array(box[0::2]), np.array(box[1::2])
    poly = None
    if i == 4:
        poly = (np.array([[1, 2], [1, -2], [-1, 2], [-1, -2]], float), 5 * np.ones(4),
                None, None, lo, hi)
    kw = {"region": expr, "box": box}
    return region(f"g{i} (eq. 58)", kw, kw, 2, lambda x: f(x[:, 0], x[:, 1]) <= 0, lo, hi,
                  polytope=poly)


MIXTURE_HI = 0.6  # every component in [0, 0.6]
MIXTURE_CUT = "x1 + 2*x2 <= 1"


def mixture(S):
    """S components in [0, 0.6] summing to 1, with the cut x1 + 2 x2 <= 1; measured in
    x1..x_{S-1}, where 0.4 <= x1 + ... + x_{S-1} <= 1 keeps x_S in [0, 0.6]."""
    s = S - 1
    total = " + ".join(f"x{k + 1}" for k in range(s))
    expr = f"max(max({total} - 1, {1 - MIXTURE_HI} - ({total})), x1 + 2*x2 - 1)"

    def inside(x):
        t = x.sum(1)
        return ((x >= 0).all(1) & (x <= MIXTURE_HI).all(1) & (t <= 1) & (t >= 1 - MIXTURE_HI)
                & (x[:, 0] + 2 * x[:, 1] <= 1))
    A = np.zeros((1, S))
    A[0, :2] = [1, 2]
    poly = (A, np.ones(1), np.ones((1, S)), np.ones(1), np.zeros(S), MIXTURE_HI * np.ones(S))
    gen = {"d": S, "mixture": True, "box": [0, MIXTURE_HI] * S, "constraints": [MIXTURE_CUT]}
    kw = {"region": expr, "box": [0, MIXTURE_HI] * s}
    return region(f"mixture S={S}", gen, kw, s, inside, np.zeros(s), MIXTURE_HI * np.ones(s),
                  polytope=poly, project=True)


def rejection(inside, lo, hi, n, draw):
    """The first n points of `draw(k)` (k points of [0,1]^s) scaled to the box and inside."""
    k = 1024
    while True:
        u = lo + (hi - lo) * draw(k)
        x = u[inside(u)]
        if len(x) >= n:
            return x[:n]
        k *= 4


def sobol_rejection(inside, lo, hi, n, seed):
    s = len(lo)

    def draw(k):
        return qmc.Sobol(s, scramble=True, seed=seed).random(k)
    return rejection(inside, lo, hi, n, draw)


def uniform_rejection(inside, lo, hi, n, seed):
    rng = np.random.default_rng(seed)
    return rejection(inside, lo, hi, n, lambda k: rng.random((k, len(lo))))


def botorch_hit_and_run(poly, n, seed):
    """n points of BoTorch's HitAndRunPolytopeSampler with its default burn-in and
    thinning, in the generated coordinates; None without BoTorch."""
    try:
        import torch
        from botorch.utils.sampling import HitAndRunPolytopeSampler
    except ImportError:
        return None
    A, b, C, d, lo, hi = poly
    t = lambda a: torch.tensor(np.asarray(a, float), dtype=torch.float64)
    eq = None if C is None else (t(C), t(d).reshape(-1, 1))
    sampler = HitAndRunPolytopeSampler(
        inequality_constraints=(t(A), t(b).reshape(-1, 1)), equality_constraints=eq,
        bounds=torch.stack([t(lo), t(hi)]), n_burnin=BURN_IN, n_thinning=THINNING,
        seed=seed)
    return sampler.draw(n).numpy()


def line_hit_and_run(inside, lo, hi, n, seed):
    """Hit-and-run for a region given by membership: as BoTorch's chain, with the next
    point uniform on the line's part inside the region (uniform on its part inside the
    box, rejected until inside)."""
    rng = np.random.default_rng(seed)
    s, width = len(lo), hi - lo
    x = uniform_rejection(inside, lo, hi, 1, seed + 1000)[0]
    out = []
    for step in range(BURN_IN + THINNING * n):
        d = rng.normal(size=s) * width
        d /= np.linalg.norm(d)
        with np.errstate(divide="ignore"):
            a, b = (lo - x) / d, (hi - x) / d
        tmin, tmax = np.minimum(a, b).max(), np.maximum(a, b).min()
        while True:
            y = x + rng.uniform(tmin, tmax) * d
            if inside(y[None, :])[0]:
                x = y
                break
        if step >= BURN_IN and (step - BURN_IN) % THINNING == THINNING - 1:
            out.append(x.copy())
    return np.array(out)


def hit_and_run(reg, n, seed):
    """The hit-and-run set in the measured coordinates, and which chain made it."""
    if reg["polytope"] is not None:
        x = botorch_hit_and_run(reg["polytope"], n, seed)
        if x is None:
            return None, None
        return (x[:, :reg["s"]] if reg["project"] else x), "BoTorch"
    return line_hit_and_run(reg["inside"], reg["lo"], reg["hi"], n, seed), "numpy"


def integrands(s, lo, hi, rng, count=8):
    """Smooth test functions with random parameters: exponentials of a linear form,
    cosines of one, and Gaussian bumps, `count` of each."""
    scale = hi - lo
    fs = []
    for _ in range(count):
        a = rng.normal(size=s) / scale
        fs.append(lambda x, a=a: np.exp(x @ a))
        w = rng.normal(size=s) * 2 / scale
        p = rng.uniform(0, 2 * np.pi)
        fs.append(lambda x, w=w, p=p: np.cos(x @ w + p))
        c = lo + scale * rng.uniform(0.25, 0.75, size=s)
        fs.append(lambda x, c=c: np.exp(-(((x - c) / scale) ** 2).sum(1) * 4))
    return fs


def reference_points(reg, seed, chunk=1 << 16):
    """Scrambled Sobol' points of the region, chunk by chunk: the ball's and the simplex's
    by exact transforms (Gaussian directions and radius u^{1/s}; normalised
    exponentials), the others by rejection from the box."""
    s, lo, hi, kind = reg["s"], reg["lo"], reg["hi"], reg["sampler"]
    dim = s + 1 if kind in ("ball", "simplex") else s
    sob = qmc.Sobol(dim, scramble=True, seed=seed)
    while True:
        u = np.clip(sob.random(chunk), 1e-16, 1 - 1e-16)
        if kind == "ball":
            g = norm.ppf(u[:, :s])
            yield g / np.linalg.norm(g, axis=1, keepdims=True) * u[:, s:] ** (1.0 / s)
        elif kind == "simplex":
            e = -np.log(u)
            yield e[:, :s] / e.sum(1, keepdims=True)
        else:
            x = lo + (hi - lo) * u
            yield x[reg["inside"](x)]


def reference_values(fs, reg, seed, total=1 << 22):
    sums, squares, got = np.zeros(len(fs)), np.zeros(len(fs)), 0
    for x in reference_points(reg, seed):
        x = x[: total - got]
        got += len(x)
        for i, f in enumerate(fs):
            v = f(x)
            sums[i] += v.sum()
            squares[i] += (v * v).sum()
        if got >= total:
            break
    mean = sums / got
    return mean, np.sqrt(np.maximum(squares / got - mean**2, 1e-300))


def measure(x, kw, fs, mean, sd):
    m = sp.metrics(np.ascontiguousarray(x), **kw)
    err = np.array([(f(x).mean() - mu) / s for f, mu, s in zip(fs, mean, sd)])
    return {
        "energy_distance": m["energy_distance"],
        "energy_distance_se": m["energy_distance_se"],
        "rms_error": float(np.sqrt((err**2).mean())),
        "min_distance": m["min_distance"],
        "inside": m["fraction_inside"],
    }


def mean_of(rows):
    keys = rows[0].keys()
    return {k: float(np.mean([r[k] for r in rows])) for k in keys}


def cli_args(gen):
    args = []
    for k, v in gen.items():
        if k == "d":
            args += ["-s", str(v)]
        elif k == "mixture":
            args += ["--mixture"]
        elif k == "constraints":
            for c in v:
                args += ["--constraint", c]
        elif k == "box":
            args += ["--box", ",".join(str(b) for b in v)]
        else:
            args += [f"--{k}", str(v)]
    return args


def space_filling(reg, n):
    """The region's space-filling run through the CLI, or None past the time limit."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "x.npy")
        cmd = [str(CLI), "generate", "-n", str(n), "--goal", "space-filling", "-q",
               "-o", out] + cli_args(reg["gen"])
        t = time.perf_counter()
        try:
            subprocess.run(cmd, check=True, capture_output=True, timeout=SPACE_FILLING_LIMIT)
        except subprocess.TimeoutExpired:
            return None, time.perf_counter() - t
        x = np.load(out)
        return (x[:, :reg["s"]] if reg["project"] else x), time.perf_counter() - t


def ours(reg, n):
    t = time.perf_counter()
    x = sp.generate(n, goal="integration", **reg["gen"])
    sec = time.perf_counter() - t
    if reg["project"]:
        assert np.abs(x.sum(1) - 1).max() <= 1e-12
        x = x[:, :reg["s"]]
    return x, sec


def run_row(reg, n, fs, mean, sd, reps):
    kw, inside, lo, hi = reg["kw"], reg["inside"], reg["lo"], reg["hi"]
    row = {"region": reg["name"], "s": reg["s"], "n": n}
    x, sec = ours(reg, n)
    row["ours"] = dict(measure(x, kw, fs, mean, sd), seconds=sec)
    x, sec = space_filling(reg, n)
    row["space-filling"] = (None if x is None else
                            dict(measure(x, kw, fs, mean, sd), seconds=sec))
    row["sobol+rejection"] = mean_of([measure(sobol_rejection(inside, lo, hi, n, r), kw,
                                              fs, mean, sd) for r in range(reps)])
    row["uniform"] = mean_of([measure(uniform_rejection(inside, lo, hi, n, r), kw, fs,
                                      mean, sd) for r in range(reps)])
    hr, t = [], time.perf_counter()
    for r in range(reps):
        x, row["hit-and-run chain"] = hit_and_run(reg, n, r)
        if x is None:
            break
        hr.append(measure(x, kw, fs, mean, sd))
    row["hit-and-run"] = mean_of(hr) if hr else None
    if hr:
        row["hit-and-run"]["seconds"] = (time.perf_counter() - t) / reps
    return row


def fmt(r, key, form):
    return "—" if r is None else format(r[key], form)


def outcome(rows):
    """Rows where ours is below Sobol' + rejection in energy distance and RMS error and at
    least its minimum distance."""
    b = lambda r: r["sobol+rejection"]
    return (sum(r["ours"]["energy_distance"] < b(r)["energy_distance"] for r in rows),
            sum(r["ours"]["rms_error"] < b(r)["rms_error"] for r in rows),
            sum(r["ours"]["min_distance"] >= b(r)["min_distance"] for r in rows), len(rows))


def write(out, rows):
    order = {make()["name"]: i for i, (make, _) in enumerate(CASES)}
    rows.sort(key=lambda r: (order.get(r["region"], len(order)), r["n"]))
    (out / "regions_integration.json").write_text(json.dumps(rows, indent=1))
    lines = [
        "| region | n | energy distance D²: ours / Sobol'+rej. / hit-and-run / uniform / "
        "space-filling | RMS integral error (in σ_f): ours / Sobol'+rej. / hit-and-run / "
        "uniform / space-filling | d_min: ours / Sobol'+rej. / hit-and-run / space-filling "
        "| seconds: ours / space-filling |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        o, b, u = r["ours"], r["sobol+rejection"], r["uniform"]
        h, f = r["hit-and-run"], r["space-filling"]
        chain = "" if h is None or r.get("hit-and-run chain") == "BoTorch" else "*"
        lines.append(
            f"| {r['region']} | {r['n']} "
            f"| {fmt(o, 'energy_distance', '.2e')} / {fmt(b, 'energy_distance', '.2e')} / "
            f"{fmt(h, 'energy_distance', '.2e')}{chain} / {fmt(u, 'energy_distance', '.2e')} / "
            f"{fmt(f, 'energy_distance', '.2e')} "
            f"| {fmt(o, 'rms_error', '.2e')} / {fmt(b, 'rms_error', '.2e')} / "
            f"{fmt(h, 'rms_error', '.2e')}{chain} / {fmt(u, 'rms_error', '.2e')} / "
            f"{fmt(f, 'rms_error', '.2e')} "
            f"| {fmt(o, 'min_distance', '.4f')} / {fmt(b, 'min_distance', '.4f')} / "
            f"{fmt(h, 'min_distance', '.4f')}{chain} / {fmt(f, 'min_distance', '.4f')} "
            f"| {o['seconds']:.1f} / "
            f"{'> %d' % SPACE_FILLING_LIMIT if f is None else format(f['seconds'], '.1f')} |")
    e, m, d, k = outcome(rows)
    lines += ["", f"Rows: {k}. Ours below Sobol' + rejection in energy distance: {e}; in RMS "
              f"integral error: {m}; minimum distance at least Sobol' + rejection's: {d}. "
              "Hit-and-run marked * is the numpy chain (not a polytope); the others are "
              "BoTorch's sampler. Space-filling '—': not finished within "
              f"{SPACE_FILLING_LIMIT} s."]
    (out / "regions_integration.md").write_text("\n".join(lines) + "\n")
    return lines


CASES = [
    (lambda: ball(2), [50, 1000]), (lambda: ball(3), [50, 200, 1000]),
    (lambda: ball(4), [100, 1000]), (lambda: ball(6), [100, 1000]),
    (lambda: ball(8), [100, 1000]),
    (lambda: simplex(3), [50, 1000]), (lambda: simplex(4), [100, 1000]),
    (lambda: simplex(5), [100]), (lambda: simplex(6), [100, 1000]),
    (polytope, [100, 1000]),
    (lambda: paper(1), [100, 1000]), (lambda: paper(2), [100, 1000]),
    (lambda: paper(3), [100, 1000]), (lambda: paper(4), [100, 1000]),
    (lambda: mixture(3), [100, 1000]), (lambda: mixture(4), [100, 1000]),
    (lambda: mixture(5), [100]), (lambda: mixture(6), [100, 1000]),
]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default="results/regions-integration")
    ap.add_argument("--resume", action="store_true",
                    help="keep the rows already in OUT and run only the cases after them")
    ap.add_argument("--only", action="append", default=[],
                    help="run only the region of this name (repeatable), e.g. 'simplex s=6'")
    args = ap.parse_args()
    # stillpoint's long-call warnings and BoTorch's deprecation notices.
    warnings.filterwarnings("ignore", category=RuntimeWarning)
    warnings.filterwarnings("ignore", category=UserWarning)
    warnings.filterwarnings("ignore", category=FutureWarning)
    cases = CASES
    if args.quick:
        cases = [(lambda: ball(3), [50]), (lambda: simplex(3), [50]),
                 (lambda: mixture(4), [50])]
    reps = 4 if args.quick else 16
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    if args.resume and (out / "regions_integration.json").exists():
        rows = json.loads((out / "regions_integration.json").read_text())
    done = {(r["region"], r["n"]) for r in rows}
    for make, ns in cases:
        reg = make()
        if args.only and reg["name"] not in args.only:
            continue
        ns = [n for n in ns if (reg["name"], n) not in done]
        if not ns:
            continue
        fs = integrands(reg["s"], reg["lo"], reg["hi"], np.random.default_rng(12345))
        mean, sd = reference_values(fs, reg, 777)
        for n in ns:
            row = run_row(reg, n, fs, mean, sd, reps)
            rows.append(row)
            o, b = row["ours"], row["sobol+rejection"]
            print(f"{reg['name']:28s} n={n:5d}  D2 {o['energy_distance']:.3e} vs "
                  f"{b['energy_distance']:.3e}  rms {o['rms_error']:.2e} vs "
                  f"{b['rms_error']:.2e}  dmin {o['min_distance']:.3f} vs "
                  f"{b['min_distance']:.3f}  {o['seconds']:.1f} s", flush=True)
            write(out, rows)
    print("\n".join(write(out, rows)))


if __name__ == "__main__":
    main()
