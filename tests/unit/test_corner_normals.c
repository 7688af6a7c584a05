/* Per-corner normals (OBJ vn per corner) in the half-edge mesh and in the smooth surface: given a
 * cube with one vn per face side, when read, copied, compacted and written back, then every
 * corner keeps its normal bit for bit; given a shallow roof (a fold of 20 degrees, below the
 * crease angle) whose file gives each side its own normal, when smoothed, then the fold is a G0
 * crease with the file's normals at its corners, G1 elsewhere; with the normals estimated it is
 * no crease. */
#include "testutil.h"
#include "surfkit/io.h"
#include "surfkit/smooth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static sk_mesh *read_obj(const char *text)
{
    sk_soup *s = NULL;
    sk_error err;
    sk_read_opts ro = {SK_FORMAT_OBJ};
    if (sk_soup_read_memory(text, strlen(text), "t.obj", &ro, &s, &err))
        fail_msg("%s", err.message);
    sk_mesh *m = NULL;
    if (sk_mesh_from_soup(s, &m, &err))
        fail_msg("%s", err.message);
    sk_soup_destroy(&s);
    return m;
}

/* the file normal of corner h (at from(h) in face(h)) */
static const double *corner_normal(const sk_mesh *m, uint32_t h)
{
    assert_non_null(m->h_wedge_normal);
    assert_int_not_equal(m->h_wedge_normal[h], SK_INVALID);
    return m->wedge_normals + 3 * (size_t)m->h_wedge_normal[h];
}

static const char *cube_obj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 1 0 0\nvn 0 1 0\nvn -1 0 0\n"
    "f 1//1 3//1 2//1\nf 1//1 4//1 3//1\nf 5//2 6//2 7//2\nf 5//2 7//2 8//2\n"
    "f 1//3 2//3 6//3\nf 1//3 6//3 5//3\nf 2//4 3//4 7//4\nf 2//4 7//4 6//4\n"
    "f 3//5 4//5 8//5\nf 3//5 8//5 7//5\nf 4//6 1//6 5//6\nf 4//6 5//6 8//6\n";

/* every corner's normal is its face's (the file gives one per face side) */
static void assert_face_normals(const sk_mesh *m)
{
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        if (m->f_deleted[f])
            continue;
        uint32_t h0 = m->f_halfedge[f], h = h0;
        const double *a = m->positions + 3 * (size_t)sk_from(m, h);
        const double *b = m->positions + 3 * (size_t)sk_to(m, h);
        const double *c = m->positions + 3 * (size_t)sk_to(m, m->h_next[h]);
        double x[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double y[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2],
                       x[0] * y[1] - x[1] * y[0]};
        do {
            const double *N = corner_normal(m, h);
            for (int k = 0; k < 3; ++k)
                assert_true(fabs(N[k] - n[k] / sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])) <
                            1e-15);
            h = m->h_next[h];
        } while (h != h0);
    }
}

static void test_cube_round_trip(void **state)
{
    (void)state;
    sk_mesh *m = read_obj(cube_obj);
    assert_int_equal(m->num_wedge_normals, 6);
    assert_face_normals(m);
    /* a copy keeps them */
    sk_mesh *c = NULL;
    assert_int_equal(sk_mesh_copy(m, &c, NULL), SK_OK);
    assert_memory_equal(c->h_wedge_normal, m->h_wedge_normal, m->num_halfedges * sizeof(uint32_t));
    assert_face_normals(c);
    sk_mesh_destroy(&c);
    /* mesh -> soup -> OBJ -> soup -> mesh: the same normal at every corner, bit for bit */
    sk_soup *s = NULL;
    assert_int_equal(sk_mesh_to_soup(m, &s, NULL), SK_OK);
    assert_non_null(s->corner_normal);
    sk_write_opts wo = {0};
    wo.format = SK_FORMAT_OBJ;
    void *data = NULL;
    size_t size = 0;
    sk_error err;
    assert_int_equal(sk_soup_write_memory(s, &wo, &data, &size, &err), SK_OK);
    char *text = malloc(size + 1);
    assert_non_null(text);
    memcpy(text, data, size);
    text[size] = 0;
    free(data);
    sk_mesh *m2 = read_obj(text);
    free(text);
    assert_int_equal(m2->num_faces, m->num_faces);
    for (uint32_t f = 0; f < m->num_faces; ++f) {
        uint32_t h = m->f_halfedge[f], h2 = m2->f_halfedge[f];
        for (int k = 0; k < 3; ++k, h = m->h_next[h], h2 = m2->h_next[h2]) {
            assert_int_equal(sk_from(m, h), sk_from(m2, h2));
            assert_memory_equal(corner_normal(m, h), corner_normal(m2, h2), 3 * sizeof(double));
        }
    }
    sk_mesh_destroy(&m2);
    sk_soup_destroy(&s);
    sk_mesh_destroy(&m);
}

