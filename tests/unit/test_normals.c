/* Vertex normal estimates: convergence slopes per Xu, Xu, Sun (Mathematics of Surfaces XI):
 * O(h^2) on regular rings (valence 6, and odd regular valence for mean/area), O(h) on irregular
 * rings for the averages and at valence 3 for all of them; the quadratic fit is O(h^2). */
#include "testutil.h"
#include "surfkit/analysis.h"

#include <math.h>
#include <string.h>

typedef double (*surf_fn)(double x, double y, double g[2]);

static double sphere(double x, double y, double g[2])
{
    double R = 2.0, z = sqrt(R * R - x * x - y * y);
    g[0] = -x / z, g[1] = -y / z;
    return z - R;
}

static double paraboloid(double x, double y, double g[2])
{
    g[0] = 4.0 * x, g[1] = 2.0 * y;
    return 2.0 * x * x + y * y;
}

/* normal error at the centre of a fan of n triangles around (x0, y0) with radius h */
static double fan_error(surf_fn f, double x0, double y0, int n, const double *theta, double h,
                        sk_normal_method method)
{
    double pos[3 * 16];
    uint32_t off[16], idx[3 * 16];
    double g[2];
    pos[0] = x0, pos[1] = y0, pos[2] = f(x0, y0, g);
    double exact[3] = {-g[0], -g[1], 1.0}, len = sqrt(exact[0] * exact[0] + exact[1] * exact[1] + 1);
    for (int k = 0; k < n; ++k) {
        double x = x0 + h * cos(theta[k]), y = y0 + h * sin(theta[k]), gg[2];
        pos[3 * (k + 1)] = x, pos[3 * (k + 1) + 1] = y, pos[3 * (k + 1) + 2] = f(x, y, gg);
        off[k] = (uint32_t)(3 * k);
        idx[3 * k] = 0, idx[3 * k + 1] = (uint32_t)(k + 1), idx[3 * k + 2] = (uint32_t)((k + 1) % n + 1);
    }
    off[n] = (uint32_t)(3 * n);
    sk_mesh *m = NULL;
    sk_error err = {0};
    assert_int_equal(sk_mesh_from_faces((size_t)n + 1, pos, (size_t)n, off, idx, &m, &err), SK_OK);
    double nrm[3 * 16];
    assert_int_equal(sk_mesh_vertex_normals(m, method, nrm, &err), SK_OK);
    sk_mesh_destroy(&m);
    double d = 0.0;
    for (int k = 0; k < 3; ++k)
        d += (nrm[k] - exact[k] / len) * (nrm[k] - exact[k] / len);
    return sqrt(d);
}

static double slope(surf_fn f, int n, const double *theta, sk_normal_method method)
{
    double x0 = 0.3, y0 = 0.2;
    double e1 = fan_error(f, x0, y0, n, theta, 1.0 / 64, method);
    double e2 = fan_error(f, x0, y0, n, theta, 1.0 / 1024, method);
    if (e2 < 1e-13) /* exact to rounding (e.g. a symmetric ring on a quadratic) */
        return 9.9;
    return log(e1 / e2) / log(16.0);
}

static void regular(int n, double *t)
{
    for (int k = 0; k < n; ++k)
        t[k] = 2.0 * M_PI * k / n;
}

static void irregular(int n, double *t)
{
    static const double jitter[8] = {0.0, 0.31, -0.22, 0.17, -0.35, 0.12, 0.27, -0.14};
    for (int k = 0; k < n; ++k)
        t[k] = 2.0 * M_PI * k / n + jitter[k % 8] * (2.0 * M_PI / n);
}

