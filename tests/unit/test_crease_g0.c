/* The G0 construction at creases (docs/creases.md): the crease edges stay patch boundaries shared
 * by both sides (gap at rounding), the normal jumps across a cube edge by 90 degrees, the surface
 * is G1 to rounding across every other edge, interpolates every vertex and each sector's normal
 * at its corners; fandisk needs no parity split any more; a roof (a fold from boundary to
 * boundary) keeps its fold; a surface without creases is the same as with detection off. */
#include "testutil.h"
#include "surfkit/smooth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct g0_result {
    size_t g0_creases, config_creases;
    sk_continuity_report r;
    double diag;
    double max_corner_normal_err_deg; /* patch normal vs s->corner_normals at every corner */
    double min_sector_angle_deg;      /* angle between the two normals at a crease-edge end */
} g0_result;

static double angle_deg(const double *a, const double *b)
{
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                 a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * 180.0 / M_PI;
}

static g0_result build_and_check(const sk_mesh *m, const sk_smooth_opts *o)
{
    g0_result g;
    memset(&g, 0, sizeof g);
    sk_smooth *s = NULL;
    sk_error err = {0};
    assert_int_equal(sk_smooth_build(m, o, &s, &err), SK_OK);
    sk_continuity_opts co = {.intersection_tess = (unsigned)-1};
    assert_int_equal(sk_smooth_continuity(s, &co, &g.r, &err), SK_OK);
    const sk_mesh *c = s->config;
    g.diag = sk_mesh_diagonal(c);
    g.min_sector_angle_deg = 180.0;
    if (s->crease_edge) {
        assert_non_null(s->corner_normals);
        for (uint32_t e = 0; e < sk_num_edges(c); ++e) {
            if (!s->crease_edge[e])
                continue;
            g.config_creases++;
            /* a crease edge is an interior edge of config (never deleted) */
            assert_true(c->h_face[2 * e] != SK_INVALID && c->h_face[2 * e + 1] != SK_INVALID);
            /* the two sides' normals at each end */
            for (uint32_t k = 0; k < 2; ++k) {
                uint32_t h = 2 * e + k, other = c->h_next[h ^ 1u]; /* both leave from(h) */
                assert_int_equal(sk_from(c, other), sk_from(c, h));
                g.min_sector_angle_deg =
                    fmin(g.min_sector_angle_deg,
                         angle_deg(s->corner_normals + 3 * (size_t)h,
                                   s->corner_normals + 3 * (size_t)other));
            }
        }
    }
    g.g0_creases = g.r.crease_edges;
    /* every corner of every patch: the vertex and its sector's normal, interpolated */
    for (size_t p = 0; p < s->surface.count; ++p) {
        const sk_patch *pa = &s->surface.patches[p];
        uint32_t h = c->f_halfedge[p];
        for (unsigned i = 0; i < sk_patch_num_corners(pa); ++i, h = c->h_next[h]) {
            static const double tu[4] = {0, 1, 1, 0}, tv[4] = {0, 0, 1, 1};
            double u = pa->kind == SK_PATCH_TRIANGLE ? (i == 1) : tu[i];
            double v = pa->kind == SK_PATCH_TRIANGLE ? (i == 2) : tv[i];
            double x[3], n[3];
            sk_patch_eval(&s->surface, p, u, v, x, NULL, NULL, n);
            const double *V = c->positions + 3 * (size_t)sk_from(c, h);
            for (int k = 0; k < 3; ++k)
                assert_true(fabs(x[k] - V[k]) <= 1e-12 * g.diag);
            const double *N = s->corner_normals ? s->corner_normals + 3 * (size_t)h
                                                : s->normals + 3 * (size_t)sk_from(c, h);
            g.max_corner_normal_err_deg = fmax(g.max_corner_normal_err_deg, angle_deg(n, N));
        }
    }
    sk_smooth_destroy(&s);
    return g;
}

static void test_cube(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("cube.off"));
    g0_result g = build_and_check(m, NULL);
    assert_int_equal(g.g0_creases, 12);
    assert_int_equal(g.config_creases, 12);
    /* G0 across the cube edges: the sides meet exactly and the normal turns by 90 degrees
     * all along each edge; the face diagonals are G1 (the faces stay flat) */
    assert_true(g.r.max_crease_gap <= 1e-12 * g.diag);
    assert_true(fabs(g.r.max_crease_jump_deg - 90.0) < 1e-9);
    assert_true(fabs(g.r.min_crease_jump_deg - 90.0) < 1e-9);
    assert_true(fabs(g.min_sector_angle_deg - 90.0) < 1e-9);
    assert_true(g.r.max_normal_jump_deg < 1e-7);
    assert_true(g.r.max_gap <= 1e-12 * g.diag);
    assert_true(g.r.max_vertex_error <= 1e-12 * g.diag);
    assert_true(g.r.max_normal_error_deg < 1e-7);
    assert_true(g.max_corner_normal_err_deg < 1e-7);
    assert_int_equal(g.r.singular_patches, 0);
    /* the faces are flat: no patch leaves its face */
    assert_true(g.r.max_overshoot < 1e-12);
    /* without creases the cube is one smooth blob: G1 across its edges */
    sk_smooth_opts o = {.crease_angle_deg = -1.0};
    g0_result b = build_and_check(m, &o);
    assert_int_equal(b.g0_creases, 0);
    assert_true(b.r.max_normal_jump_deg < 1e-7);
    assert_true(b.r.max_overshoot > 0.1);
    sk_mesh_destroy(&m);
}

