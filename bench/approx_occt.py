# Run by freecadcmd for bench/approx.sh, one job per process (SK_MODE):
#   approximate: Open CASCADE's own approximation of a disk (GeomAPI_PointsToBSplineSurface behind
#     Part.BSplineSurface().approximate, degree 3 to 8, C2) over a G x G grid of points of the
#     mesh resampled through surfkit's square parametrization (the mesh with its uv, OBJ
#     v/vt/f), at tolerance SK_TOL times SK_FACTOR; writes the surface as BREP (SK_BREP) and
#     {grid, grid_missing, seconds, degrees} as JSON (SK_OUT). approx.sh runs it under a CPU
#     time limit, since its cost explodes on large grids of rough disks.
#   measure: a surface (SK_SURF: surfkit fit's STEP, or a BREP from approximate) against the
#     mesh: control points, max and RMS distance from the mesh's vertices and face centroids to
#     the surface (projected by Open CASCADE), max distance from a 65 x 65 grid of the surface
#     to the mesh (numpy, brute force), as JSON (SK_OUT).
# Environment: SK_MODE, SK_MESH (OBJ with uv), SK_TOL (model units), SK_FACTOR, SK_GRID,
# SK_BREP, SK_SURF, SK_OUT.
import json
import os
import time

import FreeCAD
import Part
import numpy as np

V, T, F = [], [], []
with open(os.environ["SK_MESH"]) as f:
    for line in f:
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            V.append([float(x) for x in w[1:4]])
        elif w[0] == "vt":
            T.append([float(x) for x in w[1:3]])
        elif w[0] == "f":
            F.append([[int(x) - 1 for x in c.split("/")] for c in w[1:4]])
V, T = np.array(V), np.array(T)
Fv = np.array([[c[0] for c in f] for f in F])
Ft = np.array([[c[1] if len(c) > 1 else c[0] for c in f] for f in F])
A, B, C = V[Fv[:, 0]], V[Fv[:, 1]], V[Fv[:, 2]]
mode = os.environ["SK_MODE"]


def resample(G):
    """the point of the mesh at each (i/(G-1), j/(G-1)) of the square map"""
    grid = np.full((G, G, 3), np.nan)
    ta, tb, tc = T[Ft[:, 0]], T[Ft[:, 1]], T[Ft[:, 2]]
    for k in range(len(Fv)):
        lo = np.minimum(np.minimum(ta[k], tb[k]), tc[k])
        hi = np.maximum(np.maximum(ta[k], tb[k]), tc[k])
        i0, i1 = int(np.ceil(lo[0] * (G - 1) - 1e-9)), int(np.floor(hi[0] * (G - 1) + 1e-9))
        j0, j1 = int(np.ceil(lo[1] * (G - 1) - 1e-9)), int(np.floor(hi[1] * (G - 1) + 1e-9))
        if i1 < i0 or j1 < j0:
            continue
        e1, e2 = tb[k] - ta[k], tc[k] - ta[k]
        det = e1[0] * e2[1] - e1[1] * e2[0]
        if det == 0:
            continue
        for i in range(max(i0, 0), min(i1, G - 1) + 1):
            for j in range(max(j0, 0), min(j1, G - 1) + 1):
                q = np.array([i / (G - 1), j / (G - 1)]) - ta[k]
                s = (q[0] * e2[1] - q[1] * e2[0]) / det
                t = (e1[0] * q[1] - e1[1] * q[0]) / det
                if s >= -1e-12 and t >= -1e-12 and s + t <= 1 + 1e-12:
                    grid[i, j] = A[k] + s * (B[k] - A[k]) + t * (C[k] - A[k])
    return grid


def measure(surf):
    S = np.vstack([V, (A + B + C) / 3])
    d = np.empty(len(S))
    for k, p in enumerate(S):
        v = FreeCAD.Vector(*p)
        u, w = surf.parameter(v)
        d[k] = (surf.value(u, w) - v).Length
    u0, u1, v0, v1 = surf.bounds()
    n = 64
    P = np.array([list(surf.value(u0 + (u1 - u0) * i / n, v0 + (v1 - v0) * j / n))
                  for j in range(n + 1) for i in range(n + 1)])
    ab, ac = B - A, C - A
    nrm = np.cross(ab, ac)
    nn = np.einsum("ij,ij->i", nrm, nrm)

    def seg(ap, e):
        t = np.clip(np.einsum("kti,ti->kt", ap, e) / np.einsum("ti,ti->t", e, e), 0.0, 1.0)
        return np.linalg.norm(ap - t[..., None] * e, axis=2)
    best = np.empty(len(P))
    for s0 in range(0, len(P), 32):
        q = P[s0:s0 + 32]
        ap = q[:, None, :] - A[None]
        s = np.einsum("kti,ti->kt", np.cross(ap, ac), nrm) / nn
        t = np.einsum("kti,ti->kt", np.cross(ab[None], ap), nrm) / nn
        inside = (s >= 0) & (t >= 0) & (s + t <= 1)
        plane = np.abs(np.einsum("kti,ti->kt", ap, nrm)) / np.sqrt(nn)
        edges = np.minimum(np.minimum(seg(ap, ab), seg(ap, ac)), seg(q[:, None, :] - B[None], C - B))
        best[s0:s0 + 32] = np.where(inside, np.minimum(plane, edges), edges).min(axis=1)
    return {"control_points": surf.NbUPoles * surf.NbVPoles, "poles": [surf.NbUPoles, surf.NbVPoles],
            "degrees": [surf.UDegree, surf.VDegree],
            "mesh_to_surface_max": float(d.max()), "mesh_to_surface_rms": float(np.sqrt(np.mean(d * d))),
            "surface_to_mesh_max": float(best.max())}


res = {}
if mode == "approximate":
    G = int(os.environ["SK_GRID"])
    grid = resample(G)
    res = {"grid": G, "grid_missing": int(np.isnan(grid[..., 0]).sum())}
    if res["grid_missing"] == 0:
        tol = float(os.environ["SK_TOL"]) * float(os.environ["SK_FACTOR"])
        t0 = time.process_time()
        occ = Part.BSplineSurface()
        try:
            occ.approximate(Points=[[FreeCAD.Vector(*grid[i, j]) for j in range(G)] for i in range(G)],
                            DegMin=3, DegMax=8, Continuity=2, Tolerance=tol)  # 2 = C2
            res["seconds"] = time.process_time() - t0
            res["degrees"] = [occ.UDegree, occ.VDegree]
            occ.toShape().exportBrep(os.environ["SK_BREP"])
        except Exception as e:  # Open CASCADE gives up: say so in the table
            res["error"] = str(e)
else:
    faces = Part.read(os.environ["SK_SURF"]).Faces
    if len(faces) == 1:
        res = measure(faces[0].Surface)
    else:
        res = {"error": "%d faces" % len(faces)}
with open(os.environ["SK_OUT"], "w") as f:
    json.dump(res, f)
