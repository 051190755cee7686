"""Cells of benches/quad.py run with another rule (DIR/stillpoint.json.gz) against quad's
own runs and the references in results/quad: reliability, median evaluations, the best
reliable reference, cells met, and per family the geometric mean of the ratio.

    [OLD=FILE] python3 results/quad/bayes-tent/compare.py DIR
"""
import gzip, json, sys, glob, os, statistics as st
R = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
def load(p):
    d = json.load(gzip.open(p)); return d['cells']
new = load(sys.argv[1] + '/stillpoint.json.gz')
old = load(os.environ.get('OLD', R + '/stillpoint.json.gz'))  # OLD=FILE: quad's runs of before
refs = {os.path.basename(p)[:-8]: load(p) for p in glob.glob(R + '/*.json.gz') if 'stillpoint' not in p and 'single' not in p}
def stat(cell):
    runs = cell['runs'] if isinstance(cell, dict) else cell
    ok = sum(r['ok'] for r in runs) / len(runs)
    return ok, st.median(r['n'] for r in runs), len(runs)
met = [0, 0, 0]
for key in new:
    if key not in old:
        continue
    ok, n, c = stat(new[key])
    o = stat(old[key])
    best = None
    for m, cells in refs.items():
        if key in cells:
            rk, rn, rc = stat(cells[key])
            if rk >= 0.925 and (best is None or rn < best[1]): best = (m, rn)
    def okn(ok, n): return ok >= 0.925 and (best is None or n <= best[1])
    met[0] += 1; met[1] += okn(ok, n); met[2] += bool(o) and okn(o[0], o[1])
    print(f"{key:34s} new {ok:4.0%} {n:9.0f} ({c:3d}) | old {o[0]:4.0%} {o[1]:9.0f} | best {best} | new/best {n/best[1] if best else float('nan'):.2f} old/best {o[1]/best[1] if best else float('nan'):.2f}")
print('cells', met[0], 'met new', met[1], 'met old', met[2])
import math, collections
g = collections.defaultdict(lambda: [[], []])
for key in new:
    if key not in old:
        continue
    ok, n, c = stat(new[key]); o = stat(old[key])
    best = None
    for m, cells in refs.items():
        if key in cells:
            rk, rn, rc = stat(cells[key])
            if rk >= 0.925 and (best is None or rn < best[1]): best = (m, rn)
    if best:
        fam = key.split('|')[0]
        g[fam][0].append(math.log(n / best[1])); g[fam][1].append(math.log(o[1] / best[1]))
for fam, (a, b) in g.items():
    print(fam, 'new GM %.2f old GM %.2f' % (math.exp(sum(a)/len(a)), math.exp(sum(b)/len(b))), len(a))
