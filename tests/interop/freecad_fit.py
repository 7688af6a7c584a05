# Run by freecadcmd: opens surfkit fit's STEP or IGES with FreeCAD's default importer
# (Import.insert, Open CASCADE underneath) and measures the surface it got, independently of
# surfkit's own evaluation and distance code:
#   - the surface evaluated by Open CASCADE at the parameters of surfkit's tessellation (an
#     (NU + 1) x (NV + 1) grid of vertices in rows of constant v, each with its (u, v) as its
#     OBJ texture coordinate) against the vertices surfkit evaluated there;
#   - mesh to surface: every mesh vertex and the centroids of the 4 midpoint sub-triangles of
#     every triangle (the samples surfkit deviation takes by default), projected onto the
#     surface by Open CASCADE (GeomAPI_ProjectPointOnSurf behind Surface.parameter);
#   - surface to mesh: a G x G grid of points evaluated by Open CASCADE, their distances to the
#     mesh's triangles computed here (numpy, brute force, point-triangle distance).
# Environment: SK_IN (the CAD file), SK_TESS (surfkit's tessellation, OBJ), SK_NU and SK_NV (its
# cells along u and v),
# SK_MESH (the fitted mesh, OFF), SK_GRID (G), SK_OUT (the JSON written), SK_MEASURE=0 for the
# evaluation alone.
import json
import math
import os

import FreeCAD
import Import
import numpy as np

path, out = os.environ["SK_IN"], os.environ["SK_OUT"]
tu, tv = int(os.environ["SK_NU"]), int(os.environ["SK_NV"])  # the tessellation's cells
grid = int(os.environ.get("SK_GRID", "64"))

doc = FreeCAD.newDocument("fit")
Import.insert(path, doc.Name)
shapes = [o.Shape for o in doc.Objects if hasattr(o, "Shape") and not o.Shape.isNull()]
faces = [f for s in shapes for f in s.Faces]
res = {"objects": len(shapes), "faces": len(faces),
       "valid": len(shapes) > 0 and all(s.isValid() for s in shapes)}
if len(faces) == 1:
    surf = faces[0].Surface
    res["surface_type"] = type(surf).__name__
    res["poles"] = [surf.NbUPoles, surf.NbVPoles]
    res["degrees"] = [surf.UDegree, surf.VDegree]
    res["range"] = list(faces[0].ParameterRange)

    # surfkit's tessellation: its grid vertices and their (u, v), one vt per v in the OBJ
    ours, uv = [], []
    with open(os.environ["SK_TESS"]) as f:
        for line in f:
            if line.startswith("v "):
                ours.append([float(t) for t in line.split()[1:4]])
            elif line.startswith("vt "):
                uv.append([float(t) for t in line.split()[1:3]])
    res["tess_vertices"] = len(ours)
    res["tess_uvs"] = len(uv)

    # the mesh (OFF, triangles)
    with open(os.environ["SK_MESH"]) as f:
        tok = [t for line in f for t in line.split("#")[0].split()]
    assert tok[0] == "OFF"
    nv, nf = int(tok[1]), int(tok[2])
    V = np.array(tok[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
    F = np.array(tok[4 + 3 * nv:4 + 3 * nv + 4 * nf], dtype=int).reshape(nf, 4)[:, 1:]
    diag = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    res["diagonal"] = diag

    # 1. evaluation at sample parameters (every 4th grid line in each direction, and the ends)
    iu = sorted(set(list(range(0, tu + 1, 4)) + [tu]))
    iv = sorted(set(list(range(0, tv + 1, 4)) + [tv]))
    worst = math.inf if len(ours) != (tu + 1) * (tv + 1) or len(uv) != len(ours) else 0.0
    for j in iv if worst == 0.0 else []:
        for i in iu:
            k = j * (tu + 1) + i
            p = surf.value(*uv[k])
            worst = max(worst, math.dist((p.x, p.y, p.z), ours[k]))
    res["eval_samples"] = len(iu) * len(iv)
    res["eval_max_rel"] = worst / diag

    if os.environ.get("SK_MEASURE", "1") == "0":  # evaluation only (the IGES of the same fit)
        with open(out, "w") as f:
            json.dump(res, f)
        raise SystemExit(0)

    # 2. mesh to surface: vertices and 4 sub-triangle centroids per face, projected
    A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    bary = [(2 / 3, 1 / 6, 1 / 6), (1 / 6, 2 / 3, 1 / 6), (1 / 6, 1 / 6, 2 / 3), (1 / 3, 1 / 3, 1 / 3)]
    S = np.vstack([V] + [a * A + b * B + c * C for a, b, c in bary])
    d2s = np.empty(len(S))
    for k, p in enumerate(S):
        v = FreeCAD.Vector(*p)
        u, w = surf.parameter(v)
        d2s[k] = (surf.value(u, w) - v).Length
    res["mesh_to_surface_samples"] = len(S)
    res["mesh_to_surface_max"] = float(d2s.max())
    res["mesh_to_surface_rms"] = float(np.sqrt(np.mean(d2s ** 2)))

    # 3. surface to mesh: grid points of the surface, brute-force distance to the triangles
    P = np.array([[c for c in surf.value(i / grid, j / grid)] for j in range(grid + 1)
                  for i in range(grid + 1)])
    ab, ac = B - A, C - A
    nrm = np.cross(ab, ac)
    nn = np.einsum("ij,ij->i", nrm, nrm)

    def seg(ap, e):
        t = np.clip(np.einsum("kti,ti->kt", ap, e) / np.einsum("ti,ti->t", e, e), 0.0, 1.0)
        return np.linalg.norm(ap - t[..., None] * e, axis=2)

    best = np.empty(len(P))
    for s0 in range(0, len(P), 64):
        q = P[s0:s0 + 64]
        ap = q[:, None, :] - A[None]
        s = np.einsum("kti,ti->kt", np.cross(ap, ac), nrm) / nn
        t = np.einsum("kti,ti->kt", np.cross(ab[None], ap), nrm) / nn
        inside = (s >= 0) & (t >= 0) & (s + t <= 1)
        plane = np.abs(np.einsum("kti,ti->kt", ap, nrm)) / np.sqrt(nn)
        edges = np.minimum(np.minimum(seg(ap, ab), seg(ap, ac)),
                           seg(q[:, None, :] - B[None], C - B))
        best[s0:s0 + 64] = np.where(inside, np.minimum(plane, edges), edges).min(axis=1)
    res["surface_to_mesh_samples"] = len(P)
    res["surface_to_mesh_max"] = float(best.max())
    res["surface_to_mesh_rms"] = float(np.sqrt(np.mean(best ** 2)))
with open(out, "w") as f:
    json.dump(res, f)
