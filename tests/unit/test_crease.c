/* Crease detection (sk_mesh_crease_edges): the cube's 12 edges and none of its face diagonals, a
 * folded strip's fold at angles below the fold and nothing above it, none on a smooth scan, the
 * counts fall as the angle grows, the smooth surface reports them, bad angles refused. */
#include "testutil.h"
#include "surfkit/smooth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double dihedral_deg(const sk_mesh *m, uint32_t e)
{
    double n[2][3];
    for (int s = 0; s < 2; ++s) {
        uint32_t h = m->f_halfedge[m->h_face[2 * e + (uint32_t)s]];
        const double *a = m->positions + 3 * (size_t)sk_from(m, h);
        const double *b = m->positions + 3 * (size_t)sk_to(m, h);
        const double *c = m->positions + 3 * (size_t)sk_to(m, m->h_next[h]);
        double x[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double y[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        n[s][0] = x[1] * y[2] - x[2] * y[1];
        n[s][1] = x[2] * y[0] - x[0] * y[2];
        n[s][2] = x[0] * y[1] - x[1] * y[0];
    }
    double d = n[0][0] * n[1][0] + n[0][1] * n[1][1] + n[0][2] * n[1][2];
    double l = sqrt((n[0][0] * n[0][0] + n[0][1] * n[0][1] + n[0][2] * n[0][2]) *
                    (n[1][0] * n[1][0] + n[1][1] * n[1][1] + n[1][2] * n[1][2]));
    return acos(fmax(-1.0, fmin(1.0, d / l))) * 180.0 / 3.14159265358979323846;
}

static size_t creases(const sk_mesh *m, double angle, uint8_t **flags)
{
    size_t ne = sk_num_edges(m), n = 12345;
    uint8_t *c = malloc(ne);
    sk_crease_opts o = {.angle_deg = angle};
    sk_error err = {0};
    assert_non_null(c);
    assert_int_equal(sk_mesh_crease_edges(m, &o, c, &n, &err), SK_OK);
    size_t k = 0;
    for (size_t e = 0; e < ne; ++e)
        k += c[e];
    assert_int_equal(k, n);
    if (flags)
        *flags = c;
    else
        free(c);
    return n;
}

static void test_cube(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("cube.off"));
    uint8_t *c = NULL;
    assert_int_equal(creases(m, 0.0, &c), 12);
    for (uint32_t e = 0; e < sk_num_edges(m); ++e) {
        double d = dihedral_deg(m, e);
        assert_int_equal(c[e], d > 45.0); /* 90 degrees: a cube edge; 0: a face diagonal */
    }
    free(c);
    /* (at 89 degrees some are lost: every triangle of the cube touches two of its edges, so the
     * side normals mix two faces) */
    assert_int_equal(creases(m, 60.0, NULL), 12);
    assert_int_equal(creases(m, 91.0, NULL), 0);
    sk_mesh_destroy(&m);
}

/* a strip of 2 x n quads (split into triangles) folded by fold_deg along its middle line */
static sk_mesh *folded_strip(int n, double fold_deg)
{
    double t = fold_deg * 3.14159265358979323846 / 180.0;
    int nv = 3 * (n + 1);
    double *pos = malloc((size_t)nv * 3 * sizeof(double));
    uint32_t *off = malloc((size_t)(4 * n + 1) * sizeof(uint32_t));
    uint32_t *idx = malloc((size_t)(12 * n) * sizeof(uint32_t));
    for (int i = 0; i <= n; ++i) {
        double *p = pos + 9 * i;
        p[0] = i, p[1] = -cos(t), p[2] = sin(t); /* side 0, folded up by the angle */
        p[3] = i, p[4] = 0.0, p[5] = 0.0;        /* the fold line */
        p[6] = i, p[7] = 1.0, p[8] = 0.0;        /* side 1, flat */
    }
    size_t k = 0, f = 0;
    off[0] = 0;
    for (int i = 0; i < n; ++i)
        for (int r = 0; r < 2; ++r) {
            uint32_t a = (uint32_t)(3 * i + r), b = a + 3, c = a + 4, d = a + 1;
            idx[k++] = a, idx[k++] = b, idx[k++] = c, off[++f] = (uint32_t)k;
            idx[k++] = a, idx[k++] = c, idx[k++] = d, off[++f] = (uint32_t)k;
        }
    sk_mesh *m = NULL;
    sk_error err = {0};
    assert_int_equal(sk_mesh_from_faces((size_t)nv, pos, f, off, idx, &m, &err), SK_OK);
    free(pos);
    free(off);
    free(idx);
    return m;
}

static void test_fold(void **state)
{
    (void)state;
    sk_mesh *m = folded_strip(6, 60.0);
    uint8_t *c = NULL;
    /* the fold line holds 6 edges; its interior ones are the only edges with a dihedral of 60 */
    assert_int_equal(creases(m, 40.0, &c), 6);
    for (uint32_t e = 0; e < sk_num_edges(m); ++e) {
        uint32_t a = sk_from(m, 2 * e), b = sk_to(m, 2 * e);
        assert_int_equal(c[e], a % 3 == 1 && b % 3 == 1);
    }
    free(c);
    assert_int_equal(creases(m, 59.0, NULL), 6);
    assert_int_equal(creases(m, 61.0, NULL), 0);
    sk_mesh_destroy(&m);
    /* folds of one or two edges are short pieces, not lines; three is a line */
    m = folded_strip(1, 60.0);
    assert_int_equal(creases(m, 40.0, NULL), 0);
    sk_mesh_destroy(&m);
    m = folded_strip(2, 60.0);
    assert_int_equal(creases(m, 40.0, NULL), 0);
    sk_mesh_destroy(&m);
    m = folded_strip(3, 60.0);
    assert_int_equal(creases(m, 40.0, NULL), 3);
    sk_mesh_destroy(&m);
}

static void test_meshes(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("fandisk.off"));
    size_t ne = sk_num_edges(m), c30 = creases(m, 30.0, NULL), c40 = creases(m, 40.0, NULL),
           c60 = creases(m, 60.0, NULL);
    assert_true(c30 >= c40 && c40 >= c60);
    /* fandisk: its sharp feature lines, a few percent of the edges, nearly all well above 60 */
    assert_true(c40 > ne / 50 && c40 < ne / 20);
    assert_true(c60 * 100 > c40 * 95);
    sk_mesh_destroy(&m);
    /* bunny00: a smooth scan, no crease; armadillo: under 0.5% of the edges (plain 1.55%) */
    if (!getenv("SK_TEST_QUICK")) {
        m = skt_read_mesh(skt_shared_mesh("bunny00.off"));
        assert_int_equal(creases(m, 0.0, NULL), 0);
        sk_mesh_destroy(&m);
        m = skt_read_mesh(skt_shared_mesh("armadillo.off"));
        assert_true(creases(m, 0.0, NULL) * 200 < sk_num_edges(m));
        sk_mesh_destroy(&m);
    }
    /* the smoothing and the line rule drop most of the plain threshold's edges on the cow */
    m = skt_read_mesh(skt_shared_mesh("cow.off"));
    size_t plain = 0;
    for (uint32_t e = 0; e < sk_num_edges(m); ++e)
        plain += dihedral_deg(m, e) >= 40.0;
    assert_true(creases(m, 40.0, NULL) < plain * 3 / 4);
    sk_mesh_destroy(&m);
}

