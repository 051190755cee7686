"""Integration in regions: the integration goal in a region against scrambled Sobol' +
rejection (the mean of 16 scrambles), uniform rejection (the mean of 16 seeds) and the
region's space-filling run.

For each region and n it reports the energy distance D^2 to the uniform distribution on
the region (stillpoint.metrics(x, region=...): one fixed independent uniform sample of
32 768 points, so every set is measured against the same sample), the RMS error of
smooth test integrals with random parameters (each error relative to the integrand's
standard deviation on the region; reference values from 2^22 independent uniform
points), the minimum distance and the time.

    python3 benches/regions_integration.py [--quick] [--out results/regions-integration]
"""

import argparse
import json
import pathlib
import time
import warnings

import numpy as np
from scipy.stats import qmc

import stillpoint as sp

# (name, stillpoint keyword arguments, dimension, membership test, box lo, box hi)
def ball(s):
    return (f"ball s={s}", {"shape": "ball:1", "d": s}, s,
            lambda x: (x * x).sum(1) <= 1.0, -np.ones(s), np.ones(s))


def simplex(s):
    return (f"simplex s={s}", {"shape": "simplex", "d": s}, s,
            lambda x: (x >= 0).all(1) & (x.sum(1) <= 1.0), np.zeros(s), np.ones(s))


CUTS = "max(max(x1 + x2 + x3 - 1.8, x1 - x2 - 0.4), max(x2 + 2*x3 - 2, 0.3 - x1 - x3))"


def polytope():
    def inside(x):
        a, b, c = x[:, 0], x[:, 1], x[:, 2]
        return ((a + b + c <= 1.8) & (a - b <= 0.4) & (b + 2 * c <= 2) & (a + c >= 0.3)
                & (x >= 0).all(1) & (x <= 1).all(1))
    box = [0, 1, 0, 1, 0, 1]
    return ("polytope, 4 cuts of [0,1]^3", {"region": CUTS, "box": box}, 3, inside,
            np.zeros(3), np.ones(3))


def paper(i):
    g = {
        1: ("17*x^2 - 16*|x|*y + 17*y^2 - 225", [-4.3, 4.3, -4.3, 4.3],
            lambda x, y: 17 * x**2 - 16 * abs(x) * y + 17 * y**2 - 225),
        4: ("|x| + 2*|y| - 5", [-5.1, 5.1, -2.6, 2.6],
            lambda x, y: abs(x) + 2 * abs(y) - 5),
    }[i]
    expr, box, f = g
    return (f"g{i} (eq. 58)", {"region": expr, "box": box}, 2,
            lambda x: f(x[:, 0], x[:, 1]) <= 0, np.array(box[0::2]), np.array(box[1::2]))


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


def reference_values(fs, inside, lo, hi, seed, simplex_like=False, total=1 << 22):
    rng = np.random.default_rng(seed)
    sums = np.zeros(len(fs))
    squares = np.zeros(len(fs))
    got = 0
    s = len(lo)
    while got < total:
        if simplex_like:
            # Exact uniform points of the simplex (a flat Dirichlet): rejection from the
            # box would keep 1 in s! of them.
            e = rng.exponential(size=(1 << 18, s + 1))
            x = e[:, :s] / e.sum(1, keepdims=True)
        else:
            x = rng.random((1 << 18, s)) * (hi - lo) + lo
        x = x[inside(x)][: total - got]
        got += len(x)
        for i, f in enumerate(fs):
            v = f(x)
            sums[i] += v.sum()
            squares[i] += (v * v).sum()
    mean = sums / got
    return mean, np.sqrt(np.maximum(squares / got - mean**2, 1e-300))


def measure(x, kw, fs, mean, sd):
    m = sp.metrics(x, **{k: v for k, v in kw.items() if k in ("region", "box", "shape")})
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


