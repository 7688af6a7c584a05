/* MIPS energy and its local optimisation. */
#include "testutil.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* sigma1/sigma2 + sigma2/sigma1 of the map from a 3D triangle to a 2D one, from the singular
 * values of J = Q P^-1 computed explicitly (independent of the library's cotangent form). */
static double mips_svd(const double p[9], const double q[6])
{
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = p[3 + k] - p[k];
        e2[k] = p[6 + k] - p[k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double l1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    double x[3] = {e1[0] / l1, e1[1] / l1, e1[2] / l1}, y[3];
    double ln = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    y[0] = (n[1] * x[2] - n[2] * x[1]) / ln;
    y[1] = (n[2] * x[0] - n[0] * x[2]) / ln;
    y[2] = (n[0] * x[1] - n[1] * x[0]) / ln;
    /* local 2D frame: P columns = e1, e2 in (x, y) */
    double P[4] = {l1, e2[0] * x[0] + e2[1] * x[1] + e2[2] * x[2], 0.0,
                   e2[0] * y[0] + e2[1] * y[1] + e2[2] * y[2]};
    double Q[4] = {q[2] - q[0], q[4] - q[0], q[3] - q[1], q[5] - q[1]};
    double dp = P[0] * P[3] - P[1] * P[2];
    double Pi[4] = {P[3] / dp, -P[1] / dp, -P[2] / dp, P[0] / dp};
    double J[4] = {Q[0] * Pi[0] + Q[1] * Pi[2], Q[0] * Pi[1] + Q[1] * Pi[3],
                   Q[2] * Pi[0] + Q[3] * Pi[2], Q[2] * Pi[1] + Q[3] * Pi[3]};
    double fro = J[0] * J[0] + J[1] * J[1] + J[2] * J[2] + J[3] * J[3];
    double det = J[0] * J[3] - J[1] * J[2];
    double disc = sqrt(fro * fro - 4 * det * det);
    double s1 = sqrt((fro + disc) / 2), s2 = sqrt((fro - disc) / 2);
    return s1 / s2 + s2 / s1;
}

static void given_random_triangles_then_energy_matches_singular_values(void **state)
{
    (void)state;
    srand(7);
    for (int trial = 0; trial < 200; ++trial) {
        double p[9], q[6];
        for (int k = 0; k < 9; ++k)
            p[k] = (double)rand() / RAND_MAX - 0.5;
        for (int k = 0; k < 6; ++k)
            q[k] = (double)rand() / RAND_MAX - 0.5;
        if ((q[2] - q[0]) * (q[5] - q[1]) - (q[3] - q[1]) * (q[4] - q[0]) < 0) {
            double t = q[2];
            q[2] = q[4];
            q[4] = t;
            t = q[3];
            q[3] = q[5];
            q[5] = t;
        }
        const uint32_t idx[3] = {0, 1, 2}, off[2] = {0, 3};
        sk_mesh *m = NULL;
        assert_int_equal(sk_mesh_from_faces(3, p, 1, off, idx, &m, NULL), SK_OK);
        double e = 0;
        size_t inv = 9;
        assert_int_equal(sk_mips_energy(m, q, &e, &inv, NULL), SK_OK);
        double ref = mips_svd(p, q);
        assert_int_equal(inv, 0);
        if (fabs(e - ref) > 1e-9 * ref)
            fail_msg("trial %d: %.15g vs %.15g", trial, e, ref);
        sk_mesh_destroy(&m);
    }
}

static void given_planar_disk_with_distorted_start_then_free_mips_reaches_2_per_triangle(void **state)
{
    (void)state;
    sk_mesh *m = skt_planar_disk(12, 3);
    size_t nv = m->num_vertices;
    double *uv = malloc(2 * nv * sizeof(double));
    /* start: a smooth non-conformal warp of the plane (x, y) -> (x + 0.02 y^2, 0.7 y) */
    for (size_t v = 0; v < nv; ++v) {
        double x = m->positions[3 * v], y = m->positions[3 * v + 1];
        uv[2 * v] = x + 0.02 * y * y;
        uv[2 * v + 1] = 0.7 * y;
    }
    sk_mips_opts o = {.max_sweeps = 5000, .tolerance = 1e-15, .seed = 1};
    sk_mips_stats s;
    sk_error err;
    assert_int_equal(sk_param_mips(m, &o, uv, &s, &err), SK_OK);
    double opt = 2.0 * (double)s.triangles;
    assert_true(s.energy_start > opt * 1.01);
    if (fabs(s.energy - opt) > 1e-9 * opt)
        fail_msg("energy %.15g, optimum %.15g (%zu sweeps)", s.energy, opt, s.sweeps);
    size_t inv = 1;
    double e;
    sk_mips_energy(m, uv, &e, &inv, NULL);
    assert_int_equal(inv, 0);
    free(uv);
    sk_mesh_destroy(&m);
}

static void given_fixed_boundary_then_boundary_stays_and_energy_never_rises(void **state)
{
    (void)state;
    sk_mesh *m = skt_planar_disk(10, 5);
    size_t nv = m->num_vertices;
    double *uv = malloc(2 * nv * sizeof(double)), *uv0 = malloc(2 * nv * sizeof(double));
    for (size_t v = 0; v < nv; ++v) {
        double x = m->positions[3 * v], y = m->positions[3 * v + 1];
        uv[2 * v] = x * (1.0 + 0.03 * y);
        uv[2 * v + 1] = y;
    }
    memcpy(uv0, uv, 2 * nv * sizeof(double));
    double prev = INFINITY;
    for (int round = 0; round < 5; ++round) {
        sk_mips_opts o = {.boundary = SK_BOUNDARY_GIVEN, .max_sweeps = 1, .seed = (uint64_t)round};
        sk_mips_stats s;
        assert_int_equal(sk_param_mips(m, &o, uv, &s, NULL), SK_OK);
        assert_true(s.energy <= s.energy_start);
        assert_true(s.energy <= prev);
        prev = s.energy;
    }
    for (uint32_t v = 0; v < nv; ++v)
        if (sk_is_boundary_v(m, v))
            assert_memory_equal(uv + 2 * v, uv0 + 2 * v, 2 * sizeof(double));
    free(uv);
    free(uv0);
    sk_mesh_destroy(&m);
}

static void given_flipped_start_then_mips_refuses(void **state)
{
    (void)state;
    sk_mesh *m = skt_planar_disk(4, 1);
    double uv[32];
    for (size_t v = 0; v < 16; ++v) {
        uv[2 * v] = m->positions[3 * v];
        uv[2 * v + 1] = m->positions[3 * v + 1];
    }
    uv[2 * 5] = 5.0; /* interior vertex thrown far out: flips triangles */
    sk_error err;
    assert_int_equal(sk_param_mips(m, NULL, uv, NULL, &err), SK_ERR_ARG);
    assert_non_null(strstr(err.message, "inverted"));
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_random_triangles_then_energy_matches_singular_values),
        cmocka_unit_test(given_planar_disk_with_distorted_start_then_free_mips_reaches_2_per_triangle),
        cmocka_unit_test(given_fixed_boundary_then_boundary_stays_and_energy_never_rises),
        cmocka_unit_test(given_flipped_start_then_mips_refuses),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
