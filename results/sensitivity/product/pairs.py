import numpy as np, re, itertools
src=open('sequences/src/extensible_table.rs').read()
Z=np.array([int(x) for x in re.findall(r'\b\d+\b', src.split('= [',1)[1].split('];')[0])],dtype=np.int64)
H=12
for N in [1024,2048,4096,8192,16384]:
    worst=[]
    for i,j in itertools.combinations(range(10),2):
        best=None
        for h1 in range(1,H+1):
            for h2 in range(-H,H+1):
                if h2==0: continue
                if (h1*Z[i]+h2*Z[j])%N==0:
                    w=(h1*abs(h2))
                    if best is None or w<best[0]: best=(w,h1,h2)
        if best: worst.append((best[0],i,j,best[1],best[2]))
    worst.sort()
    print(N, worst[:5])