static void test_slopes(void **state)
{
    (void)state;
    surf_fn fs[2] = {sphere, paraboloid};
    double t[16];
    for (int s = 0; s < 2; ++s) {
        regular(6, t);
        for (int mth = 0; mth < 3; ++mth) {
            double sl = slope(fs[s], 6, t, (sk_normal_method)mth);
            print_message("surface %d regular valence 6 %-6s slope %.2f\n", s,
                          sk_normal_method_name((sk_normal_method)mth), sl);
            assert_true(sl > 1.8);
        }
        regular(5, t);
        for (int mth = 1; mth < 3; ++mth) /* Theorem 1 (2): odd regular ring, mean and area */
            assert_true(slope(fs[s], 5, t, (sk_normal_method)mth) > 1.8);
        irregular(6, t);
        for (int mth = 0; mth < 3; ++mth) {
            double sl = slope(fs[s], 6, t, (sk_normal_method)mth);
            print_message("surface %d irregular valence 6 %-6s slope %.2f\n", s,
                          sk_normal_method_name((sk_normal_method)mth), sl);
            assert_true(sl > 0.6 && sl < 1.5);
        }
        double q = slope(fs[s], 6, t, SK_NORMALS_QUADRIC);
        print_message("surface %d irregular valence 6 quadric slope %.2f\n", s, q);
        assert_true(q > 1.8);
        regular(3, t);
        for (int mth = 0; mth < 3; ++mth) {
            double sl = slope(fs[s], 3, t, (sk_normal_method)mth);
            print_message("surface %d regular valence 3 %-6s slope %.2f\n", s,
                          sk_normal_method_name((sk_normal_method)mth), sl);
            assert_true(sl > 0.6 && sl < 1.5);
        }
    }
}

/* Given a vertex whose 2-ring lies on two perpendicular lines through it (so the xy column of
 * the quadratic fit is zero and the 5x5 normal equations are singular), when the quadric normals
 * are estimated, then the call succeeds and that vertex keeps its angle-weighted normal (the
 * documented fallback), finite and of unit length. */
static void test_quadric_singular_fallback(void **state)
{
    (void)state;
    double pos[3 * 9] = {0, 0, 0};
    static const double dir[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    for (int k = 0; k < 4; ++k) {
        double *p = pos + 3 * (1 + k), *q = pos + 3 * (5 + k);
        p[0] = dir[k][0], p[1] = dir[k][1], p[2] = 0.3;
        q[0] = 2 * dir[k][0], q[1] = 2 * dir[k][1], q[2] = 1.2;
    }
    uint32_t off[13], idx[36];
    for (uint32_t k = 0; k < 4; ++k) {
        uint32_t pk = 1 + k, pn = 1 + (k + 1) % 4, qk = 5 + k, qn = 5 + (k + 1) % 4;
        uint32_t tri[3][3] = {{0, pk, pn}, {pk, qk, qn}, {pk, qn, pn}};
        memcpy(idx + 9 * k, tri, sizeof tri);
    }
    for (uint32_t f = 0; f <= 12; ++f)
        off[f] = 3 * f;
    sk_mesh *m = NULL;
    sk_error err = {0};
    assert_int_equal(sk_mesh_from_faces(9, pos, 12, off, idx, &m, &err), SK_OK);
    double quad[27], angle[27];
    assert_int_equal(sk_mesh_vertex_normals(m, SK_NORMALS_QUADRIC, quad, &err), SK_OK);
    assert_int_equal(sk_mesh_vertex_normals(m, SK_NORMALS_ANGLE, angle, &err), SK_OK);
    sk_mesh_destroy(&m);
    for (int k = 0; k < 3; ++k)
        assert_true(quad[k] == angle[k]);
    assert_float_equal(quad[0] * quad[0] + quad[1] * quad[1] + quad[2] * quad[2], 1.0, 1e-15);
    assert_float_equal(quad[2], 1.0, 1e-15); /* by symmetry */
}

static void test_names(void **state)
{
    (void)state;
    assert_int_equal(sk_normal_method_from_name("quadric"), SK_NORMALS_QUADRIC);
    assert_int_equal(sk_normal_method_from_name("bogus"), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slopes),
        cmocka_unit_test(test_quadric_singular_fallback),
        cmocka_unit_test(test_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
