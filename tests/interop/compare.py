"""Checks for tests/interop (standard library only). Usage:
  compare.py blender-obj OURS.obj BLENDER.json   Blender's corner UVs equal the file's
  compare.py blender-ply OURS.ply BLENDER.json   Blender's corner UVs equal the file's vertex UVs
  compare.py ply-uv BLENDER.ply CONVERTED.obj    surfkit read Blender's PLY UVs (s t)
  compare.py obj-uv BLENDER.obj CONVERTED.obj    surfkit kept Blender's per-corner OBJ UVs (seams)
Prints one line; exit 1 on a mismatch. UV tolerance 1e-6 (Blender keeps UVs in float32)."""
import json
import math
import sys

from meshfiles import obj_corners, ply_read, ply_uv_names

TOL = 1e-6


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


def aligned(face_xyz, want_xyz):
    """Rotation r such that face corner (k + r) is file corner k, or None."""
    n = len(want_xyz)
    if len(face_xyz) != n:
        return None
    scale = max(1.0, max(abs(c) for p in want_xyz for c in p))
    for r in range(n):
        if all(close(face_xyz[(k + r) % n], want_xyz[k], 1e-5 * scale) for k in range(n)):
            return r
    return None


def blender_vs_file(want, got, label):
    """want: list of faces, each a list of (xyz, uv); got: Blender's JSON."""
    if got["uv_layers"] == 0:
        print("%s: Blender read no UVs (%d faces)" % (label, got["faces"]))
        return 1
    if got["faces"] != len(want):
        print("%s: Blender has %d faces, the file %d" % (label, got["faces"], len(want)))
        return 1
    bad, worst, unaligned = 0, 0.0, 0
    for fi, face in enumerate(want):
        r = aligned(got["faces_xyz"][fi], [c[0] for c in face])
        if r is None:
            unaligned += 1
            continue
        for k, (_, uv) in enumerate(face):
            g = got["faces_uv"][fi][(k + r) % len(face)]
            d = max(abs(g[0] - uv[0]), abs(g[1] - uv[1]))
            worst = max(worst, d)
            bad += d > TOL
    print("%s: %d faces, %d corners with a different UV (max difference %.3g), %d faces not "
          "matched by position" % (label, len(want), bad, worst, unaligned))
    return 1 if bad or unaligned else 0


def corner_uvs_equal(want, got, label):
    """want, got: lists of faces of (xyz, uv) in the same face order."""
    if len(want) != len(got):
        print("%s: %d faces read, the file has %d" % (label, len(got), len(want)))
        return 1
    bad, worst, missing = 0, 0.0, 0
    for fw, fg in zip(want, got):
        r = aligned([c[0] for c in fg], [c[0] for c in fw])
        if r is None:
            missing += len(fw)
            continue
        for k, (_, uv) in enumerate(fw):
            g = fg[(k + r) % len(fw)][1]
            if g is None:
                missing += 1
                continue
            d = max(abs(g[0] - uv[0]), abs(g[1] - uv[1]))
            worst = max(worst, d)
            bad += d > TOL
    print("%s: %d faces, %d corners with a different UV (max difference %.3g), %d corners without "
          "a UV or not matched" % (label, len(want), bad, worst, missing))
    return 1 if bad or missing else 0


def main(argv):
    mode, a, b = argv[1], argv[2], argv[3]
    if mode == "blender-obj":
        _, faces = obj_corners(a)
        return blender_vs_file(faces, json.load(open(b)), "Blender imports " + a)
    if mode == "blender-ply":
        ply, elems = ply_read(a)
        props = [e for e in elems if e[0] == "vertex"][0][2]
        names = ply_uv_names(props)
        if not names:
            print("%s has no UV properties" % a)
            return 1
        vx = ply["vertex"]
        xyz = list(zip(vx["x"], vx["y"], vx["z"]))
        uv = list(zip(vx[names[0]], vx[names[1]]))
        faces = [[(xyz[i], uv[i]) for i in f] for f in ply["face"]["vertex_indices"]]
        return blender_vs_file(faces, json.load(open(b)), "Blender imports " + a)
    if mode in ("ply-uv", "obj-uv"):
        if mode == "ply-uv":
            ply, elems = ply_read(a)
            props = [e for e in elems if e[0] == "vertex"][0][2]
            names = ply_uv_names(props)
            vx = ply["vertex"]
            xyz = list(zip(vx["x"], vx["y"], vx["z"]))
            uv = list(zip(vx[names[0]], vx[names[1]]))
            want = [[(xyz[i], uv[i]) for i in f] for f in ply["face"]["vertex_indices"]]
        else:
            want = obj_corners(a)[1]
        got = obj_corners(b)[1]
        return corner_uvs_equal(want, got, "surfkit reads " + a)
    print("unknown mode " + mode)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