static void test_smooth_reports(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("cube.off"));
    sk_smooth *s = NULL;
    sk_error err = {0};
    assert_int_equal(sk_smooth_build(m, NULL, &s, &err), SK_OK);
    assert_int_equal(s->num_creases, 12);
    for (size_t i = 0; i < s->num_creases; ++i)
        assert_true(s->creases[2 * i] != s->creases[2 * i + 1]);
    sk_smooth_destroy(&s);
    sk_smooth_opts o = {.crease_angle_deg = -1.0};
    assert_int_equal(sk_smooth_build(m, &o, &s, &err), SK_OK);
    assert_int_equal(s->num_creases, 0);
    assert_null(s->creases);
    sk_smooth_destroy(&s);
    sk_mesh_destroy(&m);
}

static void test_bad_angle(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("cube.off"));
    uint8_t c[64];
    sk_error err = {0};
    sk_crease_opts o = {.angle_deg = 180.0};
    assert_int_equal(sk_mesh_crease_edges(m, &o, c, NULL, &err), SK_ERR_ARG);
    o.angle_deg = -5.0;
    assert_int_equal(sk_mesh_crease_edges(m, &o, c, NULL, &err), SK_ERR_ARG);
    assert_int_equal(sk_mesh_crease_edges(m, NULL, NULL, NULL, &err), SK_ERR_ARG);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube),
        cmocka_unit_test(test_fold),
        cmocka_unit_test(test_meshes),
        cmocka_unit_test(test_smooth_reports),
        cmocka_unit_test(test_bad_angle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
