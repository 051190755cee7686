import numpy as np, re, itertools, sys
src=open('sequences/src/extensible_table.rs').read()
Z=np.array([int(x) for x in re.findall(r'\b\d+\b', src.split('= [',1)[1].split('];')[0])],dtype=np.int64)
coords=[int(c) for c in sys.argv[1].split(',')] if len(sys.argv)>1 else list(range(8))
z=Z[coords]; s=len(z); H=4
g=np.array(list(itertools.product(range(-H,H+1),repeat=s)),dtype=np.int64)
g=g[np.any(g!=0,axis=1)]
# keep one of h, -h
first=np.array([r[np.nonzero(r)[0][0]] for r in g[:1]])
w=np.prod(np.maximum(1,np.abs(g)).astype(float)**-2,axis=1)
dot=g@z
for N in [1024,2048,4096,8192,16384,32768]:
    m=(dot%N)==0
    idx=np.argsort(-w[m])[:8:2]
    print(N, 'sum w', f"{w[m].sum()/2:.2e}", [ (tuple(g[m][i]), f"{w[m][i]:.2e}") for i in idx])
