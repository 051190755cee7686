# The cheapest dual vector of the first S coordinates at each level 2^8..2^16 (run from the
# repository root): dualcost.py VECTOR S1,S2,..; VECTOR `table` (the tent table), a name of
# pfeval.py's VECTORS or comma-separated values. A vector's cost is the sum over its
# nonzero entries h_k (|h_k| <= 16) of 0.92 + 2 ln|h_k| (pick_freeze_search.patch's guard).
import numpy as np, sys, os
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pfsearch import ZT
from pfeval import VECTORS
A=0.92; H=16; n=1<<16
def nonzero_cheapest(z, levels):
    # per level, the least over j of the cheapest dual vector whose last nonzero entry is j
    res={m:np.inf for m in levels}
    dist=np.full(n,np.inf); dist[0]=0.0
    for zj in z:
        for m in levels:
            D=dist.reshape(-1,1<<m).min(axis=0); mask=(1<<m)-1
            for h in range(1,H+1):
                res[m]=min(res[m], D[(-h*int(zj))&mask]+A+2*np.log(h))
        new=dist.copy()
        for h in range(1,H+1):
            s=(h*int(zj))%n; c=A+2*np.log(h)
            new=np.minimum(new,np.roll(dist,s)+c); new=np.minimum(new,np.roll(dist,-s)+c)
        dist=new
    return [round(res[m],2) for m in levels]
z=ZT if sys.argv[1]=='table' else np.array([int(x) for x in VECTORS.get(sys.argv[1],sys.argv[1]).split(',')])
for s in [int(x) for x in sys.argv[2].split(',')]:
    print(s, ' '.join(f'{c:.2f}' for c in nonzero_cheapest(z[:s], list(range(8,17)))))
