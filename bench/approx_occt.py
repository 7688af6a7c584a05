# Run by freecadcmd for bench/approx.sh: Open CASCADE's own approximation of a disk
# (GeomAPI_PointsToBSplineSurface behind Part.BSplineSurface().approximate) over a G x G grid
# of points of the mesh resampled through surfkit's square parametrization (the mesh with its
# uv, OBJ v/vt/f), and the same measurement of it and of surfkit fit's surface (its STEP):
# control points, max and RMS distance from the mesh's vertices and face centroids to the
# surface (projected by Open CASCADE), max distance from a 65 x 65 grid of the surface to the
# mesh (numpy, brute force), seconds of the approximation. Open CASCADE is run at tolerance T,
# T/2, T/4 (its tolerance is to the grid points only), the first within T kept.
# Environment: SK_MESH (OBJ with uv), SK_STEP (surfkit's fit), SK_TOL (model units), SK_GRID,
# SK_OUT (JSON).
import json
import os
import time

import FreeCAD
import Import
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
diag = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
tol, G = float(os.environ["SK_TOL"]), int(os.environ.get("SK_GRID", "60"))

# resample: the point of the mesh at each (i/(G-1), j/(G-1)) of the square map
grid = np.full((G, G, 3), np.nan)
ta, tb, tc = T[Ft[:, 0]], T[Ft[:, 1]], T[Ft[:, 2]]
for k in range(len(Fv)):
    lo, hi = np.minimum(np.minimum(ta[k], tb[k]), tc[k]), np.maximum(np.maximum(ta[k], tb[k]), tc[k])
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
missing = int(np.isnan(grid[..., 0]).sum())

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
            "mesh_to_surface_max": float(d.max()), "mesh_to_surface_rms": float(np.sqrt(np.mean(d * d))),
            "surface_to_mesh_max": float(best.max())}

res = {"diagonal": diag, "tolerance": tol, "grid": G, "grid_missing": missing, "occt_tries": []}
if missing == 0:
    # Open CASCADE's tolerance bounds its distance to the grid points only, not to the mesh
    # between them: its best setting at equal T is the loosest of T, T/2, T/4 whose surface is
    # within T of the mesh by the same measure as ours (the fewest poles); none met: the closest
    for factor in (1.0, 0.5, 0.25):
        t0 = time.time()
        occ = Part.BSplineSurface()
        try:
            occ.approximate(Points=[[FreeCAD.Vector(*grid[i, j]) for j in range(G)] for i in range(G)],
                            DegMin=3, DegMax=8, Continuity=2, Tolerance=tol * factor)  # 2 = C2
        except Exception as e:  # Open CASCADE gives up: say so in the table
            res.setdefault("occt_error", str(e))
            continue
        secs = time.time() - t0
        m = measure(occ)
        dev = max(m["mesh_to_surface_max"], m["surface_to_mesh_max"])
        res["occt_tries"].append({"factor": factor, "control_points": m["control_points"],
                                  "max": dev, "seconds": secs})
        best = res.get("occt")
        best_dev = max(best["mesh_to_surface_max"], best["surface_to_mesh_max"]) if best else None
        if best is None or dev < best_dev:
            res.pop("occt_error", None)
            res["occt"], res["occt_seconds"] = m, secs
            res["occt_degrees"], res["occt_factor"] = [occ.UDegree, occ.VDegree], factor
        if dev <= tol:
            break
doc = FreeCAD.newDocument("ours")
Import.insert(os.environ["SK_STEP"], doc.Name)
faces = [f for o in doc.Objects if hasattr(o, "Shape") for f in o.Shape.Faces]
if len(faces) == 1:
    res["ours"] = measure(faces[0].Surface)
with open(os.environ["SK_OUT"], "w") as f:
    json.dump(res, f)
