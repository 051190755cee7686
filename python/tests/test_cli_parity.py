"""The package gives what the command line gives: the same points (bit for bit) and the
same figures."""

import json

import numpy as np
import pytest

import stillpoint as sp


def same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def test_default_generate_is_the_cli_npy(cli, tmp_path):
    out = tmp_path / "x.npy"
    cli("generate", "-n", 50, "-s", 3, "-q", "-o", out)
    want = np.load(out)
    got = sp.generate(50, 3)
    assert got.shape == (50, 3) and got.dtype == np.float64 and got.flags.c_contiguous
    assert same_bits(got, np.ascontiguousarray(want, dtype=np.float64))


@pytest.mark.parametrize(
    "flags, kwargs",
    [
        (
            ["-n", 40, "-s", 2, "--seed", 5, "--init", "random", "--steps", 200],
            dict(n=40, d=2, seed=5, init="random", steps=200),
        ),
        (
            ["-n", 30, "-s", 2, "--energy", "e-inf", "--steps", 150, "--shifts", 0],
            dict(n=30, d=2, energy="e-inf", steps=150, shifts=0),
        ),
        (
            ["-n", 24, "-s", 2, "--energy", "md", "--integrator", "lbfgs", "--steps", 50],
            dict(n=24, d=2, energy="md", integrator="lbfgs", steps=50),
        ),
        (
            ["-n", 32, "-s", 3, "--q", "inf", "--p", 2, "--polish", "cd", "--steps", 100],
            dict(n=32, d=3, q="inf", p=2, polish="cd", steps=100),
        ),
        (
            ["-n", 40, "-s", 3, "--target", "curved"],
            dict(n=40, d=3, target="curved"),
        ),
        (
            ["-n", 48, "-s", 8],
            dict(n=48, d=8),
        ),
        (
            ["-n", 20, "--shape", "ball:1@0,0", "--steps", 300],
            dict(n=20, shape="ball:1@0,0", steps=300),
        ),
        (
            ["-n", 20, "--region", "x^2 + 4*y^2 - 1", "--box", "-1,1,-0.5,0.5", "--steps", 200, "--seed", 2],
            dict(n=20, d=2, region="x^2 + 4*y^2 - 1", box=[(-1, 1), (-0.5, 0.5)], steps=200, seed=2),
        ),
    ],
)
def test_generate_options_are_the_cli_flags(cli, tmp_path, flags, kwargs):
    out = tmp_path / "x.npy"
    cli("generate", *flags, "-q", "-o", out)
    assert same_bits(sp.generate(**kwargs), np.load(out))


@pytest.mark.parametrize("name", ["sobol", "halton-scrambled", "lhs", "lattice", "random"])
def test_baselines_are_the_cli_baselines(cli, tmp_path, name):
    out = tmp_path / "b.npy"
    cli("baseline", name, "-n", 64, "-s", 3, "--seed", 7, "-o", out)
    want = np.load(out)
    assert same_bits(sp.baseline(name, 64, 3, seed=7), want)
    assert same_bits(sp.generate(64, 3, method=name, seed=7), want)


def close(a, b, rel=1e-12):
    if a is None or b is None:
        return a is b
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(close(a[k], b[k], rel) for k in a)
    if isinstance(a, str):
        return a == b
    return abs(a - b) <= rel * max(abs(a), abs(b)) or a == b


@pytest.mark.parametrize(
    "points",
    [
        lambda: sp.generate(50, 3),
        lambda: np.random.default_rng(1).random((300, 7)),
        # Coinciding points: infinite energies are null with a note.
        lambda: np.array([[0.2, 0.3], [0.2, 0.3], [0.9, 0.1]]),
        # A single point: no pair.
        lambda: np.array([[0.5, 0.25, 0.75]]),
    ],
)
def test_metrics_are_eval_json(cli, tmp_path, points):
    x = points()
    f = tmp_path / "p.npy"
    np.save(f, x)
    want = json.loads(cli("eval", f, "--json"))
    got = sp.metrics(x)
    assert got.keys() == want.keys()
    assert close(got, want), (got, want)


def test_integrate_is_the_cli_report(cli, tmp_path):
    x = sp.baseline("sobol", 256, 4, seed=3)
    f = tmp_path / "p.npy"
    np.save(f, x)
    want = json.loads(cli("integrate", f, "--json"))
    got = sp.integrate(x)
    assert (got["n"], got["s"], got["exact"]) == (256, 4, 0.0)
    assert [r["function"] for r in got["functions"]] == [f"F{i}" for i in range(1, 9)]
    for g, w in zip(got["functions"], want["functions"]):
        assert g == w
