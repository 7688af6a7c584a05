#!/usr/bin/env python3
"""Writes the small hand-made files of tests/data/bad (must be rejected) and tests/data/good
(must parse). Run from anywhere; the files are committed, this script documents them."""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
BAD = os.path.join(HERE, "bad")
GOOD = os.path.join(HERE, "good")
os.makedirs(BAD, exist_ok=True)
os.makedirs(GOOD, exist_ok=True)

CUBE_V = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
TET = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"


def w(folder, name, data):
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def ply_bin(endian, nv, verts, faces, extra_header="", fmt_v="ddd", count_fmt="B", idx_fmt="i"):
    e = "<" if endian == "little" else ">"
    head = ("ply\nformat binary_%s_endian 1.0\n%selement vertex %d\n"
            "property double x\nproperty double y\nproperty double z\n"
            "element face %d\nproperty list uchar int vertex_indices\nend_header\n"
            % (endian, extra_header, nv, len(faces)))
    body = b"".join(struct.pack(e + fmt_v, *v) for v in verts)
    for f in faces:
        body += struct.pack(e + count_fmt, len(f)) + struct.pack(e + idx_fmt * len(f), *f)
    return head.encode() + body


TET_V = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
TET_F = [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)]


def stl_bin(tris, header=b"binary", count=None):
    h = header.ljust(80, b" ")[:80]
    n = len(tris) if count is None else count
    body = b"".join(struct.pack("<12fH", 0, 0, 0, *a, *b, *c, 0) for a, b, c in tris)
    return h + struct.pack("<I", n) + body


TET_T = [tuple(TET_V[i] for i in f) for f in TET_F]

# ----------------------------------------------------------------------------------- bad: OFF
w(BAD, "empty.off", "")
w(BAD, "only_comments.off", "# nothing here\n# at all\n")
w(BAD, "no_counts.off", "OFF\n")
w(BAD, "truncated.off", TET[: TET.index("3 1 2 3")])
w(BAD, "truncated_vertices.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n")
w(BAD, "bad_count.off", "OFF\n5 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n"
  "3 1 2 3\n3 0 3 2\n")
w(BAD, "too_few_vertices_declared.off", "OFF\n3 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
  "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n")
w(BAD, "extra_faces.off", TET + "3 0 1 2\n")
w(BAD, "index_out_of_range.off", TET.replace("3 1 2 3", "3 1 2 9001"))
w(BAD, "negative_index.off", TET.replace("3 1 2 3", "3 1 -2 3"))
w(BAD, "nan.off", TET.replace("1 0 0\n", "1 nan 0\n", 1))
w(BAD, "inf.off", TET.replace("0 1 0\n", "0 1 -inf\n", 1))
w(BAD, "overflow_coordinate.off", TET.replace("0 1 0\n", "0 1 1e999\n", 1))
w(BAD, "huge_count.off", "OFF\n1000000000000 2000000000000 0\n0 0 0\n")
w(BAD, "huge_face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n")
w(BAD, "two_index_face.off", TET.replace("3 1 2 3", "2 1 2"))
w(BAD, "short_face.off", TET.replace("3 1 2 3", "4 1 2 3"))
w(BAD, "garbage_number.off", TET.replace("1 0 0\n", "1 0x 0\n", 1))
w(BAD, "two_coordinates.off", TET.replace("1 0 0\n", "1 0\n", 1))
w(BAD, "extra_vertex_values.off", TET.replace("1 0 0\n", "1 0 0 7\n", 1))
w(BAD, "bad_header.off", "OFFF\n4 4 0\n")
w(BAD, "four_d.off", "4OFF\n1 0 0\n0 0 0 0\n")
w(BAD, "binary.off", "OFF BINARY\n" + "\x00" * 20)
w(BAD, "noff_missing_normal.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0\n0 1 0 0 0 1\n3 0 1 2\n")
w(BAD, "float_face_count.off", TET.replace("3 1 2 3", "3.0 1 2 3"))
w(BAD, "binary_garbage.off", bytes(range(256)) * 4)

