/* CAD writers: record structure of IGES, entity structure of STEP, OBJ free-form, errors. The
 * round trip through an independent CAD kernel is tests/occt. */
#include "testutil.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A quad (bicubic, flat) and two triangles (quartic, flat) sharing edges: the square [0,2]x[0,1]. */
static size_t sample_patches(sk_patch_set *out)
{
    const double P[6][3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
    sk_patch_set lin = {0};
    double quad[4 * 3];
    const int qi[4] = {0, 1, 3, 4}; /* (0,0) (1,0) (0,1) (1,1) */
    for (int k = 0; k < 4; ++k)
        memcpy(quad + 3 * k, P[qi[k]], sizeof P[0]);
    uint32_t qc[4] = {0, 1, 4, 3};
    sk_patch_set_add(&lin, SK_PATCH_TENSOR, 1, 1, quad, qc, NULL, NULL);
    sk_patch_elevate(&lin, 0, 3, 3, out, NULL);
    const int tri[2][3] = {{1, 2, 5}, {1, 5, 4}};
    for (int t = 0; t < 2; ++t) {
        double cp[3 * 3];
        memcpy(cp + 3 * sk_tri_index(1, 0, 0), P[tri[t][0]], sizeof P[0]);
        memcpy(cp + 3 * sk_tri_index(1, 1, 0), P[tri[t][1]], sizeof P[0]);
        memcpy(cp + 3 * sk_tri_index(1, 0, 1), P[tri[t][2]], sizeof P[0]);
        uint32_t ids[3] = {(uint32_t)tri[t][0], (uint32_t)tri[t][1], (uint32_t)tri[t][2]};
        size_t k;
        sk_patch_set_add(&lin, SK_PATCH_TRIANGLE, 1, 0, cp, ids, &k, NULL);
        sk_patch_elevate(&lin, k, 4, 0, out, NULL);
    }
    sk_patch_set_free(&lin);
    return out->count;
}

static size_t count(const char *text, const char *needle)
{
    size_t n = 0;
    for (const char *p = strstr(text, needle); p; p = strstr(p + 1, needle))
        ++n;
    return n;
}

static void given_patches_when_iges_written_then_records_are_80_columns_and_counted(void **state)
{
    (void)state;
    sk_patch_set p = {0};
    sample_patches(&p);
    sk_export_opts o = {.timestamp = "2026-01-02T03:04:05", .units = "in"};
    sk_export_stats st;
    const char *path = skt_tmp_path("sample.igs");
    assert_int_equal(sk_export_iges(path, &p, &o, &st, NULL), SK_OK);
    assert_int_equal(st.faces, 7); /* 1 quad + 2 triangles x 3 */
    size_t size;
    char *text = skt_read_file(path, &size);
    size_t lines = 0, counts[5] = {0};
    const char *sections = "SGDPT";
    for (char *line = text; *line; ++lines) {
        char *nl = strchr(line, '\n');
        assert_non_null(nl);
        assert_int_equal(nl - line, 80);
        const char *sec = strchr(sections, line[72]);
        assert_non_null(sec);
        counts[sec - sections]++;
        line = nl + 1;
    }
    assert_int_equal(counts[2], 2 * 7);  /* two directory lines per entity */
    assert_int_equal(counts[4], 1);
    char term[40];
    snprintf(term, sizeof term, "S%07zuG%07zuD%07zuP%07zu", counts[0], counts[1], counts[2], counts[3]);
    assert_non_null(strstr(text, term));
    assert_non_null(strstr(text, "2HIN"));                 /* units name */
    assert_non_null(strstr(text, "15H20260102.030405"));   /* date */
    assert_int_equal(count(text, "     128"), 2 * 7);      /* entity type in both DE lines */
    free(text);
    /* degenerate triangles: one entity per triangle */
    o.degenerate_triangles = true;
    assert_int_equal(sk_export_iges(path, &p, &o, &st, NULL), SK_OK);
    assert_int_equal(st.faces, 3);
    sk_patch_set_free(&p);
}

static void given_patches_when_step_written_then_faces_share_edges(void **state)
{
    (void)state;
    sk_patch_set p = {0};
    sample_patches(&p);
    sk_export_opts o = {.timestamp = "2026-01-02T03:04:05"};
    sk_export_stats st;
    const char *path = skt_tmp_path("sample.step");
    assert_int_equal(sk_export_step(path, &p, &o, &st, NULL), SK_OK);
    size_t size;
    char *text = skt_read_file(path, &size);
    assert_int_equal(count(text, "ADVANCED_FACE("), 7);
    assert_int_equal(count(text, "B_SPLINE_SURFACE_WITH_KNOTS("), 7);
    assert_int_equal(count(text, "OPEN_SHELL("), 1);
    /* vertices: 6 corners, 5 midpoints of the edges next to triangles, 2 centroids */
    assert_int_equal(st.vertices, 13);
    assert_int_equal(count(text, "VERTEX_POINT("), 13);
    /* edge uses: every face has 4 sides, the quad's side next to a triangle is in two pieces:
     * 29 oriented edges over distinct edge curves */
    assert_int_equal(count(text, "ORIENTED_EDGE("), 29);
    assert_int_equal(count(text, "EDGE_CURVE("), st.edges);
    assert_true(st.edges < 29); /* shared edges are written once */
    assert_non_null(strstr(text, "END-ISO-10303-21;"));
    assert_non_null(strstr(text, "SI_UNIT(.MILLI.,.METRE.)"));
    free(text);
    sk_patch_set_free(&p);
}

static void given_patches_when_obj_freeform_written_then_one_surf_per_tensor_patch(void **state)
{
    (void)state;
    sk_patch_set p = {0};
    sample_patches(&p);
    const char *path = skt_tmp_path("sample_ff.obj");
    assert_int_equal(sk_export_obj_freeform(path, &p, NULL, NULL, NULL), SK_OK);
    size_t size;
    char *text = skt_read_file(path, &size);
    assert_int_equal(count(text, "\nsurf "), 7);
    assert_int_equal(count(text, "deg 3 3"), 1);
    assert_int_equal(count(text, "deg 4 4"), 6);
    assert_int_equal(count(text, "\nv "), 16 + 6 * 25);
    /* B-splines with clamped knots (one span), not Bezier: degree + 1 zeros, degree + 1 ones */
    assert_int_equal(count(text, "cstype bspline\n"), 7);
    assert_int_equal(count(text, "cstype bezier"), 0);
    assert_int_equal(count(text, "\nparm u 0.0 0.0 0.0 0.0 1.0 1.0 1.0 1.0\n"), 1);
    assert_int_equal(count(text, "\nparm v 0.0 0.0 0.0 0.0 0.0 1.0 1.0 1.0 1.0 1.0\nend\n"), 6);
    free(text);
    sk_patch_set_free(&p);
}

static void given_bad_arguments_then_writers_fail_and_leave_no_file(void **state)
{
    (void)state;
    sk_patch_set p = {0};
    sample_patches(&p);
    sk_error err;
    const char *path = skt_tmp_path("bad.step");
    unlink(path);
    p.patches[1].corner_ids[2] = SK_INVALID;
    assert_int_equal(sk_export_step(path, &p, NULL, NULL, &err), SK_ERR_ARG);
    assert_non_null(strstr(err.message, "corner ids"));
    assert_int_equal(access(path, F_OK), -1);
    sk_export_opts o = {.units = "furlong"};
    assert_int_equal(sk_export_iges(skt_tmp_path("bad.igs"), &p, &o, NULL, &err), SK_ERR_ARG);
    assert_non_null(strstr(err.message, "furlong"));
    assert_int_equal(sk_export_iges("/nonexistent-dir/x.igs", &p, NULL, NULL, &err), SK_ERR_IO);
    sk_patch_set_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_patches_when_iges_written_then_records_are_80_columns_and_counted),
        cmocka_unit_test(given_patches_when_step_written_then_faces_share_edges),
        cmocka_unit_test(given_patches_when_obj_freeform_written_then_one_surf_per_tensor_patch),
        cmocka_unit_test(given_bad_arguments_then_writers_fail_and_leave_no_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
