"""The extensible randomised lattice of `stillpoint.quad` in NumPy, with and without the
tent transform, for the studies of its interval and of its rule (benches/quad_interval.py):
point k of a replicate is tent(frac(φ₂(k)·z/2^20 + Δ)) with φ₂(k) the 20-bit reversal
of k, z the tabulated generating vector (sequences/src/extensible_table.rs) and Δ the
replicate's uniform shift. ``check()`` compares it bit for bit with the package's
``_core.sequence_points`` at the package's own shifts.
"""

import os
import re

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BITS = 20
_Z = None


def generator(d):
    global _Z
    if _Z is None:
        with open(os.path.join(ROOT, "sequences", "src", "extensible_table.rs")) as fh:
            text = fh.read()
        body = text[text.index("= [") + 3:text.index("];")]
        _Z = np.array([int(v) for v in re.findall(r"\d+", body)], dtype=np.uint64)
    return _Z[:d]


def reversed_bits(k):
    k = np.asarray(k, dtype=np.uint64)
    j = np.zeros_like(k)
    for b in range(BITS):
        j |= ((k >> np.uint64(b)) & np.uint64(1)) << np.uint64(BITS - 1 - b)
    return j


def points(d, shift, start, count, tent=True):
    """Points [start, start + count) of the replicate with shift Δ = ``shift`` (d values
    in [0, 1)), tent-transformed unless ``tent=False``."""
    j = reversed_bits(np.arange(start, start + count, dtype=np.uint64))
    num = (j[:, None] * generator(d)[None, :]) & np.uint64((1 << BITS) - 1)
    y = num.astype(np.float64) * (1.0 / (1 << BITS)) + np.asarray(shift)[None, :]
    y = np.where(y >= 1.0, y - 1.0, y)
    return 1.0 - np.abs(2.0 * y - 1.0) if tent else y


def check():
    from stillpoint import _core

    d = 7
    base = _core.sequence_points(d, 3, 2, 0, 1)
    # Recover the shift from the first point (φ₂(0) = 0): tent(Δ) = x gives Δ = x/2 or
    # 1 − x/2; the package's later points decide which.
    ref = _core.sequence_points(d, 3, 2, 0, 4096)
    best = None
    for mask in range(2 ** d):
        shift = np.array([base[0, i] / 2 if not (mask >> i) & 1 else 1 - base[0, i] / 2
                          for i in range(d)])
        err = np.abs(points(d, shift, 0, 4096) - ref).max()
        best = err if best is None else min(best, err)
    return best


if __name__ == "__main__":
    print("largest difference from the package's points:", check())