# ----------------------------------------------------------------------------------- bad: OBJ
w(BAD, "empty.obj", "")
w(BAD, "whitespace_only.obj", "  \n\n \r\n")
w(BAD, "no_geometry.obj", "# only a comment\ng group\nusemtl red\n")
w(BAD, "two_index_face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n")
w(BAD, "index_out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")
w(BAD, "zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n")
w(BAD, "relative_out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n")
w(BAD, "nan.obj", "v 0 0 0\nv 1 NaN 0\nv 0 1 0\nf 1 2 3\n")
w(BAD, "short_vertex.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
w(BAD, "bad_corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n")
w(BAD, "bad_texture_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n")
w(BAD, "bad_normal_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n")
w(BAD, "forward_reference.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n")
w(BAD, "garbage_vertex.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n")
w(BAD, "binary_garbage.obj", b"v " + bytes(range(1, 256)) * 2)

# ----------------------------------------------------------------------------------- bad: PLY
w(BAD, "empty.ply", "")
w(BAD, "garbage.ply", b"ply\n" + bytes(range(256)) * 3)
w(BAD, "no_end_header.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n")
w(BAD, "no_format.ply", "ply\nelement vertex 0\nend_header\n")
w(BAD, "unknown_format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n")
w(BAD, "unknown_type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n"
  "end_header\n0\n")
w(BAD, "no_xyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
  "property float y\nend_header\n0 0\n")
w(BAD, "float_indices.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
  "property float y\nproperty float z\nelement face 0\nproperty list uchar float vertex_indices\n"
  "end_header\n")
ASCII_HEAD = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
              "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
              "end_header\n")
ASCII_TET = ASCII_HEAD + CUBE_V[:24] + "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"
w(GOOD, "tet_ascii.ply", ASCII_TET)
w(BAD, "truncated_ascii.ply", ASCII_TET[:-10])
w(BAD, "index_out_of_range_ascii.ply", ASCII_TET.replace("3 1 2 3", "3 1 2 4"))
w(BAD, "negative_index_ascii.ply", ASCII_TET.replace("3 1 2 3", "3 1 2 -1"))
w(BAD, "two_index_face_ascii.ply", ASCII_TET.replace("3 1 2 3", "2 1 2"))
w(BAD, "nan_ascii.ply", ASCII_TET.replace("1 0 0\n", "1 nan 0\n", 1))
w(BAD, "extra_data_ascii.ply", ASCII_TET + "3 0 1 2\n")
w(BAD, "huge_count.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
  "property double x\nproperty double y\nproperty double z\nend_header\n" + "\0" * 48)
w(BAD, "huge_count_ascii.ply", ASCII_HEAD.replace("vertex 4", "vertex 4000000000") + CUBE_V)
good_bin = ply_bin("little", 4, TET_V, TET_F)
w(GOOD, "tet_binary_le.ply", good_bin)
w(GOOD, "tet_binary_be.ply", ply_bin("big", 4, TET_V, TET_F))
w(BAD, "truncated_binary.ply", good_bin[:-7])
w(BAD, "truncated_binary_vertices.ply", good_bin[: good_bin.index(b"end_header\n") + 11 + 40])
w(BAD, "index_out_of_range_binary.ply", ply_bin("little", 4, TET_V, [(0, 1, 2), (0, 1, 4)]))
w(BAD, "negative_index_binary.ply", ply_bin("big", 4, TET_V, [(0, 1, 2), (0, -1, 3)]))
w(BAD, "two_index_face_binary.ply", ply_bin("little", 4, TET_V, [(0, 1, 2), (0, 1)]))
w(BAD, "nan_binary.ply", ply_bin("little", 4, [(0, 0, 0), (1, float("nan"), 0), (0, 1, 0),
                                              (0, 0, 1)], TET_F))
w(BAD, "huge_list_binary.ply", ply_bin("little", 4, TET_V, [(0, 1, 2)], count_fmt="I",
                                       idx_fmt="i").replace(b"list uchar", b"list uint")[:-16]
  + struct.pack("<I", 0xFFFFFFF0) + b"\0" * 12)

# ----------------------------------------------------------------------------------- bad: STL
w(BAD, "empty.stl", "")
ASCII_STL = ("solid t\n" + "".join(
    "  facet normal 0 0 0\n    outer loop\n" +
    "".join("      vertex %g %g %g\n" % p for p in t) + "    endloop\n  endfacet\n"
    for t in TET_T) + "endsolid t\n")
w(GOOD, "tet_ascii.stl", ASCII_STL)
w(BAD, "truncated_ascii.stl", ASCII_STL[: ASCII_STL.index("endloop", 200)])
w(BAD, "no_endsolid.stl", ASCII_STL.replace("endsolid t\n", ""))
w(BAD, "nan_ascii.stl", ASCII_STL.replace("vertex 1 0 0", "vertex 1 nan 0", 1))
w(BAD, "two_vertex_facet.stl", ASCII_STL.replace("      vertex 0 1 0\n", "", 1))
w(BAD, "bad_keyword.stl", ASCII_STL.replace("outer loop", "outer lop", 1))
w(BAD, "garbage_number.stl", ASCII_STL.replace("vertex 1 0 0", "vertex 1 O 0", 1))
bin_stl = stl_bin(TET_T)
w(GOOD, "tet_binary.stl", bin_stl)
w(GOOD, "tet_binary_solid_header.stl", stl_bin(TET_T, header=b"solid looks like ascii"))
w(BAD, "truncated_binary.stl", bin_stl[:-20])
w(BAD, "short_header.stl", bin_stl[:50])
w(BAD, "huge_count.stl", stl_bin(TET_T, count=0xFFFFFFFF))
w(BAD, "nan_binary.stl", stl_bin([((0, 0, 0), (1, float("nan"), 0), (0, 1, 0))]))

