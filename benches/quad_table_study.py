"""`quad`'s rule on the cube at a fixed N, by table: four replicates of N/4 points of the
extensible lattice sequence with the tent table (quad's) or the first-order table
(`Engine(d)`'s), the same seeds, instances and shifts (`stillpoint._core.sequence_points`,
the package's own points), on the cube families of benches/quad.py. Per (family, s, N):
the first-order table's RMSE of the relative error of the four replicates' mean, and the
geometric mean of its Student half-width (t_3, level 0.95; without quad's round guard),
each over the tent table's. N = 1 024, 4 096, 16 384; SEEDS instances (48).

    SEEDS=48 target/py-venv/bin/python benches/quad_table_study.py
"""
import math, sys, os
import numpy as np
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import stillpoint as sp
from quad_models import FAMILIES, instance, value, exact
SEEDS = int(os.environ.get("SEEDS", 48)); NS = [1024, 4096, 16384]
T3 = 3.182446305284263
res = {}
for fam, ss in FAMILIES.items():
    for s in ss:
        for N in NS:
            out = {}
            for table in ("tent", "first-order"):
                errs, widths = [], []
                for seed in range(SEEDS):
                    p = instance(fam, s, seed); ex = exact(fam, p)
                    reps = [value(fam, p, np.asarray(sp._core.sequence_points(s, seed=seed, replicate=r, count=N // 4, table=table))).mean() for r in range(4)]
                    m = np.mean(reps); sd = np.std(reps, ddof=1)
                    errs.append((m - ex) / ex); widths.append(T3 * sd / 2 / abs(ex))
                out[table] = (math.sqrt(np.mean(np.square(errs))), math.exp(np.mean(np.log(np.maximum(widths, 1e-300)))))
            r = out["first-order"][0] / out["tent"][0]; w = out["first-order"][1] / out["tent"][1]
            res.setdefault(fam, []).append((r, w))
            print(f"{fam:14s} s={s:2d} N={N:5d} rmse fo/tent {r:.2f} width fo/tent {w:.2f}", flush=True)
allr = []; allw = []
for fam, v in res.items():
    r = [a for a, _ in v]; w = [b for _, b in v]; allr += r; allw += w
    print(f"{fam:14s} rmse {math.exp(np.mean(np.log(r))):.2f} width {math.exp(np.mean(np.log(w))):.2f}")
print(f"all rmse {math.exp(np.mean(np.log(allr))):.2f} width {math.exp(np.mean(np.log(allw))):.2f}")
