#!/usr/bin/env python3
"""Independent atlas metrics from an OBJ file with per-corner vt (bench/atlas.sh).

Reads v / vt / f (triangles; polygons are fanned) and computes, for any program's output:
charts (faces joined across an edge whose two ends have the same vt on both sides), seam length
(3D length of interior edges whose sides differ in vt) / sqrt(3D area), MIPS mean (sigma1/sigma2 +
sigma2/sigma1 per triangle), area-log mean (mean |log((A_uv / sum A_uv) / (A / sum A))|), flips
(uv orientation <= 0, exact; also mirrored charts, whose triangles are mostly clockwise, and
folds, triangles against their own chart's orientation), overlaps (pairs of uv triangles whose interiors meet: grid buckets,
separating-axis test with exact rational orientation), utilization (uv area / unit square), gutter
(the smallest distance between the uv boundary edges of two different charts, in texels at 1024:
1 texel = 1/1024 of the unit square; capped at GAP_CAP texels).
Prints one JSON line. Written for this benchmark; shares no code with surfkit.
"""
import json
import math
import sys
from fractions import Fraction



def read_obj(path):
    v, vt, fv, ft = [], [], [], []
    with open(path) as fp:
        for line in fp:
            if line.startswith("v "):
                v.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("vt "):
                vt.append([float(x) for x in line.split()[1:3]])
            elif line.startswith("f "):
                c = [tok.split("/") for tok in line.split()[1:]]
                vi = [int(t[0]) for t in c]
                ti = [int(t[1]) if len(t) > 1 and t[1] else 0 for t in c]
                for k in range(1, len(c) - 1):
                    fv.append([vi[0], vi[k], vi[k + 1]])
                    ft.append([ti[0], ti[k], ti[k + 1]])

    def fix(i, n):
        return n + i if i < 0 else i - 1

    FV = [[fix(i, len(v)) for i in f] for f in fv]
    FT = [[fix(i, len(vt)) for i in f] for f in ft]
    return v, vt, FV, FT


def orient_exact(a, b, c):
    d = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])
    bound = 1e-14 * (abs((a[0] - c[0]) * (b[1] - c[1])) + abs((a[1] - c[1]) * (b[0] - c[0])))
    if abs(d) > bound:
        return 1 if d > 0 else -1
    A = [Fraction(x) for x in a]
    B = [Fraction(x) for x in b]
    C = [Fraction(x) for x in c]
    e = (A[0] - C[0]) * (B[1] - C[1]) - (A[1] - C[1]) * (B[0] - C[0])
    return (e > 0) - (e < 0)


def interiors_meet(s, t):
    for p, q in ((s, t), (t, s)):
        for e in range(3):
            a, b = p[e], p[(e + 1) % 3]
            if all(orient_exact(a, b, q[k]) <= 0 for k in range(3)):
                return False
    return True


