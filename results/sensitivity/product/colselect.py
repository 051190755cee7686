import numpy as np, re, sys
src=open('sequences/src/extensible_table.rs').read()
Z=np.array([int(x) for x in re.findall(r'\b\d+\b', src.split('= [',1)[1].split('];')[0])],dtype=np.int64)
gamma=float(sys.argv[1]); ncol=int(sys.argv[2]); pool=int(sys.argv[3]); levels=range(int(sys.argv[4]),int(sys.argv[5])+1)
import os; RATE=float(os.environ.get("RATE","2")); AGG=os.environ.get("AGG","max")
def omega(x): return (2*np.pi)**4/24*-(x**4-2*x**3+x**2-1/30)
tabs={m:gamma*omega(np.arange(2**m)/2**m) for m in levels}
ks={m:np.arange(2**m,dtype=np.int64) for m in levels}
R={m:np.ones(2**m) for m in levels}
sel=[]
def score(c, R):
    out=[]
    for m in levels:
        N=2**m; t=tabs[m][(ks[m]*Z[c])%N]
        out.append(np.log(np.mean(R[m]*(1+t))-1)+RATE*m*np.log(2))
    return (max(out) if AGG=="max" else sum(out)), out
for col in range(ncol):
    cands=[c for c in range(pool) if c not in sel]
    if col==0: best=0
    else:
        sc=[score(c,R)[0] for c in cands]; best=cands[int(np.argmin(sc))]
    for m in levels:
        N=2**m; R[m]=R[m]*(1+tabs[m][(ks[m]*Z[best])%N])
    sel.append(best)
    print(col,best,np.round(score(best,{m:R[m]/(1+tabs[m][(ks[m]*Z[best])%(2**m)]) for m in levels})[1],1),flush=True)
print(','.join(map(str,sel)))
# table order for reference
R={m:np.ones(2**m) for m in levels}
for c in range(ncol):
    s=score(c,R)[1]
    for m in levels: R[m]=R[m]*(1+tabs[m][(ks[m]*Z[c])%(2**m)])
    print('table',c,np.round(s,1))
