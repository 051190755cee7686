import numpy as np, sys
exec(open('results/sensitivity/product/prod.py').read().split("layouts={}")[0].replace("def est(","def _unused("))
def est(u,d,centre):
    A=u[:,0::2]; B=u[:,1::2]
    ya=f(A)-centre; yb=f(B)-centre
    n=len(ya); mean=(ya.sum()+yb.sum())/(2*n); V=((ya**2).sum()+(yb**2).sum())/(2*n)-mean**2
    out={k:[] for k in 'sal sob sob2 janon'.split()}
    for i in range(d):
        ab=A.copy(); ab[:,i]=B[:,i]; yi=f(ab)-centre
        out['sal'].append(np.mean(yb*(yi-ya))/V)
        out['sob'].append((np.mean(yb*yi)-ya.mean()*yb.mean())/V)
        out['sob2'].append((np.mean(yb*yi)-mean**2)/V)
        m=(yb.mean()+yi.mean())/2; out['janon'].append((np.mean(yb*yi)-m*m)/((np.mean(yb**2)+np.mean(yi**2))/2-m*m))
    return {k:np.array(v) for k,v in out.items()}
rng=np.random.default_rng(1); shifts=rng.random((32,64))
for N in [1024,2048,4096,8192,16384,32768]:
    e={}
    for s in shifts:
        r=est(lattice(N,list(range(8)),s[:8]),d,0.0625)
        for k,v in r.items(): e.setdefault(k,[]).append(np.mean((v-S)**2))
    print(N,' '.join(f"{k} {np.sqrt(np.mean(v)):.2e}" for k,v in e.items()))
