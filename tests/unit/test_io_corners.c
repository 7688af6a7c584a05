/* Per-corner (wedge) attributes through the mesh and the OBJ / PLY readers and writers: given an
 * atlas of a closed mesh (seams: one vertex with several uvs), when it goes mesh -> soup -> OBJ ->
 * PLY (binary and ascii) -> OBJ, then every corner keeps its uv bit for bit and OBJ shares vt
 * inside a chart; given hand-written files with per-corner vt / vn and MeshLab's texcoord list,
 * when read, then each corner has its own value. */
#include "testutil.h"

#include "surfkit/atlas.h"
#include "surfkit/io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static sk_soup *reread(const sk_soup *s, sk_format fmt, bool ascii)
{
    sk_write_opts wo = {0};
    wo.format = fmt;
    wo.ascii = ascii;
    void *data = NULL;
    size_t size = 0;
    sk_error err;
    if (sk_soup_write_memory(s, &wo, &data, &size, &err))
        fail_msg("write: %s", err.message);
    sk_read_opts ro = {fmt};
    sk_soup *out = NULL;
    if (sk_soup_read_memory(data, size, "mem", &ro, &out, &err))
        fail_msg("read back: %s", err.message);
    free(data);
    return out;
}

/* corner uv of every corner equal, bit for bit */
static void assert_same_corner_uvs(const sk_soup *a, const sk_soup *b)
{
    assert_int_equal(a->num_faces, b->num_faces);
    assert_non_null(a->corner_uv);
    assert_non_null(b->corner_uv);
    size_t nc = a->face_offsets[a->num_faces];
    assert_int_equal(nc, b->face_offsets[b->num_faces]);
    for (size_t c = 0; c < nc; ++c) {
        assert_int_equal(a->face_indices[c], b->face_indices[c]);
        assert_int_not_equal(a->corner_uv[c], SK_INVALID);
        assert_int_not_equal(b->corner_uv[c], SK_INVALID);
        assert_memory_equal(a->wedge_uvs + 2 * (size_t)a->corner_uv[c],
                            b->wedge_uvs + 2 * (size_t)b->corner_uv[c], 2 * sizeof(double));
    }
}

static void test_atlas_round_trips(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("cow.off"));
    sk_atlas *a = NULL;
    assert_int_equal(sk_atlas_build(m, NULL, &a, NULL, NULL), SK_OK);
    assert_true(a->num_uvs > m->num_vertices); /* seams split vertices */
    assert_int_equal(sk_mesh_set_wedge_uvs(m, a->num_uvs, a->uvs, a->corner_uv, NULL), SK_OK);
    sk_mesh *copy = NULL;
    assert_int_equal(sk_mesh_copy(m, &copy, NULL), SK_OK);
    assert_int_equal(copy->num_wedge_uvs, a->num_uvs);
    assert_memory_equal(copy->h_wedge_uv, a->corner_uv, m->num_halfedges * sizeof(uint32_t));
    sk_soup *s = NULL;
    assert_int_equal(sk_mesh_to_soup(copy, &s, NULL), SK_OK);
    assert_int_equal(s->num_wedge_uvs, a->num_uvs);
    assert_int_equal(s->num_vertices, m->num_vertices);

    sk_soup *obj = reread(s, SK_FORMAT_OBJ, true);
    assert_same_corner_uvs(s, obj);
    assert_int_equal(obj->num_wedge_uvs, a->num_uvs); /* vt shared inside a chart */
    assert_int_equal(obj->num_vertices, m->num_vertices);
    sk_soup *ply = reread(obj, SK_FORMAT_PLY, false);
    assert_same_corner_uvs(s, ply);
    sk_soup *plya = reread(ply, SK_FORMAT_PLY, true);
    assert_same_corner_uvs(s, plya);
    sk_soup *obj2 = reread(plya, SK_FORMAT_OBJ, true);
    assert_same_corner_uvs(s, obj2);

    /* soup -> mesh -> soup keeps them too */
    sk_mesh *m2 = NULL;
    assert_int_equal(sk_mesh_from_soup(obj2, &m2, NULL), SK_OK);
    assert_non_null(m2->h_wedge_uv);
    sk_soup *s2 = NULL;
    assert_int_equal(sk_mesh_to_soup(m2, &s2, NULL), SK_OK);
    assert_same_corner_uvs(s, s2);
    /* and the half-edge corners are the atlas's */
    for (size_t f = 0; f < m->num_faces; ++f) {
        uint32_t h = m->f_halfedge[f], h2 = m2->f_halfedge[f];
        for (int k = 0; k < 3; ++k, h = m->h_next[h], h2 = m2->h_next[h2]) {
            assert_int_equal(sk_from(m, h), sk_from(m2, h2));
            assert_memory_equal(a->uvs + 2 * (size_t)a->corner_uv[h],
                                m2->wedge_uvs + 2 * (size_t)m2->h_wedge_uv[h2], 2 * sizeof(double));
        }
    }
    sk_soup_destroy(&s2);
    sk_mesh_destroy(&m2);
    sk_soup_destroy(&obj);
    sk_soup_destroy(&ply);
    sk_soup_destroy(&plya);
    sk_soup_destroy(&obj2);
    sk_soup_destroy(&s);
    sk_mesh_destroy(&copy);
    sk_atlas_destroy(&a);
    sk_mesh_destroy(&m);
}

