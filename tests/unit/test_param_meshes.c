/* Every method on every disk mesh of the shared data: the flip behaviour Tutte's / Floater's
 * theorem promises (none for Tutte, Floater, mean value with a circle or square boundary).
 * SK_TEST_QUICK=1 (the sanitizer run) keeps the small meshes only. */
#include "testutil.h"

#include "surfkit/param.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *meshes[] = {"nefertiti.off", "patch-01.off", "paraboloid-patch.off",
                               "three_peaks.off", "mushroom.off", "lion-head.off",
                               "cylinder.off", "fold.off", "in.off", "triangle.off"};

static void test_all_disks(void **state)
{
    (void)state;
    const char *quick = getenv("SK_TEST_QUICK");
    bool q = quick && quick[0] == '1';
    for (size_t i = 0; i < sizeof meshes / sizeof meshes[0]; ++i) {
        if (q && (!strcmp(meshes[i], "lion-head.off") || !strcmp(meshes[i], "mushroom.off")))
            continue;
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(meshes[i]));
        double *uv = calloc(2 * m->num_vertices, sizeof *uv);
        for (int method = SK_PARAM_TUTTE; method <= SK_PARAM_LSCM; ++method) {
            for (int b = 0; b < 2; ++b) {
                if (method == SK_PARAM_LSCM && b == 1)
                    continue;
                if (b == 1 && !strcmp(meshes[i], "triangle.off"))
                    continue; /* 3 boundary vertices: no square */
                sk_param_opts o = {0};
                o.method = (sk_param_method)method;
                o.boundary.shape = b ? SK_BOUNDARY_SQUARE : SK_BOUNDARY_CIRCLE;
                sk_error err;
                sk_param_stats st;
                sk_status s = sk_param_linear(m, &o, uv, &st, &err);
                if (s != SK_OK)
                    fail_msg("%s %s: %s", meshes[i], sk_param_method_name(o.method), err.message);
                sk_param_metrics r;
                assert_int_equal(sk_param_metrics_compute(m, uv, &r, NULL), SK_OK);
                assert_int_equal(r.faces, m->num_faces);
                bool guaranteed = method == SK_PARAM_TUTTE || method == SK_PARAM_FLOATER ||
                                  method == SK_PARAM_MEAN_VALUE;
                if (guaranteed) {
                    if (r.flipped != 0)
                        fail_msg("%s %s %s: %zu flipped", meshes[i], sk_param_method_name(o.method),
                                 b ? "square" : "circle", r.flipped);
                    assert_int_equal(r.boundary_self_intersections, 0);
                    assert_true(fabs(r.area_uv - (b ? 1.0 : 0.0)) < 1e-9 || !b);
                }
                if (r.flipped == 0)
                    assert_true(r.mips_mean >= 2.0 - 1e-12 && isfinite(r.mips_sum));
            }
        }
        free(uv);
        sk_mesh_destroy(&m);
    }
}

/* recorded values: nefertiti, Floater, circle, chord spacing */
static void test_regression_values(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("nefertiti.off"));
    double *uv = calloc(2 * m->num_vertices, sizeof *uv);
    sk_param_opts o = {0};
    o.method = SK_PARAM_FLOATER;
    assert_int_equal(sk_param_linear(m, &o, uv, NULL, NULL), SK_OK);
    sk_param_metrics r;
    assert_int_equal(sk_param_metrics_compute(m, uv, &r, NULL), SK_OK);
    assert_int_equal(r.faces, 562);
    assert_int_equal(r.flipped, 0);
    assert_true(fabs(r.mips_mean - 2.05189) < 1e-5);
    /* boundary on the unit circle */
    for (size_t v = 0; v < m->num_vertices; ++v)
        if (sk_is_boundary_v(m, (uint32_t)v))
            assert_true(fabs(hypot(uv[2 * v], uv[2 * v + 1]) - 1.0) < 1e-14);
    free(uv);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_disks),
        cmocka_unit_test(test_regression_values),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