/* an n x n grid folded along its middle column by fold_deg, each side's vertices with that side's
 * normal (the fold column has both), as OBJ text */
static char *roof_obj(int n, double fold_deg)
{
    double t = tan(fold_deg * M_PI / 360.0), c = cos(fold_deg * M_PI / 360.0);
    size_t cap = 200000, len = 0;
    char *b = malloc(cap);
    assert_non_null(b);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            len += (size_t)snprintf(b + len, cap - len, "v %d %.17g %.17g\n", i,
                                    j + 0.1 * sin(i * 1.7), -t * fabs((double)(i - n / 2)));
    /* z = -t |x - n/2|: the left side's normal (-t, 0, 1) c, the right side's (t, 0, 1) c */
    len += (size_t)snprintf(b + len, cap - len, "vn %.17g 0 %.17g\nvn %.17g 0 %.17g\n", -t * c, c,
                            t * c, c);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int a = j * (n + 1) + i + 1, bb = a + 1, cc = a + n + 2, d = a + n + 1;
            int side = i < n / 2 ? 1 : 2;
            if (i < n / 2)
                len += (size_t)snprintf(b + len, cap - len, "f %d//%d %d//%d %d//%d\nf %d//%d %d//%d %d//%d\n",
                                        a, side, bb, side, d, side, bb, side, cc, side, d, side);
            else
                len += (size_t)snprintf(b + len, cap - len, "f %d//%d %d//%d %d//%d\nf %d//%d %d//%d %d//%d\n",
                                        a, side, bb, side, cc, side, a, side, cc, side, d, side);
        }
    assert_true(len < cap);
    return b;
}

static double angle_deg(const double *a, const double *b)
{
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                 a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * 180.0 / M_PI;
}

static void test_roof_from_file_normals(void **state)
{
    (void)state;
    char *text = roof_obj(8, 20.0);
    sk_mesh *m = read_obj(text);
    free(text);
    /* the fold's dihedral (20 degrees) is below the crease angle: no crease by detection */
    uint8_t *flags = malloc(sk_num_edges(m));
    size_t n = 99;
    assert_non_null(flags);
    assert_int_equal(sk_mesh_crease_edges(m, NULL, flags, &n, NULL), SK_OK);
    assert_int_equal(n, 0);
    free(flags);
    sk_smooth *s = NULL;
    sk_error err = {0};
    assert_int_equal(sk_smooth_build(m, NULL, &s, &err), SK_OK);
    assert_int_equal(s->num_creases, 8); /* the fold column's 8 edges, from the file's normals */
    sk_continuity_report r;
    sk_continuity_opts co = {.intersection_tess = (unsigned)-1};
    assert_int_equal(sk_smooth_continuity(s, &co, &r, &err), SK_OK);
    assert_int_equal(r.crease_edges, 8);
    assert_true(r.max_normal_jump_deg < 1e-7);
    assert_true(fabs(r.max_crease_jump_deg - 20.0) < 1e-6);
    assert_true(fabs(r.min_crease_jump_deg - 20.0) < 1e-6);
    assert_true(r.max_crease_gap < 1e-12);
    assert_true(r.max_vertex_error < 1e-12);
    assert_true(r.max_normal_error_deg < 1e-7);
    /* the corner normals on the fold are the file's: one side's or the other's */
    const sk_mesh *c = s->config;
    double left[3] = {-tan(M_PI / 18) * cos(M_PI / 18), 0, cos(M_PI / 18)};
    double right[3] = {-left[0], 0, left[2]};
    for (uint32_t e = 0; e < sk_num_edges(c); ++e)
        if (s->crease_edge[e])
            for (uint32_t k = 0; k < 2; ++k) {
                const double *N = s->corner_normals + 3 * (size_t)(2 * e + k);
                assert_true(fmin(angle_deg(N, left), angle_deg(N, right)) < 1e-12);
            }
    sk_smooth_destroy(&s);
    /* estimated normals: the file's are not used, the fold is smooth */
    sk_smooth_opts o = {.estimate_normals = true};
    assert_int_equal(sk_smooth_build(m, &o, &s, &err), SK_OK);
    assert_int_equal(s->num_creases, 0);
    assert_null(s->crease_edge);
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube_round_trip),
        cmocka_unit_test(test_roof_from_file_normals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
