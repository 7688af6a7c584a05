#!/usr/bin/env python3
"""Writes an OFF mesh with its vertices and faces renumbered by a seeded random permutation (the
same surface, other ids): bench/smooth_orders.sh and tests/cli/smooth_orders.sh use it to see how
the VC1 construction depends on the input's order.
Usage: renumber.py IN.off OUT.off SEED"""
import random
import sys


def main():
    src, dst, seed = sys.argv[1], sys.argv[2], int(sys.argv[3])
    tokens = [l.split('#')[0] for l in open(src).read().split('\n')]
    words = ' '.join(tokens).split()
    if not words or words[0] != 'OFF':
        sys.exit('renumber.py: %s: not an OFF file' % src)
    nv, nf = int(words[1]), int(words[2])
    pos = 4
    verts = [words[pos + 3 * i: pos + 3 * i + 3] for i in range(nv)]
    pos += 3 * nv
    faces = []
    for _ in range(nf):
        k = int(words[pos])
        faces.append([int(x) for x in words[pos + 1: pos + 1 + k]])
        pos += 1 + k
    rng = random.Random(seed)
    new_id = list(range(nv))
    rng.shuffle(new_id)
    rng.shuffle(faces)
    out = [None] * nv
    for old, new in enumerate(new_id):
        out[new] = verts[old]
    with open(dst, 'w') as f:
        f.write('OFF\n%d %d 0\n' % (nv, nf))
        f.writelines(' '.join(v) + '\n' for v in out)
        f.writelines('%d %s\n' % (len(fc), ' '.join(str(new_id[x]) for x in fc)) for fc in faces)


if __name__ == '__main__':
    main()
