/* The parametrize pipeline (sk_parametrize): defaults, the legality checks per method, the flip
 * warning, the same results as the drivers it calls. */
#include "testutil.h"

#include "surfkit/parametrize.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void expect_illegal(sk_parametrize_opts o, const char *fragment)
{
    sk_error err;
    assert_int_equal(sk_parametrize_check(&o, &err), SK_ERR_ARG);
    if (!strstr(err.message, fragment))
        fail_msg("message '%s' lacks '%s'", err.message, fragment);
    /* and the pipeline refuses the same before touching the mesh */
    sk_mesh *m = skt_planar_disk(4, 1);
    double *uv = calloc(2 * m->num_vertices, sizeof *uv);
    sk_parametrize_stats s;
    assert_int_equal(sk_parametrize(m, &o, uv, &s, &err), SK_ERR_ARG);
    assert_non_null(strstr(err.message, fragment));
    sk_parametrize_stats_release(&s);
    free(uv);
    sk_mesh_destroy(&m);
}

static void given_illegal_combinations_then_refused_with_a_reason(void **state)
{
    (void)state;
    assert_int_equal(sk_parametrize_check(NULL, NULL), SK_OK);
    expect_illegal((sk_parametrize_opts){.method = SK_PARAM_LSCM,
                                         .boundary = {.shape = SK_BOUNDARY_SQUARE}},
                   "lscm has a free boundary");
    expect_illegal((sk_parametrize_opts){.method = SK_PARAM_HARMONIC,
                                         .boundary = {.shape = SK_BOUNDARY_FREE}},
                   "a free boundary needs lscm or mips");
    expect_illegal((sk_parametrize_opts){.boundary = {.shape = SK_BOUNDARY_FREE}},
                   "floater has a fixed boundary");
    expect_illegal((sk_parametrize_opts){.flat = true}, "go with the MIPS method");
    expect_illegal((sk_parametrize_opts){.method = SK_PARAM_TUTTE, .max_steps = 5},
                   "go with the MIPS method");
    expect_illegal((sk_parametrize_opts){.method = SK_PARAM_MIPS,
                                         .boundary = {.shape = SK_BOUNDARY_GIVEN}},
                   "not given");
    expect_illegal((sk_parametrize_opts){.method = (sk_param_method)99}, "unknown");
    expect_illegal((sk_parametrize_opts){.boundary = {.shape = (sk_boundary_shape)99}}, "unknown");
    /* the legal ones pass */
    const sk_parametrize_opts ok[] = {
        {.method = SK_PARAM_LSCM},
        {.method = SK_PARAM_MIPS, .boundary = {.shape = SK_BOUNDARY_SQUARE}, .max_steps = 9},
        {.method = SK_PARAM_MIPS, .flat = true, .boundary = {.shape = SK_BOUNDARY_FREE}},
        {.method = SK_PARAM_MEAN_VALUE, .boundary = {.shape = SK_BOUNDARY_GIVEN}},
    };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; ++i)
        assert_int_equal(sk_parametrize_check(&ok[i], NULL), SK_OK);
}

/* Given no options, then Floater with the circle boundary, normalized: the same uv as
 * sk_param_linear's default followed by sk_param_normalize. */
static void given_null_opts_then_floater_circle_normalized(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("nefertiti.off"));
    size_t n2 = 2 * m->num_vertices;
    double *a = calloc(n2, sizeof *a), *b = calloc(n2, sizeof *b);
    sk_parametrize_stats s;
    assert_int_equal(sk_parametrize(m, NULL, a, &s, NULL), SK_OK);
    assert_int_equal(s.method, SK_PARAM_FLOATER);
    assert_int_equal(s.boundary, SK_BOUNDARY_CIRCLE);
    assert_string_equal(s.name, "floater");
    assert_int_equal(s.flipped, 0);
    assert_int_equal(s.linear.vertices, m->num_vertices);
    sk_parametrize_stats_release(&s);
    sk_param_opts po = {0}; /* SK_PARAM_DEFAULT: Floater */
    assert_int_equal(sk_param_linear(m, &po, b, NULL, NULL), SK_OK);
    assert_int_equal(sk_param_normalize(m, b, NULL), SK_OK);
    assert_memory_equal(a, b, n2 * sizeof *a);
    assert_int_equal(sk_parametrize(m, NULL, a, NULL, NULL), SK_OK); /* stats may be NULL */
    free(a);
    free(b);
    sk_mesh_destroy(&m);
}

