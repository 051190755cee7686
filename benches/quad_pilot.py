"""`quad`'s pilot on the cube: coverage and width at a fixed number of evaluations when
the rule is chosen from a first round, by the package and by other judges.

For each case (families on the cube, where no law chooses the rule) and seed:
- each rule alone to N evaluations (``rule=``, ``max_n=N``), its first two rounds
  (4 replicates of 64, then 64 more points each) captured as f sees them;
- the package's own pilot (no ``rule=``, ``max_n=N + 256``): the lattice's first round,
  Sobol's first round, and the rule kept goes on from its own first round to N, the
  other's 256 evaluations counted;
- other judges, from the captured rounds: ``hw1`` the half-width after one round (the
  package's judge), ``pool1`` the replicate spread pooled over the nested prefixes,
  ``hw2``/``pool2`` the same after two rounds (512 evaluations of the other rule), each
  keeping Sobol' when its score is below c times the lattice's, for c in ``BIASES``.
Coverage at level 0.95 over the seeds (±1.3 % at 300) · the geometric mean of the
relative half-width · the RMSE of the relative error.

    target/py-venv/bin/python benches/quad_pilot.py [--seeds 300] [--n 4096]
    target/py-venv/bin/python benches/quad_pilot.py --markdown   # every N measured

Writes results/quad/pilot-<N>.json.
"""

import math
import os
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
from quad_fixed_n import integrand  # noqa: E402
from quad_interval import study_main  # noqa: E402
import quad_fixed_n  # noqa: E402

CASES = [
    ("keister s=5", "keister", 5),
    ("keister s=10", "keister", 10),
    ("lognormal s=5", "lognormal", 5),
    ("oscillatory s=5", "oscillatory", 5),
    ("product peak s=5", "product peak", 5),
    ("corner peak s=5", "corner peak", 5),
    ("gaussian s=5", "gaussian", 5),
    ("corner peak s=20", "corner peak", 20),
]
PILOT = 256
# The pilot keeps Sobol' when its first-round half-width is below this share of the
# lattice's (1: the smaller wins); each threshold is its own choice, measured alike.
BIASES = (1.0, 0.8, 0.7, 0.6, 0.5)


JUDGES = ("hw1", "pool1", "hw2", "pool2")


def judges(values, rounds):
    """Scores of a rule from its first `rounds` rounds (4 replicates, 64 then 64 more
    points each), captured as f saw them: ``hw`` the package's guarded half-width after
    those rounds, ``pool`` the replicate spread pooled over every nested prefix from 32
    points up, each level's variance scaled to the last by an error falling like 1/n
    (more degrees of freedom than one level's four means)."""
    reps = [np.concatenate([b[r] for b in values[:rounds]]) for r in range(4)]
    size = len(reps[0])
    means = {m: np.array([v[:m].mean() for v in reps]) for m in (32, 64, 128) if m <= size}
    top = means[size]
    hw = 3.182446305284263 * top.std(ddof=1) / 2.0
    hw = max(hw, abs(top.mean() - means[size // 2].mean()))
    pool = np.mean([means[m].var(ddof=1) * (m / size) ** 2 for m in means])
    return {f"hw{rounds}": hw, f"pool{rounds}": math.sqrt(pool)}


def run_case(family, s, n, seeds):
    import stillpoint as sp

    rows = {"lattice": [], "sobol": [], "ratio": [], "package": []}
    for seed in range(seeds):
        f, d, space, truth = integrand(family, s, seed)
        res, pilot = {}, {}
        for rule in ("lattice", "sobol"):
            seen = []

            def g(x, seen=seen):
                y = np.asarray(f(x), dtype=np.float64)
                seen.append(y.reshape(4, -1))
                return y

            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                kw = dict(abs_tol=0.0, rel_tol=0.0, seed=seed, rule=rule, space=space)
                sp.quad(g, d, max_n=2 * PILOT, **kw)
                r = sp.quad(f, d, max_n=n, **kw)
            pilot[rule] = judges(seen, 1) | judges(seen, 2)
            res[rule] = [float(r.estimate - truth) / abs(truth),
                         float(r.half_width) / abs(truth), int(r.n)]
            rows[rule].append(res[rule])
        rows["ratio"].append({j: pilot["sobol"][j] / max(pilot["lattice"][j], 1e-300)
                              for j in JUDGES})
        # The package's own pilot (no rule named, no law: Rule::Pilot), given the
        # budget of N plus Sobol's first round.
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = sp.quad(f, d, abs_tol=0.0, rel_tol=0.0, seed=seed, space=space,
                        max_n=n + PILOT)
        rows["package"].append([float(r.estimate - truth) / abs(truth),
                                float(r.half_width) / abs(truth), int(r.n),
                                r.rule == "sobol"])
    return rows


def summary(rows):
    chosen, share = {}, {}
    for j in JUDGES:
        cost = PILOT * (1 if j.endswith("1") else 2)
        for c in BIASES:
            pick = [q[j] < c for q in rows["ratio"]]
            key = f"{j}<{c:g}"
            chosen[key] = [(sb if p else lat)[:2] + [(sb if p else lat)[2] + cost]
                           for lat, sb, p in zip(rows["lattice"], rows["sobol"], pick)]
            share[key] = float(np.mean(pick))
    out = quad_fixed_n.summary({"lattice": rows["lattice"], "sobol": rows["sobol"],
                                "package": [r[:3] for r in rows["package"]]} | chosen)
    share["package"] = float(np.mean([r[3] for r in rows["package"]]))
    for key, v in share.items():
        out[key]["sobol_share"] = v
    out["pilot"] = out["package"]
    return out


SHOWN = ("hw1<1", "pool1<1", "hw2<0.7", "pool2<0.7")


def table(data, n):
    """Per case: each rule alone and the package's pilot (coverage · relative half-width
    · RMSE), then the other judges measured (coverage · width over the lattice's)."""
    lines = [f"| family (N = {n}, seeds) | lattice | sobol | package's pilot (N + {PILOT}) "
             "| chose Sobol' | " + " | ".join(SHOWN) + " |", "|---" * (5 + len(SHOWN)) + "|"]
    for label, _, _ in CASES:
        if label not in data:
            continue
        sm = data[label]["summary"]
        cells = [f"{sm[m]['coverage'] * 100:.1f} % · {sm[m]['width']:.2g} · "
                 f"{sm[m]['rmse']:.2g}" for m in ("lattice", "sobol", "pilot")]
        cells.append(f"{sm['pilot']['sobol_share'] * 100:.0f} %")
        lat = sm["lattice"]["width"]
        cells += [f"{sm[m]['coverage'] * 100:.1f} % · {sm[m]['width'] / lat:.2f}×"
                  for m in SHOWN if m in sm]
        lines.append(f"| {label} ({data[label]['seeds']}) | " + " | ".join(cells) + " |")
    return lines


def main():
    study_main("pilot", CASES, run_case, summary, table)


if __name__ == "__main__":
    main()
