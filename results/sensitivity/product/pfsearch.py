# A pick-freeze generating vector searched component by component (run from the repository
# root): pfsearch.py K KERNELS LO HI, KERNELS comma-separated tγ (tent kernel, weight γ) or
# rγ (first-order kernel); a candidate's score is the largest over the kernels and the
# levels 2^LO..2^HI of log(criterion / best criterion among the candidates scored there),
# every odd z mod 2^SCREEN (up to sign) scored exhaustively on levels up to 2^SCREEN, then
# bit by bit up to 2^HI with a beam of 128. Weights above 0.05 fall like (FULL/j)^2 past
# coordinate FULL (16). AGG=mean: the mean over the levels of the largest over the kernels.
import numpy as np, re, sys, os, time
src=open('sequences/src/extensible_table.rs').read()
ZT=np.array([int(x) for x in re.findall(r'\b\d+\b', src.split('= [',1)[1].split('];')[0])],dtype=np.int64)
def omega(x): return (2*np.pi)**4/24*-(x**4-2*x**3+x**2-1/30)
def rough(x): return 2*np.pi**2*(x*x-x+1/6)
FULL=int(os.environ.get('FULL','16'))
AGG=os.environ.get('AGG','max')
def wj(g, j):
    w=float(g[1:])
    if w<=0.05 or j<FULL: return w
    return w*(FULL/j)**2
def kern(g, x, j=0):
    k, w = g[0], wj(g,j)
    return w*(omega(x) if k=='t' else rough(x))
def search(K, gammas, lo, hi, screen=12, beam=128, minlev=None, top=None, verbose=True):
    """CBC with score = max over gamma, level in [lo..hi] of log(P/Pbest)."""
    top = top or hi
    M=top; n=1<<M
    terms={g: kern(g,np.arange(n)/n,0) for g in gammas}
    q={g: np.zeros(n) for g in gammas}
    z=[1]
    # z_1 = 1
    for g in gammas:
        t=terms[g][np.arange(n)]; q[g]=q[g]+t+q[g]*t
    for j in range(1,K):
        terms={g: kern(g,np.arange(n)/n,j) for g in gammas}
        ns=1<<screen; step=n>>screen
        cands=np.arange(1,ns//2,2,dtype=np.int64)
        i=np.arange(ns,dtype=np.int64)
        levs=[m for m in range(lo,screen+1)]
        sels=[(i % (1<<(screen-m)))==0 for m in levs]
        allsc=[]
        for g in gammas:
            qs=q[g][::step]; ts=terms[g][::step]
            E=np.empty((len(levs),len(cands)))
            for a in range(0,len(cands),256):
                cc=cands[a:a+256]
                idx=(i[None,:]*cc[:,None])%ns
                v=qs[None,:]+ts[idx]*(1+qs[None,:])
                for li,sel in enumerate(sels): E[li,a:a+256]=v[:,sel].mean(axis=1)
            allsc.append(np.log(E/E.min(axis=1,keepdims=True)))
        allsc=np.array(allsc)  # kernels x levels x cands
        sc=allsc.max(axis=(0,1)) if AGG=='max' else allsc.max(axis=0).mean(axis=0)*len(levs)
        order=np.argsort(sc,kind='stable')[:beam]
        B=[(sc[o],int(cands[o])) for o in order]
        for b in range(screen+1,top+1):
            nb=1<<b; step=n>>b; i=np.arange(nb,dtype=np.int64)
            ch=[(s,c) for s,c in B]+[(s,c+(1<<(b-1))) for s,c in B]
            cs=np.array([c for _,c in ch],dtype=np.int64); ss=np.array([s for s,_ in ch])
            new=ss.copy(); kmax=np.zeros(len(cs))
            if b<=hi:
                for g in gammas:
                    qs=q[g][::step]; ts=terms[g][::step]
                    e=np.empty(len(cs))
                    for k,c in enumerate(cs):
                        t=ts[(i*c)%nb]; e[k]=np.mean(qs+t*(1+qs))
                    lr=np.log(e/e.min())
                    if AGG=='max': new=np.maximum(new,lr)
                    else: kmax=np.maximum(kmax,lr)
                if AGG!='max': new=new+kmax
            order=np.argsort(new,kind='stable')[:beam]
            B=[(new[o],int(cs[o])) for o in order]
        zj=B[0][1]; z.append(zj)
        for g in gammas:
            t=terms[g][(np.arange(n,dtype=np.int64)*zj)%n]; q[g]=q[g]+t+q[g]*t
        if verbose: print(j,zj,round(B[0][0],2),flush=True)
    return np.array(z,dtype=np.int64)
def report(z, gammas, lo, hi):
    n=1<<hi
    for g in gammas:
        q=np.zeros(n)
        for jj,zj in enumerate(z):
            t=kern(g,((np.arange(n)*zj)%n)/n,jj); q=q+t+q*t
        print('gamma',g,' '.join(f"{np.log10(q[::n>>m].mean()):.2f}" for m in range(lo,hi+1)))
if __name__=='__main__':
    K=int(sys.argv[1]); gammas=sys.argv[2].split(',')
    lo,hi=int(sys.argv[3]),int(sys.argv[4]); SC=int(os.environ.get('SCREEN','12'))
    t0=time.time()
    z=search(K,gammas,lo,hi,screen=SC)
    print('Z',','.join(map(str,z)), f"{time.time()-t0:.0f}s")
    print('table:'); report(ZT[:K],gammas,lo,hi)
    print('new:'); report(z,gammas,lo,hi)
