/* Linear parametrizations: linear precision on planar meshes, LSCM up to a similarity, the warm
 * start solver, and the input check. */
#include "testutil.h"

#include "surfkit/param.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* An irregular planar disk: an n x n grid on [0,1]^2 with jittered interior vertices and
 * alternating diagonals, in the plane z = 0. */
static sk_mesh *planar_disk(int n)
{
    size_t nv = (size_t)(n + 1) * (n + 1), nf = 2 * (size_t)n * n;
    double *p = malloc(3 * nv * sizeof *p);
    uint32_t *off = malloc((nf + 1) * sizeof *off), *idx = malloc(3 * nf * sizeof *idx);
    uint64_t s = 12345;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            size_t v = (size_t)j * (n + 1) + i;
            double jx = 0, jy = 0;
            if (i > 0 && i < n && j > 0 && j < n) {
                s = s * 6364136223846793005ull + 1442695040888963407ull;
                jx = ((double)(s >> 11) / 9007199254740992.0 - 0.5) * 0.5 / n;
                s = s * 6364136223846793005ull + 1442695040888963407ull;
                jy = ((double)(s >> 11) / 9007199254740992.0 - 0.5) * 0.5 / n;
            }
            p[3 * v] = (double)i / n + jx;
            p[3 * v + 1] = (double)j / n + jy;
            p[3 * v + 2] = 0;
        }
    size_t f = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 2,
                     d = a + (uint32_t)n + 1;
            uint32_t t[6];
            if ((i + j) % 2 == 0) {
                uint32_t q[6] = {a, b, c, a, c, d};
                memcpy(t, q, sizeof q);
            } else {
                uint32_t q[6] = {a, b, d, b, c, d};
                memcpy(t, q, sizeof q);
            }
            for (int k = 0; k < 6; ++k)
                idx[3 * f + k] = t[k];
            f += 2;
        }
    for (size_t k = 0; k <= nf; ++k)
        off[k] = (uint32_t)(3 * k);
    sk_mesh *m = NULL;
    assert_int_equal(sk_mesh_from_faces(nv, p, nf, off, idx, &m, NULL), SK_OK);
    free(p);
    free(off);
    free(idx);
    return m;
}

static double max_err_to_positions(const sk_mesh *m, const double *uv)
{
    double e = 0;
    for (size_t v = 0; v < m->num_vertices; ++v)
        for (int c = 0; c < 2; ++c)
            e = fmax(e, fabs(uv[2 * v + c] - m->positions[3 * v + c]));
    return e;
}

/* given a planar disk with its boundary at its own positions, Floater, mean value and harmonic
 * reproduce every interior vertex (linear precision); Tutte does not */
static void test_linear_precision(void **state)
{
    (void)state;
    sk_mesh *m = planar_disk(24);
    double *uv = calloc(2 * m->num_vertices, sizeof *uv);
    sk_param_method methods[4] = {SK_PARAM_FLOATER, SK_PARAM_MEAN_VALUE, SK_PARAM_HARMONIC,
                                  SK_PARAM_TUTTE};
    for (int k = 0; k < 4; ++k) {
        for (size_t v = 0; v < m->num_vertices; ++v) {
            uv[2 * v] = m->positions[3 * v];
            uv[2 * v + 1] = m->positions[3 * v + 1];
        }
        for (size_t v = 0; v < m->num_vertices; ++v)
            if (!sk_is_boundary_v(m, (uint32_t)v))
                uv[2 * v] = uv[2 * v + 1] = 0.5; /* forget the interior */
        sk_param_opts o = {0};
        o.method = methods[k];
        o.boundary.shape = SK_BOUNDARY_GIVEN;
        sk_param_stats st;
        sk_error err;
        assert_int_equal(sk_param_linear(m, &o, uv, &st, &err), SK_OK);
        double e = max_err_to_positions(m, uv); /* the extent is 1: relative = absolute */
        if (methods[k] == SK_PARAM_TUTTE)
            assert_true(e > 1e-4);
        else
            assert_true(e < 1e-10);
        assert_int_equal(st.interior, 23 * 23);
        assert_int_equal(st.solve.kind, methods[k] == SK_PARAM_HARMONIC || methods[k] == SK_PARAM_TUTTE
                                            ? SK_SOLVER_CHOLESKY : SK_SOLVER_LU);
    }
    free(uv);
    sk_mesh_destroy(&m);
}

