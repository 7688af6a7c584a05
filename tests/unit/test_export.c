/* CAD writers: record structure of IGES, entity structure of STEP, OBJ free-form, errors. The
 * round trip through an independent CAD kernel is tests/occt. */
#include "testutil.h"

#include "export/export_internal.h"

#include <float.h>
#include <math.h>
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
    sk_export_opts o = {.timestamp = "2026-01-02T03:04:05", .units = "in",
                        .iges_free_surfaces = true};
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
    assert_int_equal(counts[2], 2 * (7 + 1)); /* two directory lines per entity, + the group */
    assert_int_equal(counts[4], 1);
    char term[40];
    snprintf(term, sizeof term, "S%07zuG%07zuD%07zuP%07zu", counts[0], counts[1], counts[2], counts[3]);
    assert_non_null(strstr(text, term));
    assert_non_null(strstr(text, "2HIN"));                 /* units name */
    assert_non_null(strstr(text, "15H20260102.030405"));   /* date */
    assert_int_equal(count(text, "     128"), 2 * 7);      /* entity type in both DE lines */
    assert_int_equal(count(text, "     402"), 2);          /* one group holds them */
    free(text);
    /* degenerate triangles: one entity per triangle */
    o.degenerate_triangles = true;
    assert_int_equal(sk_export_iges(path, &p, &o, &st, NULL), SK_OK);
    assert_int_equal(st.faces, 3);
    sk_patch_set_free(&p);
}

/* Number of DE entries (first DE line of each entity) of the given type, and the form number
 * (second line, columns 33-40) of the last one. */
static size_t count_entities(const char *text, int type, int *form)
{
    size_t n = 0;
    for (const char *line = text; *line;) {
        const char *nl = strchr(line, '\n');
        if (!nl)
            break;
        if (line[72] == 'D' && atoi(line) == type) {
            long seq = atol(line + 73);
            if (seq % 2 == 1)
                ++n;
            else if (form)
                *form = atoi(line + 32);
        }
        line = nl + 1;
    }
    return n;
}

static void given_patches_when_iges_written_then_faces_form_a_brep_with_shared_edges(void **state)
{
    (void)state;
    sk_patch_set p = {0};
    sample_patches(&p);
    sk_export_opts o = {.timestamp = "2026-01-02T03:04:05",
                        .split_triangles = true};
    sk_export_stats st, sst;
    assert_int_equal(sk_export_step(skt_tmp_path("brep.step"), &p, &o, &sst, NULL), SK_OK);
    const char *path = skt_tmp_path("brep.igs");
    assert_int_equal(sk_export_iges(path, &p, &o, &st, NULL), SK_OK);
    sk_patch_set_free(&p);
    size_t size;
    char *text = skt_read_file(path, &size);
    int form = -1;
    assert_int_equal(st.faces, 7);
    assert_false(st.solid);
    assert_int_equal(count_entities(text, 186, NULL), 0); /* open: no solid */
    assert_int_equal(count_entities(text, 514, &form), 1);
    assert_int_equal(form, 2); /* open shell */
    assert_int_equal(count_entities(text, 510, NULL), 7);
    assert_int_equal(count_entities(text, 508, NULL), 7);
    assert_int_equal(count_entities(text, 128, NULL), 7);
    assert_int_equal(count_entities(text, 504, NULL), 1);
    assert_int_equal(count_entities(text, 502, NULL), 1);
    /* the same vertices and edges as the STEP writer finds from the corner ids: 6 corners, 5
     * midpoints, 2 centroids; 29 loop pieces (one parameter-space line each) over fewer edges */
    assert_int_equal(st.vertices, 13);
    assert_int_equal(st.edges, sst.edges);
    assert_int_equal(count_entities(text, 126, NULL), st.edges);
    assert_int_equal(count_entities(text, 110, NULL), 29);
    free(text);
}

/* A tensor patch with a side collapsed to a point (the degenerate form of a triangle) is a B-rep
 * face bounded by its other three sides: no edge for the collapsed one. */
