import numpy as np, re, sys
src=open('sequences/src/extensible_table.rs').read()
Z=np.array([int(x) for x in re.findall(r'\b\d+\b', src.split('= [',1)[1].split('];')[0])],dtype=np.int64)
def radinv(k,bits=20):
    k=np.asarray(k,dtype=np.int64); j=np.zeros_like(k)
    for b in range(bits): j|=((k>>b)&1)<<(bits-1-b)
    return j
def lattice(N, coords, shift, tent=True):
    j=radinv(np.arange(N))
    u=((j[:,None]*Z[coords][None,:])&((1<<20)-1))/2.0**20
    u=(u+shift)%1.0
    return 1-np.abs(2*u-1) if tent else u
d=4
v=3.0**-d-4.0**-d
S=np.full(d,4.0**(1-d)/12/v); T=np.full(d,3.0**(1-d)/12/v)
f=lambda x: np.prod(x,axis=1)
def est(u, d, centre):
    A=u[:,0::2]; B=u[:,1::2]
    ya=f(A)-centre; yb=f(B)-centre
    n=len(ya); mean=(ya.sum()+yb.sum())/(2*n); V=((ya**2).sum()+(yb**2).sum())/(2*n)-mean**2
    fs=[];ts=[]
    for i in range(d):
        ab=A.copy(); ab[:,i]=B[:,i]; yi=f(ab)-centre
        fs.append(np.mean(yb*(yi-ya))/V)
        m=(ya.mean()+yi.mean())/2; Vi=(np.mean(ya**2)+np.mean(yi**2))/2-m*m
        ts.append(np.mean((ya-yi)**2)/2/Vi)
    return np.array(fs),np.array(ts)
layouts={}
for extra in sys.argv[1:]:
    layouts[extra]=[int(c) for c in extra.split(',')]
rng=np.random.default_rng(1)
shifts=rng.random((32,64))
for name,coords in layouts.items():
    for N in [1024,2048,4096,8192,16384,32768]:
        ef=[];et=[]
        for s in shifts:
            u=lattice(N,coords,s[:len(coords)])
            fs,ts=est(u,d,0.0625)
            ef.append(np.mean((fs-S)**2)); et.append(np.mean((ts-T)**2))
        print(f"{name:12s} N={N:6d} rmse_all {np.sqrt((np.mean(ef)+np.mean(et))/2):.2e} first {np.sqrt(np.mean(ef)):.2e} total {np.sqrt(np.mean(et)):.2e}",flush=True)
