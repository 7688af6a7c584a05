# Cuts a disk from a closed mesh (OFF): the `target` faces whose centroids are nearest to vertex
# `seed`, the connected piece of them around the nearest face; writes OFF. A scan cut this way has
# a ragged (staircase) boundary with many ear triangles.
#   python3 cut_disk.py IN.off OUT.off TARGET SEED
import sys, math
src, out, target, seed = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
tok = [t for l in open(src) for t in l.split('#')[0].split()]
nv, nf = int(tok[1]), int(tok[2])
V = [tuple(map(float, tok[4+3*i:7+3*i])) for i in range(nv)]
o = 4+3*nv
F = [tuple(map(int, tok[o+4*i+1:o+4*i+4])) for i in range(nf)]
c = V[seed]
cent = [tuple(sum(V[v][k] for v in f)/3 for k in range(3)) for f in F]
d = sorted(range(nf), key=lambda i: math.dist(cent[i], c))
keep = set(d[:target])
# grow-only component from the nearest face via shared edges
from collections import defaultdict
e2f = defaultdict(list)
for i in keep:
    f = F[i]
    for k in range(3):
        e2f[frozenset((f[k], f[(k+1)%3]))].append(i)
comp, stack = {d[0]}, [d[0]]
while stack:
    i = stack.pop(); f = F[i]
    for k in range(3):
        for j in e2f[frozenset((f[k], f[(k+1)%3]))]:
            if j not in comp: comp.add(j); stack.append(j)
fs = [F[i] for i in sorted(comp)]
used = sorted({v for f in fs for v in f}); idx = {v: i for i, v in enumerate(used)}
with open(out, 'w') as w:
    w.write("OFF\n%d %d 0\n" % (len(used), len(fs)))
    for v in used: w.write("%.17g %.17g %.17g\n" % V[v])
    for f in fs: w.write("3 %d %d %d\n" % tuple(idx[v] for v in f))