static void given_a_collapsed_side_when_iges_written_then_a_face_without_that_edge(void **state)
{
    (void)state;
    sk_patch_set p = {0}, d = {0};
    sample_patches(&p);
    assert_int_equal(sk_patch_triangle_to_degenerate_tensor(&p, 1, &d, NULL), SK_OK);
    assert_int_equal(sk_patch_elevate(&p, 0, p.patches[0].degree, p.patches[0].degree_v, &d, NULL),
                     SK_OK); /* a copy of the quad */
    sk_export_stats st;
    const char *path = skt_tmp_path("collapsed.igs");
    assert_int_equal(sk_export_iges(path, &d, NULL, &st, NULL), SK_OK);
    sk_patch_set_free(&p);
    sk_patch_set_free(&d);
    size_t size;
    char *text = skt_read_file(path, &size);
    assert_int_equal(st.faces, 2);
    assert_int_equal(st.vertices, 6);       /* 1 2 5 (triangle), 0 1 4 3 (quad): 1 shared */
    assert_int_equal(st.edges, 3 + 4);      /* no shared side: the triangle (1, 2, 5) */
    assert_false(st.solid);
    assert_int_equal(count_entities(text, 128, NULL), 2);
    assert_int_equal(count_entities(text, 510, NULL), 2);
    assert_int_equal(count_entities(text, 508, NULL), 2);
    assert_int_equal(count_entities(text, 126, NULL), 7);
    assert_int_equal(count_entities(text, 402, NULL), 0);
    assert_int_equal(count_entities(text, 514, NULL), 1);
    free(text);
}

/* The default layout: one face per triangle (a biquartic with the side s = 0 collapsed to its
 * first corner) bounded by the triangle's three edges; STEP writes every distinct control point
 * once, so the collapsed row is one point five times; IGES leaves out the parameter-space curves
 * unless asked. */
static void given_triangles_when_written_then_one_face_each_and_points_shared(void **state)
{
    (void)state;
    sk_patch_set p = {0};
    sample_patches(&p);
    sk_export_opts o = {.timestamp = "2026-01-02T03:04:05"};
    sk_export_stats st;
    const char *path = skt_tmp_path("one_face.step");
    assert_int_equal(sk_export_step(path, &p, &o, &st, NULL), SK_OK);
    size_t size;
    char *text = skt_read_file(path, &size);
    assert_int_equal(st.faces, 3);
    assert_int_equal(count(text, "ADVANCED_FACE("), 3);
    assert_int_equal(st.vertices, 6);
    assert_int_equal(count(text, "VERTEX_POINT("), 6);
    /* quad 4 sides, triangles 3 each; (1, 4) and (1, 5) are shared */
    assert_int_equal(st.edges, 8);
    assert_int_equal(count(text, "EDGE_CURVE("), 8);
    assert_int_equal(count(text, "ORIENTED_EDGE("), 10);
    /* no two CARTESIAN_POINTs of the geometry at the same coordinates (the header's placement
     * origin, #15, comes first and stands apart) */
    size_t npts = 0;
    char **pts = malloc(1000 * sizeof *pts);
    assert_non_null(strstr(text, "#15=CARTESIAN_POINT('',(0.,0.,0.));"));
    for (const char *c = strstr(strstr(text, "#16="), "CARTESIAN_POINT('',("); c; c = strstr(c + 1, "CARTESIAN_POINT('',(")) {
        const char *e = strchr(c, ')');
        assert_non_null(e);
        assert_true(npts < 1000);
        pts[npts] = calloc((size_t)(e - c) + 1, 1);
        memcpy(pts[npts], c, (size_t)(e - c));
        for (size_t k = 0; k < npts; ++k)
            assert_string_not_equal(pts[k], pts[npts]);
        ++npts;
    }
    /* the quad's 16, each triangle's 21 distinct points, less those on the sides it shares with
     * the quad or the other triangle where they agree to the bit */
    assert_true(npts <= 16 + 21 + 21);
    assert_true(npts >= 16 + 21 + 21 - 5 - 5);
    for (size_t k = 0; k < npts; ++k)
        free(pts[k]);
    free(pts);
    /* each triangle's surface: the first row (s = 0) is one point, five times */
    size_t degenerate_rows = 0;
    for (const char *c = strstr(text, "B_SPLINE_SURFACE_WITH_KNOTS('',4,4,(("); c;
         c = strstr(c + 1, "B_SPLINE_SURFACE_WITH_KNOTS('',4,4,((")) {
        unsigned ids[5];
        assert_int_equal(sscanf(c + strlen("B_SPLINE_SURFACE_WITH_KNOTS('',4,4,(("),
                                "#%u,#%u,#%u,#%u,#%u", &ids[0], &ids[1], &ids[2], &ids[3], &ids[4]),
                         5);
        degenerate_rows += ids[0] == ids[1] && ids[1] == ids[2] && ids[2] == ids[3] &&
                           ids[3] == ids[4];
    }
    assert_int_equal(degenerate_rows, 2);
    free(text);

    path = skt_tmp_path("one_face.igs");
    assert_int_equal(sk_export_iges(path, &p, &o, &st, NULL), SK_OK);
    text = skt_read_file(path, &size);
    assert_int_equal(st.faces, 3);
    assert_int_equal(st.vertices, 6);
    assert_int_equal(st.edges, 8);
    assert_int_equal(count_entities(text, 510, NULL), 3);
    assert_int_equal(count_entities(text, 128, NULL), 3);
    assert_int_equal(count_entities(text, 126, NULL), 8);
    assert_int_equal(count_entities(text, 110, NULL), 0);
    free(text);
    o.iges_pcurves = true;
    assert_int_equal(sk_export_iges(path, &p, &o, &st, NULL), SK_OK);
    text = skt_read_file(path, &size);
    assert_int_equal(count_entities(text, 110, NULL), 10); /* one per loop piece */
    free(text);
    /* the tensor patches that tests compare with a CAD kernel's reading: the same 3 */
    sk_patch_set t = {0};
    assert_int_equal(sk_export_tensor_patches(&p, &o, &t, NULL), SK_OK);
    assert_int_equal(t.count, 3);
    sk_patch_set_free(&t);
    sk_patch_set_free(&p);
}

