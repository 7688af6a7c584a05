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

static bool interior(const sk_mesh *m, uint32_t e)
{
    return m->h_face[2 * e] != SK_INVALID && m->h_face[2 * e + 1] != SK_INVALID;
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

/* a strip of n quads along x by turns + 1 panels across (split into triangles); its profile across
 * is a polyline of unit segments that turns by turns_deg[j] at its j-th inner line */
static sk_mesh *profile_strip(int n, int turns, const double *turns_deg)
{
    int k = turns + 1, nv = (n + 1) * (k + 1);
    double *pos = malloc((size_t)nv * 3 * sizeof(double));
    uint32_t *off = malloc((size_t)(2 * n * k + 1) * sizeof(uint32_t));
    uint32_t *idx = malloc((size_t)(6 * n * k) * sizeof(uint32_t));
    double y[16], z[16], dir = 0.0;
    assert_true(pos && off && idx && k < 16);
    y[0] = z[0] = 0.0;
    for (int j = 0; j < k; ++j) {
        if (j > 0)
            dir += turns_deg[j - 1] * 3.14159265358979323846 / 180.0;
        y[j + 1] = y[j] + cos(dir);
        z[j + 1] = z[j] + sin(dir);
    }
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= k; ++j) {
            double *p = pos + 3 * (i * (k + 1) + j);
            p[0] = i, p[1] = y[j], p[2] = z[j];
        }
    size_t q = 0, f = 0;
    off[0] = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < k; ++j) {
            uint32_t a = (uint32_t)(i * (k + 1) + j), b = a + (uint32_t)(k + 1), c = b + 1, d = a + 1;
            idx[q++] = a, idx[q++] = b, idx[q++] = c, off[++f] = (uint32_t)q;
            idx[q++] = a, idx[q++] = c, idx[q++] = d, off[++f] = (uint32_t)q;
        }
    sk_mesh *m = NULL;
    sk_error err = {0};
    assert_int_equal(sk_mesh_from_faces((size_t)nv, pos, f, off, idx, &m, &err), SK_OK);
    free(pos);
    free(off);
    free(idx);
    return m;
}

/* the smooth sides (step 3): a 60-degree fold between flat sides is a crease line; the same fold
 * inside a band bent by 35 degrees at every line (a thin part of a coarse scan: each side's
 * smooth region bends by far more than A / 2 and more than a third of the jump) is not, though
 * its dihedral and side normals pass steps 1-2 */
