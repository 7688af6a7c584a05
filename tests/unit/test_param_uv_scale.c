/* UV scale: every method's uv normalized to the unit square (sk_param_normalize) with its metrics
 * unchanged, and the free-boundary MIPS keeps its scale bounded during the optimization without
 * changing what it computes. SK_TEST_QUICK=1 keeps nefertiti only. */
#include "testutil.h"

#include "surfkit/parametrize.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const meshes[] = {"nefertiti.off", "lion-head.off"};

/* SK_TEST_QUICK=1 (the sanitizer run): nefertiti only */
static size_t num_meshes(void)
{
    const char *q = getenv("SK_TEST_QUICK");
    return q && *q && strcmp(q, "0") != 0 ? 1 : sizeof meshes / sizeof meshes[0];
}

/* Bounding box of the uv of the vertices of faces. */
static void uv_box(const sk_mesh *m, const double *uv, double lo[2], double hi[2])
{
    lo[0] = lo[1] = INFINITY;
    hi[0] = hi[1] = -INFINITY;
    for (size_t f = 0; f < m->num_faces; ++f) {
        uint32_t h0 = m->f_halfedge[f], h = h0;
        do {
            const double *q = uv + 2 * (size_t)m->h_vertex[h];
            for (int k = 0; k < 2; ++k) {
                lo[k] = fmin(lo[k], q[k]);
                hi[k] = fmax(hi[k], q[k]);
            }
            h = m->h_next[h];
        } while (h != h0);
    }
}

static void assert_unit_square(const char *what, const sk_mesh *m, const double *uv)
{
    double lo[2], hi[2];
    uv_box(m, uv, lo, hi);
    if (!(lo[0] == 0.0 && lo[1] == 0.0 && hi[0] <= 1.0 && hi[1] <= 1.0 &&
          fmax(hi[0], hi[1]) == 1.0))
        fail_msg("%s: uv box [%.17g, %.17g] x [%.17g, %.17g]", what, lo[0], hi[0], lo[1], hi[1]);
}

static void assert_same_metrics(const char *what, const sk_param_metrics *a,
                                const sk_param_metrics *b)
{
    assert_int_equal(a->flipped, b->flipped);
    assert_int_equal(a->boundary_self_intersections, b->boundary_self_intersections);
    const double x[] = {a->mips_sum, a->conformal_mean, a->area_log_mean, a->stretch_max};
    const double y[] = {b->mips_sum, b->conformal_mean, b->area_log_mean, b->stretch_max};
    for (int k = 0; k < 4; ++k)
        if (!(fabs(x[k] - y[k]) <= 1e-11 * fabs(y[k]) + 1e-14))
            fail_msg("%s: metric %d %.17g before normalization, %.17g after", what, k, y[k], x[k]);
}

/* Given each method on nefertiti and lion-head through sk_parametrize, when run raw and with the
 * default normalization, then the normalized uv box is [0, 1] x [0, h] or [0, w] x [0, 1], and
 * the metrics and the MIPS energy are those of the raw map; and sk_param_normalize on the raw uv
 * gives exactly the pipeline's uv. */
static void given_every_method_when_normalized_then_unit_square_and_same_metrics(void **state)
{
    (void)state;
    for (size_t i = 0; i < num_meshes(); ++i) {
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(meshes[i]));
        size_t n2 = 2 * m->num_vertices;
        double *raw = calloc(n2, sizeof *raw), *uv = calloc(n2, sizeof *uv);
        for (int k = SK_PARAM_TUTTE; k <= SK_PARAM_MIPS + 1; ++k) {
            sk_parametrize_opts o = {.method = k > SK_PARAM_MIPS ? SK_PARAM_MIPS : (sk_param_method)k,
                                     .flat = k > SK_PARAM_MIPS, .seed = 1};
            sk_parametrize_stats ps;
            sk_error err;
            o.raw = true;
            sk_status st = sk_parametrize(m, &o, raw, &ps, &err);
            char what[128];
            snprintf(what, sizeof what, "%s %s", meshes[i], ps.name ? ps.name : "?");
            if (st < 0)
                fail_msg("%s: %s", what, err.message);
            double e_raw = ps.hierarchical ? ps.hparam.energy : ps.mips.energy;
            sk_parametrize_stats_release(&ps);
            o.raw = false;
            if (sk_parametrize(m, &o, uv, &ps, &err) < 0)
                fail_msg("%s: %s", what, err.message);
            if (k == SK_PARAM_MIPS)
                assert_true(ps.hparam.energy == e_raw); /* the optimizer's numbers unchanged */
            if (k == SK_PARAM_MIPS + 1)
                assert_true(ps.mips.energy == e_raw);
            sk_parametrize_stats_release(&ps);
            assert_unit_square(what, m, uv);
            sk_param_metrics before, after;
            assert_int_equal(sk_param_metrics_compute(m, raw, &before, NULL), SK_OK);
            assert_int_equal(sk_param_metrics_compute(m, uv, &after, NULL), SK_OK);
            assert_same_metrics(what, &after, &before);
            assert_int_equal(sk_param_normalize(m, raw, &err), SK_OK);
            assert_memory_equal(raw, uv, n2 * sizeof *uv);
        }
        free(raw);
        free(uv);
        sk_mesh_destroy(&m);
    }
}