typedef struct progress_log {
    size_t calls, stop_at;
    double last;
    bool monotone;
} progress_log;

static int log_progress(void *user, double f)
{
    progress_log *l = user;
    if (f < l->last || f < 0.0 || f > 1.0)
        l->monotone = false;
    l->last = f;
    return ++l->calls == l->stop_at;
}

/* The writers report their progress, increasing to 1; a non-zero return cancels and leaves no
 * file. */
static void given_a_progress_callback_when_writing_then_fractions_to_one_and_cancel(void **state)
{
    (void)state;
    sk_patch_set p = {0};
    sample_patches(&p);
    for (int f = 0; f < 2; ++f) {
        progress_log l = {.monotone = true};
        sk_export_opts o = {.progress = log_progress, .progress_user = &l};
        const char *path = skt_tmp_path(f ? "progress.igs" : "progress.step");
        unlink(path);
        sk_status s = f ? sk_export_iges(path, &p, &o, NULL, NULL)
                        : sk_export_step(path, &p, &o, NULL, NULL);
        assert_int_equal(s, SK_OK);
        assert_true(l.monotone);
        assert_true(l.calls >= 2);
        assert_true(l.last == 1.0);
        unlink(path);
        progress_log stop = {.monotone = true, .stop_at = 2};
        o.progress_user = &stop;
        sk_error err;
        s = f ? sk_export_iges(path, &p, &o, NULL, &err) : sk_export_step(path, &p, &o, NULL, &err);
        assert_int_equal(s, SK_ERR_CANCELLED);
        assert_int_equal(stop.calls, 2);
        assert_int_equal(access(path, F_OK), -1);
    }
    sk_patch_set_free(&p);
}