def count_overlaps(tri):
    n = len(tri)
    lo = [(min(p[0] for p in t), min(p[1] for p in t)) for t in tri]
    hi = [(max(p[0] for p in t), max(p[1] for p in t)) for t in tri]
    glo = (min(b[0] for b in lo), min(b[1] for b in lo))
    ghi = (max(b[0] for b in hi), max(b[1] for b in hi))
    cells = max(1, int(math.sqrt(n)))
    sx = (ghi[0] - glo[0]) / cells + 1e-300
    sy = (ghi[1] - glo[1]) / cells + 1e-300

    def cell(x, s, g):
        return min(max(int((x - g) // s), 0), cells - 1)

    grid = {}
    for i in range(n):
        for x in range(cell(lo[i][0], sx, glo[0]), cell(hi[i][0], sx, glo[0]) + 1):
            for y in range(cell(lo[i][1], sy, glo[1]), cell(hi[i][1], sy, glo[1]) + 1):
                grid.setdefault((x, y), []).append(i)
    ccw = []
    for t in tri:
        o = orient_exact(*t)
        ccw.append(None if o == 0 else (t if o > 0 else t[::-1]))
    seen, count = set(), 0
    for items in grid.values():
        for a in range(len(items)):
            i = items[a]
            for b in range(a + 1, len(items)):
                j = items[b]
                if (i, j) in seen:
                    continue
                if lo[i][0] > hi[j][0] or lo[j][0] > hi[i][0] or lo[i][1] > hi[j][1] or lo[j][1] > hi[i][1]:
                    continue
                seen.add((i, j))
                if ccw[i] is None or ccw[j] is None:
                    continue
                if interiors_meet(ccw[i], ccw[j]):
                    count += 1
    return count


GAP_CAP = 16.0  # texels at 1024: a gutter wider than this is reported as this


def seg_point(p, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    ll = dx * dx + dy * dy
    t = 0.0 if ll == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / ll))
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)


def seg_seg(a, b, c, d):
    def side(p, q, r):
        v = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
        return (v > 0) - (v < 0)

    if side(a, b, c) * side(a, b, d) < 0 and side(c, d, a) * side(c, d, b) < 0:
        return 0.0
    return min(seg_point(c, a, b), seg_point(d, a, b), seg_point(a, c, d), seg_point(b, c, d))


def min_gutter(segs):
    """segs: (chart, a, b) boundary edges; the smallest distance between two charts' edges, in
    texels at 1024, found in a grid of GAP_CAP-texel cells (each edge in every cell its box
    touches), capped at GAP_CAP."""
    cap = GAP_CAP / 1024
    grid = {}
    for i, (_, a, b) in enumerate(segs):
        for x in range(int(math.floor(min(a[0], b[0]) / cap)), int(math.floor(max(a[0], b[0]) / cap)) + 1):
            for y in range(int(math.floor(min(a[1], b[1]) / cap)), int(math.floor(max(a[1], b[1]) / cap)) + 1):
                grid.setdefault((x, y), []).append(i)
    best = cap
    for (x, y), items in grid.items():
        others = []
        for dx, dy in ((0, 0), (1, -1), (1, 0), (1, 1), (0, 1)):
            others.append(grid.get((x + dx, y + dy), ()))
        for k, group in enumerate(others):
            for ii, i in enumerate(items):
                ci, a, b = segs[i]
                for j in (group[ii + 1:] if k == 0 else group):
                    cj, c, d = segs[j]
                    if ci == cj:
                        continue
                    if (min(a[0], b[0]) - max(c[0], d[0]) >= best or min(c[0], d[0]) - max(a[0], b[0]) >= best or
                            min(a[1], b[1]) - max(c[1], d[1]) >= best or min(c[1], d[1]) - max(a[1], b[1]) >= best):
                        continue
                    best = min(best, seg_seg(a, b, c, d))
    return best * 1024


def sub(a, b):
    return [a[k] - b[k] for k in range(len(a))]


def norm(a):
    return math.sqrt(sum(x * x for x in a))


def metrics(path):
    V, T, FV, FT = read_obj(path)
    nf = len(FV)
    a3s, auvs, mips = [], [], []
    flips = 0
    tri, orient = [], []
    for f in range(nf):
        p0, p1, p2 = (V[i] for i in FV[f])
        q = [tuple(T[i]) for i in FT[f]]
        tri.append(q)
        e1, e2 = sub(p1, p0), sub(p2, p0)
        cr = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
              e1[0] * e2[1] - e1[1] * e2[0]]
        a3 = 0.5 * norm(cr)
        l1 = norm(e1)
        x2 = sum(e1[k] * e2[k] for k in range(3)) / l1
        y2 = 2 * a3 / l1
        d1, d2 = sub(q[1], q[0]), sub(q[2], q[0])
        auv = 0.5 * (d1[0] * d2[1] - d1[1] * d2[0])
        # J = [d1 d2] [[l1, x2], [0, y2]]^-1
        j00, j10 = d1[0] / l1, d1[1] / l1
        j01, j11 = (d2[0] - j00 * x2) / y2, (d2[1] - j10 * x2) / y2
        fro = j00 * j00 + j01 * j01 + j10 * j10 + j11 * j11
        det = j00 * j11 - j01 * j10
        mips.append(fro / abs(det) if det != 0 else math.inf)
        a3s.append(a3)
        auvs.append(abs(auv))
        orient.append(orient_exact(*q))
        if orient[-1] <= 0:
            flips += 1
    A3, AUV = sum(a3s), sum(auvs)
    alog = [abs(math.log((u / AUV) / (a / A3))) if u > 0 else math.inf for u, a in zip(auvs, a3s)]
    # seams and charts: an edge joins two faces when both of its ends have the same vt on both sides
    edges = {}
    for f in range(nf):
        for k in range(3):
            a, b = FV[f][k], FV[f][(k + 1) % 3]
            ta, tb = FT[f][k], FT[f][(k + 1) % 3]
            edges.setdefault((min(a, b), max(a, b)), []).append((f, {a: ta, b: tb}))
    parent = list(range(nf))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    seam = 0.0
    for (a, b), side in edges.items():
        if len(side) != 2:
            continue
        (f, ma), (g, mb) = side
        if ma[a] == mb[a] and ma[b] == mb[b]:
            parent[find(f)] = find(g)
        else:
            seam += norm(sub(V[a], V[b]))
    charts = len({find(f) for f in range(nf)})
    # the charts' uv boundary: a face side whose uv edge no other face of its chart shares
    uses = {}
    for f in range(nf):
        for k in range(3):
            ta, tb = FT[f][k], FT[f][(k + 1) % 3]
            key = (find(f), min(ta, tb), max(ta, tb))
            uses[key] = uses.get(key, 0) + 1
    segs = [(c, T[a], T[b]) for (c, a, b), n in uses.items() if n == 1]
    # a chart laid out mirrored (most of its triangles clockwise) is a reflection, not a fold:
    # "flipped" counts every clockwise or degenerate uv triangle, "folds" only those whose
    # orientation differs from their own chart's majority (or is degenerate)
    balance = {}
    for f in range(nf):
        balance[find(f)] = balance.get(find(f), 0) + orient[f]
    mirrored = sum(1 for b in balance.values() if b < 0)
    folds = sum(1 for f in range(nf) if orient[f] == 0 or
                orient[f] * (1 if balance[find(f)] >= 0 else -1) < 0)
    return {
        "file": path, "faces": nf, "charts": charts, "seam_length_rel": seam / math.sqrt(A3),
        "mips_mean": sum(mips) / nf, "area_log_mean": sum(alog) / nf, "flipped": flips,
        "mirrored_charts": mirrored, "folds": folds, "overlaps": count_overlaps(tri), "utilization": AUV,
        "gutter_texels": min_gutter(segs),
        "uv_in_unit_square": all(0 <= x <= 1 for t in T for x in t),
    }


if __name__ == "__main__":
    for p in sys.argv[1:]:
        print(json.dumps(metrics(p)))
