import sys; sys.path.insert(0,'benches')
import numpy as np
from sensitivity import models, salib, rmse, qmcpy_si
names=sys.argv[1].split(',')
for name,f,d,lo,hi,ex in models():
    if name not in names: continue
    for N in [1024,2048,4096,8192,16384,32768,65536]:
        e=[rmse(*salib(f,d,lo,hi,N,seed=s)[:2],ex)**2 for s in range(32)]
        q=[rmse(*qmcpy_si(f,d,lo,hi,N,seed=s)[:2],ex)**2 for s in range(32)]
        print(name,N,f"SALib {np.sqrt(np.mean(e)):.3e} QMCPy {np.sqrt(np.mean(q)):.3e}",flush=True)
