# RMSE of all 2d indices (multi.py's: sobol_indices' estimators on the first N points of
# the shifted lattice, input i's A and B in coordinates 2i - 1 and 2i, the tent for the
# inputs the face test finds non-periodic) with a given generating vector against the tent
# table's, over NSH shifts (run from the repository root):
#   pfeval.py VECTOR MODELS [NS [NSH]]
# VECTOR is a name of VECTORS below or comma-separated values; coordinates past its length
# are the tent table's. For the product and linear models it prints both against SALib's
# RMSE over 32 seeds (sensitivity.md, "By size").
import numpy as np, sys, os
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import multi
VECTORS={
 # pfsearch.py 10 t0.05,t0.3 8 16
 'beam-2w': '1,4979,38739,8769,5487,46575,49337,9153,62471,38603',
 # FULL=16 pfsearch.py 48 t0.05,t0.3,t1 8 16
 'beam-3w': '1,37747,38739,8769,62831,49541,41005,58999,30343,8265,67,50831,33809,12759,171,8645,'
            '5245,4319,5059,9907,34233,34711,5713,38187,13873,9333,13767,21323,8975,12949,34209,9185,'
            '20717,20775,25607,16653,9665,16709,29701,42293,13925,10137,47077,26515,58977,34325,26077,37851',
 # pick_freeze_search.patch: cargo run --release -p stillpoint --example pick_freeze_table -- 12
 # with the settings named (PF_*; defaults weights 0.05,0.3,1, levels 2^8..2^20, guard on
 # 2^10..2^20 at factor 2, no slack)
 'exh-3w': '1,11821,112075,228851,313651,134575,208479,251753,193217,293177,182087,229277',  # PF_FACTOR=0
 'exh-3w-guard': '1,11821,112075,228851,313651,134415,295247,95925,69151,58459,211413,122119',  # defaults
 'exh-1w-guard': '1,4981,22637,102701,27863,45665,197257,281,3761,6227,22023,201541',  # PF_WEIGHTS=0.05
 'exh-2w-guard': '1,4981,22637,471127,10729,32359,312543,112137,61905,54503,33865,72475',  # PF_WEIGHTS=0.05,0.3
 'exh-slack': '1,4981,22637,102701,13969,43579,379059,83015,300017,318349,25433,40397',  # PF_SLACK=1
 'exh-2w-l10': '1,4981,22637,471127,201151,202431,395473,54943,109761,41369,356891,60883',  # PF_WEIGHTS=0.05,0.3 PF_FACTOR=0 PF_MIN_LEVEL=10
 'exh-2w': '1,4981,22637,471127,201151,211311,400775,413669,215391,394059,76413,397997',  # PF_WEIGHTS=0.05,0.3 PF_FACTOR=0
 'exh-slack2': '1,4981,22637,102701,13969,43579,379059,330771,181577,53253,121493,211409',  # PF_SLACK=2
 'exh-slack3': '1,4979,8861,211127,23169,151501,144105,513507,205753,1975,89815,210555',  # PF_SLACK=3
 'exh-pair': '1,11821,112075,228851,421073,4545,515911,182027,240411,86857,21349,219973',  # PF_PAIR=2
 # PF_SLACK=2 PF_PAIR=2, 64 coordinates (its first 12 are those of -- 12)
 'exh-slack2-pair': '1,4981,22637,102701,13969,43579,379059,270647,64407,311995,2693,238535,174979,296313,15619,'
                    '281947,11619,27601,81,39,34389,27551,92853,23,249,323,303,95,396587,3005,7669,159,389,6069,'
                    '14643,7875,11255,9353,7329,33,37,89,175,191,251,293,461,21,45,163,169,24057,10269,17867,221,'
                    '229,235,313,393,409,469,485,515,591',
}
NS=[1024,2048,4096,8192,16384,32768,65536]
SALIB={'product4':[1.07e-2,6.54e-3,3.33e-3,1.81e-3,8.25e-4,5.27e-4,3.23e-4],
       'linear5':[3.35e-4,3.02e-4,7.67e-5,7.12e-5,2.41e-6,6.96e-7,2.48e-11]}
if __name__=='__main__':
    z=np.array([int(x) for x in VECTORS.get(sys.argv[1],sys.argv[1]).split(',')],dtype=np.int64)
    table=multi.Z.copy(); full=np.concatenate([z,table[len(z):]])
    Ns=[int(x) for x in sys.argv[3].split(',')] if len(sys.argv)>3 else NS
    nsh=int(sys.argv[4]) if len(sys.argv)>4 else 24
    for name in sys.argv[2].split(','):
        f,d,S,T,tent,lo,hi=multi.M[name]
        multi.Z=table; cur=np.array(multi.run(f,d,S,T,list(range(2*d)),tent,Ns,lo,hi,nsh))
        multi.Z=full; new=np.array(multi.run(f,d,S,T,list(range(2*d)),tent,Ns,lo,hi,nsh))
        print(f"{name:9s} now ", ' '.join(f"{x:.2e}" for x in cur))
        print(f"{name:9s} new ", ' '.join(f"{x:.2e}" for x in new), ' ratio', ' '.join(f"{y/x:.2f}" for x,y in zip(cur,new)))
        if name in SALIB:
            sa=np.array([SALIB[name][NS.index(N)] for N in Ns])
            print(f"{name:9s} /SALib now", ' '.join(f"{x:.2f}" for x in cur/sa), ' new', ' '.join(f"{x:.2f}" for x in new/sa), flush=True)
