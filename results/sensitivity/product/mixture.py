"""A generating vector drawn per seed among the searched ones: the RMSE such a mixture
would have, from the measured RMSE ratios of sensitivity.md's table ("A generating
vector searched for pick-freeze"). Drawing the vector uniformly among k per seed gives a
mean squared error that is the mean of the k vectors' mean squared errors (each over its
own shifts), so the mixture's ratio to SALib is the root mean square of the k ratios at
each N. Prints the best subsets of up to four vectors by their worst ratio over the
product (N = 1 024 ... 65 536) and linear (1 024 ... 32 768) models, then the best among
the vectors that cost Ishigami at most 2.9x the current table (the others cost it
9.5-120x). Run: python3 results/sensitivity/product/mixture.py
"""
import itertools, math
V = {
"current": ([.75,.85,1.36,1.07,.42,.21,.28],[.35,.34,1.32,.07,.36,.56]),
"beam-2w": ([.69,.46,.62,.76,.58,.45,.24],[.29,.30,.55,.09,.45,.30]),
"beam-3w": ([.58,.57,.58,.52,.82,.32,.32],[.26,.26,.11,.11,1.61,4.74]),
"exh-3w": ([1.99,1.16,1.28,.82,.87,.47,.22],[.41,.24,.14,.13,3.9,1.5]),
"exh-3w-guard": ([.62,.74,.66,.86,.97,.20,.23],[3.3,3.6,.40,.02,.51,.36]),
"exh-1w-guard": ([.68,.84,.41,.56,.30,.38,.28],[.33,.24,.12,.05,1.37,.32]),
"exh-2w-guard": ([.55,.47,.64,.50,.32,.39,.28],[1.10,.87,.39,.30,.26,.66]),
"exh-slack": ([3.3,.50,.62,.69,.42,.42,.21],[.35,.16,.19,.22,.44,.89]),
"exh-2w-l10": ([.79,.90,.49,.43,.61,.67,.15],[.59,.20,.23,.23,6.8,.47]),
"exh-2w": ([.80,.98,.90,.73,.27,.30,.28],[1.15,1.05,.27,.24,6.7,.16]),
"exh-slack2": ([.65,.44,.54,.63,.40,.40,.16],[.76,.84,3.2,.21,.56,.86]),
"exh-slack3": ([.78,.57,.67,.52,.58,.87,.19],[.90,.15,.56,.18,5.2,1.65]),
"exh-pair": ([.47,.55,.48,.54,.86,.34,.36],[.29,.26,.89,.11,1.49,5.1]),
"exh-slack2-pair": ([.69,.52,.42,.63,.49,.46,.39],[.23,.16,.21,.23,.54,1.13]),
}
mild = ["current","exh-slack","exh-slack2","exh-slack2-pair","beam-3w","exh-pair"]
best=[]
for k in range(1,5):
    for sub in itertools.combinations(V, k):
        p=[math.sqrt(sum(V[v][0][i]**2 for v in sub)/k) for i in range(7)]
        l=[math.sqrt(sum(V[v][1][i]**2 for v in sub)/k) for i in range(6)]
        best.append((max(p+l), sub, p, l))
best.sort()
for w,sub,p,l in best[:8]:
    print(f"{w:.2f}", sub, " ".join(f"{x:.2f}" for x in p), "|", " ".join(f"{x:.2f}" for x in l), "mild" if all(s in mild for s in sub) else "")
print("best among mild only:")
for w,sub,p,l in [b for b in best if all(s in mild for s in b[1])][:4]:
    print(f"{w:.2f}", sub, " ".join(f"{x:.2f}" for x in p), "|", " ".join(f"{x:.2f}" for x in l))
