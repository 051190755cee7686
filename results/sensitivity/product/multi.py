import numpy as np, sys
exec(open('results/sensitivity/product/prod.py').read().split("d=4")[0])
def run(f, d, S, T, coords, tent, Ns, lo=0.0, hi=1.0, nsh=24):
    rng=np.random.default_rng(1); shifts=rng.random((nsh,2*d))
    out=[]
    for N in Ns:
        e=[]
        for s in shifts:
            u=lattice(N,coords[:2*d],s,tent=tent)
            u=lo+(hi-lo)*u
            A=u[:,0::2]; B=u[:,1::2]
            c=np.mean(f(A[:512]))
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
M={}
def ish(x): return np.sin(x[:,0])+7*np.sin(x[:,1])**2+0.1*x[:,2]**4*np.sin(x[:,0])
a,b,p4=7.0,0.1,np.pi**4; v1=b*p4/5+b*b*p4*p4/50+0.5; v2=a*a/8; v13=8*b*b*p4*p4/225; v=v1+v2+v13
M['ishigami']=(ish,3,np.array([v1,v2,0])/v,np.array([v1+v13,v2,v13])/v,False,-np.pi,np.pi)
def g(a):
    a=np.asarray(a,float); vi=1/(3*(1+a)**2); al=np.prod(1+vi); V=al-1
    return (lambda x: np.prod((np.abs(4*x-2)+a)/(1+a),axis=1)), len(a), vi/V, vi*al/(1+vi)/V, False, 0.0, 1.0
M['g6']=g([0,1,4.5,9,99,99]); M['g0x6']=g([0]*6); M['g8']=g([0,0.5,3,9,99,99,99,99])
c=np.array([1,2,3,0.5,0]); s=c**2/np.sum(c**2); M['linear5']=(lambda x: x@c,5,s,s,True,0.0,1.0)
d=4; vv=3.0**-d-4.0**-d
M['product4']=(lambda x: np.prod(x,axis=1),4,np.full(4,4.0**(1-d)/12/vv),np.full(4,3.0**(1-d)/12/vv),True,0.0,1.0)
cc=np.array([2,1.5,1,0.5,0.25,0.1]); m1=(np.exp(cc)-1)/cc; m2=(np.exp(2*cc)-1)/(2*cc)
Vt=np.prod(m2)-np.prod(m1)**2; Vi=(m2-m1**2)*np.prod(m1**2)/m1**2; Ti=(np.prod(m2)-m1**2*np.prod(m2)/m2)/Vt
M['exp6']=(lambda x: np.exp(x@cc),6,Vi/Vt,Ti,True,0.0,1.0)
M['gsparse']=g([0,1,2]+[99]*21)
if __name__=='__main__':
    SEL=[int(c) for c in sys.argv[1].split(',')]
    Ns=[1024,2048,4096,8192,16384,32768]
    for name in sys.argv[2].split(','):
        f,d,S,T,tent,lo,hi=M[name]
        cur=run(f,d,S,T,list(range(2*d)),tent,Ns,lo,hi)
        new=run(f,d,S,T,SEL,tent,Ns,lo,hi)
        print(f"{name:9s} now ", ' '.join(f"{x:.2e}" for x in cur))
        print(f"{name:9s} sel ", ' '.join(f"{x:.2e}" for x in new), ' ratio', ' '.join(f"{y/x:.2f}" for x,y in zip(cur,new)),flush=True)
