"""What choosing `quad`'s rule from a pilot round would do on the cube, before building
it: coverage and width at a fixed number of evaluations when the rule is the one whose
first round had the smaller spread.

For each case (families on the cube, where no law chooses the rule) and seed, both rules
run their first round (4 replicates of 64 points, ``max_n=256``) and, separately, to N
evaluations (``max_n=N``; the first round of that run is the pilot's points, so the
pilot is reused). "pilot" keeps the N-point run of the rule whose pilot half-width was
smaller; its interval is the package's own at N, and the other rule's 256 evaluations
are the pilot's price (N + 256 in all). Coverage at level 0.95 over the seeds (±1.3 % at
300) · the geometric mean of the relative half-width · the RMSE of the relative error,
for the lattice alone (today's rule on the cube), Sobol' alone, and the pilot's choice
(with the share of seeds where it chose Sobol').

    target/py-venv/bin/python benches/quad_pilot.py [--seeds 300] [--n 4096]
    target/py-venv/bin/python benches/quad_pilot.py --markdown   # every N measured

Writes results/quad/pilot-<N>.json.
"""

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
]
PILOT = 256


def run_case(family, s, n, seeds):
    import stillpoint as sp

    rows = {"lattice": [], "sobol": [], "pilot": []}
    for seed in range(seeds):
        f, d, space, truth = integrand(family, s, seed)
        res, pilot = {}, {}
        for rule in ("lattice", "sobol"):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                kw = dict(abs_tol=0.0, rel_tol=0.0, seed=seed, rule=rule, space=space)
                pilot[rule] = float(sp.quad(f, d, max_n=PILOT, **kw).half_width)
                r = sp.quad(f, d, max_n=n, **kw)
            res[rule] = [float(r.estimate - truth) / abs(truth),
                         float(r.half_width) / abs(truth), int(r.n)]
            rows[rule].append(res[rule])
        chosen = min(("lattice", "sobol"), key=lambda k: pilot[k])
        rows["pilot"].append(res[chosen][:2] + [res[chosen][2] + PILOT, chosen == "sobol"])
    return rows


def summary(rows):
    out = quad_fixed_n.summary({k: [r[:3] for r in v] for k, v in rows.items()})
    out["pilot"]["sobol_share"] = float(np.mean([r[3] for r in rows["pilot"]]))
    return out


def table(data, n):
    lines = [f"| family (N = {n}, seeds) | lattice | sobol | pilot's choice (N + {PILOT}) "
             "| chose Sobol' |", "|---|---|---|---|---|"]
    for label, _, _ in CASES:
        if label not in data:
            continue
        sm = data[label]["summary"]
        cells = [f"{sm[m]['coverage'] * 100:.1f} % · {sm[m]['width']:.2g} · "
                 f"{sm[m]['rmse']:.2g}" for m in ("lattice", "sobol", "pilot")]
        lines.append(f"| {label} ({data[label]['seeds']}) | " + " | ".join(cells)
                     + f" | {sm['pilot']['sobol_share'] * 100:.0f} % |")
    return lines


def main():
    study_main("pilot", CASES, run_case, summary, table)


if __name__ == "__main__":
    main()
