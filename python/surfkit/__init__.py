"""surfkit: hierarchical parametrization and VC1 smooth surfaces of triangulated surfaces.

numpy arrays in and out over libsurfkit::

    import surfkit
    mesh = surfkit.read("lion-head.off")          # Mesh: vertices (V,3) float64, faces (F,3)
    print(mesh.info())                            # topology as a dict
    uv = surfkit.parametrize(mesh, method="mips") # (V,2) float64, no flipped triangle
    surface = surfkit.smooth(mesh)                # VC1 patches: control points, report dict
    surfkit.write("lion-uv.obj", mesh.with_uv(uv))

Library errors (bad files, meshes that are not what a method needs) raise surfkit.Error whose
str() is the library's one-line message. The long calls release the GIL, so threads or a
concurrent.futures pool run several meshes at once.
"""
import numpy as np

from . import _core
from ._core import Error

__all__ = ["Error", "Mesh", "Surface", "read", "write", "parametrize", "smooth",
           "library_version", "__version__"]

library_version = _core.library_version
__version__ = library_version

#: parametrization methods (see `surfkit param --help`)
METHODS = ("tutte", "floater", "mvc", "harmonic", "lscm", "mips", "mips-flat")


class Mesh:
    """A polygon mesh as numpy arrays.

    vertices: (V, 3) float64. faces: (F, 3) int64 when every face is a triangle, else a list of
    int64 arrays (one per face). normals: (V, 3) float64 or None; uv: (V, 2) float64 or None.
    Construct from arrays (``Mesh(vertices, faces)``) or with :func:`read`.
    """

    def __init__(self, vertices, faces, normals=None, uv=None):
        v = np.ascontiguousarray(vertices, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ValueError("vertices must have shape (V, 3)")
        self.vertices = v
        if isinstance(faces, np.ndarray) and faces.ndim == 2:
            self.faces = np.ascontiguousarray(faces, dtype=np.int64)
        else:
            fl = [np.asarray(f, dtype=np.int64).ravel() for f in faces]
            if fl and all(len(f) == 3 for f in fl):
                self.faces = np.array(fl, dtype=np.int64).reshape(-1, 3)
            else:
                self.faces = fl
        self.normals = None if normals is None else _shaped(normals, 3, len(v), "normals")
        self.uv = None if uv is None else _shaped(uv, 2, len(v), "uv")

    @property
    def num_vertices(self):
        return len(self.vertices)

    @property
    def num_faces(self):
        return len(self.faces)

    def with_uv(self, uv):
        """A copy of this mesh carrying per-vertex uv (what OBJ writes as vt)."""
        return Mesh(self.vertices, self.faces, self.normals, uv)

    def info(self):
        """Vertices, faces (triangles, quads), edges, boundary edges and loops, components,
        Euler characteristic and genus, as the CLI's `surfkit info` counts them."""
        return _core.info(self.vertices, *self._flat())

    def _flat(self):
        """(offsets uint32 (F+1,), indices uint32): the faces as the library takes them."""
        if isinstance(self.faces, np.ndarray):
            f = self.faces
            sizes = np.full(len(f), f.shape[1] if f.ndim == 2 else 0, dtype=np.int64)
            idx = f.ravel()
        else:
            sizes = np.array([len(x) for x in self.faces], dtype=np.int64)
            idx = np.concatenate(self.faces) if self.faces else np.zeros(0, dtype=np.int64)
        if idx.size and (idx.min() < 0 or idx.max() >= len(self.vertices)):
            bad = int(idx[(idx < 0) | (idx >= len(self.vertices))][0])
            raise Error("face index %d out of range (the mesh has %d vertices)"
                        % (bad, len(self.vertices)))
        offsets = np.zeros(len(sizes) + 1, dtype=np.uint32)
        np.cumsum(sizes, out=offsets[1:])
        return offsets, np.ascontiguousarray(idx, dtype=np.uint32)

    def __repr__(self):
        return "Mesh(%d vertices, %d faces)" % (self.num_vertices, self.num_faces)


class Surface:
    """A smooth surface: one Bezier patch per face of the configuration mesh (after edge
    deletion: triangles and quads).

    points: (P, 3) float64 all control points; kind (N,) 3 triangle / 4 quad; degree (N,);
    first (N,) index of each patch's first point; corners (N, 4) vertex ids (the fourth is
    2**32 - 1 for triangles); deleted (D, 2) deleted edges; problems: vertex ids;
    report: the continuity report (dict, as `surfkit smooth --report`); stats: construction
    counts. Control point order within a patch: see include/surfkit/smooth.h.
    """

    def __init__(self, d):
        for k in ("points", "kind", "degree", "first", "corners", "deleted", "problems", "report",
                  "stats"):
            setattr(self, k, d[k])

    @property
    def num_patches(self):
        return len(self.kind)

    def patch_points(self, p):
        """(n, 3) control points of patch p."""
        k, n = int(self.kind[p]), int(self.degree[p])
        count = (n + 1) * (n + 2) // 2 if k == 3 else (n + 1) ** 2
        return self.points[self.first[p]:self.first[p] + count]

    def __repr__(self):
        return "Surface(%d patches, max normal jump %.3g deg)" % (
            self.num_patches, self.report["max_normal_jump_deg"])


def _shaped(a, cols, rows, what):
    a = np.ascontiguousarray(a, dtype=np.float64)
    if a.shape != (rows, cols):
        raise ValueError("%s must have shape (%d, %d)" % (what, rows, cols))
    return a


def _mesh(mesh):
    if not isinstance(mesh, Mesh):
        raise TypeError("expected a surfkit.Mesh, got %s" % type(mesh).__name__)
    return mesh


def read(path):
    """Reads OFF, OBJ, PLY or STL (format from the extension) into a Mesh; a malformed or
    non-manifold file raises Error naming the file and what is wrong."""
    v, offsets, indices, normals, uv = _core.read(path)
    idx = indices.astype(np.int64)
    sizes = np.diff(offsets.astype(np.int64))
    if len(sizes) and (sizes == 3).all():
        faces = idx.reshape(-1, 3)
    else:
        faces = np.split(idx, offsets[1:-1].astype(np.int64))
    return Mesh(v, faces, normals, uv)


def write(path, mesh_or_surface, tess=4):
    """Writes a Mesh (with its normals and uv when present) as OFF, OBJ, PLY or STL by the
    extension, or a Surface as STEP (.step/.stp), IGES (.igs/.iges) or its watertight
    tessellation (.obj, .ply, .off, .stl; tess segments per patch side); atomically (no partial
    file on error)."""
    if isinstance(mesh_or_surface, Surface):
        s = mesh_or_surface
        _core.write_surface(path, np.ascontiguousarray(s.points, dtype=np.float64),
                            np.ascontiguousarray(s.kind, dtype=np.uint8),
                            np.ascontiguousarray(s.degree, dtype=np.uint8),
                            np.ascontiguousarray(s.first, dtype=np.uint32),
                            np.ascontiguousarray(s.corners, dtype=np.uint32), int(tess))
        return
    m = _mesh(mesh_or_surface)
    _core.write(path, m.vertices, *m._flat(), m.normals, m.uv)


def parametrize(mesh, method="floater", boundary=None, seed=1, steps=0, metrics=False):
    """Parametrization of a triangulated disk: (V, 2) float64 uv.

    method: tutte, floater (default), mvc, harmonic, lscm, mips (hierarchical MIPS) or
    mips-flat; boundary: circle, square or free (default: free for lscm and mips, else circle;
    square: corners at the four sharpest boundary turns, computed with the edges whose ends lie
    on one side split as the CLI does, but only the input vertices' uv come back, so a triangle
    of such an edge lies flat on that side); seed, steps: as the CLI's --seed and --steps (mips). The uv is normalized into the unit
    square (one scale and translation), as the CLI writes it. With metrics=True returns (uv, dict)
    with flips, MIPS energy and distortion (as `surfkit param --report`)."""
    m = _mesh(mesh)
    uv, stats = _core.parametrize(m.vertices, *m._flat(), str(method),
                                  None if boundary is None else str(boundary), int(seed),
                                  int(steps))
    return (uv, stats) if metrics else uv


def smooth(mesh, scheme="vc1", estimate_normals=False, allow_split=False):
    """VC1 smooth surface (Cottin & van Damme) interpolating the vertices and normals (the
    mesh's, or estimated when it has none), or scheme="pn" for PN triangles."""
    m = _mesh(mesh)
    return Surface(_core.smooth(m.vertices, *m._flat(), m.normals, str(scheme),
                                bool(estimate_normals), bool(allow_split)))
