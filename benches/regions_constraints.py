"""Linear constraints and mixtures against Sobol' + rejection and hit-and-run (BoTorch's
HitAndRunPolytopeSampler): one mixture cell (S = 4 components, n = 100: the 3-simplex in
the first three components), the 4-cut polytope of benches/regions_integration.py given
as --constraint, and the README's bounded three-component mixture with a cut, each
measured as regions_integration.py measures its cells (energy distance to uniform, RMS
error of 24 random smooth integrals, minimum distance; Sobol' + rejection, hit-and-run
and uniform rejection as means of 16). The anchors and measures are those of
regions_integration.py, imported from it; its table also has bounded mixtures of
S = 3-6 components at n = 100 and 1000.

Usage (the package installed, SciPy, BoTorch): python benches/regions_constraints.py
"""
import importlib.util, os, time, warnings
import numpy as np
import stillpoint as sp
spec = importlib.util.spec_from_file_location("ri", os.path.join(os.path.dirname(os.path.abspath(__file__)), "regions_integration.py"))
ri = importlib.util.module_from_spec(spec); spec.loader.exec_module(ri)
for w in (RuntimeWarning, UserWarning, FutureWarning):
    warnings.filterwarnings("ignore", category=w)
reps = 16
n = 100


def cell(name, gen, reg):
    fs = ri.integrands(reg["s"], reg["lo"], reg["hi"], np.random.default_rng(12345))
    mean, sd = ri.reference_values(fs, reg, 777)
    kw, inside, lo, hi = reg["kw"], reg["inside"], reg["lo"], reg["hi"]
    row = {}
    for goal in ("integration", "space-filling"):
        t = time.perf_counter()
        x = sp.generate(n, goal=goal, **gen)
        sec = time.perf_counter() - t
        if reg["project"]:
            assert np.abs(x.sum(1) - 1).max() <= 1e-12
            x = x[:, :reg["s"]]
        row[goal] = ri.measure(x, kw, fs, mean, sd)
        row[goal]["seconds"] = sec
    row["sobol"] = ri.mean_of([ri.measure(ri.sobol_rejection(inside, lo, hi, n, r), kw, fs, mean, sd) for r in range(reps)])
    row["hit-and-run"] = ri.mean_of([ri.measure(ri.hit_and_run(reg, n, r)[0], kw, fs, mean, sd) for r in range(reps)])
    row["uniform"] = ri.mean_of([ri.measure(ri.uniform_rejection(inside, lo, hi, n, r), kw, fs, mean, sd) for r in range(reps)])
    o, f, b, h, u = (row[k] for k in ("integration", "space-filling", "sobol", "hit-and-run", "uniform"))
    print(f"{name}: n={n}")
    for k in ("energy_distance", "rms_error", "min_distance"):
        print(f"  {k:16s} ours {o[k]:.3e}  space-filling {f[k]:.3e}  sobol+rej {b[k]:.3e}  hit-and-run {h[k]:.3e}  uniform {u[k]:.3e}  ratio sobol/ours {b[k]/o[k]:.2f}")
    print(f"  seconds: integration {o['seconds']:.1f}, space-filling {f['seconds']:.1f}", flush=True)


s3 = ri.simplex(3)
s3["project"] = True
# x1 >= 0 twice (BoTorch needs an inequality besides the bounds).
s3["polytope"] = (np.array([[-1.0, 0, 0, 0]]), np.zeros(1), np.ones((1, 4)), np.ones(1), np.zeros(4), np.ones(4))
cell("mixture S=4 (3-simplex in x1..x3)", {"d": 4, "mixture": True}, s3)
cons = ["x1 + x2 + x3 <= 1.8", "x1 - x2 <= 0.4", "x2 + 2*x3 <= 2", "x1 + x3 >= 0.3"]
cell("polytope, 4 cuts of [0,1]^3 as --constraint", {"constraints": cons, "box": [0, 1, 0, 1, 0, 1]},
     ri.polytope())

# The README's bounded mixture (S = 3, bounds and one cut), n = 100, in (x1, x2).
lo, hi = np.array([0.1, 0.0]), np.array([0.8, 0.6])
readme = ri.region(
    "bounded mixture S=3 (README's)", None,
    {"region": "max(x1 + x2 - 1, 0.3 - x1 - x2)", "box": [0.1, 0.8, 0, 0.6]}, 2,
    lambda x: (x[:, 0] + x[:, 1] <= 1) & (x[:, 0] + x[:, 1] >= 0.3), lo, hi,
    polytope=(np.array([[-1.0, -1.0, 0.0]]), np.array([-0.3]), np.ones((1, 3)), np.ones(1),
              np.array([0.1, 0.0, 0.0]), np.array([0.8, 0.6, 1.0])), project=True)
cell("bounded mixture S=3 (README's), in x1,x2",
     {"d": 3, "mixture": True, "box": [0.1, 0.8, 0, 0.6, 0, 1], "constraints": ["x1 + x2 >= 0.3"]},
     readme)