/* Given the free-boundary hierarchical MIPS (whose scale drifted to 1e9 on nefertiti and 1e4 on
 * lion-head), then its raw result has a bounding box with the larger side in [1, 2). */
static void given_free_mips_then_raw_scale_stays_bounded(void **state)
{
    (void)state;
    for (size_t i = 0; i < num_meshes(); ++i) {
        sk_mesh *m = skt_read_mesh(skt_shared_mesh(meshes[i]));
        double *uv = calloc(2 * m->num_vertices, sizeof *uv);
        sk_hparam_opts o = {.seed = 1};
        sk_hparam_stats hs;
        assert_int_equal(sk_param_hierarchical(m, &o, uv, &hs, NULL), SK_OK);
        assert_true(hs.num_levels > 1 && hs.levels != NULL); /* the level table, allocated */
        assert_true(hs.levels[hs.num_levels - 1].energy == hs.energy);
        sk_hparam_stats_release(&hs);
        assert_null(hs.levels);
        double lo[2], hi[2];
        uv_box(m, uv, lo, hi);
        double ext = fmax(hi[0] - lo[0], hi[1] - lo[1]);
        if (!(ext >= 1.0 && ext < 2.0 && fmax(fmax(fabs(lo[0]), fabs(hi[0])),
                                              fmax(fabs(lo[1]), fabs(hi[1]))) < 10.0))
            fail_msg("%s: raw uv box [%g, %g] x [%g, %g]", meshes[i], lo[0], hi[0], lo[1], hi[1]);
        free(uv);
        sk_mesh_destroy(&m);
    }
}

/* Given one start at two scales 2^40 apart, when free MIPS with global steps (frozen model)
 * runs, then both give the same energies and bit-identical uv: the renormalization by powers of
 * two is exact and reaches neither the local nor the global steps' numerics. */
static void given_start_at_two_scales_when_free_mips_then_identical_results(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("nefertiti.off"));
    size_t n2 = 2 * m->num_vertices;
    double *a = calloc(n2, sizeof *a), *b = calloc(n2, sizeof *b);
    sk_param_opts po = {.method = SK_PARAM_FLOATER};
    assert_int_equal(sk_param_linear(m, &po, a, NULL, NULL), SK_OK);
    for (size_t i = 0; i < n2; ++i)
        b[i] = ldexp(a[i], 40);
    sk_mips_opts o = {.global_steps = 6, .sweeps_per_global = 2, .frozen_model = true,
                      .max_sweeps = 40, .seed = 3};
    sk_mips_stats sa, sb;
    assert_int_equal(sk_param_mips(m, &o, a, &sa, NULL), SK_OK);
    assert_int_equal(sk_param_mips(m, &o, b, &sb, NULL), SK_OK);
    assert_true(sa.energy < sa.energy_start);
    assert_int_equal(sa.steps, sb.steps);
    assert_int_equal(sa.global_steps, sb.global_steps);
    assert_true(sa.energy == sb.energy);
    assert_memory_equal(a, b, n2 * sizeof *a);
    free(a);
    free(b);
    sk_mesh_destroy(&m);
}

static void given_degenerate_uv_when_normalized_then_refused(void **state)
{
    (void)state;
    sk_mesh *m = skt_planar_disk(3, 1);
    double *uv = calloc(2 * m->num_vertices, sizeof *uv);
    sk_error err;
    assert_int_equal(sk_param_normalize(m, uv, &err), SK_ERR_NUMERIC);
    assert_non_null(strstr(err.message, "same point"));
    uv[3] = NAN;
    assert_int_equal(sk_param_normalize(m, uv, &err), SK_ERR_NUMERIC);
    assert_non_null(strstr(err.message, "non-finite"));
    free(uv);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_every_method_when_normalized_then_unit_square_and_same_metrics),
        cmocka_unit_test(given_free_mips_then_raw_scale_stays_bounded),
        cmocka_unit_test(given_start_at_two_scales_when_free_mips_then_identical_results),
        cmocka_unit_test(given_degenerate_uv_when_normalized_then_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