/* A closed surface (a flat tetrahedron) gives a solid: 186 over a closed 514 shell. */
static void given_closed_patches_when_iges_written_then_a_solid(void **state)
{
    (void)state;
    const double P[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const int tri[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    sk_patch_set p = {0}, lin = {0};
    for (int t = 0; t < 4; ++t) {
        double cp[3 * 3];
        memcpy(cp + 3 * sk_tri_index(1, 0, 0), P[tri[t][0]], sizeof P[0]);
        memcpy(cp + 3 * sk_tri_index(1, 1, 0), P[tri[t][1]], sizeof P[0]);
        memcpy(cp + 3 * sk_tri_index(1, 0, 1), P[tri[t][2]], sizeof P[0]);
        uint32_t ids[3] = {(uint32_t)tri[t][0], (uint32_t)tri[t][1], (uint32_t)tri[t][2]};
        size_t k;
        assert_int_equal(sk_patch_set_add(&lin, SK_PATCH_TRIANGLE, 1, 0, cp, ids, &k, NULL), SK_OK);
        assert_int_equal(sk_patch_elevate(&lin, k, 4, 0, &p, NULL), SK_OK);
    }
    sk_patch_set_free(&lin);
    sk_export_opts o = {.timestamp = "2026-01-02T03:04:05",
                        .split_triangles = true};
    sk_export_stats st;
    const char *path = skt_tmp_path("tetra.igs");
    assert_int_equal(sk_export_iges(path, &p, &o, &st, NULL), SK_OK);
    size_t size;
    char *text = skt_read_file(path, &size);
    int form = -1;
    assert_true(st.solid);
    assert_int_equal(st.faces, 12);
    assert_int_equal(st.vertices, 4 + 6 + 4);  /* corners, edge midpoints, centroids */
    assert_int_equal(st.edges, 12 + 12);       /* half edges of the mesh edges, inner edges */
    assert_int_equal(count_entities(text, 186, NULL), 1);
    assert_int_equal(count_entities(text, 514, &form), 1);
    assert_int_equal(form, 1); /* closed shell */
    assert_int_equal(count_entities(text, 110, NULL), 12 * 4);
    free(text);
    path = skt_tmp_path("tetra.step");
    assert_int_equal(sk_export_step(path, &p, &o, &st, NULL), SK_OK);
    sk_patch_set_free(&p);
    text = skt_read_file(path, &size);
    assert_true(st.solid);
    assert_int_equal(count(text, "MANIFOLD_SOLID_BREP("), 1);
    assert_int_equal(count(text, "CLOSED_SHELL("), 1);
    assert_int_equal(count(text, "ADVANCED_BREP_SHAPE_REPRESENTATION("), 1);
    assert_int_equal(count(text, "SHELL_BASED_SURFACE_MODEL("), 0);
    free(text);
}

static void given_patches_when_step_written_then_faces_share_edges(void **state)
{
    (void)state;
    sk_patch_set p = {0};
    sample_patches(&p);
    sk_export_opts o = {.timestamp = "2026-01-02T03:04:05",
                        .split_triangles = true};
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

static void given_reals_when_formatted_then_shortest_exact_with_a_point(void **state)
{
    (void)state;
    const double special[] = {1.0, 100.0, 1e-7, 0.1, 0.3, 0.30000000000000004, 1e15, 1e16, 1e17,
                              999999999999999.0, 123456789012345678.0, 1e300, -2.5e-300,
                              DBL_MAX, DBL_MIN, 5e-324, -1.5e-310, 2.0 / 3.0, -3.141592653589793};
    uint64_t seed = 12345;
    char a[32], b[32];
    assert_string_equal(sk__fmt_real(a, 0.0), "0.");
    assert_string_equal(sk__fmt_real(a, -0.0), "0.");
    assert_string_equal(sk__fmt_real(a, 100.0), "1.E+02");
    assert_string_equal(sk__fmt_real(a, 0.5), "0.5");
    for (int i = 0; i < 200000; ++i) {
        double x;
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        uint32_t r = (uint32_t)(seed >> 33);
        if (i < (int)(sizeof special / sizeof special[0]))
            x = special[i];
        else if (i % 3 == 0) /* short decimals */
            x = (double)(r % 100000) / pow(10.0, (double)(r % 13));
        else /* full-precision values over a wide range of exponents */
            x = ldexp((double)r / 4294967296.0 * 3.0 - 1.5, (int)(r % 400) - 200);
        skt_cad_real_ref(b, x);
        sk__fmt_real(a, x);
        if (strcmp(a, b))
            fail_msg("%.17g: %s, shortest is %s", x, a, b);
        assert_true(strtod(a, NULL) == x);
    }
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
        cmocka_unit_test(given_patches_when_iges_written_then_faces_form_a_brep_with_shared_edges),
        cmocka_unit_test(given_closed_patches_when_iges_written_then_a_solid),
        cmocka_unit_test(given_a_collapsed_side_when_iges_written_then_a_face_without_that_edge),
        cmocka_unit_test(given_triangles_when_written_then_one_face_each_and_points_shared),
        cmocka_unit_test(given_a_progress_callback_when_writing_then_fractions_to_one_and_cancel),
        cmocka_unit_test(given_reals_when_formatted_then_shortest_exact_with_a_point),
        cmocka_unit_test(given_patches_when_step_written_then_faces_share_edges),
        cmocka_unit_test(given_patches_when_obj_freeform_written_then_one_surf_per_tensor_patch),
        cmocka_unit_test(given_bad_arguments_then_writers_fail_and_leave_no_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