def write(out, rows):
    (out / "regions_integration.json").write_text(json.dumps(rows, indent=1))
    lines = [
        "| region | n | energy distance D²: ours / Sobol'+rej. / uniform / space-filling "
        "| RMS integral error (in σ_f): ours / Sobol'+rej. / uniform / space-filling "
        "| d_min: ours / Sobol'+rej. / space-filling | ours: seconds |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        o, b, u, f = r["ours"], r["sobol+rejection"], r["uniform"], r["space-filling"]
        lines.append(
            f"| {r['region']} | {r['n']} "
            f"| {o['energy_distance']:.2e} / {b['energy_distance']:.2e} / "
            f"{u['energy_distance']:.2e} / {f['energy_distance']:.2e} "
            f"| {o['rms_error']:.2e} / {b['rms_error']:.2e} / {u['rms_error']:.2e} / "
            f"{f['rms_error']:.2e} "
            f"| {o['min_distance']:.4f} / {b['min_distance']:.4f} / {f['min_distance']:.4f} "
            f"| {o['seconds']:.1f} |")
    (out / "regions_integration.md").write_text("\n".join(lines) + "\n")
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default="results/regions-integration")
    ap.add_argument("--resume", action="store_true",
                    help="keep the rows already in OUT and run only the cases after them")
    args = ap.parse_args()
    # The long-call warning is expected at n = 1000, s = 8.
    warnings.filterwarnings("ignore", category=RuntimeWarning)
    cases = [(ball(2), [50, 200]), (ball(3), [50, 200, 1000]), (ball(4), [200]),
             (ball(6), [200]), (ball(8), [200, 1000]), (simplex(3), [100, 400]),
             (simplex(4), [100]), (simplex(6), [200]), (polytope(), [100, 400]),
             (paper(1), [100]), (paper(4), [100, 400])]
    if args.quick:
        cases = [(ball(3), [50]), (simplex(3), [50])]
    reps = 4 if args.quick else 16
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    if args.resume and (out / "regions_integration.json").exists():
        rows = json.loads((out / "regions_integration.json").read_text())
    done = {(r["region"], r["n"]) for r in rows}
    for (name, kw, s, inside, lo, hi), ns in cases:
        ns = [n for n in ns if (name, n) not in done]
        if not ns:
            continue
        rng = np.random.default_rng(12345)
        fs = integrands(s, lo, hi, rng)
        mean, sd = reference_values(fs, inside, lo, hi, 777, name.startswith("simplex"))
        gen = {k: v for k, v in kw.items()}
        for n in ns:
            row = {"region": name, "s": s, "n": n}
            t = time.perf_counter()
            x = sp.generate(n, goal="integration", **gen)
            row["ours"] = measure(x, kw, fs, mean, sd)
            row["ours"]["seconds"] = time.perf_counter() - t
            t = time.perf_counter()
            x = sp.generate(n, goal="space-filling", **gen)
            row["space-filling"] = measure(x, kw, fs, mean, sd)
            row["space-filling"]["seconds"] = time.perf_counter() - t
            sob = [measure(sobol_rejection(inside, lo, hi, n, r), kw, fs, mean, sd)
                   for r in range(reps)]
            row["sobol+rejection"] = mean_of(sob)
            uni = [measure(uniform_rejection(inside, lo, hi, n, r), kw, fs, mean, sd)
                   for r in range(reps)]
            row["uniform"] = mean_of(uni)
            rows.append(row)
            o, b = row["ours"], row["sobol+rejection"]
            print(f"{name:28s} n={n:5d}  D2 {o['energy_distance']:.3e} vs {b['energy_distance']:.3e}"
                  f"  rms {o['rms_error']:.2e} vs {b['rms_error']:.2e}"
                  f"  dmin {o['min_distance']:.3f} vs {b['min_distance']:.3f}"
                  f"  {o['seconds']:.1f} s", flush=True)
            write(out, rows)
    print("\n".join(write(out, rows)))

if __name__ == "__main__":
    main()