static void test_obj_corner_normals_and_seams(void **state)
{
    (void)state;
    /* two triangles sharing the edge 2-3: a seam in uv (vertex 2 has two vt) and a crease in
     * normals (two vn); the last face has no vt / vn */
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 2 0\n"
                       "vt 0 0\nvt 0.5 0\nvt 0 0.5\nvt 0.7 0.7\nvt 0.9 0.1\n"
                       "vn 0 0 1\nvn 0 1 0\n"
                       "f 1/1/1 2/2/1 3/3/1\nf 2/5/2 4/4/2 3/1/2\nf 4 5 3\n";
    sk_soup *s = NULL;
    sk_error err;
    sk_read_opts ro = {SK_FORMAT_OBJ};
    if (sk_soup_read_memory(text, strlen(text), "t.obj", &ro, &s, &err))
        fail_msg("%s", err.message);
    assert_int_equal(s->num_wedge_uvs, 5);
    assert_int_equal(s->num_wedge_normals, 2);
    uint32_t want_uv[9] = {0, 1, 2, 4, 3, 0, SK_INVALID, SK_INVALID, SK_INVALID};
    uint32_t want_n[9] = {0, 0, 0, 1, 1, 1, SK_INVALID, SK_INVALID, SK_INVALID};
    assert_memory_equal(s->corner_uv, want_uv, sizeof want_uv);
    assert_memory_equal(s->corner_normal, want_n, sizeof want_n);
    /* per-vertex: the first corner wins (vertex 2, index 1: vt 2 not vt 5) */
    assert_true(s->uvs[2] == 0.5 && s->uvs[3] == 0);
    sk_soup *b = reread(s, SK_FORMAT_OBJ, true);
    assert_int_equal(b->num_wedge_uvs, 5);
    assert_memory_equal(b->corner_uv, want_uv, sizeof want_uv);
    assert_memory_equal(b->corner_normal, want_n, sizeof want_n);
    assert_memory_equal(b->wedge_normals, s->wedge_normals, 6 * sizeof(double));
    sk_soup_destroy(&b);
    sk_soup_destroy(&s);
}

static void test_ply_meshlab_texcoord(void **state)
{
    (void)state;
    const char *text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 2\n"
                       "property list uchar int vertex_indices\n"
                       "property list uchar float texcoord\nend_header\n"
                       "0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
                       "3 0 1 2 6 0 0 0.5 0 0 0.5\n3 1 3 2 6 0.25 0.25 0.75 0.75 0.125 0.875\n";
    sk_soup *s = NULL;
    sk_error err;
    sk_read_opts ro = {SK_FORMAT_PLY};
    if (sk_soup_read_memory(text, strlen(text), "t.ply", &ro, &s, &err))
        fail_msg("%s", err.message);
    assert_non_null(s->corner_uv);
    assert_int_equal(s->num_wedge_uvs, 6);
    /* vertex 1 and 2 have two uvs each */
    assert_true(s->wedge_uvs[2 * s->corner_uv[1]] == 0.5);
    assert_true(s->wedge_uvs[2 * s->corner_uv[3]] == 0.25);
    assert_true(s->wedge_uvs[2 * s->corner_uv[5] + 1] == 0.875);
    sk_soup *b = reread(s, SK_FORMAT_PLY, false);
    assert_same_corner_uvs(s, b);
    sk_soup_destroy(&b);
    sk_soup_destroy(&s);
    /* a texcoord list of the wrong length is an error naming the face */
    const char *bad = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 1\n"
                      "property list uchar int vertex_indices\n"
                      "property list uchar float texcoord\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2 4 0 0 1 0\n";
    assert_int_equal(sk_soup_read_memory(bad, strlen(bad), "bad.ply", &ro, &s, &err),
                     SK_ERR_PARSE);
    assert_non_null(strstr(err.message, "face 0 has 4 texcoord values for 3 corners"));
    assert_null(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_obj_corner_normals_and_seams),
        cmocka_unit_test(test_ply_meshlab_texcoord),
        cmocka_unit_test(test_atlas_round_trips),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
