import numpy as np, sys
exec(open('results/sensitivity/product/prod.py').read().split("layouts={}")[0])
rng=np.random.default_rng(1); shifts=rng.random((16,64))
sets=[list(range(o,o+8)) for o in (0,8,16,24)]
r2=np.random.default_rng(7)
sets+= [sorted(r2.choice(32,8,replace=False)) for _ in range(6)]
Ns=[1024,2048,4096,8192,16384,32768]
salib=[8.5e-3,6.4e-3,3.4e-3,1.95e-3,7.4e-4,np.nan]
for coords in sets:
    row=[]
    for N in Ns:
        e=[]
        for s in shifts:
            fs,ts=est(lattice(N,coords,s[:8]),d,0.0625)
            e.append((np.mean((fs-S)**2)+np.mean((ts-T)**2))/2)
        row.append(np.sqrt(np.mean(e)))
    print(','.join(map(str,coords)).ljust(28),' '.join(f"{x:.1e}({x/s_:.2f})" for x,s_ in zip(row,salib)),flush=True)
