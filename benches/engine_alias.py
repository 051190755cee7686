#!/usr/bin/env python3
"""Which dual vectors of `Engine(d)`'s lattice cost the robot arm (results/law-lattice/
engine.md, "The robot arm at 16 384"). The shifted, tent-transformed rank-1 lattice's
error as a function of its shift D is e(D) = sum over the nonzero dual vectors h (h.z = 0
mod 2^m) of F^(h) exp(2 pi i h.D), F = f(laws(tent(y))); so the mean of
e(D) exp(-2 pi i h.D) over uniform random shifts estimates F^(h) for a dual h, and
2|F^(h)|^2 / E[e^2] is the share of the rule's mean square error that h (with -h)
carries. Nominal laws of benches/uq_families.py's RobotArm (theta uniform on
[0, 2 pi], lengths lognormal(log 0.5, 0.2)); theta_1 does not move the arm's distance, so
its entry is left at 0. An estimated share has noise of about 2/K.

    python benches/engine_alias.py [table|vec:NAME] [ORDER] [M] [K]

ORDER: input ORDER[j] takes coordinate j (dot-separated, default 0.1.2.3.4.5.6.7, as
benches/uq_engine.py's ORDER=p...); M: the level 2^M (14); K: shifts (1 500). Prints
the rule's relative RMSE and the dual vectors with the largest shares (entries up to 8
on the angles, up to 4 on the lengths).
"""
import itertools
import os
import re
import sys

import numpy as np
from scipy.stats import norm

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def generator(name):
    if name == "table":
        text = open(os.path.join(ROOT, "sequences", "src", "engine_table.rs")).read()
        body = text[text.index("= [") + 3:text.index("];")]
        return np.array([int(v) for v in re.findall(r"\d+", body)], dtype=np.int64)
    return np.load(os.path.join(ROOT, "target", "engine-vectors", name[4:] + ".npy"))


def arm(y):
    u = 1.0 - np.abs(2.0 * y - 1.0)
    theta = 2 * np.pi * u[:, :4]
    length = np.exp(np.log(0.5) + 0.2 * norm.ppf(np.clip(u[:, 4:], 1e-16, 1 - 1e-16)))
    ang = np.cumsum(theta, axis=1)
    return np.hypot((length * np.cos(ang)).sum(1), (length * np.sin(ang)).sum(1))


def main():
    args = sys.argv[1:] + [None] * 4
    name = args[0] or "table"
    perm = np.array([int(v) for v in (args[1] or "0.1.2.3.4.5.6.7").split(".")])
    m = int(args[2] or 14)
    shifts = int(args[3] or 1500)
    n = 1 << m
    z = np.empty(8, dtype=np.int64)
    z[perm] = generator(name)[:8] % n
    base = (np.arange(n)[:, None] * z[None, :] % n) / n
    rng = np.random.default_rng(7)
    D = rng.random((shifts, 8))
    e = np.array([arm((base + s) % 1.0).mean() for s in D])
    mean = e.mean()
    e -= mean
    mse = np.mean(e ** 2)
    ranges = [[0]] + [range(-8, 9)] * 3 + [range(-4, 5)] * 4
    H = np.array(list(itertools.product(*ranges)), dtype=np.int64)
    H = H[np.any(H != 0, axis=1) & ((H @ z) % n == 0)]
    H = H[H[np.arange(len(H)), np.argmax(H != 0, axis=1)] > 0]
    share = np.array([2 * abs(np.mean(e * np.exp(-2j * np.pi * (D @ h)))) ** 2 for h in H]) / mse
    order = np.argsort(-share)
    print(f"{name} order {'.'.join(map(str, perm))} at 2^{m}: relative RMSE {np.sqrt(mse) / mean:.2e}"
          f" over {shifts} shifts; {len(H)} dual vectors searched")
    for i in order[:5]:
        print(f"    {tuple(int(v) for v in H[i])}  share {share[i]:.3f}")


if __name__ == "__main__":
    main()
