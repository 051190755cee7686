#!/usr/bin/env python3
"""What `stillpoint.quad`'s face test sees on the integrands of benches/quad.py: per family
and dimension, over 100 instances, the largest change of f over the test's steps toward
either corner as a share of f's size (min / median / max), recomputed here in NumPy with
the library's geometry (three points 2^-30, 2^-29, 2^-28 of the way from a corner to an
interior point, toward two opposite corners; NumPy draws the corner and the point), and
the share of instances for which the library itself chose the first-order lattice (its
own face test: ``quad(..., rel_tol=0.5)``, read from ``rule``; only where the face test
runs: the cube and bounded laws, not under unbounded laws, where the probe round decides).

    target/py-venv/bin/python benches/quad_face_test.py [--families a,b] [--instances 100]
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import quad as Q  # noqa: E402

STEP = 2.0 ** -30


def integrand(family, s, run):
    """f on the cube (model families through their laws' quantiles) and the space texts
    quad takes for it (None on the cube)."""
    if family in Q.MODEL_FAMILIES:
        on_cube, texts, on_values, _ = Q.model(family, s, run)
        return on_cube, texts, on_values
    p = Q.instance(family, s, run)
    f = lambda x: Q.value(family, p, x)  # noqa: E731
    return f, None, f


def change(g, d, seed):
    rng = np.random.default_rng([seed, 0xFACE])
    b = rng.uniform(0.25, 0.75, d)
    c0 = rng.integers(0, 2, d).astype(float)
    ts = STEP * np.array([1.0, 2.0, 4.0])
    pts = [c[None, :] + ts[:, None] * (b - c)[None, :] for c in (c0, 1 - c0)]
    v = np.asarray(g(np.vstack(pts + [b[None, :]])), dtype=float)
    if not np.all(np.isfinite(v)):
        return np.inf
    out = 0.0
    for i in range(2):
        f = v[3 * i:3 * i + 3]
        size = max(np.max(np.abs(f)), abs(v[-1]))
        if size > 0:
            out = max(out, np.max(np.abs(np.diff(f))) / size)
    return out


def main():
    import stillpoint as sp

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--families", default=",".join(Q.FAMILIES))
    ap.add_argument("--instances", type=int, default=100)
    args = ap.parse_args()
    print("| family | s | change / size: min · median · max | first-order lattice chosen |")
    print("|---|---|---|---|")
    for family in args.families.split(","):
        for s in Q.FAMILIES[family]:
            d = s[0] if isinstance(s, tuple) else s
            seen, chosen = [], []
            for run in range(args.instances):
                g, texts, on_values = integrand(family, s, run)
                seen.append(change(g, d, run))
                r = sp.quad(on_values, d, rel_tol=0.5, seed=run, space=texts)
                if "face test" in r.rule_reason:
                    chosen.append(r.rule == "first-order lattice")
            v = np.array(seen)
            shown = f"{np.mean(chosen):.0%}" if chosen else "— (no face test)"
            print(f"| {family} | {s} | {v.min():.1e} · {np.median(v):.1e} · {v.max():.1e} "
                  f"| {shown} |", flush=True)


if __name__ == "__main__":
    main()
