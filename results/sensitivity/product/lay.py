import numpy as np, sys
exec(open('results/sensitivity/product/prod.py').read().split("d=4")[0])
def run(f, d, S, T, colsA, colsB, Ns, nsh=24, centre=None):
    rng=np.random.default_rng(1); shifts=rng.random((nsh,2*d))
    out=[]
    for N in Ns:
        e=[]
        for s in shifts:
            u=lattice(N,list(range(2*d)),s)
            A=u[:,colsA]; B=u[:,colsB]
            c=np.mean(f(A[:512])) if centre is None else centre
            ya=f(A)-c; yb=f(B)-c; n=len(ya)
            mean=(ya.sum()+yb.sum())/(2*n); V=((ya**2).sum()+(yb**2).sum())/(2*n)-mean**2
            fs=[];ts=[]
            for i in range(d):
                ab=A.copy(); ab[:,i]=B[:,i]; yi=f(ab)-c
                fs.append(np.mean(yb*(yi-ya))/V)
                m=(ya.mean()+yi.mean())/2; Vi=(np.mean(ya**2)+np.mean(yi**2))/2-m*m
                ts.append(np.mean((ya-yi)**2)/2/Vi)
            e.append((np.mean((np.array(fs)-S)**2)+np.mean((np.array(ts)-T)**2))/2)
        out.append(np.sqrt(np.mean(e)))
    return out
models={}
d=4; v=3.0**-d-4.0**-d
models['product4']=(lambda x: np.prod(x,axis=1),4,np.full(4,4.0**(1-d)/12/v),np.full(4,3.0**(1-d)/12/v))
c=np.array([1,2,3,0.5,0]); s=c**2/np.sum(c**2)
models['linear5']=(lambda x: x@c,5,s,s)
cc=np.array([2,1.5,1,0.5,0.25,0.1])
# exp6: f=exp(sum c_i x_i): var factor per i: E e^{2cx}=(e^{2c}-1)/(2c), E e^{cx}=(e^c-1)/c
m1=(np.exp(cc)-1)/cc; m2=(np.exp(2*cc)-1)/(2*cc)
Vt=np.prod(m2)-np.prod(m1)**2
Vi=(m2-m1**2)*np.prod(m1**2)/m1**2
Ti=(np.prod(m2)-m1**2*np.prod(m2)/m2)/Vt
models['exp6']=(lambda x: np.exp(x@cc),6,Vi/Vt,Ti)
Ns=[1024,2048,4096,8192,16384,32768,65536]
for name in sys.argv[1].split(','):
    f,d,S,T=models[name]
    inter=(list(range(0,2*d,2)),list(range(1,2*d,2)))
    split=(list(range(d)),list(range(d,2*d)))
    for lname,(ca,cb) in [('inter',inter),('split',split)]:
        r=run(f,d,S,T,ca,cb,Ns)
        print(name,lname,' '.join(f"{x:.2e}" for x in r),flush=True)