/* fandisk: its sharp feature lines as G0 creases; odd vertex count, but the crease vertices need
 * no parity, so no split is needed (it failed with SK_ERR_TOPOLOGY without --allow-split). */
static void test_fandisk(void **state)
{
    (void)state;
    if (getenv("SK_TEST_QUICK"))
        skip(); /* 12k faces: a few seconds in release, minutes under ASan */
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("fandisk.off"));
    size_t ne = sk_num_edges(m);
    g0_result g = build_and_check(m, NULL);
    assert_true(g.g0_creases > ne / 50); /* 706 of 19419 */
    assert_true(g.r.max_normal_jump_deg < 1e-7);
    assert_true(g.r.max_crease_gap <= 1e-12 * g.diag);
    assert_true(g.r.max_crease_jump_deg > 60.0);
    assert_true(g.r.max_vertex_error <= 1e-12 * g.diag);
    assert_true(g.r.max_normal_error_deg < 1e-7);
    assert_true(g.max_corner_normal_err_deg < 1e-7);
    assert_int_equal(g.r.singular_patches, 0);
    assert_true(g.r.max_overshoot <= 0.5);
    sk_mesh_destroy(&m);
}

/* mech-holes-shark: a few sharp edges; the lines the construction cannot follow are dropped,
 * the rest are G0; everything else G1 and interpolating */
static void test_mech(void **state)
{
    (void)state;
    if (getenv("SK_TEST_QUICK"))
        skip();
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("mech-holes-shark.off"));
    g0_result g = build_and_check(m, NULL);
    assert_true(g.g0_creases >= 3);
    assert_true(g.r.max_normal_jump_deg < 1e-7);
    assert_true(g.r.max_crease_gap <= 1e-12 * g.diag);
    assert_true(g.r.max_vertex_error <= 1e-12 * g.diag);
    assert_true(g.r.max_normal_error_deg < 1e-7);
    assert_true(g.max_corner_normal_err_deg < 1e-7);
    sk_mesh_destroy(&m);
}

/* a roof: an n x n grid folded along its middle column by 2 * slope; the fold runs from boundary
 * to boundary (crease vertices on the boundary: a free boundary end and a fixed crease end) */
static sk_mesh *roof(int n, double slope)
{
    size_t nv = (size_t)(n + 1) * (size_t)(n + 1), nf = 2 * (size_t)n * (size_t)n, f = 0, k = 0;
    double *pos = malloc(nv * 3 * sizeof(double));
    uint32_t *off = malloc((nf + 1) * sizeof(uint32_t)), *idx = malloc(3 * nf * sizeof(uint32_t));
    assert_true(pos && off && idx);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            double *p = pos + 3 * ((size_t)j * (size_t)(n + 1) + (size_t)i);
            p[0] = i;
            p[1] = j + 0.1 * sin(i * 1.7); /* not a plain grid: no symmetric ties */
            p[2] = -slope * fabs((double)(i - n / 2));
        }
    off[0] = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)(n + 1) + 1,
                     d = a + (uint32_t)(n + 1);
            /* diagonals leaning away from the fold column on either side */
            uint32_t t[2][3] = {{a, b, c}, {a, c, d}}, l[2][3] = {{a, b, d}, {b, c, d}};
            for (int q = 0; q < 2; ++q) {
                const uint32_t *x = i < n / 2 ? l[q] : t[q];
                idx[k++] = x[0], idx[k++] = x[1], idx[k++] = x[2];
                off[++f] = (uint32_t)k;
            }
        }
    sk_mesh *m = NULL;
    sk_error err = {0};
    assert_int_equal(sk_mesh_from_faces(nv, pos, f, off, idx, &m, &err), SK_OK);
    free(pos);
    free(off);
    free(idx);
    return m;
}

static void test_roof(void **state)
{
    (void)state;
    sk_mesh *m = roof(8, 1.0); /* faces at +-45 degrees: a 90-degree fold */
    g0_result g = build_and_check(m, NULL);
    assert_int_equal(g.g0_creases, 8);
    assert_true(g.r.max_normal_jump_deg < 1e-7);
    assert_true(fabs(g.r.max_crease_jump_deg - 90.0) < 1e-6);
    assert_true(fabs(g.r.min_crease_jump_deg - 90.0) < 1e-6);
    assert_true(g.r.max_crease_gap <= 1e-12 * g.diag);
    assert_true(g.r.max_vertex_error <= 1e-12 * g.diag);
    assert_true(g.max_corner_normal_err_deg < 1e-7);
    assert_int_equal(g.r.singular_patches, 0);
    sk_mesh_destroy(&m);
}

/* no crease detected: the same surface, bit for bit, as with the detection off */
static void test_no_creases_same(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("sphere.off"));
    sk_smooth *a = NULL, *b = NULL;
    sk_error err = {0};
    sk_smooth_opts off = {.crease_angle_deg = -1.0};
    assert_int_equal(sk_smooth_build(m, NULL, &a, &err), SK_OK);
    assert_int_equal(sk_smooth_build(m, &off, &b, &err), SK_OK);
    assert_int_equal(a->num_creases, 0);
    assert_null(a->crease_edge);
    assert_null(a->corner_normals);
    assert_int_equal(a->surface.count, b->surface.count);
    assert_int_equal(a->surface.num_points, b->surface.num_points);
    assert_memory_equal(a->surface.points, b->surface.points,
                        3 * a->surface.num_points * sizeof(double));
    sk_smooth_destroy(&a);
    sk_smooth_destroy(&b);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube),
        cmocka_unit_test(test_roof),
        cmocka_unit_test(test_no_creases_same),
        cmocka_unit_test(test_fandisk),
        cmocka_unit_test(test_mech),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