/* given a planar disk, LSCM reproduces it up to a similarity (fitted by least squares) */
static void test_lscm_similarity(void **state)
{
    (void)state;
    sk_mesh *m = planar_disk(20);
    size_t n = m->num_vertices;
    double *uv = calloc(2 * n, sizeof *uv);
    sk_param_opts o = {0};
    o.method = SK_PARAM_LSCM;
    assert_int_equal(sk_param_linear(m, &o, uv, NULL, NULL), SK_OK);
    /* fit uv ~ [a -b; b a] x + t: a complex-linear least squares z' = alpha z + beta */
    double mx[2] = {0, 0}, mu[2] = {0, 0};
    for (size_t v = 0; v < n; ++v)
        for (int c = 0; c < 2; ++c) {
            mx[c] += m->positions[3 * v + c] / n;
            mu[c] += uv[2 * v + c] / n;
        }
    double sxx = 0, sa = 0, sb = 0;
    for (size_t v = 0; v < n; ++v) {
        double x = m->positions[3 * v] - mx[0], y = m->positions[3 * v + 1] - mx[1];
        double u = uv[2 * v] - mu[0], w = uv[2 * v + 1] - mu[1];
        sxx += x * x + y * y;
        sa += x * u + y * w;
        sb += x * w - y * u;
    }
    double a = sa / sxx, b = sb / sxx, scale = sqrt(a * a + b * b), e = 0;
    for (size_t v = 0; v < n; ++v) {
        double x = m->positions[3 * v] - mx[0], y = m->positions[3 * v + 1] - mx[1];
        double u = a * x - b * y + mu[0], w = b * x + a * y + mu[1];
        e = fmax(e, fmax(fabs(u - uv[2 * v]), fabs(w - uv[2 * v + 1])));
    }
    assert_true(e < 1e-10 * scale);
    sk_param_metrics r;
    assert_int_equal(sk_param_metrics_compute(m, uv, &r, NULL), SK_OK);
    assert_int_equal(r.flipped, 0);
    assert_true(fabs(r.mips_mean - 2.0) < 1e-9);
    free(uv);
    sk_mesh_destroy(&m);
}

/* given the direct solution, Gauss-Seidel from a nearby warm start converges to it */
static void test_gauss_seidel_warm_start(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("nefertiti.off"));
    size_t n = m->num_vertices;
    double *uv = calloc(2 * n, sizeof *uv), *uv2 = calloc(2 * n, sizeof *uv2);
    sk_param_opts o = {0};
    o.method = SK_PARAM_MEAN_VALUE;
    assert_int_equal(sk_param_linear(m, &o, uv, NULL, NULL), SK_OK);
    for (size_t v = 0; v < 2 * n; ++v)
        uv2[v] = uv[v] + (sk_is_boundary_v(m, (uint32_t)(v / 2)) ? 0 : 0.01 * sin((double)v));
    o.solver = SK_LINEAR_GAUSS_SEIDEL;
    o.boundary.shape = SK_BOUNDARY_GIVEN;
    o.tolerance = 1e-13;
    sk_param_stats st;
    assert_int_equal(sk_param_linear(m, &o, uv2, &st, NULL), SK_OK);
    double e = 0;
    for (size_t v = 0; v < 2 * n; ++v)
        e = fmax(e, fabs(uv2[v] - uv[v]));
    assert_true(e < 1e-9);
    assert_true(st.iterations > 1 && st.iterations < 10000);
    /* the same through sk_param_solve_weights with an explicit fixed set */
    double *w = malloc(m->num_halfedges * sizeof *w);
    assert_int_equal(sk_param_weights(m, SK_PARAM_HARMONIC, w, NULL), SK_OK);
    for (size_t h = 0; h < m->num_halfedges; ++h)
        assert_true(w[h] == w[h ^ 1]);
    sk_param_opts d = {0};
    assert_int_equal(sk_param_solve_weights(m, w, true, NULL, &d, uv, &st, NULL), SK_OK);
    assert_int_equal(st.solve.kind, SK_SOLVER_CHOLESKY);
    free(w);
    free(uv);
    free(uv2);
    sk_mesh_destroy(&m);
}

static void expect_reject(const char *name, const char *fragment)
{
    sk_mesh *m = skt_read_mesh(skt_shared_mesh(name));
    double *uv = calloc(2 * m->num_vertices + 2, sizeof *uv);
    sk_error err;
    sk_param_opts o = {0};
    assert_int_equal(sk_param_linear(m, &o, uv, NULL, &err), SK_ERR_TOPOLOGY);
    if (!strstr(err.message, fragment))
        fail_msg("%s: '%s' lacks '%s'", name, err.message, fragment);
    o.method = SK_PARAM_LSCM;
    assert_int_equal(sk_param_linear(m, &o, uv, NULL, &err), SK_ERR_TOPOLOGY);
    free(uv);
    sk_mesh_destroy(&m);
}

static void test_rejections(void **state)
{
    (void)state;
    expect_reject("sphere.off", "closed surface of genus 0");
    expect_reject("cube.off", "closed surface of genus 0");
    expect_reject("eight.off", "closed surface of genus 2: cut it to a disk first");
    expect_reject("elephant.off", "closed surface of genus 3");
    expect_reject("knot1.off", "closed surface of genus 1");
    expect_reject("holes.off", "7 boundary loops");
    expect_reject("lion.off", "5 boundary loops");
    expect_reject("pig.off", "7 boundary loops");
    expect_reject("mask_cone.off", "2 components");
    expect_reject("mech-holes-shark.off", "4 boundary loops");
    expect_reject("degtri_sliding.off", "4 degenerate (zero-area) triangles");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear_precision),
        cmocka_unit_test(test_lscm_similarity),
        cmocka_unit_test(test_gauss_seidel_warm_start),
        cmocka_unit_test(test_rejections),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