static void test_smooth_sides(void **state)
{
    (void)state;
    const double flat[4] = {0.0, 60.0, 0.0, 0.0}, bent[4] = {35.0, 60.0, 35.0, 35.0};
    sk_mesh *m = profile_strip(8, 4, flat);
    uint8_t *c = NULL;
    assert_int_equal(creases(m, 40.0, &c), 8);
    for (uint32_t e = 0; e < sk_num_edges(m); ++e)
        assert_int_equal(c[e], interior(m, e) && dihedral_deg(m, e) > 50.0);
    free(c);
    sk_mesh_destroy(&m);
    m = profile_strip(8, 4, bent);
    size_t fold = 0;
    for (uint32_t e = 0; e < sk_num_edges(m); ++e)
        fold += interior(m, e) && dihedral_deg(m, e) > 50.0;
    assert_int_equal(fold, 8);
    assert_int_equal(creases(m, 40.0, NULL), 0);
    /* at 30 degrees the bends are sharp edges themselves: the smooth regions stop there, every
     * panel is flat, and the fold is a crease line again */
    uint8_t *c30 = NULL;
    assert_true(creases(m, 30.0, &c30) >= 8);
    for (uint32_t e = 0; e < sk_num_edges(m); ++e)
        if (interior(m, e) && dihedral_deg(m, e) > 50.0)
            assert_int_equal(c30[e], 1);
    free(c30);
    sk_mesh_destroy(&m);
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
    /* all of its 706 (as before the smooth-side rule), nearly every edge sharper than 60 degrees
     * among them: the feature lines are kept whole */
    uint8_t *c = NULL;
    size_t sharp = 0, missed = 0;
    assert_true(creases(m, 40.0, &c) >= 700);
    for (uint32_t e = 0; e < ne; ++e)
        if (interior(m, e) && dihedral_deg(m, e) > 60.0) {
            sharp++;
            missed += !c[e];
        }
    assert_true(missed * 100 < sharp); /* 4 of 699, as before the smooth-side rule */
    free(c);
    sk_mesh_destroy(&m);
    /* mech-holes-shark: the line 2880-9-3534-918 (a plane meeting a fan of slivers: its sides
     * bend more than A / 2, by less than a third of the jump) */
    m = skt_read_mesh(skt_shared_mesh("mech-holes-shark.off"));
    assert_true(creases(m, 40.0, &c) >= 3);
    for (uint32_t e = 0; e < sk_num_edges(m); ++e) {
        uint32_t a = sk_from(m, 2 * e), b = sk_to(m, 2 * e);
        if ((a == 9 && b == 2880) || (a == 2880 && b == 9))
            assert_int_equal(c[e], 1);
    }
    free(c);
    sk_mesh_destroy(&m);
    /* organic scans: under 0.5% of the edges (the target; the thin parts' bands of sharp
     * edges are not creases: cow 5.4%, lion-head 1.4%, pig 2.4%, elephant 4.8% before the
     * smooth-side rule), none on a sphere */
    const char *organic[] = {"cow.off", "lion-head.off", "pig.off", "elephant.off"};
    for (size_t i = 0; i < sizeof organic / sizeof *organic; ++i) {
        m = skt_read_mesh(skt_shared_mesh(organic[i]));
        assert_true(creases(m, 0.0, NULL) * 200 < sk_num_edges(m));
        sk_mesh_destroy(&m);
    }
    m = skt_read_mesh(skt_shared_mesh("sphere.off"));
    assert_int_equal(creases(m, 0.0, NULL), 0);
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

/* true when edge a-b of m is flagged in c */
static bool edge_flagged(const sk_mesh *m, const uint8_t *c, uint32_t a, uint32_t b)
{
    for (uint32_t e = 0; e < sk_num_edges(m); ++e) {
        uint32_t x = sk_from(m, 2 * e), y = sk_to(m, 2 * e);
        if ((x == a && y == b) || (x == b && y == a))
            return c[e] != 0;
    }
    fail_msg("no edge %u-%u", a, b);
    return false;
}

/* Given the cow's tail root, where the plain rules found a cluster of seven crease edges around
 * vertex 43 that closes three faces (956-43-961, 970-961-43, 43-2384-970: every edge sharp), when
 * the creases are detected, then each such face keeps only its sharpest edge, the fold's hinges
 * 43-956 (160 degrees between the face normals) and 43-2384 (113 degrees) stay as a line of two
 * edges, and the edges of 58-59 degrees across the fold (43-961, 43-970, 961-970, 970-2384) and
 * 956-961 are gone. On every shared mesh no face has all its edges creases. */
static void test_fold_hinges(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("cow.off"));
    uint8_t *c = NULL;
    creases(m, 0.0, &c);
    assert_true(edge_flagged(m, c, 43, 956));
    assert_true(edge_flagged(m, c, 43, 2384));
    const uint32_t gone[][2] = {{43, 961}, {43, 970}, {961, 970}, {970, 2384}, {956, 961}};
    for (size_t i = 0; i < sizeof gone / sizeof *gone; ++i)
        assert_false(edge_flagged(m, c, gone[i][0], gone[i][1]));
    free(c);
    sk_mesh_destroy(&m);
    const char *names[] = {"cow.off",       "lion-head.off", "pig.off",  "elephant.off",
                           "fandisk.off",   "cube.off",      "mech-holes-shark.off",
                           "icosahedron.off", "three_peaks.off"};
    for (size_t i = 0; i < sizeof names / sizeof *names; ++i) {
        m = skt_read_mesh(skt_shared_mesh(names[i]));
        creases(m, 0.0, &c);
        for (uint32_t f = 0; f < m->num_faces; ++f) {
            uint32_t h0 = m->f_halfedge[f], h = h0;
            bool all = true;
            do {
                all = all && c[sk_edge(h)];
                h = m->h_next[h];
            } while (h != h0);
            if (all)
                fail_msg("%s: face %u has only crease edges", names[i], f);
        }
        free(c);
        sk_mesh_destroy(&m);
    }
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
        cmocka_unit_test(test_smooth_sides),
        cmocka_unit_test(test_meshes),
        cmocka_unit_test(test_fold_hinges),
        cmocka_unit_test(test_smooth_reports),
        cmocka_unit_test(test_bad_angle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
