#!/usr/bin/env python3
"""Which randomised lattice for integrals against normal laws: the experiments behind
stillpoint.sequences.law_lattice (the first-order kernel for unbounded coordinates; an
even n as two odd lattices).

    target/bench-venv/bin/python benches/law_rules.py 4096     # ~5 min on 2 cores
    target/bench-venv/bin/python benches/law_rules.py 16384    # ~40 min

Seven integrands of normal inputs (Keister s = 5, 10; ‖Z‖ in s = 16; a lognormal product
s = 10; cos(c + a·Z) s = 8; an arithmetic Asian call on 32 steps, PCA and standard
paths), RMSE over 32 randomisations divided by SciPy's scrambled Sobol' (LMS + shift).
Rules, all with the first-order kernel 2π²B2 and product weight 0.05 (a plain CBC here,
O(n²) per coordinate): `tent` one even lattice of n points, shifted then tent-transformed;
`shift` the same without the tent; `odd` an (n−1)-point lattice with the tent (what only
odd n can have); `halves` two odd lattices of n/2 ± 1 points with their own shifts, then
the tent (the rule stillpoint takes for even n); `dup` the (n−1)-point lattice and one of
its points again; `owen+tent` the Owen-scrambled Sobol' baseline with the tent. Needs the
stillpoint binary at $STILLPOINT (default target/release/stillpoint) for the baseline.
"""
import numpy as np, math, subprocess, sys, os, time
from scipy.special import ndtri, gammaln
from scipy.stats import qmc
from scipy import integrate
BIN=os.environ.get("STILLPOINT", "target/release/stillpoint")
def units(n): return np.array([z for z in range(1, n//2+1) if math.gcd(z, n)==1])
def cbc(n, s, omega, gammas):
    """plain CBC minimizing sum_k prod_j (1+g_j omega(k z_j/n)) ; omega on grid r/n"""
    k = np.arange(n); om = omega(k / n)
    cand = units(n)
    p = np.ones(n); z=[1]
    p *= 1 + gammas[0]*om[(k*1)%n]
    for j in range(1, s):
        best=None; bv=np.inf
        # vectorised in chunks
        for c0 in range(0, len(cand), 256):
            cc = cand[c0:c0+256]
            vals = ((1 + gammas[j]*om[(np.outer(cc, k)) % n]) * p).sum(1)
            i = np.argmin(vals)
            if vals[i] < bv: bv, best = vals[i], cc[i]
        z.append(int(best)); p *= 1 + gammas[j]*om[(k*best)%n]
    return np.array(z)
B2 = lambda x: x*x - x + 1/6
om_b2 = lambda x: 2*np.pi**2*B2(x)
def lattice(n, z, rng, tent=False):
    x = (np.outer(np.arange(n), z) % n)/n
    x = (x + rng.random(len(z))) % 1.0
    if tent: x = 1 - np.abs(2*x-1)
    return x
def clip(u): return np.clip(u, 2**-53, 1-2**-53)
# models: f(u) on cube, exact
def keister(s):
    def f(u):
        T = ndtri(clip(u))/math.sqrt(2); return math.pi**(s/2)*np.cos(np.linalg.norm(T,axis=1))
    r = integrate.quad(lambda r: r**(s-1)*math.cos(r)*math.exp(-r*r), 0, np.inf, limit=200)[0]
    return f, 2*math.pi**(s/2)/math.gamma(s/2)*r
def norm_radial(s):
    f = lambda u: np.linalg.norm(ndtri(clip(u)),axis=1)
    return f, math.sqrt(2)*math.exp(gammaln((s+1)/2)-gammaln(s/2))
def lognormal(s, seed=1):
    r=np.random.default_rng(seed); mu=r.uniform(-.5,.5,s); sg=r.uniform(0,1,s); sg*=0.5/np.linalg.norm(sg)
    f = lambda u: np.exp((mu + sg*ndtri(clip(u))).sum(1))
    return f, math.exp((mu+sg**2/2).sum())
def osc(s, seed=2):
    r=np.random.default_rng(seed); a=r.uniform(0,1,s); a*=1.5/np.linalg.norm(a); w=r.uniform()
    f = lambda u: np.cos(2*np.pi*w + ndtri(clip(u))@a)
    return f, math.cos(2*np.pi*w)*math.exp(-(a@a)/2)
def asian(m, kind, sigma=0.3, K=100.0):
    T=1.0; dt=T/m; t=dt*np.arange(1,m+1)
    C=np.minimum.outer(t,t)
    if kind=="pca":
        lam,V=np.linalg.eigh(C); o=np.argsort(lam)[::-1]; A=V[:,o]*np.sqrt(lam[o])
    else:
        A=np.linalg.cholesky(C)
    r=0.05
    def f(u):
        W=ndtri(clip(u))@A.T
        S=100*np.exp((r-sigma**2/2)*t + sigma*W)
        return math.exp(-r*T)*np.maximum(S.mean(1)-K,0)
    return f, None
def sobol_sets(n,s,R,seed=0):
    for i in range(R): yield qmc.Sobol(s, scramble=True, seed=seed*1000+i).random(n)
def cli_sets(n,s,R,args):
    for i in range(R):
        p=subprocess.run([BIN]+args+["-n",str(n),"-s",str(s),"--seed",str(i+1)]+(["-q"] if args[0]=="generate" else [])+["-o","/tmp/rs.npy"],capture_output=True,text=True)
        if p.returncode: raise SystemExit(p.stderr)
        yield np.load("/tmp/rs.npy")
def lat_sets(n,z,R,tent,seed=7):
    rng=np.random.default_rng(seed)
    for i in range(R): yield lattice(n,z,rng,tent)
def rmse(f, exact, sets):
    v=np.array([f(x).mean() for x in sets])
    if exact is None: return v
    return math.sqrt(((v-exact)**2).mean())
def atent(x, c):
    return np.where(x < c, x / c, (1 - x) / (1 - c))
def alat_sets(n,z,R,c,seed=7):
    rng=np.random.default_rng(seed)
    for i in range(R): yield atent(lattice(n,z,rng,False), c)
B4 = lambda x: x**4 - 2*x**3 + x**2 - 1/30
om_b4 = lambda x: -(2*np.pi)**4*B4(x)/24
def sel_sets(N, z, R, which, seed=7):
    rng=np.random.default_rng(seed); n=N//2
    j=np.arange(N)
    if which=="half": S=j[:n]
    else: S=np.concatenate([j[:n][j[:n]%2==0], j[n:][j[n:]%2==1]])
    base=(np.outer(S, z) % N)/N
    for i in range(R):
        yield 1-np.abs(2*((base+rng.random(len(z)))%1.0)-1)

if __name__ == "__main__":
    n=int(sys.argv[1]); reps=32
    models = {"keister5":(5,)+keister(5), "keister10":(10,)+keister(10), "normrad16":(16,)+norm_radial(16),
              "lognorm10":(10,)+lognormal(10), "osc8":(8,)+osc(8)}
    for k,kind in [("asian32pca","pca"),("asian32std","std")]:
        s,f,_=(32,)+asian(32,kind); models[k]=(s,f,8.144087473)
    smax=32; om=om_b2; g=[0.05]*smax
    zn=cbc(n,smax,om,g); zo=cbc(n-1,smax,om,g); za=cbc(n//2-1,smax,om,g); zb=cbc(n//2+1,smax,om,g)
    def halves(s):
        ra=lat_sets(n//2-1,za[:s],reps,True,seed=3); rb=lat_sets(n//2+1,zb[:s],reps,True,seed=4)
        for a,b in zip(ra,rb): yield np.vstack([a,b])
    def dup(s):
        rng=np.random.default_rng(5)
        for a in lat_sets(n-1,zo[:s],reps,True,seed=6): yield np.vstack([a,a[rng.integers(n-1)][None]])
    def owent(s):
        for a in cli_sets(n,s,reps,["baseline","sobol"]): yield 1-np.abs(2*a-1)
    for m,(s,f,ex) in models.items():
        ref=rmse(f,ex,sobol_sets(n,s,reps))
        out={"tent":rmse(f,ex,lat_sets(n,zn[:s],reps,True)),
             "shift":rmse(f,ex,lat_sets(n,zn[:s],reps,False)),
             "odd":rmse(f,ex,lat_sets(n-1,zo[:s],reps,True)),
             "halves":rmse(f,ex,halves(s)), "dup":rmse(f,ex,dup(s)), "owen+tent":rmse(f,ex,owent(s))}
        print(n, m, f"sobol={ref:.3g}", " ".join(f"{k}={v/ref:.2f}" for k,v in out.items()), flush=True)
