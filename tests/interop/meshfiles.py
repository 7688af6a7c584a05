"""Small stand-alone readers for the interop checks (standard library only): OBJ corners with their
UVs, PLY header and per-vertex UVs (ascii and binary), so the checks compare against what the
files say, independently of surfkit's readers."""
import struct


def obj_corners(path):
    """(positions, faces) where each face is a list of (position, uv or None) corners."""
    v, vt, faces = [], [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                v.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == "vt":
                vt.append(tuple(float(x) for x in t[1:3]))
            elif t[0] == "f":
                face = []
                for c in t[1:]:
                    idx = c.split("/")
                    vi = int(idx[0])
                    vi = vi - 1 if vi > 0 else len(v) + vi
                    uv = None
                    if len(idx) > 1 and idx[1]:
                        ti = int(idx[1])
                        uv = vt[ti - 1 if ti > 0 else len(vt) + ti]
                    face.append((v[vi], uv))
                faces.append(face)
    return v, faces


_PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h",
              "ushort": "H", "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I",
              "float": "f", "float32": "f", "double": "d", "float64": "d"}


def ply_read(path):
    """(vertex property dict name -> list, faces as index lists, header elements)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt, elements = None, []
    for line in header:
        t = line.split()
        if not t:
            continue
        if t[0] == "format":
            fmt = t[1]
        elif t[0] == "element":
            elements.append([t[1], int(t[2]), []])
        elif t[0] == "property":
            elements[-1][2].append(t[1:])
    body = data[end:]
    out = {}
    if fmt == "ascii":
        toks = body.split()
        pos = 0

        def take(ty):
            nonlocal pos
            pos += 1
            return float(toks[pos - 1]) if _PLY_TYPES[ty] in "fd" else int(toks[pos - 1])
    else:
        order = "<" if fmt == "binary_little_endian" else ">"
        pos = 0

        def take(ty):
            nonlocal pos
            c = _PLY_TYPES[ty]
            val = struct.unpack_from(order + c, body, pos)[0]
            pos += struct.calcsize(c)
            return val
    for name, count, props in elements:
        rows = {p[-1]: [] for p in props}
        for _ in range(count):
            for p in props:
                if p[0] == "list":
                    n = take(p[1])
                    rows[p[-1]].append([take(p[2]) for _ in range(n)])
                else:
                    rows[p[-1]].append(take(p[0]))
        out[name] = rows
    return out, [(e[0], e[1], [p[-1] for p in e[2]]) for e in elements]


def ply_uv_names(props):
    for u, v in (("s", "t"), ("texture_u", "texture_v"), ("u", "v")):
        if u in props and v in props:
            return u, v
    return None