# ----------------------------------------------------------------------------------- bad: sniff
w(BAD, "unknown_format.mesh", "hello world\nthis is not a mesh\n")

# ----------------------------------------------------------------------------------- good
w(GOOD, "crlf.off", TET.replace("\n", "\r\n"))
w(GOOD, "cr_only.off", TET.replace("\n", "\r"))
w(GOOD, "mixed_line_endings.off", "OFF\r\n4 4 0\n0 0 0\r1 0 0\r\n0 1 0\n0 0 1\r\n3 0 2 1\r"
  "3 0 1 3\n3 1 2 3\r\n3 0 3 2")
w(GOOD, "one_line_header.off", "OFF 4 4 0\n" + TET[10:])
w(GOOD, "comments.off", "# a comment\nOFF # header\n\n# counts next\n4 4 0\n# vertices\n"
  "0 0 0\n1 0 0 # trailing\n0 1 0\n0 0 1\n\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n# end\n")
w(GOOD, "no_edge_count.off", TET.replace("4 4 0", "4 4"))
w(GOOD, "coff.off", "COFF\n4 4 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n"
  "0 0 1 1 1 1 1\n3 0 2 1 255 0 0\n3 0 1 3\n3 1 2 3\n3 0 3 2 0.5 0.5 0.5 1\n")
w(GOOD, "noff.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n")
w(GOOD, "stoff.off", "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n")
w(GOOD, "quads.off", "OFF\n8 6 12\n" + CUBE_V + "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n"
  "4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n")
w(GOOD, "crlf.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n")
w(GOOD, "mixed_line_endings.obj", "v 0 0 0\rv 1 0 0\r\nv 0 1 0\nf 1 2 3")
w(GOOD, "forms.obj", "# all face forms\nmtllib x.mtl\no thing\ng group\ns 1\nusemtl red\n"
  "v 0 0 0\nv 1 0 0 1.0\nv 0 1 0 0.5 0.5 0.5\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n"
  "vn 0 0 1\nvn 1 0 0\nf 1 2 3\nf 1/1 2/2 4/3\nf 1//1 3//2 4//1\nf 2/2/1 3/3/2 4/1/1\n"
  "f -4 -2 -1\nl 1 2\np 3\nfoo bar\n")
w(GOOD, "continuation.obj", "v 0 0 0\nv 1 \\\n0 0\nv 0 1 0\nf 1 2 \\\n 3\n")
w(GOOD, "crlf.stl", ASCII_STL.replace("\n", "\r\n"))
w(GOOD, "crlf_ascii.ply", ASCII_TET.replace("\n", "\r\n"))
w(GOOD, "extra_props.ply", "ply\nformat ascii 1.0\ncomment hi\nobj_info x\n"
  "element vertex 3\nproperty uchar red\nproperty float32 x\nproperty list uchar int junk\n"
  "property float64 y\nproperty int16 z\nproperty float nx\nproperty float ny\n"
  "property float nz\nproperty float s\nproperty float t\n"
  "element material 2\nproperty int a\nproperty list ushort float b\n"
  "element face 1\nproperty uchar flags\nproperty list int8 uint32 vertex_index\n"
  "property list uchar int texcoord\n"
  "end_header\n"
  "1 0 2 5 6 0 0 0 0 1 0.25 0.5\n2 1 0 0 0 0 0 1 1 0\n3 0 0 1 0 0 0 1 0 1\n"
  "7 2 1.5 2.5\n8 0\n9 3 0 1 2 0\n")
# found by fuzzing: huge coordinates made the number writer cast a double to int64 (UB)
w(GOOD, "large_values.off", "OFF\n3 1 0\n3.8275e+137 -5.55556e+127 7.26434e+22\n"
  "1.7976931348623157e308 0 -0\n4.9406564584124654e-324 1 2\n3 0 1 2\n")
# issue 17: parse, but every corner of the only face is unusable (a repeated vertex); validation read
# uninitialised memory and `info` crashed; and a valid disk plus one such face (valgrind saw it)
w(GOOD, "repeated_vertex_only.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2 0\n")
w(GOOD, "disk_plus_repeated_vertex.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
  "3 0 1 2\n3 0 2 3\n3 0 0 1\n")
# found by fuzz_pipeline (content sniffing): only comments, and the "solid" test read 5 bytes past
# the end of the buffer
w(BAD, "comments_only.mesh", "# nothing here\n# at all\n")