/* Given MIPS through the pipeline (raw), then the hierarchical and flat drivers' own results, with
 * the default seed 1 and the resolved free boundary; the level table is there. */
static void given_mips_then_same_as_the_drivers(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("nefertiti.off"));
    size_t n2 = 2 * m->num_vertices;
    double *a = calloc(n2, sizeof *a), *b = calloc(n2, sizeof *b);
    sk_parametrize_opts o = {.method = SK_PARAM_MIPS, .raw = true};
    sk_parametrize_stats s;
    assert_int_equal(sk_parametrize(m, &o, a, &s, NULL), SK_OK);
    assert_string_equal(s.name, "mips-hierarchical");
    assert_int_equal(s.boundary, SK_BOUNDARY_FREE);
    assert_true(s.hierarchical && s.hparam.num_levels > 1 && s.hparam.levels);
    sk_hparam_opts ho = {.seed = 1};
    sk_hparam_stats hs;
    assert_int_equal(sk_param_hierarchical(m, &ho, b, &hs, NULL), SK_OK);
    assert_memory_equal(a, b, n2 * sizeof *a);
    assert_true(hs.energy == s.hparam.energy);
    sk_hparam_stats_release(&hs);
    sk_parametrize_stats_release(&s);
    o.flat = true;
    o.max_steps = 5000;
    o.boundary.shape = SK_BOUNDARY_CIRCLE;
    assert_int_equal(sk_parametrize(m, &o, a, &s, NULL), SK_OK);
    assert_string_equal(s.name, "mips-flat");
    assert_int_equal(s.mips.steps, 5000);
    sk_mips_flat_opts fo = {.boundary = {.shape = SK_BOUNDARY_CIRCLE}, .max_steps = 5000, .seed = 1};
    sk_mips_stats ms;
    assert_int_equal(sk_param_mips_flat(m, &fo, b, &ms, NULL), SK_OK);
    assert_memory_equal(a, b, n2 * sizeof *a);
    sk_parametrize_stats_release(&s);
    free(a);
    free(b);
    sk_mesh_destroy(&m);
}

/* Given harmonic weights on three_peaks (obtuse triangles: 33 flip), then SK_WARN_FLIPS with the
 * complete uv and the count; the metrics agree. */
static void given_flipping_method_then_warning_and_complete_uv(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("three_peaks.off"));
    double *uv = calloc(2 * m->num_vertices, sizeof *uv);
    sk_parametrize_opts o = {.method = SK_PARAM_HARMONIC};
    sk_parametrize_stats s;
    sk_error err;
    assert_int_equal(sk_parametrize(m, &o, uv, &s, &err), SK_WARN_FLIPS);
    assert_int_equal(s.flipped, 33);
    assert_non_null(strstr(err.message, "33 of 3671 triangles flipped"));
    sk_param_metrics pm;
    assert_int_equal(sk_param_metrics_compute(m, uv, &pm, NULL), SK_OK);
    assert_int_equal(pm.flipped, 33);
    sk_parametrize_stats_release(&s);
    free(uv);
    sk_mesh_destroy(&m);
}

static void given_non_disk_then_topology_error(void **state)
{
    (void)state;
    sk_mesh *m = skt_read_mesh(skt_shared_mesh("eight.off"));
    double *uv = calloc(2 * m->num_vertices, sizeof *uv);
    sk_parametrize_opts o = {.method = SK_PARAM_MIPS};
    sk_parametrize_stats s;
    sk_error err;
    assert_int_equal(sk_parametrize(m, &o, uv, &s, &err), SK_ERR_TOPOLOGY);
    assert_non_null(strstr(err.message, "genus 2"));
    sk_parametrize_stats_release(&s);
    free(uv);
    sk_mesh_destroy(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(given_illegal_combinations_then_refused_with_a_reason),
        cmocka_unit_test(given_null_opts_then_floater_circle_normalized),
        cmocka_unit_test(given_mips_then_same_as_the_drivers),
        cmocka_unit_test(given_flipping_method_then_warning_and_complete_uv),
        cmocka_unit_test(given_non_disk_then_topology_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
